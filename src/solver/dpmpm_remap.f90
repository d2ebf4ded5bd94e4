!> The MUSL remap of one step (doc/theory.md 4.1, doc/architecture.md "One step"): the
!> points' velocities and positions from the updated nodal velocities (g2p), their
!> momenta mapped back to the grid in the same pass, the nodal velocities taken from
!> them, and the point velocity gradients (fluid points: the divergences) from those.
!> With two phases it also ties the fluid to the skeleton at impermeable faces and,
!> where the implicit drag locks the phases, removes the split that the two point sets'
!> projections make of the locked velocity and relaxes the relative velocity as the
!> step's drag would.
module dpmpm_remap
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: node_slots_t, node_slots
  use dpmpm_phase, only: phase_t, solid_phase, fluid_phase
  use dpmpm_state, only: state_t
  use dpmpm_transfer, only: g2p, g2p_remap, point_gradient, point_divergences, momentum_p2g, &
    momentum_project_p2g
  use dpmpm_boundary, only: remap_nodal_velocity, tie_fluid
  use dpmpm_drag, only: relax_remapped, remove_split, locked_velocity
  use dpmpm_tied_sides, only: join_pairs, unjoin_pairs, copy_pairs
  use dpmpm_rigid, only: drive_rigid_nodes, hold_rigid_points, body_velocities
  use dpmpm_contact, only: contact_remap
  implicit none
  private
  public :: musl_remap, remap_locks, tied_save_t, join_tied, split_tied

  !> The tied faces' node sums of both phases and of the drag, kept while the pairs are
  !> joined (join_tied, split_tied).
  type :: tied_save_t
    real(wp), allocatable :: s(:), f(:), d(:)
  end type tied_save_t

contains

  !> MUSL (double mapping): g2p of the points' velocities and positions, then their
  !> updated momenta mapped back to the grid and the velocity gradients taken from these
  !> smoother nodal velocities. With two phases the fluid is tied to the solid at
  !> impermeable faces, and with implicit drag, where the drag locks the phases, the
  !> relative velocity the remap adds is shrunk as the step's drag would
  !> (relax_remapped): without it the step is unstable on scattered points
  !> (doc/verification.md, "Long runs"). The fluid points get the divergences of the
  !> fluid's and the solid's velocity.
  !> Locked (remap_locks): the points of each phase gather in lockp the velocity c that
  !> the implicit drag locks both phases to (locked_velocity), from the exterior nodes as
  !> each phase's walls mirror them. There the phases' nodal increments are nearly equal;
  !> each point set projects them with its own masses, and the difference of the two
  !> projections would reach the pore-pressure update as a relative velocity no drag
  !> acted on. The remap carries c to the grid through each point set (P c, in the force
  !> slots of the phase's node field), and P_f c - P_s c is taken from the remapped
  !> relative velocity (remove_split; doc/verification.md, "Long runs").
  subroutine musl_remap(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    real(wp), allocatable :: wstep(:, :, :, :), lockv(:, :, :, :), vdash(:, :, :, :)
    integer :: ip, nd
    logical :: coupled, locked, tied
    real(wp) :: unused
    type(tied_save_t) :: tsave
    integer :: a, flo(3), fhi(3)
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    coupled = self%nph == 2
    tied = coupled .and. any(self%bnd%tied)
    locked = remap_locks(self)
    ! Relative velocity of the nodal update, before the remap overwrites it.
    if (coupled) wstep = self%phase(fluid_phase)%nvel(sl%new_lo:sl%new_hi, :, :, :) - &
                         self%phase(solid_phase)%nvel(sl%new_lo:sl%new_hi, :, :, :)
    if (locked) then
      associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
        allocate (lockv(nd, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                        self%dec%alo(3):self%dec%ahi(3)))
        ! (tied faces: at each pair as one node)
        if (tied) call join_tied(self, tsave)
        call locked_velocity(nd, self%dec%alo, self%dec%olo, self%dec%ohi, self%bnd%faces, f%bc, s%node, &
                             f%node, self%cpl%ndrag, dt, s%nvel, f%nvel, lockv)
        if (tied) call split_tied(self, tsave, lockv)
      end associate
      call self%dec%halo_copy(lockv)
    end if
    ! One phase on absorbing faces: the velocities the dashpots acted on, before the remap
    ! overwrites them (kept at their nodes below).
    if (self%nph == 1 .and. self%bnd%faces%absorbing) vdash = self%phase(solid_phase)%nvel(sl%new_lo:sl%new_hi, :, :, :)
    ! (Not locked, lockv is unallocated: an absent argument.)
    do ip = 1, self%nph
      if (locked) call self%mirror%unfold(lockv, 0, self%phase(ip)%bc)
      call remap_velocities(self, self%phase(ip), dt, ip == solid_phase, lockv)
    end do
    if (allocated(vdash)) call keep_dashpot_velocities(self, vdash, self%phase(solid_phase)%nvel)
    ! the nodes of rigid bodies move with them in the remapped field too (a frictional
    ! contact: the soil's remapped velocities corrected against the body's, contact_remap)
    if (self%has_rigid .and. self%bodies%on) then
      call contact_remap(self, dt)
    else if (self%has_rigid) then
      call drive_rigid_nodes(nd, self%dec%alo, self%dec%olo, self%dec%ohi, self%phase(solid_phase)%node, &
                             self%rnode, self%bnd%faces%walls, dt, self%phase(solid_phase)%nvel)
    end if
    if (coupled) then
      associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
        if (tied) then
          ! Tied faces: each pair's remapped sums at one node (on the lower face), its
          ! velocities from them.
          call join_tied(self, tsave)
          do a = 1, nd
            if (.not. (self%bnd%tied(2*a - 1) .and. self%bnd%tied(2*a))) cycle
            flo = max(self%dec%olo, self%zlo)
            fhi = min(self%dec%ohi, self%zhi)
            if (flo(a) > 0 .or. fhi(a) < 0) cycle
            flo(a) = 0
            fhi(a) = 0
            do ip = 1, self%nph
              call remap_nodal_velocity(nd, self%dec%alo, flo, fhi, self%phase(ip)%node, self%bnd%faces, &
                                        self%phase(ip)%bc, self%phase(ip)%nvel, .false.)
            end do
          end do
        end if
        call tie_fluid(nd, self%dec%alo, self%dec%olo, self%dec%ohi, self%bnd%faces, s%node, f%node, &
                       s%nvel, f%nvel)
        if (locked) then
          call remove_split(nd, self%dec%alo, self%dec%olo, self%dec%ohi, self%bnd%faces, f%bc, s%node, f%node, &
                            s%node(sl%force_lo:sl%force_hi, :, :, :), f%node(sl%force_lo:sl%force_hi, :, :, :), s%nvel, f%nvel)
          call relax_remapped(nd, self%dec%alo, self%dec%olo, self%dec%ohi, self%bnd%faces, f%bc, s%node, &
                              f%node, self%cpl%ndrag, dt, wstep, s%nvel, f%nvel)
        end if
        ! the corrections keep the pair's momentum; the skeleton at rigid nodes keeps v_r
        if (self%has_rigid) call drive_rigid_nodes(nd, self%dec%alo, self%dec%olo, self%dec%ohi, s%node, &
                                                   self%rnode, self%bnd%faces%walls, dt, s%nvel)
        if (tied) call split_tied(self, tsave)
      end associate
    end if
    ! the kinematic conditions of whole faces (the rigid base, tied faces) on the remapped
    ! field too (the new velocities only; no work)
    unused = 0.0_wp
    do ip = 1, self%nph
      call self%bnd%hold(self%cfg, self%dec%alo, max(self%dec%olo, self%zlo), min(self%dec%ohi, self%zhi), &
                         self%phase(ip)%node, self%phase(ip)%nvel, .false., self%time, dt, &
                         self%cfg%gravity, unused, self%dec%comm)
    end do
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

  !> The nodes of absorbing faces keep, in each component that a dashpot damps, the new
  !> velocity of the nodal update, which the dashpot acted on (vdash), in place of the
  !> remapped one, as the kinematic conditions of other faces hold theirs (boundary_t%hold).
  !> The remapped velocity there is the points' FLIP velocity projected back, not the one
  !> the dashpot acted on; with flip = 1, strain rates next to the face taken from it let a
  !> mode grow once the waves have left (doc/verification.md, "Site response: 20 s of
  !> shaking and after"; doc/theory.md 6.6). One phase only (two phases: not examined).
  subroutine keep_dashpot_velocities(self, vdash, nvel)
    class(state_t), intent(in) :: self
    real(wp), intent(in) :: vdash(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(inout) :: nvel(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer :: i, j, k, nd, lo(3), hi(3)
    real(wp) :: cd(3)
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    lo = max(self%dec%olo, self%zlo)
    hi = min(self%dec%ohi, self%zhi)
    do k = lo(3), hi(3)
      do j = lo(2), hi(2)
        do i = lo(1), hi(1)
          if (.not. self%bnd%faces%near_face([i, j, k])) cycle
          cd = self%bnd%faces%dashpot([i, j, k], .false.)
          where (cd(1:nd) > 0.0_wp) nvel(sl%new_lo:sl%new_hi, i, j, k) = vdash(1:nd, i, j, k)
        end do
      end do
    end do
  end subroutine keep_dashpot_velocities

  !> Two phases with the MUSL remap and implicit drag: the remap carries the velocity the
  !> drag locks both phases to through each point set (g2p gathers it).
  logical function remap_locks(self)
    class(state_t), intent(in) :: self
    remap_locks = self%nph == 2 .and. self%cfg%scheme == 'musl' .and. self%cfg%remap_drag .and. &
                  self%cfg%drag == 'implicit'
  end function remap_locks

  !> g2p of the phase's points (velocities and positions) and their new momenta on the
  !> grid again: nodal velocities (new slots of ph%nvel, owned nodes) from them; the
  !> masses in ph%node are those of the step. Components held by the phase's face
  !> conditions are zero. With lockv (the locked velocity on the grid), g2p gathers it at
  !> the points into ph%lockp and the same pass puts the momentum of its projection
  !> through the phase's points into the force slots of ph%node (g2p_remap), folded and
  !> summed over the ranks with the momenta. The points of rigid materials keep their
  !> velocity (solid: the phase of the skeleton), between g2p and the scatter.
  subroutine remap_velocities(self, ph, dt, solid, lockv)
    class(state_t), intent(inout) :: self
    type(phase_t), intent(inout) :: ph
    real(wp), intent(in) :: dt
    logical, intent(in) :: solid
    real(wp), contiguous, intent(in), optional :: lockv(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer :: nd
    nd = self%nd
    ! Reuse the momentum and force slots of node(); the masses are unchanged (zero beyond
    ! the box).
    ph%node(2:1 + 2*nd, self%zlo(1):self%zhi(1), self%zlo(2):self%zhi(2), self%zlo(3):self%zhi(3)) = 0.0_wp
    ! (Without lockv, gf is absent and g2p gathers nothing; lockp, then unallocated, is
    ! absent too.)
    associate (ps => ph%pts, st => ph%st, lo => self%dec%alo)
      if (self%has_rigid .and. solid) then
        call g2p(nd, st%nw, ps%n, st%i0, st%sw, st%sdw, lo, ph%nvel, self%cfg%flip, dt, ps%v, ps%x, &
                 gradient=.false., gf=lockv, gv=ph%lockp)
        call hold_rigid_points(nd, ps%n, ps%mat, self%mats, &
                               body_velocities(self%mats, self%time + 0.5_wp*dt), ps%v)
        if (present(lockv)) then
          call momentum_project_p2g(nd, st%nw, ps%n, st%i0, st%sw, ps%mass, ps%v, lo, ph%lockp, ph%node)
        else
          call momentum_p2g(nd, st%nw, ps%n, st%i0, st%sw, ps%mass, ps%v, lo, ph%node)
        end if
      else
        call g2p_remap(nd, st%nw, ps%n, st%i0, st%sw, st%sdw, lo, ph%nvel, self%cfg%flip, dt, ps%mass, &
                       ps%v, ps%x, ph%node, gf=lockv, gv=ph%lockp)
      end if
    end associate
    call self%mirror%fold(ph%node, 1, ph%bc)
    call self%dec%halo_sum(ph%node)
    ! Rough walls let go of nodes moving away from them in scenes of one phase (nodal_update).
    call remap_nodal_velocity(nd, self%dec%alo, max(self%dec%olo, self%zlo), min(self%dec%ohi, self%zhi), &
                              ph%node, self%bnd%faces, ph%bc, ph%nvel, self%bnd%faces%walls%rough .and. self%nph == 1)
  end subroutine remap_velocities

  !> The node sums of both phases and the drag of tied pairs put together at the lower
  !> face's node for the coupled update (join_pairs), the sums as they were kept in save.
  subroutine join_tied(self, save)
    class(state_t), intent(inout) :: self
    type(tied_save_t), intent(out) :: save
    associate (s => self%phase(solid_phase), f => self%phase(fluid_phase), dec => self%dec)
      call join_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, s%node, save%s, &
                      dec%comm)
      call join_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, f%node, save%f, &
                      dec%comm)
      call join_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, self%cpl%ndrag, save%d, &
                      dec%comm)
    end associate
  end subroutine join_tied

  !> After a pass over the joined pairs: the sums kept by join_tied back, and the joined
  !> node's velocities (both slots, both phases; with field, field's values instead)
  !> given to the upper face's node of each pair.
  subroutine split_tied(self, save, field)
    class(state_t), intent(inout) :: self
    type(tied_save_t), intent(inout) :: save
    real(wp), intent(inout), optional :: field(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    associate (s => self%phase(solid_phase), f => self%phase(fluid_phase), dec => self%dec)
      call unjoin_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, s%node, save%s)
      call unjoin_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, f%node, save%f)
      call unjoin_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, self%cpl%ndrag, save%d)
      if (present(field)) then
        call copy_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, field, dec%comm)
        return
      end if
      call copy_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, s%nvel, dec%comm)
      call copy_pairs(self%nd, dec%alo, dec%olo, dec%ohi, self%grid%ncells, self%bnd%tied, f%nvel, dec%comm)
    end associate
  end subroutine split_tied

end module dpmpm_remap
