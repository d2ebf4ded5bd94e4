!> Geometry of the regular grid (its faces' conditions: dpmpm_walls, src/boundary).
!> Node (i, j, k) sits at origin + (i, j, k)*h; cell (i, j, k) spans the nodes
!> i..i+1, j..j+1, k..k+1. Unused axes (d > ndim) have one cell and h = 1.
!> cell_of is the one rule that puts a position into a cell (generation, migration,
!> restart and scene checks all use it).
module dpmpm_grid
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t
  implicit none
  private
  public :: grid_t, cell_of, cells_of, axis_cells_of, count_cells_outside
  public :: node_slots_t, node_slots

  !> Cell indices are clamped to +-cell_clamp so that a point far away (or at a
  !> NaN position) still gets a valid integer cell, outside the grid.
  real(wp), parameter :: cell_clamp = 1.0e9_wp

  !> Regular grid of ncells(d) cells of size h(d) along each axis.
  type :: grid_t
    integer :: ndim = 1
    integer :: ncells(3) = 1
    real(wp) :: origin(3) = 0.0_wp
    real(wp) :: h(3) = 1.0_wp
    real(wp) :: cell_volume = 1.0_wp   !< product of h over the used axes
  contains
    procedure :: init => grid_init
    procedure :: interior_nodes
    procedure :: inside => grid_inside
    procedure :: all_inside => grid_all_inside
  end type grid_t

  !> The slots of the node fields of nd dimensions (node_slots): a phase's
  !> node(:, i, j, k) holds the mass (slot mass), the momentum (mom_lo:mom_hi) and the
  !> force (force_lo:force_hi); its nvel(:, i, j, k) the velocity before the nodal update
  !> (old_lo:old_hi) and after it (new_lo:new_hi).
  type :: node_slots_t
    integer :: mass = 1
    integer :: mom_lo = 2, mom_hi = 1
    integer :: force_lo = 2, force_hi = 1
    integer :: old_lo = 1, old_hi = 0
    integer :: new_lo = 1, new_hi = 0
  end type node_slots_t

contains

  !> The slots of the node fields (node_slots_t) for nd dimensions.
  pure function node_slots(nd) result(sl)
    integer, intent(in) :: nd
    type(node_slots_t) :: sl
    sl%mass = 1
    sl%mom_lo = 2
    sl%mom_hi = 1 + nd
    sl%force_lo = 2 + nd
    sl%force_hi = 1 + 2*nd
    sl%old_lo = 1
    sl%old_hi = nd
    sl%new_lo = nd + 1
    sl%new_hi = 2*nd
  end function node_slots

  !> Geometry from the input.
  subroutine grid_init(self, cfg)
    class(grid_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    integer :: d
    self%ndim = cfg%ndim
    self%ncells = 1
    self%origin = 0.0_wp
    self%h = 1.0_wp
    do d = 1, cfg%ndim
      self%ncells(d) = cfg%ncells(d)
      self%origin(d) = cfg%origin(d)
      self%h(d) = cfg%length(d)/real(cfg%ncells(d), wp)
    end do
    self%cell_volume = product(self%h(1:self%ndim))
  end subroutine grid_init

  !> The nodes at least margin nodes inside the boundary faces: the box ilo..ihi,
  !> unbounded along the unused axes. With margin 1, the nodes that no face condition
  !> holds, whatever the conditions (walls_t%constrained all false).
  pure subroutine interior_nodes(self, margin, ilo, ihi)
    class(grid_t), intent(in) :: self
    integer, intent(in) :: margin
    integer, intent(out) :: ilo(3), ihi(3)
    integer :: d
    ilo = -huge(1); ihi = huge(1)
    do d = 1, self%ndim
      ilo(d) = margin; ihi(d) = self%ncells(d) - margin
    end do
  end subroutine interior_nodes

  !> Integer cell (0-based, per axis) holding position x: floor((x - origin)/h)
  !> on the axes 1..ndim, 0 on the unused axes. NaN maps far below the grid.
  pure function cell_of(origin, h, x, ndim) result(c)
    real(wp), intent(in) :: origin(3), h(3)
    real(wp), intent(in) :: x(:)
    integer, intent(in) :: ndim
    integer :: c(3)
    integer :: d
    c = 0
    do d = 1, ndim
      c(d) = clamped_floor((x(d) - origin(d))/h(d))
    end do
  end function cell_of

  !> floor(s) with s clamped to +-cell_clamp (NaN to -cell_clamp): the cell index along
  !> one axis of a position s cells from the origin.
  pure integer function clamped_floor(s) result(c)
    real(wp), intent(in) :: s
    real(wp) :: t
    ! (min and max instead of branches, and floor as the truncation less one where it
    ! lies above t, so that loops over points vectorise; max takes -cell_clamp for NaN)
    t = min(max(s, -cell_clamp), cell_clamp)
    c = int(t)
    c = c - merge(1, 0, real(c, wp) > t)
  end function clamped_floor

  !> cell_of of the points x(:, 1:n) at once: c(:, k) is the cell of x(:, k). One call
  !> per point set keeps the per-point work inside this module (inlined), not a call
  !> across modules per point.
  pure subroutine cells_of(origin, h, x, n, ndim, c)
    real(wp), intent(in) :: origin(3), h(3)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: n, ndim
    integer, intent(out) :: c(:, :)
    integer :: k
    do k = 1, n
      c(:, k) = cell_of(origin, h, x(:, k), ndim)
    end do
  end subroutine cells_of

  !> How many of the points x(:, 1:n) have their cell_of outside the cells clo..chi
  !> (one loop in this module, without an array of the cells).
  pure integer function count_cells_outside(origin, h, x, n, ndim, clo, chi) result(nout)
    real(wp), intent(in) :: origin(3), h(3)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: n, ndim, clo(3), chi(3)
    integer :: k, c(3)
    nout = 0
    do k = 1, n
      c = cell_of(origin, h, x(:, k), ndim)
      if (.not. all(c >= clo .and. c <= chi)) nout = nout + 1
    end do
  end function count_cells_outside

  !> The cell index along axis d alone of the points x(:, 1:n), as cell_of gives it.
  pure subroutine axis_cells_of(origin, h, x, n, d, c)
    real(wp), intent(in) :: origin(3), h(3)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: n, d
    integer, intent(out) :: c(:)
    integer :: k
    do k = 1, n
      c(k) = clamped_floor((x(d, k) - origin(d))/h(d))
    end do
  end subroutine axis_cells_of

  !> True when every point x(:, 1:n) lies inside the grid (grid_inside of each, inside
  !> this module instead of one call per point).
  pure logical function grid_all_inside(self, x, n) result(yes)
    class(grid_t), intent(in) :: self
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: n
    integer :: k, d, nout
    real(wp) :: lo(3), hi(3)
    ! (the points outside counted in one pass over the positions, in a loop without a
    ! branch that the compiler vectorises; the test of grid_inside)
    do d = 1, 3
      lo(d) = self%origin(d)
      hi(d) = self%origin(d) + self%h(d)*self%ncells(d)
    end do
    nout = 0
    select case (self%ndim)
    case (1)
      do k = 1, n
        nout = nout + merge(1, 0, x(1, k) < lo(1)) + merge(1, 0, x(1, k) >= hi(1))
      end do
    case (2)
      do k = 1, n
        nout = nout + merge(1, 0, x(1, k) < lo(1)) + merge(1, 0, x(1, k) >= hi(1)) + &
               merge(1, 0, x(2, k) < lo(2)) + merge(1, 0, x(2, k) >= hi(2))
      end do
    case default
      do k = 1, n
        nout = nout + merge(1, 0, x(1, k) < lo(1)) + merge(1, 0, x(1, k) >= hi(1)) + &
               merge(1, 0, x(2, k) < lo(2)) + merge(1, 0, x(2, k) >= hi(2)) + &
               merge(1, 0, x(3, k) < lo(3)) + merge(1, 0, x(3, k) >= hi(3))
      end do
    end select
    yes = nout == 0
  end function grid_all_inside

  !> True when x lies inside the grid (lower faces included, upper excluded).
  pure logical function grid_inside(self, x)
    class(grid_t), intent(in) :: self
    real(wp), intent(in) :: x(:)
    integer :: d
    grid_inside = .true.
    do d = 1, self%ndim
      if (x(d) < self%origin(d) .or. x(d) >= self%origin(d) + self%h(d)*self%ncells(d)) &
        grid_inside = .false.
    end do
  end function grid_inside

end module dpmpm_grid
