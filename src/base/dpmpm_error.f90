!> The one error path of dpmpm: a message with the rank on stderr, then MPI_Abort.
!> Used for conditions that only some ranks may hit (a point leaving the grid, a
!> failed HDF5 call), where a collective stop would hang the others.
module dpmpm_error
  use, intrinsic :: iso_fortran_env, only: error_unit
  use mpi_f08, only: MPI_Abort, MPI_COMM_WORLD, MPI_Comm_rank, MPI_Initialized
  implicit none
  private
  public :: fatal

contains

  !> Print "dpmpm: error on rank R: <where>: <message>" and abort all ranks.
  subroutine fatal(message, where)
    character(len=*), intent(in) :: message
    character(len=*), intent(in), optional :: where
    integer :: rank
    logical :: up
    call MPI_Initialized(up)
    rank = -1
    if (up) call MPI_Comm_rank(MPI_COMM_WORLD, rank)
    if (present(where)) then
      write (error_unit, '(a,i0,a)') 'dpmpm: error on rank ', rank, ': '//where//': '//message
    else
      write (error_unit, '(a,i0,a)') 'dpmpm: error on rank ', rank, ': '//message
    end if
    flush (error_unit)
    if (up) call MPI_Abort(MPI_COMM_WORLD, 1)
    stop 1, quiet = .true.
  end subroutine fatal

end module dpmpm_error
