!> The pieces the stages of a step (dpmpm_step) share: the node box and the stencils of
!> the step, the cell-smoothed force fields put in place and back, the free-surface
!> test, the rigid bodies' node sums and drive, the surface loads' forces and work,
!> the interphase force, the wall test of the points, and the gravity and damping of
!> the step's time.
module dpmpm_step_parts
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: node_slots_t, node_slots
  use dpmpm_error, only: fatal
  use dpmpm_config, only: bc_free, fbc_drained
  use dpmpm_mls_velocity, only: velocity_fold_signs
  use dpmpm_mirror, only: mirror_sign
  use dpmpm_particles, only: particle_set_t
  use dpmpm_phase, only: phase_t, solid_phase, fluid_phase
  use dpmpm_state, only: state_t
  use dpmpm_transfer, only: reaches_thin_node, interphase_p2g
  use dpmpm_remap, only: remap_locks
  use dpmpm_outflow, only: left_through_opening, carried_energy
  use dpmpm_cell_smoothing, only: smoothed_mean_stress, cell_mean
  use dpmpm_rigid, only: rigid_p2g, drive_rigid_nodes, body_velocities
  use dpmpm_contact, only: contact_nodes
  use dpmpm_surface_loads, only: surface_forces
  use mpi_f08, only: MPI_PROC_NULL, operator(/=)
  implicit none
  private
  public :: step_box, compute_stencils, swap_force_fields, restore_force_fields, free_surface_points
  public :: rigid_node_sums, drive_rigid, add_surface_forces, surface_work, add_interphase_force
  public :: check_inside, velocity_signs, gravity_now, damping_now

contains

  !> The fields of the forces under cell smoothing put in place of the points' own, which
  !> the held arrays keep until they are moved back: with scell (volumetric_smoothing; the
  !> pair of cell and material of each solid point) the skeleton's stresses with the mean
  !> stress of their pair (smoothed_mean_stress), with fcell
  !> (pressure_smoothing) the pore pressures as each cell's mean. Unallocated cells leave
  !> their set as it is and its held array unallocated.
  subroutine swap_force_fields(self, scell, fcell, sheld, pheld)
    class(state_t), intent(inout) :: self
    integer, allocatable, intent(in) :: scell(:), fcell(:)
    real(wp), allocatable, intent(out) :: sheld(:, :), pheld(:)
    real(wp), allocatable :: sbar(:, :), pbar(:)
    integer :: ncell
    ncell = product(self%dec%chi - self%dec%clo + 1)
    if (allocated(scell)) then
      associate (s => self%phase(solid_phase)%pts)
        allocate (sbar(size(s%stress, 1), size(s%stress, 2)))
        call smoothed_mean_stress(self%nd, s%n, ncell*size(self%mats), scell, s%vol, s%stress, sbar)
        call move_alloc(s%stress, sheld)
        call move_alloc(sbar, s%stress)
      end associate
    end if
    if (allocated(fcell)) then
      associate (f => self%phase(fluid_phase)%pts)
        allocate (pbar(size(f%pressure)))
        call cell_mean(f%n, ncell, fcell, f%vol, f%pressure, pbar)
        call move_alloc(f%pressure, pheld)
        call move_alloc(pbar, f%pressure)
      end associate
    end if
  end subroutine swap_force_fields

  !> The points' own fields of the forces back in place after the forces of the step
  !> (swap_force_fields): the skeleton's stresses from sheld, the pore pressures from
  !> pheld, with the cells' mean pressures kept in pforce for the interphase force.
  !> Unallocated held arrays leave their set as it is (and pforce unallocated).
  subroutine restore_force_fields(self, sheld, pheld, pforce)
    class(state_t), intent(inout) :: self
    real(wp), allocatable, intent(inout) :: sheld(:, :), pheld(:)
    real(wp), allocatable, intent(inout) :: pforce(:)
    if (allocated(sheld)) call move_alloc(sheld, self%phase(solid_phase)%pts%stress)
    if (allocated(pheld)) then
      call move_alloc(self%phase(fluid_phase)%pts%pressure, pforce)
      call move_alloc(pheld, self%phase(fluid_phase)%pts%pressure)
    end if
  end subroutine restore_force_fields

  !> Tractions on the body's surface inside the grid (dpmpm_surface_loads): their nodal
  !> forces of this step, kept in sforce for their work, join the solid's nodal forces.
  subroutine add_surface_forces(self)
    class(state_t), intent(inout) :: self
    integer :: nd
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    associate (s => self%phase(solid_phase)%node, olo => self%dec%olo, ohi => self%dec%ohi)
      call surface_forces(self%bnd%faces, self%time, nd, self%dec%alo, olo, ohi, s, self%dec%comm, self%sforce)
      s(sl%force_lo:sl%force_hi, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) = &
        s(sl%force_lo:sl%force_hi, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) + &
        self%sforce(1:nd, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3))
    end associate
  end subroutine add_surface_forces

  !> The work of the surface loads in this step, f . (v_old + v_new) dt / 2 at their
  !> nodes, added to the external work.
  subroutine surface_work(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    integer :: i, j, k, nd
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    associate (v => self%phase(solid_phase)%nvel, olo => self%dec%olo, ohi => self%dec%ohi)
      do k = olo(3), ohi(3)
        do j = olo(2), ohi(2)
          do i = olo(1), ohi(1)
            if (all(self%sforce(1:nd, i, j, k) == 0.0_wp)) cycle
            self%ext_work = self%ext_work + 0.5_wp*dt*dot_product(self%sforce(1:nd, i, j, k), &
                                                                  v(sl%old_lo:sl%old_hi, i, j, k) + &
                                                                  v(sl%new_lo:sl%new_hi, i, j, k))
          end do
        end do
      end do
    end associate
  end subroutine surface_work

  !> Rigid bodies (dpmpm_rigid, doc/theory.md 6.8): their share of the node fields,
  !> folded at mirror walls and summed over the ranks, then every owned node they
  !> reach moves with them; the force and work that takes go to the drive's impulse and
  !> the external work.
  subroutine drive_rigid(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    real(wp) :: force(3)
    ! (a frictional contact instead, doc/theory.md 6.8.1)
    if (self%bodies%on) then
      call contact_nodes(self, dt, gravity_now(self))
      return
    end if
    call rigid_node_sums(self, dt)
    associate (s => self%phase(solid_phase))
      force = 0.0_wp
      call drive_rigid_nodes(self%nd, self%dec%alo, self%dec%olo, self%dec%ohi, s%node, self%rnode, &
                             self%bnd%faces%walls, dt, s%nvel, force, self%ext_work)
      self%drive_impulse = self%drive_impulse + dt*force
    end associate
  end subroutine drive_rigid

  !> Fluid points at the free surface of the pore fluid (doc/theory.md 4.6): those whose
  !> grid functions reach a node inside the grid that the fluid fills to less than
  !> free_surface_fraction of a cell, sum_p N_Ip V_p < f h^d. There a node carries a sliver
  !> of a point's mass but the full gradient of its grid function, which the stiff pore
  !> fluid can accelerate hard; the surface is drained to the air (p = 0). A node
  !> on the surface of a full body holds half a cell and is not thin; nodes on the grid's
  !> faces follow the face conditions.
  subroutine free_surface_points(self, fvol, fsurf)
    class(state_t), intent(inout) :: self
    !> sum_p N_Ip V_p of this rank's fluid points (fluid_p2g)
    real(wp), contiguous, intent(inout) :: fvol(:, :, :, :)
    logical, allocatable, intent(out) :: fsurf(:)
    associate (f => self%phase(fluid_phase), alo => self%dec%alo)
      allocate (fsurf(f%pts%n))
      call self%mirror%fold(fvol, 1, f%bc)
      call self%dec%halo_sum(fvol)
      call self%dec%halo_copy(fvol)
      call reaches_thin_node(self%nd, f%st%nw, f%pts%n, f%st%i0, f%st%sw, alo, fvol, self%grid%ncells, &
                             self%cfg%free_surface_fraction*product(self%grid%h(1:self%nd)), fsurf)
    end associate
  end subroutine free_surface_points

  !> The rigid bodies' share of the node fields (rigid_p2g) in self%rnode, folded at
  !> mirror walls and summed over the ranks; the bodies move at their velocity in the middle
  !> of the step (of length dt).
  subroutine rigid_node_sums(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    associate (s => self%phase(solid_phase))
      self%rnode = 0.0_wp
      call rigid_p2g(self%nd, s%st%nw, s%pts%n, s%st%i0, s%st%sw, s%pts%mass, s%pts%mat, self%mats, &
                     body_velocities(self%mats, self%time + 0.5_wp*dt), self%dec%alo, self%rnode)
      call self%mirror%fold(self%rnode, 1, self%bnd%kind(:, 1))
      call self%dec%halo_sum(self%rnode)
    end associate
  end subroutine rigid_node_sums

  !> The node box of this step (wlo..whi): the stencils of every phase's points (a
  !> fluid point writes into the solid's fields too), widened by the ghost width for
  !> the images of mirror walls, to the block's end where that lies within a ghost
  !> width of a grid face (exterior nodes), and over the slabs next to a neighbour
  !> rank (halo sums add its points there); zlo..zhi merges it with the box of the
  !> step before, whose fields are cleared now. Node fields outside zlo..zhi stay zero,
  !> and loops over nodes may skip them. Gauss quadrature and MLS nodal velocities
  !> write beyond the point stencils and keep the whole block.
  subroutine step_box(self)
    class(state_t), intent(inout) :: self
    integer :: lo(3), hi(3), d, e, ip, n, p, gw(3)
    associate (alo => self%dec%alo, ahi => self%dec%ahi)
      if (self%plan%gauss .or. self%plan%velocity_mls) then
        self%wlo = alo; self%whi = ahi
        self%zlo = alo; self%zhi = ahi
        self%box_known = .false.
        return
      end if
      gw = self%dec%gw
      lo = huge(1); hi = -huge(1)
      do ip = 1, self%nph
        associate (st => self%phase(ip)%st)
          n = self%phase(ip)%pts%n
          do p = 1, n
            lo = min(lo, st%i0(:, p))
            hi = max(hi, st%i0(:, p) + st%nw - 1)
          end do
        end associate
      end do
      do d = 1, 3
        if (d > self%nd) then
          lo(d) = alo(d); hi(d) = ahi(d)
          cycle
        end if
        lo(d) = lo(d) - gw(d); hi(d) = hi(d) + gw(d)
        if (lo(d) <= gw(d)) lo(d) = alo(d)
        if (hi(d) >= self%grid%ncells(d) - gw(d)) hi(d) = ahi(d)
      end do
      do d = 1, self%nd
        if (self%dec%nbr_lo(d) /= MPI_PROC_NULL) then
          lo(d) = alo(d); hi(d) = max(hi(d), self%dec%olo(d) + gw(d))
        end if
        if (self%dec%nbr_hi(d) /= MPI_PROC_NULL) then
          hi(d) = ahi(d); lo(d) = min(lo(d), self%dec%ohi(d) - gw(d))
        end if
        if (self%dec%nbr_lo(d) /= MPI_PROC_NULL .or. self%dec%nbr_hi(d) /= MPI_PROC_NULL) then
          ! a neighbour's slab spans the block along the other axes
          do e = 1, self%nd
            if (e /= d) then
              lo(e) = alo(e); hi(e) = ahi(e)
            end if
          end do
        end if
      end do
      lo = max(lo, alo); hi = min(hi, ahi)
      if (self%box_known) then
        self%zlo = min(lo, self%wlo); self%zhi = max(hi, self%whi)
      else
        self%zlo = alo; self%zhi = ahi
      end if
      self%wlo = lo; self%whi = hi
      self%box_known = .true.
    end associate
  end subroutine step_box

  !> Kernel weights and gradients of every point of phase tr, evaluated once per
  !> step, with its per-point work arrays sized to the set's capacity (and the body
  !> acceleration of the manufactured solution, when the scene has one).
  subroutine compute_stencils(self, tr)
    class(state_t), intent(inout) :: self
    type(phase_t), intent(inout) :: tr
    integer :: n, cap
    n = tr%pts%n
    if (tr%st%nd == 0) call tr%st%init(self%nd, self%kernel)
    if (size(tr%st%i0, 2) < n) then
      if (allocated(tr%vgrad)) deallocate (tr%vgrad)
      if (allocated(tr%divf)) deallocate (tr%divf, tr%divs)
      if (allocated(tr%xold)) deallocate (tr%xold, tr%volold, tr%vt)
      if (allocated(tr%lockp)) deallocate (tr%lockp)
    end if
    call tr%st%build(n, tr%pts%cap, tr%pts%x, self%grid%origin, self%grid%h)
    cap = size(tr%st%i0, 2)
    ! (The fluid points keep only the two divergences of the pore-pressure update.)
    if (tr%pts%has_pressure) then
      if (.not. allocated(tr%divf)) allocate (tr%divf(cap), tr%divs(cap))
    else if (.not. allocated(tr%vgrad)) then
      allocate (tr%vgrad(9, cap))
    end if
    if (self%plan%gauss .and. .not. allocated(tr%xold)) &
      allocate (tr%xold(self%nd, cap), tr%volold(cap), tr%vt(cap))
    if (remap_locks(self) .and. .not. allocated(tr%lockp)) allocate (tr%lockp(self%nd, cap))
    if (allocated(tr%bacc)) then
      if (size(tr%bacc, 2) < n) deallocate (tr%bacc)
    end if
    if (self%cfg%benchmark == 'mms' .and. .not. allocated(tr%bacc)) allocate (tr%bacc(self%nd, cap))
  end subroutine compute_stencils

  !> Points that crossed a fixed or roller face (walls are impenetrable) are put
  !> back just inside it and counted; wide kernels interpolate a small normal
  !> velocity next to a wall. Fluid points (outflow) that crossed a face drained for
  !> the pore fluid have left the model through it: they are removed and counted with
  !> their mass; so are points that crossed a face through its opening (dpmpm_outflow),
  !> whose energy leaves the balance as negative external work. A point beyond a free
  !> face stops the run with its id.
  subroutine check_inside(self, ps, outflow)
    class(state_t), intent(inout) :: self
    type(particle_set_t), intent(inout) :: ps
    logical, intent(in) :: outflow
    integer :: p, d, side, face
    real(wp) :: wall(2), eps
    logical, allocatable :: gone(:)
    character(len=256) :: msg
    ! Nothing to do when every point is inside (the common case; one pass in dpmpm_grid).
    if (self%grid%all_inside(ps%x, ps%n)) return
    allocate (gone(ps%n))
    gone = .false.
    do p = 1, ps%n
      if (self%grid%inside(ps%x(:, p))) cycle
      if (any(self%bnd%faces%walls%opened)) then
        if (left_through_opening(self%bnd%faces%walls, self%grid, ps%x(:, p))) then
          gone(p) = .true.
          self%noutflow = self%noutflow + 1
          self%outflow_mass = self%outflow_mass + ps%mass(p)
          cycle
        end if
      end if
      if (outflow) then
        do d = 1, self%nd
          wall = [self%grid%origin(d), self%grid%origin(d) + self%grid%ncells(d)*self%grid%h(d)]
          do side = 1, 2
            face = 2*(d - 1) + side
            if (self%bnd%fbc(face) /= fbc_drained) cycle
            if ((side == 1 .and. ps%x(d, p) < wall(1)) .or. (side == 2 .and. ps%x(d, p) >= wall(2))) &
              gone(p) = .true.
          end do
        end do
        if (gone(p)) then
          self%noutflow = self%noutflow + 1
          self%outflow_mass = self%outflow_mass + ps%mass(p)
          cycle
        end if
      end if
      do d = 1, self%nd
        wall = [self%grid%origin(d), self%grid%origin(d) + self%grid%ncells(d)*self%grid%h(d)]
        eps = 1.0e-9_wp*self%grid%h(d)
        do side = 1, 2
          if (self%bnd%kind(2*(d - 1) + side, 1) == bc_free) cycle
          if (side == 1 .and. ps%x(d, p) < wall(1)) then
            ps%x(d, p) = wall(1) + eps
            self%nwall = self%nwall + 1
          else if (side == 2 .and. ps%x(d, p) >= wall(2)) then
            ps%x(d, p) = wall(2) - eps
            self%nwall = self%nwall + 1
          end if
        end do
      end do
      if (.not. self%grid%inside(ps%x(:, p))) then
        write (msg, '(a,a,a,i0,a,3es12.4)') trim(ps%name), ' ', 'point ', ps%id(p), ' left the grid at x =', &
          ps%x(:, p)
        call fatal(trim(msg)//'; enlarge the grid or add a boundary condition', 'step')
      end if
    end do
    if (any(gone) .and. any(self%bnd%faces%walls%opened)) &
      self%ext_work = self%ext_work - carried_energy(self%mats, ps, gone)
    if (any(gone)) call ps%remove(gone)
  end subroutine check_inside

  !> Per-face signs of the nodal velocity moment sums vacc (count, moments, right-hand
  !> sides) under the face conditions bc of their phase.
  function velocity_signs(self, vacc, bc) result(sg)
    class(state_t), intent(in) :: self
    real(wp), intent(in) :: vacc(:, :, :, :)
    integer, intent(in) :: bc(6)
    real(wp) :: sg(size(vacc, 1), 6)
    real(wp) :: vsign(3)
    integer :: f, c, d
    sg = 1.0_wp
    do f = 1, 2*self%nd
      d = (f + 1)/2
      do c = 1, self%nd
        vsign(c) = mirror_sign(bc(f), d, c)
      end do
      call velocity_fold_signs(self%nd, self%plan%velocity_basis, d, vsign(1:self%nd), sg(:, f))
    end do
  end function velocity_signs

  !> The interphase force p grad n_f (eq. 2) at the nodes: added to the fluid's
  !> internal force and taken from the solid's (interphase_p2g), with the nodal
  !> porosity of this step and the fluid points' porosity of the p2g (fluid_p2g), so
  !> that the two together are the transpose of the mixture flux.
  subroutine add_interphase_force(self, pf)
    class(state_t), intent(inout) :: self
    !> the fluid points' pressures of the pressure forces (with the cell smoothing, the
    !> cells' means, as the other pressure forces of the step took them)
    real(wp), intent(in) :: pf(:)
    real(wp), allocatable :: ff(:, :, :, :), fs(:, :, :, :)
    integer :: nd
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    allocate (ff(nd, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                 self%dec%alo(3):self%dec%ahi(3)))
    ff = 0.0_wp
    associate (f => self%phase(fluid_phase))
      call interphase_p2g(nd, f%st%nw, f%pts%n, f%st%i0, f%st%sw, f%st%sdw, f%pts%vol, pf, &
                          f%pts%porosity, self%dec%alo, self%cpl%nporo, ff)
    end associate
    fs = -ff
    call self%mirror%fold(ff, 0, self%phase(2)%bc)
    call self%mirror%fold(fs, 0, self%phase(1)%bc)
    call self%dec%halo_sum(ff)
    call self%dec%halo_sum(fs)
    self%phase(2)%node(sl%force_lo:sl%force_hi, :, :, :) = self%phase(2)%node(sl%force_lo:sl%force_hi, :, :, :) + ff
    self%phase(1)%node(sl%force_lo:sl%force_hi, :, :, :) = self%phase(1)%node(sl%force_lo:sl%force_hi, :, :, :) + fs
  end subroutine add_interphase_force

  !> Gravity at the start of the step: ramped linearly over the first half of the
  !> equilibrium phase (&run equilibrium_time), full afterwards.
  function gravity_now(self) result(g)
    class(state_t), intent(in) :: self
    real(wp) :: g(3)
    g = self%cfg%gravity
    if (self%cfg%equilibrium_time > 0.0_wp) &
      g = g*min(1.0_wp, self%time/(0.5_wp*self%cfg%equilibrium_time))
  end function gravity_now

  !> The local damping coefficient of the step: equilibrium_damping during the
  !> equilibrium phase, 0 afterwards.
  real(wp) function damping_now(self) result(a)
    class(state_t), intent(in) :: self
    a = 0.0_wp
    if (self%time < self%cfg%equilibrium_time) a = self%cfg%equilibrium_damping
  end function damping_now

end module dpmpm_step_parts
