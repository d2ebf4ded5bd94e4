!> The resolved parameters of a run: types, defaults and names only (data, no I/O).
!> dpmpm_input (in io) fills a config_t (defaults first, then the file, then checks);
!> everything else only reads it.
module dpmpm_config
  use dpmpm_kinds, only: wp, i8
  use dpmpm_strings, only: next_word
  implicit none
  private
  public :: config_t, material_cfg_t, region_cfg_t, load_cfg_t, table_length
  public :: max_poly, max_table, name_len, face_names, face_index
  public :: bc_free, bc_fixed, bc_roller, bc_names
  public :: fbc_default, fbc_drained, fbc_impermeable, fbc_names
  public :: optional_fields, field_listed, porosity_varies, resolve_geostatic, region_levels, &
            level_unset

  integer, parameter :: name_len = 64
  !> Largest number of vertices of a 2D polygon region.
  integer, parameter :: max_poly = 64
  integer, parameter :: max_table = 64   !< entries of a load's time table
  !> Grid faces in the order used by every per-face array: x-, x+, y-, y+, z-, z+.
  character(len=2), parameter :: face_names(6) = ['x-', 'x+', 'y-', 'y+', 'z-', 'z+']
  !> surface and water_level of a region not given (a finite value, so that the echo of
  !> the input reads back)
  real(wp), parameter :: level_unset = -1.0e30_wp
  !> Boundary condition types on a grid face.
  integer, parameter :: bc_free = 0, bc_fixed = 1, bc_roller = 2
  character(len=6), parameter :: bc_names(0:2) = ['free  ', 'fixed ', 'roller']
  !> Conditions of the pore fluid on a grid face. Drained: the fluid may cross the
  !> face and the pore pressure there is prescribed (0 unless given); impermeable:
  !> the normal fluid velocity equals the normal solid velocity. The default is
  !> drained at free faces and impermeable at fixed and roller faces.
  integer, parameter :: fbc_default = 0, fbc_drained = 1, fbc_impermeable = 2
  character(len=11), parameter :: fbc_names(0:2) = ['default    ', 'drained    ', 'impermeable']

  !> One &material group.
  type :: material_cfg_t
    integer :: id = 1
    !> linear_elastic | neo_hookean | fluid | mohr_coulomb | drucker_prager | rigid
    character(len=name_len) :: model = 'linear_elastic'
    real(wp) :: density = 1000.0_wp          !< kg/m^3 (grain density of a soil, intrinsic)
    real(wp) :: youngs_modulus = 1.0e6_wp    !< Pa (of the skeleton)
    real(wp) :: poisson_ratio = 0.3_wp
    real(wp) :: bulk_modulus = 2.2e9_wp      !< Pa, fluid K_f (model fluid)
    real(wp) :: conductivity = 0.0_wp        !< m/s, hydraulic conductivity k of a soil; 0 = none
    !> constant | kozeny_carman (k scaled by n^3/(1-n)^2 against its value at the initial porosity)
    character(len=name_len) :: conductivity_law = 'constant'
    ! mohr_coulomb and drucker_prager (effective stress of the skeleton)
    real(wp) :: friction_angle = 30.0_wp     !< degrees, phi
    real(wp) :: dilatancy_angle = 0.0_wp     !< degrees, psi, 0 <= psi <= phi
    real(wp) :: cohesion = 0.0_wp            !< Pa, c0
    real(wp) :: tensile_strength = 0.0_wp    !< Pa, tension cut-off sigma_t
    real(wp) :: cohesion_softening = 0.0_wp  !< Pa, h in c = max(c_res, c0 - h epsp)
    real(wp) :: residual_cohesion = 0.0_wp   !< Pa, c_res
    character(len=name_len) :: dp_match = 'plane_strain' !< plane_strain | outer | inner
    real(wp) :: velocity(3) = 0.0_wp         !< m/s, model rigid: the body's prescribed velocity
  end type material_cfg_t

  !> One &region group: a box or a 2D polygon filled with points of one material.
  type :: region_cfg_t
    character(len=name_len) :: shape = 'box'       !< box | polygon
    real(wp) :: lo(3) = 0.0_wp, hi(3) = 0.0_wp       !< box corners (m)
    integer :: npoly = 0                             !< polygon vertex count
    real(wp) :: poly(2, max_poly) = 0.0_wp           !< polygon vertices (x, y)
    integer :: material = 1                          !< material id
    character(len=name_len) :: phase = 'solid'      !< solid | fluid | saturated
    integer :: fluid_material = 0                    !< material id of the pore fluid (saturated)
    !> initial porosity n_f: saturated soil, or dry porous soil in a solid region (0 = not porous)
    real(wp) :: porosity = 0.0_wp
    integer :: ppc = 2                               !< points per cell per direction
    !> regular | random (scattered in each cell) | uniform (scattered over the whole region)
    character(len=name_len) :: placement = 'regular'
    integer :: seed = 1                              !< seed of the random placement
    integer :: fluid_seed = -1                       !< seed of the fluid points; -1 = seed + 1
    real(wp) :: velocity(3) = 0.0_wp                 !< initial velocity (m/s)
    real(wp) :: stress(6) = 0.0_wp                   !< initial stress (Pa, Voigt, tension positive)
    !> d stress / d x_d (Pa/m): the initial stress at x is stress + sum_d stress_gradient(:, d) x_d
    real(wp) :: stress_gradient(6, 3) = 0.0_wp
    real(wp) :: pore_pressure = 0.0_wp               !< initial pore pressure at x = 0 (Pa)
    real(wp) :: pore_pressure_gradient(3) = 0.0_wp   !< its gradient (Pa/m)
    !> level ground at rest under gravity (along -axis ndim): the stress and pore pressure
    !> above come from the weight of the region (resolve_geostatic)
    logical :: geostatic = .false.
    real(wp) :: k0 = -1.0_wp                         !< sigma'_h / sigma'_v; < 0: nu / (1 - nu)
    real(wp) :: surface = level_unset                !< m, ground surface; default the region's top
    real(wp) :: water_level = level_unset            !< m, free water surface; default the surface
    real(wp) :: overburden = 0.0_wp                  !< Pa, vertical effective stress at the surface
  end type region_cfg_t

  !> One &load group: a traction on a grid face (or on the part lo..hi of it), times a
  !> function of time.
  type :: load_cfg_t
    integer :: face = 0                              !< index into face_names
    real(wp) :: traction(3) = 0.0_wp                 !< Pa, force per area on the body
    real(wp) :: ramp_time = 0.0_wp                   !< s; 0 = step load
    !> m; the load acts on lo(t) <= x(t) <= hi(t) along each axis t of the face with hi(t) > lo(t)
    real(wp) :: lo(3) = 0.0_wp, hi(3) = 0.0_wp
    character(len=name_len) :: time_function = 'ramp' !< ramp | sine | table
    real(wp) :: frequency = 0.0_wp                   !< Hz (sine)
    real(wp) :: duration = 0.0_wp                    !< s the sine lasts; 0 = for ever
    real(wp) :: times(max_table) = -1.0_wp           !< s (table; the entries >= 0, increasing)
    real(wp) :: factors(max_table) = 0.0_wp          !< the factor at each time (table)
    !> on the body's surface seen from face (its outermost nodes), not on the grid face
    logical :: surface = .false.
  end type load_cfg_t

  !> All parameters of a run.
  type :: config_t
    character(len=4096) :: input_file = ''
    character(len=:), allocatable :: input_text      !< the input file, echoed into the output
    !> Every group as read, defaults included, in the input's syntax (dpmpm --check prints it)
    character(len=:), allocatable :: echo
    ! &run
    character(len=name_len) :: name = 'dpmpm'        !< output file base name
    real(wp) :: t_end = 1.0_wp                       !< s
    real(wp) :: dt = 0.0_wp                          !< fixed step (s); 0 = from CFL every step
    real(wp) :: cfl = 0.5_wp                         !< Courant number
    integer(i8) :: max_steps = huge(1_i8)
    character(len=name_len) :: scheme = 'musl'       !< musl | usl
    real(wp) :: flip = 1.0_wp                        !< FLIP fraction of the FLIP/PIC blend
    real(wp) :: gravity(3) = 0.0_wp                  !< m/s^2
    real(wp) :: progress_seconds = 10.0_wp           !< wall seconds between progress lines
    !> wall seconds after which the run writes a checkpoint and stops; 0 = no limit
    real(wp) :: max_wall_time = 0.0_wp
    character(len=1024) :: restart = ''              !< checkpoint file to continue from
    ! two-phase coupling (&run)
    character(len=name_len) :: drag = 'explicit'     !< explicit | implicit (per-node 2x2 solve)
    real(wp) :: drag_safety = 0.8_wp                 !< fraction of the nodal drag limit (explicit)
    !> grad n_f term of the pressure equation; must be given where the porosity varies
    logical :: porosity_gradient = .false.
    logical :: porosity_gradient_given = .false.     !< porosity_gradient was set in &run
    !> Pa (gauge, compression positive): the pore pressure does not fall below it (the
    !> water cavitates); about minus the atmospheric pressure
    real(wp) :: cavitation_pressure = -1.0e5_wp
    !> none | cell: the pore-pressure change of a step smoothed over the fluid points of
    !> each cell
    character(len=name_len) :: pressure_smoothing = 'none'
    logical :: remap_drag = .true.                   !< MUSL: the step's implicit drag on the remapped pair
    ! run monitor (&run)
    real(wp) :: growth_limit = 10.0_wp               !< stop when energy exceeds this x (input + initial); 0 = off
    !> s of the equilibrium phase: gravity ramped over its first half, local damping
    !> (equilibrium_damping) throughout, the velocities set to zero at its end; 0 = none
    real(wp) :: equilibrium_time = 0.0_wp
    real(wp) :: equilibrium_damping = 0.8_wp         !< local damping coefficient alpha, in [0, 1)
    ! &grid
    integer :: ndim = 2
    integer :: ncells(3) = [1, 1, 1]
    real(wp) :: origin(3) = 0.0_wp
    real(wp) :: length(3) = [1.0_wp, 1.0_wp, 1.0_wp]
    integer :: dims(3) = [0, 0, 0]                   !< ranks per axis; 0 = MPI_Dims_create
    ! &shape: grid functions, and how velocities and the force-integral fields are
    ! reconstructed from the points (doc/input.md, doc/theory.md 3.3)
    character(len=name_len) :: kernel = 'linear'     !< grid functions: linear | quadratic | cubic
    character(len=name_len) :: velocity_kernel = ''  !< MLS weight of nodal velocities; '' = projection
    character(len=name_len) :: velocity_basis = 'constant'
    real(wp) :: velocity_radius = 0.0_wp             !< cells; 0 = tensor B-spline of natural support
    character(len=name_len) :: quadrature = 'points' !< points | gauss (force integrals)
    integer :: gauss_points = 2                      !< Gauss points per cell per axis
    character(len=name_len) :: field_kernel = 'wendland_c2' !< MLS weight of stress at Gauss points
    character(len=name_len) :: field_basis = 'constant'
    real(wp) :: field_radius = 2.0_wp                !< cells; 0 = tensor B-spline of natural support
    ! &material, &region, &load (repeatable)
    type(material_cfg_t), allocatable :: materials(:)
    type(region_cfg_t), allocatable :: regions(:)
    type(load_cfg_t), allocatable :: loads(:)
    ! &boundary: one type per face (face_names order)
    integer :: bc(6) = bc_free
    integer :: fluid_bc(6) = fbc_default             !< pore-fluid condition per face
    real(wp) :: pore_pressure(6) = 0.0_wp            !< Pa, prescribed on drained faces
    real(wp) :: pore_pressure_ramp(6) = 0.0_wp       !< s, linear ramp of pore_pressure; 0 = step
    !> Pa/m, gradient of a drained face's pore pressure along the face (a reservoir: rho_f g
    !> down); with it the pressure is pore_pressure + gradient . x, not below 0
    real(wp) :: pore_pressure_gradient(3, 6) = 0.0_wp
    !> condition 'absorbing': the material id whose impedance the face's dashpots match; 0 = none
    integer :: absorbing(6) = 0
    !> Coulomb friction coefficient of a roller face (a rough wall); 0 = smooth
    real(wp) :: wall_friction(6) = 0.0_wp
    ! &output
    character(len=1024) :: output_dir = '.'
    real(wp) :: frame_interval = 0.0_wp              !< s between frames; 0 = first and last only
    integer :: diag_every = 0                        !< steps between diagnostics; 0 = automatic
    integer :: checkpoint_every = 0                  !< steps between checkpoints; 0 = none
    real(wp) :: checkpoint_seconds = 0.0_wp          !< wall-clock s between checkpoints; 0 = none
    integer :: compression = 1                       !< gzip level (with shuffle) of frames; 0 = off
    character(len=256) :: solid_fields = 'all'       !< optional datasets of solid sets, or 'all'
    character(len=256) :: fluid_fields = 'all'       !< optional datasets of fluid sets, or 'all'
    ! &benchmark
    character(len=name_len) :: benchmark = 'none'   !< none | axial_bar | mms | biot_column | terzaghi
    real(wp) :: amplitude = 0.0_wp                   !< benchmark amplitude (m/s bar, m mms)
  end type config_t

  !> Datasets of a point set that &output solid_fields / fluid_fields may leave out (id, x, v,
  !> mass and volume are always written; porosity, pore_pressure and plastic_strain only
  !> where the set has them; a fluid set has no stress: its stress is -pore_pressure on the
  !> diagonal).
  character(len=*), parameter :: optional_fields(6) = [character(len=14) :: 'displacement', &
                                                       'stress', 'material', 'porosity', &
                                                       'pore_pressure', 'plastic_strain']

contains

  !> True when field is named in list (words separated by blanks or commas) or the list
  !> holds 'all' (unless explicit is true).
  pure logical function field_listed(list, field, explicit) result(yes)
    character(len=*), intent(in) :: list, field
    logical, intent(in), optional :: explicit
    logical :: all_counts
    integer :: i, j
    all_counts = .true.
    if (present(explicit)) all_counts = .not. explicit
    yes = .false.
    j = 0
    do
      call next_word(list, j + 1, i, j)
      if (i > j) exit
      if ((all_counts .and. list(i:j) == 'all') .or. list(i:j) == field) yes = .true.
    end do
  end function field_listed

  !> Index of a face name in face_names, 0 if unknown.
  pure integer function face_index(name)
    character(len=*), intent(in) :: name
    integer :: k
    face_index = 0
    do k = 1, 6
      if (trim(adjustl(name)) == face_names(k)) face_index = k
    end do
  end function face_index

  !> Entries of a load's time table: the leading times >= 0.
  !> Top of region r along the vertical axis ndim (box hi, or the highest polygon vertex).
  pure real(wp) function region_top(cfg, r) result(top)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: r
    associate (reg => cfg%regions(r))
      if (reg%shape == 'polygon' .and. cfg%ndim == 2) then
        top = maxval(reg%poly(2, 1:reg%npoly))
      else
        top = reg%hi(cfg%ndim)
      end if
    end associate
  end function region_top

  !> Ground surface s and water level w of region r: as given, or the region's top and
  !> the surface when left out.
  pure subroutine region_levels(cfg, r, s, w)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: r
    real(wp), intent(out) :: s, w
    s = cfg%regions(r)%surface
    if (s == level_unset) s = region_top(cfg, r)
    w = cfg%regions(r)%water_level
    if (w == level_unset) w = s
  end subroutine region_levels

  !> The initial state of the geostatic regions of level ground (doc/input.md, "Initial
  !> state"): with g = -gravity(ndim) along the vertical axis ndim, the surface S, water
  !> level W and overburden q of the region, the vertical effective stress
  !> sigma'_v = -(q + gamma (S - y)), the horizontal ones K0 sigma'_v, and in water and
  !> saturated soil the pore pressure p = rho_f g (W - y). gamma is the unit weight that
  !> loads the skeleton: (1 - n)(rho_s - rho_f) g in saturated soil (buoyant), (1 - n) rho_s g
  !> in dry soil, rho g in a body that is not porous. Writes stress, stress_gradient,
  !> pore_pressure and pore_pressure_gradient of each such region (checked by
  !> check_config: none of them given, gravity along -ndim only).
  subroutine resolve_geostatic(cfg)
    type(config_t), intent(inout) :: cfg
    integer :: r, a, m, mf, c
    real(wp) :: g, s, w, gam, k0, rhof, n
    if (.not. allocated(cfg%regions)) return
    a = cfg%ndim
    g = -cfg%gravity(a)
    do r = 1, size(cfg%regions)
      associate (reg => cfg%regions(r))
        if (.not. reg%geostatic) cycle
        call region_levels(cfg, r, s, w)
        m = findloc(cfg%materials%id, reg%material, dim=1)
        n = reg%porosity
        reg%stress = 0.0_wp
        reg%stress_gradient = 0.0_wp
        reg%pore_pressure = 0.0_wp
        reg%pore_pressure_gradient = 0.0_wp
        rhof = 0.0_wp
        select case (trim(reg%phase))
        case ('fluid')
          rhof = cfg%materials(m)%density
          gam = 0.0_wp
        case ('saturated')
          mf = findloc(cfg%materials%id, reg%fluid_material, dim=1)
          rhof = cfg%materials(mf)%density
          gam = (1.0_wp - n)*(cfg%materials(m)%density - rhof)*g
        case default
          gam = (1.0_wp - n)*cfg%materials(m)%density*g
        end select
        if (rhof > 0.0_wp) then
          reg%pore_pressure = rhof*g*w
          reg%pore_pressure_gradient(a) = -rhof*g
        end if
        if (trim(reg%phase) == 'fluid') cycle
        k0 = reg%k0
        if (k0 < 0.0_wp) k0 = cfg%materials(m)%poisson_ratio/(1.0_wp - cfg%materials(m)%poisson_ratio)
        do c = 1, 3
          reg%stress(c) = -(reg%overburden + gam*s)*merge(1.0_wp, k0, c == a)
          reg%stress_gradient(c, a) = gam*merge(1.0_wp, k0, c == a)
        end do
      end associate
    end do
  end subroutine resolve_geostatic

  !> True when the initial porosity differs between the regions of a two-phase scene:
  !> free water (n = 1) beside porous soil, or porous regions of different porosity.
  !> Bodies that are not porous (solid, porosity 0) take no part.
  pure logical function porosity_varies(cfg) result(varies)
    type(config_t), intent(in) :: cfg
    real(wp) :: n, first
    logical :: have
    integer :: r
    varies = .false.
    have = .false.
    first = 0.0_wp
    if (.not. allocated(cfg%regions)) return
    do r = 1, size(cfg%regions)
      select case (trim(cfg%regions(r)%phase))
      case ('fluid')
        n = 1.0_wp
      case ('saturated')
        n = cfg%regions(r)%porosity
      case default
        n = cfg%regions(r)%porosity
        if (.not. n > 0.0_wp) cycle
      end select
      if (.not. have) then
        first = n
        have = .true.
      else if (n /= first) then
        varies = .true.
      end if
    end do
    if (.not. any(cfg%regions%phase == 'fluid' .or. cfg%regions%phase == 'saturated')) &
      varies = .false.
  end function porosity_varies

  pure integer function table_length(times) result(n)
    real(wp), intent(in) :: times(:)
    n = 0
    do while (n < size(times))
      if (times(n + 1) < 0.0_wp) exit
      n = n + 1
    end do
  end function table_length

end module dpmpm_config
