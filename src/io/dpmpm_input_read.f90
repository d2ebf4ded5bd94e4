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
                          name_len, max_table, max_props, max_probes, face_names, face_index, bc_free, bc_fixed, bc_roller, &
                          bc_names, fbc_default, fbc_drained, fbc_impermeable, level_unset
  use dpmpm_input_problems, only: input_problems_t, ngroups, group_names, &
                                  repeatable, g_run, g_grid, g_shape, g_material, g_region, &
                                  g_boundary, g_load, g_output, g_benchmark, g_motion, add_value, add_raw, &
                                  add_file_problem, place, lines_of, real_ok, prop_unset, count_given
  use dpmpm_strings, only: itoa, rtoa, rtoa_list, quote, lower
  use dpmpm_nml_text, only: nml_records, nml_echo, nml_names
  use dpmpm_input_read_error, only: read_error, is_name_char
  use dpmpm_motion, only: absolute_beside
  implicit none
  private
  public :: load_text, parse_input, split_records, next_eol

  !> Length of the buffers that strings with a shorter limit are read into, so that a value
  !> longer than its limit is seen (and refused) instead of cut.
  integer, parameter :: long_len = 4096
  !> Largest Coulomb friction coefficient of a rough wall: tan 63.4 degrees.
  real(wp), parameter :: max_wall_friction = 2.0_wp

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
    call drop_byte_order_marks(text)
  end subroutine load_text

  !> A UTF-8 byte order mark (some Windows editors write one) would hide the group after it
  !> from scan_groups, and one in the middle of the file (two files joined) from the namelist
  !> reader as well: drop every mark that starts a line. It is invisible in an editor.
  subroutine drop_byte_order_marks(text)
    character(len=:), allocatable, intent(inout) :: text
    character(len=*), parameter :: bom = achar(239)//achar(187)//achar(191)
    integer :: i
    if (len(text) >= 3) then
      if (text(1:3) == bom) text = text(4:)
    end if
    do
      i = index(text, new_line('a')//bom)
      if (i == 0) exit
      text = text(1:i)//text(i + 4:)
    end do
  end subroutine drop_byte_order_marks

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
      case (g_motion)
        call read_motion(pb, records, cfg, ok(g))
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
    call lower_choices(cfg)
    cfg%input_text = text
  end subroutine parse_input

  !> The values that choose among names (a scheme, a model, a placement...) in lower case,
  !> as the group and variable names are not case sensitive: 'Points' is 'points'. Names of
  !> files (name, restart, dir) keep their case.
  subroutine lower_choices(cfg)
    type(config_t), intent(inout) :: cfg
    integer :: k
    cfg%scheme = lower(cfg%scheme)
    cfg%drag = lower(cfg%drag)
    cfg%pressure_smoothing = lower(cfg%pressure_smoothing)
    cfg%volumetric_smoothing = lower(cfg%volumetric_smoothing)
    cfg%balance = lower(cfg%balance)
    cfg%kernel = lower(cfg%kernel)
    cfg%velocity_kernel = lower(cfg%velocity_kernel)
    cfg%velocity_basis = lower(cfg%velocity_basis)
    cfg%quadrature = lower(cfg%quadrature)
    cfg%field_kernel = lower(cfg%field_kernel)
    cfg%field_basis = lower(cfg%field_basis)
    cfg%field_support = lower(cfg%field_support)
    cfg%solid_fields = lower(cfg%solid_fields)
    cfg%fluid_fields = lower(cfg%fluid_fields)
    cfg%benchmark = lower(cfg%benchmark)
    cfg%motion_format = lower(cfg%motion_format)
    cfg%motion_quantity = lower(cfg%motion_quantity)
    cfg%motion_baseline = lower(cfg%motion_baseline)
    do k = 1, size(cfg%materials)
      cfg%materials(k)%model = lower(cfg%materials(k)%model)
      cfg%materials(k)%conductivity_law = lower(cfg%materials(k)%conductivity_law)
      cfg%materials(k)%dp_match = lower(cfg%materials(k)%dp_match)
    end do
    do k = 1, size(cfg%regions)
      cfg%regions(k)%shape = lower(cfg%regions(k)%shape)
      cfg%regions(k)%phase = lower(cfg%regions(k)%phase)
      cfg%regions(k)%placement = lower(cfg%regions(k)%placement)
    end do
  end subroutine lower_choices

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
    allocate (character(len=w) :: records(max(n, 1)))
    records = ''
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
      j = i
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
      call misplaced_group(pb, text(pos:eol - 1), j - pos + 1, line)
      pos = eol + 1
    end do
  end subroutine scan_groups

  !> A '&' outside strings and comments at or after position from of line (number line of
  !> the file), after other characters: the namelist reader looks for a group only where a
  !> line starts with it and would skip this one without a word, so it is a problem.
  subroutine misplaced_group(pb, line, from, number)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: line
    integer, intent(in) :: from, number
    character(len=1) :: quote
    integer :: i, j
    quote = ' '
    do i = from, len(line)
      if (quote /= ' ') then
        if (line(i:i) == quote) quote = ' '
        cycle
      end if
      select case (line(i:i))
      case ("'", '"')
        quote = line(i:i)
      case ('!')
        return
      case ('&')
        j = i + 1
        do while (j <= len(line))
          if (.not. is_name_char(line(j:j))) exit
          j = j + 1
        end do
        call add_file_problem(pb, '&'//lower(line(i + 1:j - 1))//' (line '//itoa(number)// &
                              '): the group opens after other characters ('// &
                              quote_text(adjustl(line(1:i - 1)))//'); a group must open at the '// &
                              'start of its line, else it is not read')
        return
      end select
    end do
  end subroutine misplaced_group

  !> text in quotes, cut at 40 characters, without the characters that would not print.
  function quote_text(text) result(s)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, min(len_trim(text), 40)
      if (iachar(text(i:i)) >= 32 .and. iachar(text(i:i)) < 127) then
        s = s//text(i:i)
      else
        s = s//'?'
      end if
    end do
    s = "'"//s//"'"
  end function quote_text

  !> After the read of occurrence k of group g (status ios, message msg) and the write of
  !> its namelist into echo: ok tells whether it was read; if so, its echo is added to
  !> cfg_echo, else the error is a problem.
  subroutine took_group(pb, g, k, ios, msg, echo, cfg_echo, ok, records)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: g, k, ios
    character(len=*), intent(in) :: msg, echo(:), records(:)
    character(len=:), allocatable, intent(inout) :: cfg_echo
    logical, intent(out) :: ok
    ok = ios == 0
    if (ok) then
      cfg_echo = cfg_echo//nml_echo(echo)
    else
      call read_error(pb, g, k, ios, msg, echo, records)
    end if
  end subroutine took_group

  !> Read &run (its variables: dpmpm_vars_run.inc).
  subroutine read_run(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    include "dpmpm_vars_run_local.inc"
    include "dpmpm_vars_run_namelist.inc"
    logical :: given
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    include "dpmpm_vars_run_default.inc"
    ios = 0
    if (pb%count(g_run) > 0) read (records, nml=run, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=run)
    call took_group(pb, g_run, 1, ios, msg, echo, cfg%echo, ok, records)
    if (.not. ok) return
    ! Whether porosity_gradient was given: a second read from the other default keeps it
    ! only if the group sets it.
    cfg%porosity_gradient_given = .false.
    if (pb%count(g_run) > 0) then
      given = porosity_gradient
      porosity_gradient = .not. porosity_gradient
      read (records, nml=run, iostat=ios)
      cfg%porosity_gradient_given = porosity_gradient .eqv. given
      porosity_gradient = given
    end if
    associate (dest => cfg)
      include "dpmpm_vars_run_kept.inc"
    end associate
  end subroutine read_run

  !> Read &grid (its variables: dpmpm_vars_grid.inc).
  subroutine read_grid(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    include "dpmpm_vars_grid_local.inc"
    include "dpmpm_vars_grid_namelist.inc"
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    include "dpmpm_vars_grid_default.inc"
    ios = 0
    if (pb%count(g_grid) > 0) read (records, nml=grid, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=grid)
    call took_group(pb, g_grid, 1, ios, msg, echo, cfg%echo, ok, records)
    if (.not. ok) return
    associate (dest => cfg)
      include "dpmpm_vars_grid_kept.inc"
    end associate
  end subroutine read_grid

  !> Read &shape (its variables: dpmpm_vars_shape.inc).
  subroutine read_shape(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    include "dpmpm_vars_shape_local.inc"
    include "dpmpm_vars_shape_namelist.inc"
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    include "dpmpm_vars_shape_default.inc"
    ios = 0
    if (pb%count(g_shape) > 0) read (records, nml=shape, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=shape)
    call took_group(pb, g_shape, 1, ios, msg, echo, cfg%echo, ok, records)
    if (.not. ok) return
    associate (dest => cfg)
      include "dpmpm_vars_shape_kept.inc"
    end associate
  end subroutine read_shape

  !> Read every &material (its variables: dpmpm_vars_material.inc).
  subroutine read_materials(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(material_cfg_t), allocatable :: list(:)
    include "dpmpm_vars_material_local.inc"
    include "dpmpm_vars_material_namelist.inc"
    integer :: k, n, ios, nprops
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    allocate (list(pb%count(g_material)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      include "dpmpm_vars_material_default.inc"
      ! props not given stay at a mark, so that NPROPS is the count of those given
      umat_props = prop_unset
      read (records(first_record(pb, g_material, k):), nml=material, iostat=ios, iomsg=msg)
      nprops = count_given(umat_props)
      call nml_records(echo)
      write (echo, nml=material)
      if (ios == 0) call echo_given(echo, 'umat_props', umat_props(1:nprops))
      call took_group(pb, g_material, k, ios, msg, echo, cfg%echo, ok, records)
      if (.not. ok) exit
      n = k
      associate (dest => list(k))
        include "dpmpm_vars_material_kept.inc"
        dest%umat_nprops = nprops
      end associate
    end do
    cfg%materials = list(1:n)
  end subroutine read_materials

  !> Read every &region (its variables: dpmpm_vars_region.inc).
  subroutine read_regions(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(region_cfg_t), allocatable :: list(:)
    include "dpmpm_vars_region_local.inc"
    include "dpmpm_vars_region_namelist.inc"
    integer :: k, n, ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    allocate (list(pb%count(g_region)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      include "dpmpm_vars_region_default.inc"
      read (records(first_record(pb, g_region, k):), nml=region, iostat=ios, iomsg=msg)
      call nml_records(echo)
      write (echo, nml=region)
      call took_group(pb, g_region, k, ios, msg, echo, cfg%echo, ok, records)
      if (.not. ok) exit
      n = k
      associate (dest => list(k))
        include "dpmpm_vars_region_kept.inc"
        dest%poly(1, :) = poly_x
        dest%poly(2, :) = poly_y
        dest%line = pb%line_of(g_region, k)
      end associate
    end do
    cfg%regions = list(1:n)
  end subroutine read_regions

  !> Read every &boundary (its variables: dpmpm_vars_boundary.inc) and set cfg%bc, cfg%fluid_bc, cfg%pore_pressure and
  !> cfg%pore_pressure_ramp; the names are
  !> checked here as they are not kept. A fluid condition left out (or 'default') stays
  !> fbc_default: the solver makes it drained at free faces and impermeable at fixed and
  !> roller faces.
  subroutine read_boundaries(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    include "dpmpm_vars_boundary_local.inc"
    include "dpmpm_vars_boundary_namelist.inc"
    logical :: seen(6), impermeable
    integer :: k, f, c, fc, ios, absorbing, j
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    character(len=:), allocatable :: why
    seen = .false.
    ok = .true.
    do k = 1, pb%count(g_boundary)
      include "dpmpm_vars_boundary_default.inc"
      absorbing = 0
      read (records(first_record(pb, g_boundary, k):), nml=boundary, iostat=ios, iomsg=msg)
      call nml_records(echo)
      write (echo, nml=boundary)
      call took_group(pb, g_boundary, k, ios, msg, echo, cfg%echo, ok, records)
      if (.not. ok) exit
      face = lower(face)
      condition = lower(condition)
      fluid = lower(fluid)
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
      case ('tied')
        c = bc_free
      case default
        c = -1
        call add_value(pb, g_boundary, k, 'condition', quote(condition), &
                       'the conditions are free, fixed, roller, absorbing, tied')
      end select
      if (.not. real_ok(friction, ge=0.0_wp, le=max_wall_friction)) then
        call add_value(pb, g_boundary, k, 'friction', rtoa(friction), &
                       'must be a finite Coulomb friction coefficient in [0, '// &
                       rtoa(max_wall_friction)//']: mu = tan(delta) of a wall friction angle '// &
                       'delta up to 63 degrees, above the friction angle of any soil (0: a '// &
                       "smooth wall; a wall that holds the body is condition = 'fixed')")
      else if (friction > 0.0_wp .and. c /= bc_roller) then
        call add_value(pb, g_boundary, k, 'friction', rtoa(friction), &
                       "only a roller face takes a friction coefficient (condition = 'roller': "// &
                       'the wall holds the normal velocity, friction resists sliding along it)')
      else if (friction > 0.0_wp .and. trim(cfg%kernel) /= 'linear') then
        call add_value(pb, g_boundary, k, 'friction', rtoa(friction), "a rough wall needs "// &
                       "kernel = 'linear': with the mirror walls of B-splines part of the wall's "// &
                       'normal force acts through nodes inside the grid, and the friction taken '// &
                       'from the face nodes would be too low (doc/input.md, &boundary)')
      end if
      if (.not. lift_off .and. .not. (friction > 0.0_wp)) &
        call add_value(pb, g_boundary, k, 'lift_off', '.false.', &
                       'only a rough wall (friction > 0) lets go of nodes or holds them; '// &
                       'leave lift_off out')
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
      if (.not. all([(real_ok(opening_lo(j)) .and. real_ok(opening_hi(j)), j=1, 3)])) &
        call add_value(pb, g_boundary, k, 'opening_lo', rtoa_list(opening_lo)//' .. '// &
                       rtoa_list(opening_hi), 'the corners of an opening must be finite numbers (m)')
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
        cfg%wall_lift_off(f) = lift_off
        cfg%tied(f) = trim(adjustl(condition)) == 'tied'
        cfg%has_opening(f) = any(opening_lo /= 0.0_wp) .or. any(opening_hi /= 0.0_wp)
        cfg%opening_lo(:, f) = opening_lo
        cfg%opening_hi(:, f) = opening_hi
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

  !> Read every &load (its variables: dpmpm_vars_load.inc).
  subroutine read_loads(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(load_cfg_t), allocatable :: list(:)
    include "dpmpm_vars_load_local.inc"
    include "dpmpm_vars_load_namelist.inc"
    real(wp), parameter :: factor_unset = -huge(1.0_wp)
    integer :: k, n, ios, j, nfactors
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    allocate (list(pb%count(g_load)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      include "dpmpm_vars_load_default.inc"
      ! factors not given stay at a mark, so that their count can be held against the times
      factors = factor_unset
      read (records(first_record(pb, g_load, k):), nml=load, iostat=ios, iomsg=msg)
      nfactors = 0
      do j = 1, size(factors)
        if (factors(j) /= factor_unset) nfactors = j
      end do
      where (factors == factor_unset) factors = 0.0_wp
      call nml_records(echo)
      write (echo, nml=load)
      if (ios == 0) call echo_given(echo, 'factors', factors(1:nfactors))
      call took_group(pb, g_load, k, ios, msg, echo, cfg%echo, ok, records)
      if (.not. ok) exit
      n = k
      associate (dest => list(k))
        include "dpmpm_vars_load_kept.inc"
        dest%time_function = lower(time_function)
        dest%nfactors = nfactors
        dest%face = face_index(lower(face))
        if (dest%face == 0) then
          call add_value(pb, g_load, k, 'face', quote(face), 'the faces are '//all_faces())
        else if (.not. face_in_grid(dest%face, cfg%ndim)) then
          call add_value(pb, g_load, k, 'face', quote(face), &
                         'the grid has no such face with ndim = '//itoa(cfg%ndim))
        end if
      end associate
    end do
    cfg%loads = list(1:n)
  end subroutine read_loads

  !> In the group written in echo, variable name (an array) with only the values given, so
  !> that the echo reads back with as many as the input had (the zeros after them would
  !> count as given); left out when none was.
  subroutine echo_given(echo, name, values)
    character(len=*), intent(inout) :: echo(:)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: values(:)
    integer :: k, eq
    do k = 1, size(echo)
      eq = index(echo(k), '=')
      if (eq == 0) cycle
      if (lower(trim(adjustl(echo(k) (1:eq - 1)))) /= name) cycle
      echo(k) = ''
      if (size(values) > 0) echo(k) = name//' = '//rtoa_list(values)
      return
    end do
  end subroutine echo_given

  !> Read &output (its variables: dpmpm_vars_output.inc).
  subroutine read_output(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    include "dpmpm_vars_output_local.inc"
    include "dpmpm_vars_output_namelist.inc"
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    include "dpmpm_vars_output_default.inc"
    ios = 0
    if (pb%count(g_output) > 0) read (records, nml=output, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=output)
    call took_group(pb, g_output, 1, ios, msg, echo, cfg%echo, ok, records)
    if (.not. ok) return
    associate (dest => cfg)
      include "dpmpm_vars_output_kept.inc"
    end associate
  end subroutine read_output

  !> Read &benchmark (its variables: dpmpm_vars_benchmark.inc).
  subroutine read_benchmark(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    include "dpmpm_vars_benchmark_local.inc"
    include "dpmpm_vars_benchmark_namelist.inc"
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    include "dpmpm_vars_benchmark_default.inc"
    ios = 0
    if (pb%count(g_benchmark) > 0) read (records, nml=benchmark, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=benchmark)
    call took_group(pb, g_benchmark, 1, ios, msg, echo, cfg%echo, ok, records)
    if (.not. ok) return
    associate (dest => cfg)
      include "dpmpm_vars_benchmark_kept.inc"
    end associate
  end subroutine read_benchmark

  !> Read &motion (its variables: dpmpm_vars_motion.inc); the files it names are read after
  !> the checks (dpmpm_motion).
  subroutine read_motion(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=long_len) :: given(3)
    include "dpmpm_vars_motion_local.inc"
    include "dpmpm_vars_motion_namelist.inc"
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    include "dpmpm_vars_motion_default.inc"
    ios = 0
    if (pb%count(g_motion) > 0) read (records, nml=motion, iostat=ios, iomsg=msg)
    ! the echo names the files by their absolute paths, so that it reads back from any
    ! folder; the configuration keeps them as given (messages quote them so)
    given = [character(len=long_len) :: file_x, file_y, file_z]
    file_x = absolute_beside(pb%file, trim(file_x))
    file_y = absolute_beside(pb%file, trim(file_y))
    file_z = absolute_beside(pb%file, trim(file_z))
    call nml_records(echo)
    write (echo, nml=motion)
    file_x = given(1)
    file_y = given(2)
    file_z = given(3)
    call took_group(pb, g_motion, 1, ios, msg, echo, cfg%echo, ok, records)
    if (.not. ok) return
    associate (dest => cfg)
      include "dpmpm_vars_motion_kept.inc"
    end associate
  end subroutine read_motion

  !> A string read into a long buffer (a TEXT variable of &group) must fit the limit of its
  !> component in config_t.
  subroutine check_length(pb, group, var, value, limit)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: group, var, value
    integer, intent(in) :: limit
    character(len=:), allocatable :: count
    integer :: n
    n = len_trim(value)
    if (n <= limit) return
    count = itoa(n)
    if (n == len(value)) count = 'more than '//itoa(n - 1)
    call add_value(pb, group_index(group), 1, var, quote(value(1:40))//'...', 'is '//count// &
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
