!> One simulation: the scene built from a config_t on a communicator, and the
!> explicit one-phase time step (p2g, nodal update, g2p, MUSL or USL stress update,
!> migration). A thin object over plain-array kernels; nothing here touches
!> MPI_COMM_WORLD, so tests can run several simulations on sub-communicators.
module dpmpm_simulation
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use dpmpm_kinds, only: wp, i8
  use dpmpm_error, only: fatal, clean_stop
  use dpmpm_log, only: log_t
  use dpmpm_strings, only: i8toa
  use dpmpm_timer, only: timer_set_t, t_total, t_stencil, t_p2g, t_halo, t_nodal, t_g2p, t_stress, &
                         t_migrate, t_output, ntimers, timer_names
  use dpmpm_config, only: config_t, bc_free, bc_fixed, bc_roller, fbc_default, fbc_drained, &
                          fbc_impermeable, fbc_names, face_names
  use dpmpm_grid, only: grid_t
  use dpmpm_decomp, only: decomp_t
  use dpmpm_kernels, only: kernel_width, kernel_reach, max_stencil, bspline_1d
  use dpmpm_shape_plan, only: shape_plan_t
  use dpmpm_mls, only: mls_stats_t, basis_size, packed_size
  use dpmpm_reconstruct, only: psi_stencil, occupancy_pass, velocity_accumulate, velocity_solve, &
                               velocity_fold_signs, gauss_accumulate, gauss_solve, gauss_forces, &
                               gauss_velocity_gradient, gauss_strain, gauss_cell_components, &
                               gauss_solution_components
  use dpmpm_particles, only: particle_set_t
  use dpmpm_generate, only: generate_points
  use dpmpm_materials, only: material_t, materials_from_config, stress_update, strain_energy, &
                             wave_speed, voigt_to_tensor, model_neo_hookean, model_fluid, is_plastic
  use dpmpm_two_phase, only: fluid_p2g, interphase_p2g, solid_porosity_p2g, drag_solve, &
                             drag_limit, interp_scalar, pressure_update, fluid_density, &
                             drag_relax
  use dpmpm_migrate, only: migrate
  use dpmpm_output, only: output_t, output_h5_path
  use dpmpm_checkpoint, only: checkpoint_state_t, checkpoint_path, write_checkpoint, read_checkpoint
  use dpmpm_diagnostics, only: diag_record_t
  use dpmpm_scene_check, only: check_scene_points
  use dpmpm_posix, only: stop_signal, signal_name
  use dpmpm_two_phase_verify, only: two_phase_errors, two_phase_profiles, error_name_len
  use dpmpm_benchmarks, only: benchmark_setup, benchmark_errors, benchmark_error_names, nbench_err, &
                              benchmark_body_force, benchmark_nerr
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_INTEGER8, &
                     MPI_SUM, MPI_MAX, MPI_MIN, MPI_Wtime, MPI_Gather, MPI_Gatherv, MPI_INTEGER, &
                     MPI_MAXLOC, MPI_2DOUBLE_PRECISION, MPI_Bcast
  implicit none
  private
  public :: simulation_t, run_scene

  !> Steps between the collective looks at a stop request (signal, max_wall_time).
  integer(i8), parameter :: stop_every = 10
  !> Exit code of a run stopped early with a checkpoint to continue from.
  integer, parameter :: exit_stopped = 3

  !> Grid-transfer work arrays of one point set: per-point stencils, velocity
  !> gradients, the node fields of its phase, and (with Gauss quadrature) the
  !> reconstruction sums and solutions with the positions and volumes they used.
  type :: transfer_t
    ! Per-point stencil: first node, weights and x-derivatives per axis.
    integer, allocatable :: i0(:, :)
    real(wp), allocatable :: sw(:, :, :), sdw(:, :, :)
    real(wp), allocatable :: vgrad(:, :)      !< velocity gradient of the set's phase (9, n)
    real(wp), allocatable :: vgrad2(:, :)     !< fluid points: solid velocity gradient (9, n)
    ! Node fields on the stored nodes (owned + ghosts).
    real(wp), allocatable :: node(:, :, :, :) !< mass, momentum(nd), force(nd)
    real(wp), allocatable :: nvel(:, :, :, :) !< velocity before (nd) and after (nd) the update
    ! Gauss quadrature: reconstruction sums and solutions (cell arrays), velocity
    ! gradients at the Gauss points, positions and volumes at the force evaluation,
    ! effective point volumes. Fluid sets: gsol2 is the solid share -n_s p.
    real(wp), allocatable :: gacc(:, :, :, :), gsol(:, :, :, :), gsol2(:, :, :, :), glg(:, :, :, :)
    !> Fluid sets: the sums of the second field and the Gauss-point gradients of the
    !> second velocity, made in the same passes over the points as the first.
    real(wp), allocatable :: gacc2(:, :, :, :), glg2(:, :, :, :)
    real(wp), allocatable :: xold(:, :), volold(:), vt(:)
  end type transfer_t

  !> The state of a run.
  type :: simulation_t
    type(config_t) :: cfg
    type(decomp_t) :: dec
    type(grid_t) :: grid
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: solid
    type(particle_set_t) :: fluid             !< pore or free fluid (two-phase scenes only)
    logical :: two_phase = .false.            !< the scene has fluid points
    type(log_t) :: log
    type(timer_set_t) :: timers
    type(output_t) :: out
    logical :: write_output = .true.
    type(shape_plan_t) :: plan                !< grid functions and MLS choices (&shape)
    integer :: kernel = 1
    integer :: nw(3) = 1                      !< stencil nodes per axis
    type(transfer_t) :: ts                    !< transfer arrays of the solid points
    type(transfer_t) :: tf                    !< transfer arrays of the fluid points
    ! Two-phase node fields: sum N m_s n_f of the solid points (then the nodal
    ! porosity, 1 where there is no solid), and the drag coefficient D (kg/s).
    real(wp), allocatable :: nporo(:, :, :, :), ndrag(:, :, :, :)
    integer :: fbc(6) = 0                     !< resolved pore-fluid condition per face
    real(wp) :: kf_max = 0.0_wp, rhof_min = 0.0_wp !< stiffest, lightest pore fluid (CFL)
    real(wp) :: dt_wave = 0.0_wp, dt_drag = huge(1.0_wp) !< the two limits of the last step
    integer :: governing = 0                  !< limit that set the last step: 1 wave, 2 drag
    ! MLS nodal velocities (allocated only when the plan uses them).
    real(wp), allocatable :: vacc(:, :, :, :)
    real(wp), allocatable :: bacc(:, :)       !< body acceleration per point (manufactured solution)
    ! Occupancy of the Gauss cells (one component; see gauss_occupancy).
    real(wp), allocatable :: occ(:, :, :, :), occ2(:, :, :, :)
    integer :: fill = 1                       !< half-width of the occupancy closing (cells)
    type(mls_stats_t) :: mls_stats            !< fallback counts of the MLS solves on this rank
    integer(i8) :: nkept = 0                  !< point gradients left point-wise (no quadrature weight)
    integer(i8) :: nwall = 0                  !< points put back inside a wall they had crossed
    integer :: nd = 1
    real(wp) :: time = 0.0_wp
    real(wp) :: dt = 0.0_wp
    !> work of gravity and tractions on this rank, minus the energy dissipated by drag
    real(wp) :: ext_work = 0.0_wp
    integer(i8) :: step = 0
    real(wp) :: wall_start = 0.0_wp
    real(wp) :: wall_checkpoint = 0.0_wp      !< wall clock of the last checkpoint (or start)
    integer :: nframes = 0
    integer(i8) :: last_frame_step = -1       !< step of the last frame written
    real(wp) :: next_frame = 0.0_wp
    real(wp), allocatable :: err_hist(:, :)   !< benchmark errors over diagnostics (time, errors)
    integer :: nerr = 0
    !> Two-phase benchmarks: error names and their values at each frame (time, errors).
    character(len=error_name_len), allocatable :: fnames(:)
    real(wp), allocatable :: ferr(:, :)
    integer :: nferr = 0
    real(wp) :: energy0 = 0.0_wp              !< kinetic + strain - external work at the start
    real(wp) :: energy_scale = 0.0_wp         !< largest of |energy0| and kinetic + strain so far
    real(wp) :: energy_error = 0.0_wp         !< largest |energy - energy0| so far
    real(wp) :: energy_drift = 0.0_wp         !< energy_error / energy_scale
    !> why the last run stopped before t_end: a signal number, -1 for max_wall_time, 0 not
    integer :: stopped = 0
    ! Run monitor (doc/verification.md, "Long runs"): energies against the work done
    ! on the body and the energy it started with, not against the run's own maximum.
    real(wp) :: drag_loss = 0.0_wp            !< energy dissipated by drag on this rank
    logical :: monitor_started = .false.      !< the first record of this run was taken
    real(wp) :: mon_e0 = 0.0_wp               !< kinetic + stored energy at the first record
    real(wp) :: mon_w0 = 0.0_wp               !< work of the loads at the first record
    real(wp) :: mon_d0 = 0.0_wp               !< drag dissipation at the first record
    real(wp) :: mon_input = 0.0_wp            !< mon_e0 + largest |work of the loads| so far
    real(wp) :: mon_ratio = 0.0_wp            !< largest (kinetic + stored) / mon_input so far
    real(wp) :: mon_ke_max = 0.0_wp           !< largest kinetic energy at a record so far
    real(wp) :: mon_balance = 0.0_wp          !< largest |E + D - W - E0| / (input + D) so far
    logical :: mon_warned = .false.           !< the growth warning was given
    real(wp) :: mon_prev(4) = 0.0_wp          !< field maxima at the previous record
    real(wp) :: mon_prev_time = 0.0_wp        !< time of the previous record
  contains
    procedure :: init => sim_init
    procedure :: run => sim_run
    procedure :: advance => sim_advance
    procedure :: stable_dt => sim_stable_dt
    procedure :: diagnostics => sim_diagnostics
    procedure :: write_frame => sim_write_frame
    procedure :: gather_points => sim_gather_points
    procedure :: free => sim_free
  end type simulation_t

contains

  !> Build, run and finish the scene described by cfg on the ranks of comm.
  subroutine run_scene(cfg, comm)
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    type(simulation_t) :: sim
    logical :: stopped
    call sim%init(cfg, comm)
    call sim%run()
    stopped = sim%stopped /= 0
    call sim%free()
    if (stopped) call clean_stop(exit_stopped)
  end subroutine run_scene

  !> Decompose the grid, create the points, open the output.
  subroutine sim_init(self, cfg, comm, write_output)
    class(simulation_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    logical, intent(in), optional :: write_output
    integer :: nmin, nmax, nb, status
    integer(i8) :: ntot, nfl
    integer(i8), allocatable :: counts(:), fcounts(:)
    character(len=256) :: line
    call self%free()
    self%cfg = cfg
    self%write_output = .true.
    if (present(write_output)) self%write_output = write_output
    self%ext_work = 0.0_wp
    self%drag_loss = 0.0_wp
    self%monitor_started = .false.
    self%mon_ratio = 0.0_wp
    self%mon_ke_max = 0.0_wp
    self%mon_balance = 0.0_wp
    self%mon_warned = .false.
    self%mon_prev = 0.0_wp
    self%energy0 = 0.0_wp
    self%energy_scale = 0.0_wp
    self%energy_error = 0.0_wp
    self%energy_drift = 0.0_wp
    self%nframes = 0
    self%last_frame_step = -1
    self%next_frame = 0.0_wp
    self%nerr = 0
    call self%log%init(comm)
    self%wall_start = MPI_Wtime()
    self%wall_checkpoint = self%wall_start
    self%nd = cfg%ndim
    call self%plan%init(cfg)
    self%kernel = self%plan%grid_kernel
    self%nw = 1
    self%nw(1:self%nd) = kernel_width(self%kernel)
    self%mls_stats = mls_stats_t()
    self%nkept = 0
    self%nwall = 0
    call self%grid%init(cfg)
    call self%dec%init(comm, cfg%ndim, cfg%ncells, self%plan%ghost_width(), cfg%dims)
    call materials_from_config(cfg%materials, self%mats)
    self%two_phase = any(cfg%regions%phase /= 'solid')
    call self%solid%init('solid', self%nd, any(self%mats%model == model_neo_hookean), &
                         has_porosity=self%two_phase, has_plastic=any(is_plastic(self%mats%model)))
    if (self%two_phase) &
      call self%fluid%init('fluid', self%nd, .false., has_porosity=.true., has_pressure=.true.)
    if (len_trim(cfg%restart) > 0) then
      call restart_from(self, trim(cfg%restart))
    else
      allocate (counts(size(cfg%regions)), fcounts(size(cfg%regions)))
      fcounts = 0
      call generate_points(cfg, self%grid, self%dec%clo, self%dec%chi, self%mats, self%solid, &
                           counts=counts)
      call benchmark_setup(cfg, self%mats, self%solid)
      if (self%two_phase) then
        call generate_points(cfg, self%grid, self%dec%clo, self%dec%chi, self%mats, self%fluid, &
                             'fluid', fcounts)
        call check_scene_points(cfg, self%grid, self%dec%comm, counts + fcounts, self%solid, &
                                status, self%fluid)
      else
        call check_scene_points(cfg, self%grid, self%dec%comm, counts, self%solid, status)
      end if
      if (status /= 0) call clean_stop(status)
    end if
    if (self%two_phase) call init_two_phase(self)

    ntot = self%solid%n
    call MPI_Allreduce(MPI_IN_PLACE, ntot, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    call MPI_Allreduce(self%solid%n, nmin, 1, MPI_INTEGER, MPI_MIN, self%dec%comm)
    call MPI_Allreduce(self%solid%n, nmax, 1, MPI_INTEGER, MPI_MAX, self%dec%comm)
    write (line, '(a,i0,a,i0,a,i0,a,i0,a,i0,a,i0,a,i0)') 'dpmpm: ', self%dec%nranks, ' ranks (', &
      self%dec%dims(1), ' x ', self%dec%dims(2), ' x ', self%dec%dims(3), '); ', ntot, &
      ' solid points; per rank min ', nmin, ' max ', nmax
    call self%log%info(line)
    if (self%two_phase) then
      nfl = self%fluid%n
      call MPI_Allreduce(MPI_IN_PLACE, nfl, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
      write (line, '(a,i0,a,a)') 'dpmpm: ', nfl, ' fluid points; drag ', trim(cfg%drag)
      if (cfg%porosity_gradient) line = trim(line)//'; with the porosity-gradient term'
      call self%log%info(trim(line))
      ntot = ntot + nfl
    end if
    if (ntot == 0) then
      call self%log%error('the regions produced no points')
      call clean_stop(2)
    end if

    associate (lo => self%dec%alo, hi => self%dec%ahi)
      allocate (self%ts%node(1 + 2*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
      allocate (self%ts%nvel(2*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
      if (self%plan%velocity_mls) then
        nb = basis_size(self%plan%velocity_basis, self%nd)
        allocate (self%vacc(1 + packed_size(nb) + nb*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
      end if
      if (self%plan%gauss) then
        associate (ng => self%plan%ngauss, basis => self%plan%field_basis, nd => self%nd)
          allocate (self%ts%gacc(gauss_cell_components(nd, ng, basis), lo(1):hi(1), lo(2):hi(2), &
                              lo(3):hi(3)))
          allocate (self%ts%gsol(gauss_solution_components(nd, ng, basis), lo(1):hi(1), &
                              lo(2):hi(2), lo(3):hi(3)))
          allocate (self%ts%glg(ng**nd*nd*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        end associate
        allocate (self%occ(1, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (self%occ2, mold=self%occ)
        self%fill = max(1, min(floor(kernel_reach(self%plan%field_kernel, self%plan%field_radius, &
                                                  self%plan%field_radial) + 1.0e-9_wp), &
                               minval(self%dec%gw(1:self%nd))))
      end if
      if (self%two_phase) then
        allocate (self%tf%node, mold=self%ts%node)
        allocate (self%tf%nvel, mold=self%ts%nvel)
        allocate (self%nporo(1, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (self%ndrag(1, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        if (self%plan%gauss) then
          allocate (self%tf%gacc, mold=self%ts%gacc)
          allocate (self%tf%gsol, mold=self%ts%gsol)
          allocate (self%tf%gsol2, mold=self%ts%gsol)
          allocate (self%tf%glg, mold=self%ts%glg)
          allocate (self%tf%gacc2, mold=self%ts%gacc)
          allocate (self%tf%glg2, mold=self%ts%glg)
        end if
      end if
    end associate
    allocate (self%err_hist(1 + nbench_err, 64))
    if (len_trim(cfg%restart) == 0) then
      self%time = 0.0_wp
      self%step = 0
    end if
    self%dt = self%stable_dt()
    if (self%write_output) then
      call remove_stale_temporary(self)
      if (len_trim(cfg%restart) > 0) then
        call resume_output(self)
      else
        call announce_output(self)
        call self%out%open(self%cfg, self%dec%comm)
      end if
    end if
    call self%diagnostics()
    ! A restarted run keeps the frame schedule of the run it continues.
    if (len_trim(cfg%restart) == 0) call self%write_frame()
  end subroutine sim_init

  !> A <name>.ckpt.h5.tmp left by a run killed while writing its checkpoint is a torn copy
  !> (the checkpoint before it is whole): removed, and said.
  subroutine remove_stale_temporary(self)
    type(simulation_t), intent(in) :: self
    character(len=:), allocatable :: tmp
    logical :: exists
    integer :: u, ios
    if (.not. self%log%root) return
    tmp = checkpoint_path(self%cfg%output_dir, self%cfg%name)//'.tmp'
    inquire (file=tmp, exist=exists)
    if (.not. exists) return
    open (newunit=u, file=tmp, status='old', iostat=ios)
    if (ios == 0) close (u, status='delete', iostat=ios)
    if (ios == 0) then
      call self%log%info('dpmpm: removed '//tmp//', a checkpoint torn by an earlier run''s end')
    else
      call self%log%warning('cannot remove '//tmp//' (a torn checkpoint of an earlier run)')
    end if
  end subroutine remove_stale_temporary

  !> Say where the output goes, and warn when that replaces the file of an earlier run.
  subroutine announce_output(self)
    type(simulation_t), intent(in) :: self
    character(len=:), allocatable :: path
    logical :: exists
    path = trim(self%cfg%output_dir)//'/'//trim(self%cfg%name)//'.h5'
    call self%log%info('dpmpm: writing '//path)
    if (.not. self%log%root) return
    inquire (file=path, exist=exists)
    if (exists) call self%log%warning(path//' exists and is overwritten (another &run name '// &
                                      'or &output dir keeps it)')
  end subroutine announce_output

  !> Continue from a checkpoint: the points of this rank's cells, time, step, energy
  !> balance and frame schedule (the output file: resume_output).
  subroutine restart_from(self, path)
    type(simulation_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    type(checkpoint_state_t) :: st
    character(len=256) :: line
    character(len=:), allocatable :: problem
    associate (g => self%grid, c => self%cfg)
      if (self%two_phase) then
        call read_checkpoint(path, st, g%origin, g%h, self%dec%clo, self%dec%chi, g%ncells, &
                             c%length, problem, self%solid, self%fluid)
      else
        call read_checkpoint(path, st, g%origin, g%h, self%dec%clo, self%dec%chi, g%ncells, &
                             c%length, problem, self%solid)
      end if
    end associate
    ! Every rank read the same file and found the same problem.
    if (len(problem) > 0) then
      call self%log%error('restart: '//problem)
      call clean_stop(2)
    end if
    self%step = st%step
    self%time = st%time
    ! ext_work is kept per rank and summed in the diagnostics: the total goes to rank 0.
    self%ext_work = 0.0_wp
    if (self%dec%rank == 0) self%ext_work = st%ext_work
    self%energy0 = st%energy0
    self%energy_scale = st%energy_scale
    self%energy_error = st%energy_error
    if (st%energy_scale > 0.0_wp) self%energy_drift = st%energy_error/st%energy_scale
    self%next_frame = st%next_frame
    self%nframes = st%nframes
    self%last_frame_step = st%step
    write (line, '(a,a,a,i0,a,es12.5)') 'dpmpm: restart from ', path, ' at step ', st%step, &
      ', t = ', st%time
    call self%log%info(trim(line))
  end subroutine restart_from

  !> The output of a restarted run continues <name>.h5 of the run it continues: the frames
  !> and diagnostics up to the checkpoint are kept, what came after is written again.
  !> Where that file is missing or cannot be opened, the run writes <name>_from<step>.h5.
  subroutine resume_output(self)
    type(simulation_t), intent(inout) :: self
    character(len=:), allocatable :: why
    character(len=32) :: tag
    logical :: ok
    call self%out%resume(self%cfg, self%dec%comm, self%nframes, self%step, ok, why)
    if (ok) then
      write (tag, '(i0)') self%nframes
      call self%log%info('dpmpm: continuing '//output_h5_path(self%cfg)//' from its first '// &
                         trim(tag)//' frames (later frames of the earlier run are written again)')
      return
    end if
    write (tag, '(i0)') self%step
    self%cfg%name = trim(self%cfg%name)//'_from'//trim(tag)
    call self%log%info('dpmpm: '//why//': a new file instead')
    call announce_output(self)
    call self%out%open(self%cfg, self%dec%comm)
  end subroutine resume_output

  !> Write the checkpoint <output_dir>/<name>.ckpt.h5 (collective).
  subroutine write_state(self)
    type(simulation_t), intent(inout) :: self
    type(checkpoint_state_t) :: st
    character(len=:), allocatable :: path
    real(wp) :: work
    call self%timers%tic(t_output)
    call MPI_Allreduce(self%ext_work, work, 1, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    st = checkpoint_state_t(step=self%step, time=self%time, ext_work=work, &
                            energy0=self%energy0, energy_scale=self%energy_scale, &
                            energy_error=self%energy_error, next_frame=self%next_frame, &
                            nframes=self%nframes, ndim=self%nd, ncells=self%cfg%ncells, &
                            origin=self%cfg%origin, length=self%cfg%length)
    path = checkpoint_path(self%cfg%output_dir, self%cfg%name)
    if (self%two_phase) then
      call write_checkpoint(path, self%cfg%output_dir, self%dec%comm, st, self%solid, self%fluid)
    else
      call write_checkpoint(path, self%cfg%output_dir, self%dec%comm, st, self%solid)
    end if
    self%wall_checkpoint = MPI_Wtime()
    call self%timers%toc(t_output)
  end subroutine write_state

  !> Two-phase set-up: the pore-fluid condition of each face (drained at free
  !> faces, impermeable at fixed and roller faces unless given), and the stiffest
  !> and lightest fluid for the undrained wave speed of the time step.
  subroutine init_two_phase(self)
    type(simulation_t), intent(inout) :: self
    integer :: f, m
    character(len=256) :: line
    do f = 1, 2*self%nd
      self%fbc(f) = self%cfg%fluid_bc(f)
      if (self%fbc(f) == fbc_default) then
        self%fbc(f) = merge(fbc_drained, fbc_impermeable, self%grid%bc(f) == bc_free)
      end if
    end do
    self%kf_max = 0.0_wp
    self%rhof_min = huge(1.0_wp)
    do m = 1, size(self%mats)
      if (self%mats(m)%model /= model_fluid) cycle
      self%kf_max = max(self%kf_max, self%mats(m)%bulk_fluid)
      self%rhof_min = min(self%rhof_min, self%mats(m)%density)
    end do
    line = '  pore fluid at the faces:'
    do f = 1, 2*self%nd
      line = trim(line)//' '//face_names(f)//' '//trim(fbc_names(self%fbc(f)))
    end do
    call self%log%info(trim(line))
  end subroutine init_two_phase

  !> Conditions under which the fluid nodes beyond a face are folded: an
  !> impermeable face at a fixed or roller solid face is a plane of symmetry of
  !> the fluid (roller); elsewhere the fluid is free.
  pure function fluid_mirror_bc(self) result(bc)
    type(simulation_t), intent(in) :: self
    integer :: bc(6)
    integer :: f
    bc = bc_free
    do f = 1, 2*self%nd
      if (self%fbc(f) == fbc_impermeable .and. self%grid%bc(f) /= bc_free) bc(f) = bc_roller
    end do
  end function fluid_mirror_bc

  !> Fluid velocity components tied to the solid at node idx: the normal
  !> components at impermeable faces where the solid is free to move.
  pure function fluid_ties(self, idx) result(tie)
    type(simulation_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    logical :: tie(3)
    integer :: d, side, f
    tie = .false.
    do d = 1, self%nd
      do side = 1, 2
        f = 2*(d - 1) + side
        if (self%fbc(f) /= fbc_impermeable .or. self%grid%bc(f) /= bc_free) cycle
        if (side == 1 .and. idx(d) <= 0) tie(d) = .true.
        if (side == 2 .and. idx(d) >= self%grid%ncells(d)) tie(d) = .true.
      end do
    end do
  end function fluid_ties

  !> Step to t_end (or max_steps), with diagnostics, frames and progress lines.
  subroutine sim_run(self)
    class(simulation_t), intent(inout) :: self
    integer(i8) :: diag_every, nwall, step0
    logical :: checkpoint_due
    character(len=16) :: eta_text
    real(wp) :: last_progress, now, eta, dt, loop_start, time0, done
    character(len=256) :: line
    integer :: k
    self%stopped = 0
    diag_every = self%cfg%diag_every
    if (diag_every <= 0) diag_every = max(1_i8, int(self%cfg%t_end/self%dt/500.0_wp, i8))
    last_progress = MPI_Wtime()
    loop_start = last_progress
    time0 = self%time
    step0 = self%step
    call self%timers%tic(t_total)
    do while (self%time < self%cfg%t_end*(1.0_wp - 1.0e-12_wp) .and. self%step < self%cfg%max_steps)
      dt = min(self%stable_dt(), self%cfg%t_end - self%time)
      call self%advance(dt)
      self%dt = dt
      self%time = self%time + self%dt
      self%step = self%step + 1
      call check_state(self)
      ! With explicit drag the first step may be far shorter than the wave step.
      if (self%step == 1 .and. self%cfg%diag_every <= 0) &
        diag_every = max(1_i8, int(self%cfg%t_end/self%dt/500.0_wp, i8))
      if (mod(self%step, diag_every) == 0) call self%diagnostics()
      if (self%cfg%frame_interval > 0.0_wp .and. &
          self%time >= self%next_frame - 1.0e-9_wp*self%cfg%frame_interval) call self%write_frame()
      if (self%cfg%checkpoint_every > 0) then
        if (mod(self%step, int(self%cfg%checkpoint_every, i8)) == 0) call write_state(self)
      end if
      now = MPI_Wtime()
      if (now - last_progress >= self%cfg%progress_seconds) then
        last_progress = now
        ! The run ends at t_end or at max_steps, whichever comes first: the ETA follows the
        ! nearer one, at the pace of this run's steps so far.
        done = max((self%time - time0)/(self%cfg%t_end - time0), &
                   real(self%step - step0, wp)/real(self%cfg%max_steps - step0, wp))
        eta = (now - loop_start)*(1.0_wp - done)/max(done, tiny(1.0_wp))
        ! A fixed width keeps the leading zero of an ETA below 1 s (f0.1 drops it).
        write (eta_text, '(f16.1)') eta
        write (line, '(a,i0,a,es12.5,a,es10.3,a,f6.1,a)') 'step ', self%step, '  t = ', &
          self%time, '  dt = ', self%dt, '  ', 100.0_wp*max(self%time/self%cfg%t_end, &
          real(self%step, wp)/real(self%cfg%max_steps, wp)), &
          '%  ETA '//trim(adjustl(eta_text))//' s'
        call self%log%info(line)
      end if
      ! A run at its end finishes normally, whatever stop is asked (its last frame must stay:
      ! a continued run would have nothing left to write it).
      if (mod(self%step, stop_every) == 0 .and. self%time < self%cfg%t_end*(1.0_wp - 1.0e-12_wp) &
          .and. self%step < self%cfg%max_steps) then
        self%stopped = stop_request(self, checkpoint_due)
        if (self%stopped /= 0) exit
        if (checkpoint_due) call write_state(self)
      end if
    end do
    call self%timers%toc(t_total)
    ! Stopped early: the checkpoint first, of the state exactly as the loop left it.
    if (self%stopped /= 0) call write_state(self)
    if (mod(self%step, diag_every) /= 0) call self%diagnostics()
    if (self%last_frame_step /= self%step) call self%write_frame()
    ! The end state too, so that a finished run can be continued to a later t_end.
    if (self%cfg%checkpoint_every > 0 .and. self%stopped == 0) then
      if (mod(self%step, int(self%cfg%checkpoint_every, i8)) /= 0) call write_state(self)
    end if
    if (self%write_output .and. self%cfg%benchmark /= 'none') then
      call self%out%write_verification('time', self%err_hist(1, 1:self%nerr))
      do k = 1, benchmark_nerr(self%cfg%benchmark)
        call self%out%write_verification(trim(benchmark_error_names(k)), &
                                         self%err_hist(1 + k, 1:self%nerr))
        call self%out%write_verification_attr('max_'//trim(benchmark_error_names(k)), &
                                              maxval(self%err_hist(1 + k, 1:self%nerr)))
        call self%out%write_verification_attr('final_'//trim(benchmark_error_names(k)), &
                                              self%err_hist(1 + k, self%nerr))
        ! Time average over the records after the start (the paper's eq. 15 with
        ! diagnostics at every step).
        if (self%nerr > 1) call self%out%write_verification_attr('mean_'// &
          trim(benchmark_error_names(k)), sum(self%err_hist(1 + k, 2:self%nerr))/(self%nerr - 1))
      end do
      call self%out%write_verification_attr('steps', real(self%step, wp))
      call self%out%write_verification_attr('wall_time_step_loop', self%timers%acc(t_total))
    end if
    if (self%write_output .and. two_phase_benchmark(self)) call write_two_phase_verification(self)
    call report_mls(self)
    write (line, '(a,i0,a,es12.5,a,f0.2,a)') 'dpmpm: done, ', self%step, ' steps to t = ', &
      self%time, ' in ', MPI_Wtime() - self%wall_start, ' s'
    if (self%stopped /= 0) line = 'dpmpm: ended early, '//line(len('dpmpm: done, ') + 1:)
    call self%log%info(line)
    write (line, '(a,es10.3)') '  energy balance: largest change / largest kinetic + stored energy ', &
      self%energy_drift
    call self%log%info(line)
    write (line, '(a,es10.3,a,es10.3,a)') '  energy against the work done + initial energy: '// &
      'largest (kinetic + stored) / (work + initial) ', self%mon_ratio, ', largest balance error ', &
      self%mon_balance, ' (doc/verification.md, "Long runs")'
    call self%log%info(line)
    nwall = self%nwall
    call MPI_Allreduce(MPI_IN_PLACE, nwall, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    if (nwall > 0) call self%log%info('  points put back inside a wall they had crossed: '// &
                                      i8toa(nwall))
    do k = 2, ntimers
      write (line, '(a,a12,f10.3,a)') '  time in ', timer_names(k), self%timers%acc(k), ' s (rank 0)'
      call self%log%info(line)
    end do
    if (self%write_output) then
      call self%out%close()
      call self%log%info('dpmpm: output '//trim(self%cfg%output_dir)//'/'//trim(self%cfg%name)//'.h5')
    end if
    if (self%stopped /= 0) call report_stop(self)
  end subroutine sim_run

  !> Collective: a stop signal (SIGTERM, SIGUSR1: what batch schedulers send before the
  !> kill) on any rank, returned as its number, or -1 when max_wall_time is over; 0 to go on.
  !> checkpoint_due: checkpoint_seconds of wall time have passed since the last checkpoint.
  integer function stop_request(self, checkpoint_due) result(why)
    type(simulation_t), intent(in) :: self
    logical, intent(out) :: checkpoint_due
    integer :: req(3)
    real(wp) :: now
    now = MPI_Wtime()
    req = [stop_signal(), 0, 0]
    if (self%cfg%max_wall_time > 0.0_wp) then
      if (now - self%wall_start >= self%cfg%max_wall_time) req(2) = 1
    end if
    if (self%cfg%checkpoint_seconds > 0.0_wp) then
      if (now - self%wall_checkpoint >= self%cfg%checkpoint_seconds) req(3) = 1
    end if
    call MPI_Allreduce(MPI_IN_PLACE, req, 3, MPI_INTEGER, MPI_MAX, self%dec%comm)
    why = req(1)
    if (why == 0 .and. req(2) > 0) why = -1
    checkpoint_due = req(3) > 0
  end function stop_request

  !> Say why the run stopped before t_end and how to continue it.
  subroutine report_stop(self)
    type(simulation_t), intent(in) :: self
    character(len=:), allocatable :: why, path
    character(len=256) :: line
    if (self%stopped > 0) then
      why = 'on '//signal_name(self%stopped)
    else
      if (self%cfg%max_wall_time >= 1.0_wp) then
        write (line, '(f0.1)') self%cfg%max_wall_time
      else
        write (line, '(es9.2)') self%cfg%max_wall_time
      end if
      why = 'at max_wall_time = '//trim(adjustl(line))//' s'

    end if
    path = checkpoint_path(self%cfg%output_dir, self%cfg%name)
    write (line, '(a,i0,a,es12.5,a,es12.5)') ' at step ', self%step, ', t = ', self%time, &
      ' of t_end = ', self%cfg%t_end
    call self%log%info('dpmpm: stopped '//why//trim(line)//'; checkpoint '//path)
    call self%log%info('dpmpm: to continue, run the same input with restart = '''//path// &
                       ''' in &run, or with dpmpm --restart')
  end subroutine report_stop

  !> Does the run compare with a two-phase reference (column or Terzaghi)?
  logical function two_phase_benchmark(self)
    type(simulation_t), intent(in) :: self
    two_phase_benchmark = self%two_phase .and. (self%cfg%benchmark == 'biot_column' .or. &
                                                self%cfg%benchmark == 'terzaghi')
  end function two_phase_benchmark

  !> Errors against the two-phase reference at the current frame, kept for the
  !> output and logged (collective).
  subroutine record_two_phase_errors(self)
    type(simulation_t), intent(inout) :: self
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:), tmp(:, :)
    character(len=512) :: line
    integer :: k
    call two_phase_errors(self%cfg, self%mats, self%solid, self%fluid, self%time, self%dec%comm, &
                          names, values)
    if (.not. allocated(self%ferr)) then
      self%fnames = names
      allocate (self%ferr(1 + size(values), 8))
      self%nferr = 0
    end if
    if (self%nferr == size(self%ferr, 2)) then
      allocate (tmp(size(self%ferr, 1), 2*self%nferr))
      tmp(:, 1:self%nferr) = self%ferr
      call move_alloc(tmp, self%ferr)
    end if
    self%nferr = self%nferr + 1
    self%ferr(:, self%nferr) = [self%time, values]
    if (self%time <= 0.0_wp) return
    write (line, '(a,es11.4,a)') '  errors at t = ', self%time, ':'
    do k = 1, size(names)
      write (line, '(a,1x,a,1x,es10.3)') trim(line), trim(names(k)), values(k)
    end do
    call self%log%info(trim(line))
  end subroutine record_two_phase_errors

  !> /verification of a two-phase benchmark: the frame times, each error over the
  !> frames and at the last frame (final_<name>), and the reference profiles at
  !> the final time on 401 depths (profile_z, profile_p, profile_sigma_eff,
  !> profile_v_s, profile_v_f).
  subroutine write_two_phase_verification(self)
    type(simulation_t), intent(inout) :: self
    integer, parameter :: nz = 401
    character(len=17), parameter :: pnames(4) = [character(len=17) :: 'profile_p', &
      'profile_sigma_eff', 'profile_v_s', 'profile_v_f']
    real(wp) :: z(nz), fields(4, nz)
    integer :: k
    if (self%nferr == 0) return
    call self%out%write_verification('frame_time', self%ferr(1, 1:self%nferr))
    do k = 1, size(self%fnames)
      call self%out%write_verification(trim(self%fnames(k)), self%ferr(1 + k, 1:self%nferr))
      call self%out%write_verification_attr('final_'//trim(self%fnames(k)), &
                                            self%ferr(1 + k, self%nferr))
    end do
    call two_phase_profiles(self%cfg, self%mats, self%time, nz, z, fields)
    call self%out%write_verification('profile_z', z)
    do k = 1, 4
      call self%out%write_verification(trim(pnames(k)), fields(k, :))
    end do
  end subroutine write_two_phase_verification

  !> Log how often each MLS path was taken (summed over ranks) and store the
  !> counts as attributes of /verification when the run writes one.
  subroutine report_mls(self)
    type(simulation_t), intent(inout) :: self
    integer(i8) :: c(6)
    character(len=256) :: line
    character(len=16), parameter :: names(6) = [character(len=16) :: 'mls_full', 'mls_reduced', &
      'mls_regularised', 'mls_constant', 'mls_empty', 'strain_pointwise']
    integer :: k
    if (.not. (self%plan%velocity_mls .or. self%plan%gauss)) return
    c = [self%mls_stats%nfull, self%mls_stats%nreduced, self%mls_stats%nregularised, &
         self%mls_stats%nconstant, self%mls_stats%nempty, self%nkept]
    call MPI_Allreduce(MPI_IN_PLACE, c, 6, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    write (line, '(a,5(1x,i0),a,i0)') '  MLS solves: full, reduced basis, regularised, constant '// &
      'basis, empty:', c(1:5), '; point gradients left point-wise: ', c(6)
    call self%log%info(line)
    if (self%write_output .and. self%cfg%benchmark /= 'none') then
      do k = 1, 6
        call self%out%write_verification_attr(trim(names(k)), real(c(k), wp))
      end do
    end if
  end subroutine report_mls

  !> Stable step: Courant number times the smallest cell size over the fastest
  !> signal (wave speed plus point speed). A fixed dt above the critical step
  !> (Courant number 1) is refused.
  real(wp) function sim_stable_dt(self) result(dt)
    class(simulation_t), intent(inout) :: self
    real(wp) :: rate, c, crit, rho, nf
    integer :: p
    character(len=256) :: line
    rate = 0.0_wp
    do p = 1, self%solid%n
      rho = self%solid%mass(p)/self%solid%vol(p)
      c = wave_speed(self%mats(self%solid%mat(p)), rho)
      if (self%two_phase) then
        ! Undrained wave of the mixture, c_u^2 = (E_c + K_f/n) / rho_sat (physics.md 5).
        nf = self%solid%porosity(p)
        if (nf > 0.0_wp) c = sqrt((self%mats(self%solid%mat(p))%pwave + self%kf_max/nf)/ &
                                  (rho + nf*self%rhof_min))
      end if
      rate = max(rate, c + norm2(self%solid%v(:, p)))
    end do
    do p = 1, self%fluid%n
      associate (mat => self%mats(self%fluid%mat(p)))
        c = sqrt(mat%bulk_fluid/mat%density)
      end associate
      rate = max(rate, c + norm2(self%fluid%v(:, p)))
    end do
    call MPI_Allreduce(MPI_IN_PLACE, rate, 1, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    if (.not. ieee_is_finite(rate)) then
      call self%log%error('non-finite wave speed or velocity at step '//i8toa(self%step)// &
                          '; the run became unstable')
      call clean_stop(4)
    end if
    crit = minval(self%grid%h(1:self%nd))/rate
    if (self%cfg%dt > 0.0_wp) then
      if (self%cfg%dt > crit) then
        write (line, '(a,es11.4,a,es11.4,a,i0,a)') '&run dt = ', self%cfg%dt, &
          ' s is above the stable time step ', crit, ' s (Courant number 1) at step ', self%step, &
          '; use a smaller dt or dt = 0 for the automatic step'
        call self%log%error(line)
        call clean_stop(2)
      end if
      dt = self%cfg%dt
    else
      dt = self%cfg%cfl*crit
    end if
    self%dt_wave = dt
  end function sim_stable_dt

  !> One explicit step of length dt.
  subroutine sim_advance(self, dt)
    class(simulation_t), intent(inout) :: self
    real(wp), intent(inout) :: dt
    integer :: m, nlost, n
    real(wp) :: wplastic
    if (self%two_phase) then
      call advance_two_phase(self, dt)
      return
    end if
    n = self%solid%n
    call self%timers%tic(t_stencil)
    call compute_stencils(self, self%solid, self%ts)
    call self%timers%toc(t_stencil)

    call self%timers%tic(t_p2g)
    self%ts%node = 0.0_wp
    if (allocated(self%bacc)) then
      call benchmark_body_force(self%cfg, self%mats, self%solid, self%time, self%bacc)
      call p2g(self%nd, self%nw, n, self%ts%i0, self%ts%sw, self%ts%sdw, self%solid%mass, self%solid%v, &
               self%solid%vol, self%solid%stress, .not. self%plan%gauss, self%dec%alo, self%ts%node, &
               self%bacc)
    else
      call p2g(self%nd, self%nw, n, self%ts%i0, self%ts%sw, self%ts%sdw, self%solid%mass, self%solid%v, &
               self%solid%vol, self%solid%stress, .not. self%plan%gauss, self%dec%alo, self%ts%node)
    end if
    if (self%plan%gauss) call gauss_force_integrals(self, self%solid, self%ts, self%solid%stress, &
                                                    self%ts%gsol, self%ts%node)
    call fold_exterior(self, self%ts%node, 1)
    if (self%plan%velocity_mls) then
      self%vacc = 0.0_wp
      associate (pl => self%plan)
        call velocity_accumulate(self%nd, n, self%solid%x, self%solid%mass, self%solid%v, &
                                 self%grid%origin, self%grid%h, pl%velocity_kernel, &
                                 pl%velocity_radius, pl%velocity_radial, pl%velocity_basis, &
                                 self%dec%alo, self%vacc)
      end associate
      call fold_planes(self, self%vacc, velocity_signs(self), .true., self%grid%bc)
    end if
    call self%timers%toc(t_p2g)
    call self%timers%tic(t_halo)
    call self%dec%halo_sum(self%ts%node)
    if (self%plan%velocity_mls) call self%dec%halo_sum(self%vacc)
    call self%timers%toc(t_halo)

    call self%timers%tic(t_nodal)
    if (self%plan%velocity_mls) call velocity_solve(self%nd, self%plan%velocity_basis, &
      self%dec%alo, self%dec%olo, self%dec%ohi, self%vacc, self%ts%node, self%mls_stats)
    call nodal_update(self, dt)
    call self%timers%toc(t_nodal)
    call self%timers%tic(t_halo)
    call self%dec%halo_copy(self%ts%nvel)
    call unfold_exterior(self, self%ts%nvel)
    call self%timers%toc(t_halo)

    call self%timers%tic(t_g2p)
    call g2p(self%nd, self%nw, n, self%ts%i0, self%ts%sw, self%ts%sdw, self%dec%alo, self%ts%nvel, &
             self%cfg%flip, dt, self%solid%v, self%solid%x, self%ts%vgrad)
    if (self%cfg%scheme == 'musl') call musl_remap(self)
    if (self%plan%gauss) then
      ! Strain rates by the transpose of the quadrature force operator (physics.md 3.5).
      call gauss_point_gradients(self, self%solid, self%ts, self%ts%gsol, self%ts%nvel, self%ts%vgrad)
    end if
    call self%timers%toc(t_g2p)

    call self%timers%tic(t_stress)
    wplastic = 0.0_wp
    do m = 1, size(self%mats)
      call stress_update(self%mats(m), m, dt, self%solid%n, self%solid%mat, self%ts%vgrad, &
                         self%solid%stress, self%solid%vol, self%solid%vol0, self%solid%defgrad, &
                         self%solid%epsp, wplastic)
    end do
    ! The plastic work leaves the energy balance like the drag dissipation.
    self%ext_work = self%ext_work - wplastic
    call self%timers%toc(t_stress)

    call self%timers%tic(t_migrate)
    call check_inside(self, self%solid)
    call migrate(self%dec, self%grid%origin, self%grid%h, self%solid, nlost)
    if (nlost > 0) call fatal('points were lost in migration (moved more than one rank width in a step)', &
                              'migrate')
    call self%timers%toc(t_migrate)
  end subroutine sim_advance

  !> One step of the double-point scheme (physics.md 6; the 3.5 pair with Gauss
  !> quadrature). dt may shrink to the explicit-drag limit of this step's nodes.
  subroutine advance_two_phase(self, dt)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(inout) :: dt
    integer :: m, nlost, ns, nf, mbc(6)
    real(wp) :: wplastic
    real(wp), allocatable :: volb(:), pseudo(:, :), pseudo2(:, :), nval(:), ngrad(:, :), gnrel(:), kf(:)
    ns = self%solid%n
    nf = self%fluid%n
    mbc = fluid_mirror_bc(self)
    call self%timers%tic(t_stencil)
    call compute_stencils(self, self%solid, self%ts)
    call compute_stencils(self, self%fluid, self%tf)
    call self%timers%toc(t_stencil)

    call self%timers%tic(t_p2g)
    self%ts%node = 0.0_wp
    self%tf%node = 0.0_wp
    self%nporo = 0.0_wp
    self%ndrag = 0.0_wp
    call p2g(self%nd, self%nw, ns, self%ts%i0, self%ts%sw, self%ts%sdw, self%solid%mass, &
             self%solid%v, self%solid%vol, self%solid%stress, .not. self%plan%gauss, self%dec%alo, &
             self%ts%node)
    call p2g(self%nd, self%nw, nf, self%tf%i0, self%tf%sw, self%tf%sdw, self%fluid%mass, &
             self%fluid%v, self%fluid%vol, self%fluid%stress, .false., self%dec%alo, self%tf%node)
    call solid_porosity_p2g(self%nw, ns, self%ts%i0, self%ts%sw, self%solid%mass, &
                            self%solid%porosity, self%dec%alo, self%nporo)
    call fluid_p2g(self%nd, self%nw, nf, self%tf%i0, self%tf%sw, self%tf%sdw, self%fluid%mass, &
                   self%fluid%vol, self%fluid%porosity, self%fluid%pressure, self%fluid%kinv, &
                   .not. self%plan%gauss, self%dec%alo, self%ts%node, self%tf%node, self%ndrag)
    if (self%plan%gauss) then
      call gauss_force_integrals(self, self%solid, self%ts, self%solid%stress, self%ts%gsol, &
                                 self%ts%node)
      ! Pore pressure at the Gauss points from the fluid points: -n_f p on the
      ! fluid, -(1 - n_f) p on the solid (physics.md 3.5 step 5), in one pass.
      allocate (pseudo(6, nf), pseudo2(6, nf))
      pseudo = 0.0_wp
      pseudo2 = 0.0_wp
      do m = 1, 3
        pseudo(m, :) = -self%fluid%porosity(1:nf)*self%fluid%pressure(1:nf)
        pseudo2(m, :) = -(1.0_wp - self%fluid%porosity(1:nf))*self%fluid%pressure(1:nf)
      end do
      call gauss_force_integrals(self, self%fluid, self%tf, pseudo, self%tf%gsol, self%tf%node, &
                                 pseudo2, self%tf%gsol2, self%ts%node)
    end if
    call fold_exterior(self, self%ts%node, 1)
    call fold_exterior(self, self%nporo, 1)
    call fold_exterior(self, self%tf%node, 1, mbc)
    call fold_exterior(self, self%ndrag, 1, mbc)
    call self%timers%toc(t_p2g)
    call self%timers%tic(t_halo)
    call self%dec%halo_sum(self%ts%node)
    call self%dec%halo_sum(self%tf%node)
    call self%dec%halo_sum(self%nporo)
    call self%dec%halo_sum(self%ndrag)
    call self%timers%toc(t_halo)

    ! Porosity at the nodes, then at the fluid points (start-of-step positions,
    ! physics.md 6 step 5) with its gradient; the interphase force when asked for.
    call self%timers%tic(t_nodal)
    call nodal_porosity(self)
    call self%timers%toc(t_nodal)
    call self%timers%tic(t_halo)
    call self%dec%halo_copy(self%nporo)
    call unfold_exterior(self, self%nporo, nscalar=1)
    call self%timers%toc(t_halo)
    call self%timers%tic(t_g2p)
    allocate (nval(nf), ngrad(3, nf), gnrel(nf), kf(nf))
    call interp_scalar(self%nd, self%nw, nf, self%tf%i0, self%tf%sw, self%tf%sdw, self%dec%alo, &
                       self%nporo, nval, ngrad)
    self%fluid%porosity(1:nf) = min(1.0_wp, max(nval, 1.0e-6_wp))
    call self%timers%toc(t_g2p)
    if (self%cfg%porosity_gradient) call add_interphase_force(self, ngrad)

    call self%timers%tic(t_nodal)
    self%dt_drag = huge(1.0_wp)
    if (self%cfg%drag == 'explicit') then
      self%dt_drag = self%cfg%drag_safety*nodal_drag_limit(self)
      dt = min(dt, self%dt_drag)
    end if
    call report_governing(self, dt)
    call nodal_update_two_phase(self, dt)
    call self%timers%toc(t_nodal)
    call self%timers%tic(t_halo)
    call self%dec%halo_copy(self%ts%nvel)
    call unfold_exterior(self, self%ts%nvel)
    call self%dec%halo_copy(self%tf%nvel)
    call unfold_exterior(self, self%tf%nvel, bc=mbc)
    call self%timers%toc(t_halo)

    call self%timers%tic(t_g2p)
    call g2p(self%nd, self%nw, ns, self%ts%i0, self%ts%sw, self%ts%sdw, self%dec%alo, self%ts%nvel, &
             self%cfg%flip, dt, self%solid%v, self%solid%x, self%ts%vgrad)
    call g2p(self%nd, self%nw, nf, self%tf%i0, self%tf%sw, self%tf%sdw, self%dec%alo, self%tf%nvel, &
             self%cfg%flip, dt, self%fluid%v, self%fluid%x, self%tf%vgrad)
    if (self%cfg%scheme == 'musl') then
      call musl_remap_two_phase(self, dt)
    else
      call point_gradient(self%nd, self%nw, nf, self%tf%i0, self%tf%sw, self%tf%sdw, &
                          self%dec%alo, self%ts%nvel, self%tf%vgrad2)
    end if
    ! With the same nodal velocities as the point gradients (remapped under MUSL).
    gnrel = 0.0_wp
    if (self%cfg%porosity_gradient) call relative_flux(self, gnrel)
    if (self%plan%gauss) then
      call gauss_point_gradients(self, self%solid, self%ts, self%ts%gsol, self%ts%nvel, &
                                 self%ts%vgrad)
      call gauss_point_gradients(self, self%fluid, self%tf, self%tf%gsol, self%tf%nvel, &
                                 self%tf%vgrad, self%ts%nvel, self%tf%vgrad2)
    end if
    call self%timers%toc(t_g2p)

    call self%timers%tic(t_stress)
    ! Skeleton: effective stress, volume, and porosity from the volume change
    ! with incompressible grains, n' = 1 - (1 - n) V / V'.
    volb = self%solid%vol(1:ns)
    wplastic = 0.0_wp
    do m = 1, size(self%mats)
      if (self%mats(m)%model == model_fluid) cycle
      call stress_update(self%mats(m), m, dt, ns, self%solid%mat, self%ts%vgrad, &
                         self%solid%stress, self%solid%vol, self%solid%vol0, self%solid%defgrad, &
                         self%solid%epsp, wplastic)
    end do
    self%ext_work = self%ext_work - wplastic
    self%solid%porosity(1:ns) = 1.0_wp - (1.0_wp - self%solid%porosity(1:ns))*volb/ &
                                self%solid%vol(1:ns)
    ! Fluid: pore pressure (eq. 10), then the volume the point represents,
    ! V = m / (n rho_f(p)), and the stress -p I it exerts.
    do m = 1, nf
      kf(m) = self%mats(self%fluid%mat(m))%bulk_fluid
    end do
    call pressure_update(nf, dt, kf, self%fluid%porosity, self%tf%vgrad, self%tf%vgrad2, gnrel, &
                         self%fluid%pressure)
    do m = 1, nf
      associate (mat => self%mats(self%fluid%mat(m)))
        self%fluid%vol(m) = self%fluid%mass(m)/(self%fluid%porosity(m)* &
                            fluid_density(mat%density, mat%bulk_fluid, self%fluid%pressure(m)))
      end associate
      self%fluid%stress(1:3, m) = -self%fluid%pressure(m)
    end do
    call self%timers%toc(t_stress)

    call self%timers%tic(t_migrate)
    call check_inside(self, self%solid)
    call check_inside(self, self%fluid)
    call migrate(self%dec, self%grid%origin, self%grid%h, self%solid, nlost)
    if (nlost > 0) call fatal('points were lost in migration (moved more than one rank width in a step)', &
                              'migrate')
    call migrate(self%dec, self%grid%origin, self%grid%h, self%fluid, nlost)
    if (nlost > 0) call fatal('fluid points were lost in migration (moved more than one rank width '// &
                              'in a step)', 'migrate')
    call self%timers%toc(t_migrate)
  end subroutine advance_two_phase

  !> grad n . (v_f - v_s) at the fluid points from the new nodal velocities (the
  !> porosity-gradient term of eq. 10), discretised so that the whole bracket of
  !> eq. 10 is the divergence of the nodal mixture flux,
  !>   sum_I grad N_I . (n_I v_f,I + (1 - n_I) v_s,I),
  !> that is sum_I grad N_I . ((n_I - n_p)(v_f,I - v_s,I)). The flux form keeps
  !> one constraint per cell at steady seepage; the product grad n . w of two
  !> interpolated fields asks for a different one at each point of the cell
  !> where n jumps, and their pressures then drift apart.
  subroutine relative_flux(self, gnrel)
    type(simulation_t), intent(in) :: self
    real(wp), intent(out) :: gnrel(:)
    integer :: p, a, b, c, i, j, k, nd
    real(wp) :: g(3), np
    nd = self%nd
    do p = 1, self%fluid%n
      np = self%fluid%porosity(p)
      gnrel(p) = 0.0_wp
      do c = 1, self%nw(3)
        k = self%tf%i0(3, p) + c - 1
        do b = 1, self%nw(2)
          j = self%tf%i0(2, p) + b - 1
          do a = 1, self%nw(1)
            i = self%tf%i0(1, p) + a - 1
            g(1) = self%tf%sdw(a, 1, p)*self%tf%sw(b, 2, p)*self%tf%sw(c, 3, p)
            g(2) = self%tf%sw(a, 1, p)*self%tf%sdw(b, 2, p)*self%tf%sw(c, 3, p)
            g(3) = self%tf%sw(a, 1, p)*self%tf%sw(b, 2, p)*self%tf%sdw(c, 3, p)
            gnrel(p) = gnrel(p) + (self%nporo(1, i, j, k) - np)* &
                       dot_product(g(1:nd), self%tf%nvel(nd + 1:2*nd, i, j, k) - &
                                   self%ts%nvel(nd + 1:2*nd, i, j, k))
          end do
        end do
      end do
    end do
  end subroutine relative_flux

  !> Log which limit sets the time step when it changes (wave CFL or the drag
  !> limit of explicit drag), with both values.
  subroutine report_governing(self, dt)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    integer :: gov
    character(len=256) :: line
    gov = merge(2, 1, self%dt_drag < self%dt_wave)
    if (gov == self%governing) return
    self%governing = gov
    if (gov == 2) then
      write (line, '(a,i0,a,es10.3,a,es10.3,a)') 'step ', self%step, ': time step ', dt, &
        ' s set by the explicit drag (relative motion of the phases at the nodes); wave CFL ', &
        self%dt_wave, ' s'
    else if (self%cfg%drag == 'explicit') then
      write (line, '(a,i0,a,es10.3,a,es10.3,a)') 'step ', self%step, ': time step ', dt, &
        ' s set by the wave CFL (undrained wave); explicit-drag limit ', self%dt_drag, ' s'
    else
      write (line, '(a,i0,a,es10.3,a)') 'step ', self%step, ': time step ', dt, &
        ' s set by the wave CFL (undrained wave); implicit drag has no step limit'
    end if
    call self%log%info(trim(line))
  end subroutine report_governing

  !> Internal forces by Gauss quadrature of the stress-like field fields(6, :) of
  !> the points of ps, reconstructed by MLS (solution in sol), added to node;
  !> keeps the positions and volumes for the transposed strain operator.
  subroutine gauss_force_integrals(self, ps, tr, fields, sol, node, fields2, sol2, node2)
    type(simulation_t), intent(inout) :: self
    type(particle_set_t), intent(in) :: ps
    type(transfer_t), intent(inout) :: tr
    real(wp), intent(in) :: fields(:, :)
    real(wp), intent(inout) :: sol(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(inout) :: node(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    !> A second field of the same points (fluid: the solid's share of p), with its own
    !> reconstruction and nodes; the pass over the points and the occupancy are shared.
    real(wp), intent(in), optional :: fields2(:, :)
    real(wp), intent(inout), optional :: sol2(:, self%dec%alo(1):, self%dec%alo(2):, &
                                              self%dec%alo(3):)
    real(wp), intent(inout), optional :: node2(:, self%dec%alo(1):, self%dec%alo(2):, &
                                               self%dec%alo(3):)
    integer :: n
    logical :: two
    two = present(fields2) .and. present(sol2) .and. present(node2)
    n = ps%n
    tr%xold(:, 1:n) = ps%x(:, 1:n)
    tr%volold(1:n) = ps%vol(1:n)
    tr%gacc = 0.0_wp
    associate (pl => self%plan, clo => self%dec%clo, chi => self%dec%chi)
      if (two) then
        tr%gacc2 = 0.0_wp
        call gauss_accumulate(self%nd, n, ps%x, ps%vol, fields, self%grid%origin, self%grid%h, &
                              self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                              pl%field_radial, pl%field_basis, self%dec%alo, tr%gacc, fields2, &
                              tr%gacc2)
      else
        call gauss_accumulate(self%nd, n, ps%x, ps%vol, fields, self%grid%origin, self%grid%h, &
                              self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                              pl%field_radial, pl%field_basis, self%dec%alo, tr%gacc)
      end if
      call self%timers%tic(t_halo)
      call self%dec%halo_sum(tr%gacc)
      call gauss_occupancy(self, tr%gacc)
      if (two) then
        call self%dec%halo_sum(tr%gacc2)
        tr%gacc2(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)) = &
          tr%gacc(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3))
      end if
      call self%timers%toc(t_halo)
      call gauss_solve(self%nd, pl%ngauss, pl%field_basis, self%dec%alo, clo, chi, tr%gacc, sol, &
                       self%mls_stats)
      if (two) call gauss_solve(self%nd, pl%ngauss, pl%field_basis, self%dec%alo, clo, chi, &
                                tr%gacc2, sol2, self%mls_stats)
      call self%timers%tic(t_halo)
      call self%dec%halo_copy(sol)
      if (two) call self%dec%halo_copy(sol2)
      call self%timers%toc(t_halo)
      call gauss_forces(self%nd, pl%ngauss, pl%field_basis, self%kernel, self%grid%h, &
                        self%dec%alo, clo, chi, sol, node)
      if (two) call gauss_forces(self%nd, pl%ngauss, pl%field_basis, self%kernel, self%grid%h, &
                                 self%dec%alo, clo, chi, sol2, node2)
    end associate
  end subroutine gauss_force_integrals

  !> Occupied Gauss cells: acc(1, c) holds the point count of each owned cell on
  !> entry and 1 (occupied) or 0 on exit. A cell is occupied when it holds a
  !> point or when the closing (dilation, then erosion, by a box of half-width
  !> self%fill cells) fills it: scattered points leave cells empty inside the
  !> body (on W1's uniform scatter 13 of 100 cells hold no solid point, runs of
  !> up to 3 hold no fluid point), and a cell left out of the quadrature cuts the
  !> body there. A gap of more than 2 fill cells stays open, and the closing does
  !> not grow a body past its outermost occupied cells.
  subroutine gauss_occupancy(self, acc)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(inout) :: acc(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    associate (clo => self%dec%clo, chi => self%dec%chi)
      self%occ = 0.0_wp
      self%occ(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)) = &
        merge(1.0_wp, 0.0_wp, acc(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)) > 0.5_wp)
      call self%dec%halo_copy(self%occ)
      self%occ2 = 0.0_wp
      call occupancy_pass(self%nd, self%fill, .true., self%dec%alo, clo, chi, self%grid%ncells, &
                          self%occ, self%occ2)
      call self%dec%halo_copy(self%occ2)
      call occupancy_pass(self%nd, self%fill, .false., self%dec%alo, clo, chi, self%grid%ncells, &
                          self%occ2, self%occ)
      acc(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)) = &
        self%occ(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3))
    end associate
  end subroutine gauss_occupancy

  !> Point velocity gradients vgrad of the points of ps by the transpose of the
  !> quadrature force operator of their reconstruction sol, from the nodal
  !> velocities nvel (physics.md 3.5 step 7).
  subroutine gauss_point_gradients(self, ps, tr, sol, nvel, vgrad, nvel2, vgrad2)
    type(simulation_t), intent(inout) :: self
    type(particle_set_t), intent(in) :: ps
    type(transfer_t), intent(inout) :: tr
    real(wp), intent(in) :: sol(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: nvel(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(inout) :: vgrad(:, :)
    !> A second nodal velocity (fluid points: the solid's), transposed in the same pass.
    real(wp), intent(in), optional :: nvel2(:, self%dec%alo(1):, self%dec%alo(2):, &
                                            self%dec%alo(3):)
    real(wp), intent(inout), optional :: vgrad2(:, :)
    integer :: nkept
    call gauss_velocity_gradient(self%nd, self%plan%ngauss, self%kernel, self%grid%h, &
                                 self%dec%alo, self%dec%clo, self%dec%chi, sol, nvel, tr%glg)
    call self%dec%halo_copy(tr%glg)
    associate (pl => self%plan)
      if (present(nvel2) .and. present(vgrad2)) then
        call gauss_velocity_gradient(self%nd, pl%ngauss, self%kernel, self%grid%h, &
                                     self%dec%alo, self%dec%clo, self%dec%chi, sol, nvel2, tr%glg2)
        call self%dec%halo_copy(tr%glg2)
        call gauss_strain(self%nd, ps%n, tr%xold, tr%volold, self%grid%origin, self%grid%h, &
                          self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                          pl%field_radial, pl%field_basis, self%dec%alo, sol, tr%glg, vgrad, &
                          tr%vt, nkept, tr%glg2, vgrad2)
        ! Both gradients keep their point-wise value at the same points.
        nkept = 2*nkept
      else
        call gauss_strain(self%nd, ps%n, tr%xold, tr%volold, self%grid%origin, self%grid%h, &
                          self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                          pl%field_radial, pl%field_basis, self%dec%alo, sol, tr%glg, vgrad, &
                          tr%vt, nkept)
      end if
    end associate
    self%nkept = self%nkept + nkept
  end subroutine gauss_point_gradients

  !> Kernel weights and derivatives of every point of ps, evaluated once per step,
  !> with the per-point work arrays of tr sized to the set's capacity.
  subroutine compute_stencils(self, ps, tr)
    type(simulation_t), intent(inout) :: self
    type(particle_set_t), intent(in) :: ps
    type(transfer_t), intent(inout) :: tr
    integer :: p, d, n
    real(wp) :: y(3)
    n = ps%n
    if (.not. allocated(tr%i0)) then
      allocate (tr%i0(3, 0), tr%sw(max_stencil, 3, 0), tr%sdw(max_stencil, 3, 0))
    end if
    if (size(tr%i0, 2) < n) then
      deallocate (tr%i0, tr%sw, tr%sdw)
      allocate (tr%i0(3, ps%cap), tr%sw(max_stencil, 3, ps%cap), tr%sdw(max_stencil, 3, ps%cap))
      if (allocated(tr%vgrad)) deallocate (tr%vgrad)
      if (allocated(tr%vgrad2)) deallocate (tr%vgrad2)
      if (allocated(tr%xold)) deallocate (tr%xold, tr%volold, tr%vt)
    end if
    if (.not. allocated(tr%vgrad)) allocate (tr%vgrad(9, size(tr%i0, 2)))
    if (ps%has_pressure .and. .not. allocated(tr%vgrad2)) allocate (tr%vgrad2(9, size(tr%i0, 2)))
    if (self%plan%gauss .and. .not. allocated(tr%xold)) &
      allocate (tr%xold(self%nd, size(tr%i0, 2)), tr%volold(size(tr%i0, 2)), tr%vt(size(tr%i0, 2)))
    if (allocated(self%bacc) .and. .not. ps%has_pressure) then
      if (size(self%bacc, 2) < n) deallocate (self%bacc)
    end if
    if (self%cfg%benchmark == 'mms' .and. .not. allocated(self%bacc)) &
      allocate (self%bacc(self%nd, size(tr%i0, 2)))
    do p = 1, n
      y = 0.0_wp
      do d = 1, self%nd
        y(d) = (ps%x(d, p) - self%grid%origin(d))/self%grid%h(d)
      end do
      call psi_stencil(self%nd, self%kernel, y, self%grid%h, tr%i0(:, p), tr%sw(:, :, p), &
                       tr%sdw(:, :, p))
    end do
  end subroutine compute_stencils

  !> Particle to grid: mass, momentum and internal force -sum_p V_p sigma_p grad N_I.
  !> Point quadrature of the stress (point_forces) is skipped when the forces
  !> come from Gauss points; bacc adds a body acceleration per point as m_p N_I b_p.
  subroutine p2g(nd, nw, n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, bacc)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :)
    real(wp), intent(in) :: mass(:), v(:, :), vol(:), stress(:, :)
    logical, intent(in) :: point_forces
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in), optional :: bacc(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), s(3, 3), mv(3), fs(3), mb(3)
    do p = 1, n
      s = 0.0_wp
      if (point_forces) s = voigt_to_tensor(stress(:, p))
      mv = 0.0_wp
      mv(1:nd) = mass(p)*v(:, p)
      mb = 0.0_wp
      if (present(bacc)) mb(1:nd) = mass(p)*bacc(:, p)
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            nn = sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(1) = sdw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(2) = sw(a, 1, p)*sdw(b, 2, p)*sw(c, 3, p)
            g(3) = sw(a, 1, p)*sw(b, 2, p)*sdw(c, 3, p)
            fs = nn*mb - vol(p)*matmul(s, g)
            node(1, i, j, k) = node(1, i, j, k) + nn*mass(p)
            node(2:1 + nd, i, j, k) = node(2:1 + nd, i, j, k) + nn*mv(1:nd)
            node(2 + nd:1 + 2*nd, i, j, k) = node(2 + nd:1 + 2*nd, i, j, k) + fs(1:nd)
          end do
        end do
      end do
    end do
  end subroutine p2g

  !> Nodal velocities before and after the update, with gravity, tractions and
  !> boundary conditions, on the owned nodes.
  subroutine nodal_update(self, dt)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    integer :: i, j, k, nd
    real(wp) :: m, vold(3), vnew(3), fext(3)
    logical :: fix(3)
    nd = self%nd
    self%ts%nvel = 0.0_wp
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          m = self%ts%node(1, i, j, k)
          if (m <= 0.0_wp) cycle
          fix = self%grid%constrained([i, j, k])
          vold = 0.0_wp
          vold(1:nd) = self%ts%node(2:1 + nd, i, j, k)/m
          fext = m*self%cfg%gravity + face_traction(self, [i, j, k])
          vnew = 0.0_wp
          vnew(1:nd) = vold(1:nd) + dt*(self%ts%node(2 + nd:1 + 2*nd, i, j, k) + fext(1:nd))/m
          where (fix) vold = 0.0_wp
          where (fix) vnew = 0.0_wp
          self%ts%nvel(1:nd, i, j, k) = vold(1:nd)
          self%ts%nvel(nd + 1:2*nd, i, j, k) = vnew(1:nd)
          self%ext_work = self%ext_work + 0.5_wp*dt*dot_product(fext(1:nd), vold(1:nd) + vnew(1:nd))
        end do
      end do
    end do
  end subroutine nodal_update

  !> Nodal update of both phases on the owned nodes (physics.md 6 steps 7-8):
  !> forces, gravity, the total-stress traction (on the solid where there is
  !> solid) and the prescribed pore pressure of drained faces, the drag solve
  !> (explicit or implicit) where both phases meet, each phase alone elsewhere,
  !> and the per-phase conditions: solid fixed/roller components are zero; at
  !> impermeable faces the normal fluid velocity is zero (solid held) or the
  !> solid's (solid free: the mixture moves together in that component).
  subroutine nodal_update_two_phase(self, dt)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    integer :: i, j, k, nd, c, mbc(6)
    real(wp) :: ms, mf, dn, vs(3), vf(3), fs(3), ff(3), as, af, vsn(3), vfn(3), tr(3), fps(3), fpf(3), v
    logical :: sfix(3), ffix(3), tie(3), implicit
    nd = self%nd
    implicit = self%cfg%drag == 'implicit'
    mbc = fluid_mirror_bc(self)
    self%ts%nvel = 0.0_wp
    self%tf%nvel = 0.0_wp
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          ms = self%ts%node(1, i, j, k)
          mf = self%tf%node(1, i, j, k)
          dn = self%ndrag(1, i, j, k)
          if (ms <= 0.0_wp .and. mf <= 0.0_wp) cycle
          if (ms <= 0.0_wp .or. mf <= 0.0_wp) dn = 0.0_wp
          vs = 0.0_wp; vf = 0.0_wp; fs = 0.0_wp; ff = 0.0_wp
          tr = face_traction(self, [i, j, k])
          fps = face_pore_pressure(self, [i, j, k], self%grid%bc)
          fpf = face_pore_pressure(self, [i, j, k], mbc)
          if (ms > 0.0_wp) then
            vs(1:nd) = self%ts%node(2:1 + nd, i, j, k)/ms
            fs(1:nd) = self%ts%node(2 + nd:1 + 2*nd, i, j, k)
            fs = fs + ms*self%cfg%gravity + tr + self%nporo(1, i, j, k)*fps
          end if
          if (mf > 0.0_wp) then
            vf(1:nd) = self%tf%node(2:1 + nd, i, j, k)/mf
            ff(1:nd) = self%tf%node(2 + nd:1 + 2*nd, i, j, k)
            ff = ff + mf*self%cfg%gravity - self%nporo(1, i, j, k)*fpf
            if (ms <= 0.0_wp) ff = ff + tr
          end if
          sfix = self%grid%constrained([i, j, k])
          ffix = self%grid%constrained([i, j, k], mbc)
          tie = fluid_ties(self, [i, j, k])
          vsn = 0.0_wp; vfn = 0.0_wp
          do c = 1, nd
            if (ms > 0.0_wp .and. mf > 0.0_wp .and. tie(c)) then
              ! The mixture moves together normal to an impermeable face.
              v = (ms*vs(c) + mf*vf(c))/(ms + mf)
              vs(c) = v; vf(c) = v
              v = v + dt*(fs(c) + ff(c))/(ms + mf)
              vsn(c) = v; vfn(c) = v
            else if (ms > 0.0_wp .and. mf > 0.0_wp) then
              if (sfix(c)) then
                ! Solid held: the fluid moves against a resting skeleton.
                vs(c) = 0.0_wp
                af = (ff(c) - dn*vf(c))/merge(mf + dt*dn, mf, implicit)
              else
                call drag_solve(ms, mf, dn, fs(c), ff(c), vs(c), vf(c), dt, implicit, as, af)
                vsn(c) = vs(c) + dt*as
              end if
              vfn(c) = vf(c) + dt*af
            else if (ms > 0.0_wp) then
              vsn(c) = vs(c) + dt*fs(c)/ms
            else
              vfn(c) = vf(c) + dt*ff(c)/mf
            end if
            if (sfix(c)) then
              vs(c) = 0.0_wp; vsn(c) = 0.0_wp
            end if
            if (ffix(c)) then
              vf(c) = 0.0_wp; vfn(c) = 0.0_wp
            end if
            ! Energy dissipated by the drag: the drag force (at the old relative
            ! velocity w, or the new one when implicit) times the mid-step w, with
            ! the constrained velocities (a held phase does no work; a tied pair and
            ! a node with one phase, dn = 0, give none).
            v = dt*dn*merge(vfn(c) - vsn(c), vf(c) - vs(c), implicit)*0.5_wp*(vf(c) + vfn(c) - vs(c) - vsn(c))
            self%ext_work = self%ext_work - v
            self%drag_loss = self%drag_loss + v
          end do
          self%ts%nvel(1:nd, i, j, k) = vs(1:nd)
          self%ts%nvel(nd + 1:2*nd, i, j, k) = vsn(1:nd)
          self%tf%nvel(1:nd, i, j, k) = vf(1:nd)
          self%tf%nvel(nd + 1:2*nd, i, j, k) = vfn(1:nd)
          ! Work of the external forces (gravity, tractions, boundary pore pressure).
          if (ms > 0.0_wp) self%ext_work = self%ext_work + 0.5_wp*dt*dot_product( &
            ms*self%cfg%gravity(1:nd) + tr(1:nd) + self%nporo(1, i, j, k)*fps(1:nd), vs(1:nd) + vsn(1:nd))
          if (mf > 0.0_wp) self%ext_work = self%ext_work + 0.5_wp*dt*dot_product( &
            mf*self%cfg%gravity(1:nd) - self%nporo(1, i, j, k)*fpf(1:nd) + &
            merge(tr(1:nd), 0.0_wp*tr(1:nd), ms <= 0.0_wp), vf(1:nd) + vfn(1:nd))
        end do
      end do
    end do
  end subroutine nodal_update_two_phase

  !> Nodal porosity on the owned nodes: sum N_I m n_f over the nodal solid mass
  !> (1 where there is no solid).
  subroutine nodal_porosity(self)
    type(simulation_t), intent(inout) :: self
    integer :: i, j, k
    real(wp) :: ms
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          ms = self%ts%node(1, i, j, k)
          if (ms > 0.0_wp) then
            self%nporo(1, i, j, k) = self%nporo(1, i, j, k)/ms
          else
            self%nporo(1, i, j, k) = 1.0_wp
          end if
        end do
      end do
    end do
  end subroutine nodal_porosity

  !> The interphase force p grad n_f (eq. 2) at the nodes: added to the fluid's
  !> internal force and taken from the solid's (interphase_p2g), with grad n_f at
  !> the fluid points from the nodal porosity.
  subroutine add_interphase_force(self, ngrad)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: ngrad(:, :)
    real(wp), allocatable :: ff(:, :, :, :), fs(:, :, :, :)
    integer :: nd
    nd = self%nd
    allocate (ff(nd, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                 self%dec%alo(3):self%dec%ahi(3)))
    ff = 0.0_wp
    call interphase_p2g(nd, self%nw, self%fluid%n, self%tf%i0, self%tf%sw, self%fluid%vol, &
                        self%fluid%pressure, ngrad, self%dec%alo, ff)
    fs = -ff
    call fold_exterior(self, ff, 0, fluid_mirror_bc(self))
    call fold_exterior(self, fs, 0)
    call self%dec%halo_sum(ff)
    call self%dec%halo_sum(fs)
    self%tf%node(2 + nd:1 + 2*nd, :, :, :) = self%tf%node(2 + nd:1 + 2*nd, :, :, :) + ff
    self%ts%node(2 + nd:1 + 2*nd, :, :, :) = self%ts%node(2 + nd:1 + 2*nd, :, :, :) + fs
  end subroutine add_interphase_force

  !> Largest stable step of explicit drag over the owned nodes, from the summed
  !> node fields (collective: the minimum over all ranks).
  real(wp) function nodal_drag_limit(self) result(dtmin)
    type(simulation_t), intent(in) :: self
    integer :: i, j, k
    dtmin = huge(1.0_wp)
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          dtmin = min(dtmin, drag_limit(self%ts%node(1, i, j, k), self%tf%node(1, i, j, k), &
                                        self%ndrag(1, i, j, k)))
        end do
      end do
    end do
    call MPI_Allreduce(MPI_IN_PLACE, dtmin, 1, MPI_DOUBLE_PRECISION, MPI_MIN, self%dec%comm)
  end function nodal_drag_limit

  !> Nodal force of the &load tractions at node idx (zero away from the loaded
  !> faces): the traction, ramped over its ramp time, times the node's share of
  !> the face area.
  function face_traction(self, idx) result(fext)
    type(simulation_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    real(wp) :: fext(3)
    integer :: l, f
    real(wp) :: w
    fext = 0.0_wp
    do l = 1, size(self%cfg%loads)
      f = self%cfg%loads(l)%face
      w = face_weight(self, idx, f, self%grid%bc)
      if (w == 0.0_wp) cycle
      fext(1:self%nd) = fext(1:self%nd) + w*ramp_factor(self%time, self%cfg%loads(l)%ramp_time)* &
                        face_area(self, idx, (f + 1)/2)*self%cfg%loads(l)%traction(1:self%nd)
    end do
  end function face_traction

  !> Nodal force of the prescribed pore pressure p_b of drained faces at node idx
  !> (ramped over pore_pressure_ramp), per unit porosity: A p_b n_out, shared with
  !> the face conditions bc of the phase that takes it (face_weight). The solid
  !> takes n_f times it, the fluid minus n_f times it (the split of the total
  !> traction of the weak form, paper eq. 5).
  function face_pore_pressure(self, idx, bc) result(fp)
    type(simulation_t), intent(in) :: self
    integer, intent(in) :: idx(3), bc(6)
    real(wp) :: fp(3), w
    integer :: f, d
    fp = 0.0_wp
    do f = 1, 2*self%nd
      if (self%fbc(f) /= fbc_drained .or. self%cfg%pore_pressure(f) == 0.0_wp) cycle
      w = face_weight(self, idx, f, bc)
      if (w == 0.0_wp) cycle
      d = (f + 1)/2
      fp(d) = fp(d) + w*ramp_factor(self%time, self%cfg%pore_pressure_ramp(f))* &
              merge(-1.0_wp, 1.0_wp, mod(f, 2) == 1)*face_area(self, idx, d)*self%cfg%pore_pressure(f)
    end do
  end function face_pore_pressure

  !> Share of node idx in a load on grid face f: the grid function of the node at
  !> the face, Psi_I(x_face) along the face normal (zero for nodes beyond the grid
  !> along the other axes), so that a uniform face load balances the internal
  !> forces of a uniform stress node by node, as in the weak form; with linear
  !> grid functions only the face nodes carry it. Behind a fixed or roller face
  !> of bc (mirror-folded exterior nodes) the exterior share goes to the mirror
  !> image: the solid's conditions for the solid, fluid_mirror_bc for the fluid,
  !> which is free at a drained face even where the solid is held.
  real(wp) function face_weight(self, idx, f, bc) result(w)
    type(simulation_t), intent(in) :: self
    integer, intent(in) :: idx(3), f, bc(6)
    integer :: t, d, r
    real(wp) :: dw, wm
    d = (f + 1)/2
    w = 0.0_wp
    do t = 1, self%nd
      if (t /= d .and. (idx(t) < 0 .or. idx(t) > self%grid%ncells(t))) return
    end do
    if (mod(f, 2) == 1) then
      r = idx(d)
    else
      r = self%grid%ncells(d) - idx(d)
    end if
    if (bc(f) /= bc_free) then
      if (r < 0) return
      call bspline_1d(self%kernel, real(r, wp), w, dw)
      if (r > 0) then
        call bspline_1d(self%kernel, real(-r, wp), wm, dw)
        w = w + wm
      end if
    else
      call bspline_1d(self%kernel, real(r, wp), w, dw)
    end if
  end function face_weight

  !> Factor of a load ramped linearly from 0 over t_ramp (1 at once when t_ramp = 0).
  pure real(wp) function ramp_factor(t, t_ramp) result(r)
    real(wp), intent(in) :: t, t_ramp
    r = 1.0_wp
    if (t_ramp > 0.0_wp) r = min(1.0_wp, t/t_ramp)
  end function ramp_factor

  !> Share of the face area (normal to axis d) that node idx carries.
  real(wp) function face_area(self, idx, d)
    type(simulation_t), intent(in) :: self
    integer, intent(in) :: idx(3), d
    integer :: t
    face_area = 1.0_wp
    do t = 1, self%nd
      if (t == d) cycle
      face_area = face_area*self%grid%h(t)
      if (idx(t) == 0 .or. idx(t) == self%grid%ncells(t)) face_area = 0.5_wp*face_area
    end do
  end function face_area

  !> Grid to particle: FLIP/PIC blend of the velocity, position update with the
  !> new nodal velocity, and the velocity gradient from the new nodal velocity (USL).
  subroutine g2p(nd, nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), flip, dt
    real(wp), intent(inout) :: v(:, :), x(:, :), vgrad(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), dv(3), vn(3), lg(3, 3)
    do p = 1, n
      dv = 0.0_wp; vn = 0.0_wp; lg = 0.0_wp
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            nn = sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(1) = sdw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(2) = sw(a, 1, p)*sdw(b, 2, p)*sw(c, 3, p)
            g(3) = sw(a, 1, p)*sw(b, 2, p)*sdw(c, 3, p)
            vn(1:nd) = vn(1:nd) + nn*nvel(nd + 1:2*nd, i, j, k)
            dv(1:nd) = dv(1:nd) + nn*(nvel(nd + 1:2*nd, i, j, k) - nvel(1:nd, i, j, k))
            lg(1:nd, 1) = lg(1:nd, 1) + nvel(nd + 1:2*nd, i, j, k)*g(1)
            lg(1:nd, 2) = lg(1:nd, 2) + nvel(nd + 1:2*nd, i, j, k)*g(2)
            lg(1:nd, 3) = lg(1:nd, 3) + nvel(nd + 1:2*nd, i, j, k)*g(3)
          end do
        end do
      end do
      v(:, p) = flip*(v(:, p) + dv(1:nd)) + (1.0_wp - flip)*vn(1:nd)
      x(:, p) = x(:, p) + dt*vn(1:nd)
      vgrad(:, p) = reshape(lg, [9])
    end do
  end subroutine g2p

  !> MUSL (double mapping): map the updated point momenta back to the grid and
  !> take the velocity gradient from these smoother nodal velocities.
  subroutine musl_remap(self)
    type(simulation_t), intent(inout) :: self
    call remap_velocities(self, self%solid, self%ts, self%grid%bc)
    call self%dec%halo_copy(self%ts%nvel)
    call unfold_exterior(self, self%ts%nvel)
    call point_gradient(self%nd, self%nw, self%solid%n, self%ts%i0, self%ts%sw, self%ts%sdw, &
                        self%dec%alo, self%ts%nvel, self%ts%vgrad)
  end subroutine musl_remap

  !> The MUSL remap of both phases: solid and fluid nodal velocities from the
  !> updated point momenta, the fluid tied to the solid at impermeable faces, then
  !> the solid velocity gradient at the solid points and both at the fluid points.
  !> With implicit drag, where the drag locks the phases, the relative velocity the
  !> remap adds is shrunk as the step's drag would (relax_remapped): without it the
  !> step is unstable on scattered points (doc/verification.md, "Long runs").
  subroutine musl_remap_two_phase(self, dt)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    real(wp), allocatable :: wstep(:, :, :, :)
    ! Relative velocity of the nodal update, before the remap overwrites it.
    wstep = self%tf%nvel(self%nd + 1:2*self%nd, :, :, :) - self%ts%nvel(self%nd + 1:2*self%nd, :, :, :)
    call remap_velocities(self, self%solid, self%ts, self%grid%bc)
    call remap_velocities(self, self%fluid, self%tf, fluid_mirror_bc(self))
    call tie_fluid(self)
    if (self%cfg%remap_drag .and. self%cfg%drag == 'implicit') call relax_remapped(self, dt, wstep)
    call self%dec%halo_copy(self%ts%nvel)
    call unfold_exterior(self, self%ts%nvel)
    call self%dec%halo_copy(self%tf%nvel)
    call unfold_exterior(self, self%tf%nvel, bc=fluid_mirror_bc(self))
    call point_gradient(self%nd, self%nw, self%solid%n, self%ts%i0, self%ts%sw, self%ts%sdw, &
                        self%dec%alo, self%ts%nvel, self%ts%vgrad)
    call point_gradient(self%nd, self%nw, self%fluid%n, self%tf%i0, self%tf%sw, self%tf%sdw, &
                        self%dec%alo, self%tf%nvel, self%tf%vgrad)
    call point_gradient(self%nd, self%nw, self%fluid%n, self%tf%i0, self%tf%sw, self%tf%sdw, &
                        self%dec%alo, self%ts%nvel, self%tf%vgrad2)
  end subroutine musl_remap_two_phase

  !> The MUSL-remapped velocities of the nodes where both phases move freely
  !> (owned nodes, new-velocity slots): where the drag locks the phases, the
  !> relative velocity the remap adds to that of the nodal update (wstep) is
  !> shrunk as the step's implicit drag would (drag_relax).
  !> Each point set projects the same nodal increments with its own masses, so
  !> the plain remap leaves a relative velocity of the phases that no drag has
  !> acted on; fed to the strain and pore-pressure rates it makes the
  !> amplification of the step exceed 1 once the drag couples the phases.
  subroutine relax_remapped(self, dt, wstep)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    real(wp), intent(in) :: wstep(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer :: i, j, k, c, nd
    logical :: sfix(3), ffix(3), tie(3)
    nd = self%nd
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          if (self%ts%node(1, i, j, k) <= 0.0_wp .or. self%tf%node(1, i, j, k) <= 0.0_wp) cycle
          sfix = self%grid%constrained([i, j, k])
          ffix = self%grid%constrained([i, j, k], fluid_mirror_bc(self))
          tie = fluid_ties(self, [i, j, k])
          do c = 1, nd
            if (sfix(c) .or. ffix(c) .or. tie(c)) cycle
            call drag_relax(self%ts%node(1, i, j, k), self%tf%node(1, i, j, k), &
                            self%ndrag(1, i, j, k), dt, wstep(c, i, j, k), self%ts%nvel(nd + c, i, j, k), &
                            self%tf%nvel(nd + c, i, j, k))
          end do
        end do
      end do
    end do
  end subroutine relax_remapped

  !> Set the fluid velocity components tied to the solid (fluid_ties) to the solid's
  !> on the owned nodes, in the new-velocity slots of nvel.
  subroutine tie_fluid(self)
    type(simulation_t), intent(inout) :: self
    integer :: i, j, k, nd
    logical :: tie(3)
    nd = self%nd
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          tie = fluid_ties(self, [i, j, k])
          if (.not. any(tie)) cycle
          if (self%ts%node(1, i, j, k) <= 0.0_wp .or. self%tf%node(1, i, j, k) <= 0.0_wp) cycle
          where (tie(1:nd)) self%tf%nvel(nd + 1:2*nd, i, j, k) = self%ts%nvel(nd + 1:2*nd, i, j, k)
        end do
      end do
    end do
  end subroutine tie_fluid

  !> Nodal velocities (new slots of tr%nvel, owned nodes) from the point momenta
  !> of ps mapped to the grid again; the masses in tr%node are those of the step.
  !> Components held by the face conditions bc are zero.
  subroutine remap_velocities(self, ps, tr, bc)
    type(simulation_t), intent(inout) :: self
    type(particle_set_t), intent(in) :: ps
    type(transfer_t), intent(inout) :: tr
    integer, intent(in) :: bc(6)
    integer :: p, a, b, c, i, j, k, nd
    real(wp) :: nn, m
    logical :: fix(3)
    nd = self%nd
    ! Reuse the momentum slots of node(); the masses are unchanged.
    tr%node(2:1 + 2*nd, :, :, :) = 0.0_wp
    do p = 1, ps%n
      do c = 1, self%nw(3)
        k = tr%i0(3, p) + c - 1
        do b = 1, self%nw(2)
          j = tr%i0(2, p) + b - 1
          do a = 1, self%nw(1)
            i = tr%i0(1, p) + a - 1
            nn = tr%sw(a, 1, p)*tr%sw(b, 2, p)*tr%sw(c, 3, p)
            tr%node(2:1 + nd, i, j, k) = tr%node(2:1 + nd, i, j, k) + nn*ps%mass(p)*ps%v(:, p)
          end do
        end do
      end do
    end do
    call fold_exterior(self, tr%node, 1, bc)
    call self%dec%halo_sum(tr%node)
    tr%nvel = 0.0_wp
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          m = tr%node(1, i, j, k)
          if (m <= 0.0_wp) cycle
          fix = self%grid%constrained([i, j, k], bc)
          tr%nvel(nd + 1:2*nd, i, j, k) = tr%node(2:1 + nd, i, j, k)/m
          where (fix(1:nd)) tr%nvel(nd + 1:2*nd, i, j, k) = 0.0_wp
        end do
      end do
    end do
  end subroutine remap_velocities

  !> Velocity gradients of the points, sum_I v_I (x) grad N_I from the new nodal
  !> velocities nvel(nd+1:2nd), as 3x3 column-major.
  subroutine point_gradient(nd, nw, n, i0, sw, sdw, lo, nvel, vgrad)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: vgrad(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: g(3), lg(3, 3)
    do p = 1, n
      lg = 0.0_wp
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            g(1) = sdw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(2) = sw(a, 1, p)*sdw(b, 2, p)*sw(c, 3, p)
            g(3) = sw(a, 1, p)*sw(b, 2, p)*sdw(c, 3, p)
            lg(1:nd, 1) = lg(1:nd, 1) + nvel(nd + 1:2*nd, i, j, k)*g(1)
            lg(1:nd, 2) = lg(1:nd, 2) + nvel(nd + 1:2*nd, i, j, k)*g(2)
            lg(1:nd, 3) = lg(1:nd, 3) + nvel(nd + 1:2*nd, i, j, k)*g(3)
          end do
        end do
      end do
      vgrad(:, p) = reshape(lg, [9])
    end do
  end subroutine point_gradient

  !> Sign of vector component c under reflection in the face of axis d with
  !> condition bc: a fixed wall mirrors every component oddly (zero velocity on
  !> the wall), a roller only the normal one (a plane of symmetry).
  pure real(wp) function mirror_sign(bc, d, c) result(sg)
    integer, intent(in) :: bc, d, c
    sg = 1.0_wp
    if (bc == bc_fixed .or. c == d) sg = -1.0_wp
  end function mirror_sign

  !> Per-face signs of the components of a field with nscalar scalars followed
  !> by vectors of nd components, under reflection in each face (mirror_sign).
  function scalar_vector_signs(self, ncomp, nscalar, bc) result(sg)
    type(simulation_t), intent(in) :: self
    integer, intent(in) :: ncomp, nscalar, bc(6)
    real(wp) :: sg(ncomp, 6)
    integer :: f, c
    sg = 1.0_wp
    do f = 1, 2*self%nd
      do c = nscalar + 1, ncomp
        sg(c, f) = mirror_sign(bc(f), (f + 1)/2, mod(c - nscalar - 1, self%nd) + 1)
      end do
    end do
  end function scalar_vector_signs

  !> Per-face signs of the nodal velocity moment sums (count, moments, right-hand sides).
  function velocity_signs(self) result(sg)
    type(simulation_t), intent(in) :: self
    real(wp) :: sg(size(self%vacc, 1), 6)
    real(wp) :: vsign(3)
    integer :: f, c, d
    sg = 1.0_wp
    do f = 1, 2*self%nd
      d = (f + 1)/2
      do c = 1, self%nd
        vsign(c) = mirror_sign(self%grid%bc(f), d, c)
      end do
      call velocity_fold_signs(self%nd, self%plan%velocity_basis, d, vsign(1:self%nd), sg(:, f))
    end do
  end function velocity_signs

  !> Fold the exterior nodes beyond fixed and roller faces onto their mirror
  !> images inside the grid (node -k onto +k, ncells+k onto ncells-k), as if the
  !> points had mirror images behind the wall. Scalars (the first nscalar
  !> components) fold evenly, vector components with mirror_sign. Linear in f,
  !> so it is applied before halo_sum on every rank that stores exterior nodes.
  !> bc replaces the grid's face conditions (the fluid's, fluid_mirror_bc).
  subroutine fold_exterior(self, f, nscalar, bc)
    type(simulation_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer, intent(in) :: nscalar
    integer, intent(in), optional :: bc(6)
    integer :: bcs(6)
    bcs = self%grid%bc
    if (present(bc)) bcs = bc
    call fold_planes(self, f, scalar_vector_signs(self, size(f, 1), nscalar, bcs), .true., bcs)
  end subroutine fold_exterior

  !> Set the exterior nodes from their mirror images (the inverse of fold_exterior
  !> for velocities), after halo_copy so that the images are present.
  subroutine unfold_exterior(self, f, nscalar, bc)
    type(simulation_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer, intent(in), optional :: nscalar
    integer, intent(in), optional :: bc(6)
    integer :: bcs(6), ns
    bcs = self%grid%bc
    if (present(bc)) bcs = bc
    ns = 0
    if (present(nscalar)) ns = nscalar
    call fold_planes(self, f, scalar_vector_signs(self, size(f, 1), ns, bcs), .false., bcs)
  end subroutine unfold_exterior

  !> The plane loop of fold_exterior (fold: exterior added onto its image and
  !> cleared) and unfold_exterior (exterior set from its image), with the
  !> component signs sg(:, face) of each fixed or roller face.
  subroutine fold_planes(self, f, sg, fold, bc)
    type(simulation_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: sg(:, :)
    logical, intent(in) :: fold
    integer, intent(in) :: bc(6)
    integer :: d, side, k, ext, img, face
    do d = 1, self%nd
      do side = 1, 2
        face = 2*(d - 1) + side
        if (bc(face) == bc_free) cycle
        do k = 1, self%dec%gw(d)
          if (side == 1) then
            ext = -k; img = k
          else
            ext = self%grid%ncells(d) + k; img = self%grid%ncells(d) - k
          end if
          if (ext < self%dec%alo(d) .or. ext > self%dec%ahi(d)) cycle
          if (img < self%dec%alo(d) .or. img > self%dec%ahi(d)) cycle
          if (fold) then
            call plane_op(f, d, ext - self%dec%alo(d) + 1, img - self%dec%alo(d) + 1, sg(:, face), .true.)
          else
            call plane_op(f, d, img - self%dec%alo(d) + 1, ext - self%dec%alo(d) + 1, sg(:, face), .false.)
          end if
        end do
      end do
    end do
  end subroutine fold_planes

  !> On planes normal to axis d (1-based indices ia, ib of the array): with
  !> accumulate, f(ib) += sg f(ia) and f(ia) = 0; otherwise f(ib) = sg f(ia).
  subroutine plane_op(f, d, a, b, sg, accumulate)
    real(wp), intent(inout) :: f(:, :, :, :)
    integer, intent(in) :: d, a, b
    real(wp), intent(in) :: sg(:)
    logical, intent(in) :: accumulate
    integer :: la(3), ha(3), lb(3), hb(3), c
    la = 1
    ha = [size(f, 2), size(f, 3), size(f, 4)]
    lb = la
    hb = ha
    la(d) = a; ha(d) = a
    lb(d) = b; hb(d) = b
    do c = 1, size(f, 1)
      associate (fa => f(c, la(1):ha(1), la(2):ha(2), la(3):ha(3)), &
                 fb => f(c, lb(1):hb(1), lb(2):hb(2), lb(3):hb(3)))
        if (accumulate) then
          fb = fb + sg(c)*fa
          fa = 0.0_wp
        else
          fb = sg(c)*fa
        end if
      end associate
    end do
  end subroutine plane_op

  !> Points that crossed a fixed or roller face (walls are impenetrable) are put
  !> back just inside it and counted; wide kernels interpolate a small normal
  !> velocity next to a wall. A point beyond a free face stops the run with its id.
  subroutine check_inside(self, ps)
    type(simulation_t), intent(inout) :: self
    type(particle_set_t), intent(inout) :: ps
    integer :: p, d, side
    real(wp) :: wall(2), eps
    character(len=256) :: msg
    do p = 1, ps%n
      if (self%grid%inside(ps%x(:, p))) cycle
      do d = 1, self%nd
        wall = [self%grid%origin(d), self%grid%origin(d) + self%grid%ncells(d)*self%grid%h(d)]
        eps = 1.0e-9_wp*self%grid%h(d)
        do side = 1, 2
          if (self%grid%bc(2*(d - 1) + side) == bc_free) cycle
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
  end subroutine check_inside

  !> Global diagnostics at the current step (collective).
  subroutine sim_diagnostics(self)
    class(simulation_t), intent(inout) :: self
    type(diag_record_t) :: rec
    real(wp) :: s(9), vmax, err(nbench_err), fm(4)
    real(wp), allocatable :: tmp(:, :)
    integer :: p, m
    s = 0.0_wp
    vmax = 0.0_wp
    do p = 1, self%solid%n
      s(1) = s(1) + 0.5_wp*self%solid%mass(p)*sum(self%solid%v(:, p)**2)
      s(4) = s(4) + self%solid%mass(p)
      s(5:4 + self%nd) = s(5:4 + self%nd) + self%solid%mass(p)*self%solid%v(:, p)
      vmax = max(vmax, norm2(self%solid%v(:, p)))
    end do
    do m = 1, size(self%mats)
      if (self%mats(m)%model == model_fluid) cycle
      s(2) = s(2) + strain_energy(self%mats(m), m, self%solid%n, self%solid%mat, self%solid%stress, &
                                  self%solid%vol, self%solid%vol0, self%solid%defgrad)
    end do
    if (self%two_phase) then
      do p = 1, self%fluid%n
        s(1) = s(1) + 0.5_wp*self%fluid%mass(p)*sum(self%fluid%v(:, p)**2)
        s(4) = s(4) + self%fluid%mass(p)
        s(5:4 + self%nd) = s(5:4 + self%nd) + self%fluid%mass(p)*self%fluid%v(:, p)
        vmax = max(vmax, norm2(self%fluid%v(:, p)))
        ! Stored energy of the compressed pore fluid, n p^2 / (2 K_f) per mixture volume.
        s(2) = s(2) + 0.5_wp*self%fluid%porosity(p)*self%fluid%pressure(p)**2/ &
               self%mats(self%fluid%mat(p))%bulk_fluid*self%fluid%vol(p)
      end do
      s(8) = s(8) + real(self%fluid%n, wp)
    end if
    s(3) = self%ext_work
    s(8) = s(8) + real(self%solid%n, wp)
    s(9) = self%drag_loss
    call MPI_Allreduce(MPI_IN_PLACE, s, 9, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    do m = 1, 4
      fm(m) = field_max(self, m)
    end do
    call MPI_Allreduce(MPI_IN_PLACE, fm, 4, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    call MPI_Allreduce(MPI_IN_PLACE, vmax, 1, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    rec%step = self%step
    rec%npoints = nint(s(8), i8)
    rec%values = [self%time, self%dt, s(1), s(2), s(3), vmax, MPI_Wtime() - self%wall_start, &
                  s(4), s(5), s(6), s(7)]
    if (self%write_output) call self%out%add_diag(rec)
    ! Energy balance: kinetic + strain - external work stays at its initial value;
    ! its largest change is measured relative to the largest kinetic + stored
    ! energy seen so far; a ratio taken step by step would be ruled by the first
    ! steps of a step load, when little energy is stored yet.
    if (self%step == 0) self%energy0 = s(1) + s(2) - s(3)
    self%energy_scale = max(self%energy_scale, abs(self%energy0), s(1) + s(2))
    self%energy_error = max(self%energy_error, abs(s(1) + s(2) - s(3) - self%energy0))
    if (self%energy_scale > 0.0_wp) self%energy_drift = self%energy_error/self%energy_scale
    call monitor_energy(self, s(1), s(2), s(3) + s(9), s(9), fm)
    if (self%cfg%benchmark /= 'none') then
      err = benchmark_errors(self%cfg, self%mats, self%solid, self%time, self%dec%comm)
      if (self%nerr == size(self%err_hist, 2)) then
        allocate (tmp(size(self%err_hist, 1), 2*self%nerr))
        tmp(:, 1:self%nerr) = self%err_hist
        call move_alloc(tmp, self%err_hist)
      end if
      self%nerr = self%nerr + 1
      self%err_hist(:, self%nerr) = [self%time, err]
    end if
  end subroutine sim_diagnostics

  !> Largest value over this rank's points of monitored field m: 1 speed of the
  !> solid points, 2 speed of the fluid points, 3 largest |component| of the
  !> effective stress, 4 |pore pressure| (0 where a set is absent).
  real(wp) function field_max(self, m) result(f)
    type(simulation_t), intent(in) :: self
    integer, intent(in) :: m
    integer :: p
    f = 0.0_wp
    select case (m)
    case (1)
      do p = 1, self%solid%n
        f = max(f, norm2(self%solid%v(:, p)))
      end do
    case (2)
      if (.not. self%two_phase) return
      do p = 1, self%fluid%n
        f = max(f, norm2(self%fluid%v(:, p)))
      end do
    case (3)
      do p = 1, self%solid%n
        f = max(f, maxval(abs(self%solid%stress(:, p))))
      end do
    case (4)
      if (.not. self%two_phase) return
      do p = 1, self%fluid%n
        f = max(f, abs(self%fluid%pressure(p)))
      end do
    end select
  end function field_max

  !> The run monitor at a diagnostics record (collective; ke, se, w, d global sums
  !> of kinetic and stored energy, work of loads and gravity, drag dissipation
  !> since t = 0; fm the field maxima of field_max). The scale is what the body
  !> was given: its kinetic + stored energy at the first record plus the largest
  !> |work of the loads| since then. Kinetic + stored energy above growth_limit
  !> times that scale cannot come from the loads: the run is stopped, with a
  !> warning first at a fifth of it.
  subroutine monitor_energy(self, ke, se, w, d, fm)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: ke, se, w, d, fm(4)
    real(wp) :: ratio, wl, dl
    self%mon_ke_max = max(self%mon_ke_max, ke)
    if (.not. self%monitor_started) then
      self%monitor_started = .true.
      self%mon_e0 = ke + se
      self%mon_w0 = w
      self%mon_d0 = d
      self%mon_input = ke + se
      self%mon_prev = fm
      self%mon_prev_time = self%time
      return
    end if
    wl = w - self%mon_w0
    dl = d - self%mon_d0
    self%mon_input = max(self%mon_input, self%mon_e0 + abs(wl))
    if (self%mon_input <= 0.0_wp) then
      self%mon_prev = fm
      self%mon_prev_time = self%time
      return
    end if
    ratio = (ke + se)/self%mon_input
    self%mon_ratio = max(self%mon_ratio, ratio)
    self%mon_balance = max(self%mon_balance, abs(ke + se + dl - wl - self%mon_e0)/(self%mon_input + dl))
    if (self%cfg%growth_limit > 0.0_wp) then
      if (ratio > self%cfg%growth_limit) then
        call report_growth(self, fm, ratio, .true.)
      else if (ratio > 0.2_wp*self%cfg%growth_limit .and. .not. self%mon_warned) then
        self%mon_warned = .true.
        call report_growth(self, fm, ratio, .false.)
      end if
    end if
    self%mon_prev = fm
    self%mon_prev_time = self%time
  end subroutine monitor_energy

  !> Name the growing field (the monitored field whose maximum grew most since
  !> the previous record), the point that holds its largest value (id, set,
  !> position, cell) and the time; warn, or (stop) write a last frame and stop
  !> with code 3 (collective).
  subroutine report_growth(self, fm, ratio, stop)
    type(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: fm(4), ratio
    logical, intent(in) :: stop
    character(len=*), parameter :: fnames(4) = [character(len=20) :: 'velocity', 'velocity', &
      'effective stress', 'pore pressure']
    real(wp) :: growth(4), val, best(2), info(8)
    integer :: m, p
    character(len=640) :: line
    character(len=40) :: cells
    do m = 1, 4
      growth(m) = 0.0_wp
      if (fm(m) > 0.0_wp) growth(m) = fm(m)/max(self%mon_prev(m), fm(m)*1.0e-30_wp)
    end do
    m = maxloc(growth, 1)
    ! The largest value of field m on this rank, then the rank that holds it.
    best = [-1.0_wp, real(self%dec%rank, wp)]
    info = 0.0_wp
    associate (ps => self%solid)
      if (m == 1 .or. m == 3) then
        do p = 1, ps%n
          val = merge(norm2(ps%v(:, p)), maxval(abs(ps%stress(:, p))), m == 1)
          if (val > best(1)) then
            best(1) = val
            info = point_info(self, ps, p)
          end if
        end do
      end if
    end associate
    associate (ps => self%fluid)
      if (m == 2 .or. m == 4) then
        do p = 1, ps%n
          val = merge(norm2(ps%v(:, p)), abs(ps%pressure(p)), m == 2)
          if (val > best(1)) then
            best(1) = val
            info = point_info(self, ps, p)
          end if
        end do
      end if
    end associate
    call MPI_Allreduce(MPI_IN_PLACE, best, 1, MPI_2DOUBLE_PRECISION, MPI_MAXLOC, self%dec%comm)
    call MPI_Bcast(info, 8, MPI_DOUBLE_PRECISION, nint(best(2)), self%dec%comm)
    write (cells, '(3(1x,i0))') nint(info(5:4 + self%nd))
    write (line, '(a,es11.4,a,i0,a,es11.3e3,a,a,a,a,a,es11.3e3,a,es11.3e3,a,es11.4,a,i0,a,3es12.4,a)') &
      'monitor: at t = ', self%time, ' s (step ', self%step, ') kinetic + stored energy is ', ratio, &
      ' times the work done + initial energy; growing field: ', trim(fnames(m)), ' of the ', &
      trim(merge('solid', 'fluid', m == 1 .or. m == 3)), ' points, largest ', best(1), ' (', &
      min(growth(m), huge(1.0_wp)), ' times its value at t = ', self%mon_prev_time, ') at point id ', &
      nint(info(1), i8), ', x =', info(2:4), ', cell'
    line = trim(line)//trim(cells)//' (from 0 at the grid origin)'
    call self%log%error(trim(line))
    if (.not. stop) then
      call self%log%error('monitor: warning; the run stops when the ratio exceeds growth_limit = '// &
                          trim(rtoa_short(self%cfg%growth_limit)))
      return
    end if
    call self%write_frame()
    if (self%write_output) call self%out%close()
    call self%log%error('monitor: the run is unstable and was stopped; last frame written at t = '// &
                        trim(rtoa_short(self%time))//' s (raise growth_limit, or 0 to switch the monitor off)')
    call clean_stop(4)
  end subroutine report_growth

  !> id, position (3) and cell indices (3, from 0) of point p of ps, as reals.
  function point_info(self, ps, p) result(info)
    type(simulation_t), intent(in) :: self
    type(particle_set_t), intent(in) :: ps
    integer, intent(in) :: p
    real(wp) :: info(8)
    integer :: d
    info = 0.0_wp
    info(1) = real(ps%id(p), wp)
    info(2:1 + self%nd) = ps%x(:, p)
    do d = 1, self%nd
      info(4 + d) = real(floor((ps%x(d, p) - self%grid%origin(d))/self%grid%h(d)), wp)
    end do
  end function point_info

  !> Short text of a real for messages.
  function rtoa_short(x) result(t)
    real(wp), intent(in) :: x
    character(len=24) :: t
    write (t, '(es11.3e3)') x
    t = adjustl(t)
  end function rtoa_short

  !> After each step: every point's position, velocity, stress, volume (and, where
  !> present, pore pressure, porosity, det F) finite, volumes and det F positive.
  !> Otherwise the first bad point is named with its field and the run stops with
  !> code 3 before a frame of the bad state is written (collective).
  subroutine check_state(self)
    type(simulation_t), intent(inout) :: self
    character(len=48) :: field
    real(wp) :: bad(2), info(8), value
    character(len=640) :: line
    integer :: iset
    character(len=*), parameter :: fields(8) = [character(len=24) :: 'position', 'velocity', &
      'stress', 'volume', 'pore pressure', 'porosity', 'det F', '']
    bad = [0.0_wp, real(self%dec%rank, wp)]
    info = 0.0_wp
    value = 0.0_wp
    iset = 0
    call scan_set(self%solid, 1)
    if (self%two_phase .and. bad(1) == 0.0_wp) call scan_set(self%fluid, 2)
    call MPI_Allreduce(MPI_IN_PLACE, bad, 1, MPI_2DOUBLE_PRECISION, MPI_MAXLOC, self%dec%comm)
    if (bad(1) == 0.0_wp) return
    ! info(6:8) are free for the field code, the set and the value.
    call MPI_Bcast(info, 8, MPI_DOUBLE_PRECISION, nint(bad(2)), self%dec%comm)
    field = fields(nint(bad(1)))
    write (line, '(a,es11.4,a,i0,a,a,a,a,a,i0,a,3es12.4,a,es11.3)') 'monitor: at t = ', self%time, &
      ' s (step ', self%step, ') the ', trim(field), ' of ', &
      trim(merge('solid', 'fluid', nint(info(7)) == 1)), ' point id ', nint(info(1), i8), &
      ' at x =', info(2:4), ' is not valid: ', info(8)
    call self%log%error(trim(line))
    call self%log%error('monitor: no frame of this state is written; the last frame is the one '// &
                        'before; the run stops')
    if (self%write_output) call self%out%close()
    call clean_stop(4)
  contains
    subroutine scan_set(ps, is)
      type(particle_set_t), intent(in) :: ps
      integer, intent(in) :: is
      integer :: p, code
      real(wp) :: v, fdet
      do p = 1, ps%n
        code = 0
        if (.not. all(ieee_is_finite(ps%x(:, p)))) then
          code = 1; v = sum(ps%x(:, p))
        else if (.not. all(ieee_is_finite(ps%v(:, p)))) then
          code = 2; v = sum(ps%v(:, p))
        else if (.not. all(ieee_is_finite(ps%stress(:, p)))) then
          code = 3; v = sum(ps%stress(:, p))
        else if (.not. (ps%vol(p) > 0.0_wp .and. ieee_is_finite(ps%vol(p)))) then
          code = 4; v = ps%vol(p)
        end if
        if (code == 0 .and. ps%has_pressure) then
          if (.not. ieee_is_finite(ps%pressure(p))) then
            code = 5; v = ps%pressure(p)
          end if
        end if
        if (code == 0 .and. ps%has_porosity) then
          if (.not. ieee_is_finite(ps%porosity(p))) then
            code = 6; v = ps%porosity(p)
          end if
        end if
        if (code == 0 .and. allocated(ps%defgrad)) then
          if (size(ps%defgrad, 2) >= p) then
            fdet = det3(ps%defgrad(:, p))
            if (.not. (fdet > 0.0_wp .and. ieee_is_finite(fdet))) then
              code = 7; v = fdet
            end if
          end if
        end if
        if (code /= 0) then
          bad(1) = real(code, wp)
          info = point_info(self, ps, p)
          info(7) = real(is, wp)
          info(8) = v
          return
        end if
      end do
    end subroutine scan_set
  end subroutine check_state

  !> Determinant of a 3x3 matrix stored column-major in 9 values.
  pure real(wp) function det3(a) result(d)
    real(wp), intent(in) :: a(9)
    d = a(1)*(a(5)*a(9) - a(8)*a(6)) - a(4)*(a(2)*a(9) - a(8)*a(3)) + a(7)*(a(2)*a(6) - a(5)*a(3))
  end function det3

  !> Write one frame of all point sets.
  subroutine sim_write_frame(self)
    class(simulation_t), intent(inout) :: self
    self%nframes = self%nframes + 1
    self%last_frame_step = self%step
    self%next_frame = self%next_frame + self%cfg%frame_interval
    if (.not. self%write_output) return
    call self%timers%tic(t_output)
    call self%out%begin_frame(self%step, self%time)
    call self%out%write_set(self%solid, self%cfg)
    if (self%two_phase) call self%out%write_set(self%fluid, self%cfg)
    call self%out%end_frame()
    call self%timers%toc(t_output)
    if (two_phase_benchmark(self)) call record_two_phase_errors(self)
  end subroutine sim_write_frame

  !> Gather the points of all ranks on rank 0, sorted by id: ids, positions,
  !> velocities and stresses (for comparisons between runs); of the fluid points
  !> (stress -p I) when fluid is true.
  subroutine sim_gather_points(self, ids, x, v, stress, fluid)
    class(simulation_t), intent(in), target :: self
    integer(i8), allocatable, intent(out) :: ids(:)
    real(wp), allocatable, intent(out) :: x(:, :), v(:, :), stress(:, :)
    logical, intent(in), optional :: fluid
    type(particle_set_t), pointer :: ps
    integer, allocatable :: counts(:), displs(:), order(:)
    integer(i8), allocatable :: gid(:)
    real(wp), allocatable :: buf(:, :), gbuf(:, :)
    integer :: nr, m, k, ntot, nd
    nd = self%nd
    ps => self%solid
    if (present(fluid)) then
      if (fluid) ps => self%fluid
    end if
    if (ps%ndim == 0) then
      allocate (ids(0), x(nd, 0), v(nd, 0), stress(6, 0))
      return
    end if
    m = 2*nd + 6
    nr = self%dec%nranks
    allocate (counts(nr), displs(nr))
    call MPI_Gather(ps%n, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, 0, self%dec%comm)
    ntot = 0
    if (self%dec%rank == 0) then
      displs(1) = 0
      do k = 2, nr
        displs(k) = displs(k - 1) + counts(k - 1)
      end do
      ntot = sum(counts)
    end if
    allocate (gid(max(ntot, 1)), gbuf(m, max(ntot, 1)), buf(m, ps%n))
    buf(1:nd, :) = ps%x(:, 1:ps%n)
    buf(nd + 1:2*nd, :) = ps%v(:, 1:ps%n)
    buf(2*nd + 1:m, :) = ps%stress(:, 1:ps%n)
    call MPI_Gatherv(ps%id, ps%n, MPI_INTEGER8, gid, counts, displs, MPI_INTEGER8, &
                     0, self%dec%comm)
    call MPI_Gatherv(buf, m*ps%n, MPI_DOUBLE_PRECISION, gbuf, m*counts, m*displs, &
                     MPI_DOUBLE_PRECISION, 0, self%dec%comm)
    if (self%dec%rank /= 0) then
      allocate (ids(0), x(nd, 0), v(nd, 0), stress(6, 0))
      return
    end if
    order = sort_index(gid(1:ntot))
    ids = gid(order)
    x = gbuf(1:nd, order)
    v = gbuf(nd + 1:2*nd, order)
    stress = gbuf(2*nd + 1:m, order)
  end subroutine sim_gather_points

  !> Permutation that sorts a (merge sort, stable).
  function sort_index(a) result(idx)
    integer(i8), intent(in) :: a(:)
    integer, allocatable :: idx(:), tmp(:)
    integer :: n, width, lo, mid, hi, i, j, k
    n = size(a)
    idx = [(k, k = 1, n)]
    allocate (tmp(n))
    width = 1
    do while (width < n)
      lo = 1
      do while (lo <= n)
        mid = min(lo + width - 1, n)
        hi = min(lo + 2*width - 1, n)
        i = lo; j = mid + 1; k = lo
        do while (k <= hi)
          if (j > hi) then
            tmp(k) = idx(i); i = i + 1
          else if (i > mid) then
            tmp(k) = idx(j); j = j + 1
          else if (a(idx(j)) < a(idx(i))) then
            tmp(k) = idx(j); j = j + 1
          else
            tmp(k) = idx(i); i = i + 1
          end if
          k = k + 1
        end do
        lo = lo + 2*width
      end do
      idx = tmp
      width = 2*width
    end do
  end function sort_index

  !> Release everything.
  subroutine sim_free(self)
    class(simulation_t), intent(inout) :: self
    call self%solid%free()
    call self%fluid%free()
    call self%dec%free()
    self%ts = transfer_t()
    self%tf = transfer_t()
    if (allocated(self%nporo)) deallocate (self%nporo, self%ndrag)
    if (allocated(self%vacc)) deallocate (self%vacc)
    if (allocated(self%bacc)) deallocate (self%bacc)
    self%governing = 0
    self%two_phase = .false.
    if (allocated(self%err_hist)) deallocate (self%err_hist)
    if (allocated(self%ferr)) deallocate (self%ferr, self%fnames)
    self%nferr = 0
    if (allocated(self%mats)) deallocate (self%mats)
  end subroutine sim_free

end module dpmpm_simulation
