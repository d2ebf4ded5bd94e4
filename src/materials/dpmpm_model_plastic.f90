!> The elasto-plastic soils, Mohr-Coulomb and Drucker-Prager: the stress is first rotated
!> with the spin (Jaumann, sigma + dt (W sigma - sigma W)), then dpmpm_plasticity's return
!> takes the strain increment dt D (elastic predictor and return). One state value per
!> point (dpmpm_model_table): the accumulated plastic strain that softens the cohesion.
!> In a saturated soil this is the effective stress; the pore pressure stays apart.
!> dissipation (when present) gains the plastic work of the step,
!> V (sigma_n + sigma_n+1)/2 : d eps^p with d eps^p = dt D - C^-1 (sigma_n+1 - sigma_n)
!> (sigma_n after the rotation), so that the energy balance can count it.
module dpmpm_model_plastic
  use dpmpm_kinds, only: wp
  use dpmpm_material_params, only: material_t
  use dpmpm_plasticity, only: plastic_returns
  implicit none
  private
  public :: plastic_update, jaumann_strain

contains

  !> The update of stress_update (dpmpm_materials) for the points of material index m;
  !> state(1, :) is the accumulated plastic strain.
  subroutine plastic_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
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
    integer, parameter :: nb = 64
    real(wp) :: dsig(6), dep(6), sr(6, nb), sn(6, nb), de(6, nb), jb(nb), ep(nb), wsum
    real(wp) :: rcp_youngs, rcp_mu
    integer :: p, k, q, nk, idx(nb)
    logical :: flat
    flat = .false.
    if (present(plane)) flat = plane
    rcp_youngs = 1.0_wp/mat%youngs
    rcp_mu = 1.0_wp/mat%mu
    wsum = 0.0_wp
    if (present(dissipation)) wsum = dissipation
    ! In blocks of up to nb points of the material: rotation and strain increment, the
    ! returns in one call, then the plastic work and the volume.
    p = 0
    do while (p < n)
      nk = 0
      do while (p < n .and. nk < nb)
        p = p + 1
        if (pmat(p) /= m) cycle
        nk = nk + 1
        idx(nk) = p
        call jaumann_strain(dt, vgrad(:, p), stress(:, p), flat, sr(:, nk), de(:, nk), jb(nk))
        ep(nk) = state(1, p)
      end do
      sn(:, 1:nk) = sr(:, 1:nk)
      call plastic_returns(mat%plastic, nk, de, sn, ep)
      do k = 1, nk
        q = idx(k)
        stress(:, q) = sn(:, k)
        state(1, q) = ep(k)
        if (present(dissipation)) then
          dsig = sn(:, k) - sr(:, k)
          dep(1:3) = de(1:3, k) - ((1.0_wp + mat%poisson)*dsig(1:3) - mat%poisson*sum(dsig(1:3))) &
                     *rcp_youngs
          dep(4:6) = de(4:6, k) - dsig(4:6)*rcp_mu
          wsum = wsum + 0.5_wp*vol(q)*dot_product(sr(:, k) + sn(:, k), dep)
        end if
        vol(q) = vol(q)*jb(k)
        ! Grains that have moved apart: the volume stays at the bound (doc/theory.md 5.4).
        if (mat%max_dilation > 0.0_wp) vol(q) = min(vol(q), mat%max_dilation*vol0(q))
      end do
    end do
    if (present(dissipation)) dissipation = wsum
  end subroutine plastic_update

  !> The elastic predictor's kinematics of the plastic soils for one point with velocity
  !> gradient lv (3x3 column-major): the stress s rotated with the spin W = (L - L^T)/2,
  !> sr = s + dt (W s - s W), the strain increment deps = dt D (engineering shears) and
  !> jac = det(I + dt L). W s - s W = Z + Z^T with Z = W s is written out for its few
  !> terms; plane (2D) leaves out the third row and column of L, which are zero there.
  pure subroutine jaumann_strain(dt, lv, s, plane, sr, deps, jac)
    real(wp), intent(in) :: dt, lv(9), s(6)
    logical, intent(in) :: plane
    real(wp), intent(out) :: sr(6), deps(6), jac
    real(wp) :: w12, w13, w23, a11, a22, a33
    w12 = 0.5_wp*dt*(lv(4) - lv(2))
    a11 = 1.0_wp + dt*lv(1)
    a22 = 1.0_wp + dt*lv(5)
    if (plane) then
      ! only w12: the in-plane block turns, s13 and s23 turn into each other
      sr(1) = s(1) + 2.0_wp*w12*s(6)
      sr(2) = s(2) - 2.0_wp*w12*s(6)
      sr(3) = s(3)
      sr(4) = s(4) - w12*s(5)
      sr(5) = s(5) + w12*s(4)
      sr(6) = s(6) + w12*(s(2) - s(1))
      deps = 0.0_wp
      deps(1) = dt*lv(1)
      deps(2) = dt*lv(5)
      deps(6) = dt*(lv(4) + lv(2))
      jac = a11*a22 - dt*dt*lv(4)*lv(2)
    else
      w13 = 0.5_wp*dt*(lv(7) - lv(3))
      w23 = 0.5_wp*dt*(lv(8) - lv(6))
      sr(1) = s(1) + 2.0_wp*(w12*s(6) + w13*s(5))
      sr(2) = s(2) + 2.0_wp*(w23*s(4) - w12*s(6))
      sr(3) = s(3) - 2.0_wp*(w13*s(5) + w23*s(4))
      sr(4) = s(4) - w12*s(5) - w13*s(6) + w23*(s(3) - s(2))
      sr(5) = s(5) + w12*s(4) + w13*(s(3) - s(1)) - w23*s(6)
      sr(6) = s(6) + w12*(s(2) - s(1)) + w13*s(4) + w23*s(5)
      deps(1) = dt*lv(1)
      deps(2) = dt*lv(5)
      deps(3) = dt*lv(9)
      deps(4) = dt*(lv(8) + lv(6))
      deps(5) = dt*(lv(7) + lv(3))
      deps(6) = dt*(lv(4) + lv(2))
      a33 = 1.0_wp + dt*lv(9)
      jac = a11*(a22*a33 - dt*dt*lv(8)*lv(6)) - dt*lv(4)*(dt*lv(2)*a33 - dt*dt*lv(8)*lv(3)) &
            + dt*lv(7)*(dt*dt*lv(2)*lv(6) - a22*dt*lv(3))
    end if
  end subroutine jaumann_strain

end module dpmpm_model_plastic
