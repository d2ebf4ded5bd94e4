!> One explicit time step over the list of phases (doc/architecture.md, "One step";
!> doc/theory.md 4.1): stencils, p2g of every phase (with
!> the coupling terms when there are two), the reverse halo exchange, the nodal
!> update (MLS nodal velocities where chosen, drag where the phases meet, every
!> boundary condition), the forward halo exchange, g2p with the MUSL remap or USL,
!> the stress and pore-pressure updates, and migration. A one-phase scene is the
!> same step with one phase and no coupling.
module dpmpm_step
  use dpmpm_kinds, only: wp, i8
  use dpmpm_error, only: fatal
  use dpmpm_timer, only: t_stencil, t_p2g, t_halo, t_nodal, t_g2p, t_stress, t_migrate
  use dpmpm_config, only: bc_free, fbc_drained
  use dpmpm_mls_velocity, only: velocity_accumulate, velocity_solve, velocity_fold_signs
  use dpmpm_materials, only: stress_update, model_fluid
  use dpmpm_axisym, only: hoop_force_p2g, hoop_rate, pressure_hoop_p2g, hoop_divergences, fluid_area_p2g
  use dpmpm_benchmarks, only: benchmark_body_force
  use dpmpm_migrate, only: migrate
  use dpmpm_energy, only: state_valid
  use dpmpm_cell_order, only: sort_by_cell
  use dpmpm_mirror, only: mirror_sign
  use dpmpm_particles, only: particle_set_t
  use dpmpm_phase, only: phase_t, solid_phase, fluid_phase
  use dpmpm_state, only: state_t
  use dpmpm_transfer, only: p2g, g2p, point_divergences, interp_two_values, fluid_p2g, reaches_thin_node, body_force_work, &
                            interphase_p2g, solid_porosity_p2g, porous_p2g, mixture_flux
  use dpmpm_nodal_update, only: nodal_update, nodal_update_coupled
  use dpmpm_damping, only: viscous_forces, rayleigh_mass_args
  use dpmpm_drag, only: nodal_drag_limit
  use dpmpm_remap, only: tied_save_t, join_tied, split_tied, musl_remap, remap_locks
  use dpmpm_pore_pressure, only: nodal_porosity, skeleton_porosity, skeleton_kinv, point_cells, &
                                 fluid_pressure_step, fluid_state
  use dpmpm_inflow, only: refill_inflow
  use dpmpm_outflow, only: left_through_opening, carried_energy
  use dpmpm_cell_smoothing, only: smooth_volumetric_rate, smoothed_mean_stress, cell_mean
  use dpmpm_quadrature, only: gauss_p2g, gauss_point_gradients, gauss_pressure_forces, &
                              gauss_point_divergences, gauss_mixture_divergence, gauss_gravity, gauss_gravity_work
  use dpmpm_gauss_fields, only: thin_node_forces
  use dpmpm_time_step, only: report_governing
  use dpmpm_tied_sides, only: tie_sums
  use dpmpm_rigid, only: rigid_p2g, drive_rigid_nodes, hold_rigid_points, body_velocities
  use dpmpm_contact, only: contact_hide, contact_nodes, contact_move
  use dpmpm_surface_loads, only: surface_forces
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_MIN, MPI_PROC_NULL, operator(/=)
  implicit none
  private
  public :: advance

contains

  !> One explicit step of length dt over the phases of self (1: solid; 2: fluid,
  !> coupled to the solid by drag and pore pressure). dt may shrink to the
  !> explicit-drag limit of this step's nodes.
  subroutine advance(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(inout) :: dt
    integer :: m, ip, nlost, ns, nf, nd, blo(3), bhi(3)
    integer, allocatable :: fcell(:), scell(:)
    logical, allocatable :: fsurf(:)
    logical :: coupled, surface, fluid_mom
    real(wp) :: wplastic, rforce(3)
    real(wp), allocatable :: fvol(:, :, :, :), sheld(:, :), pheld(:), pforce(:)
    real(wp), allocatable :: volb(:), nval(:), nkinv(:), gnrel(:), skinv(:)
    real(wp), allocatable :: gpf(:, :, :, :), gps(:, :, :, :), gms(:, :, :, :), gmf(:, :, :, :)
    type(tied_save_t) :: tsave
    logical :: ggrav
    coupled = self%nph == 2
    ! the free surface of the pore fluid is looked for (free_surface_points)
    surface = coupled .and. self%cfg%free_surface_fraction > 0.0_wp .and. .not. self%plan%gauss
    nd = self%nd
    ! gravity by the Gauss quadrature of the forces (gauss_gravity)
    ggrav = self%plan%gauss .and. any(self%cfg%gravity /= 0.0_wp)
    ns = self%phase(solid_phase)%pts%n
    nf = 0
    if (coupled) nf = self%phase(fluid_phase)%pts%n

    ! 1. Stencils of every point, once per step.
    call self%timers%tic(t_stencil)
    do ip = 1, self%nph
      call compute_stencils(self, self%phase(ip))
    end do
    call step_box(self)
    ! the owned nodes where node fields may be nonzero (loops of the nodal updates)
    blo = max(self%dec%olo, self%zlo)
    bhi = min(self%dec%ohi, self%zhi)
    ! The cell of each fluid point at the start of the step (points are in this rank's
    ! cells then), for the cell smoothing of the pore pressure.
    if (coupled .and. self%cfg%pressure_smoothing == 'cell') then
      allocate (fcell(nf))
      call point_cells(nd, nf, self%phase(fluid_phase)%pts%x, self%grid%origin, self%grid%h, &
                       self%dec%clo, self%dec%chi, fcell)
    end if
    ! and, for the cell smoothing of the volumetric strain rate, the pair of cell and
    ! material of each solid point (1..ncell*nmat; the same for the forces and the rates)
    if (self%cfg%volumetric_smoothing == 'cell') then
      allocate (scell(ns))
      call point_cells(nd, ns, self%phase(solid_phase)%pts%x, self%grid%origin, self%grid%h, &
                       self%dec%clo, self%dec%chi, scell)
      scell = self%phase(solid_phase)%pts%mat(1:ns) + size(self%mats)*(scell - 1)
    end if
    call self%timers%toc(t_stencil)

    ! 2. p2g of every phase; the solid's internal force by point quadrature unless
    ! Gauss quadrature gives it; the fluid's pore-pressure forces come with the coupling.
    call self%timers%tic(t_p2g)
    ! A rigid body with a frictional contact stays out of the soil's node fields up to g2p
    ! (dpmpm_contact).
    if (self%has_rigid) call contact_hide(self, dt, gravity_now(self))
    ! With cell smoothing the forces take each cell's mean stress of the skeleton
    ! (volumetric_smoothing) and mean pore pressure (pressure_smoothing): these stand in
    ! the points' place up to the end of the forces (doc/theory.md 4.5).
    call swap_force_fields(self, scell, fcell, sheld, pheld)
    ! (With a fluid, fluid_p2g sums the fluid's mass and momentum in its own pass, unless
    ! the fluid points carry body accelerations; the skeleton's porosity and 1/k at the
    ! nodes come with its p2g.)
    fluid_mom = coupled
    if (coupled) then
      fluid_mom = .not. allocated(self%phase(fluid_phase)%bacc)
      self%nporo = 0.0_wp
      self%ndrag = 0.0_wp
      associate (s => self%phase(solid_phase)%pts)
        allocate (skinv(ns))
        call skeleton_kinv(ns, self%mats, s%mat, s%porosity, s%vol, s%vol0, skinv)
      end associate
    end if
    do ip = 1, self%nph
      associate (ph => self%phase(ip), ps => self%phase(ip)%pts)
        ph%node(:, self%zlo(1):self%zhi(1), self%zlo(2):self%zhi(2), self%zlo(3):self%zhi(3)) = 0.0_wp
        if (ip == fluid_phase .and. fluid_mom) then
          continue
        else if (allocated(ph%bacc)) then
          call benchmark_body_force(self%cfg, self%mats, ps, self%time, ph%bacc)
          call p2g(nd, ph%st%nw, ps%n, ph%st%i0, ph%st%sw, ph%st%sdw, ps%mass, ps%v, ps%vol, ps%stress, &
                   ip == solid_phase .and. .not. self%plan%gauss, self%dec%alo, ph%node, ph%bacc)
          if (coupled .and. ip == solid_phase) &
            call solid_porosity_p2g(ph%st%nw, ns, ph%st%i0, ph%st%sw, ps%mass, ps%porosity, skinv, &
                                    self%dec%alo, self%nporo)
        else if (coupled .and. ip == solid_phase) then
          call porous_p2g(nd, ph%st%nw, ps%n, ph%st%i0, ph%st%sw, ph%st%sdw, ps%mass, ps%v, ps%vol, ps%stress, &
                          .not. self%plan%gauss, self%dec%alo, ph%node, ps%porosity, skinv, self%nporo)
        else
          call p2g(nd, ph%st%nw, ps%n, ph%st%i0, ph%st%sw, ph%st%sdw, ps%mass, ps%v, ps%vol, ps%stress, &
                   ip == solid_phase .and. .not. self%plan%gauss, self%dec%alo, ph%node)
        end if
      end associate
    end do
    if (coupled) then
      associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
        if (surface) then
          ! the fluid volume at the nodes for the free-surface test, summed in the same
          ! pass (unallocated, fvol is an absent argument)
          allocate (fvol(1, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                         self%dec%alo(3):self%dec%ahi(3)))
          fvol = 0.0_wp
        end if
        call fluid_p2g(nd, f%st%nw, nf, f%st%i0, f%st%sw, f%st%sdw, f%pts%mass, f%pts%v, f%pts%vol, &
                       f%pts%porosity, f%pts%pressure, f%pts%kinv, fluid_mom, &
                       (.not. self%plan%gauss), self%dec%alo, s%node, f%node, self%ndrag, fvol)
      end associate
    end if
    ! Gauss quadrature: the forces of the skeleton and the pore pressure, and with gravity
    ! the Gauss masses (gms, gmf); with the porosity-gradient terms the pressure's force
    ! gpf is shared at the nodes once the nodal porosity is known (gps: the solid's copy).
    if (self%plan%gauss) then
      call gauss_p2g(self, ggrav, gpf, gms, gmf)
      if (allocated(gpf)) gps = gpf
    end if
    ! Axisymmetry: the hoop stress's nodal force (dpmpm_axisym), from the stress of p2g;
    ! with pore water the pressure's on both phases (the pressures of fluid_p2g) and the
    ! fluid's r-z areas for the free-surface tests.
    if (self%cfg%axisymmetric) then
      associate (s => self%phase(solid_phase))
        call hoop_force_p2g(s%st%nw, s%pts%n, s%st%i0, s%st%sw, s%pts%x, self%grid%h(1), &
                            s%pts%vol, s%pts%stress, self%dec%alo, s%node)
      end associate
      if (coupled) then
        associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
          call pressure_hoop_p2g(f%st%nw, nf, f%st%i0, f%st%sw, f%pts%x, self%grid%h(1), f%pts%vol, &
                                 f%pts%porosity, f%pts%pressure, self%dec%alo, s%node, f%node)
          if (allocated(fvol)) call fluid_area_p2g(f%st%nw, nf, f%st%i0, f%st%sw, f%pts%x, self%grid%h(1), &
                                                   f%pts%vol, self%dec%alo, fvol)
        end associate
      end if
    end if
    if (allocated(sheld)) call move_alloc(sheld, self%phase(solid_phase)%pts%stress)
    if (allocated(pheld)) then
      ! (the cells' mean pressures kept for the interphase force)
      call move_alloc(self%phase(fluid_phase)%pts%pressure, pforce)
      call move_alloc(pheld, self%phase(fluid_phase)%pts%pressure)
    end if
    do ip = 1, self%nph
      call self%mirror%fold(self%phase(ip)%node, 1, self%phase(ip)%bc)
      if (self%plan%gauss) call self%mirror%fold(self%phase(ip)%nvol, 2, self%phase(ip)%bc)
    end do
    if (coupled) then
      call self%mirror%fold(self%nporo, 3, self%bnd%kind(:, 1))
      call self%mirror%fold(self%ndrag, 1, self%phase(fluid_phase)%bc)
    end if
    ! (each share folded with the conditions of the phase it goes to)
    if (allocated(gpf)) then
      call self%mirror%fold(gpf, 0, self%phase(fluid_phase)%bc)
      call self%mirror%fold(gps, 0, self%phase(solid_phase)%bc)
    end if
    if (allocated(gms)) call self%mirror%fold(gms, 1, self%phase(solid_phase)%bc)
    if (allocated(gmf)) call self%mirror%fold(gmf, 1, self%phase(fluid_phase)%bc)
    if (self%plan%velocity_mls) then
      do ip = 1, self%nph
        associate (ph => self%phase(ip), ps => self%phase(ip)%pts, pl => self%plan)
          ph%vacc = 0.0_wp
          call velocity_accumulate(nd, ps%n, ps%x, ps%mass, ps%v, self%grid%origin, self%grid%h, &
                                   pl%velocity_kernel, pl%velocity_radius, pl%velocity_radial, &
                                   pl%velocity_basis, self%dec%alo, ph%vacc)
          call self%mirror%fold_planes(ph%vacc, velocity_signs(self, ph%vacc, ph%bc), .true., ph%bc)
        end associate
      end do
    end if
    call self%timers%toc(t_p2g)

    ! 3. Reverse halo exchange.
    call self%timers%tic(t_halo)
    do ip = 1, self%nph
      call self%dec%halo_sum(self%phase(ip)%node)
      if (self%plan%gauss) call self%dec%halo_sum(self%phase(ip)%nvol)
    end do
    if (coupled) then
      call self%dec%halo_sum(self%nporo)
      call self%dec%halo_sum(self%ndrag)
    end if
    if (allocated(gpf)) then
      call self%dec%halo_sum(gpf)
      call self%dec%halo_sum(gps)
    end if
    if (allocated(gms)) call self%dec%halo_sum(gms)
    if (allocated(gmf)) call self%dec%halo_sum(gmf)
    if (self%plan%velocity_mls) then
      do ip = 1, self%nph
        call self%dec%halo_sum(self%phase(ip)%vacc)
      end do
    end if
    call self%timers%toc(t_halo)
    ! The fluid points at the free surface of the pore fluid (their pressure is 0 after
    ! the pressure update).
    ! (Not with Gauss quadrature: the forces come from the fields reconstructed over whole
    ! cells, and a thin node inside a scattered set is no surface.)
    if (surface) call free_surface_points(self, fvol, fsurf)
    ! Porosity and 1/k of the porous skeleton at the owned nodes (doc/theory.md 3.5).
    if (coupled .and. any(self%bnd%tied)) call tie_sums(nd, self%dec%alo, self%dec%olo, self%dec%ohi, &
      self%grid%ncells, self%bnd%tied, self%nporo, self%dec%comm)
    if (coupled) call nodal_porosity(self%dec%alo, self%dec%olo, self%dec%ohi, self%nporo)
    if (allocated(gpf)) call gauss_pressure_forces(self, gpf, gps)
    ! Nodes that the Gauss points of a set reach but its points barely reach take no
    ! internal force (thin_node_forces).
    if (self%plan%gauss) then
      do ip = 1, self%nph
        call thin_node_forces(nd, self%dec%alo, blo, bhi, self%phase(ip)%nvol, self%phase(ip)%node, &
                              self%nthin)
      end do
      if (allocated(gmf)) then
        call gauss_gravity(self, self%phase(fluid_phase), gravity_now(self), gmf, self%nporo)
        call gauss_gravity(self, self%phase(solid_phase), gravity_now(self), gms, transfer=gmf)
      else if (allocated(gms)) then
        call gauss_gravity(self, self%phase(solid_phase), gravity_now(self), gms)
      end if
    end if

    ! Rayleigh damping's viscous stress: its forces join the internal forces (dpmpm_damping).
    if (.not. coupled) call viscous_forces(self, blo, bhi, dt)
    ! 4. Nodal update: MLS nodal velocities, then each phase alone or both with drag.
    call self%timers%tic(t_nodal)
    if (self%has_surface_loads) then
      ! Tractions on the body's surface inside the grid join the nodal forces of the solid.
      associate (s => self%phase(solid_phase)%node, olo => self%dec%olo, ohi => self%dec%ohi)
        call surface_forces(self%bnd%faces, self%time, nd, self%dec%alo, olo, ohi, s, self%dec%comm, self%sforce)
        s(2 + nd:1 + 2*nd, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) = &
          s(2 + nd:1 + 2*nd, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) + &
          self%sforce(1:nd, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3))
      end associate
    end if
    if (self%plan%velocity_mls) then
      do ip = 1, self%nph
        call velocity_solve(nd, self%plan%velocity_basis, self%dec%alo, self%dec%olo, self%dec%ohi, &
                            self%phase(ip)%vacc, self%phase(ip)%node, self%mls_stats)
      end do
    end if
    if (.not. coupled) then
      call nodal_update(nd, self%dec%alo, blo, bhi, self%phase(solid_phase)%node, &
                        gravity_now(self), self%bnd%faces, self%time, dt, self%phase(solid_phase)%nvel, &
                        self%ext_work, damping_now(self), self%drag_loss, rayleigh_mass_args(self%cfg, self%time + dt))
      if (self%has_rigid) call drive_rigid(self, dt)
      call self%timers%toc(t_nodal)
    else
      ! Porosity and 1/k of the porous skeleton at the fluid points (start-of-step
      ! positions, doc/theory.md 3.5): the porosity for the pressure update, 1/k for the
      ! next step's drag; the interphase force when asked for. Free water (no porous
      ! solid around) gets n = 1 and no drag.
      call self%timers%toc(t_nodal)
      call self%timers%tic(t_halo)
      call self%dec%halo_copy(self%nporo)
      call self%mirror%unfold(self%nporo, 3, self%bnd%kind(:, 1))
      call self%timers%toc(t_halo)
      call self%timers%tic(t_g2p)
      allocate (nval(nf), gnrel(nf), nkinv(nf))
      associate (f => self%phase(fluid_phase))
        call interp_two_values(nd, f%st%nw, nf, f%st%i0, f%st%sw, self%dec%alo, self%nporo, 3, nval, nkinv)
        call self%timers%toc(t_g2p)
        ! (with the porosity the fluid points had in p2g)
        if (self%cfg%porosity_gradient .and. .not. self%plan%gauss) then
          if (allocated(pforce)) then
            call add_interphase_force(self, pforce)
          else
            call add_interphase_force(self, f%pts%pressure)
          end if
        end if
        ! The floor only guards against negative interpolation weights; porous points
        ! have n > 0 and water away from them n = 1.
        f%pts%porosity(1:nf) = min(1.0_wp, max(nval, 1.0e-3_wp))
        f%pts%kinv(1:nf) = max(0.0_wp, nkinv)
      end associate

      call self%timers%tic(t_nodal)
      self%dt_drag = huge(1.0_wp)
      if (self%cfg%drag == 'explicit') then
        self%dt_drag = nodal_drag_limit(self%dec%alo, self%dec%olo, self%dec%ohi, &
                                        self%phase(solid_phase)%node, self%phase(fluid_phase)%node, self%ndrag)
        call MPI_Allreduce(MPI_IN_PLACE, self%dt_drag, 1, MPI_DOUBLE_PRECISION, MPI_MIN, self%dec%comm)
        self%dt_drag = self%cfg%drag_safety*self%dt_drag
        dt = min(dt, self%dt_drag)
      end if
      call report_governing(self, dt)
      associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
        ! Rigid bodies drive the skeleton at their nodes and the fluid there is solved
        ! against it; rnode is allocated only with rigid bodies, fvol only with the
        ! free-surface test (unallocated, each is an absent argument).
        if (self%has_rigid) call rigid_node_sums(self, dt)
        rforce = 0.0_wp
        ! Tied faces: each pair one node in the update (kept: the sums of the two nodes).
        if (any(self%bnd%tied)) call join_tied(self, tsave)
        call nodal_update_coupled(nd, self%dec%alo, blo, bhi, s%node, f%node, &
                                  self%nporo, self%ndrag, gravity_now(self), self%bnd%faces, f%bc, &
                                  self%cfg%drag == 'implicit', self%time, dt, s%nvel, f%nvel, &
                                  self%ext_work, self%drag_loss, damping_now(self), self%rnode, rforce, &
                                  fvol, self%cfg%free_surface_fraction)
        if (self%has_rigid) self%drive_impulse = self%drive_impulse + dt*rforce
        if (any(self%bnd%tied)) call split_tied(self, tsave)
      end associate
      call self%timers%toc(t_nodal)
    end if

    ! The kinematic conditions of whole faces (the rigid base, tied faces), both phases.
    do ip = 1, self%nph
      call self%bnd%hold(self%cfg, self%dec%alo, blo, bhi, self%phase(ip)%node, self%phase(ip)%nvel, &
                         .true., self%time, dt, gravity_now(self), self%ext_work, self%dec%comm)
    end do

    ! The work of the surface loads over the step (their nodes' mean velocity), and of
    ! the gravity by Gauss quadrature beyond the points' own.
    if (self%has_surface_loads) call surface_work(self, dt)
    if (allocated(gms)) call gauss_gravity_work(self, self%phase(solid_phase)%nvel, gms, dt)
    if (allocated(gmf)) call gauss_gravity_work(self, self%phase(fluid_phase)%nvel, gmf, dt)

    ! 5. Forward halo exchange, and the exterior nodes from their mirror images.
    call self%timers%tic(t_halo)
    do ip = 1, self%nph
      call self%dec%halo_copy(self%phase(ip)%nvel)
      call self%mirror%unfold(self%phase(ip)%nvel, 0, self%phase(ip)%bc)
    end do
    call self%timers%toc(t_halo)

    ! The work of the benchmark's body forces (manufactured solution) over the step.
    do ip = 1, self%nph
      associate (ph => self%phase(ip))
        if (allocated(ph%bacc)) self%ext_work = self%ext_work + &
          body_force_work(nd, ph%st%nw, ph%pts%n, ph%st%i0, ph%st%sw, self%dec%alo, ph%nvel, ph%pts%mass, &
                          ph%bacc, dt)
      end associate
    end do

    ! 6. g2p: velocities, positions, velocity gradients (MUSL: from the remapped
    ! nodal velocities, musl_remap; Gauss quadrature: by the transposed force operator).
    ! The fluid points take the divergences of both phases' velocities in a pass of their
    ! own.
    call self%timers%tic(t_g2p)
    if (self%cfg%scheme == 'musl') then
      call musl_remap(self, dt)
    else
      do ip = 1, self%nph
        associate (ph => self%phase(ip), ps => self%phase(ip)%pts)
          ! (The fluid points have no vgrad: unallocated, it is an absent argument and g2p
          ! forms no gradient.)
          call g2p(nd, ph%st%nw, ps%n, ph%st%i0, ph%st%sw, ph%st%sdw, self%dec%alo, ph%nvel, self%cfg%flip, &
                   dt, ps%v, ps%x, ph%vgrad)
        end associate
      end do
      if (self%has_rigid) call hold_rigid_points(nd, ns, self%phase(solid_phase)%pts%mat, self%mats, &
                                                 body_velocities(self%mats, self%time + 0.5_wp*dt), &
                                                 self%phase(solid_phase)%pts%v)
      if (coupled) then
        associate (f => self%phase(fluid_phase))
          call point_divergences(nd, f%st%nw, nf, f%st%i0, f%st%sw, f%st%sdw, self%dec%alo, f%nvel, &
                                 self%phase(solid_phase)%nvel, f%divf, f%divs)
        end associate
      end if
    end if
    if (coupled) then
      ! With the same nodal velocities as the point gradients (remapped under MUSL).
      gnrel = 0.0_wp
      if (self%cfg%porosity_gradient) then
        associate (f => self%phase(fluid_phase))
          call mixture_flux(nd, f%st%nw, nf, f%st%i0, f%st%sw, f%st%sdw, self%dec%alo, f%pts%porosity, &
                            self%nporo, f%nvel, self%phase(solid_phase)%nvel, gnrel)
        end associate
      end if
    end if
    if (self%plan%gauss) then
      ! Strain rates by the transpose of the quadrature force operator (doc/theory.md 3.6).
      associate (s => self%phase(solid_phase))
        call gauss_point_gradients(self, s, s%gsol, s%nvel, s%vgrad)
      end associate
      if (coupled .and. self%cfg%porosity_gradient) then
        call gauss_mixture_divergence(self, gnrel)
      else if (coupled) then
        associate (f => self%phase(fluid_phase))
          call gauss_point_divergences(self, f, f%gsol, f%nvel, self%phase(solid_phase)%nvel, f%divf, &
                                       f%divs)
        end associate
      end if
    end if
    ! (the frictional contact's body back in the point set, moved by its velocity)
    if (self%has_rigid) call contact_move(self, dt)
    call self%timers%toc(t_g2p)

    ! Stress of the skeleton; with a fluid, the skeleton's porosity from its volume
    ! change, then the pore pressure (eq. 10), the fluid volume and stress.
    call self%timers%tic(t_stress)
    associate (s => self%phase(solid_phase))
      ! Axisymmetry: the hoop strain rate v_r / r as the third diagonal (dpmpm_axisym).
      if (self%cfg%axisymmetric) then
        call hoop_rate(s%st%nw, ns, s%st%i0, s%st%sw, s%pts%x, self%grid%h(1), self%dec%alo, &
                       s%nvel, s%vgrad)
        ! and v_r / r of both phases in the divergences at the fluid points
        if (coupled) call hoop_divergences(self%phase(fluid_phase)%st%nw, nf, self%phase(fluid_phase)%st%i0, &
                                           self%phase(fluid_phase)%st%sw, self%phase(fluid_phase)%pts%x, &
                                           self%grid%h(1), self%dec%alo, self%phase(fluid_phase)%nvel, &
                                           s%nvel, self%phase(fluid_phase)%divf, self%phase(fluid_phase)%divs)
      end if
      if (allocated(scell)) call smooth_volumetric_rate(nd, ns, product(self%dec%chi - self%dec%clo + 1)* &
                                                        size(self%mats), scell, s%pts%vol, s%vgrad)
      if (coupled) volb = s%pts%vol(1:ns)
      wplastic = 0.0_wp
      do m = 1, size(self%mats)
        if (coupled .and. self%mats(m)%model == model_fluid) cycle
        call stress_update(self%mats(m), m, dt, ns, s%pts%mat, s%vgrad, s%pts%stress, s%pts%vol, &
                           s%pts%vol0, s%pts%defgrad, s%pts%state, wplastic, &
                           plane=nd == 2 .and. .not. self%cfg%axisymmetric, &
                           time=self%time, step=self%step, x=s%pts%x, ids=s%pts%id, &
                           celent=self%grid%cell_volume**(1.0_wp/nd))
      end do
      ! The plastic work leaves the energy balance like the drag dissipation.
      self%ext_work = self%ext_work - wplastic
      if (coupled) call skeleton_porosity(ns, volb, s%pts%vol, s%pts%porosity)
    end associate
    if (coupled) then
      associate (f => self%phase(fluid_phase))
        ! fcell is allocated only with cell smoothing; unallocated, it is an absent argument.
        call fluid_pressure_step(nf, dt, self%mats, f%pts%mat, f%pts%porosity, f%divf, f%divs, gnrel, &
                                 self%cfg%cavitation_pressure, f%pts%pressure, self%ncavitated, &
                                 fcell, product(self%dec%chi - self%dec%clo + 1), f%pts%vol)
        if (allocated(fsurf)) then
          self%nfree_surface = self%nfree_surface + count(fsurf(1:nf))
          where (fsurf(1:nf)) f%pts%pressure(1:nf) = 0.0_wp
        end if
        call fluid_state(nf, self%mats, f%pts%mat, f%pts%mass, f%pts%porosity, f%pts%pressure, &
                         f%pts%vol, f%pts%stress)
      end associate
    end if
    call self%timers%toc(t_stress)

    ! 7. Migration of the points that left this rank's block. A value made non-finite in
    ! this step (a non-finite load, a blow-up) would lose its point in the migration, or trap
    ! in the wall test, on some rank counts only: the points stay where they are and the
    ! check of the state after the step (check_state) names the point and stops the run.
    call self%timers%tic(t_migrate)
    self%checked_valid = state_valid(self)
    if (.not. self%checked_valid) then
      call self%timers%toc(t_migrate)
      return
    end if
    do ip = 1, self%nph
      call check_inside(self, self%phase(ip)%pts, ip == fluid_phase)
    end do
    do ip = 1, self%nph
      call migrate(self%dec, self%grid%origin, self%grid%h, self%phase(ip)%pts, nlost, in_grid=.true.)
      if (nlost > 0) call fatal(trim(merge('points      ', 'fluid points', ip == solid_phase))// &
                                ' were lost in migration (moved more than one rank width in a step)', &
                                'migrate')
    end do
    if (coupled) call refill_inflow(self, self%phase(fluid_phase)%pts, self%phase(solid_phase)%pts)
    ! Every sort_every steps (counted from the run's start, as a restart counts them)
    ! the points of each set in the order of their cells.
    if (self%cfg%sort_every > 0) then
      if (mod(self%step + 1, int(self%cfg%sort_every, i8)) == 0) then
        do ip = 1, self%nph
          call sort_by_cell(self%phase(ip)%pts, self%grid%origin, self%grid%h, self%dec%clo, self%dec%chi)
        end do
      end if
    end if
    call self%timers%toc(t_migrate)
  end subroutine advance

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

  !> The work of the surface loads in this step, f . (v_old + v_new) dt / 2 at their
  !> nodes, added to the external work.
  subroutine surface_work(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    integer :: i, j, k, nd
    nd = self%nd
    associate (v => self%phase(solid_phase)%nvel, olo => self%dec%olo, ohi => self%dec%ohi)
      do k = olo(3), ohi(3)
        do j = olo(2), ohi(2)
          do i = olo(1), ohi(1)
            if (all(self%sforce(1:nd, i, j, k) == 0.0_wp)) cycle
            self%ext_work = self%ext_work + 0.5_wp*dt*dot_product(self%sforce(1:nd, i, j, k), &
                                                                  v(1:nd, i, j, k) + v(nd + 1:2*nd, i, j, k))
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
    nd = self%nd
    allocate (ff(nd, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                 self%dec%alo(3):self%dec%ahi(3)))
    ff = 0.0_wp
    associate (f => self%phase(fluid_phase))
      call interphase_p2g(nd, f%st%nw, f%pts%n, f%st%i0, f%st%sw, f%st%sdw, f%pts%vol, pf, &
                          f%pts%porosity, self%dec%alo, self%nporo, ff)
    end associate
    fs = -ff
    call self%mirror%fold(ff, 0, self%phase(2)%bc)
    call self%mirror%fold(fs, 0, self%phase(1)%bc)
    call self%dec%halo_sum(ff)
    call self%dec%halo_sum(fs)
    self%phase(2)%node(2 + nd:1 + 2*nd, :, :, :) = self%phase(2)%node(2 + nd:1 + 2*nd, :, :, :) + ff
    self%phase(1)%node(2 + nd:1 + 2*nd, :, :, :) = self%phase(1)%node(2 + nd:1 + 2*nd, :, :, :) + fs
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

end module dpmpm_step
