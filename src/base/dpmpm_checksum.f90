!> Checksums of the datasets of a checkpoint (dpmpm_checkpoint), through the C file beside
!> this module (dpmpm_checksum.c). The checksum of a dataset of n columns (points; the
!> slowest index of its Fortran shape) is the exclusive or, over the columns j = 0 .. n-1, of
!> the 64-bit FNV-1a hash of j (8 bytes, least significant first) followed by the bytes of
!> column j as the file stores them. It depends on the data and their order in the file only:
!> each rank hashes the columns it wrote at their global numbers and the parts combine by
!> exclusive or, so the value is the same on any number of ranks, and a reader hashes what
!> it reads. FNV-1a finds damage (zeroed or cut blocks, flipped bits); it is no protection
!> against deliberate change.
module dpmpm_checksum
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int64_t
  use dpmpm_kinds, only: i8
  implicit none
  private
  public :: checksum_columns

  interface
    function c_checksum_columns(a, width, ncols, first) bind(C, name='dpmpm_checksum_columns') &
      result(h)
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: a
      integer(c_int64_t), value :: width, ncols, first
      integer(c_int64_t) :: h
    end function c_checksum_columns
  end interface

contains

  !> The checksum of ncols columns of width bytes each at a, the first of them column first
  !> (0-based) of the whole dataset; 0 for no columns. Parts combine with ieor.
  integer(i8) function checksum_columns(a, width, ncols, first) result(h)
    type(c_ptr), intent(in) :: a
    integer(i8), intent(in) :: width, ncols, first
    h = 0
    if (ncols <= 0) return
    h = int(c_checksum_columns(a, int(width, c_int64_t), int(ncols, c_int64_t), &
                               int(first, c_int64_t)), i8)
  end function checksum_columns

end module dpmpm_checksum
