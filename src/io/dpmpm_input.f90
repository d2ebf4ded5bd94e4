!> Reading and checking of the namelist input file.
!>
!> Rank 0 reads the whole file, finds where each group opens, reads every group
!> with Fortran namelist I/O into local variables (the defaults are those of
!> config_t), checks all values and collects every problem found. If there is
!> any, rank 0 prints them all, one per line, and every rank stops cleanly with
!> exit code 2; otherwise the resolved config_t is broadcast to all ranks.
module dpmpm_input
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
  use dpmpm_kinds, only: wp, i8, mpi_wp, mpi_i8
  use dpmpm_config, only: field_listed, optional_fields
  use dpmpm_config, only: config_t, material_cfg_t, region_cfg_t, load_cfg_t, max_poly, &
                          name_len, face_names, face_index, bc_free, bc_fixed, bc_roller, &
                          bc_names, fbc_default, fbc_drained, fbc_impermeable, fbc_names
  use dpmpm_kernels, only: kernel_from_name, kernel_names, ngrid_kernels, is_grid_kernel
  use dpmpm_mls, only: basis_from_name
  use dpmpm_shape_plan, only: shape_plan_t, max_gauss
  use dpmpm_plasticity, only: plastic_params_t, plastic_setup, softening_limit, dp_match_names, &
                              dp_plane_strain, surface_mohr_coulomb, surface_drucker_prager
  use dpmpm_error, only: clean_stop
  use dpmpm_strings, only: itoa, i8toa, next_word
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Comm_size, MPI_Bcast, MPI_Dims_create, &
                     MPI_INTEGER, MPI_CHARACTER, MPI_LOGICAL
  implicit none
  private
  public :: read_input, print_config

  integer, parameter :: g_run = 1, g_grid = 2, g_shape = 3, g_material = 4, g_region = 5, &
                        g_boundary = 6, g_load = 7, g_output = 8, g_benchmark = 9, ngroups = 9
  character(len=9), parameter :: group_names(ngroups) = [character(len=9) :: 'run', 'grid', &
    'shape', 'material', 'region', 'boundary', 'load', 'output', 'benchmark']
  logical, parameter :: repeatable(ngroups) = [.false., .false., .false., .true., .true., &
                                               .true., .true., .false., .false.]
  !> The variables of each group, for messages about a group that cannot be read.
  character(len=*), parameter :: group_vars(ngroups) = [character(len=192) :: &
    'name, t_end, dt, cfl, max_steps, scheme, flip, gravity, progress_seconds, drag, '// &
    'drag_safety, porosity_gradient, restart, max_wall_time, remap_drag, growth_limit', &
    'ndim, ncells, origin, length, dims', &
    'kernel, velocity_kernel, velocity_basis, velocity_radius, quadrature, gauss_points, '// &
    'field_kernel, field_basis, field_radius', &
    'id, model, density, youngs_modulus, poisson_ratio, bulk_modulus, conductivity, '// &
    'friction_angle, dilatancy_angle, cohesion, tensile_strength, cohesion_softening, '// &
    'residual_cohesion, dp_match', &
    'shape, lo, hi, npoly, poly_x, poly_y, material, phase, fluid_material, porosity, ppc, '// &
    'placement, seed, fluid_seed, velocity, stress, stress_gradient, pore_pressure, '// &
    'pore_pressure_gradient', &
    'face, condition, fluid, pore_pressure, pore_pressure_ramp', &
    'face, traction, ramp_time', &
    'dir, frame_interval, diag_every, checkpoint_every, checkpoint_seconds, compression, '// &
    'solid_fields, fluid_fields', &
    'name, amplitude']
  character(len=*), parameter :: err_prefix = 'dpmpm: input error: '
  !> Length of the buffers that strings with a shorter limit are read into, so that a value
  !> longer than its limit is seen (and refused) instead of cut.
  integer, parameter :: long_len = 4096

  !> A string of any length, to collect messages.
  type :: text_t
    character(len=:), allocatable :: s
  end type text_t

  !> Rank 0's state while reading one file: where each group opens and the problems found.
  type :: reader_t
    character(len=:), allocatable :: file
    integer :: count(ngroups) = 0
    integer :: nopen = 0
    integer, allocatable :: open_group(:), open_line(:)
    integer :: nprob = 0
    type(text_t), allocatable :: prob(:)
  end type reader_t

  !> Broadcast from rank 0 of a value or an array of values.
  interface bcast
    module procedure bcast_int, bcast_int_1d, bcast_i8, bcast_real, bcast_real_1d, &
      bcast_real_2d, bcast_str, bcast_logical
  end interface bcast

contains

  ! ---------------------------------------------------------------------------------------------
  ! Public procedures
  ! ---------------------------------------------------------------------------------------------

  !> Read, check and broadcast the input file (collective over comm). On any problem rank 0
  !> prints all of them to stderr and every rank stops with exit code 2.
  !> With restart_latest (the command line's --restart) the input's &run restart is taken
  !> as 'latest': continue from <dir>/<name>.ckpt.h5 when it exists, else start afresh.
  subroutine read_input(filename, comm, cfg, restart_latest)
    character(len=*), intent(in) :: filename
    type(MPI_Comm), intent(in) :: comm
    type(config_t), intent(out) :: cfg
    logical, intent(in), optional :: restart_latest
    integer :: rank, nranks, nprob, k
    type(reader_t) :: rd
    logical :: latest

    call MPI_Comm_rank(comm, rank)
    call MPI_Comm_size(comm, nranks)
    latest = .false.
    if (present(restart_latest)) latest = restart_latest
    nprob = 0
    if (rank == 0) then
      call read_and_check(rd, filename, nranks, cfg, latest)
      nprob = rd%nprob
    end if
    call MPI_Bcast(nprob, 1, MPI_INTEGER, 0, comm)
    if (nprob > 0) then
      if (rank == 0) then
        do k = 1, rd%nprob
          write (error_unit, '(a)') rd%prob(k)%s
        end do
        flush (error_unit)
      end if
      call clean_stop(2)
    end if
    call bcast_config(cfg, comm)
    cfg%input_file = filename
  end subroutine read_input

  !> Print every resolved parameter, defaults included, as namelist groups that can be read
  !> back as input.
  subroutine print_config(cfg, unit)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: unit
    integer :: k, f
    write (unit, '(a)') '! dpmpm: resolved parameters of '//trim(cfg%input_file)
    write (unit, '(a)') '&run'
    call put_s(unit, 'name', cfg%name)
    call put_r(unit, 't_end', [cfg%t_end])
    call put_r(unit, 'dt', [cfg%dt])
    call put_r(unit, 'cfl', [cfg%cfl])
    write (unit, '(a,i0)') '  max_steps = ', cfg%max_steps
    call put_s(unit, 'scheme', cfg%scheme)
    call put_r(unit, 'flip', [cfg%flip])
    call put_r(unit, 'gravity', cfg%gravity)
    call put_r(unit, 'progress_seconds', [cfg%progress_seconds])
    call put_s(unit, 'drag', cfg%drag)
    call put_r(unit, 'drag_safety', [cfg%drag_safety])
    call put_l(unit, 'porosity_gradient', cfg%porosity_gradient)
    call put_l(unit, 'remap_drag', cfg%remap_drag)
    call put_r(unit, 'growth_limit', [cfg%growth_limit])
    call put_s(unit, 'restart', cfg%restart)
    call put_r(unit, 'max_wall_time', [cfg%max_wall_time])
    write (unit, '(a)') '/', '&grid'
    call put_i(unit, 'ndim', [cfg%ndim])
    call put_i(unit, 'ncells', cfg%ncells)
    call put_r(unit, 'origin', cfg%origin)
    call put_r(unit, 'length', cfg%length)
    call put_i(unit, 'dims', cfg%dims)
    write (unit, '(a)') '/', '&shape'
    call put_s(unit, 'kernel', cfg%kernel)
    call put_s(unit, 'velocity_kernel', cfg%velocity_kernel)
    call put_s(unit, 'velocity_basis', cfg%velocity_basis)
    call put_r(unit, 'velocity_radius', [cfg%velocity_radius])
    call put_s(unit, 'quadrature', cfg%quadrature)
    call put_i(unit, 'gauss_points', [cfg%gauss_points])
    call put_s(unit, 'field_kernel', cfg%field_kernel)
    call put_s(unit, 'field_basis', cfg%field_basis)
    call put_r(unit, 'field_radius', [cfg%field_radius])
    write (unit, '(a)') '/'
    if (allocated(cfg%materials)) then
      do k = 1, size(cfg%materials)
        associate (m => cfg%materials(k))
          write (unit, '(a)') '&material'
          call put_i(unit, 'id', [m%id])
          call put_s(unit, 'model', m%model)
          call put_r(unit, 'density', [m%density])
          call put_r(unit, 'youngs_modulus', [m%youngs_modulus])
          call put_r(unit, 'poisson_ratio', [m%poisson_ratio])
          call put_r(unit, 'bulk_modulus', [m%bulk_modulus])
          call put_r(unit, 'conductivity', [m%conductivity])
          if (m%model == 'mohr_coulomb' .or. m%model == 'drucker_prager') then
            call put_r(unit, 'friction_angle', [m%friction_angle])
            call put_r(unit, 'dilatancy_angle', [m%dilatancy_angle])
            call put_r(unit, 'cohesion', [m%cohesion])
            call put_r(unit, 'tensile_strength', [m%tensile_strength])
            call put_r(unit, 'cohesion_softening', [m%cohesion_softening])
            call put_r(unit, 'residual_cohesion', [m%residual_cohesion])
            if (m%model == 'drucker_prager') call put_s(unit, 'dp_match', m%dp_match)
          end if
          write (unit, '(a)') '/'
        end associate
      end do
    end if
    if (allocated(cfg%regions)) then
      do k = 1, size(cfg%regions)
        associate (r => cfg%regions(k))
          write (unit, '(a)') '&region'
          call put_s(unit, 'shape', r%shape)
          if (r%shape == 'polygon') then
            call put_i(unit, 'npoly', [r%npoly])
            call put_r(unit, 'poly_x', r%poly(1, 1:r%npoly))
            call put_r(unit, 'poly_y', r%poly(2, 1:r%npoly))
          else
            call put_r(unit, 'lo', r%lo)
            call put_r(unit, 'hi', r%hi)
          end if
          call put_i(unit, 'material', [r%material])
          call put_s(unit, 'phase', r%phase)
          call put_i(unit, 'fluid_material', [r%fluid_material])
          call put_r(unit, 'porosity', [r%porosity])
          call put_i(unit, 'ppc', [r%ppc])
          call put_s(unit, 'placement', r%placement)
          call put_i(unit, 'seed', [r%seed])
          call put_i(unit, 'fluid_seed', [r%fluid_seed])
          call put_r(unit, 'velocity', r%velocity)
          call put_r(unit, 'stress', r%stress)
          call put_r(unit, 'stress_gradient', reshape(r%stress_gradient, [18]))
          call put_r(unit, 'pore_pressure', [r%pore_pressure])
          call put_r(unit, 'pore_pressure_gradient', r%pore_pressure_gradient)
          write (unit, '(a)') '/'
        end associate
      end do
    end if
    do f = 1, 2*max(1, min(3, cfg%ndim))
      write (unit, '(a)') '&boundary'
      call put_s(unit, 'face', face_names(f))
      call put_s(unit, 'condition', bc_names(cfg%bc(f)))
      call put_s(unit, 'fluid', fbc_names(cfg%fluid_bc(f)))
      call put_r(unit, 'pore_pressure', [cfg%pore_pressure(f)])
      call put_r(unit, 'pore_pressure_ramp', [cfg%pore_pressure_ramp(f)])
      write (unit, '(a)') '/'
    end do
    if (allocated(cfg%loads)) then
      do k = 1, size(cfg%loads)
        write (unit, '(a)') '&load'
        call put_s(unit, 'face', face_names(max(1, cfg%loads(k)%face)))
        call put_r(unit, 'traction', cfg%loads(k)%traction)
        call put_r(unit, 'ramp_time', [cfg%loads(k)%ramp_time])
        write (unit, '(a)') '/'
      end do
    end if
    write (unit, '(a)') '&output'
    call put_s(unit, 'dir', cfg%output_dir)
    call put_r(unit, 'frame_interval', [cfg%frame_interval])
    call put_i(unit, 'diag_every', [cfg%diag_every])
    call put_i(unit, 'checkpoint_every', [cfg%checkpoint_every])
    call put_r(unit, 'checkpoint_seconds', [cfg%checkpoint_seconds])
    call put_i(unit, 'compression', [cfg%compression])
    call put_s(unit, 'solid_fields', cfg%solid_fields)
    call put_s(unit, 'fluid_fields', cfg%fluid_fields)
    write (unit, '(a)') '/', '&benchmark'
    call put_s(unit, 'name', cfg%benchmark)
    call put_r(unit, 'amplitude', [cfg%amplitude])
    write (unit, '(a)') '/'
  end subroutine print_config

  ! ---------------------------------------------------------------------------------------------
  ! Reading on rank 0
  ! ---------------------------------------------------------------------------------------------

  !> Rank 0: read the file into cfg and collect all problems in rd.
  subroutine read_and_check(rd, filename, nranks, cfg, latest)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: filename
    integer, intent(in) :: nranks
    type(config_t), intent(inout) :: cfg
    logical, intent(in) :: latest
    integer :: u, ios, g
    logical :: ok(ngroups)
    character(len=512) :: msg

    rd%file = trim(filename)
    allocate (rd%prob(8))
    call load_text(rd, filename, cfg%input_text)
    if (rd%nprob > 0) return
    call scan_groups(rd, cfg%input_text)

    open (newunit=u, file=filename, status='old', action='read', form='formatted', &
          iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call add_file_problem(rd, 'cannot open the file: '//trim(msg))
      return
    end if
    ok = .true.
    do g = 1, ngroups
      if (rd%count(g) == 0) cycle
      if (.not. repeatable(g) .and. rd%count(g) > 1) then
        call add_file_problem(rd, '&'//trim(group_names(g))//' is given '// &
                              itoa(rd%count(g))//' times'//lines_of(rd, g)//': give it once')
        ok(g) = .false.
        cycle
      end if
      rewind (u)
      select case (g)
      case (g_run)
        call read_run(rd, u, cfg, ok(g))
      case (g_grid)
        call read_grid(rd, u, cfg, ok(g))
      case (g_shape)
        call read_shape(rd, u, cfg, ok(g))
      case (g_material)
        call read_materials(rd, u, cfg, ok(g))
      case (g_region)
        call read_regions(rd, u, cfg, ok(g))
      case (g_boundary)
        call read_boundaries(rd, u, cfg, ok(g))
      case (g_load)
        call read_loads(rd, u, cfg, ok(g))
      case (g_output)
        call read_output(rd, u, cfg, ok(g))
      case (g_benchmark)
        call read_benchmark(rd, u, cfg, ok(g))
      end select
    end do
    close (u)
    if (rd%count(g_grid) == 0) call add_file_problem(rd, &
      '&grid is missing: it is required (ndim, ncells, origin, length)')
    if (rd%count(g_material) == 0) call add_file_problem(rd, &
      'no &material group: at least one is required')
    if (rd%count(g_region) == 0) call add_file_problem(rd, &
      'no &region group: at least one is required')
    if (.not. allocated(cfg%materials)) allocate (cfg%materials(0))
    if (.not. allocated(cfg%regions)) allocate (cfg%regions(0))
    if (.not. allocated(cfg%loads)) allocate (cfg%loads(0))
    if (latest) cfg%restart = 'latest'
    call resolve_latest(cfg)
    call check_config(rd, cfg, nranks, ok)
  end subroutine read_and_check

  !> restart = 'latest': the run's own checkpoint <dir>/<name>.ckpt.h5 when it exists (the
  !> run continues), else none (the run starts at t = 0); said on standard output. This
  !> lets a chain of batch jobs run the same input again and again.
  subroutine resolve_latest(cfg)
    type(config_t), intent(inout) :: cfg
    character(len=:), allocatable :: path
    logical :: exists
    if (trim(cfg%restart) /= 'latest') return
    path = trim(cfg%output_dir)//'/'//trim(cfg%name)//'.ckpt.h5'
    inquire (file=path, exist=exists)
    if (exists) then
      cfg%restart = path
      write (output_unit, '(a)') 'dpmpm: restart = ''latest'': continuing from '//path
    else
      cfg%restart = ''
      write (output_unit, '(a)') 'dpmpm: restart = ''latest'': no checkpoint '//path// &
        ' yet, starting at t = 0'
    end if
    flush (output_unit)
  end subroutine resolve_latest

  !> Read the whole file as text (it is echoed into the output files).
  subroutine load_text(rd, filename, text)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: filename
    character(len=:), allocatable, intent(out) :: text
    logical :: exists
    integer :: u, ios, n
    character(len=512) :: msg
    allocate (character(len=0) :: text)
    inquire (file=filename, exist=exists)
    if (.not. exists) then
      call add_file_problem(rd, 'file not found')
      return
    end if
    open (newunit=u, file=filename, status='old', action='read', access='stream', &
          form='unformatted', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call add_file_problem(rd, 'cannot open the file: '//trim(msg))
      return
    end if
    inquire (unit=u, size=n)
    if (n < 0) then
      call add_file_problem(rd, 'cannot tell the size of the file')
      close (u)
      return
    end if
    deallocate (text)
    allocate (character(len=n) :: text)
    if (n > 0) then
      read (u, iostat=ios, iomsg=msg) text
      if (ios /= 0) call add_file_problem(rd, 'cannot read the file: '//trim(msg))
    end if
    close (u)
    ! A UTF-8 byte order mark (some Windows editors write one) would hide the first group
    ! from scan_groups; the namelist reader skips it, so drop it here.
    if (len(text) >= 3) then
      if (text(1:3) == achar(239)//achar(187)//achar(191)) text = text(4:)
    end if
  end subroutine load_text

  !> Find the group openings: "&name" as the first word of a line. Unknown names are problems.
  subroutine scan_groups(rd, text)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: text
    integer :: pos, eol, line, i, j, g, cap
    character(len=:), allocatable :: word
    integer, allocatable :: tmp(:)
    cap = 16
    allocate (rd%open_group(cap), rd%open_line(cap))
    pos = 1
    line = 0
    do while (pos <= len(text))
      line = line + 1
      eol = index(text(pos:), new_line('a'))
      if (eol == 0) then
        eol = len(text) + 1
      else
        eol = pos + eol - 1
      end if
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
              call add_file_problem(rd, '&'//word//' (line '//itoa(line)// &
                                    '): unknown group; the groups are '//all_groups())
            else
              if (rd%nopen == cap) then
                cap = 2*cap
                allocate (tmp(cap))
                tmp(1:rd%nopen) = rd%open_group(1:rd%nopen)
                call move_alloc(tmp, rd%open_group)
                allocate (tmp(cap))
                tmp(1:rd%nopen) = rd%open_line(1:rd%nopen)
                call move_alloc(tmp, rd%open_line)
              end if
              rd%nopen = rd%nopen + 1
              rd%open_group(rd%nopen) = g
              rd%open_line(rd%nopen) = line
              rd%count(g) = rd%count(g) + 1
            end if
          end if
        end if
      end if
      pos = eol + 1
    end do
  end subroutine scan_groups

  !> Record a namelist read error of occurrence k of group g.
  subroutine read_error(rd, g, k, ios, msg)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: g, k, ios
    character(len=*), intent(in) :: msg
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
    call add_raw(rd, '&'//trim(group_names(g))//': cannot read the group: '//what//hint// &
                 '; the variables of &'//trim(group_names(g))//' are '//trim(group_vars(g))// &
                 place(rd, g, k))
  end subroutine read_error

  !> Read &run.
  subroutine read_run(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=name_len) :: scheme, drag
    character(len=long_len) :: name, restart
    real(wp) :: t_end, dt, cfl, flip, gravity(3), progress_seconds, drag_safety, max_wall_time
    real(wp) :: growth_limit
    logical :: porosity_gradient, remap_drag
    integer(i8) :: max_steps
    integer :: ios
    character(len=512) :: msg
    namelist /run/ name, t_end, dt, cfl, max_steps, scheme, flip, gravity, progress_seconds, &
      drag, drag_safety, porosity_gradient, restart, max_wall_time, remap_drag, growth_limit
    restart = cfg%restart
    max_wall_time = cfg%max_wall_time
    remap_drag = cfg%remap_drag; growth_limit = cfg%growth_limit
    name = cfg%name; t_end = cfg%t_end; dt = cfg%dt; cfl = cfg%cfl; max_steps = cfg%max_steps
    scheme = cfg%scheme; flip = cfg%flip; gravity = cfg%gravity
    progress_seconds = cfg%progress_seconds
    drag = cfg%drag; drag_safety = cfg%drag_safety; porosity_gradient = cfg%porosity_gradient
    read (u, nml=run, iostat=ios, iomsg=msg)
    ok = ios == 0
    if (.not. ok) then
      call read_error(rd, g_run, 1, ios, msg)
      return
    end if
    call check_length(rd, g_run, 'name', name, len(cfg%name))
    call check_length(rd, g_run, 'restart', restart, len(cfg%restart))
    cfg%name = name; cfg%t_end = t_end; cfg%dt = dt; cfg%cfl = cfl; cfg%max_steps = max_steps
    cfg%scheme = scheme; cfg%flip = flip; cfg%gravity = gravity
    cfg%progress_seconds = progress_seconds
    cfg%drag = drag; cfg%drag_safety = drag_safety; cfg%porosity_gradient = porosity_gradient
    cfg%restart = restart
    cfg%max_wall_time = max_wall_time
    cfg%remap_drag = remap_drag; cfg%growth_limit = growth_limit
  end subroutine read_run

  !> Read &grid.
  subroutine read_grid(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    integer :: ndim, ncells(3), dims(3)
    real(wp) :: origin(3), length(3)
    integer :: ios
    character(len=512) :: msg
    namelist /grid/ ndim, ncells, origin, length, dims
    ndim = cfg%ndim; ncells = cfg%ncells; origin = cfg%origin; length = cfg%length
    dims = cfg%dims
    read (u, nml=grid, iostat=ios, iomsg=msg)
    ok = ios == 0
    if (.not. ok) then
      call read_error(rd, g_grid, 1, ios, msg)
      return
    end if
    cfg%ndim = ndim; cfg%ncells = ncells; cfg%origin = origin; cfg%length = length
    cfg%dims = dims
  end subroutine read_grid

  !> Read &shape.
  subroutine read_shape(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=name_len) :: kernel, velocity_kernel, velocity_basis, quadrature, field_kernel, &
                               field_basis
    real(wp) :: velocity_radius, field_radius
    integer :: gauss_points
    integer :: ios
    character(len=512) :: msg
    namelist /shape/ kernel, velocity_kernel, velocity_basis, velocity_radius, quadrature, &
      gauss_points, field_kernel, field_basis, field_radius
    kernel = cfg%kernel
    velocity_kernel = cfg%velocity_kernel; velocity_basis = cfg%velocity_basis
    velocity_radius = cfg%velocity_radius; quadrature = cfg%quadrature
    gauss_points = cfg%gauss_points; field_kernel = cfg%field_kernel
    field_basis = cfg%field_basis; field_radius = cfg%field_radius
    read (u, nml=shape, iostat=ios, iomsg=msg)
    ok = ios == 0
    if (.not. ok) then
      call read_error(rd, g_shape, 1, ios, msg)
      return
    end if
    cfg%kernel = kernel
    cfg%velocity_kernel = velocity_kernel; cfg%velocity_basis = velocity_basis
    cfg%velocity_radius = velocity_radius; cfg%quadrature = quadrature
    cfg%gauss_points = gauss_points; cfg%field_kernel = field_kernel
    cfg%field_basis = field_basis; cfg%field_radius = field_radius
  end subroutine read_shape

  !> Read every &material.
  subroutine read_materials(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(material_cfg_t) :: def
    type(material_cfg_t), allocatable :: list(:)
    integer :: id, k, n, ios
    character(len=name_len) :: model, dp_match
    real(wp) :: density, youngs_modulus, poisson_ratio, bulk_modulus, conductivity
    real(wp) :: friction_angle, dilatancy_angle, cohesion, tensile_strength, cohesion_softening, &
                residual_cohesion
    character(len=512) :: msg
    namelist /material/ id, model, density, youngs_modulus, poisson_ratio, bulk_modulus, &
      conductivity, friction_angle, dilatancy_angle, cohesion, tensile_strength, &
      cohesion_softening, residual_cohesion, dp_match
    allocate (list(rd%count(g_material)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      id = def%id; model = def%model; density = def%density
      youngs_modulus = def%youngs_modulus; poisson_ratio = def%poisson_ratio
      bulk_modulus = def%bulk_modulus; conductivity = def%conductivity
      friction_angle = def%friction_angle; dilatancy_angle = def%dilatancy_angle
      cohesion = def%cohesion; tensile_strength = def%tensile_strength
      cohesion_softening = def%cohesion_softening; residual_cohesion = def%residual_cohesion
      dp_match = def%dp_match
      read (u, nml=material, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call read_error(rd, g_material, k, ios, msg)
        ok = .false.
        exit
      end if
      n = k
      list(k) = material_cfg_t(id=id, model=model, density=density, &
                               youngs_modulus=youngs_modulus, poisson_ratio=poisson_ratio, &
                               bulk_modulus=bulk_modulus, conductivity=conductivity, &
                               friction_angle=friction_angle, dilatancy_angle=dilatancy_angle, &
                               cohesion=cohesion, tensile_strength=tensile_strength, &
                               cohesion_softening=cohesion_softening, &
                               residual_cohesion=residual_cohesion, dp_match=dp_match)
    end do
    cfg%materials = list(1:n)
  end subroutine read_materials

  !> Read every &region.
  subroutine read_regions(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(region_cfg_t) :: def
    type(region_cfg_t), allocatable :: list(:)
    character(len=name_len) :: shape, phase, placement
    real(wp) :: lo(3), hi(3), poly_x(max_poly), poly_y(max_poly), velocity(3), stress(6), &
                porosity, stress_gradient(6, 3), pore_pressure, pore_pressure_gradient(3)
    integer :: npoly, material, fluid_material, ppc, seed, fluid_seed, k, n, ios
    character(len=512) :: msg
    namelist /region/ shape, lo, hi, npoly, poly_x, poly_y, material, phase, fluid_material, &
      porosity, ppc, placement, seed, fluid_seed, velocity, stress, stress_gradient, pore_pressure, &
      pore_pressure_gradient
    allocate (list(rd%count(g_region)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      shape = def%shape; lo = def%lo; hi = def%hi; npoly = def%npoly
      poly_x = def%poly(1, :); poly_y = def%poly(2, :); material = def%material
      phase = def%phase; ppc = def%ppc; placement = def%placement; seed = def%seed
      velocity = def%velocity; stress = def%stress; stress_gradient = def%stress_gradient
      pore_pressure = def%pore_pressure; pore_pressure_gradient = def%pore_pressure_gradient
      fluid_material = def%fluid_material; porosity = def%porosity; fluid_seed = def%fluid_seed
      read (u, nml=region, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call read_error(rd, g_region, k, ios, msg)
        ok = .false.
        exit
      end if
      n = k
      list(k)%shape = shape; list(k)%lo = lo; list(k)%hi = hi; list(k)%npoly = npoly
      list(k)%poly(1, :) = poly_x; list(k)%poly(2, :) = poly_y; list(k)%material = material
      list(k)%phase = phase; list(k)%ppc = ppc; list(k)%placement = placement
      list(k)%seed = seed; list(k)%velocity = velocity; list(k)%stress = stress
      list(k)%fluid_material = fluid_material; list(k)%porosity = porosity
      list(k)%fluid_seed = fluid_seed; list(k)%stress_gradient = stress_gradient
      list(k)%pore_pressure = pore_pressure; list(k)%pore_pressure_gradient = pore_pressure_gradient
    end do
    cfg%regions = list(1:n)
  end subroutine read_regions

  !> Read every &boundary and set cfg%bc, cfg%fluid_bc, cfg%pore_pressure and
  !> cfg%pore_pressure_ramp; the names are
  !> checked here as they are not kept. A fluid condition left out (or 'default') stays
  !> fbc_default: the solver makes it drained at free faces and impermeable at fixed and
  !> roller faces.
  subroutine read_boundaries(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=name_len) :: face, condition, fluid
    real(wp) :: pore_pressure, pore_pressure_ramp
    logical :: seen(6), impermeable
    integer :: k, f, c, fc, ios
    character(len=512) :: msg
    character(len=:), allocatable :: why
    namelist /boundary/ face, condition, fluid, pore_pressure, pore_pressure_ramp
    seen = .false.
    ok = .true.
    do k = 1, rd%count(g_boundary)
      face = ''; condition = bc_names(bc_free); fluid = ''; pore_pressure = 0.0_wp
      pore_pressure_ramp = 0.0_wp
      read (u, nml=boundary, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call read_error(rd, g_boundary, k, ios, msg)
        ok = .false.
        exit
      end if
      f = face_index(face)
      select case (trim(adjustl(condition)))
      case ('free')
        c = bc_free
      case ('fixed')
        c = bc_fixed
      case ('roller')
        c = bc_roller
      case default
        c = -1
        call add_value(rd, g_boundary, k, 'condition', quote(condition), &
                       'the conditions are free, fixed, roller')
      end select
      select case (trim(adjustl(fluid)))
      case ('', 'default')
        fc = fbc_default
      case ('drained')
        fc = fbc_drained
      case ('impermeable')
        fc = fbc_impermeable
      case default
        fc = -1
        call add_value(rd, g_boundary, k, 'fluid', quote(fluid), 'the fluid conditions are '// &
                       'default (drained at a free face, impermeable at a fixed or roller '// &
                       'face), drained, impermeable')
      end select
      if (.not. real_ok(pore_pressure)) then
        call add_value(rd, g_boundary, k, 'pore_pressure', rtoa(pore_pressure), &
                       'must be a finite number (Pa)')
      else if (pore_pressure /= 0.0_wp .and. c >= 0 .and. fc >= 0) then
        impermeable = fc == fbc_impermeable .or. (fc == fbc_default .and. c /= bc_free)
        if (impermeable) then
          if (fc == fbc_impermeable) then
            why = "fluid = 'impermeable'"
          else
            why = 'fluid left to its default at a '//trim(bc_names(c))//' face'
          end if
          call add_value(rd, g_boundary, k, 'pore_pressure', rtoa(pore_pressure), &
                         'only a drained face takes a pore pressure, and face '// &
                         trim(adjustl(face))//' is impermeable ('//why// &
                         "); set fluid = 'drained' or leave pore_pressure out")
        end if
      end if
      if (.not. real_ok(pore_pressure_ramp) .or. pore_pressure_ramp < 0.0_wp) then
        call add_value(rd, g_boundary, k, 'pore_pressure_ramp', rtoa(pore_pressure_ramp), &
                       'must be a finite time >= 0 (s); 0 applies pore_pressure at once')
      end if
      if (f == 0) then
        call add_value(rd, g_boundary, k, 'face', quote(face), 'the faces are '//all_faces())
      else if (.not. face_in_grid(f, cfg%ndim)) then
        call add_value(rd, g_boundary, k, 'face', quote(face), &
                       'the grid has no such face with ndim = '//itoa(cfg%ndim))
      else if (seen(f)) then
        call add_value(rd, g_boundary, k, 'face', quote(face), &
                       'this face has a &boundary already; give each face once')
      else if (c >= 0 .and. fc >= 0) then
        seen(f) = .true.
        cfg%bc(f) = c
        cfg%fluid_bc(f) = fc
        cfg%pore_pressure(f) = pore_pressure
        cfg%pore_pressure_ramp(f) = pore_pressure_ramp
      end if
    end do
  end subroutine read_boundaries

  !> Read every &load.
  subroutine read_loads(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    type(load_cfg_t) :: def
    type(load_cfg_t), allocatable :: list(:)
    character(len=name_len) :: face
    real(wp) :: traction(3), ramp_time
    integer :: k, n, f, ios
    character(len=512) :: msg
    namelist /load/ face, traction, ramp_time
    allocate (list(rd%count(g_load)))
    n = 0
    ok = .true.
    do k = 1, size(list)
      face = ''; traction = def%traction; ramp_time = def%ramp_time
      read (u, nml=load, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call read_error(rd, g_load, k, ios, msg)
        ok = .false.
        exit
      end if
      f = face_index(face)
      if (f == 0) then
        call add_value(rd, g_load, k, 'face', quote(face), 'the faces are '//all_faces())
      else if (.not. face_in_grid(f, cfg%ndim)) then
        call add_value(rd, g_load, k, 'face', quote(face), &
                       'the grid has no such face with ndim = '//itoa(cfg%ndim))
      end if
      n = k
      list(k) = load_cfg_t(f, traction, ramp_time)
    end do
    cfg%loads = list(1:n)
  end subroutine read_loads

  !> Read &output.
  subroutine read_output(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=long_len) :: dir
    character(len=len(cfg%solid_fields)) :: solid_fields, fluid_fields
    real(wp) :: frame_interval, checkpoint_seconds
    integer :: diag_every, checkpoint_every, compression, ios
    character(len=512) :: msg
    namelist /output/ dir, frame_interval, diag_every, checkpoint_every, checkpoint_seconds, &
      compression, solid_fields, fluid_fields
    dir = cfg%output_dir; frame_interval = cfg%frame_interval; diag_every = cfg%diag_every
    checkpoint_every = cfg%checkpoint_every; compression = cfg%compression
    checkpoint_seconds = cfg%checkpoint_seconds
    solid_fields = cfg%solid_fields; fluid_fields = cfg%fluid_fields
    read (u, nml=output, iostat=ios, iomsg=msg)
    ok = ios == 0
    if (.not. ok) then
      call read_error(rd, g_output, 1, ios, msg)
      return
    end if
    call check_length(rd, g_output, 'dir', dir, len(cfg%output_dir))
    cfg%output_dir = dir; cfg%frame_interval = frame_interval; cfg%diag_every = diag_every
    cfg%checkpoint_every = checkpoint_every; cfg%compression = compression
    cfg%checkpoint_seconds = checkpoint_seconds
    cfg%solid_fields = solid_fields; cfg%fluid_fields = fluid_fields
  end subroutine read_output

  !> Read &benchmark.
  subroutine read_benchmark(rd, u, cfg, ok)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: u
    type(config_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    character(len=name_len) :: name
    real(wp) :: amplitude
    integer :: ios
    character(len=512) :: msg
    namelist /benchmark/ name, amplitude
    name = cfg%benchmark; amplitude = cfg%amplitude
    read (u, nml=benchmark, iostat=ios, iomsg=msg)
    ok = ios == 0
    if (.not. ok) then
      call read_error(rd, g_benchmark, 1, ios, msg)
      return
    end if
    cfg%benchmark = name; cfg%amplitude = amplitude
  end subroutine read_benchmark

  ! ---------------------------------------------------------------------------------------------
  ! Checks
  ! ---------------------------------------------------------------------------------------------

  !> Check every value read; ok(g) is false for groups that could not be read.
  subroutine check_config(rd, cfg, nranks, ok)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: nranks
    logical, intent(in) :: ok(ngroups)
    integer :: nd, d, k, j
    logical :: grid_ok, ndim_ok, exists

    ! &run
    if (.not. any(cfg%scheme == [character(len=4) :: 'musl', 'usl'])) call add_value(rd, g_run, &
      1, 'scheme', quote(cfg%scheme), 'the schemes are musl, usl')
    if (.not. real_ok(cfg%t_end, gt=0.0_wp)) call add_value(rd, g_run, 1, 't_end', &
      rtoa(cfg%t_end), 'must be > 0 (s)')
    if (.not. real_ok(cfg%dt, ge=0.0_wp)) call add_value(rd, g_run, 1, 'dt', rtoa(cfg%dt), &
      'must be >= 0 (s; 0 = from the CFL condition)')
    if (.not. real_ok(cfg%cfl, gt=0.0_wp, le=1.0_wp)) call add_value(rd, g_run, 1, 'cfl', &
      rtoa(cfg%cfl), 'must be in (0, 1]')
    if (.not. real_ok(cfg%flip, ge=0.0_wp, le=1.0_wp)) call add_value(rd, g_run, 1, 'flip', &
      rtoa(cfg%flip), 'must be in [0, 1] (1 = FLIP, 0 = PIC)')
    if (cfg%max_steps < 1) call add_value(rd, g_run, 1, 'max_steps', i8toa(cfg%max_steps), &
      'must be >= 1')
    call check_finite(rd, g_run, 1, 'gravity', cfg%gravity)
    if (.not. real_ok(cfg%progress_seconds, gt=0.0_wp)) call add_value(rd, g_run, 1, &
      'progress_seconds', rtoa(cfg%progress_seconds), 'must be > 0 (s)')
    if (.not. real_ok(cfg%max_wall_time, ge=0.0_wp)) call add_value(rd, g_run, 1, &
      'max_wall_time', rtoa(cfg%max_wall_time), 'must be >= 0 (s of wall time; 0 = no limit)')
    if (len_trim(cfg%restart) > 0) then
      inquire (file=trim(cfg%restart), exist=exists)
      if (.not. exists) call add_value(rd, g_run, 1, 'restart', quote(cfg%restart), &
        'no such file (a checkpoint <dir>/<name>.ckpt.h5 written with checkpoint_every > 0)')
    end if
    if (.not. any(cfg%drag == [character(len=8) :: 'explicit', 'implicit'])) call add_value(rd, &
      g_run, 1, 'drag', quote(cfg%drag), 'the drag treatments are explicit (limited by '// &
      'drag_safety), implicit (solid and fluid velocities solved together at each node)')
    if (.not. real_ok(cfg%drag_safety, gt=0.0_wp, le=1.0_wp)) call add_value(rd, g_run, 1, &
      'drag_safety', rtoa(cfg%drag_safety), 'must be in (0, 1] (fraction of the nodal drag limit)')
    if (.not. real_ok(cfg%growth_limit, ge=0.0_wp)) call add_value(rd, g_run, 1, &
      'growth_limit', rtoa(cfg%growth_limit), 'must be >= 0 (0 = no growth monitor)')

    ! &grid
    ndim_ok = cfg%ndim >= 1 .and. cfg%ndim <= 3
    if (.not. ndim_ok) call add_value(rd, g_grid, 1, 'ndim', itoa(cfg%ndim), 'must be 1, 2 or 3')
    grid_ok = ndim_ok .and. ok(g_grid) .and. rd%count(g_grid) == 1
    nd = merge(cfg%ndim, 3, ndim_ok)
    do d = 1, nd
      if (cfg%ncells(d) < 1) then
        call add_value(rd, g_grid, 1, 'ncells('//itoa(d)//')', itoa(cfg%ncells(d)), &
                       'zero cells: must be >= 1')
        grid_ok = .false.
      end if
      if (.not. real_ok(cfg%length(d), gt=0.0_wp)) then
        call add_value(rd, g_grid, 1, 'length('//itoa(d)//')', rtoa(cfg%length(d)), &
                       'must be > 0 (m)')
        grid_ok = .false.
      end if
      if (.not. real_ok(cfg%origin(d))) then
        call add_value(rd, g_grid, 1, 'origin('//itoa(d)//')', rtoa(cfg%origin(d)), &
                       'must be a finite number (m)')
        grid_ok = .false.
      end if
      if (cfg%dims(d) < 0) then
        call add_value(rd, g_grid, 1, 'dims('//itoa(d)//')', itoa(cfg%dims(d)), &
                       'must be >= 0 (ranks along the axis; 0 = chosen by MPI)')
        grid_ok = .false.
      end if
    end do

    ! &shape
    if (.not. is_grid_kernel(kernel_from_name(cfg%kernel))) call add_value(rd, g_shape, 1, &
      'kernel', quote(cfg%kernel), 'the grid kernels are '//all_kernels(ngrid_kernels))
    call check_mls_choice(rd, 'velocity', cfg%velocity_kernel, cfg%velocity_basis, &
                          cfg%velocity_radius, len_trim(cfg%velocity_kernel) > 0)
    if (len_trim(cfg%velocity_kernel) > 0 .and. two_phase(cfg)) call add_value(rd, g_shape, 1, &
      'velocity_kernel', quote(cfg%velocity_kernel), 'MLS nodal velocities are not available '// &
      "in two-phase scenes; use velocity_kernel = ''")
    if (.not. any(cfg%quadrature == [character(len=6) :: 'points', 'gauss'])) &
      call add_value(rd, g_shape, 1, 'quadrature', quote(cfg%quadrature), &
                     'the quadratures are points (at the material points), gauss (Gauss points '// &
                     'of the grid cells with MLS-reconstructed stresses)')
    if (cfg%gauss_points < 1 .or. cfg%gauss_points > max_gauss) call add_value(rd, g_shape, 1, &
      'gauss_points', itoa(cfg%gauss_points), 'must be 1 to '//itoa(max_gauss)// &
      ' (Gauss points per cell per axis)')
    call check_mls_choice(rd, 'field', cfg%field_kernel, cfg%field_basis, cfg%field_radius, &
                          cfg%quadrature == 'gauss')

    if (grid_ok) call check_decomposition(rd, cfg, nranks)

    ! &material
    do k = 1, size(cfg%materials)
      associate (m => cfg%materials(k))
        if (.not. any(m%model == [character(len=14) :: 'linear_elastic', 'neo_hookean', &
                                  'fluid', 'mohr_coulomb', 'drucker_prager'])) &
          call add_value(rd, g_material, k, 'model', quote(m%model), &
                         'the models are linear_elastic, neo_hookean, fluid, mohr_coulomb, '// &
                         'drucker_prager')
        if (.not. real_ok(m%density, gt=0.0_wp)) call add_value(rd, g_material, k, 'density', &
          rtoa(m%density), 'must be > 0 (kg/m^3)')
        if (m%model == 'fluid') then
          ! A linear compressible fluid: only density and bulk_modulus matter.
          if (.not. real_ok(m%bulk_modulus, gt=0.0_wp)) call add_value(rd, g_material, k, &
            'bulk_modulus', rtoa(m%bulk_modulus), 'must be > 0 (Pa) for a fluid')
        else
          if (.not. real_ok(m%youngs_modulus, gt=0.0_wp)) call add_value(rd, g_material, k, &
            'youngs_modulus', rtoa(m%youngs_modulus), 'must be > 0 (Pa)')
          if (.not. real_ok(m%poisson_ratio, gt=-1.0_wp, lt=0.5_wp)) call add_value(rd, &
            g_material, k, 'poisson_ratio', rtoa(m%poisson_ratio), &
            'must be in (-1, 0.5): 0.5 is incompressible, which these models cannot represent')
        end if
        if (.not. real_ok(m%conductivity, ge=0.0_wp)) call add_value(rd, g_material, k, &
          'conductivity', rtoa(m%conductivity), 'must be >= 0 (m/s; 0 = no pore fluid flow)')
        if (m%model == 'mohr_coulomb' .or. m%model == 'drucker_prager') &
          call check_plastic(rd, k, m)
        do j = 1, k - 1
          if (cfg%materials(j)%id == m%id) then
            call add_value(rd, g_material, k, 'id', itoa(m%id), &
                           'ids must be unique; &material number '//itoa(j)//' has it already')
            exit
          end if
        end do
      end associate
    end do

    ! &region
    do k = 1, size(cfg%regions)
      call check_region(rd, cfg, k, grid_ok, ok(g_material))
    end do

    ! &load
    do k = 1, size(cfg%loads)
      call check_finite(rd, g_load, k, 'traction', cfg%loads(k)%traction)
      if (.not. real_ok(cfg%loads(k)%ramp_time, ge=0.0_wp)) call add_value(rd, g_load, k, &
        'ramp_time', rtoa(cfg%loads(k)%ramp_time), 'must be >= 0 (s; 0 = step load)')
    end do

    ! &output
    if (.not. real_ok(cfg%frame_interval, ge=0.0_wp)) call add_value(rd, g_output, 1, &
      'frame_interval', rtoa(cfg%frame_interval), 'must be >= 0 (s; 0 = first and last only)')
    if (cfg%diag_every < 0) call add_value(rd, g_output, 1, 'diag_every', itoa(cfg%diag_every), &
      'must be >= 0 (steps; 0 = automatic)')
    if (len_trim(cfg%output_dir) == 0) call add_value(rd, g_output, 1, 'dir', "''", &
      'must name a directory')
    if (cfg%checkpoint_every < 0) call add_value(rd, g_output, 1, 'checkpoint_every', &
      itoa(cfg%checkpoint_every), 'must be >= 0 (steps; 0 = no checkpoints)')
    if (.not. real_ok(cfg%checkpoint_seconds, ge=0.0_wp)) call add_value(rd, g_output, 1, &
      'checkpoint_seconds', rtoa(cfg%checkpoint_seconds), &
      'must be >= 0 (s of wall time between checkpoints; 0 = none)')
    if (cfg%compression < 0 .or. cfg%compression > 9) call add_value(rd, g_output, 1, &
      'compression', itoa(cfg%compression), 'must be 0 (off) to 9 (gzip level)')
    call check_fields(rd, 'solid_fields', cfg%solid_fields, .false.)
    call check_fields(rd, 'fluid_fields', cfg%fluid_fields, .true.)

    ! &benchmark
    if (.not. any(cfg%benchmark == [character(len=11) :: 'none', 'axial_bar', 'mms', &
                                    'biot_column', 'terzaghi'])) &
      call add_value(rd, g_benchmark, 1, 'name', quote(cfg%benchmark), &
                     'the benchmarks are none, axial_bar, mms, biot_column, terzaghi')
    if (cfg%benchmark == 'mms' .and. cfg%ndim /= 2) call add_value(rd, g_benchmark, 1, 'name', &
      quote(cfg%benchmark), 'the manufactured solution is 2D: set &grid ndim = 2')
    if (.not. real_ok(cfg%amplitude)) call add_value(rd, g_benchmark, 1, 'amplitude', &
      rtoa(cfg%amplitude), 'must be a finite number')
  end subroutine check_config

  !> Check one MLS reconstruction choice of &shape (prefix velocity or field) when it is used.
  subroutine check_mls_choice(rd, prefix, kernel, basis, radius, used)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: prefix, kernel, basis
    real(wp), intent(in) :: radius
    logical, intent(in) :: used
    integer :: k
    if (.not. used) return
    k = kernel_from_name(kernel)
    if (k <= 0) then
      call add_value(rd, g_shape, 1, prefix//'_kernel', quote(kernel), 'the MLS weights are '// &
                     all_kernels(size(kernel_names)))
    else if (.not. is_grid_kernel(k) .and. .not. real_ok(radius, gt=0.0_wp)) then
      call add_value(rd, g_shape, 1, prefix//'_radius', rtoa(radius), 'the '//trim(kernel)// &
                     ' weight is radial and needs a support radius > 0 (in cells)')
    end if
    if (.not. real_ok(radius, ge=0.0_wp, le=4.0_wp)) call add_value(rd, g_shape, 1, &
      prefix//'_radius', rtoa(radius), 'must be in [0, 4] cells (0 = tensor-product B-spline '// &
      'of natural support)')
    if (basis_from_name(basis) < 0) call add_value(rd, g_shape, 1, prefix//'_basis', &
      quote(basis), 'the bases are constant, linear, quadratic')
  end subroutine check_mls_choice

  !> Check that the ranks can be laid out over the grid as the solver will do it, with at least
  !> the kernel's ghost width of cells per rank along every axis.
  subroutine check_decomposition(rd, cfg, nranks)
    type(reader_t), intent(inout) :: rd
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
        call add_value(rd, g_grid, 1, 'dims', itoa_list(dims(1:nd)), 'the ranks per axis '// &
                       'multiply to '//itoa(nfixed)//' but the run has '//itoa(nranks)// &
                       trim(merge(' rank ', ' ranks', nranks == 1))//': their product must '// &
                       'be the number of ranks (or use 0 to let MPI choose an axis)')
        return
      end if
    else if (mod(nranks, nfixed) /= 0) then
      call add_value(rd, g_grid, 1, 'dims', itoa_list(dims(1:nd)), 'the nonzero ranks per '// &
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
        call add_value(rd, g_grid, 1, 'ncells('//itoa(d)//')', itoa(cfg%ncells(d)), &
                       'more ranks than cells along axis '//itoa(d)//' ('//itoa(dims(d))// &
                       ' of the '//itoa(nranks)//' ranks lie along it)'//advice)
      else if (cfg%ncells(d)/dims(d) < gw) then
        call add_value(rd, g_grid, 1, 'ncells('//itoa(d)//')', itoa(cfg%ncells(d)), &
                       'too few cells per rank along axis '//itoa(d)//' ('//itoa(dims(d))// &
                       ' of the '//itoa(nranks)//' ranks lie along it)'//advice)
      end if
    end do
  end subroutine check_decomposition

  !> Check region k.
  subroutine check_region(rd, cfg, k, grid_ok, materials_ok)
    type(reader_t), intent(inout) :: rd
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
            call add_value(rd, g_region, k, 'lo('//itoa(d)//'), hi('//itoa(d)//')', &
                           rtoa(r%lo(d))//', '//rtoa(r%hi(d)), 'must be finite numbers (m)')
            cycle
          end if
          glo = cfg%origin(d)
          ghi = cfg%origin(d) + cfg%length(d)
          tol = 1.0e-12_wp*cfg%length(d)
          if (r%lo(d) >= r%hi(d)) then
            call add_value(rd, g_region, k, 'lo('//itoa(d)//'), hi('//itoa(d)//')', &
                           rtoa(r%lo(d))//', '//rtoa(r%hi(d)), 'need lo < hi')
          else if (r%lo(d) < glo - tol .or. r%hi(d) > ghi + tol) then
            call add_value(rd, g_region, k, 'lo('//itoa(d)//'), hi('//itoa(d)//')', &
                           rtoa(r%lo(d))//', '//rtoa(r%hi(d)), 'region outside the grid: the '// &
                           'box must lie in the grid, ['//rtoa(glo)//', '//rtoa(ghi)// &
                           '] along axis '//itoa(d))
          end if
        end do
      case ('polygon')
        if (cfg%ndim /= 2) then
          call add_value(rd, g_region, k, 'shape', quote(r%shape), &
                         'polygon regions need ndim = 2; use a box')
        else if (r%npoly < 3 .or. r%npoly > max_poly) then
          call add_value(rd, g_region, k, 'npoly', itoa(r%npoly), &
                         'a polygon needs 3 to '//itoa(max_poly)//' vertices (poly_x, poly_y)')
        else if (grid_ok) then
          vertices: do j = 1, r%npoly
            do d = 1, 2
              glo = cfg%origin(d)
              ghi = cfg%origin(d) + cfg%length(d)
              tol = 1.0e-12_wp*cfg%length(d)
              if (.not. real_ok(r%poly(d, j), ge=glo - tol, le=ghi + tol)) then
                call add_value(rd, g_region, k, 'poly_'//xy(d:d)//'('//itoa(j)//')', &
                               rtoa(r%poly(d, j)), 'region outside the grid: every vertex '// &
                               'must lie in the grid, ['//rtoa(glo)//', '//rtoa(ghi)//'] in '// &
                               xy(d:d))
                exit vertices
              end if
            end do
          end do vertices
        end if
      case default
        call add_value(rd, g_region, k, 'shape', quote(r%shape), &
                       'the shapes are box, polygon (polygon with ndim = 2 only)')
      end select
      m = 0
      if (materials_ok) m = findloc(cfg%materials%id, r%material, dim=1)
      if (materials_ok .and. m == 0) &
        call add_value(rd, g_region, k, 'material', itoa(r%material), 'no &material has this id')
      select case (trim(r%phase))
      case ('solid')
        if (m > 0) then
          if (cfg%materials(m)%model == 'fluid') call add_value(rd, g_region, k, 'material', &
            itoa(r%material), "material "//itoa(r%material)//" is a 'fluid' material; a solid "// &
            "region needs a solid material (or set phase = 'fluid')")
        end if
      case ('fluid')
        if (m > 0) then
          if (cfg%materials(m)%model /= 'fluid') call add_value(rd, g_region, k, 'material', &
            itoa(r%material), 'material '//itoa(r%material)//' has model '// &
            quote(cfg%materials(m)%model)//"; a fluid region needs a 'fluid' material")
        end if
        if (any(r%stress /= 0.0_wp)) call add_value(rd, g_region, k, 'stress', &
          rtoa_list(r%stress), 'a fluid region has no skeleton stress; leave stress out '// &
          '(its initial state is pore_pressure)')
        if (any(r%stress_gradient /= 0.0_wp)) call add_value(rd, g_region, k, 'stress_gradient', &
          rtoa_list(reshape(r%stress_gradient, [18])), 'a fluid region has no skeleton '// &
          'stress; leave stress_gradient out (use pore_pressure_gradient)')
      case ('saturated')
        call check_saturated(rd, cfg, k, materials_ok)
      case default
        call add_value(rd, g_region, k, 'phase', quote(r%phase), &
                       'the phases are solid, fluid, saturated (soil skeleton with pore fluid)')
      end select
      if (trim(r%phase) == 'solid') then
        if (r%pore_pressure /= 0.0_wp) call add_value(rd, g_region, k, 'pore_pressure', &
          rtoa(r%pore_pressure), "a solid region has no pore fluid; leave it out or set "// &
          "phase = 'saturated'")
        if (any(r%pore_pressure_gradient /= 0.0_wp)) call add_value(rd, g_region, k, &
          'pore_pressure_gradient', rtoa_list(r%pore_pressure_gradient), 'a solid region has '// &
          "no pore fluid; leave it out or set phase = 'saturated'")
      end if
      if (trim(r%phase) /= 'saturated') then
        if (r%fluid_material /= 0) call add_value(rd, g_region, k, 'fluid_material', &
          itoa(r%fluid_material), "only a saturated region has a pore fluid; leave it out "// &
          "or set phase = 'saturated'")
        if (r%porosity /= 0.0_wp) call add_value(rd, g_region, k, 'porosity', &
          rtoa(r%porosity), "only a saturated region has a porosity; leave it out or set "// &
          "phase = 'saturated'")
      end if
      if (r%ppc < 1 .or. r%ppc > 10) call add_value(rd, g_region, k, 'ppc', itoa(r%ppc), &
        'must be in 1..10 (points per cell along each axis)')
      if (.not. any(r%placement == [character(len=7) :: 'regular', 'random', 'uniform'])) &
        call add_value(rd, g_region, k, 'placement', quote(r%placement), &
                       'the placements are regular, random (scattered in each cell), '// &
                       'uniform (scattered over the whole region)')
      if (r%seed < 0) call add_value(rd, g_region, k, 'seed', itoa(r%seed), 'must be >= 0')
      if (r%fluid_seed < -1) call add_value(rd, g_region, k, 'fluid_seed', itoa(r%fluid_seed), &
        'must be >= 0, or -1 for seed + 1')
      call check_finite(rd, g_region, k, 'velocity', r%velocity)
      call check_finite(rd, g_region, k, 'stress', r%stress)
      call check_finite(rd, g_region, k, 'stress_gradient', reshape(r%stress_gradient, [18]))
      call check_finite(rd, g_region, k, 'pore_pressure', [r%pore_pressure])
      call check_finite(rd, g_region, k, 'pore_pressure_gradient', r%pore_pressure_gradient)
    end associate
  end subroutine check_region

  !> Check the soil skeleton, pore fluid and porosity of saturated region k.
  subroutine check_saturated(rd, cfg, k, materials_ok)
    type(reader_t), intent(inout) :: rd
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    logical, intent(in) :: materials_ok
    integer :: m, mf
    associate (r => cfg%regions(k))
      if (materials_ok) then
        m = findloc(cfg%materials%id, r%material, dim=1)
        if (m > 0) then
          if (cfg%materials(m)%model == 'fluid') then
            call add_value(rd, g_region, k, 'material', itoa(r%material), "material "// &
                           itoa(r%material)//" is a 'fluid' material; the material of a "// &
                           'saturated region is its soil skeleton (linear_elastic, '// &
                           'neo_hookean, mohr_coulomb or drucker_prager) and fluid_material '// &
                           'its pore fluid')
          else if (.not. real_ok(cfg%materials(m)%conductivity, gt=0.0_wp)) then
            call add_value(rd, g_region, k, 'material', itoa(r%material), 'material '// &
                           itoa(r%material)//' has conductivity = '// &
                           rtoa(cfg%materials(m)%conductivity)//'; the soil of a saturated '// &
                           'region needs a hydraulic conductivity > 0 (m/s)')
          end if
        end if
        mf = findloc(cfg%materials%id, r%fluid_material, dim=1)
        if (r%fluid_material == 0) then
          call add_value(rd, g_region, k, 'fluid_material', itoa(r%fluid_material), &
                         "a saturated region needs the id of a 'fluid' &material for its "// &
                         'pore fluid')
        else if (mf == 0) then
          call add_value(rd, g_region, k, 'fluid_material', itoa(r%fluid_material), &
                         'no &material has this id')
        else if (cfg%materials(mf)%model /= 'fluid') then
          call add_value(rd, g_region, k, 'fluid_material', itoa(r%fluid_material), &
                         'material '//itoa(r%fluid_material)//' has model '// &
                         quote(cfg%materials(mf)%model)//"; the pore fluid of a saturated "// &
                         "region must be a 'fluid' material")
        end if
      end if
      if (.not. real_ok(r%porosity, gt=0.0_wp, lt=1.0_wp)) call add_value(rd, g_region, k, &
        'porosity', rtoa(r%porosity), 'must be in (0, 1) for a saturated region (volume '// &
        'fraction of the pores)')
    end associate
  end subroutine check_saturated

  !> True when any region has a fluid phase (fluid or saturated).
  pure logical function two_phase(cfg)
    type(config_t), intent(in) :: cfg
    integer :: k
    two_phase = .false.
    if (.not. allocated(cfg%regions)) return
    do k = 1, size(cfg%regions)
      if (any(cfg%regions(k)%phase == [character(len=9) :: 'fluid', 'saturated'])) &
        two_phase = .true.
    end do
  end function two_phase

  !> A problem when any value of x is not a finite number.
  subroutine check_finite(rd, g, k, var, x)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: g, k
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: x(:)
    integer :: j
    do j = 1, size(x)
      if (.not. ieee_is_finite(x(j))) then
        call add_value(rd, g, k, var//'('//itoa(j)//')', rtoa(x(j)), 'must be a finite number')
      end if
    end do
  end subroutine check_finite

  !> True if x is finite and satisfies the bounds given (NaN never traps here).
  pure logical function real_ok(x, gt, ge, lt, le) result(ok)
    real(wp), intent(in) :: x
    real(wp), intent(in), optional :: gt, ge, lt, le
    ok = ieee_is_finite(x)
    if (.not. ok) return
    if (present(gt)) ok = ok .and. x > gt
    if (present(ge)) ok = ok .and. x >= ge
    if (present(lt)) ok = ok .and. x < lt
    if (present(le)) ok = ok .and. x <= le
  end function real_ok

  ! ---------------------------------------------------------------------------------------------
  ! Problems
  ! ---------------------------------------------------------------------------------------------

  !> solid_fields / fluid_fields: known names only; a fluid set has no stress to write.
  subroutine check_fields(rd, var, list, fluid)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: var, list
    logical, intent(in) :: fluid
    character(len=:), allocatable :: word
    word = unknown_field(list)
    if (len(word) > 0) then
      call add_value(rd, g_output, 1, var, "'"//trim(list)//"'", 'unknown dataset '''//word// &
                     ''': the optional datasets are displacement, stress, material, '// &
                     'porosity, pore_pressure, plastic_strain, or all (id, x, v, mass and '// &
                     'volume are always written)')
    else if (fluid .and. field_listed(list, 'stress', explicit=.true.)) then
      call add_value(rd, g_output, 1, var, "'"//trim(list)//"'", 'a fluid set has no '// &
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

  !> Strength parameters of a mohr_coulomb or drucker_prager material k.
  subroutine check_plastic(rd, k, m)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    type(plastic_params_t) :: par
    real(wp) :: hmax
    integer :: match
    logical :: ok
    ok = .true.
    if (.not. real_ok(m%friction_angle, ge=0.0_wp, lt=90.0_wp)) then
      call add_value(rd, g_material, k, 'friction_angle', rtoa(m%friction_angle), &
                     'must be in [0, 90) (degrees)')
      ok = .false.
    end if
    if (.not. real_ok(m%dilatancy_angle, ge=0.0_wp)) then
      call add_value(rd, g_material, k, 'dilatancy_angle', rtoa(m%dilatancy_angle), &
                     'must be >= 0 (degrees)')
      ok = .false.
    else if (ok .and. m%dilatancy_angle > m%friction_angle) then
      call add_value(rd, g_material, k, 'dilatancy_angle', rtoa(m%dilatancy_angle), &
                     'must not exceed friction_angle = '//rtoa(m%friction_angle)// &
                     ' (psi > phi would create energy)')
      ok = .false.
    end if
    if (.not. real_ok(m%cohesion, ge=0.0_wp)) then
      call add_value(rd, g_material, k, 'cohesion', rtoa(m%cohesion), 'must be >= 0 (Pa)')
      ok = .false.
    else if (ok .and. m%cohesion == 0.0_wp .and. m%friction_angle == 0.0_wp) then
      call add_value(rd, g_material, k, 'cohesion', rtoa(m%cohesion), &
                     'with friction_angle = 0 the soil needs a cohesion > 0 (Pa): it has no '// &
                     'shear strength at all')
    end if
    if (.not. real_ok(m%tensile_strength, ge=0.0_wp)) call add_value(rd, g_material, k, &
      'tensile_strength', rtoa(m%tensile_strength), 'must be >= 0 (Pa; 0 = no tension)')
    if (.not. real_ok(m%residual_cohesion, ge=0.0_wp)) then
      call add_value(rd, g_material, k, 'residual_cohesion', rtoa(m%residual_cohesion), &
                     'must be >= 0 (Pa)')
    else if (real_ok(m%cohesion) .and. m%residual_cohesion > m%cohesion) then
      call add_value(rd, g_material, k, 'residual_cohesion', rtoa(m%residual_cohesion), &
                     'must not exceed cohesion = '//rtoa(m%cohesion)//' (softening lowers it)')
    end if
    match = findloc(dp_match_names, trim(m%dp_match), dim=1)
    if (match == 0) then
      call add_value(rd, g_material, k, 'dp_match', quote(m%dp_match), &
                     'the matchings of Drucker-Prager to Mohr-Coulomb are plane_strain, outer, '// &
                     'inner')
      match = dp_plane_strain
    end if
    if (.not. real_ok(m%cohesion_softening, ge=0.0_wp)) then
      call add_value(rd, g_material, k, 'cohesion_softening', rtoa(m%cohesion_softening), &
                     'must be >= 0 (Pa per unit plastic strain; 0 = no softening)')
    else if (ok .and. real_ok(m%youngs_modulus, gt=0.0_wp) .and. &
             real_ok(m%poisson_ratio, gt=-1.0_wp, lt=0.5_wp)) then
      par = plastic_setup(merge(surface_mohr_coulomb, surface_drucker_prager, &
                                m%model == 'mohr_coulomb'), &
                          m%youngs_modulus/(3.0_wp*(1.0_wp - 2.0_wp*m%poisson_ratio)), &
                          m%youngs_modulus/(2.0_wp*(1.0_wp + m%poisson_ratio)), &
                          m%friction_angle, m%dilatancy_angle, m%cohesion, m%tensile_strength, &
                          m%cohesion_softening, m%residual_cohesion, match)
      hmax = softening_limit(par)
      if (m%cohesion_softening >= hmax) call add_value(rd, g_material, k, 'cohesion_softening', &
        rtoa(m%cohesion_softening), 'must be < '//rtoa(hmax)//' (Pa) with these elastic '// &
        'constants and angles: a steeper softening has no unique return')
    end if
  end subroutine check_plastic

  !> A problem with one value: "&group var = value: allowed [where]".
  subroutine add_value(rd, g, k, var, value, allowed)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: g, k
    character(len=*), intent(in) :: var, value, allowed
    call add_raw(rd, '&'//trim(group_names(g))//' '//var//' = '//value//': '//allowed// &
                 place(rd, g, k))
  end subroutine add_value

  !> A string read into a long buffer must fit the limit of its variable in config_t.
  subroutine check_length(rd, g, var, value, limit)
    type(reader_t), intent(inout) :: rd
    integer, intent(in) :: g, limit
    character(len=*), intent(in) :: var, value
    character(len=:), allocatable :: count
    integer :: n
    n = len_trim(value)
    if (n <= limit) return
    count = itoa(n)
    if (n == len(value)) count = 'more than '//itoa(n - 1)
    call add_value(rd, g, 1, var, quote(value(1:40))//'...', 'is '//count// &
                   ' characters long: at most '//itoa(limit)//' are allowed')
  end subroutine check_length

  !> A problem with the file as a whole.
  subroutine add_file_problem(rd, what)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: what
    call add_raw(rd, what)
  end subroutine add_file_problem

  !> Append "dpmpm: input error: <file>: <text>" to the problems.
  subroutine add_raw(rd, text)
    type(reader_t), intent(inout) :: rd
    character(len=*), intent(in) :: text
    type(text_t), allocatable :: tmp(:)
    if (.not. allocated(rd%prob)) allocate (rd%prob(8))
    if (rd%nprob == size(rd%prob)) then
      allocate (tmp(2*size(rd%prob)))
      tmp(1:rd%nprob) = rd%prob(1:rd%nprob)
      call move_alloc(tmp, rd%prob)
    end if
    rd%nprob = rd%nprob + 1
    rd%prob(rd%nprob)%s = err_prefix//rd%file//': '//text
  end subroutine add_raw

  !> " [line L]" or " [group k of n, line L]" for occurrence k of group g.
  function place(rd, g, k) result(s)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: g, k
    character(len=:), allocatable :: s
    integer :: j, seen
    s = ''
    seen = 0
    do j = 1, rd%nopen
      if (rd%open_group(j) /= g) cycle
      seen = seen + 1
      if (seen == k) then
        s = 'line '//itoa(rd%open_line(j))
        exit
      end if
    end do
    if (rd%count(g) > 1) then
      if (len(s) > 0) s = ', '//s
      s = 'group '//itoa(k)//' of '//itoa(rd%count(g))//s
    end if
    if (len(s) > 0) s = ' ['//trim(s)//']'
  end function place

  !> " (lines a, b, c)" listing where group g opens.
  function lines_of(rd, g) result(s)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: g
    character(len=:), allocatable :: s
    integer :: j
    s = ''
    do j = 1, rd%nopen
      if (rd%open_group(j) /= g) cycle
      if (len(s) > 0) s = s//', '
      s = s//itoa(rd%open_line(j))
    end do
    s = ' (lines '//s//')'
  end function lines_of

  ! ---------------------------------------------------------------------------------------------
  ! Broadcast
  ! ---------------------------------------------------------------------------------------------

  !> Broadcast the whole configuration from rank 0, field by field.
  subroutine bcast_config(cfg, comm)
    type(config_t), intent(inout) :: cfg
    type(MPI_Comm), intent(in) :: comm
    integer :: rank, n(4), k
    call MPI_Comm_rank(comm, rank)
    n = 0
    if (rank == 0) n = [len(cfg%input_text), size(cfg%materials), size(cfg%regions), &
                        size(cfg%loads)]
    call bcast(n, comm)
    if (rank /= 0) then
      if (allocated(cfg%input_text)) deallocate (cfg%input_text)
      allocate (character(len=n(1)) :: cfg%input_text)
      allocate (cfg%materials(n(2)), cfg%regions(n(3)), cfg%loads(n(4)))
    end if
    if (n(1) > 0) call MPI_Bcast(cfg%input_text, n(1), MPI_CHARACTER, 0, comm)
    call bcast(cfg%name, comm)
    call bcast(cfg%t_end, comm)
    call bcast(cfg%dt, comm)
    call bcast(cfg%cfl, comm)
    call bcast(cfg%max_steps, comm)
    call bcast(cfg%scheme, comm)
    call bcast(cfg%flip, comm)
    call bcast(cfg%gravity, comm)
    call bcast(cfg%progress_seconds, comm)
    call bcast(cfg%restart, comm)
    call bcast(cfg%max_wall_time, comm)
    call bcast(cfg%drag, comm)
    call bcast(cfg%drag_safety, comm)
    call bcast(cfg%porosity_gradient, comm)
    call bcast(cfg%remap_drag, comm)
    call bcast(cfg%growth_limit, comm)
    call bcast(cfg%ndim, comm)
    call bcast(cfg%ncells, comm)
    call bcast(cfg%origin, comm)
    call bcast(cfg%length, comm)
    call bcast(cfg%dims, comm)
    call bcast(cfg%kernel, comm)
    call bcast(cfg%velocity_kernel, comm)
    call bcast(cfg%velocity_basis, comm)
    call bcast(cfg%velocity_radius, comm)
    call bcast(cfg%quadrature, comm)
    call bcast(cfg%gauss_points, comm)
    call bcast(cfg%field_kernel, comm)
    call bcast(cfg%field_basis, comm)
    call bcast(cfg%field_radius, comm)
    do k = 1, n(2)
      call bcast(cfg%materials(k)%id, comm)
      call bcast(cfg%materials(k)%model, comm)
      call bcast(cfg%materials(k)%density, comm)
      call bcast(cfg%materials(k)%youngs_modulus, comm)
      call bcast(cfg%materials(k)%poisson_ratio, comm)
      call bcast(cfg%materials(k)%bulk_modulus, comm)
      call bcast(cfg%materials(k)%conductivity, comm)
      call bcast(cfg%materials(k)%friction_angle, comm)
      call bcast(cfg%materials(k)%dilatancy_angle, comm)
      call bcast(cfg%materials(k)%cohesion, comm)
      call bcast(cfg%materials(k)%tensile_strength, comm)
      call bcast(cfg%materials(k)%cohesion_softening, comm)
      call bcast(cfg%materials(k)%residual_cohesion, comm)
      call bcast(cfg%materials(k)%dp_match, comm)
    end do
    do k = 1, n(3)
      call bcast(cfg%regions(k)%shape, comm)
      call bcast(cfg%regions(k)%lo, comm)
      call bcast(cfg%regions(k)%hi, comm)
      call bcast(cfg%regions(k)%npoly, comm)
      call bcast(cfg%regions(k)%poly, comm)
      call bcast(cfg%regions(k)%material, comm)
      call bcast(cfg%regions(k)%phase, comm)
      call bcast(cfg%regions(k)%fluid_material, comm)
      call bcast(cfg%regions(k)%porosity, comm)
      call bcast(cfg%regions(k)%ppc, comm)
      call bcast(cfg%regions(k)%placement, comm)
      call bcast(cfg%regions(k)%seed, comm)
      call bcast(cfg%regions(k)%fluid_seed, comm)
      call bcast(cfg%regions(k)%velocity, comm)
      call bcast(cfg%regions(k)%stress, comm)
      call bcast(cfg%regions(k)%stress_gradient, comm)
      call bcast(cfg%regions(k)%pore_pressure, comm)
      call bcast(cfg%regions(k)%pore_pressure_gradient, comm)
    end do
    do k = 1, n(4)
      call bcast(cfg%loads(k)%face, comm)
      call bcast(cfg%loads(k)%traction, comm)
      call bcast(cfg%loads(k)%ramp_time, comm)
    end do
    call bcast(cfg%bc, comm)
    call bcast(cfg%fluid_bc, comm)
    call bcast(cfg%pore_pressure, comm)
    call bcast(cfg%pore_pressure_ramp, comm)
    call bcast(cfg%output_dir, comm)
    call bcast(cfg%frame_interval, comm)
    call bcast(cfg%diag_every, comm)
    call bcast(cfg%checkpoint_every, comm)
    call bcast(cfg%compression, comm)
    call bcast(cfg%checkpoint_seconds, comm)
    call bcast(cfg%solid_fields, comm)
    call bcast(cfg%fluid_fields, comm)
    call bcast(cfg%benchmark, comm)
    call bcast(cfg%amplitude, comm)
  end subroutine bcast_config

  subroutine bcast_int(x, comm)
    integer, intent(inout) :: x
    type(MPI_Comm), intent(in) :: comm
    call MPI_Bcast(x, 1, MPI_INTEGER, 0, comm)
  end subroutine bcast_int

  subroutine bcast_int_1d(x, comm)
    integer, intent(inout) :: x(:)
    type(MPI_Comm), intent(in) :: comm
    call MPI_Bcast(x, size(x), MPI_INTEGER, 0, comm)
  end subroutine bcast_int_1d

  subroutine bcast_i8(x, comm)
    integer(i8), intent(inout) :: x
    type(MPI_Comm), intent(in) :: comm
    call MPI_Bcast(x, 1, mpi_i8(), 0, comm)
  end subroutine bcast_i8

  subroutine bcast_real(x, comm)
    real(wp), intent(inout) :: x
    type(MPI_Comm), intent(in) :: comm
    call MPI_Bcast(x, 1, mpi_wp(), 0, comm)
  end subroutine bcast_real

  subroutine bcast_real_1d(x, comm)
    real(wp), intent(inout) :: x(:)
    type(MPI_Comm), intent(in) :: comm
    call MPI_Bcast(x, size(x), mpi_wp(), 0, comm)
  end subroutine bcast_real_1d

  subroutine bcast_real_2d(x, comm)
    real(wp), intent(inout) :: x(:, :)
    type(MPI_Comm), intent(in) :: comm
    call MPI_Bcast(x, size(x), mpi_wp(), 0, comm)
  end subroutine bcast_real_2d

  subroutine bcast_logical(x, comm)
    logical, intent(inout) :: x
    type(MPI_Comm), intent(in) :: comm
    call MPI_Bcast(x, 1, MPI_LOGICAL, 0, comm)
  end subroutine bcast_logical

  subroutine bcast_str(x, comm)
    character(len=*), intent(inout) :: x
    type(MPI_Comm), intent(in) :: comm
    call MPI_Bcast(x, len(x), MPI_CHARACTER, 0, comm)
  end subroutine bcast_str

  ! ---------------------------------------------------------------------------------------------
  ! Text helpers
  ! ---------------------------------------------------------------------------------------------

  !> "  var = 'text'" with quotes doubled inside.
  subroutine put_s(unit, var, value)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: var, value
    write (unit, '(a)') '  '//var//' = '//quote(value)
  end subroutine put_s

  !> "  var = a, b, c" for reals.
  subroutine put_r(unit, var, values)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: values(:)
    write (unit, '(a)') '  '//var//' = '//rtoa_list(values)
  end subroutine put_r

  !> "  var = .true." or "  var = .false.".
  subroutine put_l(unit, var, value)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: var
    logical, intent(in) :: value
    write (unit, '(a)') '  '//var//' = '//trim(merge('.true. ', '.false.', value))
  end subroutine put_l

  !> "  var = a, b, c" for integers.
  subroutine put_i(unit, var, values)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: var
    integer, intent(in) :: values(:)
    write (unit, '(a)') '  '//var//' = '//itoa_list(values)
  end subroutine put_i

  !> A string in single quotes, trailing blanks removed, inner quotes doubled.
  pure function quote(s) result(q)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: q
    integer :: j
    q = "'"
    do j = 1, len_trim(s)
      q = q//s(j:j)
      if (s(j:j) == "'") q = q//"'"
    end do
    q = q//"'"
  end function quote

  !> "a, b, c" for reals.
  function rtoa_list(v) result(s)
    real(wp), intent(in) :: v(:)
    character(len=:), allocatable :: s
    integer :: j
    s = ''
    do j = 1, size(v)
      if (j > 1) s = s//', '
      s = s//rtoa(v(j))
    end do
  end function rtoa_list

  pure function itoa_list(v) result(s)
    integer, intent(in) :: v(:)
    character(len=:), allocatable :: s
    integer :: j
    s = ''
    do j = 1, size(v)
      if (j > 1) s = s//', '
      s = s//itoa(v(j))
    end do
  end function itoa_list

  !> The shortest decimal form of x that reads back to the same value: fixed notation for
  !> magnitudes in [1e-4, 1e6), otherwise mantissa and exponent ("2.5e-7", "1.0e6").
  function rtoa(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=40) :: buf
    character(len=12) :: fmt
    character(len=:), allocatable :: digits, sgn
    real(wp) :: y
    integer :: nd, e, ie, j
    if (ieee_is_nan(x)) then
      s = 'NaN'
      return
    else if (.not. ieee_is_finite(x)) then
      s = trim(merge('+Infinity', '-Infinity', x > 0.0_wp))
      return
    else if (x == 0.0_wp) then
      s = '0.0'
      return
    end if
    do nd = 1, 17
      write (fmt, '(a,i0,a)') '(es40.', nd - 1, 'e3)'
      write (buf, fmt) x
      read (buf, *) y
      if (y == x) exit
    end do
    buf = adjustl(buf)
    ie = index(buf, 'E')
    read (buf(ie + 1:), *) e
    sgn = trim(merge('-', ' ', buf(1:1) == '-'))
    digits = ''
    do j = 1, ie - 1
      if (scan(buf(j:j), '0123456789') == 1) digits = digits//buf(j:j)
    end do
    if (e >= -4 .and. e < 6) then
      if (e >= 0) then
        if (len(digits) < e + 1) digits = digits//repeat('0', e + 1 - len(digits))
        s = digits(1:e + 1)//'.'
        if (len(digits) > e + 1) then
          s = s//digits(e + 2:)
        else
          s = s//'0'
        end if
      else
        s = '0.'//repeat('0', -e - 1)//digits
      end if
    else
      s = digits(1:1)//'.'
      if (len(digits) > 1) then
        s = s//digits(2:)
      else
        s = s//'0'
      end if
      s = s//'e'//itoa(e)
    end if
    s = sgn//s
  end function rtoa

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

  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: j
    t = s
    do j = 1, len(s)
      if (s(j:j) >= 'A' .and. s(j:j) <= 'Z') t(j:j) = achar(iachar(s(j:j)) + 32)
    end do
  end function lower

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

end module dpmpm_input
