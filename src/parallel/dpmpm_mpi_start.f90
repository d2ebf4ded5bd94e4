!> Start MPI with the settings dpmpm's output needs. With Open MPI, the MPI-IO layer OMPIO
!> (the default of Open MPI 4) has put one rank's block of a collective HDF5 write in the
!> wrong place on 3 ranks (28 of 60 point-set frames of a two-phase scene); ROMIO wrote
!> every frame right. Open MPI reads its component choice from the environment at
!> MPI_Init, so start_mpi excludes OMPIO there unless the user chose a layer:
!> OMPI_MCA_io=ompio (or any other value) set before the run is kept as it is. Other MPI
!> libraries ignore the variable.
module dpmpm_mpi_start
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use mpi_f08, only: MPI_Init
  implicit none
  private
  public :: start_mpi, io_layer_variable, io_layer_default

  !> The Open MPI variable that selects the MPI-IO component, and dpmpm's default value
  !> for it (every component but OMPIO: ROMIO in Open MPI 4 and 5).
  character(len=*), parameter :: io_layer_variable = 'OMPI_MCA_io'
  character(len=*), parameter :: io_layer_default = '^ompio'

  interface
    function c_setenv(name, value, overwrite) bind(C, name='setenv') result(r)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: name(*), value(*)
      integer(c_int), value :: overwrite
      integer(c_int) :: r
    end function c_setenv
  end interface

contains

  !> MPI_Init, after choosing the MPI-IO layer as described above (an existing choice in
  !> the environment wins).
  subroutine start_mpi()
    integer(c_int) :: r
    r = c_setenv(io_layer_variable//c_null_char, io_layer_default//c_null_char, 0_c_int)
    call MPI_Init()
  end subroutine start_mpi

end module dpmpm_mpi_start
