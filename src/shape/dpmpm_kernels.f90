!> Grid kernels (1D functions combined as tensor products): the linear hat of
!> Standard MPM and the quadratic B-spline. All share one interface: for a
!> coordinate in cell units, the first node of the stencil and the weights and
!> their derivatives on the stencil's nodes.
module dpmpm_kernels
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: kernel_linear, kernel_quadratic, kernel_names, kernel_from_name
  public :: kernel_width, kernel_ghost_width, kernel_eval_1d, max_stencil

  integer, parameter :: kernel_linear = 1, kernel_quadratic = 2
  character(len=12), parameter :: kernel_names(2) = ['linear      ', 'quadratic   ']
  !> Largest number of nodes per axis of any kernel's stencil.
  integer, parameter :: max_stencil = 3

contains

  !> Kernel id from its input name, 0 if unknown.
  pure integer function kernel_from_name(name) result(k)
    character(len=*), intent(in) :: name
    integer :: j
    k = 0
    do j = 1, size(kernel_names)
      if (trim(adjustl(name)) == trim(kernel_names(j))) k = j
    end do
  end function kernel_from_name

  !> Nodes per axis in the kernel's stencil.
  pure integer function kernel_width(kernel) result(n)
    integer, intent(in) :: kernel
    select case (kernel)
    case (kernel_linear)
      n = 2
    case default
      n = 3
    end select
  end function kernel_width

  !> Ghost layer (in nodes) that a point inside a rank's cells can reach beyond them.
  pure integer function kernel_ghost_width(kernel) result(g)
    integer, intent(in) :: kernel
    select case (kernel)
    case (kernel_linear)
      g = 1
    case default
      g = 2
    end select
  end function kernel_ghost_width

  !> Evaluate the 1D kernel at s = (x - origin)/h (cell units). Returns the first
  !> stencil node i0 and, for nodes i0..i0+width-1, the weights w and derivatives
  !> dw with respect to s (divide by h for d/dx).
  pure subroutine kernel_eval_1d(kernel, s, i0, w, dw)
    integer, intent(in) :: kernel
    real(wp), intent(in) :: s
    integer, intent(out) :: i0
    real(wp), intent(out) :: w(max_stencil), dw(max_stencil)
    real(wp) :: r
    w = 0.0_wp
    dw = 0.0_wp
    select case (kernel)
    case (kernel_linear)
      ! N = 1 - |xi| on the two nodes of the cell.
      i0 = floor(s)
      r = s - real(i0, wp)
      w(1) = 1.0_wp - r
      w(2) = r
      dw(1) = -1.0_wp
      dw(2) = 1.0_wp
    case (kernel_quadratic)
      ! N = 3/4 - xi^2 (|xi| <= 1/2), (3/2 - |xi|)^2/2 (1/2 <= |xi| <= 3/2).
      i0 = floor(s - 0.5_wp)
      r = s - real(i0, wp)            ! in [0.5, 1.5): distance to the first node
      w(1) = 0.5_wp*(1.5_wp - r)**2
      dw(1) = -(1.5_wp - r)
      w(2) = 0.75_wp - (r - 1.0_wp)**2
      dw(2) = -2.0_wp*(r - 1.0_wp)
      w(3) = 0.5_wp*(r - 0.5_wp)**2
      dw(3) = (r - 0.5_wp)
    end select
  end subroutine kernel_eval_1d

end module dpmpm_kernels
