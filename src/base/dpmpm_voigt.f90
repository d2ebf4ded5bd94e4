!> Voigt notation of symmetric 3x3 tensors: components xx yy zz yz xz xy, the
!> order of stresses in the point sets, the output and the checkpoints.
module dpmpm_voigt
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: voigt_to_tensor, tensor_to_voigt

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

end module dpmpm_voigt
