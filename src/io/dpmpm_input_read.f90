!> Reading of the namelist input: the file as text, and the text into a config_t.
!>
!> load_text reads the file (on one rank); parse_input reads every group of the text with
!> Fortran namelist I/O from an internal file (one record per line) into local variables,
!> whose defaults are those of config_t, and keeps the values in cfg. What is wrong with
!> the text (an unknown group, a group given twice, a value that cannot be read, a string
!> longer than its variable, an unknown face or condition) goes to the problem list; the
!> values themselves are checked by dpmpm_input_check. The same text gives the same
!> config_t on every rank.
module dpmpm_input_read
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, region_cfg_t, load_cfg_t, max_poly, &
                          name_len, max_table, face_names, face_index, bc_free, bc_fixed, bc_roller, &
                          bc_names, fbc_default, fbc_drained, fbc_impermeable
  use dpmpm_input_problems, only: input_problems_t, ngroups, group_names, &
                                  repeatable, g_run, g_grid, g_shape, g_material, g_region, &
                                  g_boundary, g_load, g_output, g_benchmark, add_value, add_raw, &
                                  add_file_problem, place, lines_of, real_ok
  use dpmpm_strings, only: itoa, rtoa, rtoa_list, quote, lower
  use dpmpm_nml_text, only: nml_records, nml_echo, nml_names
  implicit none
  private
  public :: load_text, parse_input

  !> Length of the buffers that strings with a shorter limit are read into, so that a value
  !> longer than its limit is seen (and refused) instead of cut.
  integer, parameter :: long_len = 4096

contains

  !> Read the whole file as text (it is parsed on every rank and echoed into the output
  !> files); a file that cannot be read is a problem.
  subroutine load_text(filename, text, pb)
    character(len=*), intent(in) :: filename
    character(len=:), allocatable, intent(out) :: text
    type(input_problems_t), intent(inout) :: pb
    logical :: exists
    integer :: u, ios, n
    character(len=512) :: msg
    allocate (character(len=0) :: text)
    inquire (file=filename, exist=exists)
    if (.not. exists) then
      call add_file_problem(pb, 'file not found')
      return
    end if
    open (newunit=u, file=filename, status='old', action='read', access='stream', &
          form='unformatted', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call add_file_problem(pb, 'cannot open the file: '//trim(msg))
      return
    end if
    inquire (unit=u, size=n)
    if (n < 0) then
      call add_file_problem(pb, 'cannot tell the size of the file')
      close (u)
      return
    end if
    deallocate (text)
    allocate (character(len=n) :: text)
    if (n > 0) then
      read (u, iostat=ios, iomsg=msg) text
      if (ios /= 0) call add_file_problem(pb, 'cannot read the file: '//trim(msg))
    end if
    close (u)
    ! A UTF-8 byte order mark (some Windows editors write one) would hide the first group
    ! from scan_groups; the namelist reader skips it, so drop it here.
    if (len(text) >= 3) then
      if (text(1:3) == achar(239)//achar(187)//achar(191)) text = text(4:)
    end if
  end subroutine load_text

  !> Read every group of text into cfg (which holds the defaults): problems go to pb, and
  !> pb%read_ok tells which groups could be read. cfg%input_text is the text.
  subroutine parse_input(text, cfg, pb)
    character(len=*), intent(in) :: text
    type(config_t), intent(inout) :: cfg
    type(input_problems_t), intent(inout) :: pb
    character(len=:), allocatable :: records(:)
    logical :: ok(ngroups)
    integer :: g

    call scan_groups(pb, text)
    call split_records(text, records)
    ok = .true.
    cfg%echo = ''
    do g = 1, ngroups
      if (pb%count(g) == 0 .and. repeatable(g)) cycle
      if (.not. repeatable(g) .and. pb%count(g) > 1) then
        call add_file_problem(pb, '&'//trim(group_names(g))//' is given '// &
                              itoa(pb%count(g))//' times'//lines_of(pb, g)//': give it once')
        ok(g) = .false.
        cycle
      end if
      select case (g)
      case (g_run)
        call read_run(pb, records, cfg, ok(g))
      case (g_grid)
        call read_grid(pb, records, cfg, ok(g))
      case (g_shape)
        call read_shape(pb, records, cfg, ok(g))
      case (g_material)
        call read_materials(pb, records, cfg, ok(g))
      case (g_region)
        call read_regions(pb, records, cfg, ok(g))
      case (g_boundary)
        call read_boundaries(pb, records, cfg, ok(g))
      case (g_load)
        call read_loads(pb, records, cfg, ok(g))
      case (g_output)
        call read_output(pb, records, cfg, ok(g))
      case (g_benchmark)
        call read_benchmark(pb, records, cfg, ok(g))
      end select
    end do
    pb%read_ok = ok
    if (pb%count(g_grid) == 0) call add_file_problem(pb, &
      '&grid is missing: it is required (ndim, ncells, origin, length)')
    if (pb%count(g_material) == 0) call add_file_problem(pb, &
      'no &material group: at least one is required')
    if (pb%count(g_region) == 0) call add_file_problem(pb, &
      'no &region group: at least one is required')
    if (.not. allocated(cfg%materials)) allocate (cfg%materials(0))
    if (.not. allocated(cfg%regions)) allocate (cfg%regions(0))
    if (.not. allocated(cfg%loads)) allocate (cfg%loads(0))
    cfg%input_text = text
  end subroutine parse_input

  !> The lines of text as the records of an internal file (blank-padded to the longest line),
  !> split at new-line characters as the file's records were.
  subroutine split_records(text, records)
    character(len=*), intent(in) :: text
    character(len=:), allocatable, intent(out) :: records(:)
    integer :: pos, eol, n, w, k
    n = 0
    w = 1
    pos = 1
    do while (pos <= len(text))
      eol = next_eol(text, pos)
      n = n + 1
      w = max(w, eol - pos)
      pos = eol + 1
    end do
    allocate (character(len=w) :: records(n))
    pos = 1
    do k = 1, n
      eol = next_eol(text, pos)
      records(k) = text(pos:eol - 1)
      pos = eol + 1
    end do
  end subroutine split_records

  !> Position of the first new-line character of text at or after pos (len(text) + 1 if none).
  pure integer function next_eol(text, pos) result(eol)
    character(len=*), intent(in) :: text
    integer, intent(in) :: pos
    eol = index(text(pos:), new_line('a'))
    if (eol == 0) then
      eol = len(text) + 1
    else
      eol = pos + eol - 1
    end if
  end function next_eol

  !> The record where the namelist reader starts looking for occurrence k of group g: the
  !> first record for the first occurrence, else the line where the scan found it opening.
  pure integer function first_record(pb, g, k) result(r)
    type(input_problems_t), intent(in) :: pb
    integer, intent(in) :: g, k
    r = 1
    if (k > 1) r = max(1, pb%line_of(g, k))
  end function first_record

  !> Find the group openings: "&name" as the first word of a line. Unknown names are problems.
  subroutine scan_groups(pb, text)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: text
    integer :: pos, eol, line, i, j, g
    character(len=:), allocatable :: word
    pos = 1
    line = 0
    do while (pos <= len(text))
      line = line + 1
      eol = next_eol(text, pos)
      i = pos
      do while (i < eol)
        if (text(i:i) /= ' ' .and. text(i:i) /= char(9)) exit
        i = i + 1
      end do
      if (i < eol) then
        if (text(i:i) == '&') then
          j = i + 1
          do while (j < eol)
            if (.not. is_name_char(text(j:j))) exit
            j = j + 1
          end do
          word = lower(text(i + 1:j - 1))
          if (word /= 'end') then
            g = group_index(word)
            if (g == 0) then
              call add_file_problem(pb, '&'//word//' (line '//itoa(line)// &
                                    '): unknown group; the groups are '//all_groups())
            else
              call pb%opened(g, line)
            end if
          end if
        end if
      end if
      pos = eol + 1
    end do
  end subroutine scan_groups

  !> Record a namelist read error of occurrence k of group g, whose variables are names.
  subroutine read_error(pb, g, k, ios, msg, names)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, k, ios
    character(len=*), intent(in) :: msg, names
    character(len=*), parameter :: nomatch = 'Cannot match namelist object name '
    character(len=:), allocatable :: what, hint, word
    integer :: i
    logical :: is_name
    if (ios < 0) then
      what = 'the namelist reader did not find this group (is it terminated by "/"?)'
    else
      what = trim(msg)
    end if
    hint = ''
    if (index(msg, nomatch) == 1) then
      word = trim(msg(len(nomatch) + 1:))
      is_name = len(word) > 0
      if (is_name) is_name = scan(lower(word(1:1)), 'abcdefghijklmnopqrstuvwxyz') == 1
      do i = 1, len(word)
        if (.not. is_name_char(word(i:i))) is_name = .false.
      end do
      if (is_name) then
        hint = ' (no such variable)'
      else
        hint = ' (a value that does not fit the variable before it: a string or a fraction for'// &
               ' an integer, or more values than the variable holds)'
      end if
    end if
    call add_raw(pb, '&'//trim(group_names(g))//': cannot read the group: '//what//hint// &
                 '; the variables of &'//trim(group_names(g))//' are '//names// &
                 place(pb, g, k))
  end subroutine read_error

  !> Read &run.
  subroutine read_run(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=name_len) :: scheme, drag, pressure_smoothing
    character(len=long_len) :: name, restart
    real(wp) :: t_end, dt, cfl, flip, gravity(3), progress_seconds, drag_safety, max_wall_time
    real(wp) :: growth_limit, equilibrium_time, equilibrium_damping, cavitation_pressure
    logical :: porosity_gradient, remap_drag, given
    integer(i8) :: max_steps
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    namelist /run/ name, t_end, dt, cfl, max_steps, scheme, flip, gravity, progress_seconds, &
      drag, drag_safety, porosity_gradient, restart, max_wall_time, remap_drag, growth_limit, &
      equilibrium_time, equilibrium_damping, cavitation_pressure, pressure_smoothing
    restart = cfg%restart
    cavitation_pressure = cfg%cavitation_pressure; pressure_smoothing = cfg%pressure_smoothing
    equilibrium_time = cfg%equilibrium_time; equilibrium_damping = cfg%equilibrium_damping
    max_wall_time = cfg%max_wall_time
    remap_drag = cfg%remap_drag; growth_limit = cfg%growth_limit
    name = cfg%name; t_end = cfg%t_end; dt = cfg%dt; cfl = cfg%cfl; max_steps = cfg%max_steps
    scheme = cfg%scheme; flip = cfg%flip; gravity = cfg%gravity
    progress_seconds = cfg%progress_seconds
    drag = cfg%drag; drag_safety = cfg%drag_safety; porosity_gradient = cfg%porosity_gradient
    ios = 0
    if (pb%count(g_run) > 0) read (records, nml=run, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=run)
    ok = ios == 0
    if (.not. ok) then
      call read_error(pb, g_run, 1, ios, msg, nml_names(echo))
      return
    end if
    cfg%echo = cfg%echo//nml_echo(echo)
    ! Whether porosity_gradient was given: a second read from the other default keeps it
    ! only if the group sets it.
    cfg%porosity_gradient_given = .false.
    if (pb%count(g_run) > 0) then
      given = porosity_gradient
      porosity_gradient = .not. cfg%porosity_gradient
      read (records, nml=run, iostat=ios)
      cfg%porosity_gradient_given = porosity_gradient .eqv. given
      porosity_gradient = given
    end if
    call check_length(pb, g_run, 'name', name, len(cfg%name))
    call check_length(pb, g_run, 'restart', restart, len(cfg%restart))
    cfg%name = name; cfg%t_end = t_end; cfg%dt = dt; cfg%cfl = cfl; cfg%max_steps = max_steps
    cfg%scheme = scheme; cfg%flip = flip; cfg%gravity = gravity
    cfg%progress_seconds = progress_seconds
    cfg%drag = drag; cfg%drag_safety = drag_safety; cfg%porosity_gradient = porosity_gradient
    cfg%restart = restart
    cfg%max_wall_time = max_wall_time
    cfg%remap_drag = remap_drag; cfg%growth_limit = growth_limit
    cfg%equilibrium_time = equilibrium_time; cfg%equilibrium_damping = equilibrium_damping
    cfg%cavitation_pressure = cavitation_pressure; cfg%pressure_smoothing = pressure_smoothing
  end subroutine read_run

  !> Read &grid.
  subroutine read_grid(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    integer :: ndim, ncells(3), dims(3)
    real(wp) :: origin(3), length(3)
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    namelist /grid/ ndim, ncells, origin, length, dims
    ndim = cfg%ndim; ncells = cfg%ncells; origin = cfg%origin; length = cfg%length
    dims = cfg%dims
    ios = 0
    if (pb%count(g_grid) > 0) read (records, nml=grid, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=grid)
    ok = ios == 0
    if (.not. ok) then
      call read_error(pb, g_grid, 1, ios, msg, nml_names(echo))
      return
    end if
    cfg%echo = cfg%echo//nml_echo(echo)
    cfg%ndim = ndim; cfg%ncells = ncells; cfg%origin = origin; cfg%length = length
    cfg%dims = dims
  end subroutine read_grid

  !> Read &shape.
  subroutine read_shape(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=name_len) :: kernel, velocity_kernel, velocity_basis, quadrature, field_kernel, &
                               field_basis
    real(wp) :: velocity_radius, field_radius
    integer :: gauss_points
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    namelist /shape/ kernel, velocity_kernel, velocity_basis, velocity_radius, quadrature, &
      gauss_points, field_kernel, field_basis, field_radius
    kernel = cfg%kernel
    velocity_kernel = cfg%velocity_kernel; velocity_basis = cfg%velocity_basis
    velocity_radius = cfg%velocity_radius; quadrature = cfg%quadrature
    gauss_points = cfg%gauss_points; field_kernel = cfg%field_kernel
    field_basis = cfg%field_basis; field_radius = cfg%field_radius
    ios = 0
    if (pb%count(g_shape) > 0) read (records, nml=shape, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=shape)
    ok = ios == 0
    if (.not. ok) then
      call read_error(pb, g_shape, 1, ios, msg, nml_names(echo))
      return
    end if
    cfg%echo = cfg%echo//nml_echo(echo)
    cfg%kernel = kernel
    cfg%velocity_kernel = velocity_kernel; cfg%velocity_basis = velocity_basis
    cfg%velocity_radius = velocity_radius; cfg%quadrature = quadrature
    cfg%gauss_points = gauss_points; cfg%field_kernel = field_kernel
    cfg%field_basis = field_basis; cfg%field_radius = field_radius
  end subroutine read_shape

  !> Read every &material.
  subroutine read_materials(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(material_cfg_t) :: def
    type(material_cfg_t), allocatable :: list(:)
    integer :: id, k, n, ios
    character(len=name_len) :: model, dp_match, conductivity_law
    real(wp) :: density, youngs_modulus, poisson_ratio, bulk_modulus, conductivity
    real(wp) :: friction_angle, dilatancy_angle, cohesion, tensile_strength, cohesion_softening, &
                residual_cohesion, velocity(3)
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    namelist /material/ id, model, density, youngs_modulus, poisson_ratio, bulk_modulus, &
      conductivity, conductivity_law, friction_angle, dilatancy_angle, cohesion, &
      tensile_strength, cohesion_softening, residual_cohesion, dp_match, velocity
    allocate (list(pb%count(g_material)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      id = def%id; model = def%model; density = def%density
      youngs_modulus = def%youngs_modulus; poisson_ratio = def%poisson_ratio
      bulk_modulus = def%bulk_modulus; conductivity = def%conductivity
      conductivity_law = def%conductivity_law
      friction_angle = def%friction_angle; dilatancy_angle = def%dilatancy_angle
      cohesion = def%cohesion; tensile_strength = def%tensile_strength
      cohesion_softening = def%cohesion_softening; residual_cohesion = def%residual_cohesion
      dp_match = def%dp_match; velocity = def%velocity
      read (records(first_record(pb, g_material, k):), nml=material, iostat=ios, iomsg=msg)
      call nml_records(echo)
      write (echo, nml=material)
      if (ios /= 0) then
        call read_error(pb, g_material, k, ios, msg, nml_names(echo))
        ok = .false.
        exit
      end if
      cfg%echo = cfg%echo//nml_echo(echo)
      n = k
      list(k) = material_cfg_t(id=id, model=model, density=density, &
                               youngs_modulus=youngs_modulus, poisson_ratio=poisson_ratio, &
                               bulk_modulus=bulk_modulus, conductivity=conductivity, &
                               conductivity_law=conductivity_law, &
                               friction_angle=friction_angle, dilatancy_angle=dilatancy_angle, &
                               cohesion=cohesion, tensile_strength=tensile_strength, &
                               cohesion_softening=cohesion_softening, &
                               residual_cohesion=residual_cohesion, dp_match=dp_match, &
                               velocity=velocity)
    end do
    cfg%materials = list(1:n)
  end subroutine read_materials

  !> Read every &region.
  subroutine read_regions(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(region_cfg_t) :: def
    type(region_cfg_t), allocatable :: list(:)
    character(len=name_len) :: shape, phase, placement
    real(wp) :: lo(3), hi(3), poly_x(max_poly), poly_y(max_poly), velocity(3), stress(6), &
                porosity, stress_gradient(6, 3), pore_pressure, pore_pressure_gradient(3), k0, &
                surface, water_level, overburden
    logical :: geostatic
    integer :: npoly, material, fluid_material, ppc, seed, fluid_seed, k, n, ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    namelist /region/ shape, lo, hi, npoly, poly_x, poly_y, material, phase, fluid_material, &
      porosity, ppc, placement, seed, fluid_seed, velocity, stress, stress_gradient, pore_pressure, &
      pore_pressure_gradient, geostatic, k0, surface, water_level, overburden
    allocate (list(pb%count(g_region)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      shape = def%shape; lo = def%lo; hi = def%hi; npoly = def%npoly
      poly_x = def%poly(1, :); poly_y = def%poly(2, :); material = def%material
      phase = def%phase; ppc = def%ppc; placement = def%placement; seed = def%seed
      velocity = def%velocity; stress = def%stress; stress_gradient = def%stress_gradient
      pore_pressure = def%pore_pressure; pore_pressure_gradient = def%pore_pressure_gradient
      fluid_material = def%fluid_material; porosity = def%porosity; fluid_seed = def%fluid_seed
      geostatic = def%geostatic; k0 = def%k0; surface = def%surface
      water_level = def%water_level; overburden = def%overburden
      read (records(first_record(pb, g_region, k):), nml=region, iostat=ios, iomsg=msg)
      call nml_records(echo)
      write (echo, nml=region)
      if (ios /= 0) then
        call read_error(pb, g_region, k, ios, msg, nml_names(echo))
        ok = .false.
        exit
      end if
      cfg%echo = cfg%echo//nml_echo(echo)
      n = k
      list(k)%shape = shape; list(k)%lo = lo; list(k)%hi = hi; list(k)%npoly = npoly
      list(k)%poly(1, :) = poly_x; list(k)%poly(2, :) = poly_y; list(k)%material = material
      list(k)%phase = phase; list(k)%ppc = ppc; list(k)%placement = placement
      list(k)%seed = seed; list(k)%velocity = velocity; list(k)%stress = stress
      list(k)%fluid_material = fluid_material; list(k)%porosity = porosity
      list(k)%fluid_seed = fluid_seed; list(k)%stress_gradient = stress_gradient
      list(k)%pore_pressure = pore_pressure; list(k)%pore_pressure_gradient = pore_pressure_gradient
      list(k)%geostatic = geostatic; list(k)%k0 = k0; list(k)%surface = surface
      list(k)%water_level = water_level; list(k)%overburden = overburden
    end do
    cfg%regions = list(1:n)
  end subroutine read_regions

  !> Read every &boundary and set cfg%bc, cfg%fluid_bc, cfg%pore_pressure and
  !> cfg%pore_pressure_ramp; the names are
  !> checked here as they are not kept. A fluid condition left out (or 'default') stays
  !> fbc_default: the solver makes it drained at free faces and impermeable at fixed and
  !> roller faces.
  subroutine read_boundaries(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=name_len) :: face, condition, fluid
    real(wp) :: pore_pressure, pore_pressure_ramp, pore_pressure_gradient(3), friction
    logical :: seen(6), impermeable
    integer :: k, f, c, fc, ios, material, absorbing, j
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    character(len=:), allocatable :: why
    namelist /boundary/ face, condition, fluid, pore_pressure, pore_pressure_ramp, material, &
      pore_pressure_gradient, friction
    seen = .false.
    ok = .true.
    do k = 1, pb%count(g_boundary)
      face = ''; condition = bc_names(bc_free); fluid = ''; pore_pressure = 0.0_wp
      pore_pressure_ramp = 0.0_wp; material = 0; pore_pressure_gradient = 0.0_wp
      absorbing = 0; friction = 0.0_wp
      read (records(first_record(pb, g_boundary, k):), nml=boundary, iostat=ios, iomsg=msg)
      call nml_records(echo)
      write (echo, nml=boundary)
      if (ios /= 0) then
        call read_error(pb, g_boundary, k, ios, msg, nml_names(echo))
        ok = .false.
        exit
      end if
      cfg%echo = cfg%echo//nml_echo(echo)
      f = face_index(face)
      select case (trim(adjustl(condition)))
      case ('free')
        c = bc_free
      case ('fixed')
        c = bc_fixed
      case ('roller')
        c = bc_roller
      case ('absorbing')
        c = bc_free
        absorbing = absorbing_material(pb, k, cfg, material)
      case default
        c = -1
        call add_value(pb, g_boundary, k, 'condition', quote(condition), &
                       'the conditions are free, fixed, roller, absorbing')
      end select
      if (.not. real_ok(friction) .or. friction < 0.0_wp) then
        call add_value(pb, g_boundary, k, 'friction', rtoa(friction), &
                       'must be a finite Coulomb friction coefficient >= 0 (0: a smooth wall)')
      else if (friction > 0.0_wp .and. c /= bc_roller) then
        call add_value(pb, g_boundary, k, 'friction', rtoa(friction), &
                       "only a roller face takes a friction coefficient (condition = 'roller': "// &
                       'the wall holds the normal velocity, friction resists sliding along it)')
      else if (friction > 0.0_wp .and. trim(cfg%kernel) /= 'linear') then
        call add_value(pb, g_boundary, k, 'friction', rtoa(friction), "a rough wall needs "// &
                       "kernel = 'linear': with the mirror walls of B-splines part of the wall's "// &
                       'normal force acts through nodes inside the grid, and the friction taken '// &
                       'from the face nodes would be too low (doc/input.md, &boundary)')
      else if (friction > 0.0_wp .and. allocated(cfg%regions)) then
        if (any(cfg%regions%phase == 'fluid' .or. cfg%regions%phase == 'saturated')) &
          call add_value(pb, g_boundary, k, 'friction', rtoa(friction), 'rough walls act in '// &
                         'scenes of one phase (dry soil, solids); with fluid or saturated regions '// &
                         'the walls are smooth (friction = 0)')
      end if
      if (material /= 0 .and. trim(adjustl(condition)) /= 'absorbing') &
        call add_value(pb, g_boundary, k, 'material', itoa(material), &
                       "only an absorbing face takes a material (condition = 'absorbing')")
      select case (trim(adjustl(fluid)))
      case ('', 'default')
        fc = fbc_default
      case ('drained')
        fc = fbc_drained
      case ('impermeable')
        fc = fbc_impermeable
      case default
        fc = -1
        call add_value(pb, g_boundary, k, 'fluid', quote(fluid), 'the fluid conditions are '// &
                       'default (drained at a free face, impermeable at a fixed or roller '// &
                       'face), drained, impermeable')
      end select
      if (.not. all([(real_ok(pore_pressure_gradient(j)), j=1, 3)])) then
        call add_value(pb, g_boundary, k, 'pore_pressure_gradient', rtoa_list(pore_pressure_gradient), &
                       'must be finite numbers (Pa/m)')
      else if (any(pore_pressure_gradient /= 0.0_wp) .and. pore_pressure == 0.0_wp) then
        call add_value(pb, g_boundary, k, 'pore_pressure_gradient', rtoa_list(pore_pressure_gradient), &
                       'goes with the pore_pressure at x = 0 (a reservoir to height H along y: '// &
                       'pore_pressure = rho_f g H, pore_pressure_gradient = 0, -rho_f g)')
      end if
      if (.not. real_ok(pore_pressure)) then
        call add_value(pb, g_boundary, k, 'pore_pressure', rtoa(pore_pressure), &
                       'must be a finite number (Pa)')
      else if (pore_pressure /= 0.0_wp .and. c >= 0 .and. fc >= 0) then
        impermeable = fc == fbc_impermeable .or. (fc == fbc_default .and. c /= bc_free)
        if (impermeable) then
          if (fc == fbc_impermeable) then
            why = "fluid = 'impermeable'"
          else
            why = 'fluid left to its default at a '//trim(bc_names(c))//' face'
          end if
          call add_value(pb, g_boundary, k, 'pore_pressure', rtoa(pore_pressure), &
                         'only a drained face takes a pore pressure, and face '// &
                         trim(adjustl(face))//' is impermeable ('//why// &
                         "); set fluid = 'drained' or leave pore_pressure out")
        end if
      end if
      if (.not. real_ok(pore_pressure_ramp) .or. pore_pressure_ramp < 0.0_wp) then
        call add_value(pb, g_boundary, k, 'pore_pressure_ramp', rtoa(pore_pressure_ramp), &
                       'must be a finite time >= 0 (s); 0 applies pore_pressure at once')
      end if
      if (f == 0) then
        call add_value(pb, g_boundary, k, 'face', quote(face), 'the faces are '//all_faces())
      else if (.not. face_in_grid(f, cfg%ndim)) then
        call add_value(pb, g_boundary, k, 'face', quote(face), &
                       'the grid has no such face with ndim = '//itoa(cfg%ndim))
      else if (seen(f)) then
        call add_value(pb, g_boundary, k, 'face', quote(face), &
                       'this face has a &boundary already; give each face once')
      else if (c >= 0 .and. fc >= 0) then
        seen(f) = .true.
        cfg%bc(f) = c
        cfg%fluid_bc(f) = fc
        cfg%pore_pressure(f) = pore_pressure
        cfg%pore_pressure_ramp(f) = pore_pressure_ramp
        cfg%pore_pressure_gradient(:, f) = pore_pressure_gradient
        cfg%absorbing(f) = absorbing
        cfg%wall_friction(f) = friction
      end if
    end do
  end subroutine read_boundaries

  !> The material whose impedance the dashpots of an absorbing face (&boundary k) match:
  !> material when given, else the scene's only material of a body (a soil, or the fluid
  !> where there is no other); 0 with a problem added when there is no such choice.
  integer function absorbing_material(pb, k, cfg, material) result(id)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k, material
    type(config_t), intent(in) :: cfg
    integer :: m, nsolid
    id = 0
    if (.not. allocated(cfg%materials)) return
    if (material /= 0) then
      if (findloc(cfg%materials%id, material, dim=1) == 0) then
        call add_value(pb, g_boundary, k, 'material', itoa(material), &
                       'no &material has this id')
      else
        id = material
      end if
      return
    end if
    nsolid = count(cfg%materials%model /= 'fluid')
    do m = 1, size(cfg%materials)
      if (nsolid == 0 .or. cfg%materials(m)%model /= 'fluid') then
        if (id /= 0) then
          call add_value(pb, g_boundary, k, 'material', '(not given)', "an absorbing face "// &
                         "matches the impedance of one material: name it with material = id")
          id = 0
          return
        end if
        id = cfg%materials(m)%id
      end if
    end do
  end function absorbing_material

  !> Read every &load.
  subroutine read_loads(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(load_cfg_t) :: def
    type(load_cfg_t), allocatable :: list(:)
    character(len=name_len) :: face, time_function
    real(wp) :: traction(3), ramp_time, lo(3), hi(3), frequency, duration
    real(wp) :: times(max_table), factors(max_table)
    logical :: surface
    integer :: k, n, f, ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    namelist /load/ face, traction, ramp_time, lo, hi, time_function, frequency, duration, times, &
      factors, surface
    allocate (list(pb%count(g_load)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      face = ''; traction = def%traction; ramp_time = def%ramp_time; lo = def%lo; hi = def%hi
      time_function = def%time_function; frequency = def%frequency; duration = def%duration
      times = def%times; factors = def%factors; surface = def%surface
      read (records(first_record(pb, g_load, k):), nml=load, iostat=ios, iomsg=msg)
      call nml_records(echo)
      write (echo, nml=load)
      if (ios /= 0) then
        call read_error(pb, g_load, k, ios, msg, nml_names(echo))
        ok = .false.
        exit
      end if
      cfg%echo = cfg%echo//nml_echo(echo)
      f = face_index(face)
      if (f == 0) then
        call add_value(pb, g_load, k, 'face', quote(face), 'the faces are '//all_faces())
      else if (.not. face_in_grid(f, cfg%ndim)) then
        call add_value(pb, g_load, k, 'face', quote(face), &
                       'the grid has no such face with ndim = '//itoa(cfg%ndim))
      end if
      n = k
      list(k) = load_cfg_t(face=f, traction=traction, ramp_time=ramp_time, lo=lo, hi=hi, &
                           time_function=lower(time_function), frequency=frequency, &
                           duration=duration, times=times, factors=factors, surface=surface)
    end do
    cfg%loads = list(1:n)
  end subroutine read_loads

  !> Read &output.
  subroutine read_output(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=long_len) :: dir
    character(len=len(cfg%solid_fields)) :: solid_fields, fluid_fields
    real(wp) :: frame_interval, checkpoint_seconds
    integer :: diag_every, checkpoint_every, compression, ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    namelist /output/ dir, frame_interval, diag_every, checkpoint_every, checkpoint_seconds, &
      compression, solid_fields, fluid_fields
    dir = cfg%output_dir; frame_interval = cfg%frame_interval; diag_every = cfg%diag_every
    checkpoint_every = cfg%checkpoint_every; compression = cfg%compression
    checkpoint_seconds = cfg%checkpoint_seconds
    solid_fields = cfg%solid_fields; fluid_fields = cfg%fluid_fields
    ios = 0
    if (pb%count(g_output) > 0) read (records, nml=output, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=output)
    ok = ios == 0
    if (.not. ok) then
      call read_error(pb, g_output, 1, ios, msg, nml_names(echo))
      return
    end if
    cfg%echo = cfg%echo//nml_echo(echo)
    call check_length(pb, g_output, 'dir', dir, len(cfg%output_dir))
    cfg%output_dir = dir; cfg%frame_interval = frame_interval; cfg%diag_every = diag_every
    cfg%checkpoint_every = checkpoint_every; cfg%compression = compression
    cfg%checkpoint_seconds = checkpoint_seconds
    cfg%solid_fields = solid_fields; cfg%fluid_fields = fluid_fields
  end subroutine read_output

  !> Read &benchmark.
  subroutine read_benchmark(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=name_len) :: name
    real(wp) :: amplitude
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    namelist /benchmark/ name, amplitude
    name = cfg%benchmark; amplitude = cfg%amplitude
    ios = 0
    if (pb%count(g_benchmark) > 0) read (records, nml=benchmark, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=benchmark)
    ok = ios == 0
    if (.not. ok) then
      call read_error(pb, g_benchmark, 1, ios, msg, nml_names(echo))
      return
    end if
    cfg%echo = cfg%echo//nml_echo(echo)
    cfg%benchmark = name; cfg%amplitude = amplitude
  end subroutine read_benchmark

  !> A string read into a long buffer must fit the limit of its variable in config_t.
  subroutine check_length(pb, g, var, value, limit)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, limit
    character(len=*), intent(in) :: var, value
    character(len=:), allocatable :: count
    integer :: n
    n = len_trim(value)
    if (n <= limit) return
    count = itoa(n)
    if (n == len(value)) count = 'more than '//itoa(n - 1)
    call add_value(pb, g, 1, var, quote(value(1:40))//'...', 'is '//count// &
                   ' characters long: at most '//itoa(limit)//' are allowed')
  end subroutine check_length

  !> Index of a group name in group_names, 0 if unknown.
  pure integer function group_index(name) result(g)
    character(len=*), intent(in) :: name
    integer :: j
    g = 0
    do j = 1, ngroups
      if (name == group_names(j)) g = j
    end do
  end function group_index

  pure logical function is_name_char(c)
    character(len=1), intent(in) :: c
    is_name_char = scan(c, 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_') == 1
  end function is_name_char

  pure logical function face_in_grid(f, ndim)
    integer, intent(in) :: f, ndim
    face_in_grid = ndim < 1 .or. ndim > 3 .or. (f + 1)/2 <= ndim
  end function face_in_grid

  function all_groups() result(s)
    character(len=:), allocatable :: s
    integer :: g
    s = ''
    do g = 1, ngroups
      if (g > 1) s = s//', '
      s = s//'&'//trim(group_names(g))
    end do
  end function all_groups

  function all_faces() result(s)
    character(len=:), allocatable :: s
    integer :: f
    s = ''
    do f = 1, 6
      if (f > 1) s = s//', '
      s = s//face_names(f)
    end do
  end function all_faces

end module dpmpm_input_read
