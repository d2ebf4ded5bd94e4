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
!>                     deviator scales, s = s_tr tau/tau_tr, p = p_tr;
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
      call mu_i_return(mat, dt, de, sn, gdot, inum)
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
  pure subroutine mu_i_return(mat, dt, deps, stress, gdot, inum)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt, deps(6)
    real(wp), intent(inout) :: stress(6)
    real(wp), intent(out) :: gdot, inum
    real(wp) :: p, dv, s(6), tau
    gdot = 0.0_wp
    inum = 0.0_wp
    ! elastic trial: p_tr = p_n - K tr(deps), s_tr = s_n + 2 G dev(deps)
    dv = deps(1) + deps(2) + deps(3)
    p = -(stress(1) + stress(2) + stress(3))/3.0_wp - mat%bulk*dv
    if (p <= 0.0_wp) then
      stress = 0.0_wp
      return
    end if
    s(1:3) = stress(1:3) - (stress(1) + stress(2) + stress(3))/3.0_wp &
             + 2.0_wp*mat%mu*(deps(1:3) - dv/3.0_wp)
    s(4:6) = stress(4:6) + mat%mu*deps(4:6)
    tau = sqrt(0.5_wp*(s(1)**2 + s(2)**2 + s(3)**2) + sum(s(4:6)**2))
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
