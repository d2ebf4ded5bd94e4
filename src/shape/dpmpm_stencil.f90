!> Point stencils of the grid functions (doc/theory.md 3.2): the nodes
!> a point's tensor-product B-spline reaches, with their weights N_I(x_p) and
!> gradients grad N_I(x_p), evaluated once per step and then read by every grid
!> transfer. A point's nodes are its first node plus a table of offsets that all
!> points share, so each transfer is one flat loop over (point, stencil node);
!> the tensor product over the axes is formed here and nowhere else.
module dpmpm_stencil
  use dpmpm_kinds, only: wp
  use dpmpm_kernels, only: kernel_eval_1d, kernel_width, max_stencil
  implicit none
  private
  public :: stencil_t, psi_stencil, stencil_offsets, tensor_weights

  !> Stencils of a point set on a stored block of nodes lo:hi.
  type :: stencil_t
    integer :: nd = 0                       !< dimension
    integer :: kernel = 0                   !< grid kernel id
    integer :: nq = 0                       !< nodes per point, product of nw
    integer :: nw(3) = 1                    !< nodes per axis
    integer :: lo(3) = 0, ext(3) = 1        !< first node and extent of the stored block
    integer :: nnode = 0                    !< nodes in the stored block
    integer, allocatable :: off(:, :)       !< (3, nq) offsets of the stencil nodes from the first
    integer, allocatable :: qoff(:)         !< (nq) the same offsets in the block's linear index
    integer, allocatable :: first(:)        !< (cap) linear index of a point's first node
    real(wp), allocatable :: w(:, :)        !< (nq, cap) weights N_I(x_p)
    real(wp), allocatable :: dw(:, :, :)    !< (nd, nq, cap) gradients (per metre)
  contains
    procedure :: init => stencil_init
    procedure :: build => stencil_build
    procedure :: free => stencil_free
  end type stencil_t

contains

  !> Stencil layout of grid kernel `kernel` in nd dimensions on the stored node
  !> block lo:hi (per axis; the unused axes are 0:0).
  subroutine stencil_init(self, nd, kernel, lo, hi)
    class(stencil_t), intent(inout) :: self
    integer, intent(in) :: nd, kernel, lo(3), hi(3)
    integer :: m
    call self%free()
    self%nd = nd
    self%kernel = kernel
    self%nw = 1
    self%nw(1:nd) = kernel_width(kernel)
    self%lo = lo
    self%ext = hi - lo + 1
    self%nnode = product(self%ext)
    call stencil_offsets(self%nw, self%nq, self%off)
    allocate (self%qoff(self%nq))
    do m = 1, self%nq
      self%qoff(m) = self%off(1, m) + self%ext(1)*(self%off(2, m) + self%ext(2)*self%off(3, m))
    end do
    allocate (self%first(0), self%w(self%nq, 0), self%dw(nd, self%nq, 0))
  end subroutine stencil_init

  !> Stencils of the first n points at positions x (nd, n) on the grid with the
  !> given origin and cell size; the arrays grow to cap points when they are short.
  subroutine stencil_build(self, n, cap, x, origin, h)
    class(stencil_t), intent(inout) :: self
    integer, intent(in) :: n, cap
    real(wp), intent(in) :: x(:, :), origin(3), h(3)
    integer :: p, d, i0(3)
    real(wp) :: y(3), sw(max_stencil, 3), sdw(max_stencil, 3)
    if (size(self%first) < n) then
      deallocate (self%first, self%w, self%dw)
      allocate (self%first(cap), self%w(self%nq, cap), self%dw(self%nd, self%nq, cap))
    end if
    do p = 1, n
      y = 0.0_wp
      do d = 1, self%nd
        y(d) = (x(d, p) - origin(d))/h(d)
      end do
      call psi_stencil(self%nd, self%kernel, y, h, i0, sw, sdw)
      self%first(p) = 1 + (i0(1) - self%lo(1)) + self%ext(1)*((i0(2) - self%lo(2)) + &
                                                              self%ext(2)*(i0(3) - self%lo(3)))
      call tensor_weights(self%nd, self%nq, self%off, sw, sdw, self%w(:, p), self%dw(:, :, p))
    end do
  end subroutine stencil_build

  subroutine stencil_free(self)
    class(stencil_t), intent(inout) :: self
    if (allocated(self%off)) deallocate (self%off)
    if (allocated(self%qoff)) deallocate (self%qoff)
    if (allocated(self%first)) deallocate (self%first)
    if (allocated(self%w)) deallocate (self%w)
    if (allocated(self%dw)) deallocate (self%dw)
    self%nq = 0
    self%nnode = 0
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

  !> Weights w(m) = prod_d sw(.,d) and gradients dw(d, m) of the stencil nodes
  !> m = 1..nq (offsets off) from the per-axis weights sw and derivatives sdw.
  pure subroutine tensor_weights(nd, nq, off, sw, sdw, w, dw)
    integer, intent(in) :: nd, nq, off(:, :)
    real(wp), intent(in) :: sw(max_stencil, 3), sdw(max_stencil, 3)
    real(wp), intent(out) :: w(:), dw(:, :)
    integer :: m, a, b, c
    do m = 1, nq
      a = off(1, m) + 1
      b = off(2, m) + 1
      c = off(3, m) + 1
      w(m) = sw(a, 1)*sw(b, 2)*sw(c, 3)
      dw(1, m) = sdw(a, 1)*sw(b, 2)*sw(c, 3)
      if (nd >= 2) dw(2, m) = sw(a, 1)*sdw(b, 2)*sw(c, 3)
      if (nd >= 3) dw(3, m) = sw(a, 1)*sw(b, 2)*sdw(c, 3)
    end do
  end subroutine tensor_weights

  !> Grid-function weights and gradients (per metre) per axis at a position y in
  !> cell units: first node i0, weights sw(:, d), derivatives sdw(:, d); the
  !> unused axes have one node of weight 1.
  pure subroutine psi_stencil(nd, kernel, y, h, i0, sw, sdw)
    integer, intent(in) :: nd, kernel
    real(wp), intent(in) :: y(3), h(3)
    integer, intent(out) :: i0(3)
    real(wp), intent(out) :: sw(max_stencil, 3), sdw(max_stencil, 3)
    integer :: d
    do d = 1, 3
      if (d <= nd) then
        call kernel_eval_1d(kernel, y(d), i0(d), sw(:, d), sdw(:, d))
        sdw(:, d) = sdw(:, d)/h(d)
      else
        i0(d) = 0
        sw(:, d) = 0.0_wp
        sw(1, d) = 1.0_wp
        sdw(:, d) = 0.0_wp
      end if
    end do
  end subroutine psi_stencil

end module dpmpm_stencil
