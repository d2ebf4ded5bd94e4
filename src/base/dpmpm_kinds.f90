!> Kinds used throughout dpmpm and the MPI datatypes that match them.
module dpmpm_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int64, int32
  use mpi_f08, only: MPI_Datatype, MPI_DOUBLE_PRECISION, MPI_INTEGER8
  implicit none
  private
  public :: wp, i8, i4, mpi_wp, mpi_i8

  !> Working precision for all reals (double).
  integer, parameter :: wp = real64
  !> 64-bit integers for global point ids and global counts.
  integer, parameter :: i8 = int64
  !> Default 32-bit integers (named for clarity in interfaces).
  integer, parameter :: i4 = int32

contains

  !> MPI datatype matching real(wp).
  function mpi_wp() result(t)
    type(MPI_Datatype) :: t
    t = MPI_DOUBLE_PRECISION
  end function mpi_wp

  !> MPI datatype matching integer(i8).
  function mpi_i8() result(t)
    type(MPI_Datatype) :: t
    t = MPI_INTEGER8
  end function mpi_i8

end module dpmpm_kinds
