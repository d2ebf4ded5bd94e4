!> Checks of the &material groups: each model's parameters against what they may be
!> (the model names from dpmpm_model_table), and a warning for each variable given to a
!> material whose model does not read it. The scene-level checks of a rigid body, which
!> need the regions and the shape choice, stay in dpmpm_input_check.
module dpmpm_input_check_material
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: material_cfg_t, config_t, table_length
  use dpmpm_model_table, only: model_from_name, model_names
  use dpmpm_plasticity, only: plastic_params_t, plastic_setup, softening_limit, dp_match_names, &
                              dp_plane_strain, surface_mohr_coulomb, surface_drucker_prager
  use dpmpm_input_problems, only: input_problems_t, g_material, add_value, add_warning, real_ok, &
                                  check_finite
  use dpmpm_strings, only: itoa, rtoa, rtoa_list, quote
  implicit none
  private
  public :: check_material, warn_weightless_cutoff, check_contact_scene

contains

  !> A tension cut-off at zero (mohr_coulomb, drucker_prager) in a scene without gravity:
  !> near a free surface the grid's swings of stress open points that nothing closes again,
  !> and the surface keeps rising (doc/verification.md, "Tension cut-off: opening without
  !> work"). used: some region is made of material k.
  subroutine warn_weightless_cutoff(pb, k, m, gravity, used)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    real(wp), intent(in) :: gravity(:)
    logical, intent(in) :: used
    if (.not. used .or. any(gravity /= 0.0_wp) .or. m%tensile_strength /= 0.0_wp) return
    if (m%model /= 'mohr_coulomb' .and. m%model /= 'drucker_prager') return
    call add_warning(pb, g_material, k, 'tensile_strength', rtoa(m%tensile_strength), &
                     'weightless soil without tension has no rest state at a free surface that '// &
                     'is pushed: the grid''s swings of stress open points there that nothing closes '// &
                     'again (beside a footing pushed past failure the kinetic energy grew to 35 J/m '// &
                     'in 1.5 s; a tensile_strength of c/25 kept it at 1-2 J/m, gravity as well); give '// &
                     'a small tensile_strength where no tension is not what the scene is about '// &
                     '(doc/verification.md, "Tension cut-off: opening without work")')
  end subroutine warn_weightless_cutoff

  !> Check &material k of mats: its model, density, velocity, the parameters its model reads,
  !> the variables it does not read (warnings), and its id against the groups before it.
  subroutine check_material(pb, mats, k)
    type(input_problems_t), intent(inout) :: pb
    type(material_cfg_t), intent(in) :: mats(:)
    integer, intent(in) :: k
    integer :: j
    associate (m => mats(k))
      if (model_from_name(m%model) == 0) call add_value(pb, g_material, k, 'model', &
      quote(m%model), 'the models are '//model_names())
      if (.not. real_ok(m%density, gt=0.0_wp)) call add_value(pb, g_material, k, 'density', &
      rtoa(m%density), 'must be > 0 (kg/m^3)')
      call check_finite(pb, g_material, k, 'velocity', m%velocity)
      if (any(m%velocity /= 0.0_wp) .and. m%model /= 'rigid') call add_value(pb, g_material, &
      k, 'velocity', rtoa_list(m%velocity), "only a rigid body (model = 'rigid') has a "// &
      'prescribed velocity; give a moving body its initial velocity in &region velocity')
      call check_vibration(pb, k, m)
      call check_contact(pb, k, m)
      ! (a rigid body: only density and velocity matter; the scene checks it, check_rigid)
      if (m%model == 'fluid') then
        ! A linear compressible fluid: only density and bulk_modulus matter.
        if (.not. real_ok(m%bulk_modulus, gt=0.0_wp)) call add_value(pb, g_material, k, &
        'bulk_modulus', rtoa(m%bulk_modulus), 'must be > 0 (Pa) for a fluid')
      else if (m%model == 'cam_clay') then
        call check_cam_clay(pb, k, m)
      else if (m%model == 'sanisand') then
        call check_sanisand(pb, k, m)
      else if (m%model /= 'rigid') then
        if (m%model == 'umat') call check_umat(pb, k, m)
        if (m%model == 'mu_i') call check_mu_i(pb, k, m)
        if (.not. real_ok(m%youngs_modulus, gt=0.0_wp)) call add_value(pb, g_material, k, &
        'youngs_modulus', rtoa(m%youngs_modulus), 'must be > 0 (Pa)')
        if (.not. real_ok(m%poisson_ratio, gt=-1.0_wp, lt=0.5_wp)) call add_value(pb, &
        g_material, k, 'poisson_ratio', rtoa(m%poisson_ratio), &
        'must be in (-1, 0.5): 0.5 is incompressible, which these models cannot represent')
      end if
      if (.not. real_ok(m%conductivity, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'conductivity', rtoa(m%conductivity), 'must be >= 0 (m/s; 0 = no pore fluid flow)')
      if (.not. any(m%conductivity_law == [character(len=13) :: 'constant', 'kozeny_carman'])) &
      call add_value(pb, g_material, k, 'conductivity_law', quote(m%conductivity_law), &
                     'the laws are constant, kozeny_carman (k = conductivity n^3 (1 - n0)^2 / '// &
                     '((1 - n)^2 n0^3) at porosity n, initial porosity n0)')
      call check_unused_material(pb, k, m)
      if (m%model == 'mohr_coulomb' .or. m%model == 'drucker_prager') then
        call check_plastic(pb, k, m)
      else if (m%model == 'mu_i') then
        call check_max_dilation(pb, k, m)
      else if (m%max_dilation /= 0.0_wp) then
        call add_value(pb, g_material, k, 'max_dilation', rtoa(m%max_dilation), &
                     'only a mohr_coulomb, drucker_prager or mu_i soil has this bound; leave it 0')
      end if
      do j = 1, k - 1
        if (mats(j)%id == m%id) then
          call add_value(pb, g_material, k, 'id', itoa(m%id), &
                       'ids must be unique; &material number '//itoa(j)//' has it already')
          exit
        end if
      end do
    end associate
  end subroutine check_material

  !> The variables of material k that its model does not use, given with another value than
  !> the default: a warning each (a friction angle on an elastic material, a Young's
  !> modulus on a fluid).
  subroutine check_unused_material(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    type(material_cfg_t) :: d
    logical :: plastic, skeleton
    character(len=:), allocatable :: why
    if (model_from_name(m%model) == 0) return
    why = 'does nothing with model = '//quote(m%model)
    if (m%model == 'cam_clay') then
      if (m%youngs_modulus /= d%youngs_modulus) call add_warning(pb, g_material, k, &
        'youngs_modulus', rtoa(m%youngs_modulus), why//' (its stiffness follows the pressure: '// &
        'swelling_index, with poisson_ratio or shear_modulus)')
    else if (m%model == 'sanisand') then
      if (m%youngs_modulus /= d%youngs_modulus) call add_warning(pb, g_material, k, &
        'youngs_modulus', rtoa(m%youngs_modulus), why//' (its stiffness follows the pressure: '// &
        'shear_constant, with poisson_ratio)')
      call warn_cam_clay_only(pb, k, m, d, why//" (only 'cam_clay' takes it)")
    else
      call warn_cam_clay_variables(pb, k, m, d, why//" (only 'cam_clay' takes it)")
    end if
    if (m%model /= 'sanisand') call warn_sanisand_variables(pb, k, m, d, &
                                                          why//" (only 'sanisand' takes it)")
    if (m%model /= 'umat') call warn_umat_variables(pb, k, m, d, why//" (only 'umat' takes it)")
    if (m%model /= 'mu_i') call warn_mu_i_variables(pb, k, m, d, why//" (only 'mu_i' takes it)")
    plastic = m%model == 'mohr_coulomb' .or. m%model == 'drucker_prager'
    skeleton = m%model /= 'fluid' .and. m%model /= 'rigid'
    if (.not. skeleton) then
      if (m%youngs_modulus /= d%youngs_modulus) call add_warning(pb, g_material, k, &
        'youngs_modulus', rtoa(m%youngs_modulus), why)
      if (m%poisson_ratio /= d%poisson_ratio) call add_warning(pb, g_material, k, &
        'poisson_ratio', rtoa(m%poisson_ratio), why)
    end if
    if (m%model /= 'fluid' .and. m%bulk_modulus /= d%bulk_modulus) call add_warning(pb, &
      g_material, k, 'bulk_modulus', rtoa(m%bulk_modulus), why//" (only a 'fluid' takes it)")
    if (plastic) then
      if (m%model == 'mohr_coulomb' .and. m%dp_match /= d%dp_match) call add_warning(pb, &
        g_material, k, 'dp_match', quote(m%dp_match), why//" (only 'drucker_prager' takes it)")
      return
    end if
    why = why//' (only mohr_coulomb and drucker_prager take it)'
    if (m%friction_angle /= d%friction_angle) call add_warning(pb, g_material, k, &
      'friction_angle', rtoa(m%friction_angle), why)
    if (m%dilatancy_angle /= d%dilatancy_angle) call add_warning(pb, g_material, k, &
      'dilatancy_angle', rtoa(m%dilatancy_angle), why)
    if (m%cohesion /= d%cohesion) call add_warning(pb, g_material, k, 'cohesion', &
      rtoa(m%cohesion), why)
    if (m%tensile_strength /= d%tensile_strength) call add_warning(pb, g_material, k, &
      'tensile_strength', rtoa(m%tensile_strength), why)
    if (m%cohesion_softening /= d%cohesion_softening) call add_warning(pb, g_material, k, &
      'cohesion_softening', rtoa(m%cohesion_softening), why)
    if (m%residual_cohesion /= d%residual_cohesion) call add_warning(pb, g_material, k, &
      'residual_cohesion', rtoa(m%residual_cohesion), why)
    if (m%dp_match /= d%dp_match) call add_warning(pb, g_material, k, 'dp_match', &
      quote(m%dp_match), why)
  end subroutine check_unused_material

  !> The variables of Modified Cam-Clay given to material k of another model.
  subroutine warn_cam_clay_variables(pb, k, m, d, why)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m, d
    character(len=*), intent(in) :: why
    if (m%critical_state_ratio /= d%critical_state_ratio) call add_warning(pb, g_material, k, &
      'critical_state_ratio', rtoa(m%critical_state_ratio), why)
    if (m%void_ratio /= d%void_ratio) call add_warning(pb, g_material, k, 'void_ratio', &
      rtoa(m%void_ratio), why)
    call warn_cam_clay_only(pb, k, m, d, why)
  end subroutine warn_cam_clay_variables

  !> The variables that Modified Cam-Clay alone reads (not M and e0, which sanisand reads
  !> too), given to material k of another model.
  subroutine warn_cam_clay_only(pb, k, m, d, why)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m, d
    character(len=*), intent(in) :: why
    if (m%compression_index /= d%compression_index) call add_warning(pb, g_material, k, &
      'compression_index', rtoa(m%compression_index), why)
    if (m%swelling_index /= d%swelling_index) call add_warning(pb, g_material, k, &
      'swelling_index', rtoa(m%swelling_index), why)
    if (m%preconsolidation_pressure /= d%preconsolidation_pressure) call add_warning(pb, &
      g_material, k, 'preconsolidation_pressure', rtoa(m%preconsolidation_pressure), why)
    if (m%ocr /= d%ocr) call add_warning(pb, g_material, k, 'ocr', rtoa(m%ocr), why)
    if (m%shear_modulus /= d%shear_modulus) call add_warning(pb, g_material, k, 'shear_modulus', &
      rtoa(m%shear_modulus), why)
    if (m%min_pressure /= d%min_pressure) call add_warning(pb, g_material, k, 'min_pressure', &
      rtoa(m%min_pressure), why)
  end subroutine warn_cam_clay_only

  !> The variables of SANISAND given to material k of another model.
  subroutine warn_sanisand_variables(pb, k, m, d, why)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m, d
    character(len=*), intent(in) :: why
    character(len=24), parameter :: names(16) = [character(len=24) :: 'shear_constant', &
      'extension_ratio', 'csl_lambda', 'csl_void_ratio', 'csl_exponent', 'yield_radius', &
      'hardening_h0', 'hardening_ch', 'bounding_nb', 'dilatancy_a0', 'dilatancy_nd', &
      'fabric_zmax', 'fabric_cz', 'atmospheric_pressure', 'pressure_floor', &
      'integration_tolerance']
    real(wp) :: given(16), default(16)
    integer :: j
    given = sanisand_values(m)
    default = sanisand_values(d)
    do j = 1, size(names)
      if (given(j) /= default(j)) call add_warning(pb, g_material, k, trim(names(j)), &
                                                   rtoa(given(j)), why)
    end do
  end subroutine warn_sanisand_variables

  !> The sanisand variables of m in the order of warn_sanisand_variables' names.
  pure function sanisand_values(m) result(v)
    type(material_cfg_t), intent(in) :: m
    real(wp) :: v(16)
    v = [m%shear_constant, m%extension_ratio, m%csl_lambda, m%csl_void_ratio, m%csl_exponent, &
         m%yield_radius, m%hardening_h0, m%hardening_ch, m%bounding_nb, m%dilatancy_a0, &
         m%dilatancy_nd, m%fabric_zmax, m%fabric_cz, m%atmospheric_pressure, m%pressure_floor, &
         m%integration_tolerance]
  end function sanisand_values

  !> The parameters of a sanisand material k (Dafalias & Manzari 2004, doc/input.md): each
  !> constant in the range where the model's equations hold.
  subroutine check_sanisand(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    if (.not. real_ok(m%critical_state_ratio, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'critical_state_ratio', rtoa(m%critical_state_ratio), 'must be > 0: M = q/p'' at the '// &
      'critical state in triaxial compression (1.25 for Toyoura sand)')
    if (.not. real_ok(m%void_ratio, gt=0.0_wp, lt=2.97_wp)) call add_value(pb, g_material, k, &
      'void_ratio', rtoa(m%void_ratio), 'must be in (0, 2.97): the initial void ratio e0 (the '// &
      'shear modulus has the factor (2.97 - e)^2)')
    if (.not. real_ok(m%poisson_ratio, gt=-1.0_wp, lt=0.5_wp)) call add_value(pb, g_material, &
      k, 'poisson_ratio', rtoa(m%poisson_ratio), 'must be in (-1, 0.5) (it gives K from G)')
    if (.not. real_ok(m%shear_constant, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'shear_constant', rtoa(m%shear_constant), 'must be > 0: G0, the dimensionless shear '// &
      'modulus constant')
    if (.not. real_ok(m%extension_ratio, gt=0.0_wp, le=1.0_wp)) call add_value(pb, g_material, &
      k, 'extension_ratio', rtoa(m%extension_ratio), 'must be in (0, 1]: c = M_e/M_c')
    if (.not. real_ok(m%csl_lambda, ge=0.0_wp)) call add_value(pb, g_material, k, 'csl_lambda', &
      rtoa(m%csl_lambda), 'must be >= 0: lambda_c, the fall of the critical void ratio')
    if (.not. real_ok(m%csl_void_ratio, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'csl_void_ratio', rtoa(m%csl_void_ratio), 'must be > 0: e_c0, the critical void ratio at '// &
      'p'' = 0')
    if (.not. real_ok(m%csl_exponent, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'csl_exponent', rtoa(m%csl_exponent), 'must be > 0: xi')
    if (.not. real_ok(m%yield_radius, gt=0.0_wp)) then
      call add_value(pb, g_material, k, 'yield_radius', rtoa(m%yield_radius), &
                     'must be > 0: m, the size of the yield cone (0.01 for Toyoura sand)')
    else if (real_ok(m%critical_state_ratio, gt=0.0_wp) .and. &
             real_ok(m%extension_ratio, gt=0.0_wp, le=1.0_wp)) then
      if (m%yield_radius >= m%extension_ratio*m%critical_state_ratio) call add_value(pb, &
        g_material, k, 'yield_radius', rtoa(m%yield_radius), 'must be < c M = '// &
        rtoa(m%extension_ratio*m%critical_state_ratio)//' (the yield cone inside the '// &
        'critical state surface in extension)')
    end if
    if (.not. real_ok(m%hardening_h0, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'hardening_h0', rtoa(m%hardening_h0), 'must be > 0: h0')
    if (.not. real_ok(m%hardening_ch, ge=0.0_wp)) then
      call add_value(pb, g_material, k, 'hardening_ch', rtoa(m%hardening_ch), 'must be >= 0: c_h')
    else if (real_ok(m%void_ratio, gt=0.0_wp)) then
      if (m%hardening_ch*m%void_ratio >= 1.0_wp) call add_value(pb, g_material, k, &
        'hardening_ch', rtoa(m%hardening_ch), 'must be < 1/void_ratio = '// &
        rtoa(1.0_wp/m%void_ratio)//' (b0 has the factor 1 - c_h e, which must stay > 0)')
    end if
    if (.not. real_ok(m%bounding_nb, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'bounding_nb', rtoa(m%bounding_nb), 'must be >= 0: n_b')
    if (.not. real_ok(m%dilatancy_a0, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'dilatancy_a0', rtoa(m%dilatancy_a0), 'must be >= 0: A0')
    if (.not. real_ok(m%dilatancy_nd, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'dilatancy_nd', rtoa(m%dilatancy_nd), 'must be >= 0: n_d')
    if (.not. real_ok(m%fabric_zmax, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'fabric_zmax', rtoa(m%fabric_zmax), 'must be >= 0: z_max (0: no fabric effect)')
    if (.not. real_ok(m%fabric_cz, ge=0.0_wp)) call add_value(pb, g_material, k, 'fabric_cz', &
      rtoa(m%fabric_cz), 'must be >= 0: c_z')
    if (.not. real_ok(m%atmospheric_pressure, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'atmospheric_pressure', rtoa(m%atmospheric_pressure), 'must be > 0 (Pa): p_at')
    if (.not. real_ok(m%pressure_floor, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'pressure_floor', rtoa(m%pressure_floor), 'must be > 0 (Pa): the model is undefined at '// &
      'p'' <= 0; a point below the floor is put at it (about 1e-3 atmospheric_pressure)')
    if (.not. real_ok(m%integration_tolerance, gt=0.0_wp, le=0.01_wp)) call add_value(pb, &
      g_material, k, 'integration_tolerance', rtoa(m%integration_tolerance), &
      'must be in (0, 0.01]: the relative error of a substep (1e-5 by default)')
  end subroutine check_sanisand

  !> The parameters of a cam_clay material k (Modified Cam-Clay, doc/input.md): lambda >
  !> kappa > 0, M > 0, e0 > 0, p_c0 >= 0, ocr >= 1, p_m >= 0, G >= 0 (0: from K and nu).
  subroutine check_cam_clay(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    if (.not. real_ok(m%swelling_index, gt=0.0_wp)) then
      call add_value(pb, g_material, k, 'swelling_index', rtoa(m%swelling_index), &
                     'must be > 0: kappa, the slope of e against ln p'' on unloading (a cam_clay '// &
                     'soil needs it; 0.01-0.05 for clays)')
    else if (.not. real_ok(m%compression_index, gt=m%swelling_index)) then
      call add_value(pb, g_material, k, 'compression_index', rtoa(m%compression_index), &
                     'must be > swelling_index = '//rtoa(m%swelling_index)//': lambda, the slope '// &
                     'of e against ln p'' on the normal compression line')
    end if
    if (.not. real_ok(m%critical_state_ratio, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'critical_state_ratio', rtoa(m%critical_state_ratio), 'must be > 0: M = q/p'' at the '// &
      'critical state (6 sin(phi)/(3 - sin(phi)) in compression)')
    if (.not. real_ok(m%void_ratio, gt=0.0_wp)) call add_value(pb, g_material, k, 'void_ratio', &
      rtoa(m%void_ratio), 'must be > 0: the void ratio e0 at the initial stress')
    if (.not. real_ok(m%preconsolidation_pressure, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'preconsolidation_pressure', rtoa(m%preconsolidation_pressure), &
      'must be >= 0 (Pa; 0 = ocr times the yield surface through the initial stress)')
    if (.not. real_ok(m%ocr, ge=1.0_wp)) call add_value(pb, g_material, k, 'ocr', rtoa(m%ocr), &
      'must be >= 1 (1: normally consolidated)')
    if (.not. real_ok(m%min_pressure, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'min_pressure', rtoa(m%min_pressure), 'must be >= 0 (Pa)')
    if (.not. real_ok(m%shear_modulus, ge=0.0_wp)) then
      call add_value(pb, g_material, k, 'shear_modulus', rtoa(m%shear_modulus), &
                     'must be >= 0 (Pa; 0 = from the bulk modulus and poisson_ratio)')
    else if (m%shear_modulus == 0.0_wp .and. .not. real_ok(m%poisson_ratio, gt=-1.0_wp, &
                                                          lt=0.5_wp)) then
      call add_value(pb, g_material, k, 'poisson_ratio', rtoa(m%poisson_ratio), &
                     'must be in (-1, 0.5) (it gives G from K with shear_modulus = 0)')
    end if
  end subroutine check_cam_clay

  !> The variables of a umat material k (a user's UMAT, doc/input.md): its PROPS given,
  !> NSTATV >= 0. (youngs_modulus and poisson_ratio, the stiffest the UMAT gets, are
  !> checked as for the elastic models.)
  subroutine check_umat(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    integer :: j
    if (m%umat_nprops == 0) call add_value(pb, g_material, k, 'umat_props', '(not given)', &
      'a umat needs its PROPS: umat_props = the values the UMAT reads, in its order (NPROPS is '// &
      'their count)')
    do j = 1, m%umat_nprops
      if (.not. real_ok(m%umat_props(j))) then
        call add_value(pb, g_material, k, 'umat_props('//itoa(j)//')', rtoa(m%umat_props(j)), &
                       'must be a finite number')
        exit
      end if
    end do
    if (m%umat_nstatev < 0) call add_value(pb, g_material, k, 'umat_nstatev', &
      itoa(m%umat_nstatev), 'must be >= 0: the number of state variables (NSTATV) the UMAT '// &
      'keeps per point')
  end subroutine check_umat

  !> The umat variables given to material k of another model.
  subroutine warn_umat_variables(pb, k, m, d, why)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m, d
    character(len=*), intent(in) :: why
    if (m%umat_nprops > 0) call add_warning(pb, g_material, k, 'umat_props', &
      rtoa_list(m%umat_props(1:m%umat_nprops)), why)
    if (m%umat_nstatev /= d%umat_nstatev) call add_warning(pb, g_material, k, 'umat_nstatev', &
      itoa(m%umat_nstatev), why)
    if (m%umat_name /= d%umat_name) call add_warning(pb, g_material, k, 'umat_name', &
      quote(m%umat_name), why)
  end subroutine warn_umat_variables

  !> The parameters of a mu_i material k (the mu(I) rheology, doc/input.md): 0 <= mu_s < mu_2,
  !> I_0 > 0, grain_diameter > 0, grain_density >= 0 (0: density).
  subroutine check_mu_i(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    if (.not. real_ok(m%mu_s, ge=0.0_wp)) then
      call add_value(pb, g_material, k, 'mu_s', rtoa(m%mu_s), 'must be >= 0: the friction '// &
                     'coefficient tau/p of slow flow (0.38 for glass beads, tan of the angle of '// &
                     'repose)')
    else if (.not. real_ok(m%mu_2, gt=m%mu_s)) then
      call add_value(pb, g_material, k, 'mu_2', rtoa(m%mu_2), 'must be > mu_s = '// &
                     rtoa(m%mu_s)//': the friction coefficient of fast flow, which mu(I) '// &
                     'approaches from mu_s (0.64 for glass beads)')
    end if
    if (.not. real_ok(m%i_0, gt=0.0_wp)) call add_value(pb, g_material, k, 'i_0', rtoa(m%i_0), &
      'must be > 0: the inertial number at which mu(I) is halfway from mu_s to mu_2 (0.279 for '// &
      'glass beads)')
    if (.not. real_ok(m%grain_diameter, gt=0.0_wp)) call add_value(pb, g_material, k, &
      'grain_diameter', rtoa(m%grain_diameter), 'must be > 0 (m): the grain diameter d of the '// &
      'inertial number I = gdot d/sqrt(p/rho_s)')
    if (.not. real_ok(m%grain_density, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'grain_density', rtoa(m%grain_density), 'must be >= 0 (kg/m^3): rho_s of the inertial '// &
      'number; 0 takes density')
    if (.not. real_ok(m%dilatancy_k, ge=0.0_wp)) then
      call add_value(pb, g_material, k, 'dilatancy_k', rtoa(m%dilatancy_k), 'must be >= 0: K of '// &
                     'the dilatancy tan(psi) = K (phi - phi_eq(I)); 0 for none')
    else if (m%dilatancy_k > 0.0_wp) then
      if (.not. real_ok(m%critical_fraction, gt=0.0_wp, lt=1.0_wp)) call add_value(pb, g_material, &
        k, 'critical_fraction', rtoa(m%critical_fraction), 'must be in (0, 1) with dilatancy_k > 0: '// &
        'the steady volume fraction phi_c of slow flow (about 0.6 for glass beads)')
      if (.not. real_ok(m%fraction_slope, ge=0.0_wp)) call add_value(pb, g_material, k, &
        'fraction_slope', rtoa(m%fraction_slope), 'must be >= 0: a in phi_eq(I) = phi_c - a I')
      if (.not. real_ok(m%volume_fraction, ge=0.0_wp, lt=1.0_wp)) then
        call add_value(pb, g_material, k, 'volume_fraction', rtoa(m%volume_fraction), &
                       'must be in [0, 1): the volume fraction phi of the points as placed')
      else if (m%volume_fraction == 0.0_wp .and. (m%grain_density == 0.0_wp .or. &
                                                  m%density >= m%grain_density)) then
        call add_value(pb, g_material, k, 'volume_fraction', rtoa(m%volume_fraction), &
                       'must be given with dilatancy_k > 0 when density/grain_density is not '// &
                       'below 1: the volume fraction of the points as placed (1 - porosity for '// &
                       'the skeleton of a saturated soil)')
      end if
    end if
  end subroutine check_mu_i

  !> max_dilation of a soil that takes it: 0 (no bound) or > 1.
  subroutine check_max_dilation(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    if (.not. real_ok(m%max_dilation, ge=0.0_wp) .or. (m%max_dilation > 0.0_wp .and. m%max_dilation <= 1.0_wp)) &
      call add_value(pb, g_material, k, 'max_dilation', rtoa(m%max_dilation), &
                     'must be 0 (no bound) or > 1 (the largest volume of a point over its initial one)')
  end subroutine check_max_dilation

  !> The mu_i variables given to material k of another model.
  subroutine warn_mu_i_variables(pb, k, m, d, why)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m, d
    character(len=*), intent(in) :: why
    if (m%mu_s /= d%mu_s) call add_warning(pb, g_material, k, 'mu_s', rtoa(m%mu_s), why)
    if (m%mu_2 /= d%mu_2) call add_warning(pb, g_material, k, 'mu_2', rtoa(m%mu_2), why)
    if (m%i_0 /= d%i_0) call add_warning(pb, g_material, k, 'i_0', rtoa(m%i_0), why)
    if (m%grain_diameter /= d%grain_diameter) call add_warning(pb, g_material, k, &
      'grain_diameter', rtoa(m%grain_diameter), why)
    if (m%grain_density /= d%grain_density) call add_warning(pb, g_material, k, &
      'grain_density', rtoa(m%grain_density), why)
    if (m%dilatancy_k /= d%dilatancy_k) call add_warning(pb, g_material, k, &
      'dilatancy_k', rtoa(m%dilatancy_k), why)
    if (m%critical_fraction /= d%critical_fraction) call add_warning(pb, g_material, k, &
      'critical_fraction', rtoa(m%critical_fraction), why)
    if (m%fraction_slope /= d%fraction_slope) call add_warning(pb, g_material, k, &
      'fraction_slope', rtoa(m%fraction_slope), why)
    if (m%volume_fraction /= d%volume_fraction) call add_warning(pb, g_material, k, &
      'volume_fraction', rtoa(m%volume_fraction), why)
  end subroutine warn_mu_i_variables

  !> Strength parameters of a mohr_coulomb or drucker_prager material k.
  subroutine check_plastic(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    type(plastic_params_t) :: par
    real(wp) :: hmax
    integer :: match
    logical :: ok
    ok = .true.
    if (.not. real_ok(m%friction_angle, ge=0.0_wp, lt=90.0_wp)) then
      call add_value(pb, g_material, k, 'friction_angle', rtoa(m%friction_angle), &
                     'must be in [0, 90) (degrees)')
      ok = .false.
    end if
    if (.not. real_ok(m%dilatancy_angle, ge=0.0_wp)) then
      call add_value(pb, g_material, k, 'dilatancy_angle', rtoa(m%dilatancy_angle), &
                     'must be >= 0 (degrees)')
      ok = .false.
    else if (ok .and. m%dilatancy_angle > m%friction_angle) then
      call add_value(pb, g_material, k, 'dilatancy_angle', rtoa(m%dilatancy_angle), &
                     'must not exceed friction_angle = '//rtoa(m%friction_angle)// &
                     ' (psi > phi would create energy)')
      ok = .false.
    end if
    if (.not. real_ok(m%cohesion, ge=0.0_wp)) then
      call add_value(pb, g_material, k, 'cohesion', rtoa(m%cohesion), 'must be >= 0 (Pa)')
      ok = .false.
    else if (ok .and. m%cohesion == 0.0_wp .and. m%friction_angle == 0.0_wp) then
      call add_value(pb, g_material, k, 'cohesion', rtoa(m%cohesion), &
                     'with friction_angle = 0 the soil needs a cohesion > 0 (Pa): it has no '// &
                     'shear strength at all')
    end if
    if (.not. real_ok(m%tensile_strength, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'tensile_strength', rtoa(m%tensile_strength), 'must be >= 0 (Pa; 0 = no tension)')
    call check_max_dilation(pb, k, m)
    if (.not. real_ok(m%residual_cohesion, ge=0.0_wp)) then
      call add_value(pb, g_material, k, 'residual_cohesion', rtoa(m%residual_cohesion), &
                     'must be >= 0 (Pa)')
    else if (real_ok(m%cohesion) .and. m%residual_cohesion > m%cohesion) then
      call add_value(pb, g_material, k, 'residual_cohesion', rtoa(m%residual_cohesion), &
                     'must not exceed cohesion = '//rtoa(m%cohesion)//' (softening lowers it)')
    end if
    match = findloc(dp_match_names, trim(m%dp_match), dim=1)
    if (match == 0) then
      call add_value(pb, g_material, k, 'dp_match', quote(m%dp_match), &
                     'the matchings of Drucker-Prager to Mohr-Coulomb are plane_strain, outer, '// &
                     'inner')
      match = dp_plane_strain
    end if
    if (.not. real_ok(m%cohesion_softening, ge=0.0_wp)) then
      call add_value(pb, g_material, k, 'cohesion_softening', rtoa(m%cohesion_softening), &
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
      if (m%cohesion_softening >= hmax) call add_value(pb, g_material, k, 'cohesion_softening', &
        rtoa(m%cohesion_softening), 'must be < '//rtoa(hmax)//' (Pa) with these elastic '// &
        'constants and angles: a steeper softening has no unique return')
    end if
  end subroutine check_plastic

  !> The vibration of a rigid body: a finite amplitude and a frequency >= 0, both or
  !> neither, and only on a rigid material.
  subroutine check_vibration(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    logical :: shaken
    call check_finite(pb, g_material, k, 'vibration_amplitude', m%vibration_amplitude)
    if (.not. real_ok(m%vibration_frequency, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'vibration_frequency', rtoa(m%vibration_frequency), 'must be >= 0 (Hz)')
    shaken = any(m%vibration_amplitude /= 0.0_wp)
    if (shaken .and. m%model /= 'rigid') call add_value(pb, g_material, k, &
      'vibration_amplitude', rtoa_list(m%vibration_amplitude), "only a rigid body "// &
      "(model = 'rigid') vibrates")
    if (shaken .and. m%vibration_frequency == 0.0_wp) call add_value(pb, g_material, k, &
      'vibration_frequency', '0.0', 'a vibration_amplitude needs a frequency > 0 (Hz)')
    if (.not. shaken .and. m%vibration_frequency /= 0.0_wp) call add_value(pb, g_material, k, &
      'vibration_frequency', rtoa(m%vibration_frequency), 'does nothing without a '// &
      'vibration_amplitude (m)')
  end subroutine check_vibration

  !> The contact and motion of a rigid body (doc/theory.md 6.8.1): contact stick or
  !> frictional, a friction coefficient and an adhesion >= 0 that only a frictional contact
  !> reads, a motion prescribed or free, a load only on a free body, which moves by its own
  !> equation and so meets the soil through a frictional contact and has no vibration;
  !> none of these on a material that is not rigid.
  subroutine check_contact(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    type(material_cfg_t) :: d
    logical :: rigid, frictional
    rigid = m%model == 'rigid'
    frictional = m%contact == 'frictional'
    if (.not. any(m%contact == [character(len=10) :: 'stick', 'frictional'])) call add_value(pb, &
      g_material, k, 'contact', quote(m%contact), 'the contacts are stick (the soil at the '// &
      'body''s nodes moves with it) and frictional (Coulomb friction and adhesion, separation)')
    if (.not. any(m%body_motion == [character(len=10) :: 'prescribed', 'free'])) call add_value(pb, &
      g_material, k, 'body_motion', quote(m%body_motion), 'the motions are prescribed (at '// &
      'velocity, with its vibration) and free (moved by gravity, body_load and the contact)')
    if (.not. real_ok(m%contact_friction, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'contact_friction', rtoa(m%contact_friction), 'must be >= 0 (a friction coefficient, '// &
      'e.g. a roughness factor times tan phi)')
    if (.not. real_ok(m%contact_adhesion, ge=0.0_wp)) call add_value(pb, g_material, k, &
      'contact_adhesion', rtoa(m%contact_adhesion), 'must be >= 0 (Pa, the shear strength '// &
      'of the contact at no normal stress)')
    call check_finite(pb, g_material, k, 'body_load', m%body_load)
    if (.not. rigid) then
      if (m%contact /= d%contact .or. m%body_motion /= d%body_motion .or. any(m%body_load /= 0.0_wp) &
          .or. m%contact_friction /= 0.0_wp .or. m%contact_adhesion /= 0.0_wp .or. &
          any(m%motion_times /= d%motion_times)) call add_value(pb, g_material, k, 'model', &
        quote(m%model), "contact, contact_friction, contact_adhesion, body_motion, body_load "// &
        "and motion_times belong to a rigid body (model = 'rigid')")
      return
    end if
    call check_motion_table(pb, k, m)
    if (.not. frictional .and. m%contact_friction /= 0.0_wp) call add_value(pb, g_material, k, &
      'contact_friction', rtoa(m%contact_friction), "needs contact = 'frictional' (a stick "// &
      'contact holds the soil whatever the force)')
    if (.not. frictional .and. m%contact_adhesion /= 0.0_wp) call add_value(pb, g_material, k, &
      'contact_adhesion', rtoa(m%contact_adhesion), "needs contact = 'frictional' (a stick "// &
      'contact holds the soil whatever the force)')
    if (m%body_motion == 'free') then
      if (.not. frictional) call add_value(pb, g_material, k, 'body_motion', "'free'", &
        "a free body needs contact = 'frictional' (the soil's reaction moves it)")
      if (any(m%vibration_amplitude /= 0.0_wp)) call add_value(pb, g_material, k, &
        'vibration_amplitude', rtoa_list(m%vibration_amplitude), 'a free body does not '// &
        "vibrate: its motion follows from its forces (body_motion = 'prescribed' vibrates)")
    else if (any(m%body_load /= 0.0_wp)) then
      call add_value(pb, g_material, k, 'body_load', rtoa_list(m%body_load), "only a free body "// &
        "(body_motion = 'free') takes a load; a prescribed one moves at its velocity")
    end if
  end subroutine check_contact

  !> A rigid body's time table (motion_times, motion_factors): times >= 0 increasing from the
  !> first entry, then only unused entries < 0, finite factors; a free body's factors act
  !> on its body_load, which then must be given.
  subroutine check_motion_table(pb, k, m)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: k
    type(material_cfg_t), intent(in) :: m
    integer :: n, i
    n = table_length(m%motion_times)
    if (n == 0 .and. any(m%motion_times >= 0.0_wp)) call add_value(pb, g_material, k, &
      'motion_times', rtoa_list(pack(m%motion_times, m%motion_times /= -1.0_wp)), &
      'the table starts at its first entry (a time >= 0)')
    if (n == 0) return
    if (any(m%motion_times(n + 1:) >= 0.0_wp)) call add_value(pb, g_material, k, 'motion_times', &
      rtoa(m%motion_times(n + 1)), 'the table ends at its first negative entry (entry '// &
      itoa(n + 1)//'); give the times in order')
    do i = 2, n
      if (m%motion_times(i) <= m%motion_times(i - 1)) then
        call add_value(pb, g_material, k, 'motion_times', rtoa(m%motion_times(i)), &
                       'must increase (entry '//itoa(i)//' is not after entry '//itoa(i - 1)//')')
        exit
      end if
    end do
    call check_finite(pb, g_material, k, 'motion_times', m%motion_times(1:n))
    call check_finite(pb, g_material, k, 'motion_factors', m%motion_factors(1:n))
    if (m%body_motion == 'free' .and. all(m%body_load == 0.0_wp)) call add_value(pb, &
      g_material, k, 'motion_times', rtoa_list(m%motion_times(1:n)), 'the table of a free '// &
      'body scales its body_load, which is not given')
  end subroutine check_motion_table

  !> The scene around frictional contacts (doc/theory.md 6.8.1): a frictional or free body is
  !> the only rigid body of its scene, dry (no pore water: its contact with the water is
  !> not written yet), on one, two or three axes without axisymmetry, and a free body has
  !> points (some region is made of it).
  subroutine check_contact_scene(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer :: k, r, nrigid
    logical :: used, two_phase
    if (.not. allocated(cfg%materials)) return
    two_phase = .false.
    if (allocated(cfg%regions)) two_phase = any(cfg%regions%phase /= 'solid')
    nrigid = count(cfg%materials%model == 'rigid')
    do k = 1, size(cfg%materials)
      associate (m => cfg%materials(k))
        if (m%model /= 'rigid' .or. m%contact /= 'frictional') cycle
        if (nrigid > 1) call add_value(pb, g_material, k, 'contact', "'frictional'", &
          'a frictional contact needs its body to be the only rigid body of the scene ('// &
          itoa(nrigid)//' rigid materials here)')
        if (two_phase) call add_value(pb, g_material, k, 'contact', "'frictional'", &
          'a frictional contact is not yet written for a scene with pore water; use '// &
          "contact = 'stick' there")
        if (m%body_motion /= 'free') cycle
        used = .false.
        if (allocated(cfg%regions)) then
          do r = 1, size(cfg%regions)
            used = used .or. cfg%regions(r)%material == m%id
          end do
        end if
        if (.not. used) call add_value(pb, g_material, k, 'body_motion', "'free'", &
          'a free body needs mass: no &region is made of material '//itoa(m%id))
      end associate
    end do
  end subroutine check_contact_scene

end module dpmpm_input_check_material
