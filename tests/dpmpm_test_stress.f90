!> The stress invariants the element tests compare with their closed forms, written once:
!> from a Voigt stress (tension positive, xx yy zz yz xz xy) the mean effective pressure
!> p = -tr(sigma)/3 (compression positive), the deviator s = sigma + p 1, the triaxial
!> deviator stress q = sqrt(3/2 s:s) and the equivalent shear stress tau = sqrt(s:s/2)
!> (q = sqrt(3) tau).
module dpmpm_test_stress
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: pq, ptau

contains

  !> p and sqrt(c s:s) (s:s with the shears counted twice): c = 3/2 gives q, 1/2 tau.
  pure subroutine mean_and_norm(s, c, p, r)
    real(wp), intent(in) :: s(6), c
    real(wp), intent(out) :: p, r
    real(wp) :: d(3)
    p = -(s(1) + s(2) + s(3))/3.0_wp
    d = s(1:3) + p
    r = sqrt(c*(d(1)**2 + d(2)**2 + d(3)**2 + 2.0_wp*sum(s(4:6)**2)))
  end subroutine mean_and_norm

  !> p' and q of a Voigt stress s.
  pure subroutine pq(s, p, q)
    real(wp), intent(in) :: s(6)
    real(wp), intent(out) :: p, q
    call mean_and_norm(s, 1.5_wp, p, q)
  end subroutine pq

  !> p' and tau = |s|/sqrt(2) of a Voigt stress s.
  pure subroutine ptau(s, p, tau)
    real(wp), intent(in) :: s(6)
    real(wp), intent(out) :: p, tau
    call mean_and_norm(s, 0.5_wp, p, tau)
  end subroutine ptau

end module dpmpm_test_stress
