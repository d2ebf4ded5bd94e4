!> Geometry of the regular grid and the boundary conditions on its faces.
!> Node (i, j, k) sits at origin + (i, j, k)*h; cell (i, j, k) spans the nodes
!> i..i+1, j..j+1, k..k+1. Unused axes (d > ndim) have one cell and h = 1.
!> cell_of is the one rule that puts a position into a cell (generation, migration,
!> restart and scene checks all use it).
module dpmpm_grid
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, bc_free, bc_fixed, bc_roller
  implicit none
  private
  public :: grid_t, cell_of, cells_of, axis_cells_of, count_cells_outside

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
    integer :: bc(6) = bc_free         !< per face: x-, x+, y-, y+, z-, z+
    real(wp) :: friction(6) = 0.0_wp   !< Coulomb friction coefficient of roller faces
    logical :: rough = .false.         !< some face has friction
    logical :: lift_off(6) = .true.    !< rough face lets go of nodes moving away (wall_contact)
  contains
    procedure :: init => grid_init
    procedure :: constrained => grid_constrained
    procedure :: interior_nodes
    procedure :: wall_friction
    procedure :: wall_contact
    procedure :: inside => grid_inside
    procedure :: all_inside => grid_all_inside
  end type grid_t

contains

  !> Geometry and boundary conditions from the input.
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
    self%bc = bc_free
    self%bc(1:2*cfg%ndim) = cfg%bc(1:2*cfg%ndim)
    self%friction = 0.0_wp
    where (self%bc == bc_roller) self%friction = cfg%wall_friction
    self%rough = any(self%friction > 0.0_wp)
    self%lift_off = cfg%wall_lift_off
  end subroutine grid_init

  !> Coulomb friction of the rough roller faces on which node idx lies (doc/theory.md
  !> 6.7). v(1:nd) is the node's velocity at the end of the update, before the wall
  !> conditions; dv(1:nd) the velocity whose normal component the wall takes from the node
  !> (its normal impulse per unit mass: one phase, the node's velocity v itself, held at
  !> zero where it runs into the wall; the skeleton of two phases, its effective push
  !> over the mass the push moves). Where that component runs into such a wall (vn > 0)
  !> its friction takes mu vn from the speed along the wall, down to rest at most
  !> (sticking). Components held by other conditions (fix) do not slide. Where the wall
  !> does not push the node no friction acts. Only the tangential components of v change;
  !> the caller holds the normal one.
  pure subroutine wall_friction(self, idx, nd, fix, dv, v)
    class(grid_t), intent(in) :: self
    integer, intent(in) :: idx(3), nd
    logical, intent(in) :: fix(3)
    real(wp), intent(in) :: dv(3)
    real(wp), intent(inout) :: v(3)
    real(wp) :: vt(3), vn, s
    integer :: f, d
    do f = 1, 2*nd
      if (self%friction(f) <= 0.0_wp) cycle
      d = (f + 1)/2
      if (mod(f, 2) == 1) then
        if (idx(d) /= 0) cycle
        vn = -dv(d)
      else
        if (idx(d) /= self%ncells(d)) cycle
        vn = dv(d)
      end if
      if (vn <= 0.0_wp) cycle
      vt = 0.0_wp
      vt(1:nd) = v(1:nd)
      where (fix) vt = 0.0_wp
      s = norm2(vt)
      if (s <= 0.0_wp) cycle
      v = v - vt*min(1.0_wp, self%friction(f)*vn/s)
    end do
  end subroutine wall_friction

  !> Contact of node idx with the rough roller faces it lies on (doc/theory.md 6.7), per
  !> axis: 1 where such a face holds the normal component because the node's velocity
  !> v(1:nd) (before the wall conditions) runs into it, 2 where the node moves away from
  !> it and the wall lets go, 0 where no rough face is concerned or the face holds its
  !> nodes whatever their motion (lift_off = .false.). A node on a fixed face stays held
  !> (0: the fixed face's condition decides).
  pure function wall_contact(self, idx, nd, v) result(state)
    class(grid_t), intent(in) :: self
    integer, intent(in) :: idx(3), nd
    real(wp), intent(in) :: v(3)
    integer :: state(3)
    integer :: f, d
    state = 0
    do f = 1, 2*nd
      if (self%bc(f) /= bc_fixed) cycle
      d = (f + 1)/2
      if (mod(f, 2) == 1 .and. idx(d) <= 0) return
      if (mod(f, 2) == 0 .and. idx(d) >= self%ncells(d)) return
    end do
    do f = 1, 2*nd
      if (self%friction(f) <= 0.0_wp .or. .not. self%lift_off(f)) cycle
      d = (f + 1)/2
      if (mod(f, 2) == 1) then
        if (idx(d) /= 0) cycle
        state(d) = merge(1, 2, v(d) < 0.0_wp)
      else
        if (idx(d) /= self%ncells(d)) cycle
        state(d) = merge(1, 2, v(d) > 0.0_wp)
      end if
    end do
  end function wall_contact

  !> Which velocity components are held at zero at node (i, j, k): a fixed face
  !> holds all components, a roller the normal one. Exterior nodes beyond a face
  !> (reached by wide kernels) follow the face's condition. bc replaces the
  !> grid's face conditions (e.g. those that hold the pore fluid).
  pure function grid_constrained(self, idx, bc) result(fix)
    class(grid_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    integer, intent(in), optional :: bc(6)
    logical :: fix(3)
    integer :: d, f, bcs(6)
    bcs = self%bc
    if (present(bc)) bcs = bc
    fix = .false.
    do d = 1, self%ndim
      do f = 1, 2
        if (f == 1) then
          if (idx(d) > 0) cycle
        else
          if (idx(d) < self%ncells(d)) cycle
        end if
        select case (bcs(2*(d - 1) + f))
        case (bc_fixed)
          fix = .true.
        case (bc_roller)
          fix(d) = .true.
        end select
      end do
    end do
  end function grid_constrained

  !> The nodes at least margin nodes inside the boundary faces: the box ilo..ihi,
  !> unbounded along the unused axes. With margin 1, the nodes that no face condition
  !> holds, whatever the conditions (constrained all false).
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
