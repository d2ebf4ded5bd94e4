!> The main block that every test program shares: MPI started as dpmpm's runs start it,
!> passes printed by rank 0 only, and at the end the failures of all ranks counted, MPI
!> finalized and the exit code that ctest reads (1 when a check failed).
module dpmpm_test_main
  use mpi_f08, only: MPI_Finalize, MPI_COMM_WORLD, MPI_Comm_rank, MPI_Comm_size
  use dpmpm_mpi_start, only: start_mpi
  use dpmpm_assert, only: finish_tests, am_root
  implicit none
  private
  public :: start_tests, end_tests, test_dir

contains

  !> start_mpi (the MPI-IO layer of a run), and only rank 0 prints passes; rank is this
  !> process's rank in MPI_COMM_WORLD.
  subroutine start_tests(rank)
    integer, intent(out), optional :: rank
    integer :: me
    call start_mpi()
    call MPI_Comm_rank(MPI_COMM_WORLD, me)
    am_root = me == 0
    if (present(rank)) rank = me
  end subroutine start_tests

  !> The summary line over every rank, MPI_Finalize, and stop with exit code 1 when a
  !> check failed on any rank.
  subroutine end_tests()
    integer :: status
    status = finish_tests(MPI_COMM_WORLD)
    call MPI_Finalize()
    if (status /= 0) stop 1, quiet = .true.
  end subroutine end_tests

  !> The directory a test program writes its runs into: out/<name>_np<ranks>, so that
  !> ctest -j may run the program on 1 and on 2 ranks at once without either writing into
  !> the other's files.
  function test_dir(name) result(dir)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: dir
    character(len=12) :: n
    integer :: nranks
    call MPI_Comm_size(MPI_COMM_WORLD, nranks)
    write (n, '(i0)') nranks
    dir = 'out/'//name//'_np'//trim(n)
  end function test_dir

end module dpmpm_test_main
