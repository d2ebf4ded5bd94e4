!> Neo-Hookean model (finite strain): F <- (I + dt L) F,
!> sigma = (mu (F F^T - I) + lambda ln J I)/J, V = V0 J. Plane strain (2D) keeps F33 = 1.
!> Keeps the deformation gradient, no state values (dpmpm_model_table).
module dpmpm_model_neo_hookean
  use dpmpm_kinds, only: wp
  use dpmpm_material_params, only: material_t
  use dpmpm_tensor, only: tensor_to_voigt, as_3x3, det3
  implicit none
  private
  public :: neo_hookean_update

contains

  !> The update of stress_update (dpmpm_materials) for the points of material index m.
  subroutine neo_hookean_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
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
    real(wp) :: lg(3, 3), s(3, 3), f(3, 3), b(3, 3), ident(3, 3)
    integer, parameter :: nb = 64
    real(wp) :: jb(nb), lnj(nb)
    integer :: p, p0, k, nk
    if (present(plane)) then
      if (plane) then
        call neo_hookean_plane(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad)
        return
      end if
    end if
    ident = 0.0_wp
    do k = 1, 3
      ident(k, k) = 1.0_wp
    end do
    ! (chunks of points as in neo_hookean_plane: F and J, ln J in a loop of its own, the
    ! stresses)
    do p0 = 1, n, nb
      nk = min(nb, n - p0 + 1)
      do k = 1, nk
        p = p0 + k - 1
        jb(k) = 1.0_wp
        if (pmat(p) /= m) cycle
        lg = as_3x3(vgrad(:, p))
        f = matmul(ident + dt*lg, as_3x3(defgrad(:, p)))
        defgrad(1:3, p) = f(:, 1); defgrad(4:6, p) = f(:, 2); defgrad(7:9, p) = f(:, 3)
        jb(k) = det3(f)
      end do
      do k = 1, nk
        lnj(k) = log(jb(k))
      end do
      do k = 1, nk
        p = p0 + k - 1
        if (pmat(p) /= m) cycle
        f = as_3x3(defgrad(:, p))
        b = matmul(f, transpose(f))
        s = (mat%mu*(b - ident) + mat%lambda*lnj(k)*ident)/jb(k)
        stress(:, p) = tensor_to_voigt(s)
        vol(p) = vol0(p)*jb(k)
      end do
    end do
  end subroutine neo_hookean_update

  !> The neo-Hookean update in plane strain: F33 = 1 and the
  !> in-plane 2x2 block of F carries the motion. Chunks of points: F and J in one loop,
  !> ln J in the next (J = 1 stands in at points of other materials), the stresses in a
  !> third, so that the first and the last vectorise.
  subroutine neo_hookean_plane(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    real(wp), intent(in) :: dt
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: vgrad(:, :)
    real(wp), intent(inout) :: stress(:, :), vol(:)
    real(wp), intent(in) :: vol0(:)
    real(wp), intent(inout) :: defgrad(:, :)
    integer, parameter :: nb = 64
    real(wp) :: a11, a21, a12, a22, f11, f21, f12, f22, jac(nb), lnj(nb), rj
    integer :: p, p0, k, nk
    do p0 = 1, n, nb
      nk = min(nb, n - p0 + 1)
      do k = 1, nk
        p = p0 + k - 1
        jac(k) = 1.0_wp
        if (pmat(p) /= m) cycle
        ! A = I + dt L; F <- A F (column-major: 1 = 11, 2 = 21, 4 = 12, 5 = 22).
        a11 = 1.0_wp + dt*vgrad(1, p); a21 = dt*vgrad(2, p)
        a12 = dt*vgrad(4, p); a22 = 1.0_wp + dt*vgrad(5, p)
        f11 = a11*defgrad(1, p) + a12*defgrad(2, p)
        f21 = a21*defgrad(1, p) + a22*defgrad(2, p)
        f12 = a11*defgrad(4, p) + a12*defgrad(5, p)
        f22 = a21*defgrad(4, p) + a22*defgrad(5, p)
        defgrad(1, p) = f11; defgrad(2, p) = f21; defgrad(4, p) = f12; defgrad(5, p) = f22
        jac(k) = f11*f22 - f12*f21
      end do
      do k = 1, nk
        lnj(k) = log(jac(k))
      end do
      do k = 1, nk
        p = p0 + k - 1
        if (pmat(p) /= m) cycle
        f11 = defgrad(1, p); f21 = defgrad(2, p); f12 = defgrad(4, p); f22 = defgrad(5, p)
        rj = 1.0_wp/jac(k)
        ! sigma = (mu (F F^T - I) + lambda ln J I)/J; the third normal stress has F33 = 1.
        stress(1, p) = (mat%mu*(f11*f11 + f12*f12 - 1.0_wp) + mat%lambda*lnj(k))*rj
        stress(2, p) = (mat%mu*(f21*f21 + f22*f22 - 1.0_wp) + mat%lambda*lnj(k))*rj
        stress(3, p) = mat%lambda*lnj(k)*rj
        stress(4, p) = 0.0_wp
        stress(5, p) = 0.0_wp
        stress(6, p) = mat%mu*(f11*f21 + f12*f22)*rj
        vol(p) = vol0(p)*jac(k)
      end do
    end do
  end subroutine neo_hookean_plane

end module dpmpm_model_neo_hookean
