!> Small 3x3 tensor helpers shared by the constitutive models and the transfers:
!> symmetric tensors in Voigt order xx yy zz yz xz xy, full tensors stored column-major.
module dpmpm_tensor
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: voigt_to_tensor, tensor_to_voigt, as_3x3, det3

contains

  !> 3x3 symmetric tensor from Voigt components.
  pure function voigt_to_tensor(s) result(t)
    real(wp), intent(in) :: s(6)
    real(wp) :: t(3, 3)
    t(1, 1) = s(1); t(2, 2) = s(2); t(3, 3) = s(3)
    t(2, 3) = s(4); t(3, 2) = s(4)
    t(1, 3) = s(5); t(3, 1) = s(5)
    t(1, 2) = s(6); t(2, 1) = s(6)
  end function voigt_to_tensor

  !> Voigt components of the symmetric part of a 3x3 tensor.
  pure function tensor_to_voigt(t) result(s)
    real(wp), intent(in) :: t(3, 3)
    real(wp) :: s(6)
    s = [t(1, 1), t(2, 2), t(3, 3), 0.5_wp*(t(2, 3) + t(3, 2)), 0.5_wp*(t(1, 3) + t(3, 1)), &
         0.5_wp*(t(1, 2) + t(2, 1))]
  end function tensor_to_voigt

  !> A 3x3 tensor from its 9 values stored column-major (as reshape would, without
  !> the library call for a section of run-time shape).
  pure function as_3x3(a) result(t)
    real(wp), intent(in) :: a(9)
    real(wp) :: t(3, 3)
    t(:, 1) = a(1:3)
    t(:, 2) = a(4:6)
    t(:, 3) = a(7:9)
  end function as_3x3

  !> Determinant of a 3x3 tensor.
  pure real(wp) function det3(a)
    real(wp), intent(in) :: a(3, 3)
    det3 = a(1, 1)*(a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)) - a(1, 2)*(a(2, 1)*a(3, 3) - a(2, 3)*a(3, 1)) &
           + a(1, 3)*(a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1))
  end function det3

end module dpmpm_tensor
