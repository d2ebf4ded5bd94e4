!> One explicit time step over the list of phases (doc/architecture.md, "One step";
!> doc/theory.md 4.1), as its stages in order: stencils, p2g of every phase (with
!> the coupling terms when there are two), the reverse halo exchange, the length of
!> the step where the explicit drag limits it, the node fields completed from their
!> sums, the nodal update (MLS nodal velocities where chosen, drag where the phases
!> meet, every boundary condition), the forward halo exchange, g2p with the MUSL remap
!> or USL, the constitutive update (stress, porosity, pore pressure) and migration. A
!> one-phase scene is the same step with one phase and no coupling.
module dpmpm_step
  use dpmpm_kinds, only: wp, i8
  use dpmpm_error, only: fatal
  use dpmpm_timer, only: t_stencil, t_p2g, t_halo, t_nodal, t_g2p, t_stress, t_migrate
  use dpmpm_mls_velocity, only: velocity_accumulate, velocity_solve
  use dpmpm_materials, only: stress_update, model_fluid
  use dpmpm_axisym, only: hoop_force_p2g, hoop_rate, pressure_hoop_p2g, hoop_divergences, fluid_area_p2g
  use dpmpm_benchmarks, only: benchmark_body_force
  use dpmpm_migrate, only: migrate
  use dpmpm_energy, only: state_valid
  use dpmpm_cell_order, only: sort_by_cell
  use dpmpm_phase, only: solid_phase, fluid_phase
  use dpmpm_state, only: state_t
  use dpmpm_transfer, only: p2g, g2p, point_divergences, interp_two_values, fluid_p2g, body_force_work, &
                            solid_porosity_p2g, porous_p2g, mixture_flux
  use dpmpm_nodal_update, only: nodal_update, nodal_update_coupled
  use dpmpm_damping, only: viscous_forces, rayleigh_mass_args
  use dpmpm_drag, only: nodal_drag_limit
  use dpmpm_remap, only: tied_save_t, join_tied, split_tied, musl_remap
  use dpmpm_pore_pressure, only: nodal_porosity, skeleton_porosity, skeleton_kinv, point_cells, &
                                 fluid_pressure_step, fluid_state
  use dpmpm_inflow, only: refill_inflow
  use dpmpm_cell_smoothing, only: smooth_volumetric_rate
  use dpmpm_quadrature, only: gauss_p2g, gauss_point_gradients, gauss_pressure_forces, &
                              gauss_point_divergences, gauss_mixture_divergence, gauss_gravity, gauss_gravity_work
  use dpmpm_gauss_fields, only: thin_node_forces
  use dpmpm_time_step, only: report_governing
  use dpmpm_tied_sides, only: tie_sums
  use dpmpm_rigid, only: hold_rigid_points, body_velocities
  use dpmpm_contact, only: contact_hide, contact_move
  use dpmpm_step_parts, only: step_box, compute_stencils, swap_force_fields, restore_force_fields, &
                              free_surface_points, rigid_node_sums, drive_rigid, add_surface_forces, surface_work, &
                              add_interphase_force, check_inside, velocity_signs, gravity_now, damping_now
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_MIN
  implicit none
  private
  public :: advance

  !> What the stages of one step hand on to the later ones: the scene's switches of the
  !> step, the node box of the nodal updates, the cells of the cell smoothing, the force
  !> fields held aside while the smoothed ones stand in, and the extra node fields of the
  !> free-surface test and of Gauss quadrature. Unallocated arrays are absent arguments.
  type :: step_work_t
    logical :: coupled = .false.              !< two phases, coupled by drag and pore pressure
    !> the free surface of the pore fluid is looked for (free_surface_points)
    logical :: surface = .false.
    !> the fluid's mass and momentum come with fluid_p2g (no body accelerations)
    logical :: fluid_mom = .false.
    logical :: ggrav = .false.                !< gravity by Gauss quadrature (gauss_gravity)
    integer :: nd = 0, ns = 0, nf = 0         !< dimensions; solid and fluid points at the start
    !> the owned nodes where node fields may be nonzero (loops of the nodal updates)
    integer :: blo(3) = 0, bhi(3) = -1
    !> cell of each fluid point (pressure_smoothing), pair of cell and material of each
    !> solid point (volumetric_smoothing), at the start of the step
    integer, allocatable :: fcell(:), scell(:)
    logical, allocatable :: fsurf(:)          !< fluid points at the free surface
    real(wp), allocatable :: fvol(:, :, :, :) !< fluid volume at the nodes (free-surface test)
    !> the points' own stresses and pressures while the cells' means stand in, and the
    !> cells' mean pressures kept for the interphase force
    real(wp), allocatable :: sheld(:, :), pheld(:), pforce(:)
    real(wp), allocatable :: skinv(:)         !< 1/k of the skeleton's points (skeleton_kinv)
    real(wp), allocatable :: gnrel(:)         !< mixture flux divergence at the fluid points
    !> Gauss quadrature: the pressure's force shared at the nodes (gpf; gps the solid's
    !> copy) and the Gauss masses of gravity (gms, gmf)
    real(wp), allocatable :: gpf(:, :, :, :), gps(:, :, :, :), gms(:, :, :, :), gmf(:, :, :, :)
  end type step_work_t

contains

  !> One explicit step of length dt over the phases of self (1: solid; 2: fluid,
  !> coupled to the solid by drag and pore pressure), stage by stage in the order of
  !> doc/architecture.md ("One step"). dt may shrink to the explicit-drag limit of this
  !> step's nodes (drag_time_step), before any stage uses it.
  subroutine advance(self, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(inout) :: dt
    type(step_work_t) :: w
    call start_step(self, w)
    call stencils_stage(self, w)            ! 1. stencils
    call p2g_stage(self, w, dt)             ! 2. p2g
    call reverse_halo_stage(self, w)        ! 3. reverse halo exchange
    call drag_time_step(self, w, dt)        !    the step's length (explicit drag)
    call node_fields_stage(self, w, dt)     !    node fields completed from their sums
    call nodal_update_stage(self, w, dt)    ! 4. nodal update
    call forward_halo_stage(self, w, dt)    ! 5. forward halo exchange
    call g2p_stage(self, w, dt)             ! 6. g2p, MUSL remap
    call constitutive_stage(self, w, dt)    ! 7. stress, porosity, pore pressure
    call migration_stage(self, w)           ! 8. migration
  end subroutine advance

  !> The switches and sizes of the step (step_work_t).
  subroutine start_step(self, w)
    class(state_t), intent(in) :: self
    type(step_work_t), intent(inout) :: w
    w%coupled = self%nph == 2
    w%surface = w%coupled .and. self%cfg%free_surface_fraction > 0.0_wp .and. .not. self%plan%gauss
    w%nd = self%nd
    w%ggrav = self%plan%gauss .and. any(self%cfg%gravity /= 0.0_wp)
    w%ns = self%phase(solid_phase)%pts%n
    w%nf = 0
    if (w%coupled) w%nf = self%phase(fluid_phase)%pts%n
  end subroutine start_step

  !> 1. Stencils of every point, once per step, the node box of the step, and the
  !> points' cells for the cell smoothing.
  subroutine stencils_stage(self, w)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    integer :: ip
    call self%timers%tic(t_stencil)
    do ip = 1, self%nph
      call compute_stencils(self, self%phase(ip))
    end do
    call step_box(self)
    w%blo = max(self%dec%olo, self%zlo)
    w%bhi = min(self%dec%ohi, self%zhi)
    ! The cell of each fluid point at the start of the step (points are in this rank's
    ! cells then), for the cell smoothing of the pore pressure.
    if (w%coupled .and. self%cfg%pressure_smoothing == 'cell') then
      allocate (w%fcell(w%nf))
      call point_cells(w%nd, w%nf, self%phase(fluid_phase)%pts%x, self%grid%origin, self%grid%h, &
                       self%dec%clo, self%dec%chi, w%fcell)
    end if
    ! and, for the cell smoothing of the volumetric strain rate, the pair of cell and
    ! material of each solid point (1..ncell*nmat; the same for the forces and the rates)
    if (self%cfg%volumetric_smoothing == 'cell') then
      allocate (w%scell(w%ns))
      call point_cells(w%nd, w%ns, self%phase(solid_phase)%pts%x, self%grid%origin, self%grid%h, &
                       self%dec%clo, self%dec%chi, w%scell)
      w%scell = self%phase(solid_phase)%pts%mat(1:w%ns) + size(self%mats)*(w%scell - 1)
    end if
    call self%timers%toc(t_stencil)
  end subroutine stencils_stage

  !> 2. p2g of every phase; the solid's internal force by point quadrature unless
  !> Gauss quadrature gives it; the fluid's pore-pressure forces come with the coupling.
  !> With cell smoothing the forces take each cell's mean stress of the skeleton
  !> (volumetric_smoothing) and mean pore pressure (pressure_smoothing): these stand in
  !> the points' place up to the end of the forces (doc/theory.md 4.5). Then the
  !> exterior nodes' shares folded onto their mirror images, and the MLS velocities'
  !> moment sums.
  subroutine p2g_stage(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    real(wp), intent(in) :: dt
    call self%timers%tic(t_p2g)
    ! A rigid body with a frictional contact stays out of the soil's node fields up to g2p
    ! (dpmpm_contact).
    if (self%has_rigid) call contact_hide(self, dt, gravity_now(self))
    call swap_force_fields(self, w%scell, w%fcell, w%sheld, w%pheld)
    call phases_p2g(self, w)
    call extra_forces_p2g(self, w)
    call restore_force_fields(self, w%sheld, w%pheld, w%pforce)
    call fold_node_fields(self, w)
    if (self%plan%velocity_mls) call velocity_moments(self)
    call self%timers%toc(t_p2g)
  end subroutine p2g_stage

  !> Mass, momentum and forces of every phase at the nodes. With a fluid, fluid_p2g sums
  !> the fluid's mass and momentum in its own pass, unless the fluid points carry body
  !> accelerations; the skeleton's porosity and 1/k at the nodes come with its p2g, the
  !> drag coefficient with the fluid's.
  subroutine phases_p2g(self, w)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    integer :: ip, nd
    nd = w%nd
    w%fluid_mom = w%coupled
    if (w%coupled) then
      w%fluid_mom = .not. allocated(self%phase(fluid_phase)%bacc)
      self%cpl%nporo = 0.0_wp
      self%cpl%ndrag = 0.0_wp
      associate (s => self%phase(solid_phase)%pts)
        allocate (w%skinv(w%ns))
        call skeleton_kinv(w%ns, self%mats, s%mat, s%porosity, s%vol, s%vol0, w%skinv)
      end associate
    end if
    do ip = 1, self%nph
      associate (ph => self%phase(ip), ps => self%phase(ip)%pts)
        ph%node(:, self%zlo(1):self%zhi(1), self%zlo(2):self%zhi(2), self%zlo(3):self%zhi(3)) = 0.0_wp
        if (ip == fluid_phase .and. w%fluid_mom) then
          continue
        else if (allocated(ph%bacc)) then
          call benchmark_body_force(self%cfg, self%mats, ps, self%time, ph%bacc)
          call p2g(nd, ph%st%nw, ps%n, ph%st%i0, ph%st%sw, ph%st%sdw, ps%mass, ps%v, ps%vol, ps%stress, &
                   ip == solid_phase .and. .not. self%plan%gauss, self%dec%alo, ph%node, ph%bacc)
          if (w%coupled .and. ip == solid_phase) &
            call solid_porosity_p2g(ph%st%nw, w%ns, ph%st%i0, ph%st%sw, ps%mass, ps%porosity, w%skinv, &
                                    self%dec%alo, self%cpl%nporo)
        else if (w%coupled .and. ip == solid_phase) then
          call porous_p2g(nd, ph%st%nw, ps%n, ph%st%i0, ph%st%sw, ph%st%sdw, ps%mass, ps%v, ps%vol, ps%stress, &
                          .not. self%plan%gauss, self%dec%alo, ph%node, ps%porosity, w%skinv, self%cpl%nporo)
        else
          call p2g(nd, ph%st%nw, ps%n, ph%st%i0, ph%st%sw, ph%st%sdw, ps%mass, ps%v, ps%vol, ps%stress, &
                   ip == solid_phase .and. .not. self%plan%gauss, self%dec%alo, ph%node)
        end if
      end associate
    end do
    if (w%coupled) then
      associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
        if (w%surface) then
          ! the fluid volume at the nodes for the free-surface test, summed in the same
          ! pass (unallocated, fvol is an absent argument)
          allocate (w%fvol(1, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                           self%dec%alo(3):self%dec%ahi(3)))
          w%fvol = 0.0_wp
        end if
        call fluid_p2g(nd, f%st%nw, w%nf, f%st%i0, f%st%sw, f%st%sdw, f%pts%mass, f%pts%v, f%pts%vol, &
                       f%pts%porosity, f%pts%pressure, f%pts%kinv, w%fluid_mom, &
                       (.not. self%plan%gauss), self%dec%alo, s%node, f%node, self%cpl%ndrag, w%fvol)
      end associate
    end if
  end subroutine phases_p2g

  !> The forces beside the points' own p2g. Gauss quadrature: the forces of the skeleton
  !> and the pore pressure, and with gravity the Gauss masses (gms, gmf); with the
  !> porosity-gradient terms the pressure's force gpf is shared at the nodes once the
  !> nodal porosity is known (gps: the solid's copy). Axisymmetry: the hoop stress's
  !> nodal force (dpmpm_axisym), from the stress of p2g; with pore water the pressure's
  !> on both phases (the pressures of fluid_p2g) and the fluid's r-z areas for the
  !> free-surface tests.
  subroutine extra_forces_p2g(self, w)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    if (self%plan%gauss) then
      call gauss_p2g(self, w%ggrav, w%gpf, w%gms, w%gmf)
      if (allocated(w%gpf)) w%gps = w%gpf
    end if
    if (self%cfg%axisymmetric) then
      associate (s => self%phase(solid_phase))
        call hoop_force_p2g(s%st%nw, s%pts%n, s%st%i0, s%st%sw, s%pts%x, self%grid%h(1), &
                            s%pts%vol, s%pts%stress, self%dec%alo, s%node)
      end associate
      if (w%coupled) then
        associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
          call pressure_hoop_p2g(f%st%nw, w%nf, f%st%i0, f%st%sw, f%pts%x, self%grid%h(1), f%pts%vol, &
                                 f%pts%porosity, f%pts%pressure, self%dec%alo, s%node, f%node)
          if (allocated(w%fvol)) call fluid_area_p2g(f%st%nw, w%nf, f%st%i0, f%st%sw, f%pts%x, self%grid%h(1), &
                                                     f%pts%vol, self%dec%alo, w%fvol)
        end associate
      end if
    end if
  end subroutine extra_forces_p2g

  !> Exterior nodes' shares of every node field folded onto their mirror images, each
  !> with the conditions of the phase it goes to.
  subroutine fold_node_fields(self, w)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    integer :: ip
    do ip = 1, self%nph
      call self%mirror%fold(self%phase(ip)%node, 1, self%phase(ip)%bc)
      if (self%plan%gauss) call self%mirror%fold(self%phase(ip)%nvol, 2, self%phase(ip)%bc)
    end do
    if (w%coupled) then
      call self%mirror%fold(self%cpl%nporo, 3, self%bnd%kind(:, 1))
      call self%mirror%fold(self%cpl%ndrag, 1, self%phase(fluid_phase)%bc)
    end if
    if (allocated(w%gpf)) then
      call self%mirror%fold(w%gpf, 0, self%phase(fluid_phase)%bc)
      call self%mirror%fold(w%gps, 0, self%phase(solid_phase)%bc)
    end if
    if (allocated(w%gms)) call self%mirror%fold(w%gms, 1, self%phase(solid_phase)%bc)
    if (allocated(w%gmf)) call self%mirror%fold(w%gmf, 1, self%phase(fluid_phase)%bc)
  end subroutine fold_node_fields

  !> MLS nodal velocities (eq. 12): each phase's moment sums, folded at the mirror walls
  !> with the reflected basis' signs.
  subroutine velocity_moments(self)
    class(state_t), intent(inout) :: self
    integer :: ip
    do ip = 1, self%nph
      associate (ph => self%phase(ip), ps => self%phase(ip)%pts, pl => self%plan)
        ph%vacc = 0.0_wp
        call velocity_accumulate(self%nd, ps%n, ps%x, ps%mass, ps%v, self%grid%origin, self%grid%h, &
                                 pl%velocity_kernel, pl%velocity_radius, pl%velocity_radial, &
                                 pl%velocity_basis, self%dec%alo, ph%vacc)
        call self%mirror%fold_planes(ph%vacc, velocity_signs(self, ph%vacc, ph%bc), .true., ph%bc)
      end associate
    end do
  end subroutine velocity_moments

  !> 3. Reverse halo exchange: every node field summed onto its owner.
  subroutine reverse_halo_stage(self, w)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    integer :: ip
    call self%timers%tic(t_halo)
    do ip = 1, self%nph
      call self%dec%halo_sum(self%phase(ip)%node)
      if (self%plan%gauss) call self%dec%halo_sum(self%phase(ip)%nvol)
    end do
    if (w%coupled) then
      call self%dec%halo_sum(self%cpl%nporo)
      call self%dec%halo_sum(self%cpl%ndrag)
    end if
    if (allocated(w%gpf)) then
      call self%dec%halo_sum(w%gpf)
      call self%dec%halo_sum(w%gps)
    end if
    if (allocated(w%gms)) call self%dec%halo_sum(w%gms)
    if (allocated(w%gmf)) call self%dec%halo_sum(w%gmf)
    if (self%plan%velocity_mls) then
      do ip = 1, self%nph
        call self%dec%halo_sum(self%phase(ip)%vacc)
      end do
    end if
    call self%timers%toc(t_halo)
  end subroutine reverse_halo_stage

  !> The length of the step, settled here before any stage uses it. The explicit drag
  !> (&two_phase drag = 'explicit') limits dt by the nodal masses and drag coefficients
  !> of this step's p2g (nodal_drag_limit, doc/theory.md 7.2), known on every rank only
  !> after the reverse halo exchange: so this one reduction stays inside the step.
  !> Taking the limit from the step before (in stable_dt) would lag the nodes by a step
  !> where the points move into a node of high drag. The governing limit is reported
  !> when it changes.
  subroutine drag_time_step(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(in) :: w
    real(wp), intent(inout) :: dt
    if (.not. w%coupled) return
    call self%timers%tic(t_nodal)
    self%dt_drag = huge(1.0_wp)
    if (self%cfg%drag == 'explicit') then
      self%dt_drag = nodal_drag_limit(self%dec%alo, self%dec%olo, self%dec%ohi, &
                                      self%phase(solid_phase)%node, self%phase(fluid_phase)%node, self%cpl%ndrag)
      call MPI_Allreduce(MPI_IN_PLACE, self%dt_drag, 1, MPI_DOUBLE_PRECISION, MPI_MIN, self%dec%comm)
      self%dt_drag = self%cfg%drag_safety*self%dt_drag
      dt = min(dt, self%dt_drag)
    end if
    call report_governing(self, dt)
    call self%timers%toc(t_nodal)
  end subroutine drag_time_step

  !> The node fields completed from their sums, before the nodal update: the fluid
  !> points at the free surface of the pore fluid (their pressure is 0 after the
  !> pressure update; not with Gauss quadrature, whose forces come from fields
  !> reconstructed over whole cells, where a thin node inside a scattered set is no
  !> surface), porosity and 1/k of the porous skeleton at the owned nodes
  !> (doc/theory.md 3.5), the Gauss pressure forces, thin nodes and gravity, and
  !> Rayleigh damping's viscous forces.
  subroutine node_fields_stage(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    real(wp), intent(in) :: dt
    integer :: ip
    if (w%surface) call free_surface_points(self, w%fvol, w%fsurf)
    if (w%coupled .and. any(self%bnd%tied)) call tie_sums(w%nd, self%dec%alo, self%dec%olo, self%dec%ohi, &
                                                          self%grid%ncells, self%bnd%tied, self%cpl%nporo, self%dec%comm)
    if (w%coupled) call nodal_porosity(self%dec%alo, self%dec%olo, self%dec%ohi, self%cpl%nporo)
    if (allocated(w%gpf)) call gauss_pressure_forces(self, w%gpf, w%gps)
    ! Nodes that the Gauss points of a set reach but its points barely reach take no
    ! internal force (thin_node_forces).
    if (self%plan%gauss) then
      do ip = 1, self%nph
        call thin_node_forces(w%nd, self%dec%alo, w%blo, w%bhi, self%phase(ip)%nvol, self%phase(ip)%node, &
                              self%nthin)
      end do
      if (allocated(w%gmf)) then
        call gauss_gravity(self, self%phase(fluid_phase), gravity_now(self), w%gmf, self%cpl%nporo)
        call gauss_gravity(self, self%phase(solid_phase), gravity_now(self), w%gms, transfer=w%gmf)
      else if (allocated(w%gms)) then
        call gauss_gravity(self, self%phase(solid_phase), gravity_now(self), w%gms)
      end if
    end if
    ! Rayleigh damping's viscous stress: its forces join the internal forces (dpmpm_damping).
    if (.not. w%coupled) call viscous_forces(self, w%blo, w%bhi, dt)
  end subroutine node_fields_stage

  !> 4. Nodal update on the owned nodes: the surface loads' forces, MLS nodal
  !> velocities, then each phase alone or both with drag; the kinematic conditions of
  !> whole faces (the rigid base, tied faces) on both phases; the work of the surface
  !> loads and of the gravity by Gauss quadrature over the step.
  subroutine nodal_update_stage(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    real(wp), intent(in) :: dt
    integer :: ip
    call self%timers%tic(t_nodal)
    if (self%has_surface_loads) call add_surface_forces(self)
    if (self%plan%velocity_mls) then
      do ip = 1, self%nph
        call velocity_solve(w%nd, self%plan%velocity_basis, self%dec%alo, self%dec%olo, self%dec%ohi, &
                            self%phase(ip)%vacc, self%phase(ip)%node, self%mls_stats)
      end do
    end if
    if (.not. w%coupled) then
      call nodal_update(w%nd, self%dec%alo, w%blo, w%bhi, self%phase(solid_phase)%node, &
                        gravity_now(self), self%bnd%faces, self%time, dt, self%phase(solid_phase)%nvel, &
                        self%ext_work, damping_now(self), self%drag_loss, rayleigh_mass_args(self%cfg, self%time + dt))
      if (self%has_rigid) call drive_rigid(self, dt)
      call self%timers%toc(t_nodal)
    else
      call self%timers%toc(t_nodal)
      call fluid_point_porosity(self, w)
      call self%timers%tic(t_nodal)
      call coupled_update(self, w, dt)
      call self%timers%toc(t_nodal)
    end if
    do ip = 1, self%nph
      call self%bnd%hold(self%cfg, self%dec%alo, w%blo, w%bhi, self%phase(ip)%node, self%phase(ip)%nvel, &
                         .true., self%time, dt, gravity_now(self), self%ext_work, self%dec%comm)
    end do
    if (self%has_surface_loads) call surface_work(self, dt)
    if (allocated(w%gms)) call gauss_gravity_work(self, self%phase(solid_phase)%nvel, w%gms, dt)
    if (allocated(w%gmf)) call gauss_gravity_work(self, self%phase(fluid_phase)%nvel, w%gmf, dt)
  end subroutine nodal_update_stage

  !> Porosity and 1/k of the porous skeleton at the fluid points (start-of-step
  !> positions, doc/theory.md 3.5): the porosity for the pressure update, 1/k for the
  !> next step's drag; and the interphase force when asked for, with the porosity the
  !> fluid points had in p2g. Free water (no porous solid around) gets n = 1 and no drag.
  subroutine fluid_point_porosity(self, w)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    real(wp), allocatable :: nval(:), nkinv(:)
    call self%timers%tic(t_halo)
    call self%dec%halo_copy(self%cpl%nporo)
    call self%mirror%unfold(self%cpl%nporo, 3, self%bnd%kind(:, 1))
    call self%timers%toc(t_halo)
    call self%timers%tic(t_g2p)
    allocate (nval(w%nf), nkinv(w%nf))
    associate (f => self%phase(fluid_phase))
      call interp_two_values(w%nd, f%st%nw, w%nf, f%st%i0, f%st%sw, self%dec%alo, self%cpl%nporo, 3, nval, nkinv)
      call self%timers%toc(t_g2p)
      if (self%cfg%porosity_gradient .and. .not. self%plan%gauss) then
        if (allocated(w%pforce)) then
          call add_interphase_force(self, w%pforce)
        else
          call add_interphase_force(self, f%pts%pressure)
        end if
      end if
      ! The floor only guards against negative interpolation weights; porous points
      ! have n > 0 and water away from them n = 1.
      f%pts%porosity(1:w%nf) = min(1.0_wp, max(nval, 1.0e-3_wp))
      f%pts%kinv(1:w%nf) = max(0.0_wp, nkinv)
    end associate
  end subroutine fluid_point_porosity

  !> Both phases' nodal update with the drag (nodal_update_coupled). Rigid bodies drive
  !> the skeleton at their nodes and the fluid there is solved against it; tied faces
  !> take each pair as one node in the update (kept: the sums of the two nodes). rnode
  !> is allocated only with rigid bodies, fvol only with the free-surface test
  !> (unallocated, each is an absent argument).
  subroutine coupled_update(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    real(wp), intent(in) :: dt
    real(wp) :: rforce(3)
    type(tied_save_t) :: tsave
    associate (s => self%phase(solid_phase), f => self%phase(fluid_phase))
      if (self%has_rigid) call rigid_node_sums(self, dt)
      rforce = 0.0_wp
      if (any(self%bnd%tied)) call join_tied(self, tsave)
      call nodal_update_coupled(w%nd, self%dec%alo, w%blo, w%bhi, s%node, f%node, &
                                self%cpl%nporo, self%cpl%ndrag, gravity_now(self), self%bnd%faces, f%bc, &
                                self%cfg%drag == 'implicit', self%time, dt, s%nvel, f%nvel, &
                                self%ext_work, self%drag_loss, damping_now(self), self%rnode, rforce, &
                                w%fvol, self%cfg%free_surface_fraction)
      if (self%has_rigid) self%drive_impulse = self%drive_impulse + dt*rforce
      if (any(self%bnd%tied)) call split_tied(self, tsave)
    end associate
  end subroutine coupled_update

  !> 5. Forward halo exchange of the nodal velocities, the exterior nodes from their
  !> mirror images; then the work of the benchmark's body forces (manufactured
  !> solution) over the step.
  subroutine forward_halo_stage(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(in) :: w
    real(wp), intent(in) :: dt
    integer :: ip
    call self%timers%tic(t_halo)
    do ip = 1, self%nph
      call self%dec%halo_copy(self%phase(ip)%nvel)
      call self%mirror%unfold(self%phase(ip)%nvel, 0, self%phase(ip)%bc)
    end do
    call self%timers%toc(t_halo)
    do ip = 1, self%nph
      associate (ph => self%phase(ip))
        if (allocated(ph%bacc)) self%ext_work = self%ext_work + &
          body_force_work(w%nd, ph%st%nw, ph%pts%n, ph%st%i0, ph%st%sw, self%dec%alo, ph%nvel, ph%pts%mass, &
                          ph%bacc, dt)
      end associate
    end do
  end subroutine forward_halo_stage

  !> 6. g2p: velocities, positions, velocity gradients (MUSL: from the remapped nodal
  !> velocities, musl_remap; Gauss quadrature: by the transposed force operator). The
  !> fluid points take the divergences of both phases' velocities in a pass of their
  !> own, and with the porosity gradient the mixture flux, from the same nodal
  !> velocities as the point gradients (remapped under MUSL).
  subroutine g2p_stage(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    real(wp), intent(in) :: dt
    call self%timers%tic(t_g2p)
    if (self%cfg%scheme == 'musl') then
      call musl_remap(self, dt)
    else
      call usl_g2p(self, w, dt)
    end if
    if (w%coupled) then
      allocate (w%gnrel(w%nf))
      w%gnrel = 0.0_wp
      if (self%cfg%porosity_gradient) then
        associate (f => self%phase(fluid_phase))
          call mixture_flux(w%nd, f%st%nw, w%nf, f%st%i0, f%st%sw, f%st%sdw, self%dec%alo, f%pts%porosity, &
                            self%cpl%nporo, f%nvel, self%phase(solid_phase)%nvel, w%gnrel)
        end associate
      end if
    end if
    if (self%plan%gauss) then
      ! Strain rates by the transpose of the quadrature force operator (doc/theory.md 3.6).
      associate (s => self%phase(solid_phase))
        call gauss_point_gradients(self, s, s%gsol, s%nvel, s%vgrad)
      end associate
      if (w%coupled .and. self%cfg%porosity_gradient) then
        call gauss_mixture_divergence(self, w%gnrel)
      else if (w%coupled) then
        associate (f => self%phase(fluid_phase))
          call gauss_point_divergences(self, f, f%gsol, f%nvel, self%phase(solid_phase)%nvel, f%divf, &
                                       f%divs)
        end associate
      end if
    end if
    ! (the frictional contact's body back in the point set, moved by its velocity)
    if (self%has_rigid) call contact_move(self, dt)
    call self%timers%toc(t_g2p)
  end subroutine g2p_stage

  !> USL g2p of every phase from the nodal update's velocities; rigid points keep their
  !> body's velocity; the fluid points' divergences of both phases' velocities.
  subroutine usl_g2p(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(in) :: w
    real(wp), intent(in) :: dt
    integer :: ip
    do ip = 1, self%nph
      associate (ph => self%phase(ip), ps => self%phase(ip)%pts)
        ! (The fluid points have no vgrad: unallocated, it is an absent argument and g2p
        ! forms no gradient.)
        call g2p(w%nd, ph%st%nw, ps%n, ph%st%i0, ph%st%sw, ph%st%sdw, self%dec%alo, ph%nvel, self%cfg%flip, &
                 dt, ps%v, ps%x, ph%vgrad)
      end associate
    end do
    if (self%has_rigid) call hold_rigid_points(w%nd, w%ns, self%phase(solid_phase)%pts%mat, self%mats, &
                                               body_velocities(self%mats, self%time + 0.5_wp*dt), &
                                               self%phase(solid_phase)%pts%v)
    if (w%coupled) then
      associate (f => self%phase(fluid_phase))
        call point_divergences(w%nd, f%st%nw, w%nf, f%st%i0, f%st%sw, f%st%sdw, self%dec%alo, f%nvel, &
                               self%phase(solid_phase)%nvel, f%divf, f%divs)
      end associate
    end if
  end subroutine usl_g2p

  !> 7. Constitutive update: stress of the skeleton; with a fluid, the skeleton's
  !> porosity from its volume change, then the pore pressure (eq. 10), the fluid volume
  !> and stress.
  subroutine constitutive_stage(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(inout) :: w
    real(wp), intent(in) :: dt
    call self%timers%tic(t_stress)
    call skeleton_update(self, w, dt)
    if (w%coupled) then
      associate (f => self%phase(fluid_phase))
        ! fcell is allocated only with cell smoothing; unallocated, it is an absent argument.
        call fluid_pressure_step(w%nf, dt, self%mats, f%pts%mat, f%pts%porosity, f%divf, f%divs, w%gnrel, &
                                 self%cfg%cavitation_pressure, f%pts%pressure, self%ncavitated, &
                                 w%fcell, product(self%dec%chi - self%dec%clo + 1), f%pts%vol)
        if (allocated(w%fsurf)) then
          self%nfree_surface = self%nfree_surface + count(w%fsurf(1:w%nf))
          where (w%fsurf(1:w%nf)) f%pts%pressure(1:w%nf) = 0.0_wp
        end if
        call fluid_state(w%nf, self%mats, f%pts%mat, f%pts%mass, f%pts%porosity, f%pts%pressure, &
                         f%pts%vol, f%pts%stress)
      end associate
    end if
    call self%timers%toc(t_stress)
  end subroutine constitutive_stage

  !> The skeleton's stress per material group (stress_update), after the hoop strain
  !> rate of axisymmetry and the cell smoothing of the volumetric strain rate; with a
  !> fluid, its porosity from its volume change. The plastic work leaves the energy
  !> balance like the drag dissipation.
  subroutine skeleton_update(self, w, dt)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(in) :: w
    real(wp), intent(in) :: dt
    real(wp), allocatable :: volb(:)
    real(wp) :: wplastic
    integer :: m, nd, ns
    nd = w%nd
    ns = w%ns
    associate (s => self%phase(solid_phase))
      ! Axisymmetry: the hoop strain rate v_r / r as the third diagonal (dpmpm_axisym).
      if (self%cfg%axisymmetric) then
        call hoop_rate(s%st%nw, ns, s%st%i0, s%st%sw, s%pts%x, self%grid%h(1), self%dec%alo, &
                       s%nvel, s%vgrad)
        ! and v_r / r of both phases in the divergences at the fluid points
        if (w%coupled) call hoop_divergences(self%phase(fluid_phase)%st%nw, w%nf, self%phase(fluid_phase)%st%i0, &
                                             self%phase(fluid_phase)%st%sw, self%phase(fluid_phase)%pts%x, &
                                             self%grid%h(1), self%dec%alo, self%phase(fluid_phase)%nvel, &
                                             s%nvel, self%phase(fluid_phase)%divf, self%phase(fluid_phase)%divs)
      end if
      if (allocated(w%scell)) call smooth_volumetric_rate(nd, ns, product(self%dec%chi - self%dec%clo + 1)* &
                                                          size(self%mats), w%scell, s%pts%vol, s%vgrad)
      if (w%coupled) volb = s%pts%vol(1:ns)
      wplastic = 0.0_wp
      do m = 1, size(self%mats)
        if (w%coupled .and. self%mats(m)%model == model_fluid) cycle
        call stress_update(self%mats(m), m, dt, ns, s%pts%mat, s%vgrad, s%pts%stress, s%pts%vol, &
                           s%pts%vol0, s%pts%defgrad, s%pts%state, wplastic, &
                           plane=nd == 2 .and. .not. self%cfg%axisymmetric, &
                           time=self%time, step=self%step, x=s%pts%x, ids=s%pts%id, &
                           celent=self%grid%cell_volume**(1.0_wp/nd))
      end do
      self%ext_work = self%ext_work - wplastic
      if (w%coupled) call skeleton_porosity(ns, volb, s%pts%vol, s%pts%porosity)
    end associate
  end subroutine skeleton_update

  !> 8. Migration of the points that left this rank's block, after the wall test
  !> (check_inside); fluid points added where pore water flows in through a drained
  !> face; every sort_every steps the points of each set in the order of their cells. A
  !> value made non-finite in this step (a non-finite load, a blow-up) would lose its
  !> point in the migration, or trap in the wall test, on some rank counts only: the
  !> points stay where they are and the check of the state after the step
  !> (check_state) names the point and stops the run.
  subroutine migration_stage(self, w)
    class(state_t), intent(inout) :: self
    type(step_work_t), intent(in) :: w
    integer :: ip, nlost
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
    if (w%coupled) call refill_inflow(self, self%phase(fluid_phase)%pts, self%phase(solid_phase)%pts)
    ! (counted from the run's start, as a restart counts them)
    if (self%cfg%sort_every > 0) then
      if (mod(self%step + 1, int(self%cfg%sort_every, i8)) == 0) then
        do ip = 1, self%nph
          call sort_by_cell(self%phase(ip)%pts, self%grid%origin, self%grid%h, self%dec%clo, self%dec%chi)
        end do
      end if
    end if
    call self%timers%toc(t_migrate)
  end subroutine migration_stage

end module dpmpm_step
