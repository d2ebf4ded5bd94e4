!> The walls of the grid: which velocity components each face holds (fixed: all, roller:
!> the normal one, free: none) and the Coulomb friction of rough roller faces, with the
!> contact that decides whether a rough wall holds a node or lets it go (doc/theory.md 6.7),
!> and the openings of fixed and roller faces: nodes strictly inside an opening are not held
!> by its face, and points that cross the face there leave the model (through_opening).
!> The skeleton's kinds (and a one-phase scene's) are bc; a caller passes another phase's
!> (the pore fluid's, fluid_mirror_bc) to constrained.
module dpmpm_walls
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, bc_free, bc_fixed, bc_roller
  implicit none
  private
  public :: walls_t

  !> The face conditions of a grid of ncells cells along ndim axes.
  type :: walls_t
    integer :: ndim = 1
    integer :: ncells(3) = 1
    integer :: bc(6) = bc_free         !< per face: x-, x+, y-, y+, z-, z+
    real(wp) :: friction(6) = 0.0_wp   !< Coulomb friction coefficient of roller faces
    logical :: rough = .false.         !< some face has friction
    logical :: lift_off(6) = .true.    !< rough face lets go of nodes moving away (wall_contact)
    logical :: opened(6) = .false.     !< the face has an opening
    !> the opening's box per face (m), and the node indices strictly inside it along each
    !> axis (along the normal every index; a face's nodes are those with the face's index)
    real(wp) :: open_x(2, 3, 6) = 0.0_wp
    integer :: open_node(2, 3, 6) = 0
  contains
    procedure :: init => walls_init
    procedure :: constrained => walls_constrained
    procedure :: wall_friction
    procedure :: wall_contact
    procedure :: in_opening
    procedure :: through_opening
  end type walls_t

contains

  !> The faces' conditions of the input (&boundary condition, friction, lift_off) on its grid.
  subroutine walls_init(self, cfg)
    class(walls_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    self%ndim = cfg%ndim
    self%ncells = 1
    self%ncells(1:cfg%ndim) = cfg%ncells(1:cfg%ndim)
    self%bc = bc_free
    self%bc(1:2*cfg%ndim) = cfg%bc(1:2*cfg%ndim)
    self%friction = 0.0_wp
    where (self%bc == bc_roller) self%friction = cfg%wall_friction
    self%rough = any(self%friction > 0.0_wp)
    self%lift_off = cfg%wall_lift_off
    call init_openings(self, cfg)
  end subroutine walls_init

  !> The openings of the input's faces (cfg%has_opening): the box along the face and the
  !> indices of the nodes strictly inside it, a node on the box's edge (within 1e-9 of a
  !> cell) counting as outside, so that the face still holds it.
  subroutine init_openings(self, cfg)
    class(walls_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    real(wp), parameter :: tol = 1.0e-9_wp
    integer :: f, d
    real(wp) :: h
    self%opened = .false.
    self%open_x = 0.0_wp
    self%open_node(1, :, :) = -huge(1)
    self%open_node(2, :, :) = huge(1)
    do f = 1, 2*cfg%ndim
      if (.not. cfg%has_opening(f) .or. self%bc(f) == bc_free) cycle
      self%opened(f) = .true.
      do d = 1, cfg%ndim
        if (d == (f + 1)/2) cycle
        self%open_x(:, d, f) = [cfg%opening_lo(d, f), cfg%opening_hi(d, f)]
        h = cfg%length(d)/real(cfg%ncells(d), wp)
        self%open_node(1, d, f) = floor((cfg%opening_lo(d, f) - cfg%origin(d))/h + tol) + 1
        self%open_node(2, d, f) = ceiling((cfg%opening_hi(d, f) - cfg%origin(d))/h - tol) - 1
      end do
    end do
  end subroutine init_openings

  !> Whether node idx lies strictly inside the opening of face f (its index along the
  !> face's normal is not looked at: the caller knows the node is on the face or beyond).
  pure logical function in_opening(self, f, idx)
    class(walls_t), intent(in) :: self
    integer, intent(in) :: f, idx(3)
    integer :: d
    in_opening = self%opened(f)
    if (.not. in_opening) return
    do d = 1, self%ndim
      if (idx(d) < self%open_node(1, d, f) .or. idx(d) > self%open_node(2, d, f)) then
        in_opening = .false.
        return
      end if
    end do
  end function in_opening

  !> Whether a point at x that crossed face f did so through its opening: its components
  !> along the face within the opening's box, edges included.
  pure logical function through_opening(self, f, x)
    class(walls_t), intent(in) :: self
    integer, intent(in) :: f
    real(wp), intent(in) :: x(:)
    integer :: d
    through_opening = self%opened(f)
    if (.not. through_opening) return
    do d = 1, self%ndim
      if (d == (f + 1)/2) cycle
      if (x(d) < self%open_x(1, d, f) .or. x(d) > self%open_x(2, d, f)) then
        through_opening = .false.
        return
      end if
    end do
  end function through_opening

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
    class(walls_t), intent(in) :: self
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
      if (self%in_opening(f, idx)) cycle
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
    class(walls_t), intent(in) :: self
    integer, intent(in) :: idx(3), nd
    real(wp), intent(in) :: v(3)
    integer :: state(3)
    integer :: f, d
    state = 0
    do f = 1, 2*nd
      if (self%bc(f) /= bc_fixed) cycle
      if (self%in_opening(f, idx)) cycle
      d = (f + 1)/2
      if (mod(f, 2) == 1 .and. idx(d) <= 0) return
      if (mod(f, 2) == 0 .and. idx(d) >= self%ncells(d)) return
    end do
    do f = 1, 2*nd
      if (self%friction(f) <= 0.0_wp .or. .not. self%lift_off(f)) cycle
      d = (f + 1)/2
      if (self%in_opening(f, idx)) cycle
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
  !> walls' face conditions (e.g. those that hold the pore fluid). A face does not hold
  !> the nodes strictly inside its opening.
  pure function walls_constrained(self, idx, bc) result(fix)
    class(walls_t), intent(in) :: self
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
        if (self%in_opening(2*(d - 1) + f, idx)) cycle
        select case (bcs(2*(d - 1) + f))
        case (bc_fixed)
          fix = .true.
        case (bc_roller)
          fix(d) = .true.
        end select
      end do
    end do
  end function walls_constrained

end module dpmpm_walls
