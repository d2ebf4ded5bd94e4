!> Input tests: a valid namelist file gives the expected resolved parameters on every rank,
!> optional groups give the config_t defaults, and the output of print_config reads back to
!> the same parameters; a two-phase scene resolves its phases, pore fluid, drag options and
!> fluid face conditions. Every rank parses the text that rank 0 read and broadcast, and so
!> holds the same configuration; a text parses without a file; a refused input returns its
!> status on every rank instead of stopping.
program test_input
  use, intrinsic :: iso_fortran_env, only: output_unit
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Comm_size, MPI_Barrier, MPI_Bcast, MPI_INTEGER, &
                     MPI_CHARACTER, MPI_DOUBLE_PRECISION
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, bc_free, bc_fixed, bc_roller, face_index, fbc_default, &
                          fbc_drained, fbc_impermeable
  use dpmpm_input, only: read_input, print_config, input_ok, input_refused
  use dpmpm_input_read, only: parse_input
  use dpmpm_input_problems, only: input_problems_t
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer :: rank, nranks
  character(len=16) :: tag

  call start_tests(rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  ! Rank counts run side by side under ctest -j: one set of files per rank count.
  write (tag, '(a,i0)') 'np', nranks
  call test_valid_file_gives_values_on_every_rank()
  call test_optional_groups_give_defaults()
  call test_print_config_reads_back()
  call test_two_phase_scene()
  call test_porosity_gradient_where_porosity_varies()
  call test_geostatic_level_ground()
  call test_every_rank_parses_the_same_config()
  call test_text_parses_without_a_file()
  call test_refused_input_returns_status()
  call end_tests()

contains

  !> Rank 0 writes lines to file; every rank waits until it is there.
  subroutine write_file(file, lines)
    character(len=*), intent(in) :: file
    character(len=*), intent(in) :: lines(:)
    integer :: u, k
    if (rank == 0) then
      open (newunit=u, file=file, status='replace', action='write')
      do k = 1, size(lines)
        write (u, '(a)') trim(lines(k))
      end do
      close (u)
    end if
    call MPI_Barrier(MPI_COMM_WORLD)
  end subroutine write_file

  !> A scene with every group; the rank count is left to MPI so it works on 1, 2 and 4 ranks.
  subroutine write_full_scene(file)
    character(len=*), intent(in) :: file
    call write_file(file, [character(len=100) :: &
      '! a bar and a wedge', &
      '&run name = ''bar'', t_end = 0.5, dt = 1.0e-5, cfl = 0.4, max_steps = 5000000000,', &
      '     scheme = ''usl'', flip = 0.95, gravity = 0.0, -9.81, progress_seconds = 2.5 /', &
      '&grid ndim = 2, ncells = 40, 8, origin = -1.0, 0.0, length = 2.0, 0.4 /', &
      '&shape kernel = ''quadratic'' /', &
      '&material id = 3, density = 7850.0, youngs_modulus = 2.1e11, poisson_ratio = 0.0 /', &
      '&material id = 5, model = ''neo_hookean'' /', &
      '&region lo = -1.0, 0.0, hi = 0.0, 0.2, material = 3, velocity = 0.1, 0.0 /', &
      '&region shape = ''polygon'', npoly = 3, poly_x = 0.1, 0.9, 0.1,', &
      '  poly_y = 0.0, 0.0, 0.4, material = 5, ppc = 3, placement = ''random'', seed = 7,', &
      '  stress = -1.0e3, -2.0e3, 0.0, 5.0 /', &
      '  &BOUNDARY face = ''x-'', condition = ''fixed'' / ! upper case works too', &
      '&boundary face = ''y-'', condition = ''roller'' /', &
      '&load face = ''x+'', traction = 1.0e5, 0.0, ramp_time = 1.0e-3 /', &
      '&load face = ''y+'', traction = 0.0, -2.0e4 /', &
      '&output dir = ''results/bar'', frame_interval = 0.01, diag_every = 50 /', &
      '&benchmark name = ''axial_bar'', amplitude = 0.1 /'])
  end subroutine write_full_scene

  !> Every value of the full scene as read on this rank.
  subroutine check_full_scene(cfg)
    type(config_t), intent(in) :: cfg
    call check(cfg%name == 'bar', 'run name')
    call check_close(cfg%t_end, 0.5_wp, 0.0_wp, 0.0_wp, 't_end')
    call check_close(cfg%dt, 1.0e-5_wp, 0.0_wp, 0.0_wp, 'dt')
    call check_close(cfg%cfl, 0.4_wp, 0.0_wp, 0.0_wp, 'cfl')
    call check(cfg%max_steps == 5000000000_i8, 'max_steps beyond 32 bits')
    call check(cfg%scheme == 'usl', 'scheme')
    call check_close(cfg%flip, 0.95_wp, 0.0_wp, 0.0_wp, 'flip')
    call check(all(cfg%gravity == [0.0_wp, -9.81_wp, 0.0_wp]), 'gravity')
    call check_close(cfg%progress_seconds, 2.5_wp, 0.0_wp, 0.0_wp, 'progress_seconds')
    call check_equal_int(cfg%ndim, 2, 'ndim')
    call check(all(cfg%ncells == [40, 8, 1]), 'ncells (third keeps its default)')
    call check(all(cfg%origin == [-1.0_wp, 0.0_wp, 0.0_wp]), 'origin')
    call check(all(cfg%length == [2.0_wp, 0.4_wp, 1.0_wp]), 'length')
    call check(all(cfg%dims == 0), 'dims')
    call check(cfg%kernel == 'quadratic', 'kernel')
    call check_equal_int(size(cfg%materials), 2, 'number of materials')
    if (size(cfg%materials) == 2) then
      call check_equal_int(cfg%materials(1)%id, 3, 'material 1 id')
      call check(cfg%materials(1)%model == 'linear_elastic', 'material 1 default model')
      call check_close(cfg%materials(1)%density, 7850.0_wp, 0.0_wp, 0.0_wp, 'density')
      call check_close(cfg%materials(1)%youngs_modulus, 2.1e11_wp, 0.0_wp, 0.0_wp, 'modulus')
      call check_close(cfg%materials(1)%poisson_ratio, 0.0_wp, 0.0_wp, 0.0_wp, 'poisson')
      call check_equal_int(cfg%materials(2)%id, 5, 'material 2 id')
      call check(cfg%materials(2)%model == 'neo_hookean', 'material 2 model')
      call check_close(cfg%materials(2)%density, 1000.0_wp, 0.0_wp, 0.0_wp, &
                       'material 2 default density (not carried over from material 1)')
      call check_close(cfg%materials(2)%poisson_ratio, 0.3_wp, 0.0_wp, 0.0_wp, &
                       'material 2 default poisson ratio')
    end if
    call check_equal_int(size(cfg%regions), 2, 'number of regions')
    if (size(cfg%regions) == 2) then
      call check(cfg%regions(1)%shape == 'box', 'region 1 default shape')
      call check(all(cfg%regions(1)%lo(1:2) == [-1.0_wp, 0.0_wp]), 'region 1 lo')
      call check(all(cfg%regions(1)%hi(1:2) == [0.0_wp, 0.2_wp]), 'region 1 hi')
      call check_equal_int(cfg%regions(1)%material, 3, 'region 1 material')
      call check(all(cfg%regions(1)%velocity == [0.1_wp, 0.0_wp, 0.0_wp]), 'region 1 velocity')
      call check_equal_int(cfg%regions(1)%ppc, 2, 'region 1 default ppc')
      call check(cfg%regions(1)%placement == 'regular', 'region 1 default placement')
      call check(cfg%regions(2)%shape == 'polygon', 'region 2 shape')
      call check_equal_int(cfg%regions(2)%npoly, 3, 'region 2 npoly')
      call check(all(cfg%regions(2)%poly(1, 1:3) == [0.1_wp, 0.9_wp, 0.1_wp]), 'poly_x')
      call check(all(cfg%regions(2)%poly(2, 1:3) == [0.0_wp, 0.0_wp, 0.4_wp]), 'poly_y')
      call check_equal_int(cfg%regions(2)%material, 5, 'region 2 material')
      call check_equal_int(cfg%regions(2)%ppc, 3, 'region 2 ppc')
      call check(cfg%regions(2)%placement == 'random', 'region 2 placement')
      call check_equal_int(cfg%regions(2)%seed, 7, 'region 2 seed')
      call check(cfg%regions(2)%phase == 'solid', 'region 2 default phase')
      call check(all(cfg%regions(2)%stress == [-1.0e3_wp, -2.0e3_wp, 0.0_wp, 5.0_wp, 0.0_wp, &
                                               0.0_wp]), 'region 2 stress')
      call check(all(cfg%regions(2)%velocity == 0.0_wp), 'region 2 default velocity')
    end if
    call check(all(cfg%bc == [bc_fixed, bc_free, bc_roller, bc_free, bc_free, bc_free]), &
               'boundary conditions per face')
    call check_equal_int(size(cfg%loads), 2, 'number of loads')
    if (size(cfg%loads) == 2) then
      call check_equal_int(cfg%loads(1)%face, face_index('x+'), 'load 1 face')
      call check(all(cfg%loads(1)%traction == [1.0e5_wp, 0.0_wp, 0.0_wp]), 'load 1 traction')
      call check_close(cfg%loads(1)%ramp_time, 1.0e-3_wp, 0.0_wp, 0.0_wp, 'load 1 ramp')
      call check_equal_int(cfg%loads(2)%face, face_index('y+'), 'load 2 face')
      call check(all(cfg%loads(2)%traction == [0.0_wp, -2.0e4_wp, 0.0_wp]), 'load 2 traction')
      call check_close(cfg%loads(2)%ramp_time, 0.0_wp, 0.0_wp, 0.0_wp, 'load 2 default ramp')
    end if
    call check(cfg%output_dir == 'results/bar', 'output dir')
    call check_close(cfg%frame_interval, 0.01_wp, 0.0_wp, 0.0_wp, 'frame_interval')
    call check_equal_int(cfg%diag_every, 50, 'diag_every')
    call check(cfg%benchmark == 'axial_bar', 'benchmark')
    call check_close(cfg%amplitude, 0.1_wp, 0.0_wp, 0.0_wp, 'amplitude')
  end subroutine check_full_scene

  subroutine test_valid_file_gives_values_on_every_rank()
    type(config_t) :: cfg
    integer :: st
    character(len=:), allocatable :: file
    integer :: u, n
    character(len=:), allocatable :: text
    call begin_test('valid_file_gives_values_on_every_rank')
    file = 'test_input_'//trim(tag)//'_full.nml'
    call write_full_scene(file)
    call read_input(file, MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, 0, 'read_input status')
    call check_full_scene(cfg)
    call check(cfg%input_file == file, 'input_file')
    ! The whole file text, as on disk, is on every rank.
    open (newunit=u, file=file, access='stream', form='unformatted', action='read')
    inquire (unit=u, size=n)
    allocate (character(len=n) :: text)
    read (u) text
    close (u)
    call check(allocated(cfg%input_text), 'input_text allocated')
    if (allocated(cfg%input_text)) call check(cfg%input_text == text .and. &
                                              len(cfg%input_text) == n, 'input_text')
  end subroutine test_valid_file_gives_values_on_every_rank

  subroutine test_optional_groups_give_defaults()
    type(config_t) :: cfg, def
    integer :: st
    character(len=:), allocatable :: file
    call begin_test('optional_groups_give_defaults')
    file = 'test_input_'//trim(tag)//'_minimal.nml'
    call write_file(file, [character(len=80) :: &
      '&grid ncells = 16, 16 /', &
      '&material /', &
      '&region lo = 0.25, 0.25, hi = 0.75, 0.75 /'])
    call read_input(file, MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, 0, 'read_input status')
    call check(cfg%name == def%name, 'name')
    call check(cfg%t_end == def%t_end .and. cfg%dt == def%dt .and. cfg%cfl == def%cfl, &
               't_end, dt, cfl')
    call check(cfg%max_steps == def%max_steps, 'max_steps')
    call check(cfg%scheme == def%scheme .and. cfg%flip == def%flip, 'scheme, flip')
    call check(all(cfg%gravity == def%gravity), 'gravity')
    call check(cfg%progress_seconds == def%progress_seconds, 'progress_seconds')
    call check_equal_int(cfg%ndim, def%ndim, 'ndim')
    call check(all(cfg%origin == def%origin) .and. all(cfg%length == def%length), 'grid box')
    call check(all(cfg%dims == def%dims), 'dims')
    call check(cfg%kernel == def%kernel, 'kernel')
    call check_equal_int(size(cfg%materials), 1, 'one material')
    call check_equal_int(cfg%materials(1)%id, 1, 'default material id')
    call check_equal_int(size(cfg%regions), 1, 'one region')
    call check_equal_int(cfg%regions(1)%material, 1, 'default region material')
    call check_equal_int(size(cfg%loads), 0, 'no loads')
    call check(all(cfg%bc == bc_free), 'all faces free')
    call check(cfg%output_dir == def%output_dir, 'output dir')
    call check(cfg%frame_interval == def%frame_interval, 'frame_interval')
    call check_equal_int(cfg%diag_every, def%diag_every, 'diag_every')
    call check(cfg%benchmark == def%benchmark .and. cfg%amplitude == def%amplitude, 'benchmark')
  end subroutine test_optional_groups_give_defaults

  subroutine test_print_config_reads_back()
    type(config_t) :: cfg, again
    integer :: st
    character(len=:), allocatable :: file, printed
    integer :: u
    call begin_test('print_config_reads_back')
    file = 'test_input_'//trim(tag)//'_full.nml'
    printed = 'test_input_'//trim(tag)//'_printed.nml'
    call write_full_scene(file)
    call read_input(file, MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, 0, 'read_input status')
    if (rank == 0) then
      open (newunit=u, file=printed, status='replace', action='write')
      call print_config(cfg, u)
      close (u)
      if (nranks == 1) call print_config(cfg, output_unit)
    end if
    call MPI_Barrier(MPI_COMM_WORLD)
    call read_input(printed, MPI_COMM_WORLD, again, st)
    call check_equal_int(st, 0, 'read_input status')
    call check_full_scene(again)
    call check(again%echo == cfg%echo, 'the printed parameters print the same again')
    call check(index(cfg%echo, '&material'//new_line('a')//'  id = ') > 0, 'one line per variable')
  end subroutine test_print_config_reads_back

  !> A saturated layer under free water: the phases, the pore fluid, the drag options and the
  !> fluid face conditions (given, and left to their default) as resolved on every rank, and
  !> again after print_config and reading back.
  subroutine test_two_phase_scene()
    type(config_t) :: cfg, again
    integer :: st
    character(len=:), allocatable :: file, printed
    integer :: u
    call begin_test('two_phase_scene')
    file = 'test_input_'//trim(tag)//'_two_phase.nml'
    printed = 'test_input_'//trim(tag)//'_two_phase_printed.nml'
    call write_file(file, [character(len=100) :: &
      '&run t_end = 0.1, drag = ''implicit'', drag_safety = 0.6, porosity_gradient = .true. /', &
      '&grid ndim = 2, ncells = 8, 16, length = 1.0, 2.0 /', &
      '&material id = 4, model = ''fluid'', density = 998.0, bulk_modulus = 2.0e9 /', &
      '&material id = 9, density = 2650.0, youngs_modulus = 1.0e7, poisson_ratio = 0.25,', &
      '          conductivity = 1.0e-3 /', &
      '&region lo = 0.0, 0.0, hi = 1.0, 1.0, phase = ''saturated'', material = 9,', &
      '        fluid_material = 4, porosity = 0.35, seed = 3, fluid_seed = 11 /', &
      '&region lo = 0.0, 1.0, hi = 1.0, 1.5, phase = ''fluid'', material = 4,', &
      '        placement = ''uniform'', ppc = 3 /', &
      '&boundary face = ''y-'', condition = ''fixed'' /', &
      '&boundary face = ''x-'', condition = ''roller'', fluid = ''drained'',', &
      '          pore_pressure = 2.5e3 /', &
      '&boundary face = ''x+'', condition = ''roller'', fluid = ''default'' /', &
      '&boundary face = ''y+'', fluid = ''impermeable'' /', &
      '&benchmark name = ''terzaghi'' /'])
    call read_input(file, MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, 0, 'read_input status')
    call check_two_phase(cfg)
    if (rank == 0) then
      open (newunit=u, file=printed, status='replace', action='write')
      call print_config(cfg, u)
      close (u)
    end if
    call MPI_Barrier(MPI_COMM_WORLD)
    call read_input(printed, MPI_COMM_WORLD, again, st)
    call check_equal_int(st, 0, 'read_input status')
    call check_two_phase(again)
  end subroutine test_two_phase_scene

  !> porosity_gradient left out where the porosity varies between the regions (free water
  !> over soil): refused; given as .false., it stays off; left out in one soil: off.
  subroutine test_porosity_gradient_where_porosity_varies()
    type(config_t) :: cfg
    integer :: st, k
    character(len=:), allocatable :: file
    character(len=100), parameter :: runs(3) = [character(len=100) :: '&run t_end = 0.1 /', &
                                                '&run porosity_gradient = .false. /', &
                                                '&run t_end = 0.1 /']
    logical, parameter :: expect(3) = [.false., .false., .false.]
    integer, parameter :: status(3) = [2, 0, 0]
    character(len=100), parameter :: water(3) = [character(len=100) :: &
                                    '&region lo = 0.0, 1.0, hi = 1.0, 1.5, phase = ''fluid'', material = 4 /', &
                                    '&region lo = 0.0, 1.0, hi = 1.0, 1.5, phase = ''fluid'', material = 4 /', '']
    call begin_test('porosity_gradient_where_porosity_varies')
    do k = 1, 3
      file = 'test_input_'//trim(tag)//'_pgrad.nml'
      call write_file(file, [character(len=100) :: runs(k), &
        '&grid ndim = 2, ncells = 8, 16, length = 1.0, 2.0 /', &
        '&material id = 4, model = ''fluid'', density = 998.0, bulk_modulus = 2.0e9 /', &
        '&material id = 9, density = 2650.0, youngs_modulus = 1.0e7, poisson_ratio = 0.25,', &
        '          conductivity = 1.0e-3 /', &
        '&region lo = 0.0, 0.0, hi = 1.0, 1.0, phase = ''saturated'', material = 9,', &
        '        fluid_material = 4, porosity = 0.35 /', &
        water(k)])
      call read_input(file, MPI_COMM_WORLD, cfg, st)
      call check_equal_int(st, status(k), 'read_input status of case '//char(48 + k))
      if (st /= 0) cycle
      call check(cfg%porosity_gradient .eqv. expect(k), 'porosity_gradient of case '//char(48 + k))
      call check(cfg%porosity_gradient_given .eqv. (k == 2), 'given in case '//char(48 + k))
    end do
  end subroutine test_porosity_gradient_where_porosity_varies

  !> geostatic = .true.: a saturated layer (n = 0.4, rho_s = 2650, rho_f = 1000, nu = 0.3)
  !> on 0 <= y <= 1.5 m under water up to y = 2 m, and dry sand (porosity 0.4) on top of a
  !> box from y = 1.5 to 1.75 m with an overburden of 1 kPa and K0 = 0.5, against the
  !> closed forms: sigma'_v = -(q + gamma (S - y)), sigma'_h = K0 sigma'_v, p = rho_f g (W - y).
  subroutine test_geostatic_level_ground()
    type(config_t) :: cfg
    integer :: st
    character(len=:), allocatable :: file
    real(wp) :: gs, gd
    call begin_test('geostatic_level_ground')
    file = 'test_input_'//trim(tag)//'_geostatic.nml'
    call write_file(file, [character(len=100) :: &
      '&run gravity = 0.0, -9.81, porosity_gradient = .true. /', &
      '&grid ndim = 2, ncells = 8, 16, length = 1.0, 2.0 /', &
      '&material id = 2, model = ''fluid'', density = 1000.0, bulk_modulus = 2.2e9 /', &
      '&material id = 1, density = 2650.0, youngs_modulus = 1.0e7, poisson_ratio = 0.3,', &
      '          conductivity = 1.0e-4 /', &
      '&region lo = 0.0, 0.0, hi = 1.0, 1.5, phase = ''saturated'', material = 1,', &
      '        fluid_material = 2, porosity = 0.4, geostatic = .true., water_level = 2.0 /', &
      '&region lo = 0.0, 1.5, hi = 1.0, 1.75, material = 1, porosity = 0.4,', &
      '        geostatic = .true., overburden = 1.0e3, k0 = 0.5 /'])
    call read_input(file, MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, 0, 'read_input status')
    if (st /= 0) return
    gs = 0.6_wp*1650.0_wp*9.81_wp
    gd = 0.6_wp*2650.0_wp*9.81_wp
    associate (r => cfg%regions(1))
      call check_close(r%stress(2), -gs*1.5_wp, 1.0e-14_wp, 0.0_wp, 'saturated sigma''_v at y = 0')
      call check_close(r%stress_gradient(2, 2), gs, 1.0e-14_wp, 0.0_wp, 'saturated d sigma''_v / dy')
      call check_close(r%stress(1), -gs*1.5_wp*0.3_wp/0.7_wp, 1.0e-14_wp, 0.0_wp, 'K0 = nu / (1 - nu)')
      call check_close(r%stress(3), r%stress(1), 1.0e-14_wp, 0.0_wp, 'sigma''_zz = sigma''_xx')
      call check_close(r%stress_gradient(1, 2), gs*0.3_wp/0.7_wp, 1.0e-14_wp, 0.0_wp, &
                       'horizontal gradient')
      call check_close(r%pore_pressure, 1000.0_wp*9.81_wp*2.0_wp, 1.0e-14_wp, 0.0_wp, &
                       'pore pressure at y = 0 under water to y = 2')
      call check_close(r%pore_pressure_gradient(2), -9810.0_wp, 1.0e-14_wp, 0.0_wp, 'dp / dy')
      call check(r%stress_gradient(2, 1) == 0.0_wp .and. all(r%stress(4:6) == 0.0_wp), &
                 'no shear, nothing along x')
    end associate
    associate (r => cfg%regions(2))
      call check_close(r%stress(2), -(1.0e3_wp + gd*1.75_wp), 1.0e-14_wp, 0.0_wp, &
                       'dry sigma''_v at y = 0 with the overburden')
      call check_close(r%stress(1), 0.5_wp*r%stress(2), 1.0e-14_wp, 0.0_wp, 'given K0')
      call check_close(r%stress_gradient(2, 2), gd, 1.0e-14_wp, 0.0_wp, 'dry unit weight')
      call check(r%pore_pressure == 0.0_wp, 'dry soil has no pore pressure')
    end associate
  end subroutine test_geostatic_level_ground

  !> Every value of the two-phase scene as read on this rank.
  subroutine check_two_phase(c)
    type(config_t), intent(in) :: c
    call check(c%drag == 'implicit', 'drag')
    call check_close(c%drag_safety, 0.6_wp, 0.0_wp, 0.0_wp, 'drag_safety')
    call check(c%porosity_gradient, 'porosity_gradient')
    call check_equal_int(size(c%materials), 2, 'number of materials')
    if (size(c%materials) == 2) then
      call check(c%materials(1)%model == 'fluid', 'fluid model')
      call check_close(c%materials(1)%density, 998.0_wp, 0.0_wp, 0.0_wp, 'fluid density')
      call check_close(c%materials(1)%bulk_modulus, 2.0e9_wp, 0.0_wp, 0.0_wp, 'bulk_modulus')
      call check_close(c%materials(1)%conductivity, 0.0_wp, 0.0_wp, 0.0_wp, &
                       'fluid conductivity default')
      call check(c%materials(2)%model == 'linear_elastic', 'soil model')
      call check_close(c%materials(2)%conductivity, 1.0e-3_wp, 0.0_wp, 0.0_wp, 'conductivity')
      call check_close(c%materials(2)%bulk_modulus, 2.2e9_wp, 0.0_wp, 0.0_wp, &
                       'soil bulk_modulus keeps its default')
    end if
    call check_equal_int(size(c%regions), 2, 'number of regions')
    if (size(c%regions) == 2) then
      call check(c%regions(1)%phase == 'saturated', 'region 1 phase')
      call check_equal_int(c%regions(1)%material, 9, 'region 1 soil')
      call check_equal_int(c%regions(1)%fluid_material, 4, 'region 1 fluid_material')
      call check_close(c%regions(1)%porosity, 0.35_wp, 0.0_wp, 0.0_wp, 'region 1 porosity')
      call check_equal_int(c%regions(1)%seed, 3, 'region 1 seed')
      call check_equal_int(c%regions(1)%fluid_seed, 11, 'region 1 fluid_seed')
      call check(c%regions(2)%phase == 'fluid', 'region 2 phase')
      call check_equal_int(c%regions(2)%material, 4, 'region 2 material')
      call check(c%regions(2)%placement == 'uniform', 'region 2 placement')
      call check_equal_int(c%regions(2)%ppc, 3, 'region 2 ppc')
      call check_equal_int(c%regions(2)%fluid_material, 0, 'region 2 fluid_material default')
      call check_equal_int(c%regions(2)%fluid_seed, -1, 'region 2 fluid_seed default')
    end if
    call check(all(c%bc(1:4) == [bc_roller, bc_roller, bc_fixed, bc_free]), 'solid conditions')
    call check(all(c%fluid_bc(1:4) == [fbc_drained, fbc_default, fbc_default, &
                                       fbc_impermeable]), 'fluid conditions per face')
    call check(all(c%pore_pressure == [2.5e3_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]), &
               'pore pressure per face')
    call check(c%benchmark == 'terzaghi', 'benchmark')
  end subroutine check_two_phase

  !> Rank 0 reads the file and broadcasts its text; every rank parses it. A few values and
  !> the whole echo of the configuration (every parameter, as print_config writes it) are
  !> compared with rank 0's.
  subroutine test_every_rank_parses_the_same_config()
    type(config_t) :: cfg
    character(len=:), allocatable :: file, echo, echo0
    real(wp) :: x(8), x0(8)
    integer :: iv(6), iv0(6), st
    call begin_test('every_rank_parses_the_same_config')
    file = 'test_input_'//trim(tag)//'_full.nml'
    call write_full_scene(file)
    call read_input(file, MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, input_ok, 'read_input status')
    if (st /= input_ok) return
    x = [cfg%t_end, cfg%cfl, cfg%length(2), cfg%materials(1)%youngs_modulus, &
         cfg%regions(2)%poly(1, 2), cfg%loads(1)%traction(1), cfg%loads(1)%ramp_time, &
         cfg%amplitude]
    iv = [cfg%ncells(1), size(cfg%materials), size(cfg%regions), cfg%regions(2)%seed, &
          cfg%bc(3), len(cfg%input_text)]
    x0 = x
    iv0 = iv
    call MPI_Bcast(x0, size(x0), MPI_DOUBLE_PRECISION, 0, MPI_COMM_WORLD)
    call MPI_Bcast(iv0, size(iv0), MPI_INTEGER, 0, MPI_COMM_WORLD)
    call check(all(x == x0), 'real values equal to rank 0''s, to the bit')
    call check(all(iv == iv0), 'integer values and the text length equal to rank 0''s')
    echo = echo_text(cfg)
    echo0 = echo
    call bcast_string(echo0)
    call check(echo == echo0, 'the echo of every parameter equal to rank 0''s')
    echo0 = cfg%input_text
    call bcast_string(echo0)
    call check(cfg%input_text == echo0, 'input_text equal to rank 0''s')
  end subroutine test_every_rank_parses_the_same_config

  !> parse_input turns a text into a config_t on its own: no file, no communication.
  subroutine test_text_parses_without_a_file()
    type(config_t) :: cfg, bad
    type(input_problems_t) :: pb
    character(len=:), allocatable :: text
    character(len=*), parameter :: nl = new_line('a')
    call begin_test('text_parses_without_a_file')
    text = '&run t_end = 0.25, cfl = 0.3 /'//nl//'&grid ndim = 2, ncells = 6, 3 /'//nl// &
           '&material id = 2, density = 1800.0 /'//nl//'&material id = 3 /'//nl// &
           '&region lo = 0.0, 0.0, hi = 0.5, 0.5, material = 2 /'//nl// &
           '&boundary face = ''y-'', condition = ''fixed'' /'
    call pb%init('in_memory.nml')
    call parse_input(text, cfg, pb)
    call check_equal_int(pb%nprob, 0, 'no problems')
    call check_close(cfg%t_end, 0.25_wp, 0.0_wp, 0.0_wp, 't_end')
    call check_close(cfg%cfl, 0.3_wp, 0.0_wp, 0.0_wp, 'cfl')
    call check(all(cfg%ncells(1:2) == [6, 3]), 'ncells')
    call check_equal_int(size(cfg%materials), 2, 'two materials')
    if (size(cfg%materials) == 2) then
      call check_close(cfg%materials(1)%density, 1800.0_wp, 0.0_wp, 0.0_wp, 'density 1')
      call check_close(cfg%materials(2)%density, 1000.0_wp, 0.0_wp, 0.0_wp, 'density 2 default')
      call check_equal_int(cfg%materials(2)%id, 3, 'second material id')
    end if
    call check(cfg%bc(3) == bc_fixed .and. cfg%bc(1) == bc_free, 'boundary conditions')
    call check(cfg%input_text == text, 'input_text is the text')
    call pb%free()

    ! A misspelt variable in the second &material: one problem, with the file and the place.
    text = '&grid ncells = 4, 4 /'//nl//'&material /'//nl//'&material densty = 1.0 /'//nl// &
           '&region lo = 0.25, 0.25, hi = 0.75, 0.75 /'
    call pb%init('in_memory.nml')
    call parse_input(text, bad, pb)
    call check_equal_int(pb%nprob, 1, 'one problem')
    if (pb%nprob == 1) then
      call check(index(pb%prob(1)%s, 'dpmpm: input error: in_memory.nml: &material ') == 1, &
                 'the problem names the file and the group')
      call check(index(pb%prob(1)%s, '&material densty (line 3): no such variable') > 0, &
                 'the variable and its line')
      call check(index(pb%prob(1)%s, 'the variables of &material are id, model, density, '// &
                       'youngs_modulus, poisson_ratio, bulk_modulus') > 0, 'the variables of the group')
    end if
    call check(.not. pb%read_ok(4) .and. pb%read_ok(2), 'read_ok per group')
    call pb%free()
    call check(pb%nprob == 0 .and. .not. allocated(pb%prob), 'free releases the problems')
  end subroutine test_text_parses_without_a_file

  !> A refused input (a bad value, a missing file) is a status on every rank, not a stop.
  subroutine test_refused_input_returns_status()
    type(config_t) :: cfg
    character(len=:), allocatable :: file
    integer :: st
    call begin_test('refused_input_returns_status')
    file = 'test_input_'//trim(tag)//'_refused.nml'
    call write_file(file, [character(len=80) :: &
      '&grid ncells = 16, 16 /', &
      '&material density = -1.0 /', &
      '&region lo = 0.25, 0.25, hi = 0.75, 0.75 /'])
    call read_input(file, MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, input_refused, 'a negative density is refused')
    call read_input('test_input_'//trim(tag)//'_no_such_file.nml', MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, input_refused, 'a missing file is refused')
  end subroutine test_refused_input_returns_status

  !> Every parameter of cfg as print_config writes it, as one string (through a file of
  !> this rank's own).
  function echo_text(cfg) result(text)
    type(config_t), intent(in) :: cfg
    character(len=:), allocatable :: text
    character(len=:), allocatable :: file
    character(len=16) :: r
    integer :: u, n
    write (r, '(i0)') rank
    file = 'test_input_'//trim(tag)//'_echo_rank'//trim(r)//'.nml'
    open (newunit=u, file=file, status='replace', action='write')
    call print_config(cfg, u)
    close (u)
    open (newunit=u, file=file, access='stream', form='unformatted', action='read')
    inquire (unit=u, size=n)
    allocate (character(len=n) :: text)
    read (u) text
    close (u, status='delete')
  end function echo_text

  !> Rank 0's s on every rank.
  subroutine bcast_string(s)
    character(len=:), allocatable, intent(inout) :: s
    integer :: n
    n = len(s)
    call MPI_Bcast(n, 1, MPI_INTEGER, 0, MPI_COMM_WORLD)
    if (rank /= 0) then
      deallocate (s)
      allocate (character(len=n) :: s)
    end if
    call MPI_Bcast(s, n, MPI_CHARACTER, 0, MPI_COMM_WORLD)
  end subroutine bcast_string

end program test_input
