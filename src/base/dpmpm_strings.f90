!> Small text helpers shared by input checks and run messages.
module dpmpm_strings
  use dpmpm_kinds, only: i8
  implicit none
  private
  public :: itoa, i8toa

contains

  !> Decimal text of a default integer, no blanks.
  pure function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=16) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function itoa

  !> Decimal text of a 64-bit integer, no blanks.
  pure function i8toa(i) result(s)
    integer(i8), intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function i8toa

end module dpmpm_strings
