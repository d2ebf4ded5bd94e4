!> Output tests: each rank writes a point set of its own size (one rank has none at 4
!> ranks) into the collective HDF5 file; rank 0 reads the file back serially and checks
!> the layout, the counts, that every id appears once and that the values written by
!> every rank arrived (matched by id). Several files are written in one process, so a
!> second open/close is covered too. A two-phase frame adds porosity and pore pressure.
!> The 2-rank files are checked again by scripts/check_output.py (ctest output_layout_np2).
program test_output
  use, intrinsic :: iso_c_binding, only: c_loc, c_ptr, c_char, c_null_char
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Comm, MPI_Comm_rank, MPI_Comm_size, MPI_Barrier
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5fopen_f, h5fclose_f, h5dopen_f, &
                  h5dclose_f, h5dread_f, h5dget_space_f, h5dget_type_f, h5sclose_f, &
                  h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5aopen_by_name_f, &
                  h5aread_f, h5aclose_f, h5aget_type_f, h5tget_size_f, h5tclose_f, h5lexists_f, &
                  h5kind_to_type, H5_REAL_KIND, H5_INTEGER_KIND, H5F_ACC_RDONLY_F
  use dpmpm_kinds, only: wp, i8, i4
  use dpmpm_error, only: fatal
  use dpmpm_config, only: config_t
  use dpmpm_particles, only: particle_set_t
  use dpmpm_diagnostics, only: diag_record_t, ndiag_real, diag_real_names
  use dpmpm_build_info, only: dpmpm_version
  use dpmpm_output, only: output_t, output_h5_path, output_xmf_path
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer :: rank, nranks
  character(len=*), parameter :: input_text = '&run name = ''test_output'' /'//new_line('a')// &
                                              '&grid ndim = 2 /'//new_line('a')
  call start_tests(rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  call test_two_frames_2d(MPI_COMM_WORLD)
  call test_second_file_3d(MPI_COMM_WORLD)
  call test_1d_with_empty_set(MPI_COMM_WORLD)
  call test_two_phase_sets(MPI_COMM_WORLD)
  call test_two_sets_three_frames(MPI_COMM_WORLD, 2)
  call test_two_sets_three_frames(MPI_COMM_WORLD, 1)
  call test_chosen_fields_uncompressed(MPI_COMM_WORLD)
  call test_rank_field_where_named(MPI_COMM_WORLD)
  call end_tests()

contains

  ! ------------------------------------------------------------------ tests

  !> Two frames of a 2D set, diagnostics flushed at both frames and at close, verification data.
  !> The file is marked as being written (<name>.h5.writing) from open to close.
  subroutine test_two_frames_2d(comm)
    type(MPI_Comm), intent(in) :: comm
    type(config_t) :: cfg
    type(output_t) :: out
    type(particle_set_t) :: ps
    logical :: marked
    integer :: j
    call begin_test('two_frames_2d')
    call make_config(cfg, 'test_output', 2, comm)
    call out%open(cfg, comm)
    call check(out%is_active(), 'open file is active')
    inquire (file=output_h5_path(cfg)//'.writing', exist=marked)
    call check(marked, 'open file is marked as being written')
    do j = 1, 2
      call out%add_diag(diag_record(j))
    end do
    call make_points(ps, 2, comm, frame=0)
    call out%begin_frame(0_i8, 0.0_wp)
    call out%write_set(ps, cfg)
    call out%end_frame()
    do j = 3, 4
      call out%add_diag(diag_record(j))
    end do
    call make_points(ps, 2, comm, frame=1)
    call out%begin_frame(frame_step(1), frame_time(1))
    call out%write_set(ps, cfg)
    call out%end_frame()
    call out%add_diag(diag_record(5))
    call out%write_verification('l2_error', [1.0_wp, 0.5_wp, 0.25_wp])
    call out%write_verification_attr('max_error', 0.125_wp)
    call out%close()
    call check(.not. out%is_active(), 'closed file is not active')
    if (rank == 0) then
      inquire (file=output_h5_path(cfg)//'.writing', exist=marked)
      call check(.not. marked, 'closed file is not marked')
    end if
    if (rank == 0) call verify_file(output_h5_path(cfg), 2, 2, 5, .true.)
    call check_xmf_exists(output_xmf_path(cfg))
    call MPI_Barrier(comm)
  end subroutine test_two_frames_2d

  !> A second file in the same process (open after close), 3D, one frame.
  subroutine test_second_file_3d(comm)
    type(MPI_Comm), intent(in) :: comm
    type(config_t) :: cfg
    type(output_t) :: out
    type(particle_set_t) :: ps
    call begin_test('second_file_3d')
    call make_config(cfg, 'test_output_3d', 3, comm)
    call out%open(cfg, comm)
    call out%add_diag(diag_record(1))
    call make_points(ps, 3, comm, frame=0)
    call out%begin_frame(0_i8, 0.0_wp)
    call out%write_set(ps, cfg)
    call out%end_frame()
    call out%close()
    if (rank == 0) call verify_file(output_h5_path(cfg), 3, 1, 1, .false.)
    call check_xmf_exists(output_xmf_path(cfg))
    call MPI_Barrier(comm)
  end subroutine test_second_file_3d

  !> 1D, and a 'fluid' set with no points on any rank; close ends the open frame itself.
  subroutine test_1d_with_empty_set(comm)
    type(MPI_Comm), intent(in) :: comm
    type(config_t) :: cfg
    type(output_t) :: out
    type(particle_set_t) :: ps, empty
    integer(hid_t) :: fid
    integer(hsize_t), allocatable :: dims(:)
    integer :: err
    call begin_test('1d_with_empty_set')
    call make_config(cfg, 'test_output_1d', 1, comm)
    call out%open(cfg, comm)
    call make_points(ps, 1, comm, frame=0)
    call empty%init('fluid', 1, .false.)
    call out%begin_frame(0_i8, 0.0_wp)
    call out%write_set(ps, cfg)
    call out%write_set(empty, cfg)
    call out%end_frame()
    call make_points(ps, 1, comm, frame=1)
    call out%begin_frame(frame_step(1), frame_time(1))
    call out%write_set(ps, cfg)
    call out%close()
    if (rank == 0) then
      call verify_file(output_h5_path(cfg), 1, 2, 0, .false.)
      call h5fopen_f(output_h5_path(cfg), H5F_ACC_RDONLY_F, fid, err)
      call ok(err, 'h5fopen_f')
      dims = read_dims(fid, 'frames/000000/fluid/x')
      call check(size(dims) == 2, 'empty fluid/x is 2D')
      if (size(dims) == 2) call check(all(dims == [1_hsize_t, 0_hsize_t]), &
                                      'empty fluid/x dims (1, 0)')
      dims = read_dims(fid, 'frames/000000/fluid/id')
      call check(all(dims == [0_hsize_t]), 'empty fluid/id has no entries')
      call h5fclose_f(fid, err)
      call ok(err, 'h5fclose_f')
    end if
    call check_xmf_exists(output_xmf_path(cfg))
    call MPI_Barrier(comm)
  end subroutine test_1d_with_empty_set

  !> Three frames of two sets, the fluid set missing from the middle one: the sidecar lists
  !> every frame once with its time and, in each, the sets that have points there (ParaView
  !> reads these files with each of its XDMF readers, ctest output_paraview_reads_np2).
  subroutine test_two_sets_three_frames(comm, ndim)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: ndim
    type(config_t) :: cfg
    type(output_t) :: out
    type(particle_set_t) :: solid, fluid
    character(len=:), allocatable :: xmf
    character(len=1) :: dstr
    integer :: frame
    write (dstr, '(i1)') ndim
    call begin_test('two_sets_three_frames_'//dstr//'d')
    call make_config(cfg, 'test_output_frames_'//dstr//'d', ndim, comm)
    call out%open(cfg, comm)
    call out%add_diag(diag_record(1))
    do frame = 0, 2
      call make_points(solid, ndim, comm, frame=frame, two_phase=.true.)
      call make_points(fluid, ndim, comm, frame=frame, name='fluid', two_phase=.true.)
      call out%begin_frame(frame_step(frame), frame_time(frame))
      call out%write_set(solid, cfg)
      if (frame /= 1) call out%write_set(fluid, cfg)
      call out%end_frame()
    end do
    call out%close()
    if (rank == 0) then
      xmf = read_text(output_xmf_path(cfg))
      call check(count_of(xmf, '<Time ') == 3, 'sidecar lists three times')
      call check(count_of(xmf, '<Grid Name="solid" GridType="Collection"') == 3 .and. &
                 count_of(xmf, '<Grid Name="fluid" GridType="Collection"') == 2, &
                 'sidecar lists the solid in three frames, the fluid in two')
      call check(index(xmf, '/frames/000001/fluid/') == 0, 'no fluid listed in frame 1')
      call check(count_of(xmf, 'AttributeType="Matrix"') == 3, &
                 'the stress of every solid grid as one Matrix attribute')
    end if
    call check_xmf_exists(output_xmf_path(cfg))
    call MPI_Barrier(comm)
  end subroutine test_two_sets_three_frames

  !> A two-phase frame: a solid set with porosity and a fluid set with porosity and pore
  !> pressure. The values arrive (matched by id), each set holds exactly the optional
  !> datasets it has, and the sidecar lists them as attributes of their set.
  subroutine test_two_phase_sets(comm)
    type(MPI_Comm), intent(in) :: comm
    type(config_t) :: cfg
    type(output_t) :: out
    type(particle_set_t) :: solid, fluid
    integer(hid_t) :: fid
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: por(:), pp(:)
    integer(hsize_t), allocatable :: dims(:)
    character(len=:), allocatable :: xmf
    integer :: err, n, r, j
    logical :: exists, values_ok
    character(len=*), parameter :: g = 'frames/000000/'
    call begin_test('two_phase_sets')
    call make_config(cfg, 'test_output_2p', 2, comm)
    call out%open(cfg, comm)
    call out%add_diag(diag_record(1))
    call make_points(solid, 2, comm, frame=0, two_phase=.true.)
    call make_points(fluid, 2, comm, frame=0, name='fluid', two_phase=.true.)
    call out%begin_frame(0_i8, 0.0_wp)
    call out%write_set(solid, cfg)
    call out%write_set(fluid, cfg)
    call out%end_frame()
    call out%close()
    if (rank == 0) then
      call verify_file(output_h5_path(cfg), 2, 1, 1, .false.)
      n = sum([(npoints_of(r, nranks), r=0, nranks - 1)])
      call h5fopen_f(output_h5_path(cfg), H5F_ACC_RDONLY_F, fid, err)
      call ok(err, 'h5fopen_f')
      call verify_frame(fid, g//'fluid', 2, 0, with_stress=.false.)
      dims = read_dims(fid, g//'fluid/pore_pressure')
      call check(all(dims == [int(n, hsize_t)]), 'fluid/pore_pressure holds one value per point')
      dims = read_dims(fid, g//'fluid/porosity')
      call check(all(dims == [int(n, hsize_t)]), 'fluid/porosity holds one value per point')
      ids = read_i8(fid, g//'fluid/id', n)
      por = read_real(fid, g//'fluid/porosity', n)
      pp = read_real(fid, g//'fluid/pore_pressure', n)
      values_ok = .true.
      do j = 1, n
        values_ok = values_ok .and. por(j) == porosity_of(ids(j)) .and. &
                    pp(j) == pressure_of(ids(j))
      end do
      call check(values_ok, 'fluid porosity and pore pressure match by id')
      ids = read_i8(fid, g//'solid/id', n)
      por = read_real(fid, g//'solid/porosity', n)
      call check(all([(por(j) == porosity_of(ids(j)), j=1, n)]), &
                 'solid porosity matches by id')
      call h5lexists_f(fid, g//'solid/pore_pressure', exists, err)
      call ok(err, 'h5lexists_f')
      call check(.not. exists, 'no pore_pressure in a set without pressure')
      call h5fclose_f(fid, err)
      call ok(err, 'h5fclose_f')
      xmf = read_text(output_xmf_path(cfg))
      call check(index(xmf, 'Name="pore_pressure"') > 0 .and. &
                 index(xmf, '/fluid/pore_pressure<') > 0, 'sidecar lists fluid pore_pressure')
      call check(index(xmf, '/fluid/porosity<') > 0 .and. index(xmf, '/solid/porosity<') > 0, &
                 'sidecar lists porosity of both sets')
      call check(index(xmf, '/solid/pore_pressure') == 0, 'no pore_pressure listed for solid')
      call check(index(xmf, '/fluid/stress') == 0 .and. index(xmf, '/solid/stress<') > 0, &
                 'stress listed for the solid only')
    end if
    call check_xmf_exists(output_xmf_path(cfg))
    call MPI_Barrier(comm)
  end subroutine test_two_phase_sets

  !> &output solid_fields = 'stress' and compression = 0: id, x, v, mass, volume and stress
  !> are written, displacement and material are not, and the sidecar lists what is there.
  subroutine test_chosen_fields_uncompressed(comm)
    type(MPI_Comm), intent(in) :: comm
    type(config_t) :: cfg
    type(output_t) :: out
    type(particle_set_t) :: solid
    integer(hid_t) :: fid
    character(len=:), allocatable :: xmf
    character(len=13) :: names(7)
    logical :: there(7)
    integer :: err, k
    character(len=*), parameter :: g = 'frames/000000/solid/'
    call begin_test('chosen_fields_uncompressed')
    call make_config(cfg, 'test_output_fields', 2, comm)
    cfg%solid_fields = 'stress'
    cfg%compression = 0
    call out%open(cfg, comm)
    call make_points(solid, 2, comm, frame=0)
    call out%begin_frame(0_i8, 0.0_wp)
    call out%write_set(solid, cfg)
    call out%end_frame()
    call out%close()
    if (rank == 0) then
      names = [character(len=13) :: 'id', 'x', 'v', 'mass', 'volume', 'stress', 'displacement']
      call h5fopen_f(output_h5_path(cfg), H5F_ACC_RDONLY_F, fid, err)
      call ok(err, 'h5fopen_f')
      do k = 1, 7
        call h5lexists_f(fid, g//trim(names(k)), there(k), err)
      end do
      call check(all(there(1:6)), 'id, x, v, mass, volume and the chosen stress are written')
      call check(.not. there(7), 'displacement is not written')
      call h5lexists_f(fid, g//'material', there(7), err)
      call check(.not. there(7), 'material is not written')
      call h5fclose_f(fid, err)
      xmf = read_text(output_xmf_path(cfg))
      call check(index(xmf, 'Name="stress"') > 0 .and. index(xmf, 'displacement') == 0 .and. &
                 index(xmf, 'material') == 0, 'sidecar lists the written datasets only')
    end if
    call MPI_Barrier(comm)
  end subroutine test_chosen_fields_uncompressed

  !> solid_fields = 'all rank': each point's rank dataset holds the rank that wrote it (the
  !> ids of the scene say which: id_of), and the sidecar lists it; 'all' alone does not
  !> write it (it differs between rank counts).
  subroutine test_rank_field_where_named(comm)
    type(MPI_Comm), intent(in) :: comm
    type(config_t) :: cfg, cfg_all
    type(output_t) :: out
    type(particle_set_t) :: solid
    integer(hid_t) :: fid
    integer(i8), allocatable :: ids(:)
    integer(i4), allocatable :: owner(:)
    logical :: there
    integer :: err, n, r
    character(len=*), parameter :: g = 'frames/000000/solid/'
    call begin_test('rank_field_where_named')
    call make_config(cfg, 'test_output_rank', 2, comm)
    cfg%solid_fields = 'all rank'
    call out%open(cfg, comm)
    call make_points(solid, 2, comm, frame=0)
    call out%begin_frame(0_i8, 0.0_wp)
    call out%write_set(solid, cfg)
    call out%end_frame()
    call out%close()
    if (rank == 0) then
      n = sum([(npoints_of(r, nranks), r=0, nranks - 1)])
      call h5fopen_f(output_h5_path(cfg), H5F_ACC_RDONLY_F, fid, err)
      call ok(err, 'h5fopen_f')
      ids = read_i8(fid, g//'id', n)
      owner = read_i4(fid, g//'rank', n)
      call h5fclose_f(fid, err)
      call check(all(int(owner, i8) == ids/1000_i8 - 1_i8), 'each point''s rank is the rank that wrote it')
      call check_equal_int(int(count(owner == nranks - 1)), npoints_of(nranks - 1, nranks), &
                           'the last rank''s points')
      call check(index(read_text(output_xmf_path(cfg)), 'Name="rank"') > 0, 'sidecar lists rank')
      ! (the file of 'all': test_two_frames_2d)
      call make_config(cfg_all, 'test_output', 2, comm)
      call h5fopen_f(output_h5_path(cfg_all), H5F_ACC_RDONLY_F, fid, err)
      call ok(err, 'h5fopen_f')
      call h5lexists_f(fid, g//'rank', there, err)
      call h5fclose_f(fid, err)
      call check(.not. there, '''all'' does not write rank')
    end if
    call MPI_Barrier(comm)
  end subroutine test_rank_field_where_named

  ! ------------------------------------------------------------------ scene

  !> A config with two materials (user ids 7 and 12) writing to out/<name>_np<nranks>.
  subroutine make_config(cfg, name, ndim, comm)
    type(config_t), intent(out) :: cfg
    character(len=*), intent(in) :: name
    integer, intent(in) :: ndim
    type(MPI_Comm), intent(in) :: comm
    integer :: np
    call MPI_Comm_size(comm, np)
    cfg%name = name
    cfg%ndim = ndim
    write (cfg%output_dir, '(a,i0)') 'out/test_output_np', np
    allocate (cfg%materials(2))
    cfg%materials(1)%id = 7
    cfg%materials(2)%id = 12
    cfg%input_text = input_text
  end subroutine make_config

  !> Points held by a rank: 3 + 2*rank, none on rank 2 when there are 4 ranks.
  pure integer function npoints_of(r, np)
    integer, intent(in) :: r, np
    npoints_of = 3 + 2*r
    if (np == 4 .and. r == 2) npoints_of = 0
  end function npoints_of

  !> Global id of the k-th point of rank r (unique, not contiguous).
  pure integer(i8) function id_of(r, k)
    integer, intent(in) :: r, k
    id_of = 1000_i8*(r + 1) + 7_i8*k
  end function id_of

  !> Position of a point in a frame: a function of its id, so any rank can check it.
  pure function x_of(id, ndim, frame) result(x)
    integer(i8), intent(in) :: id
    integer, intent(in) :: ndim, frame
    real(wp) :: x(ndim)
    integer :: d
    do d = 1, ndim
      x(d) = 0.001_wp*real(id, wp)*d + 0.1_wp*frame*d
    end do
  end function x_of

  !> Stress of a point (Voigt xx yy zz yz xz xy), distinct per component and id.
  pure function stress_of(id, frame) result(s)
    integer(i8), intent(in) :: id
    integer, intent(in) :: frame
    real(wp) :: s(6)
    integer :: c
    do c = 1, 6
      s(c) = 10.0_wp*real(id, wp) + real(c, wp) - 100.0_wp*frame
    end do
  end function stress_of

  pure real(wp) function mass_of(id)
    integer(i8), intent(in) :: id
    mass_of = 1.0_wp + 0.01_wp*real(id, wp)
  end function mass_of

  !> Porosity and pore pressure (Pa) of a point of a two-phase set.
  pure real(wp) function porosity_of(id)
    integer(i8), intent(in) :: id
    porosity_of = 0.2_wp + 1.0e-4_wp*real(id, wp)
  end function porosity_of

  pure real(wp) function pressure_of(id)
    integer(i8), intent(in) :: id
    pressure_of = 1.0e3_wp*real(id, wp) - 5.0e5_wp
  end function pressure_of

  pure integer function mat_of(id)
    integer(i8), intent(in) :: id
    mat_of = 1 + int(mod(id, 2_i8))
  end function mat_of

  !> This rank's points for a frame; odd frames hold them in reverse order. The set is
  !> called solid unless name is given; two_phase adds porosity, and pore pressure to a
  !> set called fluid.
  subroutine make_points(ps, ndim, comm, frame, name, two_phase)
    type(particle_set_t), intent(inout) :: ps
    integer, intent(in) :: ndim, frame
    type(MPI_Comm), intent(in) :: comm
    character(len=*), intent(in), optional :: name
    logical, intent(in), optional :: two_phase
    character(len=16) :: set_name
    logical :: porous
    integer :: r, np, k, kk, n
    integer(i8) :: id
    real(wp) :: v(ndim)
    call MPI_Comm_rank(comm, r)
    call MPI_Comm_size(comm, np)
    n = npoints_of(r, np)
    set_name = 'solid'
    if (present(name)) set_name = name
    porous = .false.
    if (present(two_phase)) porous = two_phase
    call ps%init(set_name, ndim, .false., max(n, 1), has_porosity=porous, &
                 has_pressure=porous .and. set_name == 'fluid')
    do kk = 1, n
      k = merge(n + 1 - kk, kk, mod(frame, 2) == 1)
      id = id_of(r, k)
      v = -real(id, wp)
      call ps%append(id, mat_of(id), x_of(id, ndim, 0), v, mass_of(id), 0.5_wp*mass_of(id), &
                     stress_of(id, frame), porosity=porosity_of(id), pressure=pressure_of(id))
      ps%x(:, ps%n) = x_of(id, ndim, frame)
    end do
  end subroutine make_points

  pure integer(i8) function frame_step(frame)
    integer, intent(in) :: frame
    frame_step = 10_i8*frame
  end function frame_step

  pure real(wp) function frame_time(frame)
    integer, intent(in) :: frame
    frame_time = 0.25_wp*frame
  end function frame_time

  !> Diagnostics record j: step 5j, npoints 100 + j, entry k = j + k/100.
  pure function diag_record(j) result(rec)
    integer, intent(in) :: j
    type(diag_record_t) :: rec
    integer :: k
    rec%step = 5_i8*j
    rec%npoints = 100_i8 + j
    do k = 1, ndiag_real
      rec%values(k) = real(j, wp) + 0.01_wp*k
    end do
  end function diag_record

  ! ------------------------------------------------------------------ reading back

  !> Read a file serially and check it against the scene: root attributes, /input, every
  !> frame (ids once each, x, v, displacement, stress, mass, volume, material) and ndiag
  !> diagnostics records.
  subroutine verify_file(path, ndim, nframes, ndiag, with_verification)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ndim, nframes, ndiag
    logical, intent(in) :: with_verification
    integer(hid_t) :: fid
    integer :: err, f, j, k
    character(len=64) :: g
    integer(hsize_t), allocatable :: dims(:)
    integer(i8), allocatable :: ibuf(:)
    real(wp), allocatable :: rbuf(:)
    logical :: exists
    call h5open_f(err)
    call ok(err, 'h5open_f')
    call h5fopen_f(path, H5F_ACC_RDONLY_F, fid, err)
    call ok(err, 'h5fopen_f('//path//')')
    call check(read_attr_string(fid, '.', 'dpmpm_version') == dpmpm_version, 'dpmpm_version')
    call check(len(read_attr_string(fid, '.', 'git_commit')) > 0, 'git_commit not empty')
    call check_equal_int(int(read_attr_i8(fid, '.', 'nranks')), nranks, 'nranks attribute')
    call check_equal_int(int(read_attr_i8(fid, '.', 'ndim')), ndim, 'ndim attribute')
    call check(read_string_dataset(fid, 'input') == input_text, '/input holds the input text')
    do f = 0, nframes - 1
      write (g, '(a,i6.6)') 'frames/', f
      call check(read_attr_i8(fid, trim(g), 'step') == frame_step(f), trim(g)//' step')
      call check_close(read_attr_real(fid, trim(g), 'time'), frame_time(f), 0.0_wp, 0.0_wp, &
                       trim(g)//' time')
      call verify_frame(fid, trim(g)//'/solid', ndim, f)
    end do
    write (g, '(a,i6.6)') 'frames/', nframes
    call h5lexists_f(fid, trim(g), exists, err)
    call ok(err, 'h5lexists_f')
    call check(.not. exists, 'no frame beyond the last one written')
    dims = read_dims(fid, 'diagnostics/step')
    call check(all(dims == [int(ndiag, hsize_t)]), 'number of diagnostics records')
    if (ndiag > 0) then
      ibuf = read_i8(fid, 'diagnostics/step', ndiag)
      call check(all(ibuf == [(5_i8*j, j=1, ndiag)]), 'diagnostics step values')
      ibuf = read_i8(fid, 'diagnostics/npoints', ndiag)
      call check(all(ibuf == [(100_i8 + j, j=1, ndiag)]), 'diagnostics npoints values')
      do k = 1, ndiag_real
        rbuf = read_real(fid, 'diagnostics/'//trim(diag_real_names(k)), ndiag)
        do j = 1, ndiag
          call check_close(rbuf(j), real(j, wp) + 0.01_wp*k, 0.0_wp, 1.0e-15_wp, &
                           'diagnostics '//trim(diag_real_names(k)))
        end do
      end do
    end if
    if (with_verification) then
      rbuf = read_real(fid, 'verification/l2_error', 3)
      call check(all(rbuf == [1.0_wp, 0.5_wp, 0.25_wp]), '/verification/l2_error values')
      call check_close(read_attr_real(fid, 'verification', 'max_error'), 0.125_wp, 0.0_wp, &
                       0.0_wp, '/verification max_error attribute')
    end if
    call h5fclose_f(fid, err)
    call ok(err, 'h5fclose_f')
  end subroutine verify_file

  !> Check one written set against what the ranks wrote, matching points by id. A set
  !> written without stress (a fluid set) is checked for its absence instead.
  subroutine verify_frame(fid, g, ndim, frame, with_stress)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: g
    integer, intent(in) :: ndim, frame
    logical, intent(in), optional :: with_stress
    logical :: stress_there, want_stress
    integer :: n, r, k, j, np, err
    integer(i8), allocatable :: ids(:), expected(:)
    integer(i4), allocatable :: mat(:)
    real(wp), allocatable :: x(:, :), v(:, :), u(:, :), s(:, :), mass(:), vol(:)
    integer(hsize_t), allocatable :: dims(:)
    logical :: values_ok
    np = nranks
    n = sum([(npoints_of(r, np), r=0, np - 1)])
    allocate (expected(0))
    do r = 0, np - 1
      expected = [expected, [(id_of(r, k), k=1, npoints_of(r, np))]]
    end do
    dims = read_dims(fid, g//'/id')
    call check(all(dims == [int(n, hsize_t)]), g//'/id holds the global number of points')
    dims = read_dims(fid, g//'/x')
    call check(size(dims) == 2, g//'/x is 2D')
    if (size(dims) == 2) call check(all(dims == [int(ndim, hsize_t), int(n, hsize_t)]), &
                                    g//'/x has Fortran dims (ndim, n)')
    want_stress = .true.
    if (present(with_stress)) want_stress = with_stress
    call h5lexists_f(fid, g//'/stress', stress_there, err)
    call check(stress_there .eqv. want_stress, g//'/stress written only where wanted')
    if (want_stress) then
      dims = read_dims(fid, g//'/stress')
      call check(all(dims == [6_hsize_t, int(n, hsize_t)]), g//'/stress has Fortran dims (6, n)')
    end if
    ids = read_i8(fid, g//'/id', n)
    do k = 1, n
      call check_equal_int(count(ids == expected(k)), 1, g//' id appears once')
    end do
    x = reshape(read_real(fid, g//'/x', ndim*n), [ndim, n])
    v = reshape(read_real(fid, g//'/v', ndim*n), [ndim, n])
    u = reshape(read_real(fid, g//'/displacement', ndim*n), [ndim, n])
    allocate (s(6, n))
    s = 0.0_wp
    if (want_stress) s = reshape(read_real(fid, g//'/stress', 6*n), [6, n])
    mass = read_real(fid, g//'/mass', n)
    vol = read_real(fid, g//'/volume', n)
    mat = read_i4(fid, g//'/material', n)
    values_ok = .true.
    do j = 1, n
      values_ok = values_ok .and. all(x(:, j) == x_of(ids(j), ndim, frame))
      values_ok = values_ok .and. all(v(:, j) == -real(ids(j), wp))
      values_ok = values_ok .and. all(abs(u(:, j) - (x_of(ids(j), ndim, frame) - &
                                                      x_of(ids(j), ndim, 0))) <= 1.0e-14_wp)
      if (want_stress) values_ok = values_ok .and. all(s(:, j) == stress_of(ids(j), frame))
      values_ok = values_ok .and. mass(j) == mass_of(ids(j))
      values_ok = values_ok .and. vol(j) == 0.5_wp*mass_of(ids(j))
      values_ok = values_ok .and. mat(j) == merge(7, 12, mat_of(ids(j)) == 1)
    end do
    call check(values_ok, g//': x, v, displacement, stress, mass, volume, material match by id')
  end subroutine verify_frame

  !> How many times pattern occurs in text.
  pure integer function count_of(text, pattern)
    character(len=*), intent(in) :: text, pattern
    integer :: at, k
    count_of = 0
    at = 1
    do
      k = index(text(at:), pattern)
      if (k == 0) exit
      count_of = count_of + 1
      at = at + k + len(pattern) - 1
    end do
  end function count_of

  !> The .xmf sidecar exists (its XML is parsed by scripts/check_output.py).
  subroutine check_xmf_exists(path)
    character(len=*), intent(in) :: path
    logical :: exists
    if (rank /= 0) return
    inquire (file=path, exist=exists)
    call check(exists, 'XDMF sidecar '//path//' written')
  end subroutine check_xmf_exists

  subroutine ok(err, what)
    integer, intent(in) :: err
    character(len=*), intent(in) :: what
    if (err < 0) call fatal(what//' failed', 'test_output')
  end subroutine ok

  !> The whole content of a text file.
  function read_text(path) result(text)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: text
    integer :: u, n
    open (newunit=u, file=path, access='stream', form='unformatted', action='read')
    inquire (unit=u, size=n)
    allocate (character(len=n) :: text)
    read (u) text
    close (u)
  end function read_text

  function read_dims(fid, path) result(dims)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer(hsize_t), allocatable :: dims(:)
    integer(hsize_t), allocatable :: maxdims(:)
    integer(hid_t) :: dset, space
    integer :: err, rnk
    call h5dopen_f(fid, path, dset, err)
    call ok(err, 'h5dopen_f('//path//')')
    call h5dget_space_f(dset, space, err)
    call ok(err, 'h5dget_space_f')
    call h5sget_simple_extent_ndims_f(space, rnk, err)
    call ok(err, 'h5sget_simple_extent_ndims_f')
    allocate (dims(rnk), maxdims(rnk))
    call h5sget_simple_extent_dims_f(space, dims, maxdims, err)
    call ok(err, 'h5sget_simple_extent_dims_f')
    call h5sclose_f(space, err)
    call ok(err, 'h5sclose_f')
    call h5dclose_f(dset, err)
    call ok(err, 'h5dclose_f')
  end function read_dims

  function read_real(fid, path, n) result(buf)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer, intent(in) :: n
    real(wp), allocatable, target :: buf(:)
    allocate (buf(max(n, 1)))
    call read_into(fid, path, h5kind_to_type(wp, H5_REAL_KIND), c_loc(buf))
    buf = buf(1:n)
  end function read_real

  function read_i8(fid, path, n) result(buf)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer, intent(in) :: n
    integer(i8), allocatable, target :: buf(:)
    allocate (buf(max(n, 1)))
    call read_into(fid, path, h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(buf))
    buf = buf(1:n)
  end function read_i8

  function read_i4(fid, path, n) result(buf)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer, intent(in) :: n
    integer(i4), allocatable, target :: buf(:)
    allocate (buf(max(n, 1)))
    call read_into(fid, path, h5kind_to_type(i4, H5_INTEGER_KIND), c_loc(buf))
    buf = buf(1:n)
  end function read_i4

  !> The whole dataset path of fid, read as memory type mtype into the buffer at ptr
  !> (large enough for it: read_real, read_i8, read_i4).
  subroutine read_into(fid, path, mtype, ptr)
    integer(hid_t), intent(in) :: fid, mtype
    character(len=*), intent(in) :: path
    type(c_ptr), intent(in) :: ptr
    type(c_ptr) :: buf
    integer(hid_t) :: dset
    integer :: err
    buf = ptr
    call h5dopen_f(fid, path, dset, err)
    call ok(err, 'h5dopen_f('//path//')')
    call h5dread_f(dset, mtype, buf, err)
    call ok(err, 'h5dread_f('//path//')')
    call h5dclose_f(dset, err)
    call ok(err, 'h5dclose_f')
  end subroutine read_into

  !> A scalar fixed-length string dataset, trailing NULs removed.
  function read_string_dataset(fid, path) result(s)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: s
    character(kind=c_char, len=:), allocatable, target :: buf
    integer(hid_t) :: dset, t
    integer(size_t) :: sz
    integer :: err
    type(c_ptr) :: ptr
    call h5dopen_f(fid, path, dset, err)
    call ok(err, 'h5dopen_f('//path//')')
    call h5dget_type_f(dset, t, err)
    call ok(err, 'h5dget_type_f')
    call h5tget_size_f(t, sz, err)
    call ok(err, 'h5tget_size_f')
    allocate (character(kind=c_char, len=sz) :: buf)
    ptr = c_loc(buf)
    call h5dread_f(dset, t, ptr, err)
    call ok(err, 'h5dread_f('//path//')')
    call h5tclose_f(t, err)
    call ok(err, 'h5tclose_f')
    call h5dclose_f(dset, err)
    call ok(err, 'h5dclose_f')
    s = strip_nul(buf)
  end function read_string_dataset

  function read_attr_string(fid, obj, name) result(s)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: obj, name
    character(len=:), allocatable :: s
    character(kind=c_char, len=:), allocatable, target :: buf
    integer(hid_t) :: attr, t
    integer(size_t) :: sz
    integer :: err
    type(c_ptr) :: ptr
    call h5aopen_by_name_f(fid, obj, name, attr, err)
    call ok(err, 'h5aopen_by_name_f('//name//')')
    call h5aget_type_f(attr, t, err)
    call ok(err, 'h5aget_type_f')
    call h5tget_size_f(t, sz, err)
    call ok(err, 'h5tget_size_f')
    allocate (character(kind=c_char, len=sz) :: buf)
    ptr = c_loc(buf)
    call h5aread_f(attr, t, ptr, err)
    call ok(err, 'h5aread_f('//name//')')
    call h5tclose_f(t, err)
    call ok(err, 'h5tclose_f')
    call h5aclose_f(attr, err)
    call ok(err, 'h5aclose_f')
    s = strip_nul(buf)
  end function read_attr_string

  !> An integer attribute of any stored width, read as int64.
  integer(i8) function read_attr_i8(fid, obj, name) result(v)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: obj, name
    integer(i8), target :: buf
    integer(hid_t) :: attr
    integer :: err
    type(c_ptr) :: ptr
    call h5aopen_by_name_f(fid, obj, name, attr, err)
    call ok(err, 'h5aopen_by_name_f('//name//')')
    ptr = c_loc(buf)
    call h5aread_f(attr, h5kind_to_type(i8, H5_INTEGER_KIND), ptr, err)
    call ok(err, 'h5aread_f('//name//')')
    call h5aclose_f(attr, err)
    call ok(err, 'h5aclose_f')
    v = buf
  end function read_attr_i8

  real(wp) function read_attr_real(fid, obj, name) result(v)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: obj, name
    real(wp), target :: buf
    integer(hid_t) :: attr
    integer :: err
    type(c_ptr) :: ptr
    call h5aopen_by_name_f(fid, obj, name, attr, err)
    call ok(err, 'h5aopen_by_name_f('//name//')')
    ptr = c_loc(buf)
    call h5aread_f(attr, h5kind_to_type(wp, H5_REAL_KIND), ptr, err)
    call ok(err, 'h5aread_f('//name//')')
    call h5aclose_f(attr, err)
    call ok(err, 'h5aclose_f')
    v = buf
  end function read_attr_real

  pure function strip_nul(buf) result(s)
    character(len=*), intent(in) :: buf
    character(len=:), allocatable :: s
    integer :: k
    k = index(buf, c_null_char)
    if (k == 0) then
      s = buf
    else
      s = buf(1:k - 1)
    end if
  end function strip_nul

end program test_output
