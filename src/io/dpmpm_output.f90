!> Run output: one HDF5 file per run, <output_dir>/<name>.h5, written collectively with
!> parallel HDF5 (MPI-IO), plus an XDMF sidecar <name>.xmf for ParaView.
!> The layout is a contract with users' scripts; doc/output.md describes it.
!> Every procedure is collective over the communicator given to open: all ranks call
!> them in the same order with the same set names, steps, times and diagnostics.
module dpmpm_output
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_char, c_null_char
  use mpi_f08, only: MPI_Comm, MPI_Comm_dup, MPI_Comm_free, MPI_Comm_rank, MPI_Comm_size, &
                     MPI_Barrier, MPI_Bcast, MPI_Exscan, MPI_Allreduce, MPI_INTEGER, &
                     MPI_SUM, MPI_MIN, MPI_MAX, MPI_CHARACTER, MPI_Wtime, MPI_IN_PLACE
  use hdf5, only: hid_t, hsize_t, h5fcreate_f, h5fclose_f, h5fflush_f, h5pclose_f, h5gcreate_f, &
                  h5gclose_f, h5screate_f, h5screate_simple_f, h5gopen_f, h5sclose_f, &
                  h5sselect_hyperslab_f, h5sselect_none_f, h5dcreate_f, h5dwrite_f, h5dclose_f, &
                  h5dset_extent_f, h5dget_space_f, h5tclose_f, h5lexists_f, h5kind_to_type, &
                  H5_REAL_KIND, H5_INTEGER_KIND, H5F_ACC_TRUNC_F, H5F_SCOPE_GLOBAL_F, H5P_DEFAULT_F, &
                  H5S_SCALAR_F, H5S_SELECT_SET_F, H5T_IEEE_F64LE, H5T_STD_I64LE, H5T_STD_I32LE, &
                  h5fopen_f, h5adelete_f, h5aexists_f, h5eset_auto_f, H5F_ACC_RDONLY_F, h5ocopy_f
  use dpmpm_kinds, only: wp, i8, i4, mpi_i8
  use dpmpm_error, only: fatal
  use dpmpm_strings, only: itoa, ftoa
  use dpmpm_config, only: config_t, optional_fields, field_listed
  use dpmpm_particles, only: particle_set_t
  use dpmpm_model_table, only: model_from_name, scene_state_names
  use dpmpm_diagnostics, only: diag_record_t, ndiag_real, diag_real_names
  use dpmpm_build_info, only: dpmpm_version, git_commit
  use dpmpm_h5, only: h5check, make_dir, string_type, attr_string, attr_i4, attr_i8, attr_real, &
                      write_columns, write_check_t, mpio_access_list, &
                      collective_transfer_list, rename_file, link_file, io_begin, io_check
  use dpmpm_log, only: log_t
  use dpmpm_xdmf, only: frame_rec_t, set_rec_t, write_xdmf
  use dpmpm_h5_salvage, only: file_sound, frame_sound, read_diag_records
  use dpmpm_output_resume, only: ndiag_dsets, create_diag_dset, open_in_place, read_frame_records, &
                                 reopen_diagnostics
  use dpmpm_posix, only: posix_write_file, posix_fsync, posix_strerror
  implicit none
  private
  public :: output_t, output_h5_path, output_xmf_path

  !> The output file of one run. open ... (begin_frame, write_set..., end_frame)... close;
  !> add_diag at any time, flushed at each end_frame and at close. May be opened again
  !> after close (a second run in the same process).
  type :: output_t
    private
    logical :: is_open = .false.
    logical :: in_frame = .false.
    type(MPI_Comm) :: comm
    integer :: rank = 0
    integer :: nranks = 1
    integer :: ndim = 0
    character(len=:), allocatable :: h5_path, xmf_path, h5_base, dir
    integer(hid_t) :: file_id = -1
    integer(hid_t) :: frame_id = -1
    integer(hid_t) :: dxpl = -1
    integer :: compression = 0
    integer(hid_t) :: diag_dset(ndiag_dsets) = -1
    integer :: nframes = 0
    type(frame_rec_t), allocatable :: frames(:)
    integer :: nsets = 0
    type(set_rec_t), allocatable :: sets(:)
    integer :: ndiag_buf = 0
    type(diag_record_t), allocatable :: diag_buf(:)
    integer(i8) :: ndiag_written = 0
    !> Blocks written since the last read-back check, and what the checks found and cost.
    type(write_check_t) :: check
    type(log_t) :: log
    integer :: nchecks = 0
    integer :: nrewritten = 0
    real(wp) :: check_seconds = 0.0_wp
    !> The names of the state values of the scene's models, one dataset each in the solid
    !> set (dpmpm_model_table's scene_state_names).
    character(len=24), allocatable :: state_names(:)
  contains
    procedure :: open => out_open
    procedure :: resume => out_resume
    procedure :: begin_frame => out_begin_frame
    procedure :: write_set => out_write_set
    procedure :: end_frame => out_end_frame
    procedure :: add_diag => out_add_diag
    procedure :: flush_diag => out_flush_diag
    procedure :: write_verification => out_write_verification
    procedure :: write_verification_attr => out_write_verification_attr
    procedure :: close => out_close
    procedure :: is_active => out_is_active
  end type output_t

contains

  !> Path of the HDF5 file of a run: <output_dir>/<name>.h5.
  function output_h5_path(cfg) result(path)
    type(config_t), intent(in) :: cfg
    character(len=:), allocatable :: path
    path = trim(cfg%output_dir)//'/'//trim(cfg%name)//'.h5'
  end function output_h5_path

  !> Path of the XDMF sidecar of a run: <output_dir>/<name>.xmf.
  function output_xmf_path(cfg) result(path)
    type(config_t), intent(in) :: cfg
    character(len=:), allocatable :: path
    path = trim(cfg%output_dir)//'/'//trim(cfg%name)//'.xmf'
  end function output_xmf_path

  !> True between open and close.
  pure logical function out_is_active(self)
    class(output_t), intent(in) :: self
    out_is_active = self%is_open
  end function out_is_active

  !> Create (truncate) the run's file collectively over comm: root attributes, /input,
  !> empty /frames and extendible /diagnostics datasets. Creates output_dir if missing.
  !> The file is marked as being written (set_mark) until close.
  subroutine out_open(self, cfg, comm)
    class(output_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    call start(self, cfg, comm)
    if (self%rank == 0) call make_dir(trim(cfg%output_dir))
    call MPI_Barrier(self%comm)
    call set_mark(self, 'output%open')
    call create_file(self, cfg, self%h5_path)
  end subroutine out_open

  !> Create (truncate) path collectively as a run's file (root attributes, /input, empty
  !> /frames and /diagnostics), flushed and left open in self.
  subroutine create_file(self, cfg, path)
    class(output_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    character(len=*), intent(in) :: path
    character(len=*), parameter :: where = 'output%open'
    integer(hid_t) :: fapl, gid
    integer :: err, k
    fapl = mpio_access_list(self%comm, where)
    call io_begin()
    call h5fcreate_f(path, H5F_ACC_TRUNC_F, self%file_id, err, &
                     creation_prp=H5P_DEFAULT_F, access_prp=fapl)
    call io_check(err, 'h5fcreate_f', path, where)
    call h5pclose_f(fapl, err)
    call h5check(err, 'h5pclose_f(file access)', where)
    self%dxpl = collective_transfer_list(where)

    call attr_string(self%file_id, 'dpmpm_version', dpmpm_version)
    call attr_string(self%file_id, 'git_commit', git_commit)
    call attr_i4(self%file_id, 'nranks', int(self%nranks, i4))
    call attr_i4(self%file_id, 'ndim', int(cfg%ndim, i4))
    call write_input(self, cfg)

    call h5gcreate_f(self%file_id, 'frames', gid, err)
    call h5check(err, 'h5gcreate_f(/frames)', where)
    call h5gclose_f(gid, err)
    call h5check(err, 'h5gclose_f(/frames)', where)

    call h5gcreate_f(self%file_id, 'diagnostics', gid, err)
    call h5check(err, 'h5gcreate_f(/diagnostics)', where)
    call create_diag_dset(gid, 'step', H5T_STD_I64LE, self%diag_dset(1))
    call create_diag_dset(gid, 'npoints', H5T_STD_I64LE, self%diag_dset(2))
    do k = 1, ndiag_real
      call create_diag_dset(gid, trim(diag_real_names(k)), H5T_IEEE_F64LE, self%diag_dset(2 + k))
    end do
    call h5gclose_f(gid, err)
    call h5check(err, 'h5gclose_f(/diagnostics)', where)

    call io_begin()
    call h5fflush_f(self%file_id, H5F_SCOPE_GLOBAL_F, err)
    call io_check(err, 'h5fflush_f', path, where)
    self%is_open = .true.
    self%in_frame = .false.
  end subroutine create_file

  !> Continue the file of an earlier run from its checkpoint (collective): open
  !> <dir>/<name>.h5, keep its first nframes frames and the diagnostics before step, delete
  !> what the earlier run wrote after that (the continued run writes it again), and go on
  !> numbering frames from nframes. A file that its writer did not close (its mark is there:
  !> the run was killed or stopped on an error), or that is found damaged, is not continued
  !> in place but rebuilt first (rebuild): nframes becomes the number of frames kept, and
  !> why says so and names what was lost. ok is false, with nothing written, where there is
  !> no such file; the caller then starts a new file.
  subroutine out_resume(self, cfg, comm, nframes, step, ok, why)
    class(output_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    integer, intent(inout) :: nframes
    integer(i8), intent(in) :: step
    logical, intent(out) :: ok
    character(len=:), allocatable, intent(out) :: why
    character(len=*), parameter :: where = 'output%resume'
    logical :: exists
    integer :: k, err
    call start(self, cfg, comm)
    ok = .false.
    ! Each question about the file is answered by every rank before any rank acts on it
    ! (rebuild renames the file): one rank must not find the file gone that another
    ! is about to rebuild.
    inquire (file=self%h5_path, exist=exists)
    k = merge(1, 0, exists)
    call MPI_Allreduce(MPI_IN_PLACE, k, 1, MPI_INTEGER, MPI_MIN, self%comm)
    if (k == 0) then
      why = 'no file '//self%h5_path
      call MPI_Comm_free(self%comm)
      return
    end if
    ok = .true.
    why = ''
    ! A writer that died can leave the file torn anywhere, also where no reading finds it
    ! (the headers of the diagnostics that the next extension loads): never appended to.
    inquire (file=mark_path(self), exist=exists)
    k = merge(1, 0, exists)
    call MPI_Allreduce(MPI_IN_PLACE, k, 1, MPI_INTEGER, MPI_MAX, self%comm)
    if (k == 1) then
      call rebuild(self, cfg, comm, nframes, step, .true., why)
    else
      ! A file closed by its writer and damaged since (HDF5 cannot open it, a group or frame
      ! header is damaged): rebuilt too.
      k = merge(1, 0, file_sound(self%h5_path, nframes))
      call MPI_Allreduce(MPI_IN_PLACE, k, 1, MPI_INTEGER, MPI_MIN, self%comm)
      if (k == 0) call rebuild(self, cfg, comm, nframes, step, .false., why)
    end if
    call set_mark(self, where)
    call open_in_place(self%h5_path, self%comm, nframes, self%file_id, err)
    if (err < 0) then
      ! A damaged group can refuse the deletion of the later frames (its name heap broken):
      ! the file is then rebuilt from the frames before the checkpoint.
      if (len(why) > 0) call fatal('cannot delete the frames after the checkpoint in '// &
                                   self%h5_path//', rebuilt from what it held', where)
      call rebuild(self, cfg, comm, nframes, step, .false., why)
      call open_in_place(self%h5_path, self%comm, nframes, self%file_id, err)
      if (err < 0) call fatal('cannot delete the frames after the checkpoint in '// &
                              self%h5_path//', rebuilt from what it held', where)
    end if
    call continue_in_place(self, nframes, step)
  end subroutine out_resume

  !> After open_in_place: the records of the first nframes frames, the diagnostics before
  !> step (the rest cut off), this run's rank count, and the sidecar.
  subroutine continue_in_place(self, nframes, step)
    class(output_t), intent(inout) :: self
    integer, intent(in) :: nframes
    integer(i8), intent(in) :: step
    character(len=*), parameter :: where = 'output%resume'
    logical :: exists
    integer :: err, k, nkeep
    self%dxpl = collective_transfer_list(where)
    call h5aexists_f(self%file_id, 'nranks', exists, err)
    if (exists) call h5adelete_f(self%file_id, 'nranks', err)
    call attr_i4(self%file_id, 'nranks', int(self%nranks, i4))
    do k = 0, nframes - 1
      call add_frame_records(self, k, where)
    end do
    call reopen_diagnostics(self%file_id, step, self%diag_dset, nkeep, where)
    self%ndiag_written = nkeep
    call io_begin()
    call h5fflush_f(self%file_id, H5F_SCOPE_GLOBAL_F, err)
    call io_check(err, 'h5fflush_f', self%h5_path, where)
    self%is_open = .true.
    self%in_frame = .false.
    if (self%rank == 0) call write_xdmf(self%xmf_path, self%h5_base, self%ndim, &
                                        self%frames(1:self%nframes), self%sets(1:self%nsets), &
                                        self%state_names)
    call MPI_Barrier(self%comm)
  end subroutine continue_in_place

  !> Rebuild <name>.h5 (collective) from what it holds: the frames before nframes that can
  !> still be read are copied in order (renumbered without gaps), with the diagnostics
  !> records before step, into a new file <name>.h5.tmp; once that is closed and on the
  !> disk, the old file is kept as <name>.damaged.h5 and the new one renamed <name>.h5. A
  !> kill meanwhile leaves a <name>.h5 and its mark, for the next try. nframes becomes
  !> the number of frames kept; why says why (left_open: the writer did not close the file;
  !> otherwise it is damaged) and what was lost. self is as after start again.
  subroutine rebuild(self, cfg, comm, nframes, step, left_open, why)
    class(output_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    integer, intent(inout) :: nframes
    integer(i8), intent(in) :: step
    logical, intent(in) :: left_open
    character(len=:), allocatable, intent(out) :: why
    character(len=*), parameter :: where = 'output%rebuild'
    character(len=:), allocatable :: tmp, damaged
    character(len=32) :: src_name, dst_name
    integer(hid_t) :: src
    integer :: err, e2, k, j, kept, nlost, ndiag
    type(diag_record_t), allocatable :: recs(:)
    tmp = self%h5_path//'.tmp'
    damaged = self%h5_path(1:len(self%h5_path) - 3)//'.damaged.h5'
    call create_file(self, cfg, tmp)
    kept = 0
    nlost = 0
    ndiag = 0
    ! Every rank reads the old file on its own; each copy is made only where every rank can
    ! make it (the new file is written collectively).
    call h5eset_auto_f(0, err)
    call h5fopen_f(self%h5_path, H5F_ACC_RDONLY_F, src, err)
    j = merge(1, 0, err >= 0)
    call MPI_Allreduce(MPI_IN_PLACE, j, 1, MPI_INTEGER, MPI_MIN, self%comm)
    if (j == 0 .and. err >= 0) call h5fclose_f(src, e2)
    if (j == 1) then
      do k = 0, nframes - 1
        write (src_name, '(a,i6.6)') 'frames/', k
        write (dst_name, '(a,i6.6)') 'frames/', kept
        j = merge(1, 0, frame_sound(src, k))
        call MPI_Allreduce(MPI_IN_PLACE, j, 1, MPI_INTEGER, MPI_MIN, self%comm)
        err = -1
        if (j == 1) then
          call h5ocopy_f(src, trim(src_name), self%file_id, trim(dst_name), err)
          call MPI_Allreduce(err, e2, 1, MPI_INTEGER, MPI_MAX, self%comm)
          call MPI_Allreduce(MPI_IN_PLACE, err, 1, MPI_INTEGER, MPI_MIN, self%comm)
          if (err < 0 .and. e2 >= 0) call fatal('the ranks copied '//trim(src_name)//' of '// &
                                                self%h5_path//' differently', where)
        end if
        if (err >= 0) then
          kept = kept + 1
        else
          nlost = nlost + 1
        end if
      end do
      call read_diag_records(src, step, recs, ndiag)
      call h5fclose_f(src, e2)
    else
      nlost = nframes
    end if
    call h5eset_auto_f(1, e2)
    do k = 1, ndiag
      call self%add_diag(recs(k))
    end do
    call self%flush_diag()
    call verify_written(self, where)
    call close_file(self, tmp, where)
    ! Closed by every rank and on the disk before it replaces the file, and the new names on
    ! the disk after.
    call MPI_Barrier(self%comm)
    if (self%rank == 0) then
      err = posix_fsync(tmp)
      if (err /= 0) call fatal('cannot flush '//tmp//' to the disk: '//posix_strerror(err), where)
      ! (A file system without hard links leaves a moment without <name>.h5.)
      if (.not. link_file(self%h5_path, damaged)) call rename_file(self%h5_path, damaged, where)
      call rename_file(tmp, self%h5_path, where)
      err = posix_fsync(self%dir)
      if (err /= 0) call fatal('cannot flush directory '//self%dir//' to the disk: '// &
                               posix_strerror(err), where)
    end if
    call MPI_Barrier(self%comm)
    if (left_open) then
      why = self%h5_path//' was not closed by the run that wrote it (killed, or stopped on '// &
            'an error), so it is not continued in place: kept as '//damaged//', its '// &
            itoa(kept)//' readable frames of '//itoa(nframes)//' and '//itoa(ndiag)// &
            ' diagnostics records copied into a new '//self%h5_path
    else
      why = self%h5_path//' is damaged (as a kill while writing can leave it); kept as '// &
            damaged//', its '//itoa(kept)//' readable frames of '//itoa(nframes)//' and '// &
            itoa(ndiag)//' diagnostics records copied into a new '//self%h5_path
    end if
    if (nlost > 0) why = why//'; '//itoa(nlost)//' frames could not be read and are lost'
    nframes = kept
    call MPI_Comm_free(self%comm)
    call start(self, cfg, comm)
  end subroutine rebuild

  !> The state of an output_t before a file is opened: communicator, paths, no records.
  subroutine start(self, cfg, comm)
    class(output_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    integer :: k
    if (self%is_open) call self%close()
    call MPI_Comm_dup(comm, self%comm)
    call MPI_Comm_rank(self%comm, self%rank)
    call MPI_Comm_size(self%comm, self%nranks)
    self%ndim = cfg%ndim
    self%compression = cfg%compression
    self%h5_path = output_h5_path(cfg)
    self%xmf_path = output_xmf_path(cfg)
    self%h5_base = trim(cfg%name)//'.h5'
    self%dir = trim(cfg%output_dir)
    self%state_names = scene_state_names([(model_from_name(cfg%materials(k)%model), &
                                           k=1, size(cfg%materials))], &
                                         [(cfg%materials(k)%umat_nstatev, k=1, size(cfg%materials))])
    self%nframes = 0
    self%nsets = 0
    self%ndiag_buf = 0
    self%ndiag_written = 0
    self%nchecks = 0
    self%nrewritten = 0
    self%check_seconds = 0.0_wp
    call self%log%init(self%comm)
    if (.not. allocated(self%frames)) allocate (self%frames(16))
    if (.not. allocated(self%sets)) allocate (self%sets(16))
    if (.not. allocated(self%diag_buf)) allocate (self%diag_buf(64))
  end subroutine start

  !> Frame and set records (for the sidecar) of frame k as it is in the open file.
  subroutine add_frame_records(self, k, where)
    class(output_t), intent(inout) :: self
    integer, intent(in) :: k
    character(len=*), intent(in) :: where
    type(frame_rec_t) :: frame
    type(set_rec_t) :: sets(2)
    integer :: j, nsets
    call read_frame_records(self%file_id, k, self%state_names, frame, sets, nsets, where)
    call add_frame_rec(self, frame)
    do j = 1, nsets
      call add_set_rec(self, sets(j))
    end do
  end subroutine add_frame_records

  !> Append a frame to the records of the sidecar.
  subroutine add_frame_rec(self, rec)
    class(output_t), intent(inout) :: self
    type(frame_rec_t), intent(in) :: rec
    type(frame_rec_t), allocatable :: tmp(:)
    if (self%nframes + 1 > size(self%frames)) then
      allocate (tmp(2*size(self%frames)))
      tmp(1:self%nframes) = self%frames(1:self%nframes)
      call move_alloc(tmp, self%frames)
    end if
    self%nframes = self%nframes + 1
    self%frames(self%nframes) = rec
  end subroutine add_frame_rec

  !> Append a point set of a frame to the records of the sidecar.
  subroutine add_set_rec(self, rec)
    class(output_t), intent(inout) :: self
    type(set_rec_t), intent(in) :: rec
    type(set_rec_t), allocatable :: tmp(:)
    if (self%nsets + 1 > size(self%sets)) then
      allocate (tmp(2*size(self%sets)))
      tmp(1:self%nsets) = self%sets(1:self%nsets)
      call move_alloc(tmp, self%sets)
    end if
    self%nsets = self%nsets + 1
    self%sets(self%nsets) = rec
  end subroutine add_set_rec

  !> Start frame /frames/NNNNNN (NNNNNN counts frames from 0) at a step and time (s).
  subroutine out_begin_frame(self, step, time)
    class(output_t), intent(inout) :: self
    integer(i8), intent(in) :: step
    real(wp), intent(in) :: time
    character(len=*), parameter :: where = 'output%begin_frame'
    character(len=32) :: gname
    integer :: err
    if (.not. self%is_open) call fatal('the output file is not open', where)
    if (self%in_frame) call fatal('the previous frame was not ended', where)
    write (gname, '(a,i6.6)') 'frames/', self%nframes
    call h5gcreate_f(self%file_id, trim(gname), self%frame_id, err)
    call h5check(err, 'h5gcreate_f('//trim(gname)//')', where)
    call attr_real(self%frame_id, 'time', time)
    call attr_i8(self%frame_id, 'step', step)
    call add_frame_rec(self, frame_rec_t(step=step, time=time))
    self%in_frame = .true.
  end subroutine out_begin_frame

  !> Write a point set under the current frame as group ps%name (all ranks, even with no
  !> points). Each rank's points go to a contiguous block at the offset of its rank.
  !> id, x, v, mass and volume are always written; of the optional datasets, those that
  !> cfg%solid_fields (cfg%fluid_fields for the set named 'fluid') lists: displacement,
  !> stress (not for the fluid: it is -pore_pressure on the diagonal), material, porosity
  !> (when ps%has_porosity), pore_pressure (when ps%has_pressure) and, for 'state', one
  !> dataset per state value of the models (when ps%nstate > 0), named by the model table.
  !> Every rank must hold the set with the same flags.
  subroutine out_write_set(self, ps, cfg)
    class(output_t), intent(inout) :: self
    type(particle_set_t), intent(in) :: ps
    type(config_t), intent(in) :: cfg
    character(len=*), parameter :: where = 'output%write_set'
    integer(hid_t) :: gid
    integer(i8) :: nloc, offset, nglob
    integer(i4), allocatable :: matid(:)
    character(len=:), allocatable :: fields
    logical :: has(size(optional_fields)), fluid
    integer :: err, k, n, d, flags(2), fmin(2), fmax(2)
    if (.not. self%is_open) call fatal('the output file is not open', where)
    if (.not. self%in_frame) call fatal('write_set outside begin_frame/end_frame', where)
    if (ps%ndim /= self%ndim) call fatal('point set '//trim(ps%name)//' has a different ndim '// &
                                         'than the file', where)
    n = ps%n
    d = ps%ndim
    nloc = int(n, i8)
    offset = 0
    call MPI_Exscan(nloc, offset, 1, mpi_i8(), MPI_SUM, self%comm)
    if (self%rank == 0) offset = 0
    call MPI_Allreduce(nloc, nglob, 1, mpi_i8(), MPI_SUM, self%comm)
    ! The optional datasets are created collectively: all ranks must agree on them.
    flags = merge(1, 0, [ps%has_porosity, ps%has_pressure])
    call MPI_Allreduce(flags, fmin, 2, MPI_INTEGER, MPI_MIN, self%comm)
    call MPI_Allreduce(flags, fmax, 2, MPI_INTEGER, MPI_MAX, self%comm)
    if (any(fmin /= fmax)) call fatal('ranks hold point set '//trim(ps%name)//' with '// &
                                      'different optional fields (porosity, pressure)', where)

    fluid = ps%name == 'fluid'
    fields = trim(merge(cfg%fluid_fields, cfg%solid_fields, fluid))
    do k = 1, size(optional_fields)
      has(k) = field_listed(fields, trim(optional_fields(k)))
    end do
    has(2) = has(2) .and. .not. fluid
    has(4) = has(4) .and. ps%has_porosity
    has(5) = has(5) .and. ps%has_pressure
    has(6) = has(6) .and. ps%nstate > 0
    has(7) = field_listed(fields, 'rank', explicit=.true.)
    if (has(6) .and. ps%nstate /= size(self%state_names)) &
      call fatal('point set '//trim(ps%name)//' keeps another number of state values than '// &
                 'the scene''s models name', where)

    allocate (matid(n))
    do k = 1, n
      if (ps%mat(k) < 1 .or. ps%mat(k) > size(cfg%materials)) &
        call fatal('point with a material index outside the configured materials', where)
      matid(k) = int(cfg%materials(ps%mat(k))%id, i4)
    end do

    call h5gcreate_f(self%frame_id, trim(ps%name), gid, err)
    call h5check(err, 'h5gcreate_f('//trim(ps%name)//')', where)
    call write_points_i8(self, gid, 'id', 0, nloc, offset, nglob, ps%id(1:n))
    call write_points_real(self, gid, 'x', d, nloc, offset, nglob, reshape(ps%x(:, 1:n), [d*n]))
    call write_points_real(self, gid, 'v', d, nloc, offset, nglob, reshape(ps%v(:, 1:n), [d*n]))
    if (has(1)) call write_points_real(self, gid, 'displacement', d, nloc, offset, nglob, &
                                       reshape(ps%x(:, 1:n) - ps%x0(:, 1:n), [d*n]))
    call write_points_real(self, gid, 'mass', 0, nloc, offset, nglob, ps%mass(1:n))
    call write_points_real(self, gid, 'volume', 0, nloc, offset, nglob, ps%vol(1:n))
    if (has(2)) call write_points_real(self, gid, 'stress', 6, nloc, offset, nglob, &
                                       reshape(ps%stress(:, 1:n), [6*n]))
    if (has(3)) call write_points_i4(self, gid, 'material', 0, nloc, offset, nglob, matid)
    if (has(4)) call write_points_real(self, gid, 'porosity', 0, nloc, offset, nglob, &
                                       ps%porosity(1:n))
    if (has(5)) call write_points_real(self, gid, 'pore_pressure', 0, nloc, offset, nglob, &
                                       ps%pressure(1:n))
    do k = 1, merge(ps%nstate, 0, has(6))
      call write_points_real(self, gid, trim(self%state_names(k)), 0, nloc, offset, nglob, &
                             ps%state(k, 1:n))
    end do
    if (has(7)) then
      matid = int(self%rank, i4)
      call write_points_i4(self, gid, 'rank', 0, nloc, offset, nglob, matid)
    end if
    call h5gclose_f(gid, err)
    call h5check(err, 'h5gclose_f('//trim(ps%name)//')', where)

    call add_set_rec(self, set_rec_t(frame=self%nframes - 1, name=ps%name, n=nglob, has=has))
  end subroutine out_write_set

  !> Close the current frame, write buffered diagnostics, flush the file to disk, read back
  !> and compare what every rank wrote (verify_written), and rewrite the XDMF sidecar
  !> (rank 0) so that a crashed run keeps every finished frame.
  subroutine out_end_frame(self)
    class(output_t), intent(inout) :: self
    character(len=*), parameter :: where = 'output%end_frame'
    integer :: err
    if (.not. self%in_frame) call fatal('end_frame without begin_frame', where)
    call h5gclose_f(self%frame_id, err)
    call h5check(err, 'h5gclose_f(frame)', where)
    self%frame_id = -1
    self%in_frame = .false.
    call self%flush_diag()
    call verify_written(self, where)
    if (self%rank == 0) call write_xdmf(self%xmf_path, self%h5_base, self%ndim, &
                                        self%frames(1:self%nframes), self%sets(1:self%nsets), &
                                        self%state_names)
    call MPI_Barrier(self%comm)
  end subroutine out_end_frame

  !> Buffer one diagnostics record (every rank adds the same records).
  subroutine out_add_diag(self, rec)
    class(output_t), intent(inout) :: self
    type(diag_record_t), intent(in) :: rec
    type(diag_record_t), allocatable :: tmp(:)
    if (.not. self%is_open) call fatal('the output file is not open', 'output%add_diag')
    if (self%ndiag_buf + 1 > size(self%diag_buf)) then
      allocate (tmp(2*size(self%diag_buf)))
      tmp(1:self%ndiag_buf) = self%diag_buf(1:self%ndiag_buf)
      call move_alloc(tmp, self%diag_buf)
    end if
    self%ndiag_buf = self%ndiag_buf + 1
    self%diag_buf(self%ndiag_buf) = rec
  end subroutine out_add_diag

  !> Append the buffered records to the /diagnostics datasets (extended collectively;
  !> rank 0 writes the values, the others take part with empty selections).
  subroutine out_flush_diag(self)
    class(output_t), intent(inout) :: self
    character(len=*), parameter :: where = 'output%flush_diag'
    integer :: nmin, nmax, m, k, j
    integer(i8), allocatable, target :: ibuf(:)
    real(wp), allocatable, target :: rbuf(:)
    integer(hid_t) :: ti8, twp
    if (.not. self%is_open) call fatal('the output file is not open', where)
    call MPI_Allreduce(self%ndiag_buf, nmin, 1, MPI_INTEGER, MPI_MIN, self%comm)
    call MPI_Allreduce(self%ndiag_buf, nmax, 1, MPI_INTEGER, MPI_MAX, self%comm)
    if (nmin /= nmax) call fatal('ranks hold different numbers of diagnostics records', where)
    m = self%ndiag_buf
    if (m == 0) return
    ti8 = h5kind_to_type(i8, H5_INTEGER_KIND)
    twp = h5kind_to_type(wp, H5_REAL_KIND)
    allocate (ibuf(m), rbuf(m))
    ibuf = self%diag_buf(1:m)%step
    call append_diag(self, self%diag_dset(1), ti8, m, c_loc(ibuf))
    ibuf = self%diag_buf(1:m)%npoints
    call append_diag(self, self%diag_dset(2), ti8, m, c_loc(ibuf))
    do k = 1, ndiag_real
      rbuf = [(self%diag_buf(j)%values(k), j=1, m)]
      call append_diag(self, self%diag_dset(2 + k), twp, m, c_loc(rbuf))
    end do
    self%ndiag_written = self%ndiag_written + m
    self%ndiag_buf = 0
  end subroutine out_flush_diag

  !> Write values as the 1D double dataset /verification/<name> (benchmark errors, norms),
  !> or in group (created when missing) as n x columns (values(columns, n), rank 0's).
  subroutine out_write_verification(self, name, values, group, columns)
    class(output_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: values(:)
    character(len=*), intent(in), optional :: group
    integer, intent(in), optional :: columns
    character(len=*), parameter :: where = 'output%write_verification'
    integer(hid_t) :: gid
    integer :: err, m
    integer(i8) :: n, nloc
    if (.not. self%is_open) call fatal('the output file is not open', where)
    m = 0
    if (present(columns)) m = columns
    if (present(group)) then
      gid = named_group(self, group)
    else
      gid = named_group(self, 'verification')
    end if
    n = size(values, kind=i8)/max(m, 1)
    nloc = merge(n, 0_i8, self%rank == 0)
    call write_points_real(self, gid, name, m, nloc, 0_i8, n, values(1:max(m, 1)*nloc))
    call h5gclose_f(gid, err)
    call h5check(err, 'h5gclose_f(group of '//name//')', where)
  end subroutine out_write_verification

  !> Write a scalar as attribute <name> of /verification (e.g. an L2 error of a benchmark).
  subroutine out_write_verification_attr(self, name, value)
    class(output_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: value
    integer(hid_t) :: gid
    integer :: err
    if (.not. self%is_open) call fatal('the output file is not open', &
                                       'output%write_verification_attr')
    gid = named_group(self, 'verification')
    call attr_real(gid, name, value)
    call h5gclose_f(gid, err)
    call h5check(err, 'h5gclose_f(/verification)', 'output%write_verification_attr')
  end subroutine out_write_verification_attr

  !> End an open frame, flush the diagnostics, close the file and remove its mark. The HDF5
  !> library stays initialised, so another output_t can be opened later in the same process.
  subroutine out_close(self)
    class(output_t), intent(inout) :: self
    character(len=*), parameter :: where = 'output%close'
    character(len=160) :: line
    if (.not. self%is_open) return
    if (self%in_frame) call self%end_frame()
    call self%flush_diag()
    call verify_written(self, where)
    if (self%nchecks > 0) then
      write (line, '(a,i0,a,i0,a)') 'output: ', self%nchecks, &
        ' read-back checks of the written blocks, '//ftoa(1.0e3_wp*self%check_seconds/self%nchecks, 2)// &
        ' ms each; ', self%nrewritten, ' blocks rewritten'
      call self%log%info(trim(line))
    end if
    call close_file(self, self%h5_path, where)
    call clear_mark(self)
    call MPI_Comm_free(self%comm)
  end subroutine out_close

  ! ---------------------------------------------------------------- helpers

  !> Close the diagnostics datasets, the transfer list and the file open in self (named
  !> path in messages).
  subroutine close_file(self, path, where)
    type(output_t), intent(inout) :: self
    character(len=*), intent(in) :: path, where
    integer :: err, k
    do k = 1, ndiag_dsets
      call h5dclose_f(self%diag_dset(k), err)
      call h5check(err, 'h5dclose_f(diagnostics)', where)
      self%diag_dset(k) = -1
    end do
    call h5pclose_f(self%dxpl, err)
    call h5check(err, 'h5pclose_f(transfer)', where)
    self%dxpl = -1
    call io_begin()
    call h5fclose_f(self%file_id, err)
    call io_check(err, 'h5fclose_f', path, where)
    self%file_id = -1
    self%is_open = .false.
  end subroutine close_file

  !> The mark that the run's file is open for writing: <output_dir>/<name>.h5.writing. It
  !> is made before the file is created or opened for writing and removed once the file
  !> is closed, so a continued run that finds it knows that the writer died with the file
  !> open (killed, or stopped on an error) and rebuilds the file (out_resume).
  function mark_path(self) result(path)
    type(output_t), intent(in) :: self
    character(len=:), allocatable :: path
    path = self%h5_path//'.writing'
  end function mark_path

  !> Make the mark (rank 0), on the disk before any rank writes to the file.
  subroutine set_mark(self, where)
    type(output_t), intent(in) :: self
    character(len=*), intent(in) :: where
    character(len=:), allocatable :: mark
    integer :: err
    if (self%rank == 0) then
      mark = mark_path(self)
      err = posix_write_file(mark, 'dpmpm is writing '//self%h5_path//'; a run continued '// &
                             'while this file is here rebuilds it (doc/input.md, "Restart")'// &
                             new_line('a'))
      if (err /= 0) call fatal('cannot write '//mark//': '//posix_strerror(err), where)
      err = posix_fsync(mark)
      if (err == 0) err = posix_fsync(self%dir)
      if (err /= 0) call fatal('cannot flush '//mark//' to the disk: '//posix_strerror(err), where)
    end if
    call MPI_Barrier(self%comm)
  end subroutine set_mark

  !> Remove the mark (rank 0) once every rank has closed the file. A mark left behind
  !> costs only a rebuild when the run is continued: its removal is not checked.
  subroutine clear_mark(self)
    type(output_t), intent(in) :: self
    integer :: u, ios
    call MPI_Barrier(self%comm)
    if (self%rank /= 0) return
    open (newunit=u, file=mark_path(self), status='old', iostat=ios)
    if (ios == 0) close (u, status='delete', iostat=ios)
  end subroutine clear_mark

  !> Read back every block written since the last call and compare it with what was
  !> written (write_check_t%verify: flush, independent read, rewrite and re-read on a
  !> mismatch, fatal when that fails too). Says so in the log the first time a block had
  !> to be rewritten; close reports the count and the cost.
  subroutine verify_written(self, where)
    type(output_t), intent(inout) :: self
    character(len=*), intent(in) :: where
    character(len=200) :: line
    integer :: nrew
    real(wp) :: t0
    t0 = MPI_Wtime()
    call self%check%verify(self%file_id, self%comm, where, nrew)
    self%check_seconds = self%check_seconds + (MPI_Wtime() - t0)
    self%nchecks = self%nchecks + 1
    if (nrew > 0 .and. self%nrewritten == 0) then
      write (line, '(a,i0,a,i0,a)') 'output: frame ', max(self%nframes - 1, 0), ': ', nrew, &
        ' blocks read back differently from what the collective write was given; '// &
        'rewritten with independent I/O and verified'
      call self%log%info(trim(line))
    end if
    self%nrewritten = self%nrewritten + nrew
  end subroutine verify_written

  !> /input: the input file as one fixed-length string (scalar dataset). Rank 0's text is
  !> broadcast so that every rank writes the same bytes.
  subroutine write_input(self, cfg)
    type(output_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    character(len=*), parameter :: where = 'output%open'
    character(kind=c_char, len=:), allocatable, target :: text
    integer :: n, err
    integer(hid_t) :: space, dset, stype
    n = 0
    if (self%rank == 0 .and. allocated(cfg%input_text)) n = len(cfg%input_text)
    call MPI_Bcast(n, 1, MPI_INTEGER, 0, self%comm)
    allocate (character(kind=c_char, len=max(n, 1)) :: text)
    text(:) = c_null_char
    if (self%rank == 0 .and. n > 0) text(:) = cfg%input_text
    if (n > 0) call MPI_Bcast(text, n, MPI_CHARACTER, 0, self%comm)
    stype = string_type(max(n, 1))
    call h5screate_f(H5S_SCALAR_F, space, err)
    call h5check(err, 'h5screate_f(scalar)', where)
    call h5dcreate_f(self%file_id, 'input', stype, space, dset, err)
    call h5check(err, 'h5dcreate_f(/input)', where)
    call io_begin()
    call h5dwrite_f(dset, stype, c_loc(text), err, xfer_prp=self%dxpl)
    call io_check(err, 'h5dwrite_f(/input)', self%h5_path, where)
    call h5dclose_f(dset, err)
    call h5check(err, 'h5dclose_f(/input)', where)
    call h5sclose_f(space, err)
    call h5check(err, 'h5sclose_f', where)
    call h5tclose_f(stype, err)
    call h5check(err, 'h5tclose_f', where)
  end subroutine write_input

  !> Extend one diagnostics dataset by m entries and write them from rank 0.
  subroutine append_diag(self, dset, mtype, m, ptr)
    type(output_t), intent(inout) :: self
    integer(hid_t), intent(in) :: dset, mtype
    integer, intent(in) :: m
    type(c_ptr), intent(in) :: ptr
    character(len=*), parameter :: where = 'output%flush_diag'
    integer(hid_t) :: fspace, mspace
    integer :: err
    call io_begin()
    call h5dset_extent_f(dset, [int(self%ndiag_written + m, hsize_t)], err)
    call io_check(err, 'h5dset_extent_f', self%h5_path, where)
    call h5dget_space_f(dset, fspace, err)
    call h5check(err, 'h5dget_space_f', where)
    call h5screate_simple_f(1, [int(m, hsize_t)], mspace, err)
    call h5check(err, 'h5screate_simple_f', where)
    if (self%rank == 0) then
      call h5sselect_hyperslab_f(fspace, H5S_SELECT_SET_F, [int(self%ndiag_written, hsize_t)], &
                                 [int(m, hsize_t)], err)
      call h5check(err, 'h5sselect_hyperslab_f', where)
    else
      call h5sselect_none_f(fspace, err)
      call h5check(err, 'h5sselect_none_f', where)
      call h5sselect_none_f(mspace, err)
      call h5check(err, 'h5sselect_none_f', where)
    end if
    call io_begin()
    call h5dwrite_f(dset, mtype, ptr, err, mem_space_id=mspace, file_space_id=fspace, &
                    xfer_prp=self%dxpl)
    call io_check(err, 'h5dwrite_f', self%h5_path, where)
    call self%check%add(dset, mtype, 1, [int(self%ndiag_written, hsize_t)], &
                        [int(merge(m, 0, self%rank == 0), hsize_t)], ptr, 'diagnostics', where)
    call h5sclose_f(mspace, err)
    call h5check(err, 'h5sclose_f', where)
    call h5sclose_f(fspace, err)
    call h5check(err, 'h5sclose_f', where)
  end subroutine append_diag

  !> write_columns with the file's collective transfer list.
  subroutine write_points(self, gid, name, ftype, mtype, m, nloc, offset, nglob, ptr)
    type(output_t), intent(inout) :: self
    integer(hid_t), intent(in) :: gid, ftype, mtype
    character(len=*), intent(in) :: name
    integer, intent(in) :: m
    integer(i8), intent(in) :: nloc, offset, nglob
    type(c_ptr), intent(in) :: ptr
    call write_columns(gid, self%dxpl, name, ftype, mtype, m, nloc, offset, nglob, ptr, &
                       'output%write_set', self%check, self%compression)
  end subroutine write_points

  !> write_points for doubles (file type IEEE F64LE).
  subroutine write_points_real(self, gid, name, m, nloc, offset, nglob, vals)
    type(output_t), intent(inout) :: self
    integer(hid_t), intent(in) :: gid
    character(len=*), intent(in) :: name
    integer, intent(in) :: m
    integer(i8), intent(in) :: nloc, offset, nglob
    real(wp), intent(in) :: vals(:)
    real(wp), allocatable, target :: buf(:)
    allocate (buf(max(size(vals), 1)))
    buf = 0.0_wp
    buf(1:size(vals)) = vals
    call write_points(self, gid, name, H5T_IEEE_F64LE, h5kind_to_type(wp, H5_REAL_KIND), m, &
                      nloc, offset, nglob, c_loc(buf))
  end subroutine write_points_real

  !> write_points for 64-bit integers (file type STD I64LE).
  subroutine write_points_i8(self, gid, name, m, nloc, offset, nglob, vals)
    type(output_t), intent(inout) :: self
    integer(hid_t), intent(in) :: gid
    character(len=*), intent(in) :: name
    integer, intent(in) :: m
    integer(i8), intent(in) :: nloc, offset, nglob
    integer(i8), intent(in) :: vals(:)
    integer(i8), allocatable, target :: buf(:)
    allocate (buf(max(size(vals), 1)))
    buf = 0
    buf(1:size(vals)) = vals
    call write_points(self, gid, name, H5T_STD_I64LE, h5kind_to_type(i8, H5_INTEGER_KIND), m, &
                      nloc, offset, nglob, c_loc(buf))
  end subroutine write_points_i8

  !> write_points for 32-bit integers (file type STD I32LE).
  subroutine write_points_i4(self, gid, name, m, nloc, offset, nglob, vals)
    type(output_t), intent(inout) :: self
    integer(hid_t), intent(in) :: gid
    character(len=*), intent(in) :: name
    integer, intent(in) :: m
    integer(i8), intent(in) :: nloc, offset, nglob
    integer(i4), intent(in) :: vals(:)
    integer(i4), allocatable, target :: buf(:)
    allocate (buf(max(size(vals), 1)))
    buf = 0
    buf(1:size(vals)) = vals
    call write_points(self, gid, name, H5T_STD_I32LE, h5kind_to_type(i4, H5_INTEGER_KIND), m, &
                      nloc, offset, nglob, c_loc(buf))
  end subroutine write_points_i4

  !> Open the group /<name> (/verification, /probes), creating it on first use. The caller
  !> closes the group.
  function named_group(self, name) result(gid)
    type(output_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer(hid_t) :: gid
    logical :: exists
    integer :: err
    call h5lexists_f(self%file_id, name, exists, err)
    call h5check(err, 'h5lexists_f(/'//name//')', 'output')
    if (exists) then
      call h5gopen_f(self%file_id, name, gid, err)
      call h5check(err, 'h5gopen_f(/'//name//')', 'output')
    else
      call h5gcreate_f(self%file_id, name, gid, err)
      call h5check(err, 'h5gcreate_f(/'//name//')', 'output')
    end if
  end function named_group

end module dpmpm_output
