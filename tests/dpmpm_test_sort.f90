!> The one sort of the test programs: the order that puts a list of keys in ascending
!> order, so that a test sorts its values, or carries other arrays along, with one call.
module dpmpm_test_sort
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: ascending_order

contains

  !> The permutation o with key(o) ascending, equal keys in the order given (a stable
  !> insertion sort: the lists of a test hold at most a few thousand values).
  function ascending_order(key) result(o)
    real(wp), intent(in) :: key(:)
    integer :: o(size(key))
    integer :: i, j, t
    o = [(i, i=1, size(key))]
    do i = 2, size(key)
      t = o(i)
      j = i - 1
      do while (j >= 1)
        if (key(o(j)) <= key(t)) exit
        o(j + 1) = o(j)
        j = j - 1
      end do
      o(j + 1) = t
    end do
  end function ascending_order

end module dpmpm_test_sort
