!> The frictional contact of a rigid body with the soil (&material contact = 'frictional';
!> doc/theory.md 6.8.1), around the step of dpmpm_step: the body's points are kept out of
!> the soil's node fields (their masses are 0 from before p2g to after g2p, contact_hide),
!> so the nodal update gives the soil's own velocities; at the nodes both reach, those are
!> corrected against the body's velocity by Coulomb friction and adhesion with the body's
!> outward normal from the gradient of its mass (contact_nodes, contact_node); a free body
!> takes the reaction and moves by gravity and its load; under MUSL the remapped soil
!> velocities are corrected again (contact_remap); the body's points then move by dt times
!> the body's velocity of the step (contact_move).
module dpmpm_contact
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: bc_fixed, bc_roller
  use dpmpm_materials, only: model_rigid
  use dpmpm_phase, only: solid_phase
  use dpmpm_state, only: state_t
  use dpmpm_rigid, only: body_p2g, contact_node, body_velocities
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM
  implicit none
  private
  public :: contact_hide, contact_nodes, contact_remap, contact_move

  !> passes of the free body's contact solve at most, and its relative tolerance
  integer, parameter :: max_passes = 60
  real(wp), parameter :: pass_tol = 1.0e-12_wp

contains

  !> The scene's rigid body with a frictional contact, looked for once (self%bodies%on
  !> stays .false. without one), and its mass from its points.
  subroutine contact_setup(self)
    class(state_t), intent(inout) :: self
    integer :: m
    self%bodies%known = .true.
    do m = 1, size(self%mats)
      if (self%mats(m)%model /= model_rigid) cycle
      if (self%cfg%materials(m)%contact /= 'frictional') cycle
      self%bodies%on = .true.
      self%bodies%mat = m
    end do
    if (.not. self%bodies%on) return
    m = self%bodies%mat
    associate (b => self%bodies, c => self%cfg%materials(m), ps => self%phase(solid_phase)%pts)
      b%free = c%body_motion == 'free'
      b%mu = c%contact_friction
      b%adhesion = c%contact_adhesion
      b%density = c%density
      b%load = 0.0_wp
      b%load(1:self%nd) = c%body_load(1:self%nd)
      b%mass = sum(ps%mass(1:ps%n), mask=ps%mat(1:ps%n) == m)
      call MPI_Allreduce(MPI_IN_PLACE, b%mass, 1, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    end associate
  end subroutine contact_setup

  !> The free body's velocity at the start of the step, the mean of its points' (they carry
  !> the body's velocity: from the start, after a restart, and after the equilibrium phase
  !> has set every velocity to zero).
  subroutine body_velocity(self)
    class(state_t), intent(inout) :: self
    real(wp) :: s(3)
    integer :: p
    s = 0.0_wp
    associate (ps => self%phase(solid_phase)%pts)
      do p = 1, ps%n
        if (ps%mat(p) == self%bodies%mat) s(1:self%nd) = s(1:self%nd) + ps%mass(p)*ps%v(1:self%nd, p)
      end do
    end associate
    call MPI_Allreduce(MPI_IN_PLACE, s, 3, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    self%bodies%v = s/self%bodies%mass
  end subroutine body_velocity

  !> Before p2g (the stencils of the step known): the body's points kept out of the node
  !> fields (their masses and positions saved, the masses set to 0), the body's share of
  !> the node fields in self%rnode (mass, mass gradient: body_p2g) folded at mirror walls
  !> (the gradient as a geometric vector: fixed walls reflect it as rollers do) and summed
  !> over the ranks, and the body's velocity for the step: the prescribed one at its middle,
  !> or for a free body its velocity with gravity's and the load's change (the contact's
  !> follows in contact_nodes).
  subroutine contact_hide(self, dt, gravity)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt, gravity(3)
    real(wp) :: vb(3, size(self%mats))
    integer :: p, bc(6)
    if (.not. self%bodies%known) call contact_setup(self)
    if (.not. self%bodies%on) return
    if (self%bodies%free) call body_velocity(self)
    associate (b => self%bodies, s => self%phase(solid_phase), nd => self%nd)
      b%msave = s%pts%mass(1:s%pts%n)
      b%xsave = s%pts%x(:, 1:s%pts%n)
      do p = 1, s%pts%n
        if (s%pts%mat(p) == b%mat) then
          s%pts%mass(p) = 0.0_wp
        else
          b%msave(p) = 0.0_wp
        end if
      end do
      self%rnode = 0.0_wp
      call body_p2g(nd, s%st%nw, s%pts%n, s%st%i0, s%st%sw, s%st%sdw, b%msave, self%dec%alo, self%rnode)
      if (.not. allocated(b%snode)) allocate (b%snode, mold=self%rnode)
      b%snode = 0.0_wp
      call body_p2g(nd, s%st%nw, s%pts%n, s%st%i0, s%st%sw, s%st%sdw, s%pts%mass, self%dec%alo, b%snode)
      bc = self%bnd%kind(:, 1)
      where (bc == bc_fixed) bc = bc_roller
      call self%mirror%fold(self%rnode, 1, bc)
      call self%dec%halo_sum(self%rnode)
      call self%mirror%fold(b%snode, 1, bc)
      call self%dec%halo_sum(b%snode)
      if (b%free) then
        b%vstep = b%v + dt*(gravity + b%load/b%mass)
      else
        vb = body_velocities(self%mats, self%time + 0.5_wp*dt)
        b%vstep = vb(:, b%mat)
      end if
    end associate
  end subroutine contact_hide

  !> After the nodal update of the soil alone: the contact at every owned node that both
  !> the body and the soil reach (contact_node). A prescribed body keeps its velocity; a free
  !> one of mass M takes the reaction, M (V - V*) = -J(V) with V* its velocity without the
  !> contact and J the impulse the contact gives the soil against V, solved by passes
  !> V <- (M V* - J(V) + S V)/(M + S), S the soil's mass at those nodes (exact in one pass
  !> where the soil sticks everywhere, a contraction by S/(M + S) at most elsewhere). The
  !> impulse on the soil goes to the drive's record (self%drive_impulse), the work of the
  !> contact on both and of gravity and the load on a free body to the external work, and
  !> what the contact takes out (friction, the soil stopped at the body) to the dissipation.
  subroutine contact_nodes(self, dt, gravity)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt, gravity(3)
    real(wp) :: sums(4), vstar(3), v(3), vn(3), tol, wsoil, wbody, vmean(3)
    integer :: pass
    associate (b => self%bodies)
      vstar = b%vstep
      v = vstar
      b%iterations = 0
      if (b%free) then
        call contact_pass(self, dt, v, .false., sums, wsoil)
        tol = pass_tol*(norm2(vstar) + dt*norm2(gravity) + tiny(1.0_wp))
        do pass = 1, max_passes
          b%iterations = pass
          vn = (b%mass*vstar - sums(1:3) + sums(4)*v)/(b%mass + sums(4))
          if (norm2(vn - v) <= tol) exit
          v = vn
          call contact_pass(self, dt, v, .false., sums, wsoil)
        end do
        v = vn
      end if
      ! the pass that corrects the soil against the body's velocity v
      call contact_pass(self, dt, v, .true., sums, wsoil)
      self%drive_impulse = self%drive_impulse + sums(1:3)
      b%force = -sums(1:3)/dt
      self%ext_work = self%ext_work + wsoil
      if (b%free) then
        b%vstep = vstar - sums(1:3)/b%mass
        vmean = 0.5_wp*(b%v + b%vstep)
        wbody = -dot_product(sums(1:3), vmean)
        self%ext_work = self%ext_work + wbody + dt*dot_product(b%mass*gravity + b%load, vmean)
        self%drag_loss = self%drag_loss - (wsoil + wbody)
        b%v = b%vstep
      else
        b%v = b%vstep
      end if
    end associate
  end subroutine contact_nodes

  !> One pass of the contact over the owned nodes against the body's velocity vb: sums(1:3)
  !> the impulse it gives the soil, sums(4) the soil's mass at the contact nodes (both over
  !> all ranks), wsoil (this rank) the contact's work on the soil over the step's mean
  !> velocity; with apply, the soil's new velocities corrected (else left as they are).
  subroutine contact_pass(self, dt, vb, apply, sums, wsoil)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt, vb(3)
    logical, intent(in) :: apply
    real(wp), intent(out) :: sums(4), wsoil
    integer :: i, j, k, nd
    real(wp) :: ms, g, n(3), vs(3), dv(3), ca
    logical :: fix(3)
    nd = self%nd
    sums = 0.0_wp
    wsoil = 0.0_wp
    associate (node => self%phase(solid_phase)%node, nvel => self%phase(solid_phase)%nvel, &
               rn => self%rnode, olo => self%dec%olo, ohi => self%dec%ohi, b => self%bodies)
      do k = olo(3), ohi(3)
        do j = olo(2), ohi(2)
          do i = olo(1), ohi(1)
            if (rn(1, i, j, k) <= 0.0_wp) cycle
            ms = node(1, i, j, k)
            if (ms <= 0.0_wp) cycle
            ! the normal of the soil's surface, out of the body (the body's own where the
            ! soil's mass has no gradient): a box's normals at its corners, halfway round
            ! them, would push the soil ahead of a sliding body at its front corner
            n = 0.0_wp
            g = norm2(b%snode(2:1 + nd, i, j, k))
            if (g > 0.0_wp) then
              n(1:nd) = -b%snode(2:1 + nd, i, j, k)/g
            else if (norm2(rn(2:1 + nd, i, j, k)) > 0.0_wp) then
              n(1:nd) = rn(2:1 + nd, i, j, k)/norm2(rn(2:1 + nd, i, j, k))
            end if
            g = norm2(rn(2:1 + nd, i, j, k))
            ! the adhesion's impulse on the node's share of the surface, |grad m_b| / rho_b
            ca = b%adhesion*g/b%density*dt
            vs = 0.0_wp
            vs(1:nd) = nvel(nd + 1:2*nd, i, j, k)
            call contact_node(nd, ms, vb, n, b%mu, ca, vs)
            fix = self%bnd%faces%walls%constrained([i, j, k])
            where (fix) vs = 0.0_wp
            dv = 0.0_wp
            dv(1:nd) = vs(1:nd) - nvel(nd + 1:2*nd, i, j, k)
            sums(1:3) = sums(1:3) + ms*dv
            sums(4) = sums(4) + ms
            if (apply) then
              wsoil = wsoil + 0.5_wp*ms*dot_product(dv(1:nd), nvel(1:nd, i, j, k) + vs(1:nd))
              nvel(nd + 1:2*nd, i, j, k) = vs(1:nd)
            end if
          end do
        end do
      end do
    end associate
    call MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
  end subroutine contact_pass

  !> MUSL: the remapped velocities of the soil at the contact nodes corrected against the
  !> body's velocity of the step as in contact_nodes, the adhesion's impulse over the step dt
  !> (no force or work: the remap moves no momentum between the soil and the body).
  subroutine contact_remap(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    real(wp) :: sums(4), unused
    if (.not. self%bodies%on) return
    call contact_pass(self, dt, self%bodies%vstep, .true., sums, unused)
  end subroutine contact_remap

  !> After g2p: the body's points get their masses back and move by dt times the body's
  !> velocity of the step, from where they were, at that velocity.
  subroutine contact_move(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    integer :: p
    if (.not. self%bodies%on) return
    associate (b => self%bodies, ps => self%phase(solid_phase)%pts)
      do p = 1, ps%n
        if (ps%mat(p) /= b%mat) cycle
        ps%mass(p) = b%msave(p)
        ps%x(1:self%nd, p) = b%xsave(1:self%nd, p) + dt*b%vstep(1:self%nd)
        ps%v(1:self%nd, p) = b%vstep(1:self%nd)
      end do
    end associate
  end subroutine contact_move

end module dpmpm_contact
