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
  use dpmpm_rigid, only: body_p2g, contact_node, body_velocities, motion_factor
  use mpi_f08, only: MPI_Allreduce, MPI_Allgather, MPI_Allgatherv, MPI_Comm_size, MPI_IN_PLACE, MPI_INTEGER, &
                     MPI_DOUBLE_PRECISION, MPI_SUM
  implicit none
  private
  public :: contact_hide, contact_nodes, contact_remap, contact_move, record_body, write_body

  !> passes of the free body's contact solve at most, and its relative tolerance
  integer, parameter :: max_passes = 60
  real(wp), parameter :: pass_tol = 1.0e-12_wp
  !> values of a contact node in the free body's solve: m_s, v_s*(3), n(3), a A dt, held(3)
  integer, parameter :: nrow_vals = 11

contains

  !> The scene's rigid body with a frictional contact, looked for once (self%bodies%on
  !> stays .false. without one), and its mass from its points.
  subroutine contact_setup(self)
    class(state_t), intent(inout) :: self
    integer :: m
    self%bodies%known = .true.
    self%bodies%t0 = self%time
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
  !> or for a free body its velocity with gravity's and the load's change (the load at the
  !> step's middle, its time table's factor on body_load; the contact's
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
        b%lstep = motion_factor(self%mats(b%mat), self%time + 0.5_wp*dt)*b%load
        b%vstep = b%v + dt*(gravity + b%lstep/b%mass)
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
    real(wp), allocatable :: rows(:, :)
    integer :: pass
    associate (b => self%bodies)
      vstar = b%vstep
      v = vstar
      b%iterations = 0
      if (b%free) then
        ! the contact nodes of every rank on every rank, so that the passes need no
        ! messages (a body's surface has few nodes)
        call contact_pass(self, dt, v, .false., sums, wsoil, rows)
        call gather_rows(self, rows)
        sums = row_sums(self%nd, rows, v, b%mu)
        tol = pass_tol*(norm2(vstar) + dt*norm2(gravity) + tiny(1.0_wp))
        do pass = 1, max_passes
          b%iterations = pass
          vn = (b%mass*vstar - sums(1:3) + sums(4)*v)/(b%mass + sums(4))
          if (norm2(vn - v) <= tol) exit
          v = vn
          sums = row_sums(self%nd, rows, v, b%mu)
        end do
        v = vn
      end if
      ! the pass that corrects the soil against the body's velocity v
      call contact_pass(self, dt, v, .true., sums, wsoil)
      self%drive_impulse = self%drive_impulse + sums(1:3)
      b%impulse = b%impulse - sums(1:3)
      b%force = -sums(1:3)/dt
      self%ext_work = self%ext_work + wsoil
      if (b%free) then
        b%vstep = vstar - sums(1:3)/b%mass
        vmean = 0.5_wp*(b%v + b%vstep)
        wbody = -dot_product(sums(1:3), vmean)
        self%ext_work = self%ext_work + wbody + dt*dot_product(b%mass*gravity + b%lstep, vmean)
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
  !> With rows, this rank's contact nodes listed instead (row_sums reads them), no sums.
  subroutine contact_pass(self, dt, vb, apply, sums, wsoil, rows)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt, vb(3)
    logical, intent(in) :: apply
    real(wp), intent(out) :: sums(4), wsoil
    real(wp), allocatable, intent(out), optional :: rows(:, :)
    integer :: i, j, k, nd, nrow
    real(wp) :: ms, g, gs, n(3), ns(3), vs(3), dv(3), ca
    logical :: fix(3)
    nd = self%nd
    sums = 0.0_wp
    wsoil = 0.0_wp
    nrow = 0
    if (present(rows)) allocate (rows(nrow_vals, 16))
    associate (node => self%phase(solid_phase)%node, nvel => self%phase(solid_phase)%nvel, &
               rn => self%rnode, olo => self%dec%olo, ohi => self%dec%ohi, b => self%bodies)
      do k = olo(3), ohi(3)
        do j = olo(2), ohi(2)
          do i = olo(1), ohi(1)
            if (rn(1, i, j, k) <= 0.0_wp) cycle
            ms = node(1, i, j, k)
            if (ms <= 0.0_wp) cycle
            ! the normal of the soil's surface, out of the body, where it points away from
            ! the body as the body's own does (a box's normals at its corners, halfway round
            ! them, would push the soil ahead of a sliding body at its front corner); the
            ! body's elsewhere (a node within the soil, whose mass gradient says little)
            n = 0.0_wp
            g = norm2(rn(2:1 + nd, i, j, k))
            if (g > 0.0_wp) n(1:nd) = rn(2:1 + nd, i, j, k)/g
            gs = norm2(b%snode(2:1 + nd, i, j, k))
            if (gs > 0.0_wp) then
              ns = 0.0_wp
              ns(1:nd) = -b%snode(2:1 + nd, i, j, k)/gs
              if (g <= 0.0_wp .or. dot_product(ns, n) > 0.0_wp) n = ns
            end if
            ! the adhesion's impulse on the node's share of the surface, |grad m_b| / rho_b
            ca = b%adhesion*g/b%density*dt
            vs = 0.0_wp
            vs(1:nd) = nvel(nd + 1:2*nd, i, j, k)
            fix = self%bnd%faces%walls%constrained([i, j, k])
            if (present(rows)) then
              nrow = nrow + 1
              if (nrow > size(rows, 2)) call grow(rows)
              rows(:, nrow) = [ms, vs, n, ca, merge(1.0_wp, 0.0_wp, fix)]
              cycle
            end if
            call contact_node(nd, ms, vb, n, b%mu, ca, vs)
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
    if (present(rows)) then
      rows = rows(:, 1:nrow)
      return
    end if
    call MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
  end subroutine contact_pass

  !> rows with twice the columns, the first kept.
  subroutine grow(rows)
    real(wp), allocatable, intent(inout) :: rows(:, :)
    real(wp), allocatable :: more(:, :)
    allocate (more(size(rows, 1), 2*size(rows, 2)))
    more(:, 1:size(rows, 2)) = rows
    call move_alloc(more, rows)
  end subroutine grow

  !> The rows of every rank on every rank, in the order of the ranks.
  subroutine gather_rows(self, rows)
    class(state_t), intent(in) :: self
    real(wp), allocatable, intent(inout) :: rows(:, :)
    real(wp), allocatable :: all(:, :)
    integer, allocatable :: counts(:), displs(:)
    integer :: nranks, r
    call MPI_Comm_size(self%dec%comm, nranks)
    allocate (counts(nranks), displs(nranks))
    call MPI_Allgather(size(rows), 1, MPI_INTEGER, counts, 1, MPI_INTEGER, self%dec%comm)
    displs(1) = 0
    do r = 2, nranks
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    allocate (all(nrow_vals, sum(counts)/nrow_vals))
    call MPI_Allgatherv(rows, size(rows), MPI_DOUBLE_PRECISION, all, counts, displs, &
                        MPI_DOUBLE_PRECISION, self%dec%comm)
    call move_alloc(all, rows)
  end subroutine gather_rows

  !> contact_pass's sums over the listed contact nodes (contact_pass's rows, gathered)
  !> against the body's velocity vb, without changing them.
  pure function row_sums(nd, rows, vb, mu) result(sums)
    integer, intent(in) :: nd
    real(wp), intent(in) :: rows(:, :), vb(3), mu
    real(wp) :: sums(4)
    real(wp) :: vs(3)
    integer :: r
    sums = 0.0_wp
    do r = 1, size(rows, 2)
      vs = rows(2:4, r)
      call contact_node(nd, rows(1, r), vb, rows(5:7, r), mu, rows(8, r), vs)
      where (rows(9:11, r) > 0.5_wp) vs = 0.0_wp
      sums(1:3) = sums(1:3) + rows(1, r)*(vs - rows(2:4, r))
      sums(4) = sums(4) + rows(1, r)
    end do
  end function row_sums

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

  !> A record of the body (collective; at each diagnostics record, after the step): the
  !> time, the position of its mass centre, its velocity and the mean force of the contact
  !> on it since the record before (impulse over time; 0 at the first).
  subroutine record_body(self)
    class(state_t), intent(inout) :: self
    real(wp) :: s(3), f(3), rec(10)
    real(wp), allocatable :: more(:, :)
    integer :: p
    if (.not. self%bodies%on) return
    s = 0.0_wp
    associate (b => self%bodies, ps => self%phase(solid_phase)%pts)
      do p = 1, ps%n
        if (ps%mat(p) == b%mat) s(1:self%nd) = s(1:self%nd) + ps%mass(p)*ps%x(1:self%nd, p)
      end do
      call MPI_Allreduce(MPI_IN_PLACE, s, 3, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
      f = 0.0_wp
      if (self%time > b%t0) f = b%impulse/(self%time - b%t0)
      rec = [self%time, s/b%mass, b%v, f]
      if (.not. allocated(b%hist)) allocate (b%hist(10, 64))
      if (b%nhist == size(b%hist, 2)) then
        allocate (more(10, 2*b%nhist))
        more(:, 1:b%nhist) = b%hist(:, 1:b%nhist)
        call move_alloc(more, b%hist)
      end if
      b%nhist = b%nhist + 1
      b%hist(:, b%nhist) = rec
      b%impulse = 0.0_wp
      b%t0 = self%time
    end associate
  end subroutine record_body

  !> The body's records in /verification: body_time, body_x|y|z (the mass centre),
  !> body_vx|vy|vz, body_force_x|y|z (the contact's mean force on the body), per axis of
  !> the grid.
  subroutine write_body(self)
    class(state_t), intent(inout) :: self
    character(len=1), parameter :: ax(3) = ['x', 'y', 'z']
    integer :: d
    if (.not. self%bodies%on .or. self%bodies%nhist == 0) return
    associate (h => self%bodies%hist, n => self%bodies%nhist)
      call self%out%write_verification('body_time', h(1, 1:n))
      do d = 1, self%nd
        call self%out%write_verification('body_'//ax(d), h(1 + d, 1:n))
        call self%out%write_verification('body_v'//ax(d), h(4 + d, 1:n))
        call self%out%write_verification('body_force_'//ax(d), h(7 + d, 1:n))
      end do
    end associate
  end subroutine write_body

end module dpmpm_contact
