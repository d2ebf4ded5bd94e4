!> Rank-0 logging: one helper for everything printed to stdout.
module dpmpm_log
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank
  implicit none
  private
  public :: log_t

  !> Prints only on rank 0 of its communicator.
  type :: log_t
    logical :: root = .true.
  contains
    procedure :: init => log_init
    procedure :: info => log_info
    procedure :: error => log_error
    procedure :: warning => log_warning
  end type log_t

contains

  !> Attach the logger to a communicator: only its rank 0 prints.
  subroutine log_init(self, comm)
    class(log_t), intent(inout) :: self
    type(MPI_Comm), intent(in) :: comm
    integer :: rank
    call MPI_Comm_rank(comm, rank)
    self%root = (rank == 0)
  end subroutine log_init

  !> Print one line on rank 0 and flush, so batch logs show progress as it happens.
  subroutine log_info(self, line)
    class(log_t), intent(in) :: self
    character(len=*), intent(in) :: line
    if (.not. self%root) return
    write (output_unit, '(a)') trim(line)
    flush (output_unit)
  end subroutine log_info

  !> Print one error line on rank 0 to stderr, prefixed "dpmpm: error: ".
  subroutine log_error(self, line)
    class(log_t), intent(in) :: self
    character(len=*), intent(in) :: line
    if (.not. self%root) return
    write (error_unit, '(a)') 'dpmpm: error: '//trim(line)
    flush (error_unit)
  end subroutine log_error

  !> Print one warning line on rank 0 to stderr, prefixed "dpmpm: warning: ".
  subroutine log_warning(self, line)
    class(log_t), intent(in) :: self
    character(len=*), intent(in) :: line
    if (.not. self%root) return
    write (error_unit, '(a)') 'dpmpm: warning: '//trim(line)
    flush (error_unit)
  end subroutine log_warning

end module dpmpm_log
