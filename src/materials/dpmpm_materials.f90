!> Constitutive models behind one interface. The model is chosen per material
!> group of points, not per point: each update routine loops over the points of
!> one material. Stress is Cauchy, tension positive, Voigt order xx yy zz yz xz xy.
!> The models are the lines of dpmpm_model_table, each in a module of its own with the
!> interface model_update below; stress_update dispatches to them (to a user's UMAT,
!> dpmpm_model_umat, with the few arguments more that only a UMAT reads).
module dpmpm_materials
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: material_cfg_t
  use dpmpm_model_table, only: model_linear_elastic, model_neo_hookean, model_fluid, &
                               model_mohr_coulomb, model_drucker_prager, model_rigid, &
                               model_cam_clay, model_umat, model_from_name, is_plastic, &
                               model_sanisand, &
                               is_pressure_dependent, material_nstate
  use dpmpm_model_table, only: model_mu_i
  use dpmpm_material_params, only: material_t
  use dpmpm_plasticity, only: plastic_setup, dp_match_names, dp_plane_strain, &
                              surface_mohr_coulomb, surface_drucker_prager
  use dpmpm_model_elastic, only: elastic_update
  use dpmpm_model_neo_hookean, only: neo_hookean_update
  use dpmpm_model_plastic, only: plastic_update
  use dpmpm_model_cam_clay, only: cam_clay_update, cam_clay_init_state, cam_clay_moduli, &
                                  cam_clay_energy
  use dpmpm_model_umat, only: umat_update, umat_init_state
  use dpmpm_model_sanisand, only: sanisand_update, sanisand_init_state, sanisand_moduli, &
                                  sanisand_energy
  use dpmpm_model_mu_i, only: mu_i_update
  use dpmpm_tensor, only: as_3x3, det3
  implicit none
  private
  public :: material_t, model_linear_elastic, model_neo_hookean, model_fluid, model_from_name
  public :: model_mohr_coulomb, model_drucker_prager, model_rigid, model_cam_clay, is_plastic
  public :: model_umat, model_sanisand
  public :: model_mu_i
  public :: materials_from_config, stress_update, strain_energy, wave_speed, wave_speeds
  public :: model_update, init_state, point_moduli

  !> The interface of every model's update (elastic_update, neo_hookean_update,
  !> plastic_update, ...): stress, volume, and where the model keeps them the deformation
  !> gradient defgrad(9, :) and the state values state(nstate, :) of the points of material
  !> index m (pmat(p) == m) over one step dt, from each point's velocity gradient
  !> vgrad(9, :) (3x3, column-major); dissipation gains the plastic work of the step;
  !> plane (2D, plane strain): the velocity gradients and F have no third row and column.
  abstract interface
    subroutine model_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                            dissipation, plane)
      import :: wp, material_t
      type(material_t), intent(in) :: mat
      integer, intent(in) :: m, n
      real(wp), intent(in) :: dt
      integer, intent(in) :: pmat(:)
      real(wp), intent(in) :: vgrad(:, :)
      real(wp), intent(inout) :: stress(:, :), vol(:)
      real(wp), intent(in) :: vol0(:)
      real(wp), intent(inout), optional :: defgrad(:, :), state(:, :)
      real(wp), intent(inout), optional :: dissipation
      logical, intent(in), optional :: plane
    end subroutine model_update
  end interface

contains

  !> Materials with Lame constants from E and nu.
  subroutine materials_from_config(cfgs, mats)
    type(material_cfg_t), intent(in) :: cfgs(:)
    type(material_t), allocatable, intent(out) :: mats(:)
    integer :: k, match
    real(wp) :: e, nu
    allocate (mats(size(cfgs)))
    do k = 1, size(cfgs)
      e = cfgs(k)%youngs_modulus
      nu = cfgs(k)%poisson_ratio
      mats(k)%id = cfgs(k)%id
      mats(k)%model = model_from_name(cfgs(k)%model)
      mats(k)%density = cfgs(k)%density
      mats(k)%youngs = e
      mats(k)%poisson = nu
      mats(k)%lambda = e*nu/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
      mats(k)%mu = e/(2.0_wp*(1.0_wp + nu))
      mats(k)%bulk = e/(3.0_wp*(1.0_wp - 2.0_wp*nu))
      mats(k)%pwave = mats(k)%lambda + 2.0_wp*mats(k)%mu
      mats(k)%bulk_fluid = cfgs(k)%bulk_modulus
      mats(k)%conductivity = cfgs(k)%conductivity
      mats(k)%kozeny_carman = cfgs(k)%conductivity_law == 'kozeny_carman'
      if (mats(k)%model == model_mohr_coulomb .or. mats(k)%model == model_drucker_prager) then
        match = findloc(dp_match_names, trim(cfgs(k)%dp_match), dim=1)
        if (match == 0) match = dp_plane_strain
        mats(k)%plastic = plastic_setup(merge(surface_mohr_coulomb, surface_drucker_prager, &
                                              mats(k)%model == model_mohr_coulomb), &
                                        mats(k)%bulk, mats(k)%mu, cfgs(k)%friction_angle, &
                                        cfgs(k)%dilatancy_angle, cfgs(k)%cohesion, &
                                        cfgs(k)%tensile_strength, cfgs(k)%cohesion_softening, &
                                        cfgs(k)%residual_cohesion, match)
        mats(k)%max_dilation = cfgs(k)%max_dilation
      end if
      if (mats(k)%model == model_fluid) then
        mats(k)%lambda = 0.0_wp; mats(k)%mu = 0.0_wp; mats(k)%pwave = 0.0_wp
        mats(k)%bulk = cfgs(k)%bulk_modulus
      end if
      if (mats(k)%model == model_cam_clay) then
        mats(k)%cc_lambda = cfgs(k)%compression_index
        mats(k)%cc_kappa = cfgs(k)%swelling_index
        mats(k)%cc_m = cfgs(k)%critical_state_ratio
        mats(k)%cc_e0 = cfgs(k)%void_ratio
        mats(k)%cc_pc0 = cfgs(k)%preconsolidation_pressure
        mats(k)%cc_ocr = cfgs(k)%ocr
        mats(k)%cc_shear = cfgs(k)%shear_modulus
        mats(k)%cc_min_pressure = cfgs(k)%min_pressure
        ! the stiffness follows the pressure: each point's own (point_moduli)
        mats(k)%youngs = 0.0_wp
        mats(k)%lambda = 0.0_wp; mats(k)%mu = 0.0_wp; mats(k)%pwave = 0.0_wp
        mats(k)%bulk = 0.0_wp
      end if
      if (mats(k)%model == model_sanisand) then
        mats(k)%sd_g0 = cfgs(k)%shear_constant
        mats(k)%sd_mc = cfgs(k)%critical_state_ratio
        mats(k)%sd_c = cfgs(k)%extension_ratio
        mats(k)%sd_lc = cfgs(k)%csl_lambda
        mats(k)%sd_ec0 = cfgs(k)%csl_void_ratio
        mats(k)%sd_xi = cfgs(k)%csl_exponent
        mats(k)%sd_m = cfgs(k)%yield_radius
        mats(k)%sd_h0 = cfgs(k)%hardening_h0
        mats(k)%sd_ch = cfgs(k)%hardening_ch
        mats(k)%sd_nb = cfgs(k)%bounding_nb
        mats(k)%sd_a0 = cfgs(k)%dilatancy_a0
        mats(k)%sd_nd = cfgs(k)%dilatancy_nd
        mats(k)%sd_zmax = cfgs(k)%fabric_zmax
        mats(k)%sd_cz = cfgs(k)%fabric_cz
        mats(k)%sd_pat = cfgs(k)%atmospheric_pressure
        mats(k)%sd_e0 = cfgs(k)%void_ratio
        mats(k)%sd_pmin = cfgs(k)%pressure_floor
        mats(k)%sd_tol = cfgs(k)%integration_tolerance
        ! the stiffness follows the pressure: each point's own (point_moduli)
        mats(k)%youngs = 0.0_wp
        mats(k)%lambda = 0.0_wp; mats(k)%mu = 0.0_wp; mats(k)%pwave = 0.0_wp
        mats(k)%bulk = 0.0_wp
      end if
      if (mats(k)%model == model_mu_i) then
        mats(k)%mui_mu_s = cfgs(k)%mu_s
        mats(k)%mui_mu_2 = cfgs(k)%mu_2
        mats(k)%mui_i0 = cfgs(k)%i_0
        mats(k)%mui_diameter = cfgs(k)%grain_diameter
        mats(k)%mui_grain_density = cfgs(k)%grain_density
        mats(k)%max_dilation = cfgs(k)%max_dilation
        if (mats(k)%mui_grain_density == 0.0_wp) mats(k)%mui_grain_density = cfgs(k)%density
        mats(k)%mui_k = cfgs(k)%dilatancy_k
        mats(k)%mui_phic = cfgs(k)%critical_fraction
        mats(k)%mui_slope = cfgs(k)%fraction_slope
        mats(k)%mui_phi0 = cfgs(k)%volume_fraction
        if (mats(k)%mui_phi0 == 0.0_wp) mats(k)%mui_phi0 = cfgs(k)%density/mats(k)%mui_grain_density
      end if
      mats(k)%nstate = material_nstate(mats(k)%model, cfgs(k)%umat_nstatev)
      if (mats(k)%model == model_umat) then
        ! youngs_modulus and poisson_ratio: the stiffest the UMAT gets, for the time step
        mats(k)%umat_props = cfgs(k)%umat_props
        mats(k)%umat_nprops = cfgs(k)%umat_nprops
        mats(k)%umat_nstatev = cfgs(k)%umat_nstatev
        mats(k)%umat_name = cfgs(k)%umat_name
      end if
      if (mats(k)%model == model_rigid) then
        ! no stress (stress_update and strain_energy leave it out) and no wave to resolve
        mats(k)%lambda = 0.0_wp; mats(k)%mu = 0.0_wp; mats(k)%pwave = 0.0_wp
        mats(k)%velocity = cfgs(k)%velocity
        mats(k)%vibration_amplitude = cfgs(k)%vibration_amplitude
        mats(k)%vibration_omega = 2.0_wp*acos(-1.0_wp)*cfgs(k)%vibration_frequency
        mats(k)%motion_times = cfgs(k)%motion_times
        mats(k)%motion_factors = cfgs(k)%motion_factors
      end if
    end do
  end subroutine materials_from_config

  !> Speed of the fastest (dilatational) wave at current density rho.
  pure real(wp) function wave_speed(mat, rho) result(c)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: rho
    c = sqrt(mat%pwave/rho)
  end function wave_speed

  !> wave_speed of n points of materials mats(pmat(:)) at density mass / vol, in c
  !> (the same formula; the time step's scan takes them in chunks). With the points' stress
  !> and state, a model whose stiffness follows the pressure takes each point's modulus
  !> (point_moduli).
  pure subroutine wave_speeds(mats, n, pmat, mass, vol, c, stress, state)
    type(material_t), intent(in) :: mats(:)
    integer, intent(in) :: n, pmat(:)
    real(wp), intent(in) :: mass(:), vol(:)
    real(wp), intent(out) :: c(:)
    real(wp), intent(in), optional :: stress(:, :), state(:, :)
    integer :: p
    ! (the moduli gathered first, so that the loop of roots vectorises)
    if (present(stress)) then
      call point_moduli(mats, n, pmat, stress, state, c)
    else
      do p = 1, n
        c(p) = mats(pmat(p))%pwave
      end do
    end if
    do p = 1, n
      c(p) = sqrt(c(p)/(mass(p)/vol(p)))
    end do
  end subroutine wave_speeds

  !> Update stress, volume and the state of the points of material index m over one step
  !> dt (model_update's arguments): the update of mat%model. The fluid and a rigid body
  !> have no stress to update. In a saturated soil this is the effective stress.
  subroutine stress_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                           dissipation, plane, time, step, x, ids, celent)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    real(wp), intent(in) :: dt
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: vgrad(:, :)
    real(wp), intent(inout) :: stress(:, :), vol(:)
    real(wp), intent(in) :: vol0(:)
    real(wp), intent(inout), optional :: defgrad(:, :), state(:, :)
    real(wp), intent(inout), optional :: dissipation
    logical, intent(in), optional :: plane
    !> for a umat only (TIME, KINC, COORDS, NOEL, CELENT; zero where absent): the time at
    !> the start of the step, the steps done, the points' positions and ids, the cell size
    real(wp), intent(in), optional :: time, celent
    integer(i8), intent(in), optional :: step, ids(:)
    real(wp), intent(in), optional :: x(:, :)
    select case (mat%model)
    case (model_linear_elastic)
      call elastic_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                          dissipation, plane)
    case (model_neo_hookean)
      call neo_hookean_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                              dissipation, plane)
    case (model_mohr_coulomb, model_drucker_prager)
      call plastic_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                          dissipation, plane)
    case (model_cam_clay)
      call cam_clay_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                           dissipation, plane)
    case (model_sanisand)
      call sanisand_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                           dissipation, plane)
    case (model_umat)
      call umat_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                       dissipation, plane, time, step, x, ids, celent)
    case (model_mu_i)
      call mu_i_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                       dissipation, plane)
    end select
  end subroutine stress_update

  !> The initial state values of the points of material index m from their initial stress
  !> (after the geostatic start; a restart reads them instead): 0 for every model but
  !> cam_clay (its preconsolidation pressure and void ratio), sanisand (alpha and alpha_in
  !> from the stress ratio, the void ratio) and umat (from a first call of the UMAT with a
  !> zero increment, dpmpm_model_umat's umat_init_state).
  subroutine init_state(mat, m, n, pmat, stress, state, x, ids)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: stress(:, :)
    real(wp), intent(inout) :: state(:, :)
    !> for a umat only: the points' positions and ids (COORDS and NOEL of its first call)
    real(wp), intent(in), optional :: x(:, :)
    integer(i8), intent(in), optional :: ids(:)
    select case (mat%model)
    case (model_cam_clay)
      call cam_clay_init_state(mat, m, n, pmat, stress, state)
    case (model_sanisand)
      call sanisand_init_state(mat, m, n, pmat, stress, state)
    case (model_umat)
      call umat_init_state(mat, m, n, pmat, stress, state, x, ids)
    end select
  end subroutine init_state

  !> The constrained modulus K + 4G/3 of each of n points (materials mats(pmat(:))) in pw:
  !> the material's, or for a model whose stiffness follows the pressure, the one at the
  !> point's stress and state.
  pure subroutine point_moduli(mats, n, pmat, stress, state, pw)
    type(material_t), intent(in) :: mats(:)
    integer, intent(in) :: n, pmat(:)
    real(wp), intent(in) :: stress(:, :)
    real(wp), intent(in), optional :: state(:, :)
    real(wp), intent(out) :: pw(:)
    real(wp) :: k, g
    integer :: p
    do p = 1, n
      pw(p) = mats(pmat(p))%pwave
    end do
    if (.not. any(is_pressure_dependent(mats%model))) return
    do p = 1, n
      select case (mats(pmat(p))%model)
      case (model_cam_clay)
        call cam_clay_moduli(mats(pmat(p)), -(stress(1, p) + stress(2, p) + stress(3, p))/3.0_wp, &
                             state(2, p), k, g)
      case (model_sanisand)
        call sanisand_moduli(mats(pmat(p)), -(stress(1, p) + stress(2, p) + stress(3, p))/3.0_wp, &
                             state(19, p), k, g)
      case default
        cycle
      end select
      pw(p) = k + 4.0_wp*g/3.0_wp
    end do
  end subroutine point_moduli

  !> Stored elastic energy of the points of material index m (J, per unit
  !> length/area in 2D/1D). Linear elastic (and the elastic part of the plastic soils):
  !> sigma : C^-1 : sigma / 2 times volume;
  !> neo-Hookean: (mu/2)(tr C - 3) - mu ln J + (lambda/2) (ln J)^2 per reference volume;
  !> umat: the UMAT's SSE times the volume.
  pure real(wp) function strain_energy(mat, m, n, pmat, stress, vol, vol0, defgrad, state) &
    result(e)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: stress(:, :), vol(:), vol0(:)
    real(wp), intent(in), optional :: defgrad(:, :), state(:, :)
    real(wp) :: s(6), tr, w, f(3, 3), lnj
    integer :: p
    e = 0.0_wp
    do p = 1, n
      if (pmat(p) /= m) cycle
      select case (mat%model)
      case (model_linear_elastic, model_mohr_coulomb, model_drucker_prager, model_mu_i)
        s = stress(:, p)
        tr = s(1) + s(2) + s(3)
        ! sigma : eps with eps = ((1+nu) sigma - nu tr(sigma) I)/E; shear terms count twice.
        w = ((1.0_wp + mat%poisson)*(sum(s(1:3)**2) + 2.0_wp*sum(s(4:6)**2)) - mat%poisson*tr**2) &
            /mat%youngs
        e = e + 0.5_wp*w*vol(p)
      case (model_neo_hookean)
        f = as_3x3(defgrad(:, p))
        lnj = log(det3(f))
        w = 0.5_wp*mat%mu*(sum(f**2) - 3.0_wp) - mat%mu*lnj + 0.5_wp*mat%lambda*lnj**2
        e = e + w*vol0(p)
      case (model_cam_clay)
        e = e + cam_clay_energy(mat, stress(:, p), state(2, p), vol(p))
      case (model_sanisand)
        e = e + sanisand_energy(mat, stress(:, p), state(19, p), vol(p))
      case (model_umat)
        ! the UMAT's SSE, per unit volume (dpmpm_model_umat)
        e = e + state(7, p)*vol(p)
      end select
    end do
  end function strain_energy

end module dpmpm_materials
