!> Small text helpers shared by input checks, the echo of the input and run messages:
!> numbers as short decimal text, quoting, lower case, words of a list.
module dpmpm_strings
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  use dpmpm_kinds, only: wp, i8
  implicit none
  private
  public :: itoa, i8toa, rtoa, ftoa, itoa_list, rtoa_list, quote, lower, next_word

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

  !> "a, b, c" for integers.
  pure function itoa_list(v) result(s)
    integer, intent(in) :: v(:)
    character(len=:), allocatable :: s
    integer :: j
    s = ''
    do j = 1, size(v)
      if (j > 1) s = s//', '
      s = s//itoa(v(j))
    end do
  end function itoa_list

  !> "a, b, c" for reals.
  function rtoa_list(v) result(s)
    real(wp), intent(in) :: v(:)
    character(len=:), allocatable :: s
    integer :: j
    s = ''
    do j = 1, size(v)
      if (j > 1) s = s//', '
      s = s//rtoa(v(j))
    end do
  end function rtoa_list

  !> The shortest decimal form of x that reads back to the same value: fixed notation for
  !> magnitudes in [1e-4, 1e6), otherwise mantissa and exponent ("2.5e-7", "1.0e6").
  function rtoa(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=40) :: buf
    character(len=12) :: fmt
    character(len=:), allocatable :: digits, sgn
    real(wp) :: y
    integer :: nd, e, ie, j
    if (ieee_is_nan(x)) then
      s = 'NaN'
      return
    else if (.not. ieee_is_finite(x)) then
      s = trim(merge('+Infinity', '-Infinity', x > 0.0_wp))
      return
    else if (x == 0.0_wp) then
      s = '0.0'
      return
    end if
    do nd = 1, 17
      write (fmt, '(a,i0,a)') '(es40.', nd - 1, 'e3)'
      write (buf, fmt) x
      read (buf, *) y
      if (y == x) exit
    end do
    buf = adjustl(buf)
    ie = index(buf, 'E')
    read (buf(ie + 1:), *) e
    sgn = trim(merge('-', ' ', buf(1:1) == '-'))
    digits = ''
    do j = 1, ie - 1
      if (scan(buf(j:j), '0123456789') == 1) digits = digits//buf(j:j)
    end do
    if (e >= -4 .and. e < 6) then
      if (e >= 0) then
        if (len(digits) < e + 1) digits = digits//repeat('0', e + 1 - len(digits))
        s = digits(1:e + 1)//'.'
        if (len(digits) > e + 1) then
          s = s//digits(e + 2:)
        else
          s = s//'0'
        end if
      else
        s = '0.'//repeat('0', -e - 1)//digits
      end if
    else
      s = digits(1:1)//'.'
      if (len(digits) > 1) then
        s = s//digits(2:)
      else
        s = s//'0'
      end if
      s = s//'e'//itoa(e)
    end if
    s = sgn//s
  end function rtoa

  !> x in fixed notation with d decimals, with its leading zero ("0.5", where the f0.d
  !> edit descriptor writes ".5").
  pure function ftoa(x, d) result(str)
    real(wp), intent(in) :: x
    integer, intent(in) :: d
    character(len=:), allocatable :: str
    character(len=40) :: buf, fmt
    write (fmt, '(a,i0,a)') '(f0.', d, ')'
    write (buf, fmt) x
    str = trim(adjustl(buf))
    if (str(1:1) == '.') then
      str = '0'//str
    else if (len(str) > 1) then
      if (str(1:2) == '-.') str = '-0'//str(2:)
    end if
  end function ftoa

  !> A string in single quotes, trailing blanks removed, inner quotes doubled.
  pure function quote(s) result(q)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: q
    integer :: j
    q = "'"
    do j = 1, len_trim(s)
      q = q//s(j:j)
      if (s(j:j) == "'") q = q//"'"
    end do
    q = q//"'"
  end function quote

  !> s with the ASCII capitals made small.
  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: j
    t = s
    do j = 1, len(s)
      if (s(j:j) >= 'A' .and. s(j:j) <= 'Z') t(j:j) = achar(iachar(s(j:j)) + 32)
    end do
  end function lower

  !> Bounds i..j of the first word of list at or after position from (words are separated
  !> by blanks or commas); i > j when there is none.
  pure subroutine next_word(list, from, i, j)
    character(len=*), intent(in) :: list
    integer, intent(in) :: from
    integer, intent(out) :: i, j
    integer :: n
    n = len_trim(list)
    i = from
    do while (i <= n)
      if (list(i:i) /= ' ' .and. list(i:i) /= ',') exit
      i = i + 1
    end do
    j = i - 1
    do while (j < n)
      if (list(j + 1:j + 1) == ' ' .or. list(j + 1:j + 1) == ',') exit
      j = j + 1
    end do
  end subroutine next_word

end module dpmpm_strings
