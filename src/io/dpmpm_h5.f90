!> Small serial-or-collective HDF5 helpers shared by the writers of dpmpm: a
!> checked call, scalar attributes of the project's types, fixed-length strings,
!> and creating an output directory.
module dpmpm_h5
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_char, c_null_char, c_int
  use hdf5, only: hid_t, size_t, h5screate_f, h5sclose_f, h5acreate_f, h5awrite_f, h5aclose_f, &
                  h5tcopy_f, h5tset_size_f, h5tset_strpad_f, h5kind_to_type, H5_REAL_KIND, &
                  H5_INTEGER_KIND, H5S_SCALAR_F, H5T_C_S1, H5T_STR_NULLPAD_F, H5T_IEEE_F64LE, &
                  H5T_STD_I64LE, H5T_STD_I32LE, h5tclose_f, hsize_t, h5screate_simple_f, &
                  h5dcreate_f, h5dwrite_f, h5dclose_f, h5sselect_hyperslab_f, h5sselect_none_f, &
                  H5S_SELECT_SET_F
  use dpmpm_kinds, only: wp, i8, i4
  use dpmpm_error, only: fatal
  implicit none
  private
  public :: h5check, make_dir, string_type, attr_string, attr_i4, attr_i8, attr_real, rename_file
  public :: write_columns

  interface
    function c_rename(old, new) bind(C, name='rename') result(r)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*), new(*)
      integer(c_int) :: r
    end function c_rename
  end interface

contains

  !> Abort with the failing HDF5 call named when err reports a failure.
  subroutine h5check(err, call_name, where)
    integer, intent(in) :: err
    character(len=*), intent(in) :: call_name, where
    if (err < 0) call fatal(call_name//' failed', where)
  end subroutine h5check

  !> Create a directory and its parents unless they exist, one mkdir(2) per component and
  !> no shell, so any character in the name is taken literally. Called on one rank.
  subroutine make_dir(dir)
    use dpmpm_posix, only: posix_mkdir, posix_strerror
    character(len=*), intent(in) :: dir
    integer :: i, err
    ! Each parent in turn (not the root "/", nor the empty name between two slashes).
    do i = 2, len(dir)
      if (dir(i:i) /= '/' .or. dir(i - 1:i - 1) == '/') cycle
      err = posix_mkdir(dir(1:i - 1))
      if (err /= 0) call fatal('cannot create output directory '//dir//': '//dir(1:i - 1)// &
                               ': '//posix_strerror(err), 'make_dir')
    end do
    err = posix_mkdir(dir)
    if (err /= 0) call fatal('cannot create output directory '//dir//': '// &
                             posix_strerror(err), 'make_dir')
  end subroutine make_dir

  !> A fixed-length, null-padded string type of n bytes (h5py reads it as bytes).
  function string_type(n) result(t)
    integer, intent(in) :: n
    integer(hid_t) :: t
    integer :: err
    call h5tcopy_f(H5T_C_S1, t, err)
    call h5check(err, 'h5tcopy_f(H5T_C_S1)', 'string_type')
    call h5tset_size_f(t, int(n, size_t), err)
    call h5check(err, 'h5tset_size_f', 'string_type')
    call h5tset_strpad_f(t, H5T_STR_NULLPAD_F, err)
    call h5check(err, 'h5tset_strpad_f', 'string_type')
  end function string_type

  !> Create and write one scalar attribute from the bytes at ptr.
  subroutine put_attr(loc, name, ftype, mtype, ptr)
    integer(hid_t), intent(in) :: loc, ftype, mtype
    character(len=*), intent(in) :: name
    type(c_ptr), intent(in) :: ptr
    integer(hid_t) :: space, attr
    integer :: err
    call h5screate_f(H5S_SCALAR_F, space, err)
    call h5check(err, 'h5screate_f(scalar)', 'attribute '//name)
    call h5acreate_f(loc, name, ftype, space, attr, err)
    call h5check(err, 'h5acreate_f', 'attribute '//name)
    call h5awrite_f(attr, mtype, ptr, err)
    call h5check(err, 'h5awrite_f', 'attribute '//name)
    call h5aclose_f(attr, err)
    call h5check(err, 'h5aclose_f', 'attribute '//name)
    call h5sclose_f(space, err)
    call h5check(err, 'h5sclose_f', 'attribute '//name)
  end subroutine put_attr

  !> Scalar string attribute.
  subroutine attr_string(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name, value
    character(kind=c_char, len=max(len(value), 1)), target :: buf
    integer(hid_t) :: stype
    integer :: err
    buf = value
    if (len(value) == 0) buf = c_null_char
    stype = string_type(len(buf))
    call put_attr(loc, name, stype, stype, c_loc(buf))
    call h5tclose_f(stype, err)
    call h5check(err, 'h5tclose_f', 'attribute '//name)
  end subroutine attr_string

  !> Scalar int32 attribute.
  subroutine attr_i4(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(i4), intent(in) :: value
    integer(i4), target :: buf
    buf = value
    call put_attr(loc, name, H5T_STD_I32LE, h5kind_to_type(i4, H5_INTEGER_KIND), c_loc(buf))
  end subroutine attr_i4

  !> Scalar int64 attribute.
  subroutine attr_i8(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(i8), intent(in) :: value
    integer(i8), target :: buf
    buf = value
    call put_attr(loc, name, H5T_STD_I64LE, h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(buf))
  end subroutine attr_i8

  !> Scalar double attribute.
  subroutine attr_real(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: value
    real(wp), target :: buf
    buf = value
    call put_attr(loc, name, H5T_IEEE_F64LE, h5kind_to_type(wp, H5_REAL_KIND), c_loc(buf))
  end subroutine attr_real

  !> Rename a file (the last step of writing to a temporary name); fatal on failure.
  subroutine rename_file(old, new, where)
    character(len=*), intent(in) :: old, new, where
    if (c_rename(old//c_null_char, new//c_null_char) /= 0) &
      call fatal('cannot rename '//old//' to '//new, where)
  end subroutine rename_file

  !> Create dataset <name> under gid for nglob points and write this rank's nloc points at
  !> offset, collectively with the transfer list dxpl. m = 0: shape (nglob); m > 0: Fortran shape (m, nglob), (nglob, m) in C order.
  !> ptr points to nloc*m values (at least one element, even when nloc = 0).
  subroutine write_columns(gid, dxpl, name, ftype, mtype, m, nloc, offset, nglob, ptr, where)
    integer(hid_t), intent(in) :: gid, dxpl, ftype, mtype
    character(len=*), intent(in) :: name
    integer, intent(in) :: m
    integer(i8), intent(in) :: nloc, offset, nglob
    type(c_ptr), intent(in) :: ptr
    character(len=*), intent(in) :: where
    integer(hsize_t) :: fdims(2), mdims(2), start(2), cnt(2)
    integer(hid_t) :: fspace, mspace, dset
    integer :: rank, err
    if (m == 0) then
      rank = 1
      fdims(1) = int(nglob, hsize_t)
      mdims(1) = int(max(nloc, 1_i8), hsize_t)
      start(1) = int(offset, hsize_t)
      cnt(1) = int(nloc, hsize_t)
    else
      rank = 2
      fdims = [int(m, hsize_t), int(nglob, hsize_t)]
      mdims = [int(m, hsize_t), int(max(nloc, 1_i8), hsize_t)]
      start = [0_hsize_t, int(offset, hsize_t)]
      cnt = [int(m, hsize_t), int(nloc, hsize_t)]
    end if
    call h5screate_simple_f(rank, fdims(1:rank), fspace, err)
    call h5check(err, 'h5screate_simple_f('//name//')', where)
    call h5dcreate_f(gid, name, ftype, fspace, dset, err)
    call h5check(err, 'h5dcreate_f('//name//')', where)
    call h5screate_simple_f(rank, mdims(1:rank), mspace, err)
    call h5check(err, 'h5screate_simple_f('//name//')', where)
    if (nloc > 0) then
      call h5sselect_hyperslab_f(fspace, H5S_SELECT_SET_F, start(1:rank), cnt(1:rank), err)
      call h5check(err, 'h5sselect_hyperslab_f('//name//')', where)
    else
      call h5sselect_none_f(fspace, err)
      call h5check(err, 'h5sselect_none_f('//name//')', where)
      call h5sselect_none_f(mspace, err)
      call h5check(err, 'h5sselect_none_f('//name//')', where)
    end if
    ! An empty dataset has no storage to write to; nglob is the same on every rank.
    if (nglob > 0) then
      call h5dwrite_f(dset, mtype, ptr, err, mem_space_id=mspace, file_space_id=fspace, &
                      xfer_prp=dxpl)
      call h5check(err, 'h5dwrite_f('//name//')', where)
    end if
    call h5dclose_f(dset, err)
    call h5check(err, 'h5dclose_f('//name//')', where)
    call h5sclose_f(mspace, err)
    call h5check(err, 'h5sclose_f('//name//')', where)
    call h5sclose_f(fspace, err)
    call h5check(err, 'h5sclose_f('//name//')', where)
  end subroutine write_columns

end module dpmpm_h5
