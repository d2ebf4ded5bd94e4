!> Small serial-or-collective HDF5 helpers shared by the writers of dpmpm: a
!> checked call, scalar attributes of the project's types, fixed-length strings,
!> and creating an output directory.
module dpmpm_h5
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_char, c_null_char, c_int, c_f_pointer
  use, intrinsic :: iso_fortran_env, only: int8
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_Barrier, MPI_INTEGER, MPI_SUM, MPI_LOGICAL, &
                     MPI_LOR, MPI_INFO_NULL
  use hdf5, only: hid_t, size_t, h5screate_f, h5sclose_f, h5acreate_f, h5awrite_f, h5aclose_f, &
                  h5tcopy_f, h5tset_size_f, h5tset_strpad_f, h5kind_to_type, H5_REAL_KIND, &
                  H5_INTEGER_KIND, H5S_SCALAR_F, H5T_C_S1, H5T_STR_NULLPAD_F, H5T_IEEE_F64LE, &
                  H5T_STD_I64LE, H5T_STD_I32LE, h5tclose_f, hsize_t, h5screate_simple_f, &
                  h5dcreate_f, h5dwrite_f, h5dclose_f, h5sselect_hyperslab_f, h5sselect_none_f, &
                  H5S_SELECT_SET_F, h5dread_f, h5dget_space_f, h5fflush_f, h5iinc_ref_f, &
                  h5tget_size_f, H5F_SCOPE_GLOBAL_F, h5pcreate_f, h5pclose_f, h5pset_chunk_f, &
                  h5pset_shuffle_f, h5pset_deflate_f, H5P_DATASET_CREATE_F, H5P_DEFAULT_F, &
                  h5pset_chunk_cache_f, H5P_DATASET_ACCESS_F, h5open_f, h5pset_fapl_mpio_f, &
                  h5pset_dxpl_mpio_f, H5P_FILE_ACCESS_F, H5P_DATASET_XFER_F, H5FD_MPIO_COLLECTIVE_F, &
                  h5eset_auto_f, h5eprint_f, h5fget_name_f
  use dpmpm_kinds, only: wp, i8, i4
  use dpmpm_error, only: fatal
  use dpmpm_posix, only: posix_errno, posix_clear_errno, posix_strerror
  implicit none
  private
  public :: h5check, make_dir, string_type, attr_string, attr_i4, attr_i8, attr_real, rename_file
  public :: link_file
  public :: write_columns, write_check_t, mpio_access_list, collective_transfer_list
  public :: io_begin, io_check, file_name

  interface
    function c_rename(old, new) bind(C, name='rename') result(r)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*), new(*)
      integer(c_int) :: r
    end function c_rename
    function c_link(old, new) bind(C, name='link') result(r)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*), new(*)
      integer(c_int) :: r
    end function c_link
  end interface

  !> One block that this rank wrote into one dataset: where (selection) and what (bytes).
  type :: written_t
    integer(hid_t) :: dset = -1
    integer(hid_t) :: mtype = -1
    integer(hid_t) :: dxpl = -1          !< the collective transfer list (filtered datasets)
    logical :: filtered = .false.        !< compressed: rewritten collectively by every rank
    integer :: rank = 1
    integer(hsize_t) :: start(2) = 0
    integer(hsize_t) :: cnt(2) = 0
    integer(int8), allocatable :: bytes(:)
    character(len=:), allocatable :: name
  end type written_t

  !> Read-back check of collective writes. Some MPI-IO layers (Open MPI's OMPIO with
  !> HDF5 1.10 on 3 ranks) have put one rank's block of a collective write in the wrong
  !> place without reporting an error. Every block written through add is kept (every rank
  !> adds a record for every dataset, empty where it wrote nothing); verify reads each back
  !> with independent I/O after a flush, rewrites the blocks that differ (independently, or
  !> collectively by every rank for a compressed dataset, which parallel HDF5 writes only
  !> collectively), reads them again, and stops the run if they still differ.
  type :: write_check_t
    integer :: n = 0
    type(written_t), allocatable :: rec(:)
  contains
    procedure :: add => check_add
    procedure :: verify => check_verify
    procedure :: free => check_free
  end type write_check_t

contains

  !> Abort with the failing HDF5 call named when err reports a failure.
  subroutine h5check(err, call_name, where)
    integer, intent(in) :: err
    character(len=*), intent(in) :: call_name, where
    if (err < 0) call fatal(call_name//' failed', where)
  end subroutine h5check

  !> Before an HDF5 call that writes to a file (a dataset, a flush, a close): HDF5's error
  !> printing off and errno cleared, so that io_check can say what the system said (a full
  !> disk, a quota) instead of HDF5's stack of its own layers.
  subroutine io_begin()
    integer :: err
    call h5eset_auto_f(0, err)
    call posix_clear_errno()
  end subroutine io_begin

  !> After the call that io_begin prepared: on failure (err < 0) stop with the call, the file
  !> (file, as file_name gives it for an open object) and the reason the system gave (errno),
  !> or, where it gave none, HDF5's error stack first. HDF5's error printing is on again.
  subroutine io_check(err, call_name, file, where)
    integer, intent(in) :: err
    character(len=*), intent(in) :: call_name, file, where
    integer :: errno_now, e2
    errno_now = posix_errno()
    if (err < 0 .and. errno_now == 0) call h5eprint_f(e2)
    call h5eset_auto_f(1, e2)
    if (err >= 0) return
    if (errno_now /= 0) then
      call fatal(call_name//' failed on '//file//': '//posix_strerror(errno_now), where)
    else
      call fatal(call_name//' failed on '//file//' (the system gave no reason; HDF5''s '// &
                 'account above)', where)
    end if
  end subroutine io_check

  !> The name of the file that the open HDF5 object obj belongs to, for messages.
  function file_name(obj) result(name)
    integer(hid_t), intent(in) :: obj
    character(len=:), allocatable :: name
    character(len=4096) :: buf
    integer(size_t) :: n
    integer :: err
    buf = ''
    call h5fget_name_f(obj, buf, n, err)
    name = trim(buf)
    if (err < 0) name = '(a file HDF5 cannot name)'
  end function file_name

  !> A file access list for parallel HDF5 (MPI-IO) over comm, the library opened first.
  !> The caller closes it.
  function mpio_access_list(comm, where) result(fapl)
    type(MPI_Comm), intent(in) :: comm
    character(len=*), intent(in) :: where
    integer(hid_t) :: fapl
    integer :: err
    call h5open_f(err)
    call h5check(err, 'h5open_f', where)
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, err)
    call h5check(err, 'h5pcreate_f(file access)', where)
    call h5pset_fapl_mpio_f(fapl, comm%MPI_VAL, MPI_INFO_NULL%MPI_VAL, err)
    call h5check(err, 'h5pset_fapl_mpio_f', where)
  end function mpio_access_list

  !> A transfer list for collective MPI-IO writes. The caller closes it.
  function collective_transfer_list(where) result(dxpl)
    character(len=*), intent(in) :: where
    integer(hid_t) :: dxpl
    integer :: err
    call h5pcreate_f(H5P_DATASET_XFER_F, dxpl, err)
    call h5check(err, 'h5pcreate_f(transfer)', where)
    call h5pset_dxpl_mpio_f(dxpl, H5FD_MPIO_COLLECTIVE_F, err)
    call h5check(err, 'h5pset_dxpl_mpio_f', where)
  end function collective_transfer_list

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

  !> Rename a file (the last step of writing to a temporary name); fatal on failure, with
  !> the system's reason.
  subroutine rename_file(old, new, where)
    character(len=*), intent(in) :: old, new, where
    if (c_rename(old//c_null_char, new//c_null_char) /= 0) &
      call fatal('cannot rename '//old//' to '//new//': '//posix_strerror(posix_errno()), where)
  end subroutine rename_file

  !> Give the file old the second name new (a hard link), an earlier file new removed
  !> first: false where the file system cannot, and nothing is named new then.
  logical function link_file(old, new) result(linked)
    character(len=*), intent(in) :: old, new
    integer :: u, ios
    open (newunit=u, file=new, status='old', iostat=ios)
    if (ios == 0) close (u, status='delete', iostat=ios)
    linked = c_link(old//c_null_char, new//c_null_char) == 0
  end function link_file

  !> Create dataset <name> under gid for nglob points and write this rank's nloc points at
  !> offset, collectively with the transfer list dxpl. m = 0: shape (nglob); m > 0: Fortran shape (m, nglob), (nglob, m) in C order.
  !> ptr points to nloc*m values (at least one element, even when nloc = 0).
  !> With check, this rank's block is kept for check%verify (read back after the write).
  !> With compression > 0 the dataset is chunked (about 1 MiB a chunk) and stored with the
  !> shuffle filter and gzip at that level.
  subroutine write_columns(gid, dxpl, name, ftype, mtype, m, nloc, offset, nglob, ptr, where, &
                           check, compression)
    integer(hid_t), intent(in) :: gid, dxpl, ftype, mtype
    character(len=*), intent(in) :: name
    integer, intent(in) :: m
    integer(i8), intent(in) :: nloc, offset, nglob
    type(c_ptr), intent(in) :: ptr
    character(len=*), intent(in) :: where
    type(write_check_t), intent(inout), optional :: check
    integer, intent(in), optional :: compression
    integer(hsize_t) :: fdims(2), mdims(2), start(2), cnt(2), chunk(2)
    integer(hid_t) :: fspace, mspace, dset, dcpl, dapl
    integer :: rank, err, level
    level = 0
    if (present(compression)) level = compression
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
    dcpl = H5P_DEFAULT_F
    dapl = H5P_DEFAULT_F
    if (level > 0 .and. nglob > 0) then
      ! Rows of about 1 MiB (8-byte values), at most the whole dataset.
      chunk = fdims
      chunk(rank) = int(min(nglob, max(1_i8, 131072_i8/max(m, 1))), hsize_t)
      call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, err)
      call h5check(err, 'h5pcreate_f(dataset create)', where)
      call h5pset_chunk_f(dcpl, rank, chunk(1:rank), err)
      call h5check(err, 'h5pset_chunk_f('//name//')', where)
      call h5pset_shuffle_f(dcpl, err)
      call h5check(err, 'h5pset_shuffle_f('//name//')', where)
      call h5pset_deflate_f(dcpl, level, err)
      call h5check(err, 'h5pset_deflate_f('//name//')', where)
      ! No chunk cache: a read-back must see the file, not a chunk cached by an earlier read
      ! (a collective filtered write does not refresh the cache).
      call h5pcreate_f(H5P_DATASET_ACCESS_F, dapl, err)
      call h5check(err, 'h5pcreate_f(dataset access)', where)
      call h5pset_chunk_cache_f(dapl, 0_size_t, 0_size_t, 1.0, err)
      call h5check(err, 'h5pset_chunk_cache_f('//name//')', where)
    end if
    call h5dcreate_f(gid, name, ftype, fspace, dset, err, dcpl_id=dcpl, dapl_id=dapl)
    call h5check(err, 'h5dcreate_f('//name//')', where)
    if (dcpl /= H5P_DEFAULT_F) then
      call h5pclose_f(dcpl, err)
      call h5check(err, 'h5pclose_f(dataset create)', where)
      call h5pclose_f(dapl, err)
      call h5check(err, 'h5pclose_f(dataset access)', where)
    end if
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
      call io_begin()
      call h5dwrite_f(dset, mtype, ptr, err, mem_space_id=mspace, file_space_id=fspace, &
                      xfer_prp=dxpl)
      call io_check(err, 'h5dwrite_f('//name//')', file_name(dset), where)
    end if
    if (present(check)) call check%add(dset, mtype, rank, start, cnt, ptr, name, where, &
                                       dxpl=dxpl, filtered=level > 0 .and. nglob > 0)
    call h5dclose_f(dset, err)
    call h5check(err, 'h5dclose_f('//name//')', where)
    call h5sclose_f(mspace, err)
    call h5check(err, 'h5sclose_f('//name//')', where)
    call h5sclose_f(fspace, err)
    call h5check(err, 'h5sclose_f('//name//')', where)
  end subroutine write_columns

  !> Keep a copy of the block just written to dset (selection start/cnt of the given rank,
  !> memory type mtype, data at ptr; cnt may be 0). The dataset stays open until verify or
  !> free. Every rank adds one record per dataset, in the same order. A filtered dataset
  !> is rewritten with dxpl (collective) when any rank's block differs.
  subroutine check_add(self, dset, mtype, rank, start, cnt, ptr, name, where, dxpl, filtered)
    class(write_check_t), intent(inout) :: self
    integer(hid_t), intent(in) :: dset, mtype
    integer, intent(in) :: rank
    integer(hsize_t), intent(in) :: start(:), cnt(:)
    type(c_ptr), intent(in) :: ptr
    character(len=*), intent(in) :: name, where
    integer(hid_t), intent(in), optional :: dxpl
    logical, intent(in), optional :: filtered
    type(written_t), allocatable :: tmp(:)
    integer(int8), pointer :: src(:)
    integer(size_t) :: esize
    integer :: err, refs
    integer(i8) :: nbytes
    if (.not. allocated(self%rec)) allocate (self%rec(16))
    if (self%n + 1 > size(self%rec)) then
      allocate (tmp(2*size(self%rec)))
      tmp(1:self%n) = self%rec(1:self%n)
      call move_alloc(tmp, self%rec)
    end if
    call h5tget_size_f(mtype, esize, err)
    call h5check(err, 'h5tget_size_f('//name//')', where)
    nbytes = int(esize, i8)*product(int(cnt(1:rank), i8))
    call c_f_pointer(ptr, src, [max(nbytes, 1_i8)])
    call h5iinc_ref_f(dset, refs, err)
    call h5check(err, 'h5iinc_ref_f('//name//')', where)
    self%n = self%n + 1
    associate (r => self%rec(self%n))
      r%dset = dset
      r%mtype = mtype
      r%rank = rank
      r%start = 0
      r%cnt = 0
      r%start(1:rank) = start(1:rank)
      r%cnt(1:rank) = cnt(1:rank)
      r%bytes = src(1:nbytes)
      r%name = name
      r%dxpl = -1
      if (present(dxpl)) r%dxpl = dxpl
      r%filtered = .false.
      if (present(filtered)) r%filtered = filtered
    end associate
  end subroutine check_add

  !> Collective over the ranks of the file: flush file_id, read back every block kept
  !> since the last verify and compare it byte for byte; rewrite the blocks that differ
  !> with independent I/O and compare again; fatal if they still differ. Returns in
  !> nrewritten the number of blocks rewritten over all ranks (0 when all were right).
  subroutine check_verify(self, file_id, comm, where, nrewritten)
    class(write_check_t), intent(inout) :: self
    integer(hid_t), intent(in) :: file_id
    type(MPI_Comm), intent(in) :: comm
    character(len=*), intent(in) :: where
    integer, intent(out) :: nrewritten
    logical, allocatable :: bad(:), anybad(:)
    integer :: k, nbad, nstill, err
    allocate (bad(self%n), anybad(self%n))
    call io_begin()
    call h5fflush_f(file_id, H5F_SCOPE_GLOBAL_F, err)
    call io_check(err, 'h5fflush_f', file_name(file_id), where)
    call MPI_Barrier(comm)
    do k = 1, self%n
      bad(k) = .not. block_reads_back(self%rec(k), where)
    end do
    nbad = count(bad)
    call MPI_Allreduce(nbad, nrewritten, 1, MPI_INTEGER, MPI_SUM, comm)
    if (nrewritten > 0) then
      ! Which datasets need a collective rewrite: the filtered ones with a bad block anywhere.
      call MPI_Allreduce(bad, anybad, self%n, MPI_LOGICAL, MPI_LOR, comm)
      do k = 1, self%n
        if (self%rec(k)%filtered) then
          if (anybad(k)) call rewrite_block(self%rec(k), where, self%rec(k)%dxpl)
        else if (bad(k)) then
          call rewrite_block(self%rec(k), where)
        end if
      end do
      call io_begin()
      call h5fflush_f(file_id, H5F_SCOPE_GLOBAL_F, err)
      call io_check(err, 'h5fflush_f', file_name(file_id), where)
      call MPI_Barrier(comm)
      do k = 1, self%n
        if (bad(k)) bad(k) = .not. block_reads_back(self%rec(k), where)
      end do
      nbad = count(bad)
      call MPI_Allreduce(nbad, nstill, 1, MPI_INTEGER, MPI_SUM, comm)
      if (nstill > 0) then
        do k = 1, self%n
          if (bad(k)) call fatal('dataset '//self%rec(k)%name//' reads back different '// &
                                 'bytes than were written, also after a rewrite', where)
        end do
        call MPI_Barrier(comm)
        call fatal('the output file does not hold what was written', where)
      end if
    end if
    call self%free()
  end subroutine check_verify

  !> Close the datasets kept since the last verify and forget their blocks.
  subroutine check_free(self)
    class(write_check_t), intent(inout) :: self
    integer :: k, err
    do k = 1, self%n
      call h5dclose_f(self%rec(k)%dset, err)
      call h5check(err, 'h5dclose_f('//self%rec(k)%name//')', 'write check')
      deallocate (self%rec(k)%bytes)
    end do
    self%n = 0
  end subroutine check_free

  !> Read one kept block back from the file (independent I/O); true when every byte equals
  !> what was written.
  logical function block_reads_back(r, where) result(same)
    type(written_t), intent(in) :: r
    character(len=*), intent(in) :: where
    integer(int8), allocatable, target :: buf(:)
    integer(hid_t) :: fspace, mspace
    type(c_ptr) :: p
    integer :: err
    same = .true.
    if (size(r%bytes) == 0) return
    allocate (buf(size(r%bytes)))
    buf = not(r%bytes)
    p = c_loc(buf)
    call block_spaces(r, fspace, mspace, where)
    call h5dread_f(r%dset, r%mtype, p, err, mem_space_id=mspace, file_space_id=fspace)
    call h5check(err, 'h5dread_f('//r%name//')', where)
    call close_spaces(r, fspace, mspace, where)
    same = all(buf == r%bytes)
  end function block_reads_back

  !> Write one kept block again: with independent I/O, or with the transfer list dxpl
  !> (collective: every rank calls it, those without a block with an empty selection).
  subroutine rewrite_block(r, where, dxpl)
    type(written_t), intent(in), target :: r
    character(len=*), intent(in) :: where
    integer(hid_t), intent(in), optional :: dxpl
    integer(int8), target :: none(1)
    integer(hid_t) :: fspace, mspace
    type(c_ptr) :: p
    integer :: err
    call block_spaces(r, fspace, mspace, where)
    p = c_loc(none)
    if (size(r%bytes) > 0) p = c_loc(r%bytes)
    call io_begin()
    if (present(dxpl)) then
      call h5dwrite_f(r%dset, r%mtype, p, err, mem_space_id=mspace, file_space_id=fspace, &
                      xfer_prp=dxpl)
    else
      call h5dwrite_f(r%dset, r%mtype, p, err, mem_space_id=mspace, file_space_id=fspace)
    end if
    call io_check(err, 'h5dwrite_f('//r%name//', rewrite)', file_name(r%dset), where)
    call close_spaces(r, fspace, mspace, where)
  end subroutine rewrite_block

  !> File space of a kept block's dataset with its selection, and a memory space of its shape.
  subroutine block_spaces(r, fspace, mspace, where)
    type(written_t), intent(in) :: r
    integer(hid_t), intent(out) :: fspace, mspace
    character(len=*), intent(in) :: where
    integer :: err
    call h5dget_space_f(r%dset, fspace, err)
    call h5check(err, 'h5dget_space_f('//r%name//')', where)
    if (size(r%bytes) == 0) then
      call h5sselect_none_f(fspace, err)
      call h5check(err, 'h5sselect_none_f('//r%name//')', where)
      call h5screate_simple_f(1, [1_hsize_t], mspace, err)
      call h5check(err, 'h5screate_simple_f('//r%name//')', where)
      call h5sselect_none_f(mspace, err)
      call h5check(err, 'h5sselect_none_f('//r%name//')', where)
      return
    end if
    call h5sselect_hyperslab_f(fspace, H5S_SELECT_SET_F, r%start(1:r%rank), r%cnt(1:r%rank), err)
    call h5check(err, 'h5sselect_hyperslab_f('//r%name//')', where)
    call h5screate_simple_f(r%rank, r%cnt(1:r%rank), mspace, err)
    call h5check(err, 'h5screate_simple_f('//r%name//')', where)
  end subroutine block_spaces

  subroutine close_spaces(r, fspace, mspace, where)
    type(written_t), intent(in) :: r
    integer(hid_t), intent(in) :: fspace, mspace
    character(len=*), intent(in) :: where
    integer :: err
    call h5sclose_f(mspace, err)
    call h5check(err, 'h5sclose_f('//r%name//')', where)
    call h5sclose_f(fspace, err)
    call h5check(err, 'h5sclose_f('//r%name//')', where)
  end subroutine close_spaces

end module dpmpm_h5
