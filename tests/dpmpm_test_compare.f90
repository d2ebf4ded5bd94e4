!> How far apart two results of a test are: the measure the run-to-run comparisons of the
!> test programs share.
module dpmpm_test_compare
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: reldiff

contains

  !> Normwise relative difference max|a - b| / max|b| of two arrays of point values
  !> (one column a point).
  pure real(wp) function reldiff(a, b)
    real(wp), intent(in) :: a(:, :), b(:, :)
    reldiff = maxval(abs(a - b))/max(maxval(abs(b)), tiny(1.0_wp))
  end function reldiff

end module dpmpm_test_compare
