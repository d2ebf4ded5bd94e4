!> dpmpm: double-point material point method. Usage:
!>   mpirun -n N dpmpm scene.nml          run the scene
!>   mpirun -n N dpmpm --check scene.nml  validate and print the resolved parameters
!>   dpmpm --help | --version             usage and exit codes | version and git commit
program dpmpm
  use dpmpm_mpi_start, only: start_mpi
  use mpi_f08, only: MPI_Finalize, MPI_COMM_WORLD
  use dpmpm_app, only: run_app
  implicit none
  integer :: status
  call start_mpi()
  status = run_app(MPI_COMM_WORLD)
  call MPI_Finalize()
  ! The exit status of the run (dpmpm --help lists them), without a runtime message.
  if (status /= 0) stop status, quiet = .true.
end program dpmpm
