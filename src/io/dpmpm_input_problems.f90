!> The groups of the namelist input (names, variables, where each opens in the file) and the
!> list of problems found while reading and checking it. Each problem is one line
!> "dpmpm: input error: <file>: <text> [where]"; they are collected, not printed one by one,
!> so that a user sees every problem of a file at once. A value that is valid but does
!> nothing in its scene is a warning, "dpmpm: input warning: ...", collected the same way:
!> the run goes on.
module dpmpm_input_problems
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use dpmpm_kinds, only: wp
  use dpmpm_strings, only: itoa, rtoa
  implicit none
  private
  public :: input_problems_t, ngroups, group_names, repeatable
  public :: g_run, g_grid, g_shape, g_material, g_region, g_boundary, g_load, g_output, g_benchmark
  public :: g_motion
  public :: add_value, add_raw, add_file_problem, add_warning, place, lines_of, real_ok
  public :: check_finite, prop_unset, count_given

  !> The mark of array values not given in a namelist (set before the read; count_given).
  real(wp), parameter :: prop_unset = -huge(1.0_wp)

  integer, parameter :: g_run = 1, g_grid = 2, g_shape = 3, g_material = 4, g_region = 5, &
                        g_boundary = 6, g_load = 7, g_output = 8, g_benchmark = 9, &
                        g_motion = 10, ngroups = 10
  character(len=9), parameter :: group_names(ngroups) = [character(len=9) :: 'run', 'grid', &
    'shape', 'material', 'region', 'boundary', 'load', 'output', 'benchmark', 'motion']
  logical, parameter :: repeatable(ngroups) = [.false., .false., .false., .true., .true., &
                                               .true., .true., .false., .false., .false.]
  character(len=*), parameter :: err_prefix = 'dpmpm: input error: '
  character(len=*), parameter :: warn_prefix = 'dpmpm: input warning: '

  !> A string of any length, to collect messages.
  type :: text_t
    character(len=:), allocatable :: s
  end type text_t

  !> What is known about one input file while it is read and checked: where each group
  !> opens, which groups could be read, and the problems found.
  type :: input_problems_t
    character(len=:), allocatable :: file
    integer :: count(ngroups) = 0                 !< openings of each group in the file
    logical :: read_ok(ngroups) = .true.          !< false for a group that could not be read
    integer :: nopen = 0
    integer, allocatable :: open_group(:), open_line(:)
    integer :: nprob = 0
    type(text_t), allocatable :: prob(:)
    integer :: nwarn = 0
    type(text_t), allocatable :: warn(:)          !< values that do nothing (the run goes on)
  contains
    procedure :: init => problems_init
    procedure :: free => problems_free
    procedure :: opened => problems_opened
    procedure :: line_of => problems_line_of
    procedure :: write => problems_write
    procedure :: write_warnings => problems_write_warnings
  end type input_problems_t

contains

  !> No problems yet for file (the name that the messages give).
  subroutine problems_init(self, file)
    class(input_problems_t), intent(inout) :: self
    character(len=*), intent(in) :: file
    call self%free()
    self%file = trim(file)
    allocate (self%open_group(16), self%open_line(16), self%prob(8))
  end subroutine problems_init

  !> Release everything init and the additions allocated; back to the state before init.
  subroutine problems_free(self)
    class(input_problems_t), intent(inout) :: self
    if (allocated(self%file)) deallocate (self%file)
    if (allocated(self%open_group)) deallocate (self%open_group)
    if (allocated(self%open_line)) deallocate (self%open_line)
    if (allocated(self%prob)) deallocate (self%prob)
    if (allocated(self%warn)) deallocate (self%warn)
    self%nwarn = 0
    self%count = 0
    self%read_ok = .true.
    self%nopen = 0
    self%nprob = 0
  end subroutine problems_free

  !> Group g opens at line (in the order of the file).
  subroutine problems_opened(self, g, line)
    class(input_problems_t), intent(inout) :: self
    integer, intent(in) :: g, line
    integer, allocatable :: tmp(:)
    integer :: cap
    if (.not. allocated(self%open_group)) allocate (self%open_group(16), self%open_line(16))
    cap = size(self%open_group)
    if (self%nopen == cap) then
      cap = 2*cap
      allocate (tmp(cap))
      tmp(1:self%nopen) = self%open_group(1:self%nopen)
      call move_alloc(tmp, self%open_group)
      allocate (tmp(cap))
      tmp(1:self%nopen) = self%open_line(1:self%nopen)
      call move_alloc(tmp, self%open_line)
    end if
    self%nopen = self%nopen + 1
    self%open_group(self%nopen) = g
    self%open_line(self%nopen) = line
    self%count(g) = self%count(g) + 1
  end subroutine problems_opened

  !> The line where occurrence k of group g opens, 0 if there is no such occurrence.
  pure integer function problems_line_of(self, g, k) result(line)
    class(input_problems_t), intent(in) :: self
    integer, intent(in) :: g, k
    integer :: j, seen
    line = 0
    seen = 0
    do j = 1, self%nopen
      if (self%open_group(j) /= g) cycle
      seen = seen + 1
      if (seen == k) then
        line = self%open_line(j)
        return
      end if
    end do
  end function problems_line_of

  !> Every problem, one per line, on unit.
  subroutine problems_write(self, unit)
    class(input_problems_t), intent(in) :: self
    integer, intent(in) :: unit
    integer :: k
    do k = 1, self%nprob
      write (unit, '(a)') self%prob(k)%s
    end do
    flush (unit)
  end subroutine problems_write

  !> Every warning, one per line, on unit.
  subroutine problems_write_warnings(self, unit)
    class(input_problems_t), intent(in) :: self
    integer, intent(in) :: unit
    integer :: k
    do k = 1, self%nwarn
      write (unit, '(a)') self%warn(k)%s
    end do
    flush (unit)
  end subroutine problems_write_warnings

  !> A value that is valid but does nothing: "&group var = value: why [where]", a warning.
  subroutine add_warning(pb, g, k, var, value, why)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, k
    character(len=*), intent(in) :: var, value, why
    call append(pb%warn, pb%nwarn, warn_prefix//pb%file//': &'//trim(group_names(g))//' '// &
                var//' = '//value//': '//why//place(pb, g, k))
  end subroutine add_warning

  !> A problem with one value: "&group var = value: allowed [where]".
  subroutine add_value(pb, g, k, var, value, allowed)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, k
    character(len=*), intent(in) :: var, value, allowed
    call add_raw(pb, '&'//trim(group_names(g))//' '//var//' = '//value//': '//allowed// &
                 place(pb, g, k))
  end subroutine add_value

  !> A problem with the file as a whole.
  subroutine add_file_problem(pb, what)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: what
    call add_raw(pb, what)
  end subroutine add_file_problem

  !> Append "dpmpm: input error: <file>: <text>" to the problems.
  subroutine add_raw(pb, text)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: text
    call append(pb%prob, pb%nprob, err_prefix//pb%file//': '//text)
  end subroutine add_raw

  !> Append line to the first n entries of list (grown as needed).
  subroutine append(list, n, line)
    type(text_t), allocatable, intent(inout) :: list(:)
    integer, intent(inout) :: n
    character(len=*), intent(in) :: line
    type(text_t), allocatable :: tmp(:)
    if (.not. allocated(list)) allocate (list(8))
    if (n == size(list)) then
      allocate (tmp(2*size(list)))
      tmp(1:n) = list(1:n)
      call move_alloc(tmp, list)
    end if
    n = n + 1
    list(n)%s = line
  end subroutine append

  !> " [line L]" or " [group k of n, line L]" for occurrence k of group g.
  function place(pb, g, k) result(s)
    type(input_problems_t), intent(in) :: pb
    integer, intent(in) :: g, k
    character(len=:), allocatable :: s
    integer :: j, seen
    s = ''
    seen = 0
    do j = 1, pb%nopen
      if (pb%open_group(j) /= g) cycle
      seen = seen + 1
      if (seen == k) then
        s = 'line '//itoa(pb%open_line(j))
        exit
      end if
    end do
    if (pb%count(g) > 1) then
      if (len(s) > 0) s = ', '//s
      s = 'group '//itoa(k)//' of '//itoa(pb%count(g))//s
    end if
    if (len(s) > 0) s = ' ['//trim(s)//']'
  end function place

  !> " (lines a, b, c)" listing where group g opens.
  function lines_of(pb, g) result(s)
    type(input_problems_t), intent(in) :: pb
    integer, intent(in) :: g
    character(len=:), allocatable :: s
    integer :: j
    s = ''
    do j = 1, pb%nopen
      if (pb%open_group(j) /= g) cycle
      if (len(s) > 0) s = s//', '
      s = s//itoa(pb%open_line(j))
    end do
    s = ' (lines '//s//')'
  end function lines_of

  !> True if x is finite and satisfies the bounds given (NaN never traps here).
  pure logical function real_ok(x, gt, ge, lt, le) result(ok)
    real(wp), intent(in) :: x
    real(wp), intent(in), optional :: gt, ge, lt, le
    ok = ieee_is_finite(x)
    if (.not. ok) return
    if (present(gt)) ok = ok .and. x > gt
    if (present(ge)) ok = ok .and. x >= ge
    if (present(lt)) ok = ok .and. x < lt
    if (present(le)) ok = ok .and. x <= le
  end function real_ok

  !> A problem when any value of x is not a finite number.
  subroutine check_finite(pb, g, k, var, x)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, k
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: x(:)
    integer :: j
    do j = 1, size(x)
      if (.not. ieee_is_finite(x(j))) then
        call add_value(pb, g, k, var//'('//itoa(j)//')', rtoa(x(j)), 'must be a finite number')
      end if
    end do
  end subroutine check_finite

  !> The number of values of a that the namelist gave (a was filled with prop_unset before
  !> the read): up to the last one given; the others become 0.
  integer function count_given(a) result(n)
    real(wp), intent(inout) :: a(:)
    integer :: j
    n = 0
    do j = 1, size(a)
      if (a(j) /= prop_unset) n = j
    end do
    where (a == prop_unset) a = 0.0_wp
  end function count_given

end module dpmpm_input_problems
