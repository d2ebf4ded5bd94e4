!> Elasto-plastic soil: Mohr-Coulomb and Drucker-Prager with a linear isotropic
!> elastic predictor and an implicit (backward Euler) return mapping, after de Souza
!> Neto, Peric & Owen, "Computational Methods for Plasticity" (2008), ch. 8
!> (MC in principal stresses: main plane, edges, apex; DP: cone and apex).
!>
!> Conventions: stress positive in tension, Voigt order xx yy zz yz xz xy; strain
!> increments in the same order with engineering shears (2 eps_yz, ...). The mean
!> stress is p = tr(sigma)/3 (positive in tension). Cohesion softens linearly with the
!> accumulated plastic strain epsp down to a residual value,
!>   c(epsp) = max(c_res, c0 - h epsp)       (linear hardening of the book with H = -h),
!> with epsp the strain-like variable conjugate to c of the book: d epsp = 2 cos(phi) sum dgamma
!> on the MC planes, xi dgamma on the DP cone, and (cos(phi)/sin(psi)) d eps_v^p resp.
!> (xi/eta_bar) d eps_v^p at the apex. With psi = 0 the plastic potential has no apex,
!> so the apex return (a tensile failure) leaves epsp unchanged.
!>
!> Tension cut-off, applied after the shear return (an operator split, not a
!> simultaneous multi-surface return; for nu >= 0 it can only lower the shear yield function):
!>   MC: Rankine, every principal stress <= sigma_t, associated flow, with the corners
!>       where two or three principal stresses reach sigma_t;
!>   DP: the mean stress p <= sigma_t, associated (volumetric) flow, s unchanged.
!> The cut-off does not change epsp. The volume it opens, eps_v^p, scales the returned stress
!> by exp(-eps_v^p) (opening_factor: the Kirchhoff stress J sigma is what an opening leaves).
module dpmpm_plasticity
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: plastic_params_t, plastic_setup, plastic_return, plastic_returns, principal_stresses
  public :: mc_yield, mc_potential, dp_yield, dp_potential, dp_constants, cohesion_at
  public :: softening_limit, elastic_trial
  public :: surface_mohr_coulomb, surface_drucker_prager
  public :: dp_plane_strain, dp_outer, dp_inner, dp_match_names
  public :: ret_elastic, ret_smooth, ret_edge_right, ret_edge_left, ret_apex

  integer, parameter :: surface_mohr_coulomb = 1, surface_drucker_prager = 2
  !> Drucker-Prager matchings to Mohr-Coulomb: plane strain, outer cone (touches MC on
  !> the compressive meridian sigma_1 = sigma_2), inner cone (extension meridian
  !> sigma_2 = sigma_3).
  integer, parameter :: dp_plane_strain = 1, dp_outer = 2, dp_inner = 3
  character(len=12), parameter :: dp_match_names(3) = ['plane_strain', 'outer       ', &
                                                       'inner       ']
  !> Which return was taken: none, the smooth part (MC main plane or DP cone), the MC
  !> right edge (sigma_1 = sigma_2), the MC left edge (sigma_2 = sigma_3), the apex.
  integer, parameter :: ret_elastic = 0, ret_smooth = 1, ret_edge_right = 2, ret_edge_left = 3, &
                        ret_apex = 4

  !> Relative tolerance of the yield test on the trial state.
  real(wp), parameter :: ftol = 1.0e-12_wp

  !> Constants of one elasto-plastic material (angles as sines and cosines).
  type :: plastic_params_t
    integer :: surface = surface_mohr_coulomb
    real(wp) :: bulk = 0.0_wp, shear = 0.0_wp    !< K, G of the elastic law
    real(wp) :: sin_phi = 0.0_wp, cos_phi = 1.0_wp !< friction angle phi
    real(wp) :: sin_psi = 0.0_wp                  !< dilatancy angle psi
    real(wp) :: cohesion = 0.0_wp                 !< c0 (Pa)
    real(wp) :: softening = 0.0_wp                !< h >= 0: dc/d epsp = -h (Pa)
    real(wp) :: residual = 0.0_wp                 !< c_res (Pa), <= c0
    real(wp) :: tensile = 0.0_wp                  !< tension cut-off sigma_t (Pa), >= 0
    real(wp) :: eta = 0.0_wp, xi = 0.0_wp, eta_bar = 0.0_wp !< DP constants
  end type plastic_params_t

contains

  !> Parameters from the input quantities: elastic K and G, angles in degrees, cohesion,
  !> tensile strength, softening modulus h, residual cohesion, DP matching.
  pure function plastic_setup(surface, bulk, shear, phi_deg, psi_deg, cohesion, tensile, &
                              softening, residual, match) result(par)
    integer, intent(in) :: surface, match
    real(wp), intent(in) :: bulk, shear, phi_deg, psi_deg, cohesion, tensile, softening, residual
    type(plastic_params_t) :: par
    real(wp) :: phi, psi, dum
    real(wp), parameter :: deg = acos(-1.0_wp)/180.0_wp
    phi = phi_deg*deg
    psi = psi_deg*deg
    par%surface = surface
    par%bulk = bulk
    par%shear = shear
    par%sin_phi = sin(phi)
    par%cos_phi = cos(phi)
    par%sin_psi = sin(psi)
    par%cohesion = cohesion
    par%softening = softening
    par%residual = min(residual, cohesion)
    par%tensile = tensile
    call dp_constants(match, phi, par%eta, par%xi)
    call dp_constants(match, psi, par%eta_bar, dum)
  end function plastic_setup

  !> Drucker-Prager eta and xi of f = sqrt(J2) + eta p - xi c matched to Mohr-Coulomb
  !> with the angle a (radians): plane strain eta = 3 tan a / sqrt(9 + 12 tan^2 a),
  !> xi = 3 / sqrt(9 + 12 tan^2 a); outer and inner cones eta = 6 sin a / (sqrt(3)(3 -+ sin a)),
  !> xi = 6 cos a / (sqrt(3)(3 -+ sin a)) (de Souza Neto et al. 2008, ch. 8).
  pure subroutine dp_constants(match, a, eta, xi)
    integer, intent(in) :: match
    real(wp), intent(in) :: a
    real(wp), intent(out) :: eta, xi
    real(wp) :: t, r
    select case (match)
    case (dp_outer)
      r = sqrt(3.0_wp)*(3.0_wp - sin(a))
      eta = 6.0_wp*sin(a)/r
      xi = 6.0_wp*cos(a)/r
    case (dp_inner)
      r = sqrt(3.0_wp)*(3.0_wp + sin(a))
      eta = 6.0_wp*sin(a)/r
      xi = 6.0_wp*cos(a)/r
    case default
      t = tan(a)
      r = sqrt(9.0_wp + 12.0_wp*t*t)
      eta = 3.0_wp*t/r
      xi = 3.0_wp/r
    end select
  end subroutine dp_constants

  !> Cohesion at accumulated plastic strain epsp: max(c_res, c0 - h epsp).
  pure real(wp) function cohesion_at(par, epsp) result(c)
    type(plastic_params_t), intent(in) :: par
    real(wp), intent(in) :: epsp
    c = max(par%residual, par%cohesion - par%softening*epsp)
  end function cohesion_at

  !> Largest softening modulus h for which every return has a unique solution: the
  !> denominators of the one-plane, two-plane and apex returns stay positive.
  pure real(wp) function softening_limit(par) result(hmax)
    type(plastic_params_t), intent(in) :: par
    real(wp) :: dmat(3, 3), ga(3), a0, ab, k
    k = par%bulk
    hmax = huge(1.0_wp)
    if (par%surface == surface_mohr_coulomb) then
      if (par%cos_phi <= 0.0_wp) return
      dmat = principal_elasticity(par)
      ! one plane: a0 - 4 cos^2(phi) h > 0; two planes (a, b): (a0 + A_ab)/2 - 4 cos^2(phi) h > 0
      ga = plane_vector(1, 3, par%sin_phi)
      a0 = dot_product(ga, matmul(dmat, plane_vector(1, 3, par%sin_psi)))
      hmax = a0/(4.0_wp*par%cos_phi**2)
      ab = dot_product(ga, matmul(dmat, plane_vector(2, 3, par%sin_psi)))
      hmax = min(hmax, 0.5_wp*(a0 + ab)/(4.0_wp*par%cos_phi**2))
      ab = dot_product(ga, matmul(dmat, plane_vector(1, 2, par%sin_psi)))
      hmax = min(hmax, 0.5_wp*(a0 + ab)/(4.0_wp*par%cos_phi**2))
      ! apex: K - h (cos(phi)/sin(psi)) cot(phi) > 0
      if (par%sin_psi > 0.0_wp .and. par%sin_phi > 0.0_wp) &
        hmax = min(hmax, k*par%sin_phi*par%sin_psi/par%cos_phi**2)
    else
      if (par%xi <= 0.0_wp) return
      hmax = (par%shear + k*par%eta*par%eta_bar)/par%xi**2
      if (par%eta_bar > 0.0_wp .and. par%eta > 0.0_wp) &
        hmax = min(hmax, k*par%eta*par%eta_bar/par%xi**2)
    end if
  end function softening_limit

  !> Mohr-Coulomb yield function f = (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi) of the
  !> Voigt stress sv (s1 >= s2 >= s3 its principal values).
  pure real(wp) function mc_yield(sv, sin_phi, cos_phi, c) result(f)
    real(wp), intent(in) :: sv(6), sin_phi, cos_phi, c
    real(wp) :: sig(3), vec(3, 3)
    call principal_stresses(sv, sig, vec)
    f = (sig(1) - sig(3)) + (sig(1) + sig(3))*sin_phi - 2.0_wp*c*cos_phi
  end function mc_yield

  !> Mohr-Coulomb plastic potential g = (s1 - s3) + (s1 + s3) sin(psi).
  pure real(wp) function mc_potential(sv, sin_psi) result(g)
    real(wp), intent(in) :: sv(6), sin_psi
    real(wp) :: sig(3), vec(3, 3)
    call principal_stresses(sv, sig, vec)
    g = (sig(1) - sig(3)) + (sig(1) + sig(3))*sin_psi
  end function mc_potential

  !> Drucker-Prager yield function f = sqrt(J2) + eta p - xi c.
  pure real(wp) function dp_yield(sv, eta, xi, c) result(f)
    real(wp), intent(in) :: sv(6), eta, xi, c
    f = sqrt(j2_of(sv)) + eta*sum(sv(1:3))/3.0_wp - xi*c
  end function dp_yield

  !> Drucker-Prager plastic potential g = sqrt(J2) + eta_bar p.
  pure real(wp) function dp_potential(sv, eta_bar) result(g)
    real(wp), intent(in) :: sv(6), eta_bar
    g = sqrt(j2_of(sv)) + eta_bar*sum(sv(1:3))/3.0_wp
  end function dp_potential

  !> Elastic trial stress sigma + lambda tr(deps) I + 2 G deps (engineering shears in deps).
  pure function elastic_trial(par, sv, deps) result(tr)
    type(plastic_params_t), intent(in) :: par
    real(wp), intent(in) :: sv(6), deps(6)
    real(wp) :: tr(6), lam, ev
    lam = par%bulk - 2.0_wp*par%shear/3.0_wp
    ev = deps(1) + deps(2) + deps(3)
    tr(1:3) = sv(1:3) + lam*ev + 2.0_wp*par%shear*deps(1:3)
    tr(4:6) = sv(4:6) + par%shear*deps(4:6)
  end function elastic_trial

  !> One strain increment deps at one point: elastic predictor, then the return to the
  !> yield surface of par%surface and the tension cut-off. stress (Voigt) and epsp are
  !> updated in place; code tells which return was taken, cut whether the cut-off acted.
  pure subroutine plastic_return(par, deps, stress, epsp, code, cut)
    type(plastic_params_t), intent(in) :: par
    real(wp), intent(in) :: deps(6)
    real(wp), intent(inout) :: stress(6), epsp
    integer, intent(out), optional :: code
    logical, intent(out), optional :: cut
    real(wp) :: trial(6)
    integer :: kind
    logical :: cutoff
    trial = elastic_trial(par, stress, deps)
    if (par%surface == surface_mohr_coulomb) then
      call mc_return(par, trial, stress, epsp, kind, cutoff)
    else
      call dp_return(par, trial, stress, epsp, kind, cutoff)
    end if
    if (present(code)) code = kind
    if (present(cut)) cut = cutoff
  end subroutine plastic_return

  !> plastic_return of n points, deps(:, k) on stress(:, k) and epsp(k): the returns of a
  !> block of points in one loop, without a call per point from another module.
  pure subroutine plastic_returns(par, n, deps, stress, epsp)
    type(plastic_params_t), intent(in) :: par
    integer, intent(in) :: n
    real(wp), intent(in) :: deps(6, n)
    real(wp), intent(inout) :: stress(6, n), epsp(n)
    integer :: k
    do k = 1, n
      call plastic_return(par, deps(:, k), stress(:, k), epsp(k))
    end do
  end subroutine plastic_returns

  !> Mohr-Coulomb return in principal stresses (de Souza Neto et al. 2008, ch. 8):
  !> main plane, then the edge the trial state points to, then the apex; the stress is
  !> rebuilt with the eigenvectors of the trial stress (they do not change in an
  !> isotropic return).
  pure subroutine mc_return(par, trial, stress, epsp, kind, cutoff)
    type(plastic_params_t), intent(in) :: par
    real(wp), intent(in) :: trial(6)
    real(wp), intent(out) :: stress(6)
    real(wp), intent(inout) :: epsp
    integer, intent(out) :: kind
    logical, intent(out) :: cutoff
    real(wp) :: st(3), vec(3, 3), sig(3), dgam(2), cn, f, scale, tol, pa, cot, lam, dep, tr0
    integer :: pl(2, 2)
    logical :: ok, plane
    kind = ret_elastic
    cn = cohesion_at(par, epsp)
    plane = trial(4) == 0.0_wp .and. trial(5) == 0.0_wp
    call principal_stresses(trial, st, vec)
    sig = st
    f = (st(1) - st(3)) + (st(1) + st(3))*par%sin_phi - 2.0_wp*cn*par%cos_phi
    scale = abs(st(1)) + abs(st(3)) + cn
    dep = 0.0_wp
    if (f > ftol*scale) then
      ! main plane (1, 3)
      pl(:, 1) = [1, 3]
      call mc_planes(par, 1, pl, st, epsp, sig, dgam, dep)
      kind = ret_smooth
      tol = 1.0e-14_wp*scale
      if (sig(1) + tol < sig(2) .or. sig(2) + tol < sig(3)) then
        ! Which ordering the main-plane return breaks first: the right edge (s1 = s2) when
        ! (1 - sin psi) s1 - 2 s2 + (1 + sin psi) s3 < 0 at the trial state, else the left.
        if ((1.0_wp - par%sin_psi)*st(1) - 2.0_wp*st(2) + (1.0_wp + par%sin_psi)*st(3) < 0.0_wp) &
          then
          pl(:, 2) = [2, 3]
          kind = ret_edge_right
        else
          pl(:, 2) = [1, 2]
          kind = ret_edge_left
        end if
        call mc_planes(par, 2, pl, st, epsp, sig, dgam, dep)
        ! valid with both multipliers >= 0 and the ordering kept (beyond the apex the
        ! edge solution has sigma_3 above sigma_1)
        ok = all(dgam >= 0.0_wp) .and. sig(1) + tol >= sig(3)
        if (.not. ok .and. par%sin_phi > 0.0_wp) then
          ! apex: s1 = s2 = s3 = c cot(phi); d epsp = (cos(phi)/sin(psi)) d eps_v^p
          cot = par%cos_phi/par%sin_phi
          kind = ret_apex
          call apex_return(par, sum(st)/3.0_wp, epsp, cot, &
                           merge(par%cos_phi/par%sin_psi, 0.0_wp, par%sin_psi > 0.0_wp), pa, dep)
          sig = pa
        end if
      end if
    end if
    epsp = epsp + dep
    ! Rankine cut-off: top k principal stresses returned to sigma_t (associated flow).
    cutoff = sig(1) > par%tensile
    if (cutoff) then
      lam = par%bulk - 2.0_wp*par%shear/3.0_wp
      tr0 = sum(sig)
      call rankine(lam, lam + 2.0_wp*par%shear, par%tensile, sig)
      sig = sig*opening_factor(par, tr0 - sum(sig))
    end if
    if (kind == ret_elastic .and. .not. cutoff) then
      stress = trial
    else if (plane) then
      stress = rebuild_plane(sig, vec)
    else
      stress = rebuild(sig, vec)
    end if
  end subroutine mc_return

  !> Return to m = 1 or 2 Mohr-Coulomb planes pl(:, k) = (i, j), f_ij = (1 + sin phi) s_i -
  !> (1 - sin phi) s_j - 2 c cos phi, each with the flow vector of psi, from the trial
  !> principal stresses st; softening is linear until c reaches the residual, then flat.
  pure subroutine mc_planes(par, m, pl, st, epsp, sig, dgam, dep)
    type(plastic_params_t), intent(in) :: par
    integer, intent(in) :: m, pl(2, m)
    real(wp), intent(in) :: st(3), epsp
    real(wp), intent(out) :: sig(3), dgam(2), dep
    real(wp) :: cn, h
    cn = cohesion_at(par, epsp)
    h = 0.0_wp
    if (cn > par%residual) h = par%softening
    call mc_planes_solve(par, m, pl, st, cn, h, sig, dgam, dep)
    if (h > 0.0_wp .and. cn - h*dep < par%residual) &
      call mc_planes_solve(par, m, pl, st, par%residual, 0.0_wp, sig, dgam, dep)
  end subroutine mc_planes

  !> The linear system of mc_planes for cohesion cb at the start and softening slope hb:
  !> f_i(st) - sum_l (grad f_i . D N_l - 4 cos^2(phi) hb) dgamma_l = 0.
  pure subroutine mc_planes_solve(par, m, pl, st, cb, hb, sig, dgam, dep)
    type(plastic_params_t), intent(in) :: par
    integer, intent(in) :: m, pl(2, m)
    real(wp), intent(in) :: st(3), cb, hb
    real(wp), intent(out) :: sig(3), dgam(2), dep
    real(wp) :: dn(3, 2), a(2, 2), r(2), det, k4, gp, gm, dv, np, nm
    integer :: i, l
    k4 = 4.0_wp*par%cos_phi**2*hb
    ! grad f_ij = gp e_i - gm e_j; D N_ij with N_ij = (1 + sin psi) e_i - (1 - sin psi) e_j
    ! is lambda tr(N) = 2 lambda sin psi on every component plus 2 G N.
    gp = 1.0_wp + par%sin_phi
    gm = 1.0_wp - par%sin_phi
    dv = 2.0_wp*(par%bulk - 2.0_wp*par%shear/3.0_wp)*par%sin_psi
    np = 2.0_wp*par%shear*(1.0_wp + par%sin_psi)
    nm = 2.0_wp*par%shear*(1.0_wp - par%sin_psi)
    if (m == 1 .and. pl(1, 1) == 1 .and. pl(2, 1) == 3) then
      ! the main plane alone, (i, j) = (1, 3)
      dgam(1) = (gp*st(1) - gm*st(3) - 2.0_wp*cb*par%cos_phi) &
                /(gp*(dv + np) - gm*(dv - nm) - k4)
      dgam(2) = 0.0_wp
      sig(1) = st(1) - (dv + np)*dgam(1)
      sig(2) = st(2) - dv*dgam(1)
      sig(3) = st(3) - (dv - nm)*dgam(1)
      dep = 2.0_wp*par%cos_phi*dgam(1)
      return
    end if
    do l = 1, m
      dn(:, l) = dv
      dn(pl(1, l), l) = dv + np
      dn(pl(2, l), l) = dv - nm
    end do
    do i = 1, m
      r(i) = gp*st(pl(1, i)) - gm*st(pl(2, i)) - 2.0_wp*cb*par%cos_phi
      do l = 1, m
        a(i, l) = gp*dn(pl(1, i), l) - gm*dn(pl(2, i), l) - k4
      end do
    end do
    if (m == 1) then
      dgam(1) = r(1)/a(1, 1)
      dgam(2) = 0.0_wp
      sig = st - dn(:, 1)*dgam(1)
    else
      det = a(1, 1)*a(2, 2) - a(1, 2)*a(2, 1)
      dgam(1) = (a(2, 2)*r(1) - a(1, 2)*r(2))/det
      dgam(2) = (a(1, 1)*r(2) - a(2, 1)*r(1))/det
      sig = st - dn(:, 1)*dgam(1) - dn(:, 2)*dgam(2)
    end if
    dep = 2.0_wp*par%cos_phi*(dgam(1) + dgam(2))
  end subroutine mc_planes_solve

  !> Apex return of a hydrostatic state: p = c(epsp + alpha d eps_v) * ratio with
  !> p = p_tr - K d eps_v (ratio = cot phi for MC, xi/eta for DP).
  pure subroutine apex_return(par, ptr, epsp, ratio, alpha, p, dep)
    type(plastic_params_t), intent(in) :: par
    real(wp), intent(in) :: ptr, epsp, ratio, alpha
    real(wp), intent(out) :: p, dep
    real(wp) :: cn, h, dev
    cn = cohesion_at(par, epsp)
    h = 0.0_wp
    if (cn > par%residual .and. alpha > 0.0_wp) h = par%softening
    dev = (ptr - cn*ratio)/(par%bulk - h*alpha*ratio)
    if (h > 0.0_wp .and. cn - h*alpha*dev < par%residual) then
      cn = par%residual
      h = 0.0_wp
      dev = (ptr - cn*ratio)/par%bulk
    end if
    p = ptr - par%bulk*dev
    dep = alpha*dev
  end subroutine apex_return

  !> Rankine return of sorted principal stresses sig (descending) to sig_i <= t with
  !> associated flow: the k largest are set to t by solving the k x k elasticity block
  !> (diagonal d = lambda + 2G, off-diagonal lam), the others follow.
  pure subroutine rankine(lam, d, t, sig)
    real(wp), intent(in) :: lam, d, t
    real(wp), intent(inout) :: sig(3)
    real(wp) :: r1, r2, g1, g2, s(3)
    r1 = sig(1) - t
    ! one plane
    g1 = r1/d
    s = sig - lam*g1
    s(1) = t
    if (s(2) > t) then
      ! corner of two planes
      r2 = sig(2) - t
      g1 = (d*r1 - lam*r2)/(d*d - lam*lam)
      g2 = (d*r2 - lam*r1)/(d*d - lam*lam)
      s(1:2) = t
      s(3) = sig(3) - lam*(g1 + g2)
      if (s(3) > t) s = t
    end if
    sig = s
  end subroutine rankine

  !> The factor exp(-d eps_v^p) that the stress takes after the tension cut-off, with
  !> d eps_v^p = tr(C^-1 (sigma_before - sigma_after)) = dtr/(3K) the volume the cut-off
  !> opened (the sum of its multipliers: each Rankine flow vector has unit trace).
  !> Why: the cut-off is the one plastic flow here whose volume change has no bound
  !> (with sigma_t = 0 it opens at no cost). The point's volume V follows the total
  !> strain, so with the Cauchy stress kept, V sigma (its force on the grid) and its
  !> elastic energy V sigma : C^-1 : sigma / 2 grow with the opening at no work: a point
  !> squeezed sideways, opened, then let go gives back more than it took (a closed box of
  !> such soil, kicked, came to hold 18 % more energy than it was given, doc/verification.md
  !> "Tension cut-off: opening without work"). In finite strain plasticity the return works
  !> on the Kirchhoff stress
  !> tau = J sigma (de Souza Neto et al. 2008, ch. 14), and a plastic volume ratio J^p
  !> leaves tau as it is, so sigma = tau/J falls by 1/J^p = exp(-eps_v^p): the force that
  !> the opened point carries stays that of the closed one, and its elastic energy falls.
  !> The scaled state stays admissible (every surface here contains sigma = 0). Returns
  !> without the cut-off are untouched.
  pure real(wp) function opening_factor(par, dtr) result(a)
    type(plastic_params_t), intent(in) :: par
    real(wp), intent(in) :: dtr
    a = exp(-max(dtr, 0.0_wp)/(3.0_wp*par%bulk))
  end function opening_factor

  !> Drucker-Prager return (de Souza Neto et al. 2008, ch. 8): smooth cone with
  !> dgamma = f_tr / (G + K eta eta_bar - xi^2 h); when sqrt(J2_tr) - G dgamma < 0 the
  !> apex, p = xi c / eta, s = 0. Then the cut-off p <= sigma_t.
  pure subroutine dp_return(par, trial, stress, epsp, kind, cutoff)
    type(plastic_params_t), intent(in) :: par
    real(wp), intent(in) :: trial(6)
    real(wp), intent(out) :: stress(6)
    real(wp), intent(inout) :: epsp
    integer, intent(out) :: kind
    logical, intent(out) :: cutoff
    real(wp) :: ptr, s(6), q, cn, f, dgam, p, dep, h, a
    kind = ret_elastic
    ptr = sum(trial(1:3))/3.0_wp
    s = trial
    s(1:3) = s(1:3) - ptr
    q = sqrt(j2_of(trial))
    cn = cohesion_at(par, epsp)
    f = q + par%eta*ptr - par%xi*cn
    p = ptr
    dep = 0.0_wp
    if (f > ftol*(q + abs(ptr) + cn)) then
      kind = ret_smooth
      h = 0.0_wp
      if (cn > par%residual) h = par%softening
      dgam = f/(par%shear + par%bulk*par%eta*par%eta_bar - par%xi**2*h)
      if (h > 0.0_wp .and. cn - h*par%xi*dgam < par%residual) &
        dgam = (q + par%eta*ptr - par%xi*par%residual)/(par%shear + par%bulk*par%eta*par%eta_bar)
      if (q - par%shear*dgam >= 0.0_wp .or. par%eta <= 0.0_wp) then
        if (q > 0.0_wp) s = max(0.0_wp, 1.0_wp - par%shear*dgam/q)*s
        p = ptr - par%bulk*par%eta_bar*dgam
        dep = par%xi*dgam
      else
        kind = ret_apex
        call apex_return(par, ptr, epsp, par%xi/par%eta, &
                         merge(par%xi/par%eta_bar, 0.0_wp, par%eta_bar > 0.0_wp), p, dep)
        s = 0.0_wp
      end if
    end if
    epsp = epsp + dep
    cutoff = p > par%tensile
    a = 1.0_wp
    if (cutoff) then
      a = opening_factor(par, 3.0_wp*(p - par%tensile))
      p = par%tensile
    end if
    if (kind == ret_elastic .and. .not. cutoff) then
      stress = trial
    else if (cutoff) then
      stress(1:3) = (s(1:3) + p)*a
      stress(4:6) = s(4:6)*a
    else
      stress(1:3) = s(1:3) + p
      stress(4:6) = s(4:6)
    end if
  end subroutine dp_return

  !> Eigenvalues of the symmetric stress sv (Voigt), descending, and the eigenvectors as
  !> the columns of vec, by cyclic Jacobi rotations (exact to round-off for 3 x 3). Each
  !> rotation updates only the rows and columns p, q it mixes. With sv(4) = sv(5) = 0
  !> (plane strain) z is a principal direction and the one rotation of the xy block is
  !> the whole decomposition.
  pure subroutine principal_stresses(sv, sig, vec)
    real(wp), intent(in) :: sv(6)
    real(wp), intent(out) :: sig(3), vec(3, 3)
    real(wp) :: a11, a22, a33, a23, a13, a12, off, nrm, tiny2, c, s
    integer :: sweep
    vec = 0.0_wp
    vec(1, 1) = 1.0_wp
    vec(2, 2) = 1.0_wp
    vec(3, 3) = 1.0_wp
    a11 = sv(1); a22 = sv(2); a33 = sv(3); a23 = sv(4); a13 = sv(5); a12 = sv(6)
    if (a23 == 0.0_wp .and. a13 == 0.0_wp) then
      if (a12 /= 0.0_wp) then
        call plane_angle(a11, a22, a12, c, s)
        vec(1, 1) = c; vec(2, 1) = -s
        vec(1, 2) = s; vec(2, 2) = c
      end if
    else
      nrm = a11**2 + a22**2 + a33**2 + 2.0_wp*(a23**2 + a13**2 + a12**2)
      tiny2 = epsilon(1.0_wp)**2*nrm
      do sweep = 1, 50
        off = a12**2 + a13**2 + a23**2
        if (off <= 1.0e-34_wp*nrm .or. off == 0.0_wp) exit
        ! (p, q) = (1, 2), (1, 3), (2, 3); r is the third index, a_rp and a_rq its entries.
        ! An entry below one unit of round-off of the norm is set to zero instead of
        ! rotated (a state whose shear is round-off, as in a flow between walls).
        call rotate(a11, a22, a12, a13, a23, vec(:, 1), vec(:, 2))
        call rotate(a11, a33, a13, a12, a23, vec(:, 1), vec(:, 3))
        call rotate(a22, a33, a23, a12, a13, vec(:, 2), vec(:, 3))
      end do
    end if
    ! sort descending (three elements): (1, 2), (1, 3), (2, 3) swapped when out of order
    call order(a11, a22, vec(:, 1), vec(:, 2))
    call order(a11, a33, vec(:, 1), vec(:, 3))
    call order(a22, a33, vec(:, 2), vec(:, 3))
    sig(1) = a11; sig(2) = a22; sig(3) = a33
  contains
    !> One rotation in the plane (p, q), unless apq is negligible: arp and arq are the
    !> entries of the third row r, vp and vq the eigenvector columns p and q.
    pure subroutine rotate(app, aqq, apq, arp, arq, vp, vq)
      real(wp), intent(inout) :: app, aqq, apq, arp, arq, vp(3), vq(3)
      real(wp) :: tr, cr, sr, taur
      call drop_negligible(tiny2, apq)
      if (apq == 0.0_wp) return
      call jacobi_angle(app, aqq, apq, tr, cr, sr)
      taur = sr/(1.0_wp + cr)
      call rotate_pair(sr, taur, arp, arq)
      call rotate_columns(sr, taur, vp, vq)
    end subroutine rotate

    !> ai >= aj afterwards, their eigenvector columns vi and vj swapped with them.
    pure subroutine order(ai, aj, vi, vj)
      real(wp), intent(inout) :: ai, aj, vi(3), vj(3)
      real(wp) :: tmp
      if (aj > ai) then
        tmp = ai; ai = aj; aj = tmp
        call swap_columns(vi, vj)
      end if
    end subroutine order
  end subroutine principal_stresses

  !> The Jacobi rotation that zeroes apq: tangent t, cosine c, sine s (rotation with
  !> R_pp = R_qq = c, R_pq = s, R_qp = -s, A <- R^T A R); app and aqq are updated in the
  !> stable form app - t apq, aqq + t apq, and apq becomes 0.
  pure subroutine jacobi_angle(app, aqq, apq, t, c, s)
    real(wp), intent(inout) :: app, aqq, apq
    real(wp), intent(out) :: t, c, s
    real(wp) :: theta
    theta = (aqq - app)/(2.0_wp*apq)
    if (abs(theta) > 1.0e100_wp) then
      t = 0.5_wp/theta
    else
      t = sign(1.0_wp, theta)/(abs(theta) + sqrt(theta*theta + 1.0_wp))
    end if
    c = 1.0_wp/sqrt(t*t + 1.0_wp)
    s = t*c
    app = app - t*apq
    aqq = aqq + t*apq
    apq = 0.0_wp
  end subroutine jacobi_angle

  !> apq = 0 when apq^2 <= tiny2 (the square of one unit of round-off of the norm of the
  !> matrix): its rotation would move the principal values and the rebuilt stress by less
  !> than their own round-off.
  pure subroutine drop_negligible(tiny2, apq)
    real(wp), intent(in) :: tiny2
    real(wp), intent(inout) :: apq
    if (apq*apq <= tiny2) apq = 0.0_wp
  end subroutine drop_negligible

  !> The rotation of jacobi_angle for the 2 x 2 block alone, in closed form with two
  !> square roots and no chain of divisions: with d = (aqq - app)/2 and r = sqrt(d^2 + apq^2),
  !> t = sign(d) apq/(r + |d|), c = sqrt((r + |d|)/(2 r)) and s = t c. app and aqq are
  !> updated as app - t apq, aqq + t apq (stable: no difference of large terms).
  pure subroutine plane_angle(app, aqq, apq, c, s)
    real(wp), intent(inout) :: app, aqq
    real(wp), intent(in) :: apq
    real(wp), intent(out) :: c, s
    real(wp) :: d, r, e, t, rw, sa
    d = 0.5_wp*(aqq - app)
    r = sqrt(d*d + apq*apq)
    e = r + abs(d)
    sa = sign(1.0_wp, d)*apq
    t = sa/e
    rw = 1.0_wp/sqrt(2.0_wp*r*e)
    c = e*rw
    s = sa*rw
    app = app - t*apq
    aqq = aqq + t*apq
  end subroutine plane_angle

  !> The entries a_rp, a_rq of the third row under the rotation of jacobi_angle
  !> (tau = s/(1 + c)).
  pure subroutine rotate_pair(s, tau, arp, arq)
    real(wp), intent(in) :: s, tau
    real(wp), intent(inout) :: arp, arq
    real(wp) :: g, h
    g = arp
    h = arq
    arp = g - s*(h + tau*g)
    arq = h + s*(g - tau*h)
  end subroutine rotate_pair

  !> Eigenvector columns vp, vq under the same rotation (V <- V R).
  pure subroutine rotate_columns(s, tau, vp, vq)
    real(wp), intent(in) :: s, tau
    real(wp), intent(inout) :: vp(3), vq(3)
    real(wp) :: g, h
    integer :: i
    do i = 1, 3
      g = vp(i)
      h = vq(i)
      vp(i) = g - s*(h + tau*g)
      vq(i) = h + s*(g - tau*h)
    end do
  end subroutine rotate_columns

  !> Swaps two eigenvector columns.
  pure subroutine swap_columns(u, v)
    real(wp), intent(inout) :: u(3), v(3)
    real(wp) :: tmp(3)
    tmp = u
    u = v
    v = tmp
  end subroutine swap_columns

  !> Voigt stress sum_i sig_i v_i v_i^T from principal values and eigenvectors.
  pure function rebuild(sig, vec) result(sv)
    real(wp), intent(in) :: sig(3), vec(3, 3)
    real(wp) :: sv(6)
    integer :: i
    sv = 0.0_wp
    do i = 1, 3
      sv(1) = sv(1) + sig(i)*vec(1, i)**2
      sv(2) = sv(2) + sig(i)*vec(2, i)**2
      sv(3) = sv(3) + sig(i)*vec(3, i)**2
      sv(4) = sv(4) + sig(i)*vec(2, i)*vec(3, i)
      sv(5) = sv(5) + sig(i)*vec(1, i)*vec(3, i)
      sv(6) = sv(6) + sig(i)*vec(1, i)*vec(2, i)
    end do
  end function rebuild

  !> rebuild of a plane state, whose eigenvectors have no z part except the one that is
  !> e_z: no out-of-plane shear (its components are set to exactly zero; the other four
  !> are rebuild's sums, term for term).
  pure function rebuild_plane(sig, vec) result(sv)
    real(wp), intent(in) :: sig(3), vec(3, 3)
    real(wp) :: sv(6)
    sv = rebuild(sig, vec)
    sv(4:5) = 0.0_wp
  end function rebuild_plane

  !> Second invariant of the deviatoric part of the Voigt stress sv.
  pure real(wp) function j2_of(sv) result(j2)
    real(wp), intent(in) :: sv(6)
    real(wp) :: p
    p = sum(sv(1:3))/3.0_wp
    j2 = 0.5_wp*sum((sv(1:3) - p)**2) + sum(sv(4:6)**2)
  end function j2_of

  !> (1 + sin a) e_i - (1 - sin a) e_j: gradient of an MC plane (a = phi) or its flow
  !> vector (a = psi) in principal stress space.
  pure function plane_vector(i, j, sin_a) result(v)
    integer, intent(in) :: i, j
    real(wp), intent(in) :: sin_a
    real(wp) :: v(3)
    v = 0.0_wp
    v(i) = 1.0_wp + sin_a
    v(j) = -(1.0_wp - sin_a)
  end function plane_vector

  !> Isotropic elasticity in principal axes: lambda + 2G on the diagonal, lambda off it.
  pure function principal_elasticity(par) result(d)
    type(plastic_params_t), intent(in) :: par
    real(wp) :: d(3, 3), lam
    lam = par%bulk - 2.0_wp*par%shear/3.0_wp
    d = lam
    d(1, 1) = lam + 2.0_wp*par%shear
    d(2, 2) = d(1, 1)
    d(3, 3) = d(1, 1)
  end function principal_elasticity

end module dpmpm_plasticity
