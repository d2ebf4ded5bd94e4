!> Order statistics of a few values (the rounds of a measurement): the values sorted, and
!> their median.
module dpmpm_stats
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: sorted, median

contains

  !> The values in ascending order (insertion sort: meant for a few dozen values).
  pure function sorted(v) result(s)
    real(wp), intent(in) :: v(:)
    real(wp) :: s(size(v)), key
    integer :: i, j
    s = v
    do i = 2, size(s)
      key = s(i)
      j = i - 1
      do while (j >= 1)
        if (s(j) <= key) exit
        s(j + 1) = s(j)
        j = j - 1
      end do
      s(j + 1) = key
    end do
  end function sorted

  !> Median: the middle value, or the mean of the two middle values of an even count.
  pure real(wp) function median(v) result(med)
    real(wp), intent(in) :: v(:)
    real(wp) :: s(size(v))
    integer :: n
    n = size(v)
    s = sorted(v)
    if (mod(n, 2) == 1) then
      med = s((n + 1)/2)
    else
      med = 0.5_wp*(s(n/2) + s(n/2 + 1))
    end if
  end function median

end module dpmpm_stats
