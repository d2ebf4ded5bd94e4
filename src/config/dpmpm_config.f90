!> The resolved parameters of a run: types, defaults and names only (data, no I/O).
!> dpmpm_input (in io) fills a config_t (defaults first, then the file, then checks);
!> everything else only reads it.
module dpmpm_config
  use dpmpm_kinds, only: wp, i8
  use dpmpm_strings, only: next_word
  implicit none
  private
  public :: config_t, material_cfg_t, region_cfg_t, load_cfg_t, table_length, table_factor, motion_series_t
  public :: max_poly, max_table, max_props, max_probes, name_len, face_names, face_index
  public :: bc_free, bc_fixed, bc_roller, bc_names
  public :: fbc_default, fbc_drained, fbc_impermeable, fbc_names
  public :: optional_fields, field_listed, porosity_varies, resolve_geostatic, region_levels, &
            level_unset

  integer, parameter :: name_len = 64
  !> Largest number of vertices of a 2D polygon region.
  integer, parameter :: max_poly = 64
  integer, parameter :: max_table = 64   !< entries of a load's time table
  integer, parameter :: max_props = 64   !< values of a material's umat_props (PROPS of a UMAT)
  integer, parameter :: max_probes = 16  !< points of &output whose records are kept (probes)
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

  !> One &material group (its variables: dpmpm_vars_material.inc).
  type :: material_cfg_t
    include "dpmpm_vars_material_component.inc"
    integer :: umat_nprops = 0                       !< umat_props given (NPROPS of a UMAT)
  end type material_cfg_t

  !> One &region group: a box or a 2D polygon filled with points of one material.
  type :: region_cfg_t
    include "dpmpm_vars_region_component.inc"
    real(wp) :: poly(2, max_poly) = 0.0_wp           !< polygon vertices (x, y): poly_x, poly_y
    integer :: line = 0                              !< line of the input where the group opens
  end type region_cfg_t

  !> One &load group: a traction on a grid face (or on the part lo..hi of it), times a
  !> function of time.
  type :: load_cfg_t
    integer :: face = 0                              !< index into face_names
    include "dpmpm_vars_load_component.inc"
    integer :: nfactors = 0                          !< factors given (one per time of a table)
  end type load_cfg_t

  !> One axis of a ground motion as read from its file (dpmpm_motion): the times (s, increasing)
  !> and the acceleration (m/s^2), velocity (m/s) and displacement (m) at each, scaled and
  !> baseline-corrected. No times: no motion along the axis.
  type :: motion_series_t
    real(wp), allocatable :: t(:), a(:), v(:), d(:)
  end type motion_series_t

  !> All parameters of a run.
  type :: config_t
    character(len=4096) :: input_file = ''
    character(len=:), allocatable :: input_text      !< the input file, echoed into the output
    !> Every group as read, defaults included, in the input's syntax (dpmpm --check prints it)
    character(len=:), allocatable :: echo
    ! &run, &grid, &shape, &output and &benchmark: dpmpm_vars_<group>.inc
    include "dpmpm_vars_run_component.inc"
    logical :: porosity_gradient_given = .false.     !< porosity_gradient was set in &run
    include "dpmpm_vars_grid_component.inc"
    include "dpmpm_vars_shape_component.inc"
    include "dpmpm_vars_output_component.inc"
    include "dpmpm_vars_benchmark_component.inc"
    include "dpmpm_vars_motion_component.inc"
    !> the &motion files as read (rank 0 reads them, every rank gets them): one per axis
    type(motion_series_t) :: motion(3)
    ! &material, &region, &load (repeatable)
    type(material_cfg_t), allocatable :: materials(:)
    type(region_cfg_t), allocatable :: regions(:)
    type(load_cfg_t), allocatable :: loads(:)
    ! &boundary: one type per face (face_names order)
    integer :: bc(6) = bc_free
    !> tied faces (condition = 'tied', both faces of an axis): free to the grid, their nodes
    !> at the same place along the face move together (dpmpm_tied_sides)
    logical :: tied(6) = .false.
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
    !> a rough wall lets go of nodes that move away from it (scenes of one phase); .false.
    !> holds them, so that the wall also pulls
    logical :: wall_lift_off(6) = .true.
    !> an opening in a fixed or roller face (&boundary opening_lo, opening_hi): the face
    !> does not hold its nodes strictly inside the box opening_lo..opening_hi (the
    !> components along the face; the normal one is not used), and points that cross the
    !> face there leave the model (dpmpm_walls, doc/input.md "Openings")
    logical :: has_opening(6) = .false.
    real(wp) :: opening_lo(3, 6) = 0.0_wp, opening_hi(3, 6) = 0.0_wp
  end type config_t

  !> Datasets of a point set that &output solid_fields / fluid_fields may leave out (id, x, v,
  !> mass and volume are always written; porosity, pore_pressure and state only where the
  !> set has them; a fluid set has no stress: its stress is -pore_pressure on the diagonal).
  !> state: the state values of the constitutive models, one dataset each, named by the
  !> model table (plastic_strain of mohr_coulomb and drucker_prager).
  !> ('rank', the rank that held the point, is written only where named: it differs between
  !> rank counts, and 'all' stands for the fields of the physics)
  character(len=*), parameter :: optional_fields(7) = [character(len=14) :: 'displacement', &
                                                       'stress', 'material', 'porosity', &
                                                       'pore_pressure', 'state', 'rank']

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

  !> The factor of a time table at time t: factors interpolated linearly between its
  !> times, the first factor before the first time and the last after the last (the
  !> table's entries are those before the first negative time, table_length; at least one).
  pure real(wp) function table_factor(times, factors, t) result(r)
    real(wp), intent(in) :: times(:), factors(:), t
    integer :: n, i
    n = table_length(times)
    if (t <= times(1)) then
      r = factors(1)
    else if (t >= times(n)) then
      r = factors(n)
    else
      i = 1
      do while (times(i + 1) < t)
        i = i + 1
      end do
      r = factors(i) + (factors(i + 1) - factors(i))*(t - times(i))/(times(i + 1) - times(i))
    end if
  end function table_factor

end module dpmpm_config
