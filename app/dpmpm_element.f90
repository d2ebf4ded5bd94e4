!> dpmpm_element: one material point driven along a laboratory path (isotropic,
!> oedometer, triaxial, simple shear; monotonic or cyclic; strain or stress control) by the
!> constitutive models of the simulation, for calibration. Usage:
!>   dpmpm_element test.nml | --check test.nml | --help | --version
program dpmpm_element
  use dpmpm_mpi_start, only: start_mpi
  use mpi_f08, only: MPI_Finalize, MPI_COMM_WORLD
  use dpmpm_element_app, only: run_element_app
  implicit none
  integer :: status
  call start_mpi()
  status = run_element_app(MPI_COMM_WORLD)
  call MPI_Finalize()
  ! the exit status of the test (dpmpm_element --help lists them), without a runtime message
  if (status /= 0) stop status, quiet = .true.
end program dpmpm_element
