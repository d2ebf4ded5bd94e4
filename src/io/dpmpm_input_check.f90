!> Checks of a configuration read from the input: every value against what it may be,
!> the values against each other (materials of regions, faces of the grid, the rank
!> layout against the cells), each problem to the problem list with the group, the
!> variable, the value and what is allowed.
module dpmpm_input_check
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, material_cfg_t, load_cfg_t, max_poly, max_probes, optional_fields, field_listed, &
                          face_names, &
                          porosity_varies, region_levels, level_unset, &
                          table_length
  use dpmpm_kernels, only: kernel_from_name, kernel_names, ngrid_kernels, is_grid_kernel
  use dpmpm_mls, only: basis_from_name
  use dpmpm_shape_plan, only: shape_plan_t, max_gauss
  use dpmpm_input_problems, only: input_problems_t, g_run, g_grid, g_shape, g_material, &
                                  g_region, g_load, g_output, g_benchmark, add_value, add_warning, &
                                  real_ok, check_finite, add_raw
  use dpmpm_input_check_material, only: check_material, warn_weightless_cutoff, check_contact_scene
  use dpmpm_input_check_faces, only: check_tied, check_openings, check_axisymmetric
  use dpmpm_strings, only: itoa, i8toa, rtoa, itoa_list, rtoa_list, quote, next_word
  use mpi_f08, only: MPI_Dims_create
  use dpmpm_motion, only: check_motion
  implicit none
  private
  public :: check_config

contains

  !> Check every value of cfg, read from the file of pb, for a run on nranks ranks; the
  !> groups that could not be read (pb%read_ok false) are not checked against each other.
  subroutine check_config(pb, cfg, nranks)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: nranks
    integer :: nd, d, k
    logical :: grid_ok, ndim_ok, exists, shape_ok

    ! &run
    if (len_trim(cfg%name) == 0) then
      call add_value(pb, g_run, 1, 'name', "''", 'must not be empty: it names the output '// &
                     'files <dir>/<name>.h5 and <dir>/<name>.ckpt.h5')
    else if (scan(cfg%name, '/\') > 0) then
      call add_value(pb, g_run, 1, 'name', quote(cfg%name), 'a base name without "/": the '// &
                     'directory of the output files is &output dir')
    end if
    if (.not. any(cfg%scheme == [character(len=4) :: 'musl', 'usl'])) call add_value(pb, g_run, &
      1, 'scheme', quote(cfg%scheme), 'the schemes are musl, usl')
    if (.not. real_ok(cfg%t_end, gt=0.0_wp)) call add_value(pb, g_run, 1, 't_end', &
      rtoa(cfg%t_end), 'must be > 0 (s)')
    if (.not. real_ok(cfg%dt, ge=0.0_wp)) call add_value(pb, g_run, 1, 'dt', rtoa(cfg%dt), &
      'must be >= 0 (s; 0 = from the CFL condition)')
    if (.not. real_ok(cfg%cfl, gt=0.0_wp, le=1.0_wp)) call add_value(pb, g_run, 1, 'cfl', &
      rtoa(cfg%cfl), 'must be in (0, 1]')
    if (.not. real_ok(cfg%flip, ge=0.0_wp, le=1.0_wp)) call add_value(pb, g_run, 1, 'flip', &
      rtoa(cfg%flip), 'must be in [0, 1] (1 = FLIP, 0 = PIC)')
    if (cfg%max_steps < 1) call add_value(pb, g_run, 1, 'max_steps', i8toa(cfg%max_steps), &
      'must be >= 1')
    call check_finite(pb, g_run, 1, 'gravity', cfg%gravity)
    if (.not. real_ok(cfg%progress_seconds, gt=0.0_wp)) call add_value(pb, g_run, 1, &
      'progress_seconds', rtoa(cfg%progress_seconds), 'must be > 0 (s)')
    if (.not. real_ok(cfg%max_wall_time, ge=0.0_wp)) call add_value(pb, g_run, 1, &
      'max_wall_time', rtoa(cfg%max_wall_time), 'must be >= 0 (s of wall time; 0 = no limit)')
    if (cfg%sort_every < 0) call add_value(pb, g_run, 1, 'sort_every', itoa(cfg%sort_every), &
                                           'must be >= 0 (steps; 0 = the points are never sorted)')
    if (len_trim(cfg%restart) > 0) then
      inquire (file=trim(cfg%restart), exist=exists)
      if (.not. exists) call add_value(pb, g_run, 1, 'restart', quote(cfg%restart), &
        'no such file (a checkpoint <dir>/<name>.ckpt.h5 written with checkpoint_every > 0)')
    end if
    if (.not. any(cfg%drag == [character(len=8) :: 'explicit', 'implicit'])) call add_value(pb, &
      g_run, 1, 'drag', quote(cfg%drag), 'the drag treatments are explicit (limited by '// &
      'drag_safety), implicit (solid and fluid velocities solved together at each node)')
    if (.not. real_ok(cfg%drag_safety, gt=0.0_wp, le=1.0_wp)) call add_value(pb, g_run, 1, &
      'drag_safety', rtoa(cfg%drag_safety), 'must be in (0, 1] (fraction of the nodal drag limit)')
    if (.not. real_ok(cfg%free_surface_fraction, ge=0.0_wp, lt=0.5_wp)) call add_value(pb, g_run, 1, &
      'free_surface_fraction', rtoa(cfg%free_surface_fraction), 'must be in [0, 0.5): the fraction '// &
      'of a cell below which the fluid at a node marks a free surface (0 = off; a node on the '// &
      'surface of a full body holds half a cell)')
    if (.not. real_ok(cfg%cavitation_pressure, le=0.0_wp)) call add_value(pb, g_run, 1, &
      'cavitation_pressure', rtoa(cfg%cavitation_pressure), 'must be a finite pressure <= 0 '// &
      '(Pa, gauge; -1e5 is about a vacuum, a large negative value switches the cut off)')
    if (.not. any(cfg%pressure_smoothing == [character(len=4) :: 'none', 'cell'])) &
      call add_value(pb, g_run, 1, 'pressure_smoothing', quote(cfg%pressure_smoothing), &
                     'the choices are none, cell (the step''s pore-pressure change averaged '// &
                     'over the fluid points of each cell)')
    if (.not. any(cfg%volumetric_smoothing == [character(len=4) :: 'none', 'cell'])) &
      call add_value(pb, g_run, 1, 'volumetric_smoothing', quote(cfg%volumetric_smoothing), &
                     'the choices are none, cell (the volumetric strain rate of the solid '// &
                     'points averaged over the points of each material in each cell)')
    if (.not. real_ok(cfg%growth_limit, ge=0.0_wp)) call add_value(pb, g_run, 1, &
      'growth_limit', rtoa(cfg%growth_limit), 'must be >= 0 (0 = no growth monitor)')
    if (.not. real_ok(cfg%equilibrium_time, ge=0.0_wp)) then
      call add_value(pb, g_run, 1, 'equilibrium_time', rtoa(cfg%equilibrium_time), &
                     'must be >= 0 (s; 0 = no equilibrium phase)')
    else if (real_ok(cfg%t_end) .and. cfg%equilibrium_time > cfg%t_end) then
      call add_value(pb, g_run, 1, 'equilibrium_time', rtoa(cfg%equilibrium_time), &
                     'must not exceed t_end = '//rtoa(cfg%t_end)//' (s): the run would end '// &
                     'inside the equilibrium phase, still damped (and gravity reaches its full '// &
                     'value only at half of equilibrium_time)')
    end if
    call check_one_phase(pb, cfg)
    call check_rayleigh(pb, cfg)
    if (.not. real_ok(cfg%equilibrium_damping, ge=0.0_wp) .or. .not. cfg%equilibrium_damping < 1.0_wp) &
      call add_value(pb, g_run, 1, 'equilibrium_damping', rtoa(cfg%equilibrium_damping), &
                     'must be in [0, 1) (the fraction of the unbalanced force the damping takes)')

    ! &grid
    ndim_ok = cfg%ndim >= 1 .and. cfg%ndim <= 3
    if (.not. ndim_ok) call add_value(pb, g_grid, 1, 'ndim', itoa(cfg%ndim), 'must be 1, 2 or 3')
    grid_ok = ndim_ok .and. pb%read_ok(g_grid) .and. pb%count(g_grid) == 1
    nd = merge(cfg%ndim, 3, ndim_ok)
    do d = 1, nd
      if (cfg%ncells(d) < 1) then
        call add_value(pb, g_grid, 1, 'ncells('//itoa(d)//')', itoa(cfg%ncells(d)), &
                       'zero cells: must be >= 1')
        grid_ok = .false.
      end if
      if (.not. real_ok(cfg%length(d), gt=0.0_wp)) then
        call add_value(pb, g_grid, 1, 'length('//itoa(d)//')', rtoa(cfg%length(d)), &
                       'must be > 0 (m)')
        grid_ok = .false.
      end if
      if (.not. real_ok(cfg%origin(d))) then
        call add_value(pb, g_grid, 1, 'origin('//itoa(d)//')', rtoa(cfg%origin(d)), &
                       'must be a finite number (m)')
        grid_ok = .false.
      end if
      if (cfg%dims(d) < 0) then
        call add_value(pb, g_grid, 1, 'dims('//itoa(d)//')', itoa(cfg%dims(d)), &
                       'must be >= 0 (ranks along the axis; 0 = chosen by MPI)')
        grid_ok = .false.
      end if
    end do
    if (cfg%balance_every < 0) call add_value(pb, g_grid, 1, 'balance_every', itoa(cfg%balance_every), &
                                              'must be >= 0 (steps; 0 = the split by points at the '// &
                                              'start only)')
    if (.not. real_ok(cfg%balance_tolerance, ge=0.0_wp)) call add_value(pb, g_grid, 1, 'balance_tolerance', &
      rtoa(cfg%balance_tolerance), 'must be >= 0 (the busiest rank''s points above the mean, as a '// &
      'fraction, beyond which the grid is split again)')
    if (.not. any(cfg%balance == [character(len=6) :: 'cells', 'points', 'nested'])) &
      call add_value(pb, g_grid, 1, 'balance', quote(cfg%balance), 'the choices are cells (equal '// &
                     'numbers of cells per rank along each axis), points (the split along each '// &
                     'axis chosen for equal numbers of points, at the start and as they move) and '// &
                     'nested (the same, with the cuts of each axis chosen inside each part of the '// &
                     'axes before it)')

    ! &shape
    if (.not. is_grid_kernel(kernel_from_name(cfg%kernel))) call add_value(pb, g_shape, 1, &
      'kernel', quote(cfg%kernel), 'the grid kernels are '//all_kernels(ngrid_kernels))
    call check_mls_choice(pb, 'velocity', cfg%velocity_kernel, cfg%velocity_basis, &
                          cfg%velocity_radius, len_trim(cfg%velocity_kernel) > 0)
    if (.not. any(cfg%quadrature == [character(len=6) :: 'points', 'gauss'])) &
      call add_value(pb, g_shape, 1, 'quadrature', quote(cfg%quadrature), &
                     'the quadratures are points (at the material points), gauss (Gauss points '// &
                     'of the grid cells with MLS-reconstructed stresses)')
    if (cfg%gauss_points < 1 .or. cfg%gauss_points > max_gauss) call add_value(pb, g_shape, 1, &
      'gauss_points', itoa(cfg%gauss_points), 'must be 1 to '//itoa(max_gauss)// &
      ' (Gauss points per cell per axis)')
    call check_mls_choice(pb, 'field', cfg%field_kernel, cfg%field_basis, cfg%field_radius, &
                          cfg%quadrature == 'gauss')
    if (.not. any(cfg%field_support == [character(len=4) :: 'ball', 'box'])) &
      call add_value(pb, g_shape, 1, 'field_support', quote(cfg%field_support), 'the supports are ball '// &
                     '(a radial weight of radius field_radius), box (the tensor product of the weight''s '// &
                     'profile, of half-width field_radius along each axis)')
    if (cfg%quadrature == 'gauss' .and. cfg%field_support == 'box' .and. cfg%field_radius <= 0.0_wp) &
      call add_value(pb, g_shape, 1, 'field_support', quote(cfg%field_support), 'a box needs its '// &
                     'half-width field_radius > 0 (field_radius = 0 is the tensor-product B-spline of '// &
                     'natural support already)')

    ! (the ghost width of the decomposition needs known kernels: an unknown name is
    ! reported above, not looked up)
    shape_ok = is_grid_kernel(kernel_from_name(cfg%kernel)) .and. &
               (len_trim(cfg%velocity_kernel) == 0 .or. kernel_from_name(cfg%velocity_kernel) > 0) .and. &
               (cfg%quadrature /= 'gauss' .or. kernel_from_name(cfg%field_kernel) > 0)
    if (grid_ok .and. shape_ok) call check_decomposition(pb, cfg, nranks)
    if (cfg%volumetric_smoothing == 'cell' .and. cfg%pressure_smoothing /= 'cell' .and. &
        any(cfg%regions%phase == 'saturated')) &
      call add_value(pb, g_run, 1, 'volumetric_smoothing', quote(cfg%volumetric_smoothing), 'with '// &
                     'pore water it needs pressure_smoothing = ''cell'' as well: the smoothed '// &
                     'skeleton leaves the points of a cell free to change their volume apart, which '// &
                     'the pore pressures of the points then follow one by one (a footing on '// &
                     'undrained soil: 8.6e5 point-steps at the cavitation cut in 1 s, doc/verification.md, '// &
                     '"Saturated slope")')
    if (porosity_varies(cfg) .and. .not. cfg%porosity_gradient_given) &
      call add_value(pb, g_run, 1, 'porosity_gradient', '(not given)', 'the porosity varies '// &
                     'between the regions, so choose it: .true. keeps the pore pressure right '// &
                     'across a water-soil interface (a submerged layer within 3 % of hydrostatic '// &
                     'with linear grid functions, 37 % off without); '// &
                     '.false. keeps n p continuous across a jump of porosity, the paper''s choice '// &
                     '(doc/verification.md, "Submerged layer at rest")')
    call warn_scattered_pore_water(pb, cfg)

    ! &material
    do k = 1, size(cfg%materials)
      call check_material(pb, cfg%materials, k)
      call warn_weightless_cutoff(pb, k, cfg%materials(k), cfg%gravity, &
                                  any(cfg%regions%material == cfg%materials(k)%id))
      if (cfg%materials(k)%model == 'rigid') call check_rigid(pb, cfg, k)
    end do
    call check_contact_scene(pb, cfg)

    ! &region
    do k = 1, size(cfg%regions)
      call check_region(pb, cfg, k, grid_ok, pb%read_ok(g_material))
    end do

    ! &load
    do k = 1, size(cfg%loads)
      call check_finite(pb, g_load, k, 'traction', cfg%loads(k)%traction)
      if (.not. real_ok(cfg%loads(k)%ramp_time, ge=0.0_wp)) call add_value(pb, g_load, k, &
        'ramp_time', rtoa(cfg%loads(k)%ramp_time), 'must be >= 0 (s; 0 = step load)')
      call check_load_time(pb, k, cfg%loads(k))
      call check_load_part(pb, cfg, k, cfg%loads(k))
    end do

    ! &output
    if (.not. real_ok(cfg%frame_interval, ge=0.0_wp)) call add_value(pb, g_output, 1, &
      'frame_interval', rtoa(cfg%frame_interval), 'must be >= 0 (s; 0 = first and last only)')
    if (cfg%diag_every < 0) call add_value(pb, g_output, 1, 'diag_every', itoa(cfg%diag_every), &
      'must be >= 0 (steps; 0 = automatic)')
    if (len_trim(cfg%output_dir) == 0) call add_value(pb, g_output, 1, 'dir', "''", &
      'must name a directory')
    if (cfg%checkpoint_every < 0) call add_value(pb, g_output, 1, 'checkpoint_every', &
      itoa(cfg%checkpoint_every), 'must be >= 0 (steps; 0 = no checkpoints)')
    if (.not. real_ok(cfg%checkpoint_seconds, ge=0.0_wp)) call add_value(pb, g_output, 1, &
      'checkpoint_seconds', rtoa(cfg%checkpoint_seconds), &
      'must be >= 0 (s of wall time between checkpoints; 0 = none)')
    if (cfg%compression < 0 .or. cfg%compression > 9) call add_value(pb, g_output, 1, &
      'compression', itoa(cfg%compression), 'must be 0 (off) to 9 (gzip level)')
    call check_probes(pb, cfg)
    call check_fields(pb, 'solid_fields', cfg%solid_fields, .false.)
    call check_fields(pb, 'fluid_fields', cfg%fluid_fields, .true.)

    ! &benchmark
    if (.not. any(cfg%benchmark == [character(len=11) :: 'none', 'axial_bar', 'mms', &
                                    'biot_column', 'terzaghi'])) &
      call add_value(pb, g_benchmark, 1, 'name', quote(cfg%benchmark), &
                     'the benchmarks are none, axial_bar, mms, biot_column, terzaghi')
    if (cfg%benchmark == 'mms' .and. cfg%ndim /= 2) call add_value(pb, g_benchmark, 1, 'name', &
      quote(cfg%benchmark), 'the manufactured solution is 2D: set &grid ndim = 2')
    if (.not. real_ok(cfg%amplitude)) call add_value(pb, g_benchmark, 1, 'amplitude', &
      rtoa(cfg%amplitude), 'must be a finite number')

    ! &motion (its files are read by read_input once these values are good)
    call check_motion(pb, cfg)
    call check_tied(pb, cfg)
    call check_openings(pb, cfg)
    if (cfg%axisymmetric) call check_axisymmetric(pb, cfg)
  end subroutine check_config

  !> The probes of &output: at most max_probes, each inside the grid, a positive interval.
  subroutine check_probes(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    character(len=*), parameter :: axes = 'xyz'
    real(wp) :: x(3)
    integer :: k, d
    if (cfg%nprobes < 0 .or. cfg%nprobes > max_probes) call add_value(pb, g_output, 1, 'nprobes', &
      itoa(cfg%nprobes), 'must be 0 to '//itoa(max_probes))
    if (cfg%probe_every < 1) call add_value(pb, g_output, 1, 'probe_every', itoa(cfg%probe_every), &
                                            'must be >= 1 (steps between records)')
    do k = 1, min(max(cfg%nprobes, 0), max_probes)
      x = [cfg%probe_x(k), cfg%probe_y(k), cfg%probe_z(k)]
      do d = 1, min(max(cfg%ndim, 1), 3)
        if (.not. real_ok(x(d), ge=cfg%origin(d), le=cfg%origin(d) + cfg%length(d))) &
          call add_value(pb, g_output, 1, 'probe_'//axes(d:d)//'('//itoa(k)//')', rtoa(x(d)), &
                         'must lie in the grid, '//rtoa(cfg%origin(d))//' to '// &
                         rtoa(cfg%origin(d) + cfg%length(d)))
      end do
    end do
  end subroutine check_probes

  !> Saturated soil under gravity on scattered points (placement random or uniform of a
  !> region of pore water): the choices known to scatter or drift at rest warn (doc/verification.md,
  !> "Saturated soil at rest on scattered points"; measured on the submerged layer at
  !> 0.2 s, errors in units of the hydrostatic pressure at the base).
  subroutine warn_scattered_pore_water(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    character(len=*), parameter :: see = ' (doc/verification.md, "Saturated soil at rest on scattered points")'
    character(len=:), allocatable :: pl
    integer :: k, r
    if (.not. any(cfg%regions%phase == 'saturated') .or. all(cfg%gravity == 0.0_wp)) return
    r = 0
    do k = 1, size(cfg%regions)
      if (cfg%regions(k)%placement == 'regular') cycle
      if (cfg%regions(k)%phase /= 'saturated' .and. cfg%regions(k)%phase /= 'fluid') cycle
      r = k
      exit
    end do
    if (r == 0) return
    pl = quote(cfg%regions(r)%placement)
    if (cfg%quadrature /= 'gauss') then
      call add_warning(pb, g_region, r, 'placement', pl, 'with point quadrature the pore pressures '// &
                       'of single fluid points scatter on scattered points (a submerged layer at rest: '// &
                       'RMS 0.5-1.9 of the base pressure, single points 4-11 times it); linear grid '// &
                       'functions with one Gauss point per cell and porosity_gradient = .true. keep '// &
                       'them within 3 % (RMS)'//see)
    else if (.not. cfg%porosity_gradient .and. any(cfg%gravity /= 0.0_wp)) then
      call add_warning(pb, g_region, r, 'placement', pl, 'with Gauss quadrature and porosity_gradient '// &
                       '= .false. the pore water takes gravity at its points, not by the quadrature of '// &
                       'its pressure forces: porosity_gradient = .true. does both'//see)
    end if
    if (cfg%pressure_smoothing == 'cell' .and. cfg%quadrature /= 'gauss') &
      call add_warning(pb, g_run, 1, 'pressure_smoothing', quote(cfg%pressure_smoothing), 'on '// &
                       'scattered points the cell means of the pore pressure drift at rest (a '// &
                       'submerged layer: band means 0.6-0.96 of the base pressure off, points at '// &
                       '1.5-2 m/s after 0.2 s)'//see)
  end subroutine warn_scattered_pore_water

  !> The time function of &load k: ramp (ramp_time), sine (frequency > 0, duration >= 0) or
  !> table (times >= 0 increasing from the first entry, then only unused entries < 0;
  !> finite factors).
  subroutine check_load_time(pb, k, ld)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(load_cfg_t), intent(in) :: ld
    integer :: n, i
    character(len=*), parameter :: unused = 'does nothing with time_function = '
    if (trim(ld%time_function) /= 'ramp' .and. ld%ramp_time /= 0.0_wp) &
      call add_warning(pb, g_load, k, 'ramp_time', rtoa(ld%ramp_time), unused// &
                       quote(ld%time_function)//" (only 'ramp' takes it)")
    if (trim(ld%time_function) /= 'sine') then
      if (ld%frequency /= 0.0_wp) call add_warning(pb, g_load, k, 'frequency', &
        rtoa(ld%frequency), unused//quote(ld%time_function)//" (only 'sine' takes it)")
      if (ld%duration /= 0.0_wp) call add_warning(pb, g_load, k, 'duration', &
        rtoa(ld%duration), unused//quote(ld%time_function)//" (only 'sine' takes it)")
    end if
    if (trim(ld%time_function) /= 'table') then
      if (any(ld%times /= -1.0_wp)) call add_warning(pb, g_load, k, 'times', &
        rtoa_list(pack(ld%times, ld%times /= -1.0_wp)), unused//quote(ld%time_function)// &
        " (only 'table' takes it)")
      if (ld%nfactors > 0) call add_warning(pb, g_load, k, 'factors', &
        rtoa_list(ld%factors(1:ld%nfactors)), unused//quote(ld%time_function)// &
        " (only 'table' takes it)")
    end if
    select case (trim(ld%time_function))
    case ('ramp')
    case ('sine')
      if (.not. real_ok(ld%frequency, gt=0.0_wp)) call add_value(pb, g_load, k, 'frequency', &
        rtoa(ld%frequency), "must be > 0 (Hz) with time_function = 'sine'")
      if (.not. real_ok(ld%duration, ge=0.0_wp)) call add_value(pb, g_load, k, 'duration', &
        rtoa(ld%duration), 'must be >= 0 (s; 0 = for ever)')
    case ('table')
      n = table_length(ld%times)
      if (n == 0) then
        call add_value(pb, g_load, k, 'times', '(none >= 0)', "time_function = 'table' needs "// &
                       'times (s, from the first entry on, increasing) and their factors')
      else if (any(ld%times(n + 1:) >= 0.0_wp)) then
        call add_value(pb, g_load, k, 'times', rtoa(ld%times(n + 1)), 'the table ends at its '// &
                       'first negative entry (entry '//itoa(n + 1)//'); give the times in order')
      end if
      do i = 2, n
        if (ld%times(i) <= ld%times(i - 1)) then
          call add_value(pb, g_load, k, 'times', rtoa(ld%times(i)), 'must increase (entry '// &
                         itoa(i)//' is not after entry '//itoa(i - 1)//')')
          exit
        end if
      end do
      if (n > 0) call check_finite(pb, g_load, k, 'times', ld%times(1:n))
      if (n > 0) call check_finite(pb, g_load, k, 'factors', ld%factors(1:n))
      if (n > 0 .and. ld%nfactors /= n) &
        call add_value(pb, g_load, k, 'factors', rtoa_list(ld%factors(1:max(1, ld%nfactors))), &
                       itoa(ld%nfactors)//' factors for '//itoa(n)//' times: give one '// &
                       'factor per time')
    case default
      call add_value(pb, g_load, k, 'time_function', quote(ld%time_function), &
                     'the time functions are ramp (over ramp_time), sine (frequency, duration), '// &
                     'table (times, factors)')
    end select
  end subroutine check_load_time

  !> The part lo..hi of the face of &load k: finite; along each axis of the face either
  !> lo = hi = 0 (the whole face) or lo < hi within the face (with hi < lo the load took the
  !> whole face, beyond it the part was cut at the grid's edge, both without a word); on the
  !> face's normal axis the values do nothing (a warning).
  subroutine check_load_part(pb, cfg, k, ld)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    type(load_cfg_t), intent(in) :: ld
    integer :: t, j
    real(wp) :: glo, ghi, tol
    character(len=:), allocatable :: var, val
    call check_finite(pb, g_load, k, 'lo', ld%lo)
    call check_finite(pb, g_load, k, 'hi', ld%hi)
    if (ld%face < 1 .or. ld%face > 2*cfg%ndim) return
    if (.not. all([(real_ok(ld%lo(j)) .and. real_ok(ld%hi(j)), j=1, 3)])) return
    do t = 1, cfg%ndim
      var = 'lo('//itoa(t)//'), hi('//itoa(t)//')'
      val = rtoa(ld%lo(t))//', '//rtoa(ld%hi(t))
      if (t == (ld%face + 1)/2) then
        if (ld%lo(t) /= 0.0_wp .or. ld%hi(t) /= 0.0_wp) call add_warning(pb, g_load, k, var, &
          val, 'axis '//itoa(t)//' is the normal of face '//face_names(ld%face)// &
          ': these values do nothing; leave them 0')
        cycle
      end if
      if (ld%lo(t) == 0.0_wp .and. ld%hi(t) == 0.0_wp) cycle
      glo = cfg%origin(t)
      ghi = cfg%origin(t) + cfg%length(t)
      tol = 1.0e-12_wp*cfg%length(t)
      if (ld%hi(t) <= ld%lo(t)) then
        call add_value(pb, g_load, k, var, val, 'need lo < hi for a part of the face along '// &
                       'axis '//itoa(t)//' (lo = hi = 0, the default, loads the whole face)')
      else if (ld%lo(t) < glo - tol .or. ld%hi(t) > ghi + tol) then
        call add_value(pb, g_load, k, var, val, 'the part must lie on the face, which spans ['// &
                       rtoa(glo)//', '//rtoa(ghi)//'] along axis '//itoa(t))
      end if
    end do
  end subroutine check_load_part

  !> Rayleigh damping (&run rayleigh_*): each value finite and >= 0; one form only, a ratio
  !> at two frequencies f1 < f2 or alpha and beta; one-phase scenes only.
  subroutine check_rayleigh(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    character(len=14), parameter :: names(5) = [character(len=14) :: 'rayleigh_ratio', 'rayleigh_f1', &
                                                 'rayleigh_f2', 'rayleigh_alpha', 'rayleigh_beta']
    real(wp) :: v(5)
    integer :: k
    v = [cfg%rayleigh_ratio, cfg%rayleigh_f1, cfg%rayleigh_f2, cfg%rayleigh_alpha, cfg%rayleigh_beta]
    do k = 1, 5
      if (.not. real_ok(v(k), ge=0.0_wp)) then
        call add_value(pb, g_run, 1, trim(names(k)), rtoa(v(k)), 'must be >= 0 (0 = no Rayleigh damping)')
        return
      end if
    end do
    if (all(v == 0.0_wp)) return
    if (any(v(1:3) > 0.0_wp) .and. any(v(4:5) > 0.0_wp)) then
      call add_value(pb, g_run, 1, 'rayleigh_alpha', rtoa(v(4))//', rayleigh_beta = '//rtoa(v(5)), &
                     'give either rayleigh_ratio with rayleigh_f1 and rayleigh_f2, or rayleigh_alpha '// &
                     'and rayleigh_beta, not both')
      return
    end if
    if (any(v(1:3) > 0.0_wp)) then
      if (.not. v(1) < 1.0_wp .or. v(1) == 0.0_wp) then
        call add_value(pb, g_run, 1, 'rayleigh_ratio', rtoa(v(1)), 'must be in (0, 1) with '// &
                       'rayleigh_f1 and rayleigh_f2 (the damping ratio at both frequencies, 0.05 = 5 %)')
      else if (v(2) == 0.0_wp .or. .not. v(2) < v(3)) then
        call add_value(pb, g_run, 1, 'rayleigh_f1', rtoa(v(2))//', rayleigh_f2 = '//rtoa(v(3)), &
                       'need 0 < rayleigh_f1 < rayleigh_f2 (Hz: the two frequencies at which the '// &
                       'damping ratio is rayleigh_ratio)')
      end if
    end if
    if (any(cfg%regions%phase /= 'solid')) &
      call add_value(pb, g_run, 1, 'rayleigh_'//trim(merge('ratio', 'alpha', v(1) > 0.0_wp)), &
                     rtoa(merge(v(1), v(4), v(1) > 0.0_wp)), 'Rayleigh damping is for one-phase '// &
                     'scenes: with pore water the drag damps the relative motion, and the skeleton''s '// &
                     'damping would have to be split between the phases (doc/input.md)')
  end subroutine check_rayleigh

  !> Settings of the pore water (&run) in a scene without it do nothing: a warning for each
  !> that differs from its default.
  subroutine check_one_phase(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    type(config_t) :: d
    character(len=*), parameter :: why = 'does nothing in a scene without pore or free water '// &
                                   '(every &region has phase = ''solid'')'
    if (.not. allocated(cfg%regions)) return
    if (size(cfg%regions) == 0 .or. any(cfg%regions%phase /= 'solid')) return
    if (cfg%pressure_smoothing /= d%pressure_smoothing) &
      call add_warning(pb, g_run, 1, 'pressure_smoothing', quote(cfg%pressure_smoothing), why)
    if (cfg%drag /= d%drag) call add_warning(pb, g_run, 1, 'drag', quote(cfg%drag), why)
    if (cfg%drag_safety /= d%drag_safety) &
      call add_warning(pb, g_run, 1, 'drag_safety', rtoa(cfg%drag_safety), why)
    if (cfg%porosity_gradient .neqv. d%porosity_gradient) call add_warning(pb, g_run, 1, &
      'porosity_gradient', trim(merge('.true. ', '.false.', cfg%porosity_gradient)), why)
    if (cfg%remap_drag .neqv. d%remap_drag) &
      call add_warning(pb, g_run, 1, 'remap_drag', '.false.', why)
    if (cfg%cavitation_pressure /= d%cavitation_pressure) &
      call add_warning(pb, g_run, 1, 'cavitation_pressure', rtoa(cfg%cavitation_pressure), why)
    if (cfg%free_surface_fraction /= d%free_surface_fraction) &
      call add_warning(pb, g_run, 1, 'free_surface_fraction', rtoa(cfg%free_surface_fraction), why)
  end subroutine check_one_phase

  !> Check one MLS reconstruction choice of &shape (prefix velocity or field) when it is used.
  subroutine check_mls_choice(pb, prefix, kernel, basis, radius, used)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: prefix, kernel, basis
    real(wp), intent(in) :: radius
    logical, intent(in) :: used
    integer :: k
    if (.not. used) return
    k = kernel_from_name(kernel)
    if (k <= 0) then
      call add_value(pb, g_shape, 1, prefix//'_kernel', quote(kernel), 'the MLS weights are '// &
                     all_kernels(size(kernel_names)))
    else if (.not. is_grid_kernel(k) .and. .not. real_ok(radius, gt=0.0_wp)) then
      call add_value(pb, g_shape, 1, prefix//'_radius', rtoa(radius), 'the '//trim(kernel)// &
                     ' weight is radial and needs a support radius > 0 (in cells)')
    end if
    if (.not. real_ok(radius, ge=0.0_wp, le=4.0_wp)) call add_value(pb, g_shape, 1, &
      prefix//'_radius', rtoa(radius), 'must be in [0, 4] cells (0 = tensor-product B-spline '// &
      'of natural support)')
    if (basis_from_name(basis) < 0) call add_value(pb, g_shape, 1, prefix//'_basis', &
      quote(basis), 'the bases are constant, linear, quadratic')
  end subroutine check_mls_choice

  !> Check that the ranks can be laid out over the grid as the solver will do it, with at least
  !> the kernel's ghost width of cells per rank along every axis.
  subroutine check_decomposition(pb, cfg, nranks)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: nranks
    integer :: nd, d, nfixed, gw
    type(shape_plan_t) :: plan
    integer :: dims(3)
    character(len=:), allocatable :: advice
    nd = cfg%ndim
    dims = 1
    dims(1:nd) = cfg%dims(1:nd)
    nfixed = product(dims(1:nd), mask=dims(1:nd) > 0)
    if (all(dims(1:nd) > 0)) then
      if (nfixed /= nranks) then
        call add_value(pb, g_grid, 1, 'dims', itoa_list(dims(1:nd)), 'the ranks per axis '// &
                       'multiply to '//itoa(nfixed)//' but the run has '//itoa(nranks)// &
                       trim(merge(' rank ', ' ranks', nranks == 1))//': their product must '// &
                       'be the number of ranks (or use 0 to let MPI choose an axis)')
        return
      end if
    else if (mod(nranks, nfixed) /= 0) then
      call add_value(pb, g_grid, 1, 'dims', itoa_list(dims(1:nd)), 'the nonzero ranks per '// &
                     'axis multiply to '//itoa(nfixed)//', which does not divide the '// &
                     itoa(nranks)//' ranks of the run')
      return
    end if
    call MPI_Dims_create(nranks, nd, dims(1:nd))
    call plan%init(cfg)
    gw = plan%ghost_width()
    advice = ': every rank needs at least '//itoa(gw)//' cell'//trim(merge('s', ' ', gw > 1))// &
             ' along each axis with the '//trim(cfg%kernel)//' kernel and the reach of the '// &
             'MLS weights; use fewer ranks or more cells'
    do d = 1, nd
      if (dims(d) > cfg%ncells(d)) then
        call add_value(pb, g_grid, 1, 'ncells('//itoa(d)//')', itoa(cfg%ncells(d)), &
                       'more ranks than cells along axis '//itoa(d)//' ('//itoa(dims(d))// &
                       ' of the '//itoa(nranks)//' ranks lie along it)'//advice)
      else if (cfg%ncells(d)/dims(d) < gw) then
        call add_value(pb, g_grid, 1, 'ncells('//itoa(d)//')', itoa(cfg%ncells(d)), &
                       'too few cells per rank along axis '//itoa(d)//' ('//itoa(dims(d))// &
                       ' of the '//itoa(nranks)//' ranks lie along it)'//advice)
      end if
    end do
  end subroutine check_decomposition

  !> Check region k.
  subroutine check_region(pb, cfg, k, grid_ok, materials_ok)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    logical, intent(in) :: grid_ok, materials_ok
    integer :: d, j, m
    real(wp) :: glo, ghi, tol
    character(len=*), parameter :: xy = 'xy'
    associate (r => cfg%regions(k))
      select case (trim(r%shape))
      case ('box')
        do d = 1, merge(cfg%ndim, 0, grid_ok)
          if (.not. (real_ok(r%lo(d)) .and. real_ok(r%hi(d)))) then
            call add_value(pb, g_region, k, 'lo('//itoa(d)//'), hi('//itoa(d)//')', &
                           rtoa(r%lo(d))//', '//rtoa(r%hi(d)), 'must be finite numbers (m)')
            cycle
          end if
          glo = cfg%origin(d)
          ghi = cfg%origin(d) + cfg%length(d)
          tol = 1.0e-12_wp*cfg%length(d)
          if (r%lo(d) >= r%hi(d)) then
            call add_value(pb, g_region, k, 'lo('//itoa(d)//'), hi('//itoa(d)//')', &
                           rtoa(r%lo(d))//', '//rtoa(r%hi(d)), 'need lo < hi')
          else if (r%lo(d) < glo - tol .or. r%hi(d) > ghi + tol) then
            call add_value(pb, g_region, k, 'lo('//itoa(d)//'), hi('//itoa(d)//')', &
                           rtoa(r%lo(d))//', '//rtoa(r%hi(d)), 'region outside the grid: the '// &
                           'box must lie in the grid, ['//rtoa(glo)//', '//rtoa(ghi)// &
                           '] along axis '//itoa(d))
          end if
        end do
      case ('polygon')
        if (cfg%ndim /= 2) then
          call add_value(pb, g_region, k, 'shape', quote(r%shape), &
                         'polygon regions need ndim = 2; use a box')
        else if (r%npoly < 3 .or. r%npoly > max_poly) then
          call add_value(pb, g_region, k, 'npoly', itoa(r%npoly), &
                         'a polygon needs 3 to '//itoa(max_poly)//' vertices (poly_x, poly_y)')
        else if (grid_ok) then
          vertices: do j = 1, r%npoly
            do d = 1, 2
              glo = cfg%origin(d)
              ghi = cfg%origin(d) + cfg%length(d)
              tol = 1.0e-12_wp*cfg%length(d)
              if (.not. real_ok(r%poly(d, j), ge=glo - tol, le=ghi + tol)) then
                call add_value(pb, g_region, k, 'poly_'//xy(d:d)//'('//itoa(j)//')', &
                               rtoa(r%poly(d, j)), 'region outside the grid: every vertex '// &
                               'must lie in the grid, ['//rtoa(glo)//', '//rtoa(ghi)//'] in '// &
                               xy(d:d))
                exit vertices
              end if
            end do
          end do vertices
        end if
      case default
        call add_value(pb, g_region, k, 'shape', quote(r%shape), &
                       'the shapes are box, polygon (polygon with ndim = 2 only)')
      end select
      m = 0
      if (materials_ok) m = findloc(cfg%materials%id, r%material, dim=1)
      if (materials_ok .and. m == 0) &
        call add_value(pb, g_region, k, 'material', itoa(r%material), 'no &material has this id')
      select case (trim(r%phase))
      case ('solid')
        if (m > 0) then
          if (cfg%materials(m)%model == 'fluid') call add_value(pb, g_region, k, 'material', &
            itoa(r%material), "material "//itoa(r%material)//" is a 'fluid' material; a solid "// &
            "region needs a solid material (or set phase = 'fluid')")
        end if
      case ('fluid')
        if (m > 0) then
          if (cfg%materials(m)%model /= 'fluid') call add_value(pb, g_region, k, 'material', &
            itoa(r%material), 'material '//itoa(r%material)//' has model '// &
            quote(cfg%materials(m)%model)//"; a fluid region needs a 'fluid' material")
        end if
        if (any(r%stress /= 0.0_wp)) call add_value(pb, g_region, k, 'stress', &
          rtoa_list(r%stress), 'a fluid region has no skeleton stress; leave stress out '// &
          '(its initial state is pore_pressure)')
        if (any(r%stress_gradient /= 0.0_wp)) call add_value(pb, g_region, k, 'stress_gradient', &
          rtoa_list(reshape(r%stress_gradient, [18])), 'a fluid region has no skeleton '// &
          'stress; leave stress_gradient out (use pore_pressure_gradient)')
      case ('saturated')
        call check_saturated(pb, cfg, k, materials_ok)
      case default
        call add_value(pb, g_region, k, 'phase', quote(r%phase), &
                       'the phases are solid, fluid, saturated (soil skeleton with pore fluid)')
      end select
      if (trim(r%phase) == 'solid') then
        if (r%pore_pressure /= 0.0_wp) call add_value(pb, g_region, k, 'pore_pressure', &
          rtoa(r%pore_pressure), "a solid region has no pore fluid; leave it out or set "// &
          "phase = 'saturated'")
        if (any(r%pore_pressure_gradient /= 0.0_wp)) call add_value(pb, g_region, k, &
          'pore_pressure_gradient', rtoa_list(r%pore_pressure_gradient), 'a solid region has '// &
          "no pore fluid; leave it out or set phase = 'saturated'")
      end if
      if (trim(r%phase) /= 'saturated') then
        if (r%fluid_material /= 0) call add_value(pb, g_region, k, 'fluid_material', &
          itoa(r%fluid_material), "only a saturated region has a pore fluid; leave it out "// &
          "or set phase = 'saturated'")
      end if
      if (trim(r%phase) == 'fluid' .and. r%porosity /= 0.0_wp) call add_value(pb, g_region, k, &
        'porosity', rtoa(r%porosity), "a fluid region has no porosity (free water is n = 1); "// &
        'leave it out')
      if (trim(r%phase) == 'solid') call check_dry_porous(pb, cfg, k, materials_ok)
      if (r%ppc < 1 .or. r%ppc > 10) call add_value(pb, g_region, k, 'ppc', itoa(r%ppc), &
        'must be in 1..10 (points per cell along each axis)')
      if (.not. any(r%placement == [character(len=7) :: 'regular', 'random', 'uniform', 'stirred'])) &
        call add_value(pb, g_region, k, 'placement', quote(r%placement), &
                       'the placements are regular, random (scattered in each cell), '// &
                       'uniform (scattered over the whole region), stirred (the regular '// &
                       'points after area-preserving shears)')
      if (r%placement == 'stirred' .and. cfg%ndim == 1) call add_value(pb, g_region, k, &
        'placement', quote(r%placement), 'a line has nothing to stir: stirred needs ndim = 2 or 3')
      if (r%stir_rounds < 0 .or. r%stir_rounds > 100) call add_value(pb, g_region, k, &
        'stir_rounds', itoa(r%stir_rounds), 'must be in 0..100')
      if (.not. (r%stir_shear >= 0.0_wp .and. r%stir_shear <= 100.0_wp)) call add_value(pb, &
        g_region, k, 'stir_shear', rtoa(r%stir_shear), 'must be in 0..100')
      if (r%seed < 0) call add_value(pb, g_region, k, 'seed', itoa(r%seed), 'must be >= 0')
      if (r%fluid_seed < -1) call add_value(pb, g_region, k, 'fluid_seed', itoa(r%fluid_seed), &
        'must be >= 0, or -1 for seed + 1')
      call check_finite(pb, g_region, k, 'velocity', r%velocity)
      call check_finite(pb, g_region, k, 'stress', r%stress)
      call check_finite(pb, g_region, k, 'stress_gradient', reshape(r%stress_gradient, [18]))
      call check_finite(pb, g_region, k, 'pore_pressure', [r%pore_pressure])
      call check_finite(pb, g_region, k, 'pore_pressure_gradient', r%pore_pressure_gradient)
      call check_geostatic(pb, cfg, k)
    end associate
  end subroutine check_region

  !> The level-ground initial state of region k (geostatic = .true.): it computes stress
  !> and pore pressure itself, needs gravity along -axis ndim only, and a saturated
  !> region lies below its water level; its parameters are refused without it.
  subroutine check_geostatic(pb, cfg, k)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    real(wp) :: s, w
    character(len=*), parameter :: only = 'only a region with geostatic = .true. takes it'
    associate (r => cfg%regions(k))
      if (.not. r%geostatic) then
        if (r%k0 /= -1.0_wp) call add_value(pb, g_region, k, 'k0', rtoa(r%k0), only)
        if (r%surface /= level_unset) call add_value(pb, g_region, k, 'surface', rtoa(r%surface), only)
        if (r%water_level /= level_unset) &
          call add_value(pb, g_region, k, 'water_level', rtoa(r%water_level), only)
        if (r%overburden /= 0.0_wp) &
          call add_value(pb, g_region, k, 'overburden', rtoa(r%overburden), only)
        return
      end if
      if (any(r%stress /= 0.0_wp) .or. any(r%stress_gradient /= 0.0_wp) .or. &
          r%pore_pressure /= 0.0_wp .or. any(r%pore_pressure_gradient /= 0.0_wp)) &
        call add_value(pb, g_region, k, 'geostatic', '.true.', 'it computes the stress and pore '// &
                       'pressure from gravity; leave stress, stress_gradient, pore_pressure and '// &
                       'pore_pressure_gradient out')
      if (.not. (cfg%gravity(cfg%ndim) < 0.0_wp .and. all(cfg%gravity(1:cfg%ndim - 1) == 0.0_wp))) &
        call add_value(pb, g_region, k, 'geostatic', '.true.', 'level ground needs gravity '// &
                       'along the last grid axis, pointing down (&run gravity = 0, ..., -9.81)')
      if (.not. (real_ok(r%k0, ge=0.0_wp) .or. r%k0 == -1.0_wp)) &
        call add_value(pb, g_region, k, 'k0', rtoa(r%k0), 'must be >= 0, or left out for '// &
                       'nu / (1 - nu) of the material')
      if (.not. real_ok(r%overburden, ge=0.0_wp)) call add_value(pb, g_region, k, 'overburden', &
        rtoa(r%overburden), 'must be >= 0 (Pa, the vertical effective stress at the surface)')
      call region_levels(cfg, k, s, w)
      if (.not. (real_ok(s) .and. real_ok(w))) then
        call add_value(pb, g_region, k, 'surface', rtoa(s), 'surface and water_level must be '// &
                       'finite (m)')
      else if (trim(r%phase) == 'saturated' .and. w < s) then
        call add_value(pb, g_region, k, 'water_level', rtoa(w), 'a saturated region lies below '// &
                       'its water level; the surface is at '//rtoa(s)//' m')
      end if
    end associate
  end subroutine check_geostatic

  !> A rigid body (material k, model rigid; doc/theory.md 6.8): with Standard MPM or
  !> B-spline grid functions at the points (not Gauss quadrature), in solid regions
  !> without porosity; in a scene with pore water it drives the skeleton and the water
  !> moves against it.
  subroutine check_rigid(pb, cfg, k)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    integer :: r
    if (cfg%quadrature == 'gauss') call add_value(pb, g_material, k, 'model', "'rigid'", &
      "a rigid body needs quadrature = 'points' (the Gauss points of cells it shares with "// &
      'the soil would mix its stress, zero, into the soil''s)')
    if (.not. allocated(cfg%regions)) return
    do r = 1, size(cfg%regions)
      if (cfg%regions(r)%material /= cfg%materials(k)%id) cycle
      if (trim(cfg%regions(r)%phase) /= 'solid' .or. cfg%regions(r)%porosity /= 0.0_wp) &
        call add_value(pb, g_region, r, 'material', itoa(cfg%regions(r)%material), &
                       'a rigid material fills solid regions without porosity')
      if (any(cfg%regions(r)%velocity /= 0.0_wp)) call add_warning(pb, g_region, r, &
        'velocity', rtoa_list(cfg%regions(r)%velocity(1:cfg%ndim)), 'does nothing: a rigid '// &
        'body (material '//itoa(cfg%regions(r)%material)//") moves at its &material velocity "// &
        'from the start')
      if (any(cfg%regions(r)%stress /= 0.0_wp) .or. any(cfg%regions(r)%stress_gradient /= 0.0_wp)) &
        call add_warning(pb, g_region, r, 'stress', rtoa_list(cfg%regions(r)%stress), &
                         'does nothing: a rigid body has no stress')
    end do
  end subroutine check_rigid

  !> Check the porosity of solid region k: 0 for a body that is not porous (a footing, a
  !> wall), in (0, 1) for dry soil; dry soil in a scene with a fluid needs a conductivity
  !> (its pores take the water that reaches them).
  subroutine check_dry_porous(pb, cfg, k, materials_ok)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    logical, intent(in) :: materials_ok
    integer :: m
    associate (r => cfg%regions(k))
      if (.not. real_ok(r%porosity, ge=0.0_wp, lt=1.0_wp)) then
        call add_value(pb, g_region, k, 'porosity', rtoa(r%porosity), 'must be in [0, 1) '// &
                       'for a solid region: 0 (the default) for a body that is not porous, '// &
                       'the volume fraction of the pores for dry soil')
        return
      end if
      if (r%porosity == 0.0_wp .or. .not. materials_ok) return
      if (.not. any(cfg%regions%phase == 'fluid' .or. cfg%regions%phase == 'saturated')) return
      m = findloc(cfg%materials%id, r%material, dim=1)
      if (m == 0) return
      if (.not. real_ok(cfg%materials(m)%conductivity, gt=0.0_wp)) &
        call add_value(pb, g_region, k, 'material', itoa(r%material), 'material '// &
                       itoa(r%material)//' has conductivity = '// &
                       rtoa(cfg%materials(m)%conductivity)//'; dry soil (porosity > 0) in a '// &
                       'scene with pore or free water needs a hydraulic conductivity > 0 (m/s) '// &
                       'for the water that enters it')
    end associate
  end subroutine check_dry_porous

  !> Check the soil skeleton, pore fluid and porosity of saturated region k.
  subroutine check_saturated(pb, cfg, k, materials_ok)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    logical, intent(in) :: materials_ok
    integer :: m, mf
    associate (r => cfg%regions(k))
      if (materials_ok) then
        m = findloc(cfg%materials%id, r%material, dim=1)
        if (m > 0) then
          if (cfg%materials(m)%model == 'fluid') then
            call add_value(pb, g_region, k, 'material', itoa(r%material), "material "// &
                           itoa(r%material)//" is a 'fluid' material; the material of a "// &
                           'saturated region is its soil skeleton (linear_elastic, '// &
                           'neo_hookean, mohr_coulomb or drucker_prager) and fluid_material '// &
                           'its pore fluid')
          else if (.not. real_ok(cfg%materials(m)%conductivity, gt=0.0_wp)) then
            call add_value(pb, g_region, k, 'material', itoa(r%material), 'material '// &
                           itoa(r%material)//' has conductivity = '// &
                           rtoa(cfg%materials(m)%conductivity)//'; the soil of a saturated '// &
                           'region needs a hydraulic conductivity > 0 (m/s)')
          end if
        end if
        mf = findloc(cfg%materials%id, r%fluid_material, dim=1)
        if (r%fluid_material == 0) then
          call add_value(pb, g_region, k, 'fluid_material', itoa(r%fluid_material), &
                         "a saturated region needs the id of a 'fluid' &material for its "// &
                         'pore fluid')
        else if (mf == 0) then
          call add_value(pb, g_region, k, 'fluid_material', itoa(r%fluid_material), &
                         'no &material has this id')
        else if (cfg%materials(mf)%model /= 'fluid') then
          call add_value(pb, g_region, k, 'fluid_material', itoa(r%fluid_material), &
                         'material '//itoa(r%fluid_material)//' has model '// &
                         quote(cfg%materials(mf)%model)//"; the pore fluid of a saturated "// &
                         "region must be a 'fluid' material")
        end if
      end if
      if (.not. real_ok(r%porosity, gt=0.0_wp, lt=1.0_wp)) call add_value(pb, g_region, k, &
        'porosity', rtoa(r%porosity), 'must be in (0, 1) for a saturated region (volume '// &
        'fraction of the pores)')
    end associate
  end subroutine check_saturated

  !> solid_fields / fluid_fields: known names only; a fluid set has no stress to write.
  subroutine check_fields(pb, var, list, fluid)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: var, list
    logical, intent(in) :: fluid
    character(len=:), allocatable :: word
    word = unknown_field(list)
    if (len(word) > 0) then
      call add_value(pb, g_output, 1, var, "'"//trim(list)//"'", 'unknown dataset '''//word// &
                     ''': the optional datasets are displacement, stress, material, '// &
                     'porosity, pore_pressure, state, rank, or all (id, x, v, mass and '// &
                     'volume are always written)')
    else if (fluid .and. field_listed(list, 'stress', explicit=.true.)) then
      call add_value(pb, g_output, 1, var, "'"//trim(list)//"'", 'a fluid set has no '// &
                     'stress dataset (its stress is -pore_pressure on the diagonal)')
    end if
  end subroutine check_fields

  !> The first word of list that is neither 'all' nor an optional field ('' when none).
  function unknown_field(list) result(word)
    character(len=*), intent(in) :: list
    character(len=:), allocatable :: word
    integer :: i, j
    word = ''
    j = 0
    do
      call next_word(list, j + 1, i, j)
      if (i > j) exit
      if (list(i:j) /= 'all' .and. .not. any(optional_fields == list(i:j))) then
        word = list(i:j)
        return
      end if
    end do
  end function unknown_field

  !> The names of the first n kernels, comma separated.
  function all_kernels(n) result(s)
    integer, intent(in) :: n
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, n
      if (k > 1) s = s//', '
      s = s//trim(kernel_names(k))
    end do
  end function all_kernels

end module dpmpm_input_check
