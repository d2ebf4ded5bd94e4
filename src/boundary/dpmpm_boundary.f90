!> The boundary conditions of the grid's faces, resolved once from the input: each face's
!> kind for every phase (the skeleton's fixed, roller or free; the pore fluid's drained or
!> impermeable, and the mirror conditions that follow from both), tied faces, the rigid
!> base of &motion, and the face loads (tractions, drained-face pore pressure, dashpots of
!> absorbing faces, the fluid's ties at impermeable faces: face_loads_t). The step applies
!> them at three moments: on the node fields in p2g (the mirror walls' fold, the phases'
!> kinds), in the nodal update and the remap (forces and constraints: face_loads_t and its
!> walls_t; remap_nodal_velocity and tie_fluid here), and on the velocities after the
!> update and after the remap (hold: the kinematic conditions that overwrite the velocities
!> of whole faces). doc/architecture.md, "Boundary conditions", lists where each kind is
!> decided and applied.
module dpmpm_boundary
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, bc_free, bc_fixed, fbc_default, fbc_drained, fbc_impermeable
  use dpmpm_grid, only: grid_t, node_slots_t, node_slots
  use dpmpm_face_loads, only: face_loads_t
  use dpmpm_mirror, only: fluid_mirror_bc
  use dpmpm_base_motion, only: base_face, base_velocity, shake_base
  use dpmpm_tied_sides, only: tie_sides
  use mpi_f08, only: MPI_Comm
  implicit none
  private
  public :: boundary_t, resolve_fluid_bc, remap_nodal_velocity, tie_fluid

  !> The faces' conditions of a scene: what init resolves from the input, and the face
  !> loads. Data set up once; the procedures do not change it.
  type :: boundary_t
    integer :: nd = 1
    integer :: ncells(3) = 1
    !> each phase's face conditions at the mirror walls and in its constraints
    !> (bc_free, bc_fixed, bc_roller): phase 1 the skeleton (or the one point set), phase
    !> 2 the pore fluid (fluid_mirror_bc: roller at an impermeable face that holds the
    !> skeleton, free elsewhere; fixed at a rigid base, which moves both phases)
    integer :: kind(6, 2) = bc_free
    !> the pore fluid's condition per face, resolved (fbc_drained or fbc_impermeable;
    !> 0 in scenes of one phase)
    integer :: fbc(6) = 0
    logical :: tied(6) = .false.     !< tied faces (&boundary condition = 'tied')
    integer :: base = 0              !< the face of the rigid base (&motion base); 0 none
    type(face_loads_t) :: faces      !< tractions, drained-face pressure, dashpots, fluid ties
  contains
    procedure :: init => boundary_init
    procedure :: free => boundary_free
    procedure :: hold => boundary_hold
  end type boundary_t

contains

  !> The faces' conditions of cfg on grid, with the grid functions of kernel; two_phase:
  !> the scene has pore fluid, whose conditions are resolved (resolve_fluid_bc).
  subroutine boundary_init(self, cfg, grid, kernel, two_phase)
    class(boundary_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: kernel
    logical, intent(in) :: two_phase
    call self%free()
    self%nd = cfg%ndim
    self%ncells = grid%ncells
    self%fbc = 0
    if (two_phase) self%fbc = resolve_fluid_bc(cfg, cfg%bc)
    ! The pore fluid of a tied face is tied with the skeleton: no condition of its own.
    where (cfg%tied) self%fbc = 0
    call self%faces%init(cfg, grid, kernel, self%fbc)
    self%kind(:, 1) = self%faces%walls%bc
    self%kind(:, 2) = bc_free
    if (two_phase) self%kind(:, 2) = fluid_mirror_bc(self%nd, self%fbc, self%kind(:, 1))
    self%tied = cfg%tied
    ! Two phases: the coupled update takes each tied pair as one node (join_pairs), and
    ! the face loads give that node the pair's share.
    if (two_phase) self%faces%joined = self%tied(1:5:2) .and. self%tied(2:6:2)
    self%base = base_face(cfg)
    ! A rigid base moves both phases (shake_base), so its pore water is held in every
    ! component in the coupled update as its skeleton is: no drag of water sliding along a
    ! held skeleton is booked at nodes whose velocities the base then sets.
    if (two_phase .and. self%base > 0) self%kind(self%base, 2) = bc_fixed
  end subroutine boundary_init

  !> Release what init made; no face holds a condition afterwards.
  subroutine boundary_free(self)
    class(boundary_t), intent(inout) :: self
    self%kind = bc_free
    self%fbc = 0
    self%tied = .false.
    self%base = 0
    call self%faces%free()
  end subroutine boundary_free

  !> The pore fluid's condition of each face: as given (&boundary fluid), or by default
  !> drained at a free face of the skeleton (bc) and impermeable at a fixed or roller one.
  pure function resolve_fluid_bc(cfg, bc) result(fbc)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: bc(6)
    integer :: fbc(6)
    integer :: f
    fbc = 0
    do f = 1, 2*cfg%ndim
      fbc(f) = cfg%fluid_bc(f)
      if (fbc(f) == fbc_default) then
        fbc(f) = merge(fbc_drained, fbc_impermeable, bc(f) == bc_free)
      end if
    end do
  end function resolve_fluid_bc

  !> The kinematic conditions of whole faces on the velocities of one phase at the nodes
  !> olo..ohi (node fields from lo), after the nodal update (both = .true.: the old and
  !> new velocity slots of nvel) and after the remap (.false.: the new slots only), in
  !> this order: the rigid base's nodes at the motion's velocity (shake_base; with both,
  !> the base's work added to work, gravity the step's), then the node pairs of tied
  !> faces as one node (tie_sides, one reduction over comm per tied axis). cfg holds the
  !> base's motion; time and dt the step's.
  subroutine boundary_hold(self, cfg, lo, olo, ohi, node, nvel, both, time, dt, gravity, work, comm)
    class(boundary_t), intent(in) :: self
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: nvel(:, lo(1):, lo(2):, lo(3):)
    logical, intent(in) :: both
    real(wp), intent(in) :: time, dt, gravity(3)
    real(wp), intent(inout) :: work
    type(MPI_Comm), intent(in) :: comm
    if (self%base > 0) &
      call shake_base(self%nd, lo, olo, ohi, self%base, self%ncells, base_velocity(cfg, time), &
                      base_velocity(cfg, time + dt), node, nvel, both, gravity, dt, work)
    if (any(self%tied)) &
      call tie_sides(self%nd, lo, olo, ohi, self%ncells, self%tied, node, nvel, both, comm)
  end subroutine boundary_hold

  !> MUSL remap, at the nodes olo..ohi: the new-velocity slots of nvel (cleared first)
  !> from the remapped momenta node(2:1+nd) over the step's masses node(1); components
  !> held by the face conditions bc (faces%walls) are zero (with walls, not those of a
  !> node that moves away from a rough wall, which the wall lets go as in nodal_update).
  subroutine remap_nodal_velocity(nd, lo, olo, ohi, node, faces, bc, nvel, walls)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: node(:, lo(1):, lo(2):, lo(3):)
    type(face_loads_t), intent(in) :: faces
    integer, intent(in) :: bc(6)
    real(wp), intent(inout) :: nvel(:, lo(1):, lo(2):, lo(3):)
    logical, intent(in) :: walls   !< rough walls let go of nodes moving away (nodal_update)
    integer :: i, j, k, ilo(3), ihi(3)
    real(wp) :: m, v(3)
    logical :: fix(3), row_free
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    nvel(:, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) = 0.0_wp
    ! Inside the box of free nodes no component is held.
    call faces%grid%interior_nodes(1, ilo, ihi)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        row_free = j >= ilo(2) .and. j <= ihi(2) .and. k >= ilo(3) .and. k <= ihi(3)
        do i = olo(1), ohi(1)
          m = node(1, i, j, k)
          if (m <= 0.0_wp) cycle
          nvel(sl%new_lo:sl%new_hi, i, j, k) = node(sl%mom_lo:sl%mom_hi, i, j, k)/m
          if (row_free .and. i >= ilo(1) .and. i <= ihi(1)) cycle
          fix = faces%walls%constrained([i, j, k], bc)
          if (walls .and. any(fix)) then
            ! As in the update: a rough wall holds only a node that runs into it.
            v = 0.0_wp
            v(1:nd) = nvel(sl%new_lo:sl%new_hi, i, j, k)
            where (faces%walls%wall_contact([i, j, k], nd, v) == 2) fix = .false.
          end if
          where (fix(1:nd)) nvel(sl%new_lo:sl%new_hi, i, j, k) = 0.0_wp
        end do
      end do
    end do
  end subroutine remap_nodal_velocity

  !> Set the fluid velocity components tied to the solid (fluid_ties) to the solid's
  !> on the owned nodes, in the new-velocity slots of nvel.
  subroutine tie_fluid(nd, lo, olo, ohi, faces, node_s, node_f, nvel_s, nvel_f)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    type(face_loads_t), intent(in) :: faces
    real(wp), intent(in) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: nvel_s(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: nvel_f(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k, ilo(3), ihi(3)
    logical :: tie(3), row_near
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    ! Only nodes near a face are tied.
    call faces%inner_nodes(ilo, ihi)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        row_near = j < ilo(2) .or. j > ihi(2) .or. k < ilo(3) .or. k > ihi(3)
        do i = olo(1), ohi(1)
          if (.not. (row_near .or. i < ilo(1) .or. i > ihi(1))) cycle
          tie = faces%fluid_ties([i, j, k])
          if (.not. any(tie)) cycle
          if (node_s(1, i, j, k) <= 0.0_wp .or. node_f(1, i, j, k) <= 0.0_wp) cycle
          where (tie(1:nd)) nvel_f(sl%new_lo:sl%new_hi, i, j, k) = nvel_s(sl%new_lo:sl%new_hi, i, j, k)
        end do
      end do
    end do
  end subroutine tie_fluid

end module dpmpm_boundary
