!> A small assertion module for dpmpm's Fortran test programs. Each test is one
!> procedure; a failing check prints the test, the check and the values, and the
!> program's exit code counts the failures (ctest reads the exit code).
module dpmpm_assert
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: check, check_close, check_equal_int, begin_test, finish_tests, nfailed
  public :: am_root

  integer :: nfailed = 0
  integer :: nchecks = 0
  integer :: ntests = 0
  character(len=128) :: current = ''
  !> Only this process prints passes (set false on ranks other than 0).
  logical :: am_root = .true.

contains

  !> Name the test whose checks follow.
  subroutine begin_test(name)
    character(len=*), intent(in) :: name
    current = name
    ntests = ntests + 1
    if (am_root) write (output_unit, '(a)') 'test: '//trim(name)
  end subroutine begin_test

  !> A logical condition.
  subroutine check(cond, what)
    logical, intent(in) :: cond
    character(len=*), intent(in) :: what
    nchecks = nchecks + 1
    if (.not. cond) then
      nfailed = nfailed + 1
      write (error_unit, '(a)') 'FAIL in '//trim(current)//': '//what
    end if
  end subroutine check

  !> |a - b| <= atol + rtol*|b|.
  subroutine check_close(a, b, rtol, atol, what)
    real(wp), intent(in) :: a, b, rtol, atol
    character(len=*), intent(in) :: what
    nchecks = nchecks + 1
    if (.not. (abs(a - b) <= atol + rtol*abs(b))) then
      nfailed = nfailed + 1
      write (error_unit, '(a,es24.16,a,es24.16,a,es10.3)') 'FAIL in '//trim(current)//': '// &
        what//': got ', a, ' expected ', b, ' diff ', abs(a - b)
    end if
  end subroutine check_close

  !> Integer equality.
  subroutine check_equal_int(a, b, what)
    integer, intent(in) :: a, b
    character(len=*), intent(in) :: what
    nchecks = nchecks + 1
    if (a /= b) then
      nfailed = nfailed + 1
      write (error_unit, '(a,i0,a,i0)') 'FAIL in '//trim(current)//': '//what//': got ', a, &
        ' expected ', b
    end if
  end subroutine check_equal_int

  !> Print the summary line and return the exit status (0 when all passed).
  !> With comm, the failures of all ranks are added so every rank returns the same status.
  integer function finish_tests(comm) result(status)
    use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER, MPI_SUM
    type(MPI_Comm), intent(in), optional :: comm
    if (present(comm)) call MPI_Allreduce(MPI_IN_PLACE, nfailed, 1, MPI_INTEGER, MPI_SUM, comm)
    if (am_root) write (output_unit, '(i0,a,i0,a,i0,a)') ntests, ' tests, ', nchecks, &
      ' checks, ', nfailed, ' failed'
    status = merge(0, 1, nfailed == 0)
  end function finish_tests

end module dpmpm_assert
