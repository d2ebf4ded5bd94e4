!> The parameters of one material of a scene, with the derived elastic constants: what
!> every model module reads (dpmpm_model_table lists the models).
module dpmpm_material_params
  use dpmpm_kinds, only: wp
  use dpmpm_model_table, only: model_linear_elastic
  use dpmpm_plasticity, only: plastic_params_t
  use dpmpm_config, only: max_props, max_table
  implicit none
  private
  public :: material_t

  !> Parameters of one material, with the derived elastic constants.
  type :: material_t
    integer :: id = 1
    integer :: model = model_linear_elastic  !< a line of dpmpm_model_table's model_table
    real(wp) :: density = 1.0_wp
    real(wp) :: youngs = 1.0_wp, poisson = 0.0_wp
    real(wp) :: lambda = 0.0_wp, mu = 0.0_wp, bulk = 0.0_wp
    real(wp) :: pwave = 0.0_wp          !< constrained modulus lambda + 2 mu
    real(wp) :: bulk_fluid = 0.0_wp     !< K_f of a fluid
    real(wp) :: conductivity = 0.0_wp   !< hydraulic conductivity of a soil (m/s), 0 = none
    logical :: kozeny_carman = .false.  !< k follows the porosity (Kozeny-Carman)
    type(plastic_params_t) :: plastic   !< strength of mohr_coulomb and drucker_prager
    real(wp) :: max_dilation = 0.0_wp   !< mohr_coulomb, drucker_prager, mu_i: bound of V/V0, 0 = none
    real(wp) :: velocity(3) = 0.0_wp    !< rigid: the prescribed velocity of the body (m/s)
    !> rigid: the displacement amplitude A (m) and angular frequency omega (1/s) of a
    !> vibration added to velocity, v(t) = velocity + A omega cos(omega t)
    real(wp) :: vibration_amplitude(3) = 0.0_wp, vibration_omega = 0.0_wp
    !> rigid: the time table of factors on velocity (a prescribed body) or on the load of a
    !> free one (motion_times < 0: no table, the factor 1)
    real(wp) :: motion_times(max_table) = -1.0_wp, motion_factors(max_table) = 0.0_wp
    !> cam_clay (dpmpm_model_cam_clay): compression and swelling indices lambda, kappa, the
    !> critical state ratio M, the initial void ratio e0, the preconsolidation pressure p_c0
    !> (0: from ocr), the overconsolidation ratio, a constant shear modulus (0: from K and
    !> nu), and the pressure p_m whose stiffness a point at zero stress keeps (Pa)
    real(wp) :: cc_lambda = 0.0_wp, cc_kappa = 0.0_wp, cc_m = 0.0_wp, cc_e0 = 0.0_wp
    real(wp) :: cc_pc0 = 0.0_wp, cc_ocr = 1.0_wp, cc_shear = 0.0_wp, cc_min_pressure = 0.0_wp
    !> sanisand (dpmpm_model_sanisand; Dafalias & Manzari 2004): G0, M, c, lambda_c, e_c0, xi,
    !> m, h0, c_h, n_b, A0, n_d, z_max, c_z, p_at (Pa), the initial void ratio e0, the
    !> pressure floor (Pa) and the relative error tolerance of the substeps
    real(wp) :: sd_g0 = 0.0_wp, sd_mc = 0.0_wp, sd_c = 0.0_wp, sd_lc = 0.0_wp, sd_ec0 = 0.0_wp
    real(wp) :: sd_xi = 0.0_wp, sd_m = 0.0_wp, sd_h0 = 0.0_wp, sd_ch = 0.0_wp, sd_nb = 0.0_wp
    real(wp) :: sd_a0 = 0.0_wp, sd_nd = 0.0_wp, sd_zmax = 0.0_wp, sd_cz = 0.0_wp
    real(wp) :: sd_pat = 1.0_wp, sd_e0 = 0.0_wp, sd_pmin = 1.0_wp, sd_tol = 1.0e-5_wp
    !> mu_i (dpmpm_model_mu_i): the friction coefficients mu_s and mu_2, I_0, the grain
    !> diameter d (m) and the grain density rho_s of the inertial number (kg/m^3)
    real(wp) :: mui_mu_s = 0.0_wp, mui_mu_2 = 0.0_wp, mui_i0 = 0.0_wp
    real(wp) :: mui_diameter = 0.0_wp, mui_grain_density = 0.0_wp
    !> mu_i dilatancy: tan(psi) = mui_k (phi - mui_phic + mui_slope I), phi = mui_phi0 V0/V
    real(wp) :: mui_k = 0.0_wp, mui_phic = 0.0_wp, mui_slope = 0.0_wp, mui_phi0 = 0.0_wp
    !> the state values a point of this material keeps (dpmpm_model_table's material_nstate)
    integer :: nstate = 0
    !> umat (dpmpm_model_umat): PROPS (umat_nprops of them), NSTATV and CMNAME
    real(wp) :: umat_props(max_props) = 0.0_wp
    integer :: umat_nprops = 0, umat_nstatev = 0
    character(len=80) :: umat_name = 'UMAT'
  end type material_t

end module dpmpm_material_params
