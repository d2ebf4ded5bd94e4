!> A phase of the step: one point set (solid skeleton or pore fluid) with its
!> grid-transfer work arrays and node fields. The step runs over a list of one or
!> two phases; what couples two (nodal porosity, drag) is not a phase's own but the
!> coupling's (coupling_t).
module dpmpm_phase
  use dpmpm_kinds, only: wp
  use dpmpm_particles, only: particle_set_t
  use dpmpm_stencil, only: stencil_t
  use dpmpm_gauss_fields, only: reach_cache_t, reach_cache_bytes
  implicit none
  private
  public :: phase_t, coupling_t, solid_phase, fluid_phase

  integer, parameter :: solid_phase = 1     !< index of the solid phase in the list
  integer, parameter :: fluid_phase = 2     !< index of the fluid phase (two-phase scenes)

  type :: phase_t
    type(particle_set_t) :: pts               !< the points of the phase
    integer :: bc(6) = 0                      !< its face conditions at the mirror walls
    type(stencil_t) :: st                     !< the points' stencils, rebuilt every step
    real(wp), allocatable :: vgrad(:, :)      !< solid points: velocity gradient of the phase (9, n)
    !> Fluid points: the divergences of the fluid's velocity (divf) and of the skeleton's
    !> (divs), all the pore-pressure update reads of the two velocity gradients (n)
    real(wp), allocatable :: divf(:), divs(:)
    ! Node fields on the stored nodes (owned + ghosts).
    real(wp), allocatable :: node(:, :, :, :) !< mass, momentum(nd), force(nd)
    real(wp), allocatable :: nvel(:, :, :, :) !< velocity before (nd) and after (nd) the update
    real(wp), allocatable :: vacc(:, :, :, :) !< MLS nodal velocities: moment sums (velocity_mls)
    real(wp), allocatable :: bacc(:, :)       !< body acceleration per point (manufactured solution)
    !> Two phases, MUSL, implicit drag: the locked velocity at the points (nd, n), gathered
    !> by g2p for the remap (musl_remap)
    real(wp), allocatable :: lockp(:, :)
    ! Gauss quadrature: reconstruction sums and solutions (cell arrays), velocity
    ! gradients at the Gauss points, positions and volumes at the force evaluation,
    ! effective point volumes. Fluid sets: gsol2 is the solid share -n_s p.
    real(wp), allocatable :: gacc(:, :, :, :), gsol(:, :, :, :), gsol2(:, :, :, :), glg(:, :, :, :)
    !> Fluid sets: the field sums of the second field (its counts and moments are those
    !> of gacc) and the Gauss-point gradients of the second velocity, made in the same
    !> passes over the points as the first.
    real(wp), allocatable :: gacc2(:, :, :, :), glg2(:, :, :, :)
    !> The Gauss fields hold one isotropic field s I (fluid sets: the pore pressure's
    !> shares) instead of the stress components.
    logical :: giso = .false.
    real(wp), allocatable :: xold(:, :), volold(:), vt(:)
    !> Point volume and Gauss-quadrature volume of the nodes (thin_node_forces).
    real(wp), allocatable :: nvol(:, :, :, :)
    type(reach_cache_t) :: reach              !< Gauss points within reach of each point
  contains
    procedure :: free => phase_free
    procedure :: bytes_per_point => phase_bytes_per_point
  end type phase_t

  !> The node fields that couple the two phases (doc/theory.md 3.5): what the porous
  !> skeleton's points sum at the nodes, nodal porosity (1 where there is no porous solid),
  !> porous mass and 1/k (0 there) in nporo, and the drag coefficient D (kg/s) of the
  !> fluid's points in ndrag. Allocated in two-phase scenes only, over the stored nodes.
  type :: coupling_t
    real(wp), allocatable :: nporo(:, :, :, :) !< porosity, porous mass, 1/k (3 slots)
    real(wp), allocatable :: ndrag(:, :, :, :) !< drag coefficient (1 slot)
  contains
    procedure :: free => coupling_free
  end type coupling_t

contains

  !> Release the coupling's node fields.
  subroutine coupling_free(self)
    class(coupling_t), intent(inout) :: self
    if (allocated(self%nporo)) deallocate (self%nporo)
    if (allocated(self%ndrag)) deallocate (self%ndrag)
  end subroutine coupling_free

  !> Bytes per point of the phase: the point set's fields, its stencil (first node,
  !> weights and derivatives) and the per-point work arrays of the step.
  integer function phase_bytes_per_point(self) result(b)
    class(phase_t), intent(in) :: self
    b = self%pts%bytes_per_point()
    if (allocated(self%st%i0)) b = b + size(self%st%i0, 1)*storage_size(self%st%i0)/8
    if (allocated(self%st%sw)) b = b + size(self%st%sw(:, :, 1))*storage_size(self%st%sw)/8
    if (allocated(self%st%sdw)) b = b + size(self%st%sdw(:, :, 1))*storage_size(self%st%sdw)/8
    if (allocated(self%vgrad)) b = b + size(self%vgrad, 1)*storage_size(self%vgrad)/8
    if (allocated(self%divf)) b = b + storage_size(self%divf)/8
    if (allocated(self%divs)) b = b + storage_size(self%divs)/8
    if (allocated(self%bacc)) b = b + size(self%bacc, 1)*storage_size(self%bacc)/8
    if (allocated(self%lockp)) b = b + size(self%lockp, 1)*storage_size(self%lockp)/8
    if (allocated(self%xold)) b = b + size(self%xold, 1)*storage_size(self%xold)/8
    if (allocated(self%volold)) b = b + storage_size(self%volold)/8
    if (allocated(self%vt)) b = b + storage_size(self%vt)/8
    if (self%pts%n > 0) b = b + int(reach_cache_bytes(self%reach)/self%pts%n)
  end function phase_bytes_per_point

  !> Release the points and every work array.
  subroutine phase_free(self)
    class(phase_t), intent(inout) :: self
    call self%pts%free()
    self%bc = 0
    call self%st%free()
    if (allocated(self%vgrad)) deallocate (self%vgrad)
    if (allocated(self%divf)) deallocate (self%divf)
    if (allocated(self%divs)) deallocate (self%divs)
    if (allocated(self%node)) deallocate (self%node)
    if (allocated(self%nvel)) deallocate (self%nvel)
    if (allocated(self%vacc)) deallocate (self%vacc)
    if (allocated(self%bacc)) deallocate (self%bacc)
    if (allocated(self%lockp)) deallocate (self%lockp)
    if (allocated(self%gacc)) deallocate (self%gacc)
    if (allocated(self%gsol)) deallocate (self%gsol)
    if (allocated(self%gsol2)) deallocate (self%gsol2)
    if (allocated(self%glg)) deallocate (self%glg)
    if (allocated(self%gacc2)) deallocate (self%gacc2)
    if (allocated(self%glg2)) deallocate (self%glg2)
    if (allocated(self%xold)) deallocate (self%xold)
    if (allocated(self%volold)) deallocate (self%volold)
    if (allocated(self%vt)) deallocate (self%vt)
    if (allocated(self%nvol)) deallocate (self%nvol)
    self%reach = reach_cache_t()
  end subroutine phase_free

end module dpmpm_phase
