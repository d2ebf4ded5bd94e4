!> The parts of a run's output file (dpmpm_output) that a continued run reads back: the
!> file opened in place with the frames after the checkpoint deleted, the frame and
!> point-set records of the frames kept (for the sidecar), and the diagnostics datasets
!> opened again and cut at the checkpoint's step; with the making of those datasets,
!> which a new file shares. The procedures take the open file's handles: output_t keeps
!> them.
module dpmpm_output_resume
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_INTEGER, MPI_MIN, MPI_IN_PLACE
  use hdf5, only: hid_t, hsize_t, h5fclose_f, h5pcreate_f, h5pclose_f, h5pset_chunk_f, h5gclose_f, &
                  h5screate_simple_f, h5gopen_f, h5sclose_f, h5dcreate_f, h5dclose_f, h5dset_extent_f, &
                  h5dget_space_f, h5lexists_f, h5kind_to_type, H5_REAL_KIND, H5_INTEGER_KIND, &
                  H5P_DATASET_CREATE_F, H5S_UNLIMITED_F, H5T_IEEE_F64LE, h5fopen_f, h5ldelete_f, &
                  h5dopen_f, h5dread_f, h5aopen_f, h5aread_f, h5aclose_f, h5sget_simple_extent_dims_f, &
                  h5eset_auto_f, H5F_ACC_RDWR_F
  use dpmpm_kinds, only: wp, i8
  use dpmpm_error, only: fatal
  use dpmpm_config, only: optional_fields
  use dpmpm_diagnostics, only: ndiag_real, nfirst_diag_real, diag_real_names
  use dpmpm_h5, only: h5check, mpio_access_list
  use dpmpm_xdmf, only: frame_rec_t, set_rec_t
  implicit none
  private
  public :: ndiag_dsets, create_diag_dset, open_in_place, read_frame_records, reopen_diagnostics

  !> Number of datasets under /diagnostics: step, npoints and the real entries.
  integer, parameter :: ndiag_dsets = 2 + ndiag_real
  !> Chunk length of the extendible diagnostics datasets.
  integer(hsize_t), parameter :: diag_chunk = 256

contains

  !> Create one empty extendible 1D dataset under /diagnostics.
  subroutine create_diag_dset(gid, name, ftype, dset)
    integer(hid_t), intent(in) :: gid, ftype
    character(len=*), intent(in) :: name
    integer(hid_t), intent(out) :: dset
    integer(hid_t) :: space, dcpl
    integer :: err
    call h5screate_simple_f(1, [0_hsize_t], space, err, maxdims=[H5S_UNLIMITED_F])
    call h5check(err, 'h5screate_simple_f', 'diagnostics '//name)
    call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, err)
    call h5check(err, 'h5pcreate_f(dataset create)', 'diagnostics '//name)
    call h5pset_chunk_f(dcpl, 1, [diag_chunk], err)
    call h5check(err, 'h5pset_chunk_f', 'diagnostics '//name)
    call h5dcreate_f(gid, name, ftype, space, dset, err, dcpl_id=dcpl)
    call h5check(err, 'h5dcreate_f', 'diagnostics '//name)
    call h5pclose_f(dcpl, err)
    call h5check(err, 'h5pclose_f', 'diagnostics '//name)
    call h5sclose_f(space, err)
    call h5check(err, 'h5sclose_f', 'diagnostics '//name)
  end subroutine create_diag_dset

  !> Open the run's file path for writing (collective over comm) and delete the frames from nframes on and
  !> the benchmark results of the end of the run. err < 0, the file closed again, where the
  !> file refuses a deletion on some rank.
  subroutine open_in_place(path, comm, nframes, file_id, err)
    character(len=*), intent(in) :: path
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: nframes
    integer(hid_t), intent(out) :: file_id
    integer, intent(out) :: err
    character(len=*), parameter :: where = 'output%resume'
    character(len=32) :: gname
    integer(hid_t) :: fapl
    logical :: exists
    integer :: k, e2
    fapl = mpio_access_list(comm, where)
    call h5fopen_f(path, H5F_ACC_RDWR_F, file_id, err, access_prp=fapl)
    call h5check(err, 'h5fopen_f('//path//')', where)
    call h5pclose_f(fapl, k)
    call h5eset_auto_f(0, err)
    k = nframes
    do
      write (gname, '(a,i6.6)') 'frames/', k
      call h5lexists_f(file_id, trim(gname), exists, err)
      if (err < 0 .or. .not. exists) exit
      call h5ldelete_f(file_id, trim(gname), err)
      if (err < 0) exit
      k = k + 1
    end do
    if (err >= 0) then
      call h5lexists_f(file_id, 'verification', exists, err)
      if (err >= 0 .and. exists) call h5ldelete_f(file_id, 'verification', err)
    end if
    call h5eset_auto_f(1, e2)
    call MPI_Allreduce(MPI_IN_PLACE, err, 1, MPI_INTEGER, MPI_MIN, comm)
    if (err < 0) then
      call h5fclose_f(file_id, e2)
      file_id = -1
    end if
  end subroutine open_in_place

  !> The frame record and the nsets point-set records (for the sidecar) of frame k as it
  !> is in the file open as file_id; state_names: the state values of the scene's models.
  subroutine read_frame_records(file_id, k, state_names, frame, sets, nsets, where)
    integer(hid_t), intent(in) :: file_id
    integer, intent(in) :: k
    character(len=*), intent(in) :: state_names(:)
    type(frame_rec_t), intent(out) :: frame
    type(set_rec_t), intent(out) :: sets(2)
    integer, intent(out) :: nsets
    character(len=*), intent(in) :: where
    character(len=*), parameter :: names(2) = ['solid', 'fluid']
    character(len=32) :: gname
    integer(hid_t) :: gid, dset
    integer(hsize_t) :: dims(1), maxdims(1)
    type(set_rec_t) :: rec
    real(wp), target :: time
    integer(i8), target :: step
    logical :: exists
    integer :: err, j, f
    write (gname, '(a,i6.6)') 'frames/', k
    call h5gopen_f(file_id, trim(gname), gid, err)
    call h5check(err, 'h5gopen_f('//trim(gname)//')', where)
    call read_attr(gid, 'time', h5kind_to_type(wp, H5_REAL_KIND), c_loc(time), where)
    call read_attr(gid, 'step', h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(step), where)
    frame = frame_rec_t(step=step, time=time)
    nsets = 0
    do j = 1, size(names)
      call h5lexists_f(gid, trim(names(j)), exists, err)
      if (.not. exists) cycle
      call h5dopen_f(gid, trim(names(j))//'/id', dset, err)
      call h5check(err, 'h5dopen_f('//trim(gname)//'/'//trim(names(j))//'/id)', where)
      call dataset_dims(dset, dims, maxdims, where)
      call h5dclose_f(dset, err)
      rec = set_rec_t(frame=k, name=trim(names(j)), n=int(dims(1), i8))
      do f = 1, size(optional_fields)
        if (optional_fields(f) == 'state') then
          ! the state values are written together: the first stands for them all
          rec%has(f) = size(state_names) > 0
          if (rec%has(f)) call h5lexists_f(gid, trim(names(j))//'/'//trim(state_names(1)), &
                                           rec%has(f), err)
        else
          call h5lexists_f(gid, trim(names(j))//'/'//trim(optional_fields(f)), rec%has(f), err)
        end if
      end do
      nsets = nsets + 1
      sets(nsets) = rec
    end do
    call h5gclose_f(gid, err)
    call h5check(err, 'h5gclose_f('//trim(gname)//')', where)
  end subroutine read_frame_records

  !> The diagnostics datasets of the run's file open as file_id, opened into diag_dset
  !> (a column that a file of an earlier version lacks is made, with zeros up to the
  !> checkpoint), and cut to the nkeep records before step.
  subroutine reopen_diagnostics(file_id, step, diag_dset, nkeep, where)
    integer(hid_t), intent(in) :: file_id
    integer(i8), intent(in) :: step
    integer(hid_t), intent(inout) :: diag_dset(ndiag_dsets)
    integer, intent(out) :: nkeep
    character(len=*), intent(in) :: where
    integer(hid_t) :: dset, gid
    integer(hsize_t) :: dims(1), maxdims(1)
    integer(i8), allocatable, target :: steps(:)
    type(c_ptr) :: p
    logical :: exists
    integer :: err, k
    ! Diagnostics before the checkpoint's step (records are in step order); the continued run
    ! writes the record of that step itself.
    call h5dopen_f(file_id, 'diagnostics/step', diag_dset(1), err)
    call h5check(err, 'h5dopen_f(/diagnostics/step)', where)
    call h5dopen_f(file_id, 'diagnostics/npoints', diag_dset(2), err)
    call h5check(err, 'h5dopen_f(/diagnostics/npoints)', where)
    do k = 1, ndiag_real
      call h5lexists_f(file_id, 'diagnostics/'//trim(diag_real_names(k)), exists, err)
      if (.not. exists .and. k > nfirst_diag_real) then
        ! a file written before this record had the column: zeros up to the checkpoint
        call h5gopen_f(file_id, 'diagnostics', gid, err)
        call h5check(err, 'h5gopen_f(/diagnostics)', where)
        call create_diag_dset(gid, trim(diag_real_names(k)), H5T_IEEE_F64LE, diag_dset(2 + k))
        call h5gclose_f(gid, err)
        cycle
      end if
      call h5dopen_f(file_id, 'diagnostics/'//trim(diag_real_names(k)), &
                     diag_dset(2 + k), err)
      call h5check(err, 'h5dopen_f(/diagnostics/'//trim(diag_real_names(k))//')', where)
    end do
    dset = diag_dset(1)
    call dataset_dims(dset, dims, maxdims, where)
    allocate (steps(max(dims(1), 1_hsize_t)))
    p = c_loc(steps)
    if (dims(1) > 0) then
      call h5dread_f(dset, h5kind_to_type(i8, H5_INTEGER_KIND), p, err)
      call h5check(err, 'h5dread_f(/diagnostics/step)', where)
    end if
    nkeep = 0
    do while (nkeep < int(dims(1)))
      if (steps(nkeep + 1) >= step) exit
      nkeep = nkeep + 1
    end do
    do k = 1, ndiag_dsets
      call h5dset_extent_f(diag_dset(k), [int(nkeep, hsize_t)], err)
      call h5check(err, 'h5dset_extent_f(diagnostics)', where)
    end do
  end subroutine reopen_diagnostics

  !> Read a scalar attribute of loc into the memory at ptr (memory type mtype).
  subroutine read_attr(loc, name, mtype, ptr, where)
    integer(hid_t), intent(in) :: loc, mtype
    character(len=*), intent(in) :: name, where
    type(c_ptr), intent(in) :: ptr
    integer(hid_t) :: attr
    type(c_ptr) :: p
    integer :: err
    p = ptr
    call h5aopen_f(loc, name, attr, err)
    call h5check(err, 'h5aopen_f('//name//')', where)
    call h5aread_f(attr, mtype, p, err)
    call h5check(err, 'h5aread_f('//name//')', where)
    call h5aclose_f(attr, err)
    call h5check(err, 'h5aclose_f('//name//')', where)
  end subroutine read_attr

  !> Current and largest dimensions of a 1D dataset.
  subroutine dataset_dims(dset, dims, maxdims, where)
    integer(hid_t), intent(in) :: dset
    integer(hsize_t), intent(out) :: dims(1), maxdims(1)
    character(len=*), intent(in) :: where
    integer(hid_t) :: space
    integer :: err
    call h5dget_space_f(dset, space, err)
    call h5check(err, 'h5dget_space_f', where)
    call h5sget_simple_extent_dims_f(space, dims, maxdims, err)
    if (err < 0) call fatal('h5sget_simple_extent_dims_f failed', where)
    call h5sclose_f(space, err)
    call h5check(err, 'h5sclose_f', where)
  end subroutine dataset_dims

end module dpmpm_output_resume
