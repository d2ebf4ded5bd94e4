!> Analytical reference for the finite 1D saturated column under a step load (doc/theory.md 2.7 and 9.2),
!> and for the same column shaken along its axis at its base (biot_column_base_solve; doc/theory.md
!> 9.2, "Base motion": the modes from the base reflect on their own at the free drained top).
!>
!> Column 0 <= z <= L, z measured down from the loaded top. Top: total stress step
!> sigma(0,t) = sigma' - p = -q H(t), drained, p(0,t) = 0, so sigma'(0,t) = -q. Bottom: fixed and
!> impermeable, v_s(L) = v_f(L) = 0. Zero initial state, no gravity loading (gravity enters only
!> through the drag coefficient Q = n_f^2 rho_f g / k). Signs: sigma' positive in tension, p
!> positive in compression, velocities positive downwards.
!>
!> Algorithm A of doc/theory.md 9.2 (compressible constituents): in the Laplace domain the solution
!> is exact in space, a sum of two downward modes e^{-lambda_j z} and two upward modes
!> e^{-lambda_j (L - z)} (the decaying form, so nothing overflows). The 4x4 system of the two top
!> and the two bottom conditions is solved in closed form: with V_s(L) = V_f(L) = 0 and two
!> linearly independent mode shapes, each upward amplitude is c_{j+2} = -e^{-lambda_j L} c_j
!> (every mode reflects on its own at the rigid bottom), and the top leaves a 2x2 system for
!> d_j = (1 + e^{-2 lambda_j L}) c_j. The time signal comes from the Durbin (exponential-window)
!> inversion: F is sampled at s_k = alpha + i k omega_0, omega_0 = 2 pi / T_p, and
!>   f(t) = e^{alpha t}/T_p [F(alpha) + 2 Re sum_{k>=1} sigma_k F(s_k) e^{i omega_k t}],
!> evaluated on a fine grid t_n = n dt, with Lanczos sigma factors sigma_k = sinc(k/N) against
!> Gibbs ringing, then cubic interpolation to the requested times from the four samples around
!> each. For a few requested times (the solver's checks ask for one) those samples are summed
!> directly; for many, one FFTW complex-to-real transform gives the whole grid. Algorithm B
!> (incompressible constituents, closed form with images) is here too, as an independent
!> check of algorithm A.
!>
!> Parameters of the inversion and their measured accuracy (doc/verification.md has the tables):
!> - period T_p = 4 t_end: the wrapped-around copies f(t + n T_p) are damped by e^{-alpha n T_p}.
!> - alpha T_p = 18: aliasing error e^{-18} = 1.5e-8 times the field one period later (seen as
!>   exactly that ahead of the fronts); the truncation error is amplified by at most
!>   e^{alpha t_end} = e^{4.5} = 90. alpha T_p = 14 left 4e-7, 23 and 28 gave no gain at 2^14.
!> - N = 2^14 frequencies: the fronts are smeared over about T_p/N = 2.4e-4 t_end. Away from
!>   fronts, 2^15 and 2^16 frequencies change the results by 2e-8 q.
!> - FFT length 16 N, so the highest kept frequency has 8 samples per period for the cubic
!>   interpolation; 32 samples per period changed no result by more than 1e-9 q, even at fronts.
!> Measured errors away from fronts: 3.8e-8 q on the W1 plateau, 1.5e-8 q against algorithm B
!> (K_f = 1e15), 8e-8 q against the undrained split of the sanity set of doc/theory.md 9.2.
!> Cost per depth: four FFTs of length 16 N, or for one requested time 16 sums of N terms.
module dpmpm_biot_column
  use, intrinsic :: iso_c_binding
  use dpmpm_kinds, only: wp, i8
  use dpmpm_error, only: fatal
  implicit none
  private
  include 'fftw3.f03'

  public :: biot_column_solve, biot_undrained_split, biot_wave_speeds, biot_drag
  public :: biot_incompressible_sigma, biot_default_nfreq, biot_column_base_solve

  !> Material and geometry of the saturated column (SI units).
  type, public :: biot_column_t
    !> Column length L [m].
    real(wp) :: length = 0.0_wp
    !> Porosity n_f [-].
    real(wp) :: porosity = 0.0_wp
    !> Intrinsic grain density rho_s [kg/m^3].
    real(wp) :: rho_s = 0.0_wp
    !> Intrinsic fluid density rho_f [kg/m^3].
    real(wp) :: rho_f = 0.0_wp
    !> Constrained (oedometric) modulus of the skeleton E_c [Pa].
    real(wp) :: e_c = 0.0_wp
    !> Fluid bulk modulus K_f [Pa].
    real(wp) :: k_f = 0.0_wp
    !> Hydraulic conductivity k [m/s].
    real(wp) :: conductivity = 0.0_wp
    !> Gravity g [m/s^2], used only in the drag coefficient.
    real(wp) :: gravity = 9.81_wp
    !> Load q [Pa], positive = compression of the top: sigma(0,t) = -q H(t).
    real(wp) :: load = 0.0_wp
  end type biot_column_t

  real(wp), parameter :: pi = acos(-1.0_wp)
  !> Default number of frequencies of the Durbin inversion.
  integer, parameter :: biot_default_nfreq = 2**14
  !> Default period of the inversion, in units of t_end.
  real(wp), parameter :: default_period_factor = 4.0_wp
  !> Default alpha T_p: aliasing damped by e^{-18}.
  real(wp), parameter :: default_alpha_period = 18.0_wp
  !> Time oversampling of the FFT relative to 2 N (samples per period of the highest frequency / 2).
  integer, parameter :: time_oversampling = 8
  !> Up to this many requested times the samples are summed directly instead of by an FFT.
  integer, parameter :: max_direct_times = 8

contains

  !> Drag coefficient Q = n_f^2 rho_f g / k [kg m^-3 s^-1] of the v_s-v_f equations (doc/theory.md 2.2).
  pure function biot_drag(col) result(q_drag)
    type(biot_column_t), intent(in) :: col
    real(wp) :: q_drag
    q_drag = col%porosity**2*col%rho_f*col%gravity/col%conductivity
  end function biot_drag

  !> Undrained split of the load behind the fast front (Q -> infinity, v_s = v_f):
  !> p_u = q M/(E_c + M) and sigma'_u = -q E_c/(E_c + M), M = K_f/n_f, so sigma'_u - p_u = -q.
  pure subroutine biot_undrained_split(col, p_u, sigma_u)
    type(biot_column_t), intent(in) :: col
    real(wp), intent(out) :: p_u, sigma_u
    real(wp) :: m
    m = col%k_f/col%porosity
    p_u = col%load*m/(col%e_c + m)
    sigma_u = -col%load*col%e_c/(col%e_c + m)
  end subroutine biot_undrained_split

  !> Wave speeds of doc/theory.md 2.7. c_fast: undrained speed c_u = sqrt((E_c + M)/rho_sat), the
  !> one the CFL check uses. c_slow: the slow root of the uncoupled (Q -> 0) relation
  !> m_s m_f c^4 - (a m_f + d m_s) c^2 + E_c d = 0, a = E_c + n_s^2 M, d = n_f^2 M.
  !> Optional: c_fast_uncoupled (the fast root of that relation) and c_incompressible =
  !> sqrt(E_c/rho~), rho~ = n_s rho_s + (n_s^2/n_f) rho_f (the telegraph-equation speed).
  pure subroutine biot_wave_speeds(col, c_fast, c_slow, c_fast_uncoupled, c_incompressible)
    type(biot_column_t), intent(in) :: col
    real(wp), intent(out) :: c_fast, c_slow
    real(wp), intent(out), optional :: c_fast_uncoupled, c_incompressible
    real(wp) :: nf, ns, m, ms, mf, a, d, b2, disc, c2big
    nf = col%porosity
    ns = 1.0_wp - nf
    m = col%k_f/nf
    ms = ns*col%rho_s
    mf = nf*col%rho_f
    c_fast = sqrt((col%e_c + m)/(ms + mf))
    a = col%e_c + ns**2*m
    d = nf**2*m
    ! Quadratic A c^4 - B c^2 + C = 0 in c^2; the small root as C/(A c2big) avoids cancellation.
    b2 = a*mf + d*ms
    disc = sqrt(max(b2**2 - 4.0_wp*ms*mf*col%e_c*d, 0.0_wp))
    c2big = (b2 + disc)/(2.0_wp*ms*mf)
    c_slow = sqrt(col%e_c*d/(ms*mf*c2big))
    if (present(c_fast_uncoupled)) c_fast_uncoupled = sqrt(c2big)
    if (present(c_incompressible)) c_incompressible = sqrt(col%e_c/(ns*col%rho_s + ns**2/nf*col%rho_f))
  end subroutine biot_wave_speeds

  !> Fields of the finite column by algorithm A at depths z(1:nz) and times times(1:nt), all
  !> within [0, L] and [0, t_end]: pore pressure p, effective stress sigma_eff, solid and fluid
  !> velocities v_s and v_f. window (default .true.) applies the Lanczos sigma factors; nfreq,
  !> period and alpha override the inversion parameters described in the module header (for
  !> convergence studies).
  subroutine biot_column_solve(col, t_end, nz, z, nt, times, p, sigma_eff, v_s, v_f, window, &
                               nfreq, period, alpha)
    type(biot_column_t), intent(in) :: col
    real(wp), intent(in) :: t_end
    integer, intent(in) :: nz, nt
    real(wp), intent(in) :: z(nz), times(nt)
    real(wp), intent(out) :: p(nz, nt), sigma_eff(nz, nt), v_s(nz, nt), v_f(nz, nt)
    logical, intent(in), optional :: window
    integer, intent(in), optional :: nfreq
    real(wp), intent(in), optional :: period, alpha
    ! Per frequency k: lambda_j and the amplitudes of the four fields per mode (j = 1, 2).
    complex(wp), allocatable :: lam(:, :), amp(:, :, :)
    complex(wp) :: s
    real(wp) :: tp, alph, omega0
    integer :: nf, k
    logical :: use_window

    call check_inputs(col, t_end, z, times)
    call inversion_options(t_end, 'biot_column_solve', window, nfreq, period, alpha, use_window, nf, tp, alph)
    omega0 = 2.0_wp*pi/tp

    ! Laplace-domain modes at every frequency of the Durbin grid.
    allocate (lam(2, 0:nf - 1), amp(4, 2, 0:nf - 1))
    do k = 0, nf - 1
      s = cmplx(alph, real(k, wp)*omega0, wp)
      call column_modes(col, s, lam(:, k), amp(:, :, k))
    end do
    call invert_modes(col, .false., nf, tp, alph, use_window, lam, amp, nz, z, nt, times, &
                      p, sigma_eff, v_s, v_f)
  end subroutine biot_column_solve

  !> The Durbin inversion of the module header for the mode amplitudes amp(field, j, k) and
  !> wavenumbers lam(j, k) at s_k = alph + i k 2 pi/tp (k = 0 .. nf - 1): the fields at depths
  !> z and times. base selects the depth dependence: .false. the top load's (modes from the
  !> top, reflected at the rigid bottom), .true. the base motion's (modes from the base,
  !> reflected at the free drained top).
  subroutine invert_modes(col, base, nf, tp, alph, use_window, lam, amp, nz, z, nt, times, &
                          p, sigma_eff, v_s, v_f)
    type(biot_column_t), intent(in) :: col
    logical, intent(in) :: base, use_window
    integer, intent(in) :: nf, nz, nt
    real(wp), intent(in) :: tp, alph, z(nz), times(nt)
    complex(wp), intent(in) :: lam(2, 0:nf - 1), amp(4, 2, 0:nf - 1)
    real(wp), intent(out) :: p(nz, nt), sigma_eff(nz, nt), v_s(nz, nt), v_f(nz, nt)
    complex(C_DOUBLE_COMPLEX), allocatable :: spec(:)
    real(C_DOUBLE), allocatable :: sig(:)
    real(wp), allocatable :: sigma_k(:)
    complex(wp), allocatable :: gm(:, :), gp(:, :)
    complex(wp) :: e_down(2), e_up(2)
    complex(wp), allocatable :: tw(:, :, :)
    real(wp) :: dt, f(0:3), u, w(0:3), sn
    integer :: nfft, k, iz, it, ifield, j0, i
    integer, allocatable :: jt(:)
    type(C_PTR) :: plan
    logical :: direct

    nfft = 2*time_oversampling*nf
    dt = tp/real(nfft, wp)
    allocate (sigma_k(0:nf - 1))
    do k = 0, nf - 1
      sigma_k(k) = 1.0_wp
      if (use_window .and. k > 0) sigma_k(k) = sin(pi*k/nf)/(pi*k/nf)
    end do

    ! The four grid samples t_n = n dt (n = j0 .. j0 + 3) around each requested time.
    allocate (jt(nt))
    do it = 1, nt
      jt(it) = max(0, min(int(times(it)/dt) - 1, nfft - 4))
    end do
    ! A few times: the samples summed directly, sig(n) = F_0 + 2 Re sum_k F_k e^{2 pi i k n /
    ! nfft} with the factors e^{...} of those samples tabled once; many: one FFT per field and
    ! depth gives every sample.
    direct = nt <= max_direct_times
    if (direct) then
      allocate (tw(0:nf - 1, 0:3, nt))
      do it = 1, nt
        do i = 0, 3
          do k = 0, nf - 1
            ! (k n reduced modulo nfft in 64 bits keeps the angle exact for large n)
            tw(k, i, it) = exp(cmplx(0.0_wp, 2.0_wp*pi*real(modulo(int(k, i8)*int(jt(it) + i, i8), &
                                                                   int(nfft, i8)), wp)/real(nfft, wp), wp))
          end do
        end do
      end do
    else
      allocate (sig(0:nfft - 1))
    end if
    allocate (spec(0:nfft/2))
    ! (only F_0 ... F_{N-1} are set below; the higher frequencies stay zero, and are set to
    ! zero again before each FFT, which may overwrite its input)
    spec = (0.0_wp, 0.0_wp)
    if (.not. direct) plan = fftw_plan_dft_c2r_1d(int(nfft, C_INT), spec, sig, FFTW_ESTIMATE)
    allocate (gm(2, 0:nf - 1), gp(2, 0:nf - 1))
    do iz = 1, nz
      do k = 0, nf - 1
        if (base) then
          ! Base motion: e^{-lambda (L - z)} from the base and its reflection at the top,
          ! e^{-lambda (L + z)}; velocities use their sum, stresses their difference.
          e_up = decay(lam(:, k)*(col%length - z(iz)))
          e_down = decay(lam(:, k)*(col%length + z(iz)))
          gm(:, k) = sigma_k(k)*(e_up + e_down)
          gp(:, k) = sigma_k(k)*(e_down - e_up)
        else
          ! Top load: downward term e^{-lambda z}, upward term (already reflected)
          ! e^{-lambda (2L - z)}; velocities use their difference, stresses their sum.
          e_down = decay(lam(:, k)*z(iz))
          e_up = decay(lam(:, k)*(2.0_wp*col%length - z(iz)))
          gm(:, k) = sigma_k(k)*(e_down - e_up)
          gp(:, k) = sigma_k(k)*(e_down + e_up)
        end if
      end do
      do ifield = 1, 4
        if (.not. direct) spec = (0.0_wp, 0.0_wp)
        if (ifield <= 2) then
          spec(0:nf - 1) = amp(ifield, 1, :)*gm(1, :) + amp(ifield, 2, :)*gm(2, :)
        else
          spec(0:nf - 1) = amp(ifield, 1, :)*gp(1, :) + amp(ifield, 2, :)*gp(2, :)
        end if
        ! F(alpha) is real; c2r ignores its imaginary part anyway.
        spec(0) = cmplx(real(spec(0), wp), 0.0_wp, wp)
        if (.not. direct) call fftw_execute_dft_c2r(plan, spec, sig)
        do it = 1, nt
          j0 = jt(it)
          u = times(it)/dt - real(j0, wp)
          do i = 0, 3
            if (direct) then
              sn = real(spec(0), wp) + 2.0_wp*sum(real(spec(1:nf - 1)*tw(1:nf - 1, i, it), wp))
            else
              sn = sig(j0 + i)
            end if
            f(i) = exp(alph*dt*real(j0 + i, wp))*sn/tp
          end do
          ! Cubic Lagrange weights on the nodes 0..3 at u.
          w(0) = -(u - 1.0_wp)*(u - 2.0_wp)*(u - 3.0_wp)/6.0_wp
          w(1) = u*(u - 2.0_wp)*(u - 3.0_wp)/2.0_wp
          w(2) = -u*(u - 1.0_wp)*(u - 3.0_wp)/2.0_wp
          w(3) = u*(u - 1.0_wp)*(u - 2.0_wp)/6.0_wp
          select case (ifield)
          case (1)
            v_s(iz, it) = sum(w*f)
          case (2)
            v_f(iz, it) = sum(w*f)
          case (3)
            sigma_eff(iz, it) = sum(w*f)
          case (4)
            p(iz, it) = sum(w*f)
          end select
        end do
      end do
    end do
    if (.not. direct) call fftw_destroy_plan(plan)
  end subroutine invert_modes

  !> The column of biot_column_solve with its base moving instead of its top loaded: both
  !> phases at the base z = L follow the base's velocity V_b(t) (positive downwards), the top
  !> z = 0 drained and free of traction (sigma'(0,t) = p(0,t) = 0), zero initial state
  !> (doc/theory.md 9.2, "Base motion"). V_b is the piecewise linear function through the
  !> samples vb(1:nb) at t = (i - 1) dtb, held at vb(nb) after the last; vb(1) must be 0 (the
  !> base starts from rest). Its Laplace transform is taken exactly (hat functions), so the
  !> fields are those of the code's base motion, which interpolates its record the same way.
  !> Fields, options and accuracy as biot_column_solve (col%load is not used). The Lanczos
  !> factors (window) smooth fronts but damp a smooth record's content at frequency f by
  !> about (pi f T_p/N)^2/6 (2e-5 at 60 Hz with T_p = 1 s, N = 2^14): leave them out for a
  !> record without jumps (window = .false.).
  subroutine biot_column_base_solve(col, nb, dtb, vb, t_end, nz, z, nt, times, p, sigma_eff, &
                                    v_s, v_f, window, nfreq, period, alpha)
    type(biot_column_t), intent(in) :: col
    integer, intent(in) :: nb, nz, nt
    real(wp), intent(in) :: dtb, vb(nb), t_end
    real(wp), intent(in) :: z(nz), times(nt)
    real(wp), intent(out) :: p(nz, nt), sigma_eff(nz, nt), v_s(nz, nt), v_f(nz, nt)
    logical, intent(in), optional :: window
    integer, intent(in), optional :: nfreq
    real(wp), intent(in), optional :: period, alpha
    complex(wp), allocatable :: lam(:, :), amp(:, :, :)
    complex(wp) :: s
    real(wp) :: tp, alph, omega0
    integer :: nf, k
    logical :: use_window

    call check_inputs(col, t_end, z, times)
    if (nb < 2 .or. .not. dtb > 0.0_wp) call fatal('needs nb >= 2 samples and dtb > 0', &
                                                   'biot_column_base_solve')
    if (vb(1) /= 0.0_wp) call fatal('the base must start from rest: vb(1) = 0', &
                                    'biot_column_base_solve')
    call inversion_options(t_end, 'biot_column_base_solve', window, nfreq, period, alpha, use_window, nf, tp, &
                           alph)
    omega0 = 2.0_wp*pi/tp
    allocate (lam(2, 0:nf - 1), amp(4, 2, 0:nf - 1))
    do k = 0, nf - 1
      s = cmplx(alph, real(k, wp)*omega0, wp)
      call base_modes(col, s, lam(:, k), amp(:, :, k))
      amp(:, :, k) = amp(:, :, k)*piecewise_linear_transform(nb, dtb, vb, s)
    end do
    call invert_modes(col, .true., nf, tp, alph, use_window, lam, amp, nz, z, nt, times, &
                      p, sigma_eff, v_s, v_f)
  end subroutine biot_column_base_solve

  !> The inversion's settings of a solve (doc/theory.md 9.2): the Lanczos window (on
  !> unless window says otherwise), nf frequencies, the period tp and the damping alph, each
  !> its default unless given; refuses settings the inversion cannot use (who: the caller).
  subroutine inversion_options(t_end, who, window, nfreq, period, alpha, use_window, nf, tp, alph)
    real(wp), intent(in) :: t_end
    character(len=*), intent(in) :: who
    logical, intent(in), optional :: window
    integer, intent(in), optional :: nfreq
    real(wp), intent(in), optional :: period, alpha
    logical, intent(out) :: use_window
    integer, intent(out) :: nf
    real(wp), intent(out) :: tp, alph
    use_window = .true.
    if (present(window)) use_window = window
    nf = biot_default_nfreq
    if (present(nfreq)) nf = nfreq
    tp = default_period_factor*t_end
    if (present(period)) tp = period
    alph = default_alpha_period/tp
    if (present(alpha)) alph = alpha
    if (nf < 16 .or. tp < t_end .or. alph <= 0.0_wp) &
      call fatal('needs nfreq >= 16, period >= t_end and alpha > 0', who)
  end subroutine inversion_options

  !> Laplace transform at s of the piecewise linear function through v(1:n) at t = (i - 1) h,
  !> zero at t = 0 (v(1) = 0 is not used) and held at v(n) after t_n: the sum of the hats
  !> e^{-s t_i} (e^{sh} - 2 + e^{-sh})/(s^2 h) = e^{-s t_i} 4 sinh^2(sh/2)/(s^2 h) of the
  !> inner samples, and for the last its left half with the step after it,
  !> e^{-s t_n} (e^{sh} - 1)/(s^2 h) = e^{-s t_n} 2 e^{sh/2} sinh(sh/2)/(s^2 h) (sinh keeps
  !> both free of cancellation when |s h| is small).
  pure function piecewise_linear_transform(n, h, v, s) result(f)
    integer, intent(in) :: n
    real(wp), intent(in) :: h, v(n)
    complex(wp), intent(in) :: s
    complex(wp) :: f, zh, e, acc, sh
    integer :: i
    zh = exp(-s*h)
    sh = sinh(0.5_wp*s*h)
    ! sum_{i=2}^{n-1} v(i) e^{-s (i-1) h}, e^{-s (i-1) h} by recurrence (|zh| < 1)
    acc = (0.0_wp, 0.0_wp)
    e = (1.0_wp, 0.0_wp)
    do i = 2, n - 1
      e = e*zh
      acc = acc + v(i)*e
    end do
    e = e*zh
    f = (4.0_wp*sh*sh*acc + v(n)*e*2.0_wp*exp(0.5_wp*s*h)*sh)/(s*s*h)
  end function piecewise_linear_transform

  !> Algorithm B of doc/theory.md 9.2: sigma'(z,t) of the finite column with incompressible
  !> constituents (telegraph equation rho~ u_tt = E_c u_zz - (rho_f g/k) u_t), as the image sum
  !> sigma' = sum_j (-1)^j [f(2jL + z, t) + f(2(j+1)L - z, t)] of the half-space solution
  !> f(zeta,t) = -q H(t - a)[e^{-beta a} + a beta int_a^t e^{-beta tau} I_1(beta r)/r dtau],
  !> a = zeta/c, r = sqrt(tau^2 - a^2). col%k_f is not used (infinite).
  pure function biot_incompressible_sigma(col, z, t) result(sigma)
    type(biot_column_t), intent(in) :: col
    real(wp), intent(in) :: z, t
    real(wp) :: sigma
    real(wp) :: ns, rho_t, c, beta, zeta(2), sgn
    integer :: j, i
    ns = 1.0_wp - col%porosity
    rho_t = ns*col%rho_s + ns**2/col%porosity*col%rho_f
    c = sqrt(col%e_c/rho_t)
    beta = col%rho_f*col%gravity/(2.0_wp*rho_t*col%conductivity)
    sigma = 0.0_wp
    sgn = 1.0_wp
    j = 0
    do
      zeta = [2.0_wp*j*col%length + z, 2.0_wp*(j + 1)*col%length - z]
      if (zeta(1) >= c*t) exit
      do i = 1, 2
        sigma = sigma + sgn*half_space_sigma(col%load, zeta(i)/c, beta, t)
      end do
      sgn = -sgn
      j = j + 1
    end do
  end function biot_incompressible_sigma

  ! ---------------------------------------------------------------------------------------------

  !> Half-space step response f of algorithm B at travel time a = zeta/c. With tau = a cosh(theta),
  !> r = a sinh(theta), dtau = r dtheta, the integrand becomes e^{-beta a e^{-theta}} e^{-x} I_1(x),
  !> x = beta a sinh(theta): smooth and bounded, integrated by composite Simpson in theta (4000
  !> panels; halving them changed the results by < 1e-13 at the cross-check points of doc/theory.md 9.2).
  pure function half_space_sigma(q, a, beta, t) result(f)
    real(wp), intent(in) :: q, a, beta, t
    real(wp) :: f
    integer, parameter :: npanel = 4000
    real(wp) :: theta_max, h, acc, th
    integer :: i
    if (t <= a) then
      f = 0.0_wp
      return
    end if
    if (a <= 0.0_wp) then
      f = -q
      return
    end if
    theta_max = log(t/a + sqrt((t/a)**2 - 1.0_wp))
    h = theta_max/npanel
    acc = 0.0_wp
    do i = 0, npanel
      th = i*h
      if (i == 0 .or. i == npanel) then
        acc = acc + integrand(th)
      else if (mod(i, 2) == 1) then
        acc = acc + 4.0_wp*integrand(th)
      else
        acc = acc + 2.0_wp*integrand(th)
      end if
    end do
    f = -q*(exp(-beta*a) + a*beta*acc*h/3.0_wp)
  contains
    pure real(wp) function integrand(theta)
      real(wp), intent(in) :: theta
      integrand = exp(-beta*a*exp(-theta))*scaled_i1(beta*a*sinh(theta))
    end function integrand
  end function half_space_sigma

  !> e^{-x} I_1(x) for x >= 0: power series up to x = 25 (positive terms, no cancellation),
  !> Hankel's asymptotic series beyond (smallest term about e^{-2x} < 1e-21 there).
  pure function scaled_i1(x) result(y)
    real(wp), intent(in) :: x
    real(wp) :: y, term, acc
    integer :: k
    if (x <= 25.0_wp) then
      ! I_1(x) = sum_k (x/2)^{2k+1} / (k! (k+1)!)
      term = 0.5_wp*x
      acc = term
      do k = 1, 200
        term = term*(0.25_wp*x*x)/(real(k, wp)*real(k + 1, wp))
        acc = acc + term
        if (term <= 1.0e-17_wp*acc) exit
      end do
      y = exp(-x)*acc
    else
      ! e^{-x} I_1(x) ~ (2 pi x)^{-1/2} sum_k (-1)^k prod_{i<=k} (4 - (2i-1)^2) / (k! (8x)^k)
      term = 1.0_wp
      acc = 1.0_wp
      do k = 1, 30
        term = -term*(4.0_wp - real(2*k - 1, wp)**2)/(real(k, wp)*8.0_wp*x)
        acc = acc + term
        if (abs(term) <= 1.0e-17_wp*abs(acc)) exit
      end do
      y = acc/sqrt(2.0_wp*pi*x)
    end if
  end function scaled_i1

  !> The two modes of doc/theory.md 9.2 at Laplace variable s, reduced to the amplitudes of the
  !> fields per unit load after the boundary conditions are applied:
  !> amp(:, j) = (phi_s, phi_f, Sigma', P)_j * c_j, c_j = d_j / (1 + e^{-2 lambda_j L}).
  pure subroutine column_modes(col, s, lam, amp)
    type(biot_column_t), intent(in) :: col
    complex(wp), intent(in) :: s
    complex(wp), intent(out) :: lam(2), amp(4, 2)
    complex(wp) :: phi(2, 2), sig(2), pre(2), det, d(2), e2
    integer :: j
    call mode_shapes(col, s, lam, phi, sig, pre)
    ! Top: sum_j Sigma'_j d_j = -q/s, sum_j P_j d_j = 0 (Cramer).
    det = sig(1)*pre(2) - sig(2)*pre(1)
    d(1) = -col%load/s*pre(2)/det
    d(2) = col%load/s*pre(1)/det
    do j = 1, 2
      e2 = decay(2.0_wp*lam(j)*col%length)
      amp(1:2, j) = phi(:, j)*d(j)/(1.0_wp + e2)
      amp(3, j) = sig(j)*d(j)/(1.0_wp + e2)
      amp(4, j) = pre(j)*d(j)/(1.0_wp + e2)
    end do
  end subroutine column_modes

  !> The two modes at s for a base velocity of unit transform (doc/theory.md 9.2, "Base
  !> motion"): each mode's wave from the base, b_j e^{-lambda_j (L - z)}, reflects on its own
  !> at the free drained top into a_j e^{-lambda_j z}, a_j = b_j e^{-lambda_j L}; the base
  !> condition V_s(L) = V_f(L) = 1 leaves sum_j phi_j d_j = (1, 1), d_j = b_j (1 + e^{-2
  !> lambda_j L}). amp(:, j) = (phi_s, phi_f, Sigma', P)_j d_j / (1 + e^{-2 lambda_j L}).
  pure subroutine base_modes(col, s, lam, amp)
    type(biot_column_t), intent(in) :: col
    complex(wp), intent(in) :: s
    complex(wp), intent(out) :: lam(2), amp(4, 2)
    complex(wp) :: phi(2, 2), sig(2), pre(2), det, d(2), e2
    integer :: j
    call mode_shapes(col, s, lam, phi, sig, pre)
    det = phi(1, 1)*phi(2, 2) - phi(1, 2)*phi(2, 1)
    d(1) = (phi(2, 2) - phi(1, 2))/det
    d(2) = (phi(1, 1) - phi(2, 1))/det
    do j = 1, 2
      e2 = decay(2.0_wp*lam(j)*col%length)
      amp(1:2, j) = phi(:, j)*d(j)/(1.0_wp + e2)
      amp(3, j) = sig(j)*d(j)/(1.0_wp + e2)
      amp(4, j) = pre(j)*d(j)/(1.0_wp + e2)
    end do
  end subroutine base_modes

  !> The wavenumbers lam(j) (Re > 0) and shapes of the two modes at s: velocities phi(:, j)
  !> (solid, fluid; scaled to a largest component of 1), and the effective stress sig(j) and
  !> pore pressure pre(j) of the downward wave e^{-lambda_j z} with that velocity.
  pure subroutine mode_shapes(col, s, lam, phi, sig, pre)
    type(biot_column_t), intent(in) :: col
    complex(wp), intent(in) :: s
    complex(wp), intent(out) :: lam(2), phi(2, 2), sig(2), pre(2)
    real(wp) :: nf, ns, m, ms, mf, q_drag
    complex(wp) :: a, b, c, disc, mu(2), vol(2)
    real(wp) :: nrm
    integer :: j
    nf = col%porosity
    ns = 1.0_wp - nf
    m = col%k_f/nf
    ms = ns*col%rho_s
    mf = nf*col%rho_f
    q_drag = biot_drag(col)
    ! det(mu K - B) = a mu^2 - b mu + c with K = [[E_c + ns^2 M, ns nf M], [ns nf M, nf^2 M]],
    ! B = s^2 diag(m_s, m_f) + s Q [[1, -1], [-1, 1]]. The coefficients are written out so that
    ! the large M terms cancel analytically (det K = E_c nf^2 M), not in floating point.
    a = col%e_c*nf**2*m
    b = col%e_c*(s**2*mf + s*q_drag) + m*(s**2*(ns**2*mf + nf**2*ms) + s*q_drag)
    c = s**3*(s*ms*mf + q_drag*(ms + mf))
    disc = sqrt(b**2 - 4.0_wp*a*c)
    if (real(conjg(b)*disc, wp) < 0.0_wp) disc = -disc
    ! Both roots without cancellation: mu_1 mu_2 = c/a.
    mu(1) = (b + disc)/(2.0_wp*a)
    mu(2) = 2.0_wp*c/(b + disc)
    do j = 1, 2
      lam(j) = sqrt(mu(j))          ! principal root: Re lambda > 0 for Re s > 0
      ! Null vector from the second row of (mu K - B) phi = 0; its volumetric combination
      ! ns phi_s + nf phi_f = -(ns s^2 m_f + s Q) is exact (no M left), which keeps P accurate
      ! for a nearly incompressible fluid.
      phi(1, j) = mu(j)*nf**2*m - s**2*mf - s*q_drag
      phi(2, j) = -mu(j)*ns*nf*m - s*q_drag
      vol(j) = -(ns*s**2*mf + s*q_drag)
      nrm = max(abs(phi(1, j)), abs(phi(2, j)))
      phi(:, j) = phi(:, j)/nrm
      vol(j) = vol(j)/nrm
      ! Downward wave e^{-lambda z}: Sigma' = -(E_c lambda/s) phi_s, P = (M lambda/s) vol.
      sig(j) = -col%e_c*lam(j)/s*phi(1, j)
      pre(j) = m*lam(j)/s*vol(j)
    end do
  end subroutine mode_shapes

  !> e^{-x} for Re x >= 0, set to zero where it would underflow.
  elemental function decay(x) result(y)
    complex(wp), intent(in) :: x
    complex(wp) :: y
    if (real(x, wp) > 700.0_wp) then
      y = (0.0_wp, 0.0_wp)
    else
      y = exp(-x)
    end if
  end function decay

  !> Refuse inputs outside the solution's domain.
  subroutine check_inputs(col, t_end, z, times)
    type(biot_column_t), intent(in) :: col
    real(wp), intent(in) :: t_end, z(:), times(:)
    if (.not. (col%length > 0.0_wp .and. col%porosity > 0.0_wp .and. col%porosity < 1.0_wp &
               .and. col%rho_s > 0.0_wp .and. col%rho_f > 0.0_wp .and. col%e_c > 0.0_wp &
               .and. col%k_f > 0.0_wp .and. col%conductivity > 0.0_wp &
               .and. col%gravity > 0.0_wp)) &
      call fatal('column needs length, rho_s, rho_f, e_c, k_f, conductivity, gravity > 0 and '// &
                 '0 < porosity < 1', 'biot_column_solve')
    if (.not. t_end > 0.0_wp) call fatal('t_end must be > 0', 'biot_column_solve')
    if (any(z < 0.0_wp) .or. any(z > col%length)) &
      call fatal('depths z must lie in [0, length]', 'biot_column_solve')
    if (any(times < 0.0_wp) .or. any(times > t_end)) &
      call fatal('times must lie in [0, t_end]', 'biot_column_solve')
  end subroutine check_inputs

end module dpmpm_biot_column
