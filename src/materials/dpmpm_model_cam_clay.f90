!> Modified Cam-Clay (Roscoe & Burland 1968; Wood 1990, ch. 4-7), the critical-state model
!> of soft clay, as the effective stress of a dry or saturated skeleton. In the mean
!> effective stress p (compression positive, p = -tr(sigma)/3) and the deviator
!> q = sqrt(3/2 s:s):
!>   yield surface     f = q^2/M^2 + p (p - p_c) = 0   (an ellipse through 0 and p_c);
!>   elasticity        the volume follows the swelling line, (1 + e) d eps_v^e = kappa dp/p,
!>                     integrated over a step as p + p_m = (p_n + p_m) exp((1 + e_n) deps_v^e
!>                     / kappa) (p_m, min_pressure: the soil keeps the stiffness of p + p_m, so
!>                     that a point at zero stress still carries waves), bulk modulus
!>                     K = (1 + e)(p + p_m)/kappa, shear modulus G given or from K and nu;
!>   flow              associated: deps_v^p = dgamma (2p - p_c), deps_q^p = dgamma 2q/M^2;
!>   hardening         (lambda - kappa) dp_c/p_c = (1 + e) deps_v^p, integrated as
!>                     p_c = p_c,n exp((1 + e_n) deps_v^p/(lambda - kappa)).
!> The return is implicit (backward Euler in p, q, p_c; de Souza Neto, Peric & Owen 2008,
!> ch. 7, and Borja & Lee 1990 for the exponential forms): two unknowns, deps_v^p and
!> dgamma, by Newton's method; the deviator returns radially, s = s_tr q/q_tr. With the
!> exponential forms a constant-volume step keeps ln p + ((lambda - kappa)/kappa) ln p_c
!> exactly, so that an undrained triaxial path lies on the closed form
!> p/p_0 = (1 + eta^2/M^2)^(-(lambda - kappa)/lambda) at any step size (doc/verification.md).
!> A trial stress in mean tension (possible down to -p_m) returns to the apex, zero effective
!> stress: the soil has come apart. A step whose Newton iteration does not converge is split
!> into 2, 4, ... substeps (up to 2^max_halvings); one that still fails is reported, never
!> skipped.
!> Two state values per point (dpmpm_model_table): the preconsolidation pressure p_c and the
!> void ratio e (e + 1 follows the volume: (1 + e) = (1 + e_n) J over a step).
module dpmpm_model_cam_clay
  use dpmpm_kinds, only: wp
  use dpmpm_error, only: fatal
  use dpmpm_material_params, only: material_t
  use dpmpm_model_plastic, only: jaumann_strain
  implicit none
  private
  public :: cam_clay_update, cam_clay_return, cam_clay_init_state, cam_clay_moduli
  public :: cam_clay_energy, max_halvings

  !> The most times a step is halved when its return does not converge.
  integer, parameter :: max_halvings = 10
  !> Newton's method: relative tolerance and iteration cap of one return.
  real(wp), parameter :: newton_tol = 1.0e-12_wp
  integer, parameter :: newton_max = 60

contains

  !> The update of stress_update (dpmpm_materials) for the points of material index m:
  !> the stress rotated with the spin (Jaumann), then cam_clay_return of the strain
  !> increment dt D; state(1, :) is p_c, state(2, :) the void ratio. dissipation gains
  !> V (sigma_n + sigma_n+1)/2 : (deps - deps^e), the elastic part from the swelling line
  !> and G. A point whose return fails even in 2^max_halvings substeps stops the run
  !> through fatal (MPI_Abort: every rank stops) with its index, p_c and stress.
  subroutine cam_clay_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                             dissipation, plane)
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
    real(wp) :: sr(6), de(6), jac, sn(6), st(2), wsum, dee(6)
    character(len=400) :: msg
    integer :: p, code
    logical :: flat
    flat = .false.
    if (present(plane)) flat = plane
    wsum = 0.0_wp
    if (present(dissipation)) wsum = dissipation
    do p = 1, n
      if (pmat(p) /= m) cycle
      call jaumann_strain(dt, vgrad(:, p), stress(:, p), flat, sr, de, jac)
      st = state(1:2, p)
      sn = sr
      call cam_clay_return(mat, de, sn, st, code, dee)
      if (code /= 0) then
        write (msg, '(a,i0,a,i0,a,es12.5,a,6es12.4,a,6es12.4)') 'the Cam-Clay return of point ', &
          p, ' did not converge in ', 2**max_halvings, ' substeps; p_c = ', state(1, p), &
          ', stress ', stress(:, p), ', strain increment ', de
        call fatal(trim(msg), 'cam_clay_update')
      end if
      if (present(dissipation)) wsum = wsum + 0.5_wp*vol(p)*dot_product(sr + sn, de - dee)
      stress(:, p) = sn
      ! the void ratio follows the volume of the step
      st(2) = (1.0_wp + state(2, p))*jac - 1.0_wp
      state(1:2, p) = st
      vol(p) = vol(p)*jac
    end do
    if (present(dissipation)) dissipation = wsum
  end subroutine cam_clay_update

  !> The return of one point: stress (Voigt, tension positive, rotated) takes the strain
  !> increment deps (engineering shears); st = [p_c, e] at the start (e is not changed here:
  !> the caller follows the volume). code = 0 on success; deps_e (optional) the elastic
  !> part of deps. Newton's method on the whole increment; where it fails, substeps.
  pure subroutine cam_clay_return(mat, deps, stress, st, code, deps_e)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: deps(6)
    real(wp), intent(inout) :: stress(6), st(2)
    integer, intent(out) :: code
    real(wp), intent(out), optional :: deps_e(6)
    real(wp) :: s0(6), pc0, sub(6), dsum(6), dpart(6)
    integer :: h, k, nsub
    s0 = stress
    pc0 = st(1)
    do h = 0, max_halvings
      nsub = 2**h
      stress = s0
      st(1) = pc0
      sub = deps/real(nsub, wp)
      dsum = 0.0_wp
      do k = 1, nsub
        call one_return(mat, sub, stress, st, code, dpart)
        if (code /= 0) exit
        dsum = dsum + dpart
      end do
      if (code == 0) then
        if (present(deps_e)) deps_e = dsum
        return
      end if
    end do
    stress = s0
    st(1) = pc0
    if (present(deps_e)) deps_e = 0.0_wp
  end subroutine cam_clay_return

  !> One backward-Euler return over deps (see the module note); deps_e the elastic part.
  pure subroutine one_return(mat, deps, stress, st, code, deps_e)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: deps(6)
    real(wp), intent(inout) :: stress(6), st(2)
    integer, intent(out) :: code
    real(wp), intent(out) :: deps_e(6)
    real(wp) :: pn, sdev(6), dv, ddev(6), g, ptr, qtr, pc, a, b, m2, pm, x, dg, pp, q, pcx
    real(wp) :: r1, r2, j11, j12, j21, j22, det, dx, ddg, scale, fac, dpv
    integer :: it
    logical :: polish
    code = 0
    pm = mat%cc_min_pressure
    m2 = mat%cc_m**2
    pn = -(stress(1) + stress(2) + stress(3))/3.0_wp
    sdev = stress
    sdev(1:3) = sdev(1:3) + pn
    ! volumetric strain, compression positive, and the deviatoric strain (tensor shears)
    dv = -(deps(1) + deps(2) + deps(3))
    ddev(1:3) = deps(1:3) + dv/3.0_wp
    ddev(4:6) = 0.5_wp*deps(4:6)
    a = (1.0_wp + st(2))/mat%cc_kappa
    b = (1.0_wp + st(2))/(mat%cc_lambda - mat%cc_kappa)
    call cam_clay_moduli(mat, pn, st(2), g=g)
    ptr = (pn + pm)*exp(a*dv) - pm
    sdev = sdev + 2.0_wp*g*ddev
    qtr = sqrt(1.5_wp*(sdev(1)**2 + sdev(2)**2 + sdev(3)**2 + 2.0_wp*sum(sdev(4:6)**2)))
    pc = st(1)
    ! A trial in mean tension lies beyond the apex of the surface, which holds p >= 0 only:
    ! the soil has come apart and carries no effective stress (the apex return; p_c stays,
    ! no plastic work is booked).
    if (ptr <= 0.0_wp) then
      stress = 0.0_wp
      deps_e = deps
      return
    end if
    scale = max(pc, pn + pm, ptr + pm)**2
    if (qtr**2/m2 + ptr*(ptr - pc) <= newton_tol*scale) then
      stress = sdev
      stress(1:3) = stress(1:3) - ptr
      deps_e = deps
      return
    end if
    ! Newton on r1 = x - dgamma (2p - p_c), r2 = f(p, q, p_c), x = deps_v^p
    x = 0.0_wp
    dg = 0.0_wp
    polish = .false.
    do it = 1, newton_max
      pp = (ptr + pm)*exp(-a*x) - pm
      pcx = pc*exp(b*x)
      fac = 1.0_wp + 6.0_wp*g*dg/m2
      q = qtr/fac
      r1 = x - dg*(2.0_wp*pp - pcx)
      r2 = q**2/m2 + pp*(pp - pcx)
      ! r1 is measured against its terms, not against x alone: at the critical state
      ! 2p - p_c vanishes and x with it, while the round-off of dgamma (2p - p_c) stays that
      ! of dgamma (2p + p_c) (a point there stalled at 10x the old bound for 60 iterations).
      ! Once both residuals pass, one more step takes them to round-off.
      if (polish) exit
      polish = abs(r1) <= newton_tol*max(abs(x), dg*(2.0_wp*abs(pp) + pcx), newton_tol) .and. &
               abs(r2) <= newton_tol*scale
      ! derivatives: dp/dx = -a (p + p_m), dp_c/dx = b p_c, dq/ddgamma = -q (6G/M^2)/fac
      j11 = 1.0_wp + dg*(2.0_wp*a*(pp + pm) + b*pcx)
      j12 = -(2.0_wp*pp - pcx)
      j21 = -(2.0_wp*pp - pcx)*a*(pp + pm) - pp*b*pcx
      j22 = -2.0_wp*q**2*(6.0_wp*g/m2)/(m2*fac)
      det = j11*j22 - j12*j21
      if (det == 0.0_wp) then
        code = 1
        return
      end if
      dx = -(r1*j22 - j12*r2)/det
      ddg = -(j11*r2 - j21*r1)/det
      x = x + dx
      dg = max(dg + ddg, 0.0_wp)
    end do
    if (it > newton_max .or. .not. (abs(x) < huge(1.0_wp))) then
      code = 1
      return
    end if
    pp = (ptr + pm)*exp(-a*x) - pm
    q = qtr/(1.0_wp + 6.0_wp*g*dg/m2)
    st(1) = pc*exp(b*x)
    if (qtr > 0.0_wp) sdev = sdev*(q/qtr)
    stress = sdev
    stress(1:3) = stress(1:3) - pp
    ! the elastic part: the plastic volumetric strain x and deviator 3/2 dgamma (2/M^2) s
    dpv = x/3.0_wp
    deps_e(1:3) = deps(1:3) + dpv - 3.0_wp*dg/m2*sdev(1:3)
    deps_e(4:6) = deps(4:6) - 6.0_wp*dg/m2*sdev(4:6)
  end subroutine one_return

  !> The elastic moduli at mean effective stress p (compression positive) and void ratio e:
  !> K = (1 + e)(p + p_m)/kappa, G given (shear_modulus) or 3K(1 - 2nu)/(2(1 + nu)).
  elemental subroutine cam_clay_moduli(mat, p, e, k, g)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: p, e
    real(wp), intent(out), optional :: k, g
    real(wp) :: kk
    kk = (1.0_wp + e)*max(p + mat%cc_min_pressure, 0.0_wp)/mat%cc_kappa
    if (present(k)) k = kk
    if (present(g)) then
      if (mat%cc_shear > 0.0_wp) then
        g = mat%cc_shear
      else
        g = 1.5_wp*kk*(1.0_wp - 2.0_wp*mat%poisson)/(1.0_wp + mat%poisson)
      end if
    end if
  end subroutine cam_clay_moduli

  !> The initial state of the points of material index m from their initial (effective)
  !> stress: e = void_ratio, and p_c = preconsolidation_pressure if given, else ocr times
  !> the size of the yield surface through the stress, p + q^2/(M^2 p) (p at least
  !> min_pressure, so that a point at zero stress starts on a small surface).
  subroutine cam_clay_init_state(mat, m, n, pmat, stress, state)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: stress(:, :)
    real(wp), intent(inout) :: state(:, :)
    real(wp) :: p, q, s(6)
    integer :: k
    do k = 1, n
      if (pmat(k) /= m) cycle
      s = stress(:, k)
      p = -(s(1) + s(2) + s(3))/3.0_wp
      s(1:3) = s(1:3) + p
      q = sqrt(1.5_wp*(s(1)**2 + s(2)**2 + s(3)**2 + 2.0_wp*sum(s(4:6)**2)))
      p = max(p, mat%cc_min_pressure, tiny(1.0_wp))
      state(1, k) = max(mat%cc_pc0, mat%cc_ocr*(p + q**2/(mat%cc_m**2*p)))
      state(2, k) = mat%cc_e0
    end do
  end subroutine cam_clay_init_state

  !> Stored elastic energy of one point, approximated with the moduli at its stress:
  !> V (p^2/(2K) + q^2/(6G)) (the complementary energy of the tangent moduli).
  pure real(wp) function cam_clay_energy(mat, s, e, vol) result(w)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: s(6), e, vol
    real(wp) :: p, q, d(6), k, g
    p = -(s(1) + s(2) + s(3))/3.0_wp
    d = s
    d(1:3) = d(1:3) + p
    q = sqrt(1.5_wp*(d(1)**2 + d(2)**2 + d(3)**2 + 2.0_wp*sum(d(4:6)**2)))
    call cam_clay_moduli(mat, p, e, k, g)
    w = 0.0_wp
    if (k > 0.0_wp) w = w + p**2/(2.0_wp*k)
    if (g > 0.0_wp) w = w + q**2/(6.0_wp*g)
    w = w*vol
  end function cam_clay_energy

end module dpmpm_model_cam_clay
