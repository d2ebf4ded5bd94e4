!> Point stencils of the grid functions (doc/theory.md 3.2): for every point
!> the first node its tensor-product B-spline reaches and the per-axis weights
!> and derivatives, evaluated once per step and read by every grid transfer
!> (dpmpm_transfer), which forms the products node by node.
module dpmpm_stencil
  use dpmpm_kinds, only: wp
  use dpmpm_kernels, only: psi_stencil, psi_stencils, max_stencil, grid_kernel_t, bind_grid_kernel
  implicit none
  private
  public :: stencil_t, psi_stencil, stencil_offsets, tensor_weights

  !> Stencils of a point set.
  type :: stencil_t
    integer :: nd = 0                       !< dimension
    integer :: kernel = 0                   !< grid kernel id
    !> the grid kernel bound once (stencil_init): its width, ghost layer and reach
    type(grid_kernel_t) :: gk
    integer :: nw(3) = 1                    !< nodes per axis
    integer, allocatable :: i0(:, :)        !< (3, cap) first node of a point's stencil
    !> (nw, 3, cap) weights per axis, one row of nw = gk%width values per axis (the
    !> axes beyond nd hold one node of weight 1 and derivative 0, set at allocation)
    real(wp), allocatable :: sw(:, :, :)
    real(wp), allocatable :: sdw(:, :, :)   !< (nw, 3, cap) derivatives per axis (per metre)
  contains
    procedure :: init => stencil_init
    procedure :: build => stencil_build
    procedure :: free => stencil_free
  end type stencil_t

contains

  !> Stencils of grid kernel `kernel` in nd dimensions, for no points yet. The kernel is
  !> bound here, once: a code that is no grid kernel stops the run.
  subroutine stencil_init(self, nd, kernel)
    class(stencil_t), intent(inout) :: self
    integer, intent(in) :: nd, kernel
    call self%free()
    self%nd = nd
    self%gk = bind_grid_kernel(kernel, 'stencil_init')
    self%kernel = self%gk%kernel
    self%nw = 1
    self%nw(1:nd) = self%gk%width
    allocate (self%i0(3, 0), self%sw(self%nw(1), 3, 0), self%sdw(self%nw(1), 3, 0))
  end subroutine stencil_init

  !> Stencils of the first n points at positions x (nd, n) on the grid with the
  !> given origin and cell size; the arrays grow to cap points when they are short.
  subroutine stencil_build(self, n, cap, x, origin, h)
    class(stencil_t), intent(inout) :: self
    integer, intent(in) :: n, cap
    real(wp), intent(in) :: x(:, :), origin(3), h(3)
    if (size(self%i0, 2) < n) then
      deallocate (self%i0, self%sw, self%sdw)
      allocate (self%i0(3, cap), self%sw(self%nw(1), 3, cap), self%sdw(self%nw(1), 3, cap))
      ! The axes beyond nd, once: one node (the first) of weight 1 and derivative 0.
      self%i0(self%nd + 1:3, :) = 0
      self%sw(:, self%nd + 1:3, :) = 0.0_wp
      self%sw(1, self%nd + 1:3, :) = 1.0_wp
      self%sdw(:, self%nd + 1:3, :) = 0.0_wp
    end if
    call psi_stencils(self%nd, self%kernel, n, x, origin, h, self%i0, self%sw, self%sdw)
  end subroutine stencil_build

  subroutine stencil_free(self)
    class(stencil_t), intent(inout) :: self
    if (allocated(self%i0)) deallocate (self%i0)
    if (allocated(self%sw)) deallocate (self%sw)
    if (allocated(self%sdw)) deallocate (self%sdw)
    self%nd = 0
  end subroutine stencil_free

  !> The nodes of a tensor-product stencil with nw nodes per axis, as offsets
  !> (a-1, b-1, c-1) from its first node, the first axis running fastest.
  subroutine stencil_offsets(nw, nq, off)
    integer, intent(in) :: nw(3)
    integer, intent(out) :: nq
    integer, allocatable, intent(out) :: off(:, :)
    integer :: a, b, c, m
    nq = product(nw)
    allocate (off(3, nq))
    m = 0
    do c = 1, nw(3)
      do b = 1, nw(2)
        do a = 1, nw(1)
          m = m + 1
          off(:, m) = [a - 1, b - 1, c - 1]
        end do
      end do
    end do
  end subroutine stencil_offsets

  !> Tensor products of per-axis weights sw and derivatives sdw with nw nodes per
  !> axis: w(m) = sw(a, 1) sw(b, 2) sw(c, 3) and the gradient dw(:, m) with one
  !> factor differentiated (when asked for), m running over the nodes as in
  !> stencil_offsets. An unused axis has one node of weight 1 and derivative 0.
  pure subroutine tensor_weights(nw, sw, sdw, w, dw)
    integer, intent(in) :: nw(3)
    real(wp), intent(in) :: sw(max_stencil, 3), sdw(max_stencil, 3)
    real(wp), intent(out) :: w(:)
    real(wp), intent(out), optional :: dw(:, :)
    integer :: a, b, c, m
    m = 0
    do c = 1, nw(3)
      do b = 1, nw(2)
        do a = 1, nw(1)
          m = m + 1
          w(m) = sw(a, 1)*sw(b, 2)*sw(c, 3)
          if (.not. present(dw)) cycle
          dw(1, m) = sdw(a, 1)*sw(b, 2)*sw(c, 3)
          dw(2, m) = sw(a, 1)*sdw(b, 2)*sw(c, 3)
          dw(3, m) = sw(a, 1)*sw(b, 2)*sdw(c, 3)
        end do
      end do
    end do
  end subroutine tensor_weights

end module dpmpm_stencil
