!> A namelist group as the compiler writes it (write (records, nml=group)) turned
!> into the input's own style: one "  name = value" line per variable, names in
!> lower case, strings without their padding, reals in their shortest form that
!> reads back to the same number, logicals as .true./.false. The group's reader
!> writes its namelist, so the echo of the input and the list of a group's
!> variables in messages follow the namelist and need no list of their own.
module dpmpm_nml_text
  use dpmpm_kinds, only: wp
  use dpmpm_strings, only: lower, rtoa
  implicit none
  private
  public :: nml_records, nml_echo, nml_names, nml_size

  !> Record length and count of the internal file a group is written to: one
  !> variable per record, the longest a 4096-character string or 64 reals.
  integer, parameter :: rec_len = 8192, max_recs = 64

contains

  !> Blank records to write a namelist group into.
  subroutine nml_records(records)
    character(len=:), allocatable, intent(out) :: records(:)
    allocate (character(len=rec_len) :: records(max_recs))
    records = ''
  end subroutine nml_records

  !> The group in records as input text, one line per variable, ending in a new line.
  function nml_echo(records) result(text)
    character(len=*), intent(in) :: records(:)
    character(len=:), allocatable :: text
    character(len=:), allocatable :: rec, var, val
    integer :: k
    logical :: ok
    text = ''
    do k = 1, size(records)
      rec = trim(adjustl(records(k)))
      if (len(rec) == 0) cycle
      if (rec(1:1) == '&') then
        text = text//lower(rec)//new_line('a')
      else if (rec == '/') then
        text = text//'/'//new_line('a')
      else
        call variable_record(records(k), var, val, ok)
        if (ok) text = text//'  '//var//' = '//values_text(val)//new_line('a')
      end if
    end do
  end function nml_echo

  !> The variables of the group in records, as "a, b, c".
  function nml_names(records) result(list)
    character(len=*), intent(in) :: records(:)
    character(len=:), allocatable :: list
    character(len=:), allocatable :: var, val
    integer :: k
    logical :: ok
    list = ''
    do k = 1, size(records)
      call variable_record(records(k), var, val, ok)
      if (.not. ok) cycle
      if (len(list) > 0) list = list//', '
      list = list//var
    end do
  end function nml_names

  !> The number of values of variable name (lower case) in the group in records: 1 for a
  !> scalar, the size of an array; 0 when the group has no such variable.
  integer function nml_size(records, name) result(n)
    character(len=*), intent(in) :: records(:)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: var, val
    integer :: k
    logical :: ok
    n = 0
    do k = 1, size(records)
      call variable_record(records(k), var, val, ok)
      if (.not. ok) cycle
      if (var /= name) cycle
      n = values_count(val)
      return
    end do
  end function nml_size

  !> One record of a written group split into its variable's name (lower case) and the
  !> text of its values; ok is .false. for a blank record, the group's first and last
  !> records (&name, /) and a record with no "=".
  subroutine variable_record(record, var, val, ok)
    character(len=*), intent(in) :: record
    character(len=:), allocatable, intent(out) :: var, val
    logical, intent(out) :: ok
    character(len=:), allocatable :: rec
    integer :: eq
    ok = .false.
    rec = trim(adjustl(record))
    if (len(rec) == 0) return
    if (rec(1:1) == '&' .or. rec == '/') return
    eq = index(rec, '=')
    if (eq == 0) return
    var = lower(trim(rec(1:eq - 1)))
    val = rec(eq + 1:)
    ok = .true.
  end subroutine variable_record

  !> How many values the compiler's list s ("1.0, 2*0.5, "a, b"") stands for.
  integer function values_count(s) result(n)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: tok
    integer :: pos, star, r, ios
    logical :: found
    n = 0
    pos = 1
    do
      call next_value(s, pos, tok, found)
      if (.not. found) exit
      r = 1
      star = index(tok, '*')
      if (star > 1 .and. tok(1:1) /= '"') then
        read (tok(1:star - 1), *, iostat=ios) r
        if (ios /= 0) r = 1
      end if
      n = n + r
    end do
  end function values_count

  !> The comma-separated values of one variable, each in the input's style.
  function values_text(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    character(len=:), allocatable :: tok
    integer :: pos
    logical :: found
    t = ''
    pos = 1
    do
      call next_value(s, pos, tok, found)
      if (.not. found) exit
      if (len(t) > 0) t = t//', '
      t = t//value_text(tok)
    end do
  end function values_text

  !> The next nonempty value of the comma-separated list s from position pos on (a comma
  !> inside "..." does not split), adjusted and trimmed, in tok; pos moves past its comma.
  !> found: .false. once the list is used up.
  subroutine next_value(s, pos, tok, found)
    character(len=*), intent(in) :: s
    integer, intent(inout) :: pos
    character(len=:), allocatable, intent(out) :: tok
    logical, intent(out) :: found
    integer :: i
    logical :: quoted
    found = .false.
    quoted = .false.
    do i = pos, len(s) + 1
      if (i <= len(s)) then
        if (s(i:i) == '"') quoted = .not. quoted
        if (quoted .or. s(i:i) /= ',') cycle
      end if
      tok = trim(adjustl(s(pos:i - 1)))
      pos = i + 1
      if (len(tok) == 0) cycle
      found = .true.
      return
    end do
  end subroutine next_value

  !> One value as written by the compiler ("text", T, 7*0.5, 1.5000000000000000,
  !> 12) in the input's style.
  recursive function value_text(tok) result(t)
    character(len=*), intent(in) :: tok
    character(len=:), allocatable :: t
    integer :: star, ios
    real(wp) :: x
    if (tok(1:1) == '"') then
      t = '"'//trim(tok(2:len(tok) - 1))//'"'
      return
    end if
    star = index(tok, '*')
    if (star > 0) then
      t = tok(1:star)//value_text(tok(star + 1:))
    else if (tok == 'T') then
      t = '.true.'
    else if (tok == 'F') then
      t = '.false.'
    else if (scan(tok, '.Ee') > 0) then
      read (tok, *, iostat=ios) x
      t = tok
      if (ios == 0) t = rtoa(x)
    else
      t = tok
    end if
  end function value_text

end module dpmpm_nml_text
