!> The mu(I) rheology of dense granular flow (GDR MiDi 2004; Jop, Forterre & Pouliquen 2006)
!> as an elasto-viscoplastic skeleton, in the spirit of Dunatunga & Kamrin (2015). In the mean
!> effective stress p (compression positive, p = -tr(sigma)/3), the deviator s and the
!> equivalent shear stress tau = |s|/sqrt(2):
!>   elasticity        Hookean (E, nu: the moduli and so the time step of the other soils),
!>                     on the Jaumann-rotated stress, trial s_tr, p_tr, tau_tr;
!>   friction          mu(I) = mu_s + (mu_2 - mu_s)/(I_0/I + 1), I = gdot_p d/sqrt(p/rho_s),
!>                     gdot_p the plastic shear rate, d the grain diameter, rho_s the grain
!>                     density;
!>   flow              D^p = gdot_p s/(2 tau) (deviatoric, no plastic volume change): the
!>                     deviator scales, s = s_tr tau/tau_tr, p = p_tr; with dilatancy
!>                     (dilatancy_k > 0) also the plastic volume rate gdot_p tan(psi),
!>                     tan(psi) = K (phi - phi_c + a I), and the friction mu(I) + tan(psi)
!>                     (dilatant_return);
!>   return            tau_tr <= mu_s p_tr: elastic (gdot_p = 0); else tau = tau_tr - G dt gdot_p
!>                     = mu(I(gdot_p)) p_tr, a quadratic in gdot_p with one positive root
!>                     (mu_i_rate; doc/theory.md 5.9).
!> Low pressure and separation: a trial stress in mean tension (p_tr <= 0) returns to zero
!> stress; the grains have come apart and the point carries nothing until a compression
!> gives it pressure again, from the volume it has then (the elastic strain of the gap is
!> not remembered). This replaces the density criterion of Dunatunga & Kamrin (stress-free
!> below a critical density), which would need the packing fraction as a state value.
!> max_dilation (when > 0) bounds the volume of a point, as for the other soils: a point at
!> a thinning front, apart and stress-free, would otherwise stretch without end and its
!> wave speed, so the time step, with it.
!> Two state values per point (dpmpm_model_table): the accumulated plastic shear strain
!> sum(dt gdot_p) and the inertial number I of the last step (0 where elastic or apart).
!> In a saturated soil this is the effective stress and p the effective pressure.
module dpmpm_model_mu_i
  use dpmpm_kinds, only: wp
  use dpmpm_material_params, only: material_t
  use dpmpm_model_plastic, only: jaumann_strain
  implicit none
  private
  public :: mu_i_update, mu_i_return, mu_i_rate, mu_of_i

contains

  !> The update of stress_update (dpmpm_materials) for the points of material index m: the
  !> stress rotated with the spin (Jaumann), then mu_i_return of the strain increment dt D
  !> over the step dt; state(1, :) the plastic shear strain, state(2, :) the inertial
  !> number. dissipation gains V (sigma_n + sigma_n+1)/2 : (deps - C^-1 dsigma), the plastic
  !> work of the step (with the elastic energy a point loses when it comes apart).
  subroutine mu_i_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
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
    real(wp) :: sr(6), de(6), jac, sn(6), dsig(6), dep(6), wsum, gdot, inum
    integer :: p
    logical :: flat
    flat = .false.
    if (present(plane)) flat = plane
    wsum = 0.0_wp
    if (present(dissipation)) wsum = dissipation
    do p = 1, n
      if (pmat(p) /= m) cycle
      call jaumann_strain(dt, vgrad(:, p), stress(:, p), flat, sr, de, jac)
      sn = sr
      ! (the volume fraction, phi0 V0/V, only where the return uses it: with dilatancy)
      if (mat%mui_k > 0.0_wp) then
        call mu_i_return(mat, dt, de, sn, gdot, inum, mat%mui_phi0*vol0(p)/vol(p))
      else
        call mu_i_return(mat, dt, de, sn, gdot, inum)
      end if
      if (present(dissipation)) then
        dsig = sn - sr
        dep(1:3) = de(1:3) - ((1.0_wp + mat%poisson)*dsig(1:3) - mat%poisson*sum(dsig(1:3))) &
                   /mat%youngs
        dep(4:6) = de(4:6) - dsig(4:6)/mat%mu
        wsum = wsum + 0.5_wp*vol(p)*dot_product(sr + sn, dep)
      end if
      stress(:, p) = sn
      state(1, p) = state(1, p) + dt*gdot
      state(2, p) = inum
      vol(p) = vol(p)*jac
      ! grains apart beyond the bound: the volume stays there (as the other soils, 5.4)
      if (mat%max_dilation > 0.0_wp) vol(p) = min(vol(p), mat%max_dilation*vol0(p))
    end do
    if (present(dissipation)) dissipation = wsum
  end subroutine mu_i_update

  !> The return of one point over a step dt: stress (Voigt, tension positive, rotated) takes
  !> the strain increment deps (engineering shears). gdot is the plastic shear rate of the
  !> step and inum its inertial number (both 0 where the step is elastic or the point has
  !> come apart: p_tr <= 0 gives zero stress).
  pure subroutine mu_i_return(mat, dt, deps, stress, gdot, inum, phi)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt, deps(6)
    real(wp), intent(inout) :: stress(6)
    real(wp), intent(out) :: gdot, inum
    real(wp), intent(in), optional :: phi
    real(wp) :: p, s(6), tau
    gdot = 0.0_wp
    inum = 0.0_wp
    if (mat%mui_k > 0.0_wp .and. present(phi)) then
      call dilatant_return(mat, dt, deps, stress, gdot, inum, phi)
      return
    end if
    call elastic_trial(mat, deps, stress, p, s, tau)
    if (p <= 0.0_wp) then
      stress = 0.0_wp
      return
    end if
    ! (a step of no time, dt = 0, has no rate to flow at: it stays elastic)
    if (tau > mat%mui_mu_s*p .and. dt > 0.0_wp) then
      gdot = mu_i_rate(mat, dt, tau, p)
      inum = gdot*mat%mui_diameter*sqrt(mat%mui_grain_density/p)
      ! the deviator scales to tau - G dt gdot (= mu(I) p), keeping its direction
      s = s*(max(tau - mat%mu*dt*gdot, 0.0_wp)/tau)
    end if
    stress(1:3) = s(1:3) - p
    stress(4:6) = s(4:6)
  end subroutine mu_i_return

  !> The elastic trial of a step: p_tr = p_n - K tr(deps), s_tr = s_n + 2 G dev(deps) (s, tau
  !> = |s_tr|/sqrt(2)).
  pure subroutine elastic_trial(mat, deps, stress, p, s, tau)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: deps(6), stress(6)
    real(wp), intent(out) :: p, s(6), tau
    real(wp) :: dv
    dv = deps(1) + deps(2) + deps(3)
    p = -(stress(1) + stress(2) + stress(3))/3.0_wp - mat%bulk*dv
    s(1:3) = stress(1:3) - (stress(1) + stress(2) + stress(3))/3.0_wp &
             + 2.0_wp*mat%mu*(deps(1:3) - dv/3.0_wp)
    s(4:6) = stress(4:6) + mat%mu*deps(4:6)
    tau = sqrt(0.5_wp*(s(1)**2 + s(2)**2 + s(3)**2) + sum(s(4:6)**2))
  end subroutine elastic_trial

  !> The return with dilatancy (doc/theory.md 5.9, "Dilatancy"): the point of volume
  !> fraction phi (at the start of the step) flows with the plastic shear rate x and the
  !> plastic volume rate x tan(psi), tan(psi) = K (phi - phi_c + a I), under the friction
  !> mu(I) + tan(psi) (not below 0). Over the step p = p_tr + K_b dt x tan(psi) and
  !> tau = tau_tr - G dt x = (mu(I) + tan(psi)) p, I = x d sqrt(rho_s/p): for each x the
  !> pressure is the one root of an increasing function (dilatant_pressure), and x is the
  !> root of the shear equation, bracketed in [0, tau_tr/(G dt)] and found by regula falsi
  !> (Illinois). A pressure that falls to zero leaves the point without stress (liquefied).
  pure subroutine dilatant_return(mat, dt, deps, stress, gdot, inum, phi)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt, deps(6), phi
    real(wp), intent(inout) :: stress(6)
    real(wp), intent(out) :: gdot, inum
    real(wp) :: ptr, s(6), tau, xa, xb, fa, fb, x, f, p, pa, pb
    integer :: it, side
    gdot = 0.0_wp
    inum = 0.0_wp
    call elastic_trial(mat, deps, stress, ptr, s, tau)
    if (ptr <= 0.0_wp) then
      stress = 0.0_wp
      return
    end if
    p = ptr
    if (tau > max(mat%mui_mu_s + mat%mui_k*(phi - mat%mui_phic), 0.0_wp)*ptr .and. dt > 0.0_wp) then
      ! f(0) = tau - (mu_s + tan psi_0) p_tr > 0, f(tau/(G dt)) = -(friction) p <= 0
      xa = 0.0_wp
      call shear_residual(mat, dt, tau, ptr, phi, xa, fa, pa)
      xb = tau/(mat%mu*dt)
      call shear_residual(mat, dt, tau, ptr, phi, xb, fb, pb)
      x = xb
      p = pb
      side = 0
      ! (fb = 0: no friction left at the end of the range, the root is xb)
      do it = 1, 200
        if (fb >= 0.0_wp) exit
        x = (xa*fb - xb*fa)/(fb - fa)
        call shear_residual(mat, dt, tau, ptr, phi, x, f, p)
        if (abs(f) <= 1.0e-13_wp*tau .or. xb - xa <= 1.0e-15_wp*xb) exit
        if (f > 0.0_wp) then
          xa = x
          fa = f
          if (side == 1) fb = 0.5_wp*fb
          side = 1
        else
          xb = x
          fb = f
          if (side == -1) fa = 0.5_wp*fa
          side = -1
        end if
      end do
      gdot = x
      if (p <= 0.0_wp) then
        ! the contraction took all the pressure: the grains float (liquefied)
        stress = 0.0_wp
        return
      end if
      inum = x*mat%mui_diameter*sqrt(mat%mui_grain_density/p)
      s = s*(max(tau - mat%mu*dt*x, 0.0_wp)/tau)
    end if
    stress(1:3) = s(1:3) - p
    stress(4:6) = s(4:6)
  end subroutine dilatant_return

  !> The shear equation of the dilatant return at the plastic shear rate x:
  !> tau_tr - G dt x - max(mu(I) + tan(psi), 0) p, with p = dilatant_pressure(x).
  pure subroutine shear_residual(mat, dt, tau, ptr, phi, x, f, p)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt, tau, ptr, phi, x
    real(wp), intent(out) :: f, p
    real(wp) :: inum
    p = dilatant_pressure(mat, dt, ptr, phi, x)
    inum = 0.0_wp
    if (p > 0.0_wp) inum = x*mat%mui_diameter*sqrt(mat%mui_grain_density/p)
    f = tau - mat%mu*dt*x - max(mu_of_i(mat, inum) + &
                                mat%mui_k*(phi - mat%mui_phic + mat%mui_slope*inum), 0.0_wp)*p
  end subroutine shear_residual

  !> The pressure at the end of a step of plastic shear rate x >= 0: the root of
  !> h(p) = p - A - B/sqrt(p), A = p_tr + K_b dt x K (phi - phi_c),
  !> B = K_b dt x K a x d sqrt(rho_s) >= 0 (the plastic volume change x tan(psi) dt taken
  !> back elastically). h rises with p, so the root is unique; with B > 0 it is positive and
  !> lies in [lo, hi] (doc/theory.md 5.9); with B = 0 it is max(A, 0).
  pure real(wp) function dilatant_pressure(mat, dt, ptr, phi, x) result(p)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt, ptr, phi, x
    real(wp) :: a, b, lo, hi, h, dh
    integer :: it
    a = ptr + mat%bulk*dt*x*mat%mui_k*(phi - mat%mui_phic)
    b = mat%bulk*dt*x*mat%mui_k*mat%mui_slope*x*mat%mui_diameter*sqrt(mat%mui_grain_density)
    if (b <= 0.0_wp) then
      p = max(a, 0.0_wp)
      return
    end if
    hi = max(a, 0.0_wp) + b**(2.0_wp/3.0_wp) + 1.0_wp
    lo = (b/(abs(a) + hi))**2
    p = max(a, lo)
    if (p >= hi) p = 0.5_wp*(lo + hi)
    do it = 1, 200
      h = p - a - b/sqrt(p)
      if (h > 0.0_wp) then
        hi = p
      else
        lo = p
      end if
      if (abs(h) <= 1.0e-15_wp*max(abs(a), p) .or. hi - lo <= 1.0e-15_wp*hi) exit
      dh = 1.0_wp + 0.5_wp*b/(p*sqrt(p))
      p = p - h/dh
      ! (a Newton step out of the bracket falls back to its middle)
      if (p <= lo .or. p >= hi) p = 0.5_wp*(lo + hi)
    end do
  end function dilatant_pressure

  !> The plastic shear rate gdot > 0 of a trial tau > mu_s p (p > 0) over a step dt: the
  !> root of tau - G dt gdot = mu(I) p, I = a gdot, a = d sqrt(rho_s/p). With S = tau - mu_s p
  !> and c = G dt it is c a x^2 + (c I_0 + a ((mu_2 - mu_s) p - S)) x - S I_0 = 0, whose
  !> product of roots is negative: one positive root, taken in the form without
  !> cancellation.
  pure real(wp) function mu_i_rate(mat, dt, tau, p) result(x)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt, tau, p
    real(wp) :: a, c, s, b, qa, disc
    a = mat%mui_diameter*sqrt(mat%mui_grain_density/p)
    c = mat%mu*dt
    s = tau - mat%mui_mu_s*p
    qa = c*a
    b = c*mat%mui_i0 + a*((mat%mui_mu_2 - mat%mui_mu_s)*p - s)
    disc = sqrt(b*b + 4.0_wp*qa*s*mat%mui_i0)
    if (b >= 0.0_wp) then
      x = 2.0_wp*s*mat%mui_i0/(b + disc)
    else
      x = (disc - b)/(2.0_wp*qa)
    end if
  end function mu_i_rate

  !> The friction coefficient mu(I) = mu_s + (mu_2 - mu_s) I/(I_0 + I) of inertial number I.
  elemental real(wp) function mu_of_i(mat, inum) result(mu)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: inum
    mu = mat%mui_mu_s + (mat%mui_mu_2 - mat%mui_mu_s)*inum/(mat%mui_i0 + inum)
  end function mu_of_i

end module dpmpm_model_mu_i
