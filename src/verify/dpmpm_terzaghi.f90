!> Terzaghi 1D consolidation with a compressible pore fluid (doc/theory.md 9.3): the quasi-static
!> reference for the two-phase solver.
!>
!> Layer 0 <= z <= H, z measured down from the drained top (p = 0), impermeable rigid bottom;
!> total stress step -q at t = 0. Incompressible grains, fluid modulus K_f, M = K_f/n_f.
!> - c_v = k / (gamma_w (1/E_c + n_f/K_f)), gamma_w = rho_f g; T_v = c_v t / H^2.
!> - Undrained start: p_0 = q M/(E_c + M).
!> - p(z,t) = p_0 sum_{m>=0} (2/M_m) sin(M_m z/H) exp(-M_m^2 T_v), M_m = pi (2m + 1)/2.
!> - U(T_v) = 1 - sum_{m>=0} (2/M_m^2) exp(-M_m^2 T_v).
!> - Settlement s = int_0^H (q - p)/E_c dz (sigma' = p - q, compression strain -sigma'/E_c)
!>   = s_u + (p_0 H/E_c) U, with the undrained settlement s_u = q H/(E_c + M); the same as
!>   s_u + (q/E_c - s_u/H) H U of doc/theory.md, eq. (9.1).
!> Number of terms: every term with M_m^2 T_v < 40 is kept (the first left out is below
!> e^{-40} = 4e-18 relative): 64 terms at T_v = 1e-3, 7 at T_v = 0.1, 2 at T_v = 1; in general
!> about sqrt(40/T_v)/pi. The series then converge to round-off for every T_v > 0 (measured
!> against the short-time form U = 2 sqrt(T_v/pi), exact up to e^{-1/T_v}: relative difference
!> below 1e-13 for 1e-3 <= T_v <= 1e-2, see tests/test_biot_column.f90).
module dpmpm_terzaghi
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: terzaghi_cv, terzaghi_p0, terzaghi_time_factor, terzaghi_pressure, terzaghi_degree
  public :: terzaghi_settlement, terzaghi_undrained_settlement, terzaghi_nterms

  !> Layer, material and load of the consolidation problem (SI units).
  type, public :: terzaghi_t
    !> Layer thickness H [m] (drainage path: drained top, impermeable bottom).
    real(wp) :: height = 0.0_wp
    !> Porosity n_f [-].
    real(wp) :: porosity = 0.0_wp
    !> Constrained modulus E_c [Pa].
    real(wp) :: e_c = 0.0_wp
    !> Fluid bulk modulus K_f [Pa].
    real(wp) :: k_f = 0.0_wp
    !> Hydraulic conductivity k [m/s].
    real(wp) :: conductivity = 0.0_wp
    !> Fluid density rho_f [kg/m^3] and gravity g [m/s^2]: gamma_w = rho_f g.
    real(wp) :: rho_f = 1000.0_wp
    real(wp) :: gravity = 9.81_wp
    !> Load q [Pa], positive = compression.
    real(wp) :: load = 0.0_wp
  end type terzaghi_t

  real(wp), parameter :: pi = acos(-1.0_wp)
  !> Terms with M_m^2 T_v beyond this are below e^{-40} and left out.
  real(wp), parameter :: exponent_cut = 40.0_wp

contains

  !> Consolidation coefficient c_v = k / (gamma_w (1/E_c + n_f/K_f)) [m^2/s].
  pure function terzaghi_cv(ter) result(cv)
    type(terzaghi_t), intent(in) :: ter
    real(wp) :: cv
    cv = ter%conductivity/(ter%rho_f*ter%gravity*(1.0_wp/ter%e_c + ter%porosity/ter%k_f))
  end function terzaghi_cv

  !> Initial (undrained) excess pore pressure p_0 = q M/(E_c + M), M = K_f/n_f.
  pure function terzaghi_p0(ter) result(p0)
    type(terzaghi_t), intent(in) :: ter
    real(wp) :: p0, m
    m = ter%k_f/ter%porosity
    p0 = ter%load*m/(ter%e_c + m)
  end function terzaghi_p0

  !> Time factor T_v = c_v t / H^2.
  pure function terzaghi_time_factor(ter, t) result(tv)
    type(terzaghi_t), intent(in) :: ter
    real(wp), intent(in) :: t
    real(wp) :: tv
    tv = terzaghi_cv(ter)*t/ter%height**2
  end function terzaghi_time_factor

  !> Number of series terms used at time factor tv > 0 (all terms with M_m^2 T_v < 40).
  pure function terzaghi_nterms(tv) result(n)
    real(wp), intent(in) :: tv
    integer :: n
    n = max(1, ceiling(sqrt(exponent_cut/tv)/pi + 0.5_wp))
  end function terzaghi_nterms

  !> Excess pore pressure p(z,t) at depth z in [0, H] below the drained top. At t <= 0 it is
  !> the undrained value p_0 inside the layer (0 at the drained top itself).
  pure function terzaghi_pressure(ter, z, t) result(p)
    type(terzaghi_t), intent(in) :: ter
    real(wp), intent(in) :: z, t
    real(wp) :: p, tv, mm
    integer :: m
    if (t <= 0.0_wp) then
      p = merge(0.0_wp, terzaghi_p0(ter), z <= 0.0_wp)
      return
    end if
    tv = terzaghi_time_factor(ter, t)
    p = 0.0_wp
    do m = terzaghi_nterms(tv) - 1, 0, -1          ! smallest terms first
      mm = 0.5_wp*pi*real(2*m + 1, wp)
      p = p + 2.0_wp/mm*sin(mm*z/ter%height)*exp(-mm**2*tv)
    end do
    p = terzaghi_p0(ter)*p
  end function terzaghi_pressure

  !> Average degree of consolidation U(T_v) = 1 - sum (2/M_m^2) exp(-M_m^2 T_v); U(0) = 0.
  pure function terzaghi_degree(tv) result(u)
    real(wp), intent(in) :: tv
    real(wp) :: u, acc, mm
    integer :: m
    if (tv <= 0.0_wp) then
      u = 0.0_wp
      return
    end if
    acc = 0.0_wp
    do m = terzaghi_nterms(tv) - 1, 0, -1
      mm = 0.5_wp*pi*real(2*m + 1, wp)
      acc = acc + 2.0_wp/mm**2*exp(-mm**2*tv)
    end do
    u = 1.0_wp - acc
  end function terzaghi_degree

  !> Undrained settlement s_u = q H/(E_c + M), the instantaneous compression of the layer.
  pure function terzaghi_undrained_settlement(ter) result(su)
    type(terzaghi_t), intent(in) :: ter
    real(wp) :: su
    su = ter%load*ter%height/(ter%e_c + ter%k_f/ter%porosity)
  end function terzaghi_undrained_settlement

  !> Settlement of the top (positive downwards) at time t >= 0: s = s_u + (p_0 H/E_c) U(T_v);
  !> it tends to q H/E_c.
  pure function terzaghi_settlement(ter, t) result(s)
    type(terzaghi_t), intent(in) :: ter
    real(wp), intent(in) :: t
    real(wp) :: s
    s = terzaghi_undrained_settlement(ter) + terzaghi_p0(ter)*ter%height/ter%e_c* &
        terzaghi_degree(terzaghi_time_factor(ter, max(t, 0.0_wp)))
  end function terzaghi_settlement

end module dpmpm_terzaghi
