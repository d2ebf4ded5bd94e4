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
  use dpmpm_config, only: config_t, bc_free, bc_fixed
  use dpmpm_grid, only: grid_t
  use dpmpm_decomp, only: decomp_t
  use dpmpm_kernels, only: kernel_width, max_stencil
  use dpmpm_shape_plan, only: shape_plan_t
  use dpmpm_mls, only: mls_stats_t, basis_size, packed_size
  use dpmpm_reconstruct, only: psi_stencil, weight_integral, velocity_accumulate, velocity_solve, &
                               velocity_fold_signs, gauss_accumulate, gauss_solve, gauss_forces, &
                               gauss_velocity_gradient, gauss_strain, gauss_cell_components, &
                               gauss_solution_components
  use dpmpm_particles, only: particle_set_t
  use dpmpm_generate, only: generate_points
  use dpmpm_materials, only: material_t, materials_from_config, stress_update, strain_energy, &
                             wave_speed, voigt_to_tensor, model_neo_hookean
  use dpmpm_migrate, only: migrate
  use dpmpm_output, only: output_t
  use dpmpm_diagnostics, only: diag_record_t
  use dpmpm_benchmarks, only: benchmark_setup, benchmark_errors, benchmark_error_names, nbench_err, &
                              benchmark_body_force, benchmark_nerr
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_INTEGER8, &
                     MPI_SUM, MPI_MAX, MPI_MIN, MPI_Wtime, MPI_Gather, MPI_Gatherv, MPI_INTEGER
  implicit none
  private
  public :: simulation_t, run_scene

  !> The state of a run.
  type :: simulation_t
    type(config_t) :: cfg
    type(decomp_t) :: dec
    type(grid_t) :: grid
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: solid
    type(log_t) :: log
    type(timer_set_t) :: timers
    type(output_t) :: out
    logical :: write_output = .true.
    type(shape_plan_t) :: plan                !< grid functions and MLS choices (&shape)
    integer :: kernel = 1
    integer :: nw(3) = 1                      !< stencil nodes per axis
    ! MLS reconstruction (allocated only when the plan uses it): nodal velocity
    ! moments, Gauss-point sums, their solution and velocity gradients (cell arrays),
    ! positions and volumes at the force evaluation, effective point volumes.
    real(wp), allocatable :: vacc(:, :, :, :), gacc(:, :, :, :), gsol(:, :, :, :), glg(:, :, :, :)
    real(wp), allocatable :: xold(:, :), volold(:), vt(:)
    real(wp), allocatable :: bacc(:, :)       !< body acceleration per point (manufactured solution)
    real(wp) :: wint = 1.0_wp                 !< integral of the field weight (cell units)
    type(mls_stats_t) :: mls_stats            !< fallback counts of the MLS solves on this rank
    integer(i8) :: nkept = 0                  !< point gradients left point-wise (no quadrature weight)
    integer(i8) :: nwall = 0                  !< points put back inside a wall they had crossed
    integer :: nd = 1
    ! Per-point stencil: first node, weights and x-derivatives per axis.
    integer, allocatable :: i0(:, :)
    real(wp), allocatable :: sw(:, :, :), sdw(:, :, :)
    real(wp), allocatable :: vgrad(:, :)      !< velocity gradient (9, n), column-major 3x3
    ! Node fields on the stored nodes (owned + ghosts).
    real(wp), allocatable :: node(:, :, :, :) !< mass, momentum(nd), force(nd)
    real(wp), allocatable :: nvel(:, :, :, :) !< velocity before (nd) and after (nd) the update
    real(wp) :: time = 0.0_wp
    real(wp) :: dt = 0.0_wp
    real(wp) :: ext_work = 0.0_wp             !< work of gravity and tractions on this rank
    integer(i8) :: step = 0
    real(wp) :: wall_start = 0.0_wp
    integer :: nframes = 0
    integer(i8) :: last_frame_step = -1       !< step of the last frame written
    real(wp) :: next_frame = 0.0_wp
    real(wp), allocatable :: err_hist(:, :)   !< benchmark errors over diagnostics (time, errors)
    integer :: nerr = 0
    real(wp) :: energy0 = 0.0_wp              !< kinetic + strain - external work at the start
    real(wp) :: energy_scale = 0.0_wp         !< largest of |energy0| and kinetic + strain so far
    real(wp) :: energy_drift = 0.0_wp         !< largest |energy - energy0| / energy_scale so far
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
    call sim%init(cfg, comm)
    call sim%run()
    call sim%free()
  end subroutine run_scene

  !> Decompose the grid, create the points, open the output.
  subroutine sim_init(self, cfg, comm, write_output)
    class(simulation_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    logical, intent(in), optional :: write_output
    integer :: nmin, nmax, nb
    integer(i8) :: ntot
    character(len=256) :: line
    call self%free()
    self%cfg = cfg
    self%write_output = .true.
    if (present(write_output)) self%write_output = write_output
    self%ext_work = 0.0_wp
    self%energy0 = 0.0_wp
    self%energy_scale = 0.0_wp
    self%energy_drift = 0.0_wp
    self%nframes = 0
    self%last_frame_step = -1
    self%next_frame = 0.0_wp
    self%nerr = 0
    call self%log%init(comm)
    self%wall_start = MPI_Wtime()
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
    call self%solid%init('solid', self%nd, any(self%mats%model == model_neo_hookean))
    call generate_points(cfg, self%grid, self%dec, self%mats, self%solid)
    call benchmark_setup(cfg, self%mats, self%solid)

    ntot = self%solid%n
    call MPI_Allreduce(MPI_IN_PLACE, ntot, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    call MPI_Allreduce(self%solid%n, nmin, 1, MPI_INTEGER, MPI_MIN, self%dec%comm)
    call MPI_Allreduce(self%solid%n, nmax, 1, MPI_INTEGER, MPI_MAX, self%dec%comm)
    write (line, '(a,i0,a,i0,a,i0,a,i0,a,i0,a,i0,a,i0)') 'dpmpm: ', self%dec%nranks, ' ranks (', &
      self%dec%dims(1), ' x ', self%dec%dims(2), ' x ', self%dec%dims(3), '); ', ntot, &
      ' solid points; per rank min ', nmin, ' max ', nmax
    call self%log%info(line)
    if (ntot == 0) then
      call self%log%error('the regions produced no points')
      call clean_stop(2)
    end if

    associate (lo => self%dec%alo, hi => self%dec%ahi)
      allocate (self%node(1 + 2*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
      allocate (self%nvel(2*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
      if (self%plan%velocity_mls) then
        nb = basis_size(self%plan%velocity_basis, self%nd)
        allocate (self%vacc(1 + packed_size(nb) + nb*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
      end if
      if (self%plan%gauss) then
        associate (ng => self%plan%ngauss, basis => self%plan%field_basis, nd => self%nd)
          allocate (self%gacc(gauss_cell_components(nd, ng, basis), lo(1):hi(1), lo(2):hi(2), &
                              lo(3):hi(3)))
          allocate (self%gsol(gauss_solution_components(nd, ng, basis), lo(1):hi(1), &
                              lo(2):hi(2), lo(3):hi(3)))
          allocate (self%glg(ng**nd*nd*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        end associate
        self%wint = weight_integral(self%plan%field_kernel, self%plan%field_radius, &
                                    self%plan%field_radial, self%nd)
      end if
    end associate
    allocate (self%err_hist(1 + nbench_err, 64))
    self%time = 0.0_wp
    self%step = 0
    self%dt = self%stable_dt()
    if (self%write_output) then
      call self%out%open(self%cfg, self%dec%comm)
    end if
    call self%diagnostics()
    call self%write_frame()
  end subroutine sim_init

  !> Step to t_end (or max_steps), with diagnostics, frames and progress lines.
  subroutine sim_run(self)
    class(simulation_t), intent(inout) :: self
    integer(i8) :: diag_every, nwall
    real(wp) :: last_progress, now, eta
    character(len=256) :: line
    integer :: k
    diag_every = self%cfg%diag_every
    if (diag_every <= 0) diag_every = max(1_i8, int(self%cfg%t_end/self%dt/500.0_wp, i8))
    last_progress = MPI_Wtime()
    call self%timers%tic(t_total)
    do while (self%time < self%cfg%t_end*(1.0_wp - 1.0e-12_wp) .and. self%step < self%cfg%max_steps)
      self%dt = min(self%stable_dt(), self%cfg%t_end - self%time)
      call self%advance(self%dt)
      self%time = self%time + self%dt
      self%step = self%step + 1
      if (mod(self%step, diag_every) == 0) call self%diagnostics()
      if (self%cfg%frame_interval > 0.0_wp .and. &
          self%time >= self%next_frame - 1.0e-9_wp*self%cfg%frame_interval) call self%write_frame()
      now = MPI_Wtime()
      if (now - last_progress >= self%cfg%progress_seconds) then
        last_progress = now
        eta = (now - self%wall_start)*(self%cfg%t_end - self%time)/max(self%time, tiny(1.0_wp))
        write (line, '(a,i0,a,es12.5,a,es10.3,a,f6.1,a,f0.1,a)') 'step ', self%step, '  t = ', &
          self%time, '  dt = ', self%dt, '  ', 100.0_wp*self%time/self%cfg%t_end, '%  ETA ', eta, ' s'
        call self%log%info(line)
      end if
    end do
    call self%timers%toc(t_total)
    if (mod(self%step, diag_every) /= 0) call self%diagnostics()
    if (self%last_frame_step /= self%step) call self%write_frame()
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
    call report_mls(self)
    write (line, '(a,i0,a,es12.5,a,f0.2,a)') 'dpmpm: done, ', self%step, ' steps to t = ', &
      self%time, ' in ', MPI_Wtime() - self%wall_start, ' s'
    call self%log%info(line)
    write (line, '(a,es10.3)') '  largest relative change of the total energy: ', self%energy_drift
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
  end subroutine sim_run

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
    real(wp) :: rate, c, crit
    integer :: p
    character(len=256) :: line
    rate = 0.0_wp
    do p = 1, self%solid%n
      c = wave_speed(self%mats(self%solid%mat(p)), self%solid%mass(p)/self%solid%vol(p))
      rate = max(rate, c + norm2(self%solid%v(:, p)))
    end do
    call MPI_Allreduce(MPI_IN_PLACE, rate, 1, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    if (.not. ieee_is_finite(rate)) then
      call self%log%error('non-finite wave speed or velocity at step '//i8toa(self%step)// &
                          '; the run became unstable')
      call clean_stop(3)
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
  end function sim_stable_dt

  !> One explicit step of length dt.
  subroutine sim_advance(self, dt)
    class(simulation_t), intent(inout) :: self
    real(wp), intent(in) :: dt
    integer :: m, nlost, n, nkept
    n = self%solid%n
    call self%timers%tic(t_stencil)
    call compute_stencils(self)
    call self%timers%toc(t_stencil)

    call self%timers%tic(t_p2g)
    self%node = 0.0_wp
    if (allocated(self%bacc)) then
      call benchmark_body_force(self%cfg, self%mats, self%solid, self%time, self%bacc)
      call p2g(self%nd, self%nw, n, self%i0, self%sw, self%sdw, self%solid%mass, self%solid%v, &
               self%solid%vol, self%solid%stress, .not. self%plan%gauss, self%dec%alo, self%node, &
               self%bacc)
    else
      call p2g(self%nd, self%nw, n, self%i0, self%sw, self%sdw, self%solid%mass, self%solid%v, &
               self%solid%vol, self%solid%stress, .not. self%plan%gauss, self%dec%alo, self%node)
    end if
    if (self%plan%gauss) call gauss_force_integrals(self)
    call fold_exterior(self, self%node, 1)
    if (self%plan%velocity_mls) then
      self%vacc = 0.0_wp
      associate (pl => self%plan)
        call velocity_accumulate(self%nd, n, self%solid%x, self%solid%mass, self%solid%v, &
                                 self%grid%origin, self%grid%h, pl%velocity_kernel, &
                                 pl%velocity_radius, pl%velocity_radial, pl%velocity_basis, &
                                 self%dec%alo, self%vacc)
      end associate
      call fold_planes(self, self%vacc, velocity_signs(self), .true.)
    end if
    call self%timers%toc(t_p2g)
    call self%timers%tic(t_halo)
    call self%dec%halo_sum(self%node)
    if (self%plan%velocity_mls) call self%dec%halo_sum(self%vacc)
    call self%timers%toc(t_halo)

    call self%timers%tic(t_nodal)
    if (self%plan%velocity_mls) call velocity_solve(self%nd, self%plan%velocity_basis, &
      self%dec%alo, self%dec%olo, self%dec%ohi, self%vacc, self%node, self%mls_stats)
    call nodal_update(self, dt)
    call self%timers%toc(t_nodal)
    call self%timers%tic(t_halo)
    call self%dec%halo_copy(self%nvel)
    call unfold_exterior(self, self%nvel)
    call self%timers%toc(t_halo)

    call self%timers%tic(t_g2p)
    call g2p(self%nd, self%nw, n, self%i0, self%sw, self%sdw, self%dec%alo, self%nvel, &
             self%cfg%flip, dt, self%solid%v, self%solid%x, self%vgrad)
    if (self%cfg%scheme == 'musl') call musl_remap(self)
    if (self%plan%gauss) then
      ! Strain rates by the transpose of the quadrature force operator (physics.md 3.5).
      call gauss_velocity_gradient(self%nd, self%plan%ngauss, self%kernel, self%grid%h, &
                                   self%dec%alo, self%dec%clo, self%dec%chi, self%gsol, self%nvel, &
                                   self%glg)
      call self%dec%halo_copy(self%glg)
      associate (pl => self%plan)
        call gauss_strain(self%nd, n, self%xold, self%volold, self%grid%origin, self%grid%h, &
                          self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                          pl%field_radial, pl%field_basis, self%dec%alo, self%gsol, self%glg, &
                          self%vgrad, self%vt, nkept)
      end associate
      self%nkept = self%nkept + nkept
    end if
    call self%timers%toc(t_g2p)

    call self%timers%tic(t_stress)
    do m = 1, size(self%mats)
      call stress_update(self%mats(m), m, dt, self%solid%n, self%solid%mat, self%vgrad, &
                         self%solid%stress, self%solid%vol, self%solid%vol0, self%solid%defgrad)
    end do
    call self%timers%toc(t_stress)

    call self%timers%tic(t_migrate)
    call check_inside(self)
    call migrate(self%dec, self%grid%origin, self%grid%h, self%solid, nlost)
    if (nlost > 0) call fatal('points were lost in migration (moved more than one rank width in a step)', &
                              'migrate')
    call self%timers%toc(t_migrate)
  end subroutine sim_advance

  !> Internal forces by Gauss quadrature of MLS-reconstructed stresses, added to
  !> node(); keeps the positions and volumes for the transposed strain operator.
  subroutine gauss_force_integrals(self)
    type(simulation_t), intent(inout) :: self
    integer :: n
    n = self%solid%n
    if (size(self%volold) < n) then
      deallocate (self%xold, self%volold, self%vt)
      allocate (self%xold(self%nd, self%solid%cap), self%volold(self%solid%cap), &
                self%vt(self%solid%cap))
    end if
    self%xold(:, 1:n) = self%solid%x(:, 1:n)
    self%volold(1:n) = self%solid%vol(1:n)
    self%gacc = 0.0_wp
    associate (pl => self%plan)
      call gauss_accumulate(self%nd, n, self%solid%x, self%solid%vol, self%solid%stress, &
                            self%grid%origin, self%grid%h, self%grid%ncells, pl%ngauss, &
                            pl%field_kernel, pl%field_radius, pl%field_radial, pl%field_basis, &
                            self%wint, self%dec%alo, self%gacc)
      call self%timers%tic(t_halo)
      call self%dec%halo_sum(self%gacc)
      call self%timers%toc(t_halo)
      call gauss_solve(self%nd, pl%ngauss, pl%field_basis, self%dec%alo, self%dec%clo, &
                       self%dec%chi, self%gacc, self%gsol, self%mls_stats)
      call self%timers%tic(t_halo)
      call self%dec%halo_copy(self%gsol)
      call self%timers%toc(t_halo)
      call gauss_forces(self%nd, pl%ngauss, pl%field_basis, self%kernel, self%grid%h, &
                        self%dec%alo, self%dec%clo, self%dec%chi, self%gsol, self%node)
    end associate
  end subroutine gauss_force_integrals

  !> Kernel weights and derivatives of every point, evaluated once per step.
  subroutine compute_stencils(self)
    type(simulation_t), intent(inout) :: self
    integer :: p, d, n
    real(wp) :: y(3)
    n = self%solid%n
    if (.not. allocated(self%i0)) then
      allocate (self%i0(3, 0), self%sw(max_stencil, 3, 0), self%sdw(max_stencil, 3, 0))
    end if
    if (size(self%i0, 2) < n) then
      deallocate (self%i0, self%sw, self%sdw)
      allocate (self%i0(3, self%solid%cap), self%sw(max_stencil, 3, self%solid%cap), &
                self%sdw(max_stencil, 3, self%solid%cap))
      if (allocated(self%vgrad)) deallocate (self%vgrad)
    end if
    if (.not. allocated(self%vgrad)) allocate (self%vgrad(9, size(self%i0, 2)))
    if (self%plan%gauss .and. .not. allocated(self%xold)) &
      allocate (self%xold(self%nd, size(self%i0, 2)), self%volold(size(self%i0, 2)), &
                self%vt(size(self%i0, 2)))
    if (allocated(self%bacc)) then
      if (size(self%bacc, 2) < n) deallocate (self%bacc)
    end if
    if (self%cfg%benchmark == 'mms' .and. .not. allocated(self%bacc)) &
      allocate (self%bacc(self%nd, size(self%i0, 2)))
    do p = 1, n
      y = 0.0_wp
      do d = 1, self%nd
        y(d) = (self%solid%x(d, p) - self%grid%origin(d))/self%grid%h(d)
      end do
      call psi_stencil(self%nd, self%kernel, y, self%grid%h, self%i0(:, p), self%sw(:, :, p), &
                       self%sdw(:, :, p))
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
    integer :: i, j, k, nd, l, d, f
    real(wp) :: m, vold(3), vnew(3), fext(3), ramp, area
    logical :: fix(3)
    nd = self%nd
    self%nvel = 0.0_wp
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          m = self%node(1, i, j, k)
          if (m <= 0.0_wp) cycle
          fix = self%grid%constrained([i, j, k])
          vold = 0.0_wp
          vold(1:nd) = self%node(2:1 + nd, i, j, k)/m
          fext = 0.0_wp
          fext(1:nd) = m*self%cfg%gravity(1:nd)
          do l = 1, size(self%cfg%loads)
            f = self%cfg%loads(l)%face
            d = (f + 1)/2
            if (.not. on_face([i, j, k], d, f)) cycle
            ramp = 1.0_wp
            if (self%cfg%loads(l)%ramp_time > 0.0_wp) ramp = min(1.0_wp, self%time/self%cfg%loads(l)%ramp_time)
            area = face_area([i, j, k], d)
            fext(1:nd) = fext(1:nd) + ramp*area*self%cfg%loads(l)%traction(1:nd)
          end do
          vnew = 0.0_wp
          vnew(1:nd) = vold(1:nd) + dt*(self%node(2 + nd:1 + 2*nd, i, j, k) + fext(1:nd))/m
          where (fix) vold = 0.0_wp
          where (fix) vnew = 0.0_wp
          self%nvel(1:nd, i, j, k) = vold(1:nd)
          self%nvel(nd + 1:2*nd, i, j, k) = vnew(1:nd)
          self%ext_work = self%ext_work + 0.5_wp*dt*dot_product(fext(1:nd), vold(1:nd) + vnew(1:nd))
        end do
      end do
    end do
  contains
    logical function on_face(idx, d, f)
      integer, intent(in) :: idx(3), d, f
      integer :: t
      if (mod(f, 2) == 1) then
        on_face = idx(d) == 0
      else
        on_face = idx(d) == self%grid%ncells(d)
      end if
      do t = 1, nd
        if (idx(t) < 0 .or. idx(t) > self%grid%ncells(t)) on_face = .false.
      end do
    end function on_face
    real(wp) function face_area(idx, d)
      integer, intent(in) :: idx(3), d
      integer :: t
      face_area = 1.0_wp
      do t = 1, nd
        if (t == d) cycle
        face_area = face_area*self%grid%h(t)
        if (idx(t) == 0 .or. idx(t) == self%grid%ncells(t)) face_area = 0.5_wp*face_area
      end do
    end function face_area
  end subroutine nodal_update

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
    integer :: p, a, b, c, i, j, k, nd
    real(wp) :: nn, g(3), lg(3, 3), m
    logical :: fix(3)
    nd = self%nd
    ! Reuse the momentum slots of node(); the masses are unchanged.
    self%node(2:1 + 2*nd, :, :, :) = 0.0_wp
    do p = 1, self%solid%n
      do c = 1, self%nw(3)
        k = self%i0(3, p) + c - 1
        do b = 1, self%nw(2)
          j = self%i0(2, p) + b - 1
          do a = 1, self%nw(1)
            i = self%i0(1, p) + a - 1
            nn = self%sw(a, 1, p)*self%sw(b, 2, p)*self%sw(c, 3, p)
            self%node(2:1 + nd, i, j, k) = self%node(2:1 + nd, i, j, k) + &
                                           nn*self%solid%mass(p)*self%solid%v(:, p)
          end do
        end do
      end do
    end do
    call fold_exterior(self, self%node, 1)
    call self%dec%halo_sum(self%node)
    self%nvel = 0.0_wp
    do k = self%dec%olo(3), self%dec%ohi(3)
      do j = self%dec%olo(2), self%dec%ohi(2)
        do i = self%dec%olo(1), self%dec%ohi(1)
          m = self%node(1, i, j, k)
          if (m <= 0.0_wp) cycle
          fix = self%grid%constrained([i, j, k])
          self%nvel(nd + 1:2*nd, i, j, k) = self%node(2:1 + nd, i, j, k)/m
          where (fix(1:nd)) self%nvel(nd + 1:2*nd, i, j, k) = 0.0_wp
        end do
      end do
    end do
    call self%dec%halo_copy(self%nvel)
    call unfold_exterior(self, self%nvel)
    do p = 1, self%solid%n
      lg = 0.0_wp
      do c = 1, self%nw(3)
        k = self%i0(3, p) + c - 1
        do b = 1, self%nw(2)
          j = self%i0(2, p) + b - 1
          do a = 1, self%nw(1)
            i = self%i0(1, p) + a - 1
            g(1) = self%sdw(a, 1, p)*self%sw(b, 2, p)*self%sw(c, 3, p)
            g(2) = self%sw(a, 1, p)*self%sdw(b, 2, p)*self%sw(c, 3, p)
            g(3) = self%sw(a, 1, p)*self%sw(b, 2, p)*self%sdw(c, 3, p)
            lg(1:nd, 1) = lg(1:nd, 1) + self%nvel(nd + 1:2*nd, i, j, k)*g(1)
            lg(1:nd, 2) = lg(1:nd, 2) + self%nvel(nd + 1:2*nd, i, j, k)*g(2)
            lg(1:nd, 3) = lg(1:nd, 3) + self%nvel(nd + 1:2*nd, i, j, k)*g(3)
          end do
        end do
      end do
      self%vgrad(:, p) = reshape(lg, [9])
    end do
  end subroutine musl_remap

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
  function scalar_vector_signs(self, ncomp, nscalar) result(sg)
    type(simulation_t), intent(in) :: self
    integer, intent(in) :: ncomp, nscalar
    real(wp) :: sg(ncomp, 6)
    integer :: f, c
    sg = 1.0_wp
    do f = 1, 2*self%nd
      do c = nscalar + 1, ncomp
        sg(c, f) = mirror_sign(self%grid%bc(f), (f + 1)/2, mod(c - nscalar - 1, self%nd) + 1)
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
  subroutine fold_exterior(self, f, nscalar)
    type(simulation_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer, intent(in) :: nscalar
    call fold_planes(self, f, scalar_vector_signs(self, size(f, 1), nscalar), .true.)
  end subroutine fold_exterior

  !> Set the exterior nodes from their mirror images (the inverse of fold_exterior
  !> for velocities), after halo_copy so that the images are present.
  subroutine unfold_exterior(self, f)
    type(simulation_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    call fold_planes(self, f, scalar_vector_signs(self, size(f, 1), 0), .false.)
  end subroutine unfold_exterior

  !> The plane loop of fold_exterior (fold: exterior added onto its image and
  !> cleared) and unfold_exterior (exterior set from its image), with the
  !> component signs sg(:, face) of each fixed or roller face.
  subroutine fold_planes(self, f, sg, fold)
    type(simulation_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: sg(:, :)
    logical, intent(in) :: fold
    integer :: d, side, k, ext, img, face
    do d = 1, self%nd
      do side = 1, 2
        face = 2*(d - 1) + side
        if (self%grid%bc(face) == bc_free) cycle
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
  subroutine check_inside(self)
    type(simulation_t), intent(inout) :: self
    integer :: p, d, side
    real(wp) :: wall(2), eps
    character(len=256) :: msg
    do p = 1, self%solid%n
      if (self%grid%inside(self%solid%x(:, p))) cycle
      do d = 1, self%nd
        wall = [self%grid%origin(d), self%grid%origin(d) + self%grid%ncells(d)*self%grid%h(d)]
        eps = 1.0e-9_wp*self%grid%h(d)
        do side = 1, 2
          if (self%grid%bc(2*(d - 1) + side) == bc_free) cycle
          if (side == 1 .and. self%solid%x(d, p) < wall(1)) then
            self%solid%x(d, p) = wall(1) + eps
            self%nwall = self%nwall + 1
          else if (side == 2 .and. self%solid%x(d, p) >= wall(2)) then
            self%solid%x(d, p) = wall(2) - eps
            self%nwall = self%nwall + 1
          end if
        end do
      end do
      if (.not. self%grid%inside(self%solid%x(:, p))) then
        write (msg, '(a,i0,a,3es12.4)') 'point ', self%solid%id(p), ' left the grid at x =', &
          self%solid%x(:, p)
        call fatal(trim(msg)//'; enlarge the grid or add a boundary condition', 'step')
      end if
    end do
  end subroutine check_inside

  !> Global diagnostics at the current step (collective).
  subroutine sim_diagnostics(self)
    class(simulation_t), intent(inout) :: self
    type(diag_record_t) :: rec
    real(wp) :: s(8), vmax, err(nbench_err)
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
      s(2) = s(2) + strain_energy(self%mats(m), m, self%solid%n, self%solid%mat, self%solid%stress, &
                                  self%solid%vol, self%solid%vol0, self%solid%defgrad)
    end do
    s(3) = self%ext_work
    s(8) = real(self%solid%n, wp)
    call MPI_Allreduce(MPI_IN_PLACE, s, 8, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    call MPI_Allreduce(MPI_IN_PLACE, vmax, 1, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    rec%step = self%step
    rec%npoints = nint(s(8), i8)
    rec%values = [self%time, self%dt, s(1), s(2), s(3), vmax, MPI_Wtime() - self%wall_start, &
                  s(4), s(5), s(6), s(7)]
    if (self%write_output) call self%out%add_diag(rec)
    ! Energy balance: kinetic + strain - external work stays at its initial value;
    ! its change is measured relative to the largest stored energy seen so far.
    if (self%step == 0) self%energy0 = s(1) + s(2) - s(3)
    self%energy_scale = max(self%energy_scale, abs(self%energy0), s(1) + s(2))
    if (self%energy_scale > 0.0_wp) self%energy_drift = max(self%energy_drift, &
      abs(s(1) + s(2) - s(3) - self%energy0)/self%energy_scale)
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
    call self%out%end_frame()
    call self%timers%toc(t_output)
  end subroutine sim_write_frame

  !> Gather the points of all ranks on rank 0, sorted by id: ids, positions,
  !> velocities and stresses (for comparisons between runs).
  subroutine sim_gather_points(self, ids, x, v, stress)
    class(simulation_t), intent(in) :: self
    integer(i8), allocatable, intent(out) :: ids(:)
    real(wp), allocatable, intent(out) :: x(:, :), v(:, :), stress(:, :)
    integer, allocatable :: counts(:), displs(:), order(:)
    integer(i8), allocatable :: gid(:)
    real(wp), allocatable :: buf(:, :), gbuf(:, :)
    integer :: nr, m, k, ntot, nd
    nd = self%nd
    m = 2*nd + 6
    nr = self%dec%nranks
    allocate (counts(nr), displs(nr))
    call MPI_Gather(self%solid%n, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, 0, self%dec%comm)
    ntot = 0
    if (self%dec%rank == 0) then
      displs(1) = 0
      do k = 2, nr
        displs(k) = displs(k - 1) + counts(k - 1)
      end do
      ntot = sum(counts)
    end if
    allocate (gid(max(ntot, 1)), gbuf(m, max(ntot, 1)), buf(m, self%solid%n))
    buf(1:nd, :) = self%solid%x(:, 1:self%solid%n)
    buf(nd + 1:2*nd, :) = self%solid%v(:, 1:self%solid%n)
    buf(2*nd + 1:m, :) = self%solid%stress(:, 1:self%solid%n)
    call MPI_Gatherv(self%solid%id, self%solid%n, MPI_INTEGER8, gid, counts, displs, MPI_INTEGER8, &
                     0, self%dec%comm)
    call MPI_Gatherv(buf, m*self%solid%n, MPI_DOUBLE_PRECISION, gbuf, m*counts, m*displs, &
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
    call self%dec%free()
    if (allocated(self%node)) deallocate (self%node)
    if (allocated(self%nvel)) deallocate (self%nvel)
    if (allocated(self%i0)) deallocate (self%i0, self%sw, self%sdw)
    if (allocated(self%vgrad)) deallocate (self%vgrad)
    if (allocated(self%err_hist)) deallocate (self%err_hist)
    if (allocated(self%mats)) deallocate (self%mats)
  end subroutine sim_free

end module dpmpm_simulation
