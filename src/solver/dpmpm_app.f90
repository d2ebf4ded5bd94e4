!> The dpmpm program: command line, input, scene, run.
module dpmpm_app
  use mpi_f08, only: MPI_Comm
  implicit none
  private
  public :: run_app
contains
  !> Run dpmpm on the ranks of comm.
  subroutine run_app(comm)
    type(MPI_Comm), intent(in) :: comm
    integer :: n
    n = command_argument_count()
    if (n < 1) write (*, '(a)') 'usage: dpmpm [--check] scene.nml'
    if (.false.) print *, comm%mpi_val
  end subroutine run_app
end module dpmpm_app
