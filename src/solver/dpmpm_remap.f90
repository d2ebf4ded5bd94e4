!> The MUSL remap of one step (doc/theory.md 4.1, doc/architecture.md "One step"): the
!> updated point momenta of every phase mapped back to the grid, the nodal velocities
!> taken from them, and the point velocity gradients (fluid points: the divergences)
!> from those. With two phases it also ties the fluid to the skeleton at impermeable
!> faces and, where the implicit drag locks the phases, removes the split that the two
!> point sets' projections make of the locked velocity and relaxes the relative velocity
!> as the step's drag would.
module dpmpm_remap
  use dpmpm_kinds, only: wp
  use dpmpm_phase, only: phase_t, solid_phase, fluid_phase
  use dpmpm_state, only: state_t
  use dpmpm_transfer, only: point_gradient, point_divergences, momentum_p2g, momentum_project_p2g
  use dpmpm_nodal_update, only: remap_nodal_velocity, tie_fluid
  use dpmpm_drag, only: relax_remapped, remove_split
  use dpmpm_rigid, only: drive_rigid_nodes
  implicit none
  private
  public :: musl_remap

contains

  !> MUSL (double mapping): map the updated point momenta of every phase back to the
  !> grid and take the velocity gradients from these smoother nodal velocities. With
  !> two phases the fluid is tied to the solid at impermeable faces, and with implicit
  !> drag, where the drag locks the phases, the relative velocity the remap adds is
  !> shrunk as the step's drag would (relax_remapped): without it the step is
  !> unstable on scattered points (doc/verification.md, "Long runs"). The fluid
  !> points get the divergences of the fluid's and the solid's velocity.
  !> locked: the points of each phase hold in lockp the velocity c that the implicit drag
  !> locks both phases to (locked_velocity), gathered by g2p. There the phases' nodal
  !> increments are nearly equal; each point set projects them with its own masses, and
  !> the difference of the two projections would reach the pore-pressure update as a
  !> relative velocity no drag acted on. The remap carries c to the grid through each
  !> point set (P c, in the force slots of the phase's node field), and P_f c - P_s c is
  !> taken from the remapped relative velocity (remove_split; doc/verification.md,
  !> "Long runs").
  subroutine musl_remap(self, dt, locked)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    logical, intent(in) :: locked
    real(wp), allocatable :: wstep(:, :, :, :)
    integer :: ip, nd
    logical :: coupled
    nd = self%nd
    coupled = self%nph == 2
    ! Relative velocity of the nodal update, before the remap overwrites it.
    if (coupled) wstep = self%phase(fluid_phase)%nvel(nd + 1:2*nd, :, :, :) - &
                         self%phase(solid_phase)%nvel(nd + 1:2*nd, :, :, :)
    ! (locked: the locked velocity goes back to the grid in the remap's own pass, into
    ! the force slots of each phase's node field, for remove_split)
    do ip = 1, self%nph
      if (locked) then
        call remap_velocities(self, self%phase(ip), self%phase(ip)%lockp)
      else
        call remap_velocities(self, self%phase(ip))
      end if
    end do
    ! the nodes of rigid bodies move with them in the remapped field too
    if (self%has_rigid) call drive_rigid_nodes(nd, self%dec%alo, self%dec%olo, self%dec%ohi, &
                                               self%phase(solid_phase)%node, self%rnode, self%grid, dt, &
                                               self%phase(solid_phase)%nvel)
    if (coupled) then
      associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
        call tie_fluid(nd, self%dec%alo, self%dec%olo, self%dec%ohi, self%faces, s%node, f%node, &
                       s%nvel, f%nvel)
        if (locked) then
          call remove_split(nd, self%dec%alo, self%dec%olo, self%dec%ohi, self%faces, f%bc, s%node, f%node, &
                            s%node(nd + 2:1 + 2*nd, :, :, :), f%node(nd + 2:1 + 2*nd, :, :, :), s%nvel, f%nvel)
          call relax_remapped(nd, self%dec%alo, self%dec%olo, self%dec%ohi, self%faces, f%bc, s%node, &
                              f%node, self%ndrag, dt, wstep, s%nvel, f%nvel)
        end if
        ! the corrections keep the pair's momentum; the skeleton at rigid nodes keeps v_r
        if (self%has_rigid) call drive_rigid_nodes(nd, self%dec%alo, self%dec%olo, self%dec%ohi, s%node, &
                                                   self%rnode, self%grid, dt, s%nvel)
      end associate
    end if
    do ip = 1, self%nph
      call self%dec%halo_copy(self%phase(ip)%nvel)
      call self%mirror%unfold(self%phase(ip)%nvel, 0, self%phase(ip)%bc)
    end do
    associate (s => self%phase(solid_phase))
      call point_gradient(nd, s%st%nw, s%pts%n, s%st%i0, s%st%sw, s%st%sdw, self%dec%alo, s%nvel, s%vgrad)
    end associate
    if (coupled) then
      ! the fluid points' divergences of both phases' velocities in one pass
      associate (f => self%phase(fluid_phase))
        call point_divergences(nd, f%st%nw, f%pts%n, f%st%i0, f%st%sw, f%st%sdw, self%dec%alo, f%nvel, &
                               self%phase(solid_phase)%nvel, f%divf, f%divs)
      end associate
    end if
  end subroutine musl_remap

  !> Nodal velocities (new slots of ph%nvel, owned nodes) from the point momenta of
  !> the phase mapped to the grid again; the masses in ph%node are those of the step.
  !> Components held by the phase's face conditions are zero. With lockp (the locked
  !> velocity at the phase's points), the same pass puts the momentum of its projection
  !> through the phase's points into the force slots of ph%node (momentum_project_p2g),
  !> folded and summed over the ranks with the momenta.
  subroutine remap_velocities(self, ph, lockp)
    class(state_t), intent(inout) :: self
    type(phase_t), intent(inout) :: ph
    real(wp), contiguous, intent(in), optional :: lockp(:, :)
    integer :: nd
    nd = self%nd
    ! Reuse the momentum and force slots of node(); the masses are unchanged (zero beyond
    ! the box).
    ph%node(2:1 + 2*nd, self%zlo(1):self%zhi(1), self%zlo(2):self%zhi(2), self%zlo(3):self%zhi(3)) = 0.0_wp
    if (present(lockp)) then
      call momentum_project_p2g(nd, ph%st%nw, ph%pts%n, ph%st%i0, ph%st%sw, ph%pts%mass, ph%pts%v, &
                                self%dec%alo, lockp, ph%node)
    else
      call momentum_p2g(nd, ph%st%nw, ph%pts%n, ph%st%i0, ph%st%sw, ph%pts%mass, ph%pts%v, self%dec%alo, &
                        ph%node)
    end if
    call self%mirror%fold(ph%node, 1, ph%bc)
    call self%dec%halo_sum(ph%node)
    ! Rough walls let go of nodes moving away from them in scenes of one phase (nodal_update).
    call remap_nodal_velocity(nd, self%dec%alo, max(self%dec%olo, self%zlo), min(self%dec%ohi, self%zhi), &
                              ph%node, self%grid, ph%bc, ph%nvel, self%grid%rough .and. self%nph == 1)
  end subroutine remap_velocities

end module dpmpm_remap
