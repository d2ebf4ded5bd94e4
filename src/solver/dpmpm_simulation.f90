!> One simulation: the scene built from a config_t on a communicator, its run loop
!> (time steps, diagnostics, frames, checkpoints, stop requests) and its end (the summary in
!> the log: dpmpm_run_summary). The run state is state_t (dpmpm_state); the step over the
!> phases is dpmpm_step.
!> Nothing here touches MPI_COMM_WORLD or ends the program: a collective stop
!> leaves an exit status (run_scene's result) for the program to end with.
module dpmpm_simulation
  use dpmpm_kinds, only: wp, i8
  use dpmpm_strings, only: ftoa
  use dpmpm_timer, only: t_total, t_output, t_checkpoint
  use dpmpm_config, only: config_t, fbc_names, face_names
  use dpmpm_kernels, only: kernel_reach
  use dpmpm_mls, only: mls_stats_t, basis_size, packed_size
  use dpmpm_gauss_fields, only: gauss_cell_components, gauss_solution_components, gauss_cover_radius, &
                                gauss_second_field_components
  use dpmpm_generate, only: generate_points
  use dpmpm_materials, only: materials_from_config, model_fluid, model_rigid, init_state
  use dpmpm_model_table, only: model_needs_defgrad, is_pressure_dependent
  use dpmpm_rigid, only: hold_rigid_points, body_velocities
  use dpmpm_output, only: output_h5_path
  use dpmpm_checkpoint, only: checkpoint_state_t, checkpoint_path, write_checkpoint, read_checkpoint
  use dpmpm_scene_check, only: check_scene_points
  use dpmpm_posix, only: stop_signal, peak_resident_kib
  use dpmpm_benchmarks, only: benchmark_setup, nbench_err
  use dpmpm_gather, only: gather_points
  use dpmpm_migrate, only: balance_by_points, balance_nested
  use dpmpm_error, only: fatal
  use dpmpm_phase, only: solid_phase, fluid_phase
  use dpmpm_axisym, only: axisym_point_measures
  use dpmpm_state, only: state_t, exit_bad_input, exit_stopped
  use dpmpm_step, only: advance
  use dpmpm_probes, only: probes_t
  use dpmpm_run_summary, only: report_summary, report_stop, points_per_rank
  use dpmpm_time_step, only: stable_dt
  use dpmpm_load_path, only: check_load_path
  use dpmpm_energy, only: diagnostics, monitor_stopped, check_state, monitor_state, set_monitor_state, &
                          end_equilibrium
  use dpmpm_verification_log, only: two_phase_benchmark, record_two_phase_errors, write_verification, &
                                    report_mls
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_INTEGER8, &
                     MPI_SUM, MPI_MAX, MPI_MIN, MPI_Wtime, MPI_INTEGER
  implicit none
  private
  public :: simulation_t, run_scene

  !> Steps between the collective looks at a stop request (signal, max_wall_time).
  integer(i8), parameter :: stop_every = 10

  !> A run: its state and the procedures that make, run and release it.
  type, extends(state_t) :: simulation_t
    type(probes_t) :: probes   !< records at points (&output nprobes)
  contains
    procedure :: init => sim_init
    procedure :: run => sim_run
    procedure :: write_frame => sim_write_frame
    procedure :: gather_points => sim_gather_points
    procedure :: free => sim_free
  end type simulation_t

contains

  !> Build, run and finish the scene described by cfg on the ranks of comm; the exit
  !> status of the run: 0 finished, 2 bad restart or time step, 3 stopped early with a
  !> checkpoint, 4 stopped by the run monitor (the same on every rank).
  integer function run_scene(cfg, comm) result(status)
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    type(simulation_t) :: sim
    call sim%init(cfg, comm)
    if (sim%exit_code == 0) call sim%run()
    status = sim%exit_code
    if (status == 0 .and. sim%stopped /= 0) status = exit_stopped
    call sim%free()
  end function run_scene

  !> Decompose the grid, create the points, open the output.
  subroutine sim_init(self, cfg, comm, write_output)
    class(simulation_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(MPI_Comm), intent(in) :: comm
    logical, intent(in), optional :: write_output
    integer :: nmin, nmax, status, nloc(2), m
    logical :: changed
    integer(i8) :: ntot, nfl
    integer(i8), allocatable :: counts(:), fcounts(:)
    character(len=256) :: line
    call self%free()
    self%kib_start = peak_resident_kib()
    self%cfg = cfg
    self%exit_code = 0
    self%mon%growth_stop = .false.
    self%write_output = .true.
    if (present(write_output)) self%write_output = write_output
    self%ext_work = 0.0_wp
    self%drag_loss = 0.0_wp
    self%mon%started = .false.
    self%mon%ratio = 0.0_wp
    self%mon%ke_max = 0.0_wp
    self%mon%balance = 0.0_wp
    self%mon%warned = .false.
    self%box_known = .false.
    self%drive_impulse = 0.0_wp
    self%drive_t0 = 0.0_wp
    self%ndrive = 0
    self%cut_time = -1.0_wp
    self%mon%prev = 0.0_wp
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
    self%mls_stats = mls_stats_t()
    self%nkept = 0
    self%nthin = 0
    self%nwall = 0
    self%ncavitated = 0
    self%nfree_surface = 0
    self%noutflow = 0
    self%outflow_mass = 0.0_wp
    self%inflow_mass = 0.0_wp
    call self%grid%init(cfg)
    call self%dec%init(comm, cfg%ndim, cfg%ncells, self%plan%ghost_width(), cfg%dims)
    call materials_from_config(cfg%materials, self%mats)
    self%two_phase = any(cfg%regions%phase /= 'solid')
    call self%phase(1)%pts%init('solid', self%nd, any(model_needs_defgrad(self%mats%model)), &
                         has_porosity=self%two_phase, &
                         nstate=maxval([0, self%mats%nstate]))
    if (self%two_phase) &
      call self%phase(2)%pts%init('fluid', self%nd, .false., has_porosity=.true., has_pressure=.true.)
    self%nph = merge(2, 1, self%two_phase)
    if (len_trim(cfg%restart) > 0) then
      call restart_from(self, trim(cfg%restart))
      if (self%exit_code /= 0) return
    else
      allocate (counts(size(cfg%regions)), fcounts(size(cfg%regions)))
      fcounts = 0
      call generate_points(cfg, self%grid, self%dec%clo, self%dec%chi, self%mats, self%phase(1)%pts, &
                           counts=counts)
      ! Axisymmetry: volumes and masses per radian (a restart reads them as they are).
      if (cfg%axisymmetric) then
        associate (ps => self%phase(1)%pts)
          call axisym_point_measures(ps%n, ps%x, self%grid%h(1), ps%vol, ps%vol0, ps%mass)
        end associate
      end if
      call benchmark_setup(cfg, self%mats, self%phase(1)%pts)
      ! the models' state values from the initial stress (a restart reads them instead)
      do m = 1, size(self%mats)
        associate (ps => self%phase(1)%pts)
          if (ps%nstate > 0) call init_state(self%mats(m), m, ps%n, ps%mat, ps%stress, ps%state, &
                                             ps%x, ps%id)
        end associate
      end do
      if (self%two_phase) then
        call generate_points(cfg, self%grid, self%dec%clo, self%dec%chi, self%mats, self%phase(2)%pts, &
                             'fluid', fcounts)
        ! (the pore water's volumes and masses per radian too)
        if (cfg%axisymmetric) then
          associate (ps => self%phase(2)%pts)
            call axisym_point_measures(ps%n, ps%x, self%grid%h(1), ps%vol, ps%vol0, ps%mass)
          end associate
        end if
        call check_scene_points(cfg, self%grid, self%dec%comm, counts + fcounts, self%phase(1)%pts, &
                                status, self%phase(2)%pts)
      else
        call check_scene_points(cfg, self%grid, self%dec%comm, counts, self%phase(1)%pts, status)
      end if
      if (status /= 0) then
        self%exit_code = exit_bad_input
        return
      end if
    end if
    ! The grid split for equal numbers of points per rank (the cuts are those of the points
    ! made or read now; the rank layout stays).
    self%nrebalance = 0
    if (cfg%balance /= 'cells' .and. self%dec%nranks > 1) call split_by_points(self, changed)
    call self%bnd%init(cfg, self%grid, self%kernel, self%two_phase)
    if (self%two_phase) call init_two_phase(self)
    call self%mirror%init(self%nd, self%grid%ncells, self%dec%gw, self%dec%alo, self%dec%ahi)
    self%phase(1)%bc = self%bnd%kind(:, 1)
    if (self%two_phase) self%phase(2)%bc = self%bnd%kind(:, 2)
    self%has_surface_loads = .false.
    if (allocated(cfg%loads)) self%has_surface_loads = any(cfg%loads%surface)
    self%has_rigid = any(self%mats%model == model_rigid)
    self%pressure_dependent = any(is_pressure_dependent(self%mats%model))
    if (self%has_rigid) then
      allocate (self%drive_hist(4, 64))
      ! the drive's first interval begins at the start (a restart: at its time)
      self%drive_t0 = merge(self%time, 0.0_wp, len_trim(cfg%restart) > 0)
      ! Rigid bodies move at their velocity from the start (a restart keeps the stored one).
      if (len_trim(cfg%restart) == 0) call hold_rigid_points(self%nd, self%phase(1)%pts%n, &
                                                             self%phase(1)%pts%mat, self%mats, &
                                                             body_velocities(self%mats, 0.0_wp), &
                                                             self%phase(1)%pts%v)
    end if

    ntot = self%phase(1)%pts%n
    call MPI_Allreduce(MPI_IN_PLACE, ntot, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    call MPI_Allreduce(self%phase(1)%pts%n, nmin, 1, MPI_INTEGER, MPI_MIN, self%dec%comm)
    call MPI_Allreduce(self%phase(1)%pts%n, nmax, 1, MPI_INTEGER, MPI_MAX, self%dec%comm)
    write (line, '(a,i0,a,i0,a,i0,a,i0,a,i0,a,i0,a,i0)') 'dpmpm: ', self%dec%nranks, ' ranks (', &
      self%dec%dims(1), ' x ', self%dec%dims(2), ' x ', self%dec%dims(3), '); ', ntot, &
      ' solid points; per rank min ', nmin, ' max ', nmax
    call self%log%info(line)
    if (self%two_phase) then
      nfl = self%phase(2)%pts%n
      call MPI_Allreduce(MPI_IN_PLACE, nfl, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
      ! Ids of fluid points added at inflow faces start above every id there is (a restart
      ! goes on with the count of its checkpoint; restart_from sets it, or -1 where an
      ! earlier checkpoint has none: then above every id at the restart).
      if (len_trim(cfg%restart) == 0 .or. self%ninflow < 0) then
        self%inflow_id0 = 0
        if (self%phase(2)%pts%n > 0) self%inflow_id0 = maxval(self%phase(2)%pts%id(1:self%phase(2)%pts%n))
        call MPI_Allreduce(MPI_IN_PLACE, self%inflow_id0, 1, MPI_INTEGER8, MPI_MAX, self%dec%comm)
        self%ninflow = 0
      end if
      write (line, '(a,i0,a,a)') 'dpmpm: ', nfl, ' fluid points; drag ', trim(cfg%drag)
      if (cfg%porosity_gradient) line = trim(line)//'; with the porosity-gradient term'
      call self%log%info(trim(line))
      ntot = ntot + nfl
    end if
    ! How evenly the points are spread over the ranks, with a hint where they are not.
    if (self%dec%nranks > 1) then
      nloc = points_per_rank(self)
      if (real(nloc(1), wp) > 1.5_wp*real(ntot, wp)/real(self%dec%nranks, wp)) then
        write (line, '(a,i0,a,i0)') 'dpmpm: the busiest rank holds ', nloc(1), ' points, the mean is ', &
          ntot/self%dec%nranks
        if (cfg%balance /= 'cells') then
          line = trim(line)//' (the grid is split by the points at the start)'
        else
          line = trim(line)//'; &grid balance = ''points'' splits the grid for equal numbers'
        end if
        call self%log%info(trim(line))
      end if
    end if
    if (ntot == 0) then
      call self%log%error('the regions produced no points')
      self%exit_code = exit_bad_input
      return
    end if

    call grid_fields(self)
    allocate (self%err_hist(1 + nbench_err, 64))
    if (len_trim(cfg%restart) == 0) then
      self%time = 0.0_wp
      self%step = 0
    end if
    self%dt = stable_dt(self)
    if (self%exit_code /= 0) return
    if (self%write_output) then
      call remove_stale_temporary(self)
      if (len_trim(cfg%restart) > 0) then
        call resume_output(self)
      else
        call announce_output(self)
        call self%out%open(self%cfg, self%dec%comm)
      end if
    end if
    call diagnostics(self)
    call check_load_path(self)
    if (self%bnd%faces%walls%rough .and. cfg%flip > 0.5_wp) call self%log%warning('rough walls (&boundary '// &
      'friction) with flip > 0.5: a block that the friction should hold creeps (flip 1, friction '// &
      '0.7 at 30 degrees: 2 mm in 0.1 s, 0.03 mm with flip 0.5), and with flip 1 a cohesionless '// &
      'soil flowing on a wall that lets go of its nodes throws points off it (lift_off = .false. '// &
      'holds them; doc/verification.md, "Rough walls")')
    if (maxval(self%bnd%faces%walls%friction) >= 0.45_wp .and. self%nph == 2) call self%log%warning('rough '// &
      'walls (&boundary friction) of 0.45 or more under pore water: the wall holds the skeleton '// &
      'where it would pull it (it lets go only in scenes of one phase), and a saturated block with '// &
      'friction 0.7 slid 9.5 % too far, with a soft pore fluid half the distance (doc/verification.md, '// &
      '"Larger friction: frictional flutter")')
    call warn_field_reach(self)
    if (self%two_phase) then
      call self%probes%init(self%cfg, self%grid, self%dec%comm, self%phase(1)%pts, self%phase(2)%pts)
    else
      call self%probes%init(self%cfg, self%grid, self%dec%comm, self%phase(1)%pts)
    end if
    ! A restarted run keeps the frame schedule of the run it continues.
    if (len_trim(cfg%restart) == 0) call self%write_frame()
  end subroutine sim_init

  !> Gauss quadrature with a field weight (radial, or a box) too short to reach every
  !> place of a cell from the cell's Gauss points: points there find none, keep their
  !> velocity gradient from the step before and give their stress to no Gauss point.
  subroutine warn_field_reach(self)
    class(simulation_t), intent(inout) :: self
    real(wp) :: cover
    character(len=16) :: r, c
    if (.not. self%plan%gauss .or. self%plan%field_radius <= 0.0_wp) return
    ! a box reaches the corners when its half-width passes the widest gap along an axis
    cover = gauss_cover_radius(merge(self%cfg%ndim, 1, self%plan%field_radial), self%plan%ngauss)
    if (self%plan%field_radius > cover) return
    write (r, '(f6.3)') self%plan%field_radius
    write (c, '(f6.3)') cover
    call self%log%warning('&shape field_radius = '//trim(adjustl(r))//' cells does not reach every place of a '// &
      'cell from its Gauss points (the farthest lies '//trim(adjustl(c))//' cells from them): points there keep '// &
      'their velocity gradient and give their stress to no Gauss point (counted at the end as point '// &
      'gradients left point-wise); take field_radius > '//trim(adjustl(c))//' (doc/input.md, &shape)')
  end subroutine warn_field_reach

  !> A <name>.ckpt.h5.tmp left by a run killed while writing its checkpoint is a torn copy
  !> (the checkpoint before it is whole), and so is a <name>.h5.tmp left by a run killed
  !> while rebuilding its output (the output it rebuilt is left as it was): removed, and said.
  subroutine remove_stale_temporary(self)
    class(simulation_t), intent(in) :: self
    if (.not. self%log%root) return
    call remove_torn(self, checkpoint_path(self%cfg%output_dir, self%cfg%name)//'.tmp', &
                     'a checkpoint')
    call remove_torn(self, output_h5_path(self%cfg)//'.tmp', 'a rebuilt output file')
  end subroutine remove_stale_temporary

  !> Remove the file path, what an earlier run's end tore, where it exists; said in the log.
  subroutine remove_torn(self, path, what)
    class(simulation_t), intent(in) :: self
    character(len=*), intent(in) :: path, what
    logical :: exists
    integer :: u, ios
    inquire (file=path, exist=exists)
    if (.not. exists) return
    open (newunit=u, file=path, status='old', iostat=ios)
    if (ios == 0) close (u, status='delete', iostat=ios)
    if (ios == 0) then
      call self%log%info('dpmpm: removed '//path//', '//what//' torn by an earlier run''s end')
    else
      call self%log%warning('cannot remove '//path//' ('//what//' torn by an earlier run)')
    end if
  end subroutine remove_torn

  !> Say where the output goes, and warn when that replaces the file of an earlier run.
  subroutine announce_output(self)
    class(simulation_t), intent(in) :: self
    character(len=:), allocatable :: path
    logical :: exists
    path = trim(self%cfg%output_dir)//'/'//trim(self%cfg%name)//'.h5'
    call self%log%info('dpmpm: writing '//path)
    if (.not. self%log%root) return
    inquire (file=path, exist=exists)
    if (exists) call self%log%warning(path//' exists and is overwritten (another &run name '// &
                                      'or &output dir keeps it)')
  end subroutine announce_output

  !> The node and cell fields of this rank's stored range (dec%alo .. dec%ahi), allocated
  !> anew (at the start, and after the grid was split again by the points): none of them
  !> carries a value from one step to the next that the step does not set first.
  subroutine grid_fields(self)
    class(simulation_t), intent(inout) :: self
    integer :: nb, ip
    do ip = 1, 2
      associate (ph => self%phase(ip))
        if (allocated(ph%node)) deallocate (ph%node)
        if (allocated(ph%nvel)) deallocate (ph%nvel)
        if (allocated(ph%vacc)) deallocate (ph%vacc)
        if (allocated(ph%gacc)) deallocate (ph%gacc)
        if (allocated(ph%gsol)) deallocate (ph%gsol)
        if (allocated(ph%gsol2)) deallocate (ph%gsol2)
        if (allocated(ph%glg)) deallocate (ph%glg)
        if (allocated(ph%gacc2)) deallocate (ph%gacc2)
        if (allocated(ph%glg2)) deallocate (ph%glg2)
        if (allocated(ph%nvol)) deallocate (ph%nvol)
      end associate
    end do
    if (allocated(self%occ)) deallocate (self%occ)
    if (allocated(self%occ2)) deallocate (self%occ2)
    call self%cpl%free()
    if (allocated(self%sforce)) deallocate (self%sforce)
    if (allocated(self%rnode)) deallocate (self%rnode)
    associate (lo => self%dec%alo, hi => self%dec%ahi)
      allocate (self%phase(1)%node(1 + 2*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
      allocate (self%phase(1)%nvel(2*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
      if (self%plan%velocity_mls) then
        nb = basis_size(self%plan%velocity_basis, self%nd)
        allocate (self%phase(1)%vacc(1 + packed_size(nb) + nb*self%nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        if (self%two_phase) allocate (self%phase(2)%vacc, mold=self%phase(1)%vacc)
      end if
      if (self%plan%gauss) then
        associate (ng => self%plan%ngauss, basis => self%plan%field_basis, nd => self%nd)
          allocate (self%phase(1)%gacc(gauss_cell_components(nd, ng, basis), lo(1):hi(1), lo(2):hi(2), &
                              lo(3):hi(3)))
          allocate (self%phase(1)%gsol(gauss_solution_components(nd, ng, basis), lo(1):hi(1), &
                              lo(2):hi(2), lo(3):hi(3)))
          allocate (self%phase(1)%glg(ng**nd*nd*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
          allocate (self%phase(1)%nvol(2, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
          if (any(self%cfg%gravity /= 0.0_wp)) then
            ! (the density at the Gauss points for their gravity; its counts and moments
            ! are those of gacc)
            allocate (self%phase(1)%gacc2(gauss_second_field_components(nd, ng, basis), lo(1):hi(1), &
                                          lo(2):hi(2), lo(3):hi(3)))
            allocate (self%phase(1)%gsol2, mold=self%phase(1)%gsol)
          end if
        end associate
        allocate (self%occ(1, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (self%occ2, mold=self%occ)
        self%fill = max(1, min(floor(kernel_reach(self%plan%field_kernel, self%plan%field_radius, &
                                                  self%plan%field_radial) + 1.0e-9_wp), &
                               minval(self%dec%gw(1:self%nd))))
      end if
      if (self%two_phase) then
        allocate (self%phase(2)%node, mold=self%phase(1)%node)
        allocate (self%phase(2)%nvel, mold=self%phase(1)%nvel)
        allocate (self%cpl%nporo(3, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (self%cpl%ndrag(1, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        if (self%plan%gauss) then
          ! The fluid's fields are the pore pressure's shares, isotropic: one per Gauss point.
          self%phase(2)%giso = .true.
          associate (ng => self%plan%ngauss, basis => self%plan%field_basis, nd => self%nd)
            allocate (self%phase(2)%gacc(gauss_cell_components(nd, ng, basis, isotropic=.true.), &
                                         lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
            allocate (self%phase(2)%gsol(gauss_solution_components(nd, ng, basis, isotropic=.true.), &
                                         lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
            ! (the second field's sums alone: its counts and moments are those of gacc)
            allocate (self%phase(2)%gacc2(gauss_second_field_components(nd, ng, basis, isotropic=.true.), &
                                          lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
          end associate
          allocate (self%phase(2)%gsol2, mold=self%phase(2)%gsol)
          allocate (self%phase(2)%glg, mold=self%phase(1)%glg)
          allocate (self%phase(2)%glg2, mold=self%phase(1)%glg)
          allocate (self%phase(2)%nvol, mold=self%phase(1)%nvol)
        end if
      end if
    end associate
    if (self%has_surface_loads) then
      allocate (self%sforce(self%nd, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                            self%dec%alo(3):self%dec%ahi(3)))
      self%sforce = 0.0_wp
    end if
    if (self%has_rigid) then
      allocate (self%rnode(1 + self%nd, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                           self%dec%alo(3):self%dec%ahi(3)))
      self%rnode = 0.0_wp
    end if
    ! The next step clears the whole of the new node fields, as the first step does (the
    ! steps after it clear only the box where points were or are; step_box).
    self%box_known = .false.
  end subroutine grid_fields

  !> The cuts of the grid chosen by the points of every set, which then move to their new
  !> ranks (balance_by_points; &grid balance = 'nested': balance_nested); changed: the
  !> cuts moved. Collective.
  subroutine split_by_points(self, changed)
    class(simulation_t), intent(inout) :: self
    logical, intent(out) :: changed
    integer :: nlost
    if (self%cfg%balance == 'nested') then
      if (self%two_phase) then
        call balance_nested(self%dec, self%grid%origin, self%grid%h, self%plan%ghost_width(), &
                            self%phase(1)%pts, self%phase(2)%pts, nlost, changed)
      else
        call balance_nested(self%dec, self%grid%origin, self%grid%h, self%plan%ghost_width(), &
                            self%phase(1)%pts, nlost=nlost, changed=changed)
      end if
    else if (self%two_phase) then
      call balance_by_points(self%dec, self%grid%origin, self%grid%h, self%plan%ghost_width(), &
                             self%phase(1)%pts, self%phase(2)%pts, nlost, changed)
    else
      call balance_by_points(self%dec, self%grid%origin, self%grid%h, self%plan%ghost_width(), &
                             self%phase(1)%pts, nlost=nlost, changed=changed)
    end if
    if (nlost > 0) call fatal('points outside the grid or the cells of their ranks after the '// &
                              'split by points (&grid balance)', 'split_by_points')
  end subroutine split_by_points

  !> Split the grid again by the points (&grid balance = 'points' or 'nested') when the busiest rank
  !> holds more than &grid balance_tolerance above the mean; the points move to their new ranks
  !> and the node fields are allocated for the new ranges. Collective.
  subroutine rebalance(self)
    class(simulation_t), intent(inout) :: self
    integer :: nloc(2)
    logical :: changed
    nloc = points_per_rank(self)
    if (real(nloc(1), wp) <= (1.0_wp + self%cfg%balance_tolerance)*real(nloc(2), wp)/ &
        real(self%dec%nranks, wp)) return
    call split_by_points(self, changed)
    if (.not. changed) return
    call self%mirror%init(self%nd, self%grid%ncells, self%dec%gw, self%dec%alo, self%dec%ahi)
    call grid_fields(self)
    self%nrebalance = self%nrebalance + 1
  end subroutine rebalance

  !> Continue from a checkpoint: the points of this rank's cells, time, step, energy
  !> balance and frame schedule (the output file: resume_output).
  subroutine restart_from(self, path)
    class(simulation_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    type(checkpoint_state_t) :: st
    character(len=256) :: line
    character(len=:), allocatable :: problem
    associate (g => self%grid, c => self%cfg)
      if (self%two_phase) then
        call read_checkpoint(path, st, g%origin, g%h, self%dec%clo, self%dec%chi, g%ncells, &
                             c%length, problem, self%phase(1)%pts, self%phase(2)%pts)
      else
        call read_checkpoint(path, st, g%origin, g%h, self%dec%clo, self%dec%chi, g%ncells, &
                             c%length, problem, self%phase(1)%pts)
      end if
    end associate
    ! Every rank read the same file and found the same problem.
    if (len(problem) > 0) then
      call self%log%error('restart: '//problem)
      self%exit_code = exit_bad_input
      return
    end if
    if (.not. st%has_checksum) call self%log%info('dpmpm: '//path//' carries no checksums '// &
      '(an earlier version wrote it): its data are used unchecked')
    self%step = st%step
    self%time = st%time
    self%inflow_id0 = st%inflow_id0
    self%ninflow = merge(st%ninflow, -1_i8, st%has_inflow)
    ! ext_work is kept per rank and summed in the diagnostics: the total goes to rank 0.
    self%ext_work = 0.0_wp
    if (self%dec%rank == 0) self%ext_work = st%ext_work
    ! Drag dissipation and the run monitor go on from their values at the checkpoint (a
    ! checkpoint of an earlier version has neither: the monitor then starts over).
    self%drag_loss = 0.0_wp
    if (self%dec%rank == 0) self%drag_loss = st%drag_loss
    ! (the mass through drained faces since the run's start: summed over the ranks)
    self%inflow_mass = merge(st%inflow_mass, 0.0_wp, self%dec%rank == 0)
    self%outflow_mass = merge(st%outflow_mass, 0.0_wp, self%dec%rank == 0)
    if (st%has_monitor) then
      call set_monitor_state(self, st%monitor)
    else
      call self%log%info('dpmpm: '//path//' holds no monitor state (an earlier version wrote '// &
                         'it): the energy monitor measures from the restart')
    end if
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
    class(simulation_t), intent(inout) :: self
    character(len=:), allocatable :: why
    character(len=32) :: tag
    logical :: ok
    call self%out%resume(self%cfg, self%dec%comm, self%nframes, self%step, ok, why)
    if (ok .and. len(why) > 0) call self%log%info('dpmpm: '//why)
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
    class(simulation_t), intent(inout) :: self
    type(checkpoint_state_t) :: st
    character(len=:), allocatable :: path
    real(wp) :: work(4)
    call self%timers%tic(t_checkpoint)
    call MPI_Allreduce([self%ext_work, self%drag_loss, self%inflow_mass, self%outflow_mass], work, 4, &
                       MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    st = checkpoint_state_t(step=self%step, time=self%time, ext_work=work(1), drag_loss=work(2), &
                            has_monitor=.true., monitor=monitor_state(self), &
                            energy0=self%energy0, energy_scale=self%energy_scale, &
                            energy_error=self%energy_error, next_frame=self%next_frame, &
                            nframes=self%nframes, ndim=self%nd, ncells=self%cfg%ncells, &
                            origin=self%cfg%origin, length=self%cfg%length, &
                            inflow_id0=self%inflow_id0, ninflow=self%ninflow, &
                            inflow_mass=work(3), outflow_mass=work(4))
    path = checkpoint_path(self%cfg%output_dir, self%cfg%name)
    if (self%two_phase) then
      call write_checkpoint(path, self%cfg%output_dir, self%dec%comm, st, self%phase(1)%pts, self%phase(2)%pts)
    else
      call write_checkpoint(path, self%cfg%output_dir, self%dec%comm, st, self%phase(1)%pts)
    end if
    self%wall_checkpoint = MPI_Wtime()
    call self%timers%toc(t_checkpoint)
  end subroutine write_state

  !> Two-phase set-up: the stiffest and lightest fluid for the undrained wave speed of the
  !> time step, and the pore-fluid condition of each face (resolved by the faces' init,
  !> resolve_fluid_bc) in the log.
  subroutine init_two_phase(self)
    class(simulation_t), intent(inout) :: self
    integer :: f, m
    character(len=256) :: line
    self%kf_max = 0.0_wp
    self%rhof_min = huge(1.0_wp)
    do m = 1, size(self%mats)
      if (self%mats(m)%model /= model_fluid) cycle
      self%kf_max = max(self%kf_max, self%mats(m)%bulk_fluid)
      self%rhof_min = min(self%rhof_min, self%mats(m)%density)
    end do
    line = '  pore fluid at the faces:'
    do f = 1, 2*self%nd
      ! (a tied face's fluid is tied with the skeleton: no condition of its own)
      line = trim(line)//' '//face_names(f)//' '// &
             trim(merge('tied       ', fbc_names(self%bnd%fbc(f)), self%bnd%tied(f)))
    end do
    call self%log%info(trim(line))
  end subroutine init_two_phase

  !> Step to t_end (or max_steps), with diagnostics, frames and progress lines.
  subroutine sim_run(self)
    class(simulation_t), intent(inout) :: self
    integer(i8) :: diag_every, step0
    logical :: checkpoint_due
    real(wp) :: last_progress, now, eta, dt, loop_start, time0, done
    character(len=256) :: line
    self%stopped = 0
    self%exit_code = 0
    diag_every = self%cfg%diag_every
    if (diag_every <= 0) diag_every = max(1_i8, int(self%cfg%t_end/self%dt/500.0_wp, i8))
    last_progress = MPI_Wtime()
    loop_start = last_progress
    time0 = self%time
    step0 = self%step
    call self%timers%tic(t_total)
    do while (self%time < self%cfg%t_end*(1.0_wp - 1.0e-12_wp) .and. self%step < self%cfg%max_steps)
      dt = min(stable_dt(self), self%cfg%t_end - self%time)
      if (self%exit_code /= 0) exit
      call advance(self, dt)
      self%dt = dt
      self%time = self%time + self%dt
      self%step = self%step + 1
      if (self%probes%n > 0) call sample_probes(self)
      call check_state(self)
      if (self%exit_code /= 0) exit
      if (self%cfg%balance /= 'cells' .and. self%cfg%balance_every > 0 .and. self%dec%nranks > 1) then
        if (mod(self%step, int(self%cfg%balance_every, i8)) == 0) call rebalance(self)
      end if
      if (self%time - self%dt < self%cfg%equilibrium_time .and. &
          self%time >= self%cfg%equilibrium_time) call end_equilibrium(self)
      ! With explicit drag the first step may be far shorter than the wave step.
      if (self%step == 1 .and. self%cfg%diag_every <= 0) &
        diag_every = max(1_i8, int(self%cfg%t_end/self%dt/500.0_wp, i8))
      if (mod(self%step, diag_every) == 0) call record_diagnostics(self)
      if (self%exit_code /= 0) exit
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
        write (line, '(a,i0,a,es12.5,a,es10.3,a,f6.1,a)') 'step ', self%step, '  t = ', &
          self%time, '  dt = ', self%dt, '  ', 100.0_wp*max(self%time/self%cfg%t_end, &
          real(self%step, wp)/real(self%cfg%max_steps, wp)), &
          '%  ETA '//ftoa(eta, 1)//' s'
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
    ! A collective stop (bad time step, the monitor): the run ends here, its output closed.
    if (self%exit_code /= 0) then
      if (self%out%is_active()) call self%out%close()
      return
    end if
    ! Stopped early: the checkpoint first, of the state exactly as the loop left it.
    if (self%stopped /= 0) call write_state(self)
    ! (A run that took no step, continued from a checkpoint at its end, has its record.)
    if (mod(self%step, diag_every) /= 0 .and. self%step /= step0) then
      call record_diagnostics(self)
      if (self%exit_code /= 0) return
    end if
    if (self%last_frame_step /= self%step) call self%write_frame()
    ! The end state too, so that a finished run can be continued to a later t_end.
    if (self%cfg%checkpoint_every > 0 .and. self%stopped == 0) then
      if (mod(self%step, int(self%cfg%checkpoint_every, i8)) /= 0) call write_state(self)
    end if
    call write_verification(self)
    if (self%write_output) call self%probes%write(self%out, self%grid)
    call report_mls(self)
    call report_summary(self, self%step - step0)
    if (self%write_output) then
      call self%out%close()
      call self%log%info('dpmpm: output '//trim(self%cfg%output_dir)//'/'//trim(self%cfg%name)//'.h5')
    end if
    if (self%stopped /= 0) call report_stop(self)
  end subroutine sim_run

  !> The probes' records after a step (dpmpm_probes): the solid's nodes, the followed points.
  subroutine sample_probes(self)
    class(simulation_t), intent(inout) :: self
    if (self%two_phase) then
      call self%probes%sample(self%phase(1)%nvel, self%dec%alo, self%dec%olo, self%dec%ohi, &
                              self%dec%comm, self%time, self%step, self%dt, self%phase(1)%pts, &
                              self%phase(2)%pts)
    else
      call self%probes%sample(self%phase(1)%nvel, self%dec%alo, self%dec%olo, self%dec%ohi, &
                              self%dec%comm, self%time, self%step, self%dt, self%phase(1)%pts)
    end if
  end subroutine sample_probes

  !> The diagnostics record (dpmpm_energy); when the run monitor stops the run for
  !> growth, the last frame and the verification records so far (benchmark errors, the
  !> drive force of rigid bodies) are written and the output closed here.
  subroutine record_diagnostics(self)
    class(simulation_t), intent(inout) :: self
    call diagnostics(self)
    call check_load_path(self)
    if (.not. self%mon%growth_stop) return
    call self%write_frame()
    call write_verification(self)
    if (self%write_output) call self%probes%write(self%out, self%grid)
    call monitor_stopped(self)
  end subroutine record_diagnostics

  !> Collective: a stop signal (SIGTERM, SIGUSR1: what batch schedulers send before the
  !> kill) on any rank, returned as its number, or -1 when max_wall_time is over; 0 to go on.
  !> checkpoint_due: checkpoint_seconds of wall time have passed since the last checkpoint.
  integer function stop_request(self, checkpoint_due) result(why)
    class(simulation_t), intent(in) :: self
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

  !> Write one frame of all point sets.
  subroutine sim_write_frame(self)
    class(simulation_t), intent(inout) :: self
    self%nframes = self%nframes + 1
    self%last_frame_step = self%step
    self%next_frame = self%next_frame + self%cfg%frame_interval
    if (.not. self%write_output) return
    call self%timers%tic(t_output)
    call self%out%begin_frame(self%step, self%time)
    call self%out%write_set(self%phase(1)%pts, self%cfg)
    if (self%two_phase) call self%out%write_set(self%phase(2)%pts, self%cfg)
    call self%out%end_frame()
    call self%timers%toc(t_output)
    if (two_phase_benchmark(self)) call record_two_phase_errors(self)
  end subroutine sim_write_frame

  !> Gather the points of all ranks on rank 0, sorted by id: ids, positions,
  !> velocities and stresses (for comparisons between runs); of the fluid points
  !> (stress -p I) when fluid is true.
  subroutine sim_gather_points(self, ids, x, v, stress, fluid)
    class(simulation_t), intent(in) :: self
    integer(i8), allocatable, intent(out) :: ids(:)
    real(wp), allocatable, intent(out) :: x(:, :), v(:, :), stress(:, :)
    logical, intent(in), optional :: fluid
    integer :: ip
    ip = solid_phase
    if (present(fluid)) then
      if (fluid) ip = fluid_phase
    end if
    call gather_points(self%phase(ip)%pts, self%nd, self%dec%comm, ids, x, v, stress)
  end subroutine sim_gather_points

  !> Release everything init made: the phases and their work arrays, the coupling
  !> node fields, the decomposition, the records and the materials.
  subroutine sim_free(self)
    class(simulation_t), intent(inout) :: self
    integer :: ip
    do ip = 1, size(self%phase)
      call self%phase(ip)%free()
    end do
    self%nph = 1
    call self%dec%free()
    call self%cpl%free()
    if (allocated(self%rnode)) deallocate (self%rnode)
    if (allocated(self%sforce)) deallocate (self%sforce)
    self%has_surface_loads = .false.
    if (allocated(self%drive_hist)) deallocate (self%drive_hist)
    self%has_rigid = .false.
    if (allocated(self%occ)) deallocate (self%occ)
    if (allocated(self%occ2)) deallocate (self%occ2)
    call self%bnd%free()
    self%governing = 0
    self%two_phase = .false.
    if (allocated(self%err_hist)) deallocate (self%err_hist)
    if (allocated(self%ferr)) deallocate (self%ferr)
    if (allocated(self%fnames)) deallocate (self%fnames)
    self%nferr = 0
    if (allocated(self%mats)) deallocate (self%mats)
    self%cfg = config_t()
  end subroutine sim_free

end module dpmpm_simulation
