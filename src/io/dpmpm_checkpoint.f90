!> Checkpoints: the state of a run (every point of both sets, time, step, energy
!> balance and run monitor, frame schedule) in one HDF5 file, <output_dir>/<name>.ckpt.h5. Written
!> collectively to <file>.tmp and renamed, so that a crash while writing never leaves a
!> broken checkpoint behind; read back on any number of ranks, each rank keeping the
!> points in its own cells.
!>
!> Layout: /state (nstate doubles, shape (nstate, 1), see state_to_array), /solid and /fluid
!> (the packed points of particle_set_t%pack, Fortran shape (nreal_packed, n)). The root
!> carries format_version (checkpoint_format) and every dataset an int64 attribute checksum
!> (dpmpm_checksum), so that a restart refuses a damaged file before it uses it.
module dpmpm_checkpoint
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc
  use, intrinsic :: iso_fortran_env, only: output_unit, int8
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Barrier, MPI_Exscan, MPI_Allreduce, &
                     MPI_SUM, MPI_IN_PLACE, MPI_BXOR
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5fcreate_f, h5fopen_f, h5fclose_f, &
                  h5pclose_f, h5sclose_f, h5dopen_f, h5fis_hdf5_f, h5eset_auto_f, &
                  h5dread_f, h5dclose_f, h5dget_space_f, h5sget_simple_extent_dims_f, &
                  h5sget_simple_extent_ndims_f, h5dget_type_f, h5tget_size_f, h5tclose_f, &
                  h5aexists_f, h5aopen_f, h5aread_f, h5aclose_f, h5gget_info_f, &
                  h5lget_name_by_idx_f, h5oopen_f, h5oclose_f, h5iget_type_f, H5I_DATASET_F, &
                  H5_INDEX_NAME_F, H5_ITER_INC_F, &
                  h5lexists_f, H5F_ACC_TRUNC_F, H5F_ACC_RDONLY_F, &
                  H5P_DEFAULT_F, H5T_IEEE_F64LE, &
                  h5kind_to_type, H5_REAL_KIND, H5_INTEGER_KIND
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use dpmpm_kinds, only: wp, i8, i4, mpi_i8
  use dpmpm_strings, only: itoa
  use dpmpm_particles, only: particle_set_t
  use dpmpm_grid, only: cell_of
  use dpmpm_h5, only: h5check, make_dir, rename_file, write_columns, write_check_t, &
                      mpio_access_list, collective_transfer_list, attr_i4, attr_i8, attr_string, &
                      io_begin, io_check
  use dpmpm_posix, only: posix_fsync, posix_strerror, posix_is_directory
  use dpmpm_error, only: fatal
  use dpmpm_checksum, only: checksum_columns
  use dpmpm_build_info, only: dpmpm_version
  implicit none
  private
  public :: checkpoint_state_t, checkpoint_path, write_checkpoint, read_checkpoint, nmonitor
  public :: checkpoint_format

  !> Version of the checkpoint's layout, the root attribute format_version: 2 added the
  !> checksums. A checkpoint without the attribute is of version 1 (read, unchecked); one of
  !> a later version than this is refused.
  integer, parameter :: checkpoint_format = 2

  !> Numbers of the run monitor's state; checkpoints of earlier versions hold
  !> nstate_inflow numbers (no mass through drained faces), nstate_monitor (no inflow count
  !> either) or nstate_grid (no drag dissipation, no monitor), older ones fewer (no grid:
  !> refused).
  integer, parameter :: nmonitor = 14
  integer, parameter :: nstate_grid = 18
  integer, parameter :: nstate_monitor = nstate_grid + 1 + nmonitor
  integer, parameter :: nstate_inflow = nstate_monitor + 2
  integer, parameter :: nstate = nstate_inflow + 2

  !> Scalars of a run's state that the points do not carry.
  type :: checkpoint_state_t
    integer(i8) :: step = 0
    real(wp) :: time = 0.0_wp
    real(wp) :: ext_work = 0.0_wp         !< work of the loads minus drag dissipation
    real(wp) :: energy0 = 0.0_wp
    real(wp) :: energy_scale = 0.0_wp
    real(wp) :: energy_error = 0.0_wp
    real(wp) :: next_frame = 0.0_wp
    integer :: nframes = 0
    integer :: ndim = 0
    integer :: ncells(3) = 0
    real(wp) :: origin(3) = 0.0_wp        !< grid of the run, checked on restart
    real(wp) :: length(3) = 0.0_wp
    real(wp) :: drag_loss = 0.0_wp        !< energy dissipated by drag (the monitor's D)
    logical :: has_monitor = .false.      !< monitor holds a state (not in older checkpoints)
    real(wp) :: monitor(nmonitor) = 0.0_wp !< the run monitor's state (dpmpm_energy)
    logical :: has_inflow = .false.       !< the inflow ids below are recorded
    integer(i8) :: inflow_id0 = 0         !< largest fluid point id of the run's start
    integer(i8) :: ninflow = 0            !< fluid points added at inflow faces so far
    real(wp) :: inflow_mass = 0.0_wp      !< their mass, and that of the fluid points that
    real(wp) :: outflow_mass = 0.0_wp     !< left through drained faces (0 in older files)
    logical :: has_checksum = .false.     !< the datasets were checked against their checksums
  end type checkpoint_state_t

contains

  !> <output_dir>/<name>.ckpt.h5
  function checkpoint_path(output_dir, name) result(path)
    character(len=*), intent(in) :: output_dir, name
    character(len=:), allocatable :: path
    path = trim(output_dir)//'/'//trim(name)//'.ckpt.h5'
  end function checkpoint_path

  !> Write the state st and the points of solid (and fluid, when present) to path,
  !> through path.tmp (collective over comm).
  subroutine write_checkpoint(path, output_dir, comm, st, solid, fluid)
    character(len=*), intent(in) :: path, output_dir
    type(MPI_Comm), intent(in) :: comm
    type(checkpoint_state_t), intent(in) :: st
    type(particle_set_t), intent(in) :: solid
    type(particle_set_t), intent(in), optional :: fluid
    character(len=*), parameter :: where = 'write_checkpoint'
    integer(hid_t) :: fapl, dxpl, file
    integer :: err, rank, nrewritten
    integer(i8) :: sum
    real(wp), target :: state(nstate)
    type(write_check_t) :: check
    call MPI_Comm_rank(comm, rank)
    if (rank == 0) call make_dir(trim(output_dir))
    call MPI_Barrier(comm)
    fapl = mpio_access_list(comm, where)
    call io_begin()
    call h5fcreate_f(path//'.tmp', H5F_ACC_TRUNC_F, file, err, creation_prp=H5P_DEFAULT_F, &
                     access_prp=fapl)
    call io_check(err, 'h5fcreate_f', path//'.tmp', where)
    call h5pclose_f(fapl, err)
    dxpl = collective_transfer_list(where)
    state = state_to_array(st)
    call write_columns(file, dxpl, 'state', H5T_IEEE_F64LE, h5kind_to_type(wp, H5_REAL_KIND), &
                       nstate, merge(1_i8, 0_i8, rank == 0), 0_i8, 1_i8, c_loc(state), where, &
                       check)
    sum = 0
    if (rank == 0) sum = checksum_columns(c_loc(state), 8_i8*nstate, 1_i8, 0_i8)
    call put_checksum(file, comm, 'state', sum)
    call write_set(file, dxpl, comm, 'solid', solid, check)
    if (present(fluid)) call write_set(file, dxpl, comm, 'fluid', fluid, check)
    call attr_i4(file, 'format_version', int(checkpoint_format, i4))
    call attr_string(file, 'dpmpm_version', dpmpm_version)
    ! Read back what every rank wrote before the checkpoint replaces the previous one.
    call check%verify(file, comm, where, nrewritten)
    if (nrewritten > 0 .and. rank == 0) write (output_unit, '(a,i0,a)') 'checkpoint: ', &
      nrewritten, ' blocks read back differently from what the collective write was '// &
      'given; rewritten with independent I/O and verified'
    call h5pclose_f(dxpl, err)
    call io_begin()
    call h5fclose_f(file, err)
    call io_check(err, 'h5fclose_f', path//'.tmp', where)
    call MPI_Barrier(comm)
    ! On the disk before it replaces the previous checkpoint, and the new name on the disk
    ! after: a crash of the machine (not only of the run) leaves one whole checkpoint.
    if (rank == 0) then
      err = posix_fsync(path//'.tmp')
      if (err /= 0) call fatal('cannot flush '//path//'.tmp to the disk: '// &
                               posix_strerror(err), where)
      call rename_file(path//'.tmp', path, where)
      err = posix_fsync(trim(output_dir))
      if (err /= 0) call fatal('cannot flush directory '//trim(output_dir)//' to the disk: '// &
                               posix_strerror(err), where)
    end if
    call MPI_Barrier(comm)
  end subroutine write_checkpoint

  !> Read the state and the points of the sets from path (every rank reads the whole
  !> file and keeps the points in its cells clo..chi of the grid origin, h). The sets
  !> must be initialised (empty) with the scene's fields. problem is empty on success;
  !> otherwise it says, in one line, why the file cannot continue this scene, and the sets
  !> may hold some of its points: the file is missing, a directory, not HDF5, truncated,
  !> not a checkpoint, of a later format, fails a dataset's checksum (stored at write time,
  !> dpmpm_checksum), comes from another grid or scene, or holds points that would be lost
  !> or break the run (non-finite values, outside the grid, mass or volume not positive).
  !> Every rank finds the same problem, so the caller may stop collectively. HDF5's own
  !> error printing is off meanwhile: the problem says what is wrong.
  subroutine read_checkpoint(path, st, origin, h, clo, chi, ncells, length, problem, solid, fluid)
    character(len=*), intent(in) :: path
    type(checkpoint_state_t), intent(out) :: st
    real(wp), intent(in) :: origin(3), h(3), length(3)
    integer, intent(in) :: clo(3), chi(3), ncells(3)
    character(len=:), allocatable, intent(out) :: problem
    type(particle_set_t), intent(inout) :: solid
    type(particle_set_t), intent(inout), optional :: fluid
    character(len=*), parameter :: where = 'read_checkpoint'
    integer(hid_t) :: file
    integer :: err, e2
    logical :: is_h5
    call h5open_f(err)
    call h5check(err, 'h5open_f', where)
    call h5eset_auto_f(0, err)
    problem = ''
    if (posix_is_directory(path)) then
      problem = path//' is a directory, not a checkpoint file'
    else if (.not. file_exists(path)) then
      problem = 'restart file '//path//' not found'
    else
      call h5fis_hdf5_f(path, is_h5, err)
      if (err < 0 .or. .not. is_h5) then
        problem = path//' is not an HDF5 file, so not a checkpoint (a run with &output '// &
                  'checkpoint_every > 0 writes <dir>/<name>.ckpt.h5)'
      else
        call h5fopen_f(path, H5F_ACC_RDONLY_F, file, err)
        if (err < 0) then
          problem = path//' is an HDF5 file that cannot be opened: it is truncated or damaged'
        else
          call read_opened(file, path, st, origin, h, clo, chi, ncells, length, problem, &
                           solid, fluid)
          call h5fclose_f(file, e2)
        end if
      end if
    end if
    call h5eset_auto_f(1, e2)
  end subroutine read_checkpoint

  !> read_checkpoint on the open file.
  subroutine read_opened(file, path, st, origin, h, clo, chi, ncells, length, problem, solid, &
                         fluid)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    type(checkpoint_state_t), intent(out) :: st
    real(wp), intent(in) :: origin(3), h(3), length(3)
    integer, intent(in) :: clo(3), chi(3), ncells(3)
    character(len=:), allocatable, intent(inout) :: problem
    type(particle_set_t), intent(inout) :: solid
    type(particle_set_t), intent(inout), optional :: fluid
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(2), maxdims(2)
    integer :: err, e2, nd, version
    logical :: exists
    real(wp), target :: state(nstate)
    type(c_ptr) :: cp
    nd = solid%ndim
    version = format_version(file)
    if (version < 0) then
      problem = path//': its attribute format_version cannot be read; the file is damaged'
      return
    else if (version > checkpoint_format) then
      problem = path//' was written by a later dpmpm (checkpoint format '//itoa(version)// &
                '; this one reads formats up to '//itoa(checkpoint_format)//'); continue it '// &
                'with that version'
      return
    end if
    call h5lexists_f(file, 'state', exists, err)
    if (err < 0 .or. .not. exists) then
      call h5lexists_f(file, 'frames', exists, err)
      if (err >= 0 .and. exists) then
        problem = path//' is the output of a run (it holds /frames), not a checkpoint; a run '// &
                  'with &output checkpoint_every > 0 writes <dir>/<name>.ckpt.h5'
      else
        problem = path//' is not a dpmpm checkpoint (it holds no /state)'
      end if
      return
    end if
    st%has_checksum = version >= 2
    if (st%has_checksum) then
      call verify_checksums(file, path, problem)
      if (len(problem) > 0) return
    end if
    call h5dopen_f(file, 'state', dset, err)
    if (err < 0) then
      problem = path//': /state cannot be opened; the file is damaged'
      return
    end if
    call h5dget_space_f(dset, space, err)
    if (err >= 0) call h5sget_simple_extent_dims_f(space, dims, maxdims, err)
    if (err >= 0) call h5sclose_f(space, e2)
    if (err < 0) then
      call h5dclose_f(dset, e2)
      problem = path//': /state cannot be read; the file is damaged'
      return
    end if
    if (dims(1) /= nstate .and. dims(1) /= nstate_inflow .and. dims(1) /= nstate_monitor .and. &
        dims(1) /= nstate_grid) then
      problem = path//' was written by an earlier dpmpm that did not record the grid''s '// &
                'origin and length, so it cannot be checked against this input; run the '// &
                'scene again from its start'
      call h5dclose_f(dset, e2)
      return
    end if
    state = 0.0_wp
    cp = c_loc(state)
    call h5dread_f(dset, h5kind_to_type(wp, H5_REAL_KIND), cp, err)
    call h5dclose_f(dset, e2)
    if (err < 0) then
      problem = path//': /state cannot be read; the file is truncated or damaged'
      return
    end if
    st = array_to_state(state)
    st%has_checksum = version >= 2
    st%has_monitor = dims(1) >= nstate_monitor
    st%has_inflow = dims(1) >= nstate_inflow
    if (st%ndim /= nd .or. any(st%ncells(1:nd) /= ncells(1:nd)) .or. &
        any(abs(st%origin(1:nd) - origin(1:nd)) > 1.0e-12_wp*length(1:nd)) .or. &
        any(abs(st%length(1:nd) - length(1:nd)) > 1.0e-12_wp*length(1:nd))) then
      problem = path//' comes from another grid: it has '// &
                grid_text(st%ndim, st%ncells, st%origin, st%length)//'; the input has '// &
                grid_text(nd, ncells, origin, length)//'. Restart with the &grid of the '// &
                'run that wrote it'
    else
      call read_set(file, path, 'solid', origin, h, clo, chi, ncells, solid, problem)
      if (present(fluid) .and. len(problem) == 0) &
        call read_set(file, path, 'fluid', origin, h, clo, chi, ncells, fluid, problem)
    end if
  end subroutine read_opened

  !> The root attribute format_version of an open checkpoint: 1 where it is absent (files
  !> of before it), -1 where it cannot be read.
  integer function format_version(file) result(version)
    integer(hid_t), intent(in) :: file
    integer(hid_t) :: attr
    integer(i4), target :: v
    type(c_ptr) :: cp
    logical :: exists
    integer :: err, e2
    version = -1
    call h5aexists_f(file, 'format_version', exists, err)
    if (err < 0) return
    if (.not. exists) then
      version = 1
      return
    end if
    call h5aopen_f(file, 'format_version', attr, err)
    if (err < 0) return
    cp = c_loc(v)
    call h5aread_f(attr, h5kind_to_type(i4, H5_INTEGER_KIND), cp, err)
    call h5aclose_f(attr, e2)
    if (err >= 0) version = int(v)
  end function format_version

  !> Every dataset at the root of an open checkpoint, whatever it holds, read as the bytes
  !> the file stores and compared with its attribute checksum (dpmpm_checksum: the columns
  !> are the slowest index of its shape). problem names the first that fails.
  subroutine verify_checksums(file, path, problem)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(inout) :: problem
    integer(hid_t) :: obj, dset, space, ftype, attr
    integer(hsize_t) :: dims(8), maxdims(8)
    integer(size_t) :: esize
    integer(int8), allocatable, target :: bytes(:)
    integer(i8), target :: stored
    integer(i8) :: width, ncols
    character(len=64) :: name
    integer :: err, e2, storage, nlinks, max_corder, k, rank, otype
    logical :: exists
    type(c_ptr) :: cp, ap
    call h5gget_info_f(file, storage, nlinks, max_corder, err)
    if (err < 0) then
      problem = path//': its index of datasets cannot be read; the file is damaged'
      return
    end if
    do k = 0, nlinks - 1
      name = ''
      call h5lget_name_by_idx_f(file, '.', H5_INDEX_NAME_F, H5_ITER_INC_F, int(k, hsize_t), &
                                name, err)
      if (err >= 0) call h5oopen_f(file, trim(name), obj, err)
      if (err < 0) then
        problem = path//': an object of its root cannot be opened; the file is damaged'
        return
      end if
      call h5iget_type_f(obj, otype, err)
      call h5oclose_f(obj, e2)
      if (otype /= H5I_DATASET_F) cycle
      call h5dopen_f(file, trim(name), dset, err)
      if (err >= 0) call h5dget_space_f(dset, space, err)
      if (err >= 0) call h5sget_simple_extent_ndims_f(space, rank, err)
      if (err >= 0 .and. rank > 0 .and. rank <= size(dims)) &
        call h5sget_simple_extent_dims_f(space, dims(1:rank), maxdims(1:rank), err)
      if (err >= 0) call h5sclose_f(space, e2)
      if (err >= 0) call h5dget_type_f(dset, ftype, err)
      if (err < 0 .or. rank < 1 .or. rank > size(dims)) then
        problem = path//': dataset /'//trim(name)//' cannot be opened; the file is damaged'
        return
      end if
      call h5tget_size_f(ftype, esize, err)
      width = int(esize, i8)*product(int(dims(1:rank - 1), i8))
      ncols = int(dims(rank), i8)
      allocate (bytes(max(1_i8, width*ncols)))
      cp = c_loc(bytes)
      if (width*ncols > 0) call h5dread_f(dset, ftype, cp, err)
      call h5tclose_f(ftype, e2)
      if (err < 0) then
        call h5dclose_f(dset, e2)
        problem = path//': dataset /'//trim(name)//' cannot be read; the file is truncated '// &
                  'or damaged'
        return
      end if
      call h5aexists_f(dset, 'checksum', exists, err)
      if (err >= 0 .and. exists) then
        call h5aopen_f(dset, 'checksum', attr, err)
        if (err >= 0) then
          ap = c_loc(stored)
          call h5aread_f(attr, h5kind_to_type(i8, H5_INTEGER_KIND), ap, err)
          call h5aclose_f(attr, e2)
        end if
      end if
      call h5dclose_f(dset, e2)
      if (err < 0 .or. .not. exists) then
        problem = path//': dataset /'//trim(name)//' carries no checksum; the file is damaged'
        return
      end if
      if (checksum_columns(cp, width, ncols, 0_i8) /= stored) then
        problem = path//' fails its checksum: dataset /'//trim(name)//' holds other bytes '// &
                  'than were written (the file is damaged); continue from an earlier copy or '// &
                  'run the scene again'
        return
      end if
      deallocate (bytes)
    end do
  end subroutine verify_checksums

  !> A file (or anything else) of that name exists.
  logical function file_exists(path) result(exists)
    character(len=*), intent(in) :: path
    inquire (file=path, exist=exists)
  end function file_exists

  !> "ndim = 2, ncells = 8, 8, origin = 0, 0, length = 1, 1" for messages.
  function grid_text(nd, ncells, origin, length) result(s)
    integer, intent(in) :: nd, ncells(3)
    real(wp), intent(in) :: origin(3), length(3)
    character(len=:), allocatable :: s
    character(len=256) :: buf
    integer :: n, d
    n = max(1, min(3, nd))
    write (buf, '(a,i0,a,*(i0,:,", "))') 'ndim = ', nd, ', ncells = ', ncells(1:n)
    s = trim(buf)//', origin = '
    do d = 1, n
      if (d > 1) s = s//', '
      s = s//real_text(origin(d))
    end do
    s = s//', length = '
    do d = 1, n
      if (d > 1) s = s//', '
      s = s//real_text(length(d))
    end do
  end function grid_text

  !> The fewest digits that read back to x (finite x).
  function real_text(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf, fmt
    real(wp) :: y
    integer :: nd
    do nd = 1, 17
      write (fmt, '(a,i0,a)') '(es32.', nd, ')'
      write (buf, fmt) x
      read (buf, *) y
      if (y == x) exit
    end do
    s = trim(adjustl(buf))
  end function real_text

  !> The state as doubles (integers are exact below 2^53).
  pure function state_to_array(st) result(a)
    type(checkpoint_state_t), intent(in) :: st
    real(wp) :: a(nstate)
    a = [real(st%step, wp), st%time, st%ext_work, st%energy0, st%energy_scale, st%energy_error, &
         st%next_frame, real(st%nframes, wp), real(st%ndim, wp), real(st%ncells, wp), st%origin, &
         st%length, st%drag_loss, st%monitor, real(st%inflow_id0, wp), real(st%ninflow, wp), &
         st%inflow_mass, st%outflow_mass]
  end function state_to_array

  pure function array_to_state(a) result(st)
    real(wp), intent(in) :: a(nstate)
    type(checkpoint_state_t) :: st
    st%step = nint(a(1), i8)
    st%time = a(2)
    st%ext_work = a(3)
    st%energy0 = a(4)
    st%energy_scale = a(5)
    st%energy_error = a(6)
    st%next_frame = a(7)
    st%nframes = nint(a(8))
    st%ndim = nint(a(9))
    st%ncells = nint(a(10:12))
    st%origin = a(13:15)
    st%length = a(16:18)
    st%drag_loss = a(19)
    st%monitor = a(20:nstate_monitor)
    st%inflow_id0 = nint(a(nstate_monitor + 1), i8)
    st%ninflow = nint(a(nstate_monitor + 2), i8)
    st%inflow_mass = a(nstate_inflow + 1)
    st%outflow_mass = a(nstate_inflow + 2)
  end function array_to_state

  !> The packed points of a set: this rank's at its offset in the global order.
  subroutine write_set(file, dxpl, comm, name, ps, check)
    integer(hid_t), intent(in) :: file, dxpl
    type(MPI_Comm), intent(in) :: comm
    character(len=*), intent(in) :: name
    type(particle_set_t), intent(in) :: ps
    type(write_check_t), intent(inout) :: check
    real(wp), allocatable, target :: buf(:, :)
    integer(i8) :: nloc, offset, nglob
    integer :: m, k, rank
    call MPI_Comm_rank(comm, rank)
    m = ps%nreal_packed()
    nloc = int(ps%n, i8)
    offset = 0
    call MPI_Exscan(nloc, offset, 1, mpi_i8(), MPI_SUM, comm)
    if (rank == 0) offset = 0
    call MPI_Allreduce(nloc, nglob, 1, mpi_i8(), MPI_SUM, comm)
    allocate (buf(m, max(ps%n, 1)))
    call ps%pack_points([(k, k=1, ps%n)], buf(:, 1:ps%n))
    call write_columns(file, dxpl, name, H5T_IEEE_F64LE, h5kind_to_type(wp, H5_REAL_KIND), m, &
                       nloc, offset, nglob, c_loc(buf), 'write_checkpoint', check)
    call put_checksum(file, comm, name, checksum_columns(c_loc(buf), 8_i8*m, nloc, offset))
  end subroutine write_set

  !> The checksum of dataset name (this rank's part sum, combined over comm) as its int64
  !> attribute checksum (collective).
  subroutine put_checksum(file, comm, name, sum)
    integer(hid_t), intent(in) :: file
    type(MPI_Comm), intent(in) :: comm
    character(len=*), intent(in) :: name
    integer(i8), intent(in) :: sum
    integer(hid_t) :: dset
    integer(i8) :: total
    integer :: err
    call MPI_Allreduce(sum, total, 1, mpi_i8(), MPI_BXOR, comm)
    call h5dopen_f(file, name, dset, err)
    call h5check(err, 'h5dopen_f('//name//')', 'write_checkpoint')
    call attr_i8(dset, 'checksum', total)
    call h5dclose_f(dset, err)
    call h5check(err, 'h5dclose_f('//name//')', 'write_checkpoint')
  end subroutine put_checksum

  !> Read set name and append its points in cells clo..chi to ps. Points with a non-finite
  !> value or outside the grid (ncells) would be lost, and points whose mass or volume is not
  !> positive break the run: then problem counts them (ps is left as it was).
  subroutine read_set(file, path, name, origin, h, clo, chi, ncells, ps, problem)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path, name
    real(wp), intent(in) :: origin(3), h(3)
    integer, intent(in) :: clo(3), chi(3), ncells(3)
    type(particle_set_t), intent(inout) :: ps
    character(len=:), allocatable, intent(inout) :: problem
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(2), maxdims(2)
    real(wp), allocatable, target :: buf(:, :)
    type(c_ptr) :: cp
    logical :: exists, keep
    integer :: err, e2, m, j, d, c(3), nkeep, nbad, nout, nempty
    integer, allocatable :: idx(:)
    logical, allocatable :: inside(:)
    real(wp) :: x(3)
    m = ps%nreal_packed()
    call h5lexists_f(file, name, exists, err)
    if (err < 0 .or. .not. exists) then
      problem = path//' holds no '//name//' points; it comes from another scene'
      return
    end if
    call h5dopen_f(file, name, dset, err)
    if (err >= 0) call h5dget_space_f(dset, space, err)
    if (err >= 0) call h5sget_simple_extent_dims_f(space, dims, maxdims, err)
    if (err >= 0) call h5sclose_f(space, e2)
    if (err < 0) then
      problem = path//': dataset /'//name//' cannot be opened; the file is damaged'
      return
    end if
    if (int(dims(1)) /= m) then
      call h5dclose_f(dset, e2)
      problem = path//': the '//name//' points have other fields than this scene''s '// &
                '(another model or phase set)'
      return
    end if
    allocate (buf(m, max(dims(2), 1_hsize_t)))
    if (dims(2) > 0) then
      cp = c_loc(buf)
      call h5dread_f(dset, h5kind_to_type(wp, H5_REAL_KIND), cp, err)
    end if
    call h5dclose_f(dset, e2)
    if (err < 0) then
      problem = path//': dataset /'//name//' cannot be read; the file is truncated or damaged'
      return
    end if
    ! Keep the points of this rank's cells, in the order of the file; none may be lost.
    allocate (idx(dims(2)), inside(dims(2)))
    inside = .false.
    nkeep = 0
    nbad = 0
    nout = 0
    do j = 1, int(dims(2))
      x = 0.0_wp
      x(1:ps%ndim) = buf(3:2 + ps%ndim, j)
      if (.not. all(ieee_is_finite(buf(:, j)))) then
        nbad = nbad + 1
        cycle
      end if
      c = cell_of(origin, h, x, ps%ndim)
      if (any(c(1:ps%ndim) < 0 .or. c(1:ps%ndim) >= ncells(1:ps%ndim))) then
        nout = nout + 1
        cycle
      end if
      inside(j) = .true.
      keep = .true.
      do d = 1, ps%ndim
        keep = keep .and. c(d) >= clo(d) .and. c(d) <= chi(d)
      end do
      if (.not. keep) cycle
      nkeep = nkeep + 1
      idx(nkeep) = j
    end do
    if (nbad + nout > 0) then
      problem = path//': '//itoa(nbad)//' of its '//itoa(int(dims(2)))//' '//name// &
                ' points have a non-finite value and '//itoa(nout)//' lie outside the grid; '// &
                'they would be lost. The checkpoint is damaged or comes from another scene'
      return
    end if
    nempty = count_empty(ps, buf, inside)
    if (nempty > 0) then
      problem = path//': '//itoa(nempty)//' of its '//itoa(int(dims(2)))//' '//name// &
                ' points have a mass or volume that is not positive; the checkpoint is damaged'
      return
    end if
    call ps%unpack_points(buf(:, idx(1:nkeep)))
  end subroutine read_set

  !> How many of the packed points buf(:, j) with use(j) have a mass, volume or initial
  !> volume <= 0: unpacked a block at a time into a copy of the empty set ps, so that the
  !> check reads the fields by name whatever else a point carries.
  integer function count_empty(ps, buf, use) result(nempty)
    type(particle_set_t), intent(in) :: ps
    real(wp), intent(in) :: buf(:, :)
    logical, intent(in) :: use(:)
    integer, parameter :: block = 4096
    type(particle_set_t) :: probe
    integer, allocatable :: cols(:)
    integer :: j0, k, nuse
    nempty = 0
    cols = pack([(k, k=1, size(use))], use)
    nuse = size(cols)
    probe = ps
    do j0 = 1, nuse, block
      probe%n = 0
      call probe%unpack_points(buf(:, cols(j0:min(nuse, j0 + block - 1))))
      k = probe%n
      nempty = nempty + count(.not. (probe%mass(1:k) > 0.0_wp .and. probe%vol(1:k) > 0.0_wp &
                                     .and. probe%vol0(1:k) > 0.0_wp))
    end do
    call probe%free()
  end function count_empty

end module dpmpm_checkpoint
