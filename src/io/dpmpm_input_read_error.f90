!> What went wrong reading a namelist group: the compiler's message names the variable
!> where its reader stopped, which is not always the one at fault (after a vector given in
!> part it blames the vector for the next name); so the group's text is looked at for names
!> that are no variable of the group and indices beyond a variable's size, each reported
!> with its own line (dpmpm_input_read calls read_error when a group does not read).
module dpmpm_input_read_error
  use dpmpm_input_problems, only: input_problems_t, group_names, add_raw, place
  use dpmpm_strings, only: itoa, lower
  use dpmpm_nml_text, only: nml_names, nml_size
  implicit none
  private
  public :: read_error, is_name_char

contains

  !> Record a namelist read error of occurrence k of group g, whose variables are written in
  !> echo. The compiler's message names the variable where the reader stopped, which is not
  !> always the one at fault (after a vector given in part it blames the vector for the next
  !> name); so the group's text is looked at first for names that are no variable of the
  !> group and indices beyond a variable's size, each reported with its own line.
  subroutine read_error(pb, g, k, ios, msg, echo, records)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, k, ios
    character(len=*), intent(in) :: msg, echo(:), records(:)
    character(len=*), parameter :: nomatch = 'Cannot match namelist object name '
    character(len=:), allocatable :: what, hint, word, names
    integer :: i
    logical :: is_name
    names = nml_names(echo)
    if (ios > 0) then
      if (bad_assignments(pb, g, k, echo, records) > 0) return
    end if
    if (ios < 0) then
      what = 'the namelist reader did not find this group (is it terminated by "/"?)'
    else
      what = trim(msg)
    end if
    hint = ''
    if (index(msg, nomatch) == 1) then
      word = trim(msg(len(nomatch) + 1:))
      is_name = len(word) > 0
      if (is_name) is_name = scan(lower(word(1:1)), 'abcdefghijklmnopqrstuvwxyz') == 1
      do i = 1, len(word)
        if (.not. is_name_char(word(i:i))) is_name = .false.
      end do
      if (is_name) then
        hint = ' (no such variable)'
      else
        hint = ' (a value that does not fit the variable before it: a string or a fraction for'// &
               ' an integer, or more values than the variable holds)'
      end if
    end if
    call add_raw(pb, '&'//trim(group_names(g))//': cannot read the group: '//what//hint// &
                 '; the variables of &'//trim(group_names(g))//' are '//names// &
                 place(pb, g, k))
  end subroutine read_error

  !> Look at the text of occurrence k of group g (from its opening line to its closing "/")
  !> for assignments "name = " or "name(index) = " whose name is no variable of the group
  !> (the group written in echo) or whose index lies beyond the variable's size; each is a
  !> problem naming its line. n: the problems found.
  integer function bad_assignments(pb, g, k, echo, records) result(n)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, k
    character(len=*), intent(in) :: echo(:), records(:)
    character(len=1) :: quote
    character(len=:), allocatable :: name, sub
    integer :: r, i, j, m, p, last
    n = 0
    r = pb%line_of(g, k)
    if (r < 1 .or. r > size(records)) return
    ! past "&group" on its line
    i = index(records(r), '&') + 1
    do while (i <= len(records(r)))
      if (.not. is_name_char(records(r) (i:i))) exit
      i = i + 1
    end do
    quote = ' '
    do while (r <= size(records))
      last = len_trim(records(r))
      do while (i <= last)
        associate (line => records(r))
          if (quote /= ' ') then
            if (line(i:i) == quote) quote = ' '
            i = i + 1
            cycle
          end if
          select case (line(i:i))
          case ("'", '"')
            quote = line(i:i)
            i = i + 1
          case ('!')
            exit
          case ('/')
            return
          case ('a':'z', 'A':'Z')
            j = i
            do while (j <= last)
              if (.not. (is_name_char(line(j:j)) .or. line(j:j) == '%')) exit
              j = j + 1
            end do
            name = lower(line(i:j - 1))
            m = skip_blanks(line, j)
            sub = ''
            if (m <= last) then
              if (line(m:m) == '(') then
                p = index(line(m:), ')')
                if (p > 0) then
                  sub = line(m + 1:m + p - 2)
                  m = skip_blanks(line, m + p)
                end if
              end if
            end if
            i = j
            if (m <= last) then
              if (line(m:m) == '=') then
                n = n + bad_assignment(pb, g, name, sub, r, echo)
                i = m + 1
              end if
            end if
          case default
            i = i + 1
          end select
        end associate
      end do
      r = r + 1
      i = 1
    end do
  end function bad_assignments

  !> First position at or after i of line that is not a blank (len(line) + 1 if none).
  pure integer function skip_blanks(line, i) result(j)
    character(len=*), intent(in) :: line
    integer, intent(in) :: i
    j = i
    do while (j <= len(line))
      if (line(j:j) /= ' ' .and. line(j:j) /= char(9)) exit
      j = j + 1
    end do
  end function skip_blanks

  !> 1 (and a problem) if "name(sub) =" at line of group g names no variable of the group
  !> written in echo, or an index beyond the variable's size; else 0. A subscript of more
  !> than one dimension is left to the compiler.
  integer function bad_assignment(pb, g, name, sub, line, echo) result(n)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, line
    character(len=*), intent(in) :: name, sub, echo(:)
    character(len=:), allocatable :: grp, at
    integer :: nval, colon, lo, hi, ios
    n = 0
    if (index(name, '%') > 0) return
    grp = '&'//trim(group_names(g))
    nval = nml_size(echo, name)
    at = ' (line '//itoa(line)//')'
    if (nval == 0) then
      call add_raw(pb, grp//' '//name//at//': no such variable; the variables of '//grp// &
                   ' are '//nml_names(echo))
      n = 1
      return
    end if
    if (len_trim(sub) == 0 .or. index(sub, ',') > 0) return
    colon = index(sub, ':')
    lo = 1
    hi = nval
    ios = 0
    if (colon == 0) then
      read (sub, *, iostat=ios) lo
      hi = lo
    else
      if (len_trim(sub(1:colon - 1)) > 0) read (sub(1:colon - 1), *, iostat=ios) lo
      if (ios == 0 .and. len_trim(sub(colon + 1:)) > 0) read (sub(colon + 1:), *, iostat=ios) hi
    end if
    if (ios /= 0 .or. (lo >= 1 .and. hi <= nval)) return
    call add_raw(pb, grp//' '//name//'('//trim(adjustl(sub))//')'//at//': index '// &
                 itoa(merge(lo, hi, lo < 1 .or. lo > nval))//' is out of range: '//name// &
                 ' has '//itoa(nval)//' entries, 1 to '//itoa(nval))
    n = 1
  end function bad_assignment

  !> True for a character that may stand in a Fortran name (letters, digits, underscore).
  pure logical function is_name_char(c)
    character(len=1), intent(in) :: c
    is_name_char = scan(c, 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_') == 1
  end function is_name_char

end module dpmpm_input_read_error
