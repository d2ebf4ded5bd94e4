!> Linear elastic model: hypoelastic with the Jaumann rate (objective under rotation),
!> sigma <- sigma + dt (lambda tr(D) I + 2 mu D + W sigma - sigma W), V <- V det(I + dt L).
!> Plane strain (2D) takes the short form with D33 = 0 and one spin component.
!> No state values (dpmpm_model_table).
module dpmpm_model_elastic
  use dpmpm_kinds, only: wp
  use dpmpm_material_params, only: material_t
  use dpmpm_tensor, only: voigt_to_tensor, tensor_to_voigt, as_3x3, det3
  implicit none
  private
  public :: elastic_update

contains

  !> The update of stress_update (dpmpm_materials) for the points of material index m.
  subroutine elastic_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
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
    real(wp) :: lg(3, 3), dmat(3, 3), wmat(3, 3), s(3, 3), ident(3, 3), tr
    integer :: p, k
    if (present(plane)) then
      if (plane) then
        call linear_elastic_plane(mat, m, dt, n, pmat, vgrad, stress, vol)
        return
      end if
    end if
    ident = 0.0_wp
    do k = 1, 3
      ident(k, k) = 1.0_wp
    end do
    do p = 1, n
      if (pmat(p) /= m) cycle
      lg = as_3x3(vgrad(:, p))
      dmat = 0.5_wp*(lg + transpose(lg))
      wmat = 0.5_wp*(lg - transpose(lg))
      s = voigt_to_tensor(stress(:, p))
      tr = dmat(1, 1) + dmat(2, 2) + dmat(3, 3)
      s = s + dt*(mat%lambda*tr*ident + 2.0_wp*mat%mu*dmat + matmul(wmat, s) - matmul(s, wmat))
      stress(:, p) = tensor_to_voigt(s)
      vol(p) = vol(p)*det3(ident + dt*lg)
    end do
  end subroutine elastic_update

  !> The hypoelastic (Jaumann) update in plane strain: D33 = 0,
  !> one spin component w = (L12 - L21)/2, and no out-of-plane shear stress.
  subroutine linear_elastic_plane(mat, m, dt, n, pmat, vgrad, stress, vol)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    real(wp), intent(in) :: dt
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: vgrad(:, :)
    real(wp), intent(inout) :: stress(:, :), vol(:)
    real(wp) :: l11, l21, l12, l22, d12, w12, tr, s11, s22, s12
    integer :: p
    do p = 1, n
      if (pmat(p) /= m) cycle
      l11 = vgrad(1, p); l21 = vgrad(2, p); l12 = vgrad(4, p); l22 = vgrad(5, p)
      d12 = 0.5_wp*(l12 + l21)
      w12 = 0.5_wp*(l12 - l21)
      tr = l11 + l22
      s11 = stress(1, p); s22 = stress(2, p); s12 = stress(6, p)
      ! (W s - s W) in the plane: 2 w s12, -2 w s12 and w (s22 - s11).
      stress(1, p) = s11 + dt*(mat%lambda*tr + 2.0_wp*mat%mu*l11 + 2.0_wp*w12*s12)
      stress(2, p) = s22 + dt*(mat%lambda*tr + 2.0_wp*mat%mu*l22 - 2.0_wp*w12*s12)
      stress(3, p) = stress(3, p) + dt*mat%lambda*tr
      stress(6, p) = s12 + dt*(2.0_wp*mat%mu*d12 + w12*(s22 - s11))
      vol(p) = vol(p)*((1.0_wp + dt*l11)*(1.0_wp + dt*l22) - dt*dt*l12*l21)
    end do
  end subroutine linear_elastic_plane

end module dpmpm_model_elastic
