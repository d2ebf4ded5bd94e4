!> dpmpm: double-point material point method. Usage:
!>   mpirun -n N dpmpm scene.nml          run the scene
!>   mpirun -n N dpmpm --check scene.nml  validate and print the resolved parameters
!>   dpmpm --help | --version             usage and exit codes | version and git commit
program dpmpm
  use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_COMM_WORLD
  use dpmpm_app, only: run_app
  implicit none
  call MPI_Init()
  call run_app(MPI_COMM_WORLD)
  call MPI_Finalize()
end program dpmpm
