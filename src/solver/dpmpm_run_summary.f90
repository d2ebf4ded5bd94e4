!> The end of a run in the log: the summary of what it did and cost (report_summary) and,
!> for a run stopped before t_end, why and how to continue it (report_stop). It reads the
!> run state (state_t) only; dpmpm_simulation calls it.
module dpmpm_run_summary
  use dpmpm_kinds, only: wp, i8
  use dpmpm_strings, only: i8toa, itoa, rtoa, ftoa
  use dpmpm_timer, only: t_total, t_output, t_checkpoint, ntimers, timer_names
  use dpmpm_checkpoint, only: checkpoint_path
  use dpmpm_posix, only: signal_name, peak_resident_kib
  use dpmpm_state, only: state_t
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_INTEGER8, MPI_INTEGER, &
                     MPI_SUM, MPI_MAX, MPI_Wtime, MPI_2DOUBLE_PRECISION, MPI_MAXLOC
  implicit none
  private
  public :: report_summary, report_stop, points_per_rank

contains

  !> The summary at the end of a run (collective): how far it went and in what wall time,
  !> the energy balance, the drive force of rigid bodies, the counts of points put back
  !> inside walls, of fluid points that left through drained faces, of cavitation and
  !> free-surface cuts, the re-splits of the grid, the timers (with the frames and
  !> checkpoints), the memory and the cost of a step; nsteps: the steps this run took.
  subroutine report_summary(self, nsteps)
    class(state_t), intent(in) :: self
    integer(i8), intent(in) :: nsteps
    integer(i8) :: nwall
    real(wp) :: mout
    character(len=256) :: line
    integer :: k
    write (line, '(a,i0,a,es12.5,a)') 'dpmpm: done, ', self%step, ' steps to t = ', &
      self%time, ' in '//ftoa(MPI_Wtime() - self%wall_start, 3)//' s'
    if (self%stopped /= 0) line = 'dpmpm: ended early, '//line(len('dpmpm: done, ') + 1:)
    call self%log%info(line)
    write (line, '(a,es10.3)') '  energy balance: largest change / largest kinetic + stored energy ', &
      self%energy_drift
    call self%log%info(line)
    write (line, '(a,es10.3,a,es10.3,a)') '  energy against the work done + initial energy: '// &
      'largest (kinetic + stored) / (work + initial) ', self%mon%ratio, ', largest balance error ', &
      self%mon%balance, ' (doc/verification.md, "Long runs")'
    call self%log%info(line)
    if (self%has_rigid .and. self%ndrive > 0) then
      write (line, '(a,es11.4,a,3es12.4,a)') '  rigid drive: mean force over the last record (t = ', &
        self%drive_hist(1, self%ndrive), ' s) ', self%drive_hist(2:4, self%ndrive), &
        ' N (per metre of depth in 2D); history in /verification/drive_*'
      call self%log%info(line)
    end if
    nwall = self%nwall
    call MPI_Allreduce(MPI_IN_PLACE, nwall, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    if (nwall > 0) call self%log%info('  points put back inside a wall they had crossed: '// &
                                      i8toa(nwall))
    nwall = self%noutflow
    call MPI_Allreduce(MPI_IN_PLACE, nwall, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    mout = self%outflow_mass
    call MPI_Allreduce(MPI_IN_PLACE, mout, 1, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    if (nwall > 0 .and. any(self%bnd%faces%walls%opened)) then
      call self%log%info('  points that left through openings (since this run or restart '// &
                         'began): '//i8toa(nwall)//'; mass out since the run''s start '//trim(rtoa(mout))// &
                         ' (/diagnostics/outflow_mass)')
    else if (nwall > 0) then
      call self%log%info('  fluid points that left through drained faces: '// &
                                      i8toa(nwall)//'; mass out since the run''s start '// &
                                      trim(rtoa(mout))//' (/diagnostics/outflow_mass)')
    end if
    nwall = self%ncavitated
    call MPI_Allreduce(MPI_IN_PLACE, nwall, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    if (nwall > 0) call self%log%info('  pore pressure cut at the cavitation pressure '// &
                                      trim(rtoa(self%cfg%cavitation_pressure))//' Pa: '// &
                                      i8toa(nwall)//' point-steps')
    nwall = self%nfree_surface
    call MPI_Allreduce(MPI_IN_PLACE, nwall, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    if (nwall > 0) call self%log%info('  pore pressure 0 at the free surface of the pore fluid: '// &
                                      i8toa(nwall)//' point-steps (free_surface_fraction '// &
                                      trim(rtoa(self%cfg%free_surface_fraction))//')')
    if (self%cfg%balance /= 'cells' .and. self%dec%nranks > 1) call report_balance(self)
    do k = 2, ntimers
      write (line, '(a,a12,f10.3,a)') '  time in ', timer_names(k), self%timers%acc(k), ' s (rank 0)'
      ! frames and checkpoints: how many and the time of one (what a plan of the output needs)
      if ((k == t_output .or. k == t_checkpoint) .and. self%timers%calls(k) > 0) &
        line = trim(line)//'; '//itoa(self%timers%calls(k))//trim(merge(' frame     ', &
          ' checkpoint', k == t_output))//trim(merge('s', ' ', self%timers%calls(k) > 1))//', '// &
          ftoa(self%timers%acc(k)/self%timers%calls(k), 3)//' s each'
      call self%log%info(line)
    end do
    call report_memory(self)
    call report_step_cost(self, nsteps)
  end subroutine report_summary

  !> The points of the busiest rank and of all ranks, both sets together. Collective.
  function points_per_rank(self) result(nloc)
    class(state_t), intent(in) :: self
    integer :: nloc(2)
    nloc(1) = self%phase(1)%pts%n
    if (self%two_phase) nloc(1) = nloc(1) + self%phase(2)%pts%n
    nloc(2) = nloc(1)
    call MPI_Allreduce(MPI_IN_PLACE, nloc(1), 1, MPI_INTEGER, MPI_MAX, self%dec%comm)
    call MPI_Allreduce(MPI_IN_PLACE, nloc(2), 1, MPI_INTEGER, MPI_SUM, self%dec%comm)
  end function points_per_rank

  !> The re-splits of the run and how the points are spread over the ranks now.
  subroutine report_balance(self)
    class(state_t), intent(in) :: self
    integer :: nloc(2)
    character(len=256) :: line
    nloc = points_per_rank(self)
    write (line, '(a,i0,a,i0,a,i0,a,i0)') '  grid split by the points: again ', self%nrebalance, &
      ' times in the run (balance_every ', self%cfg%balance_every, '); the busiest rank holds ', &
      nloc(1), ' points, the mean is ', nloc(2)/self%dec%nranks
    call self%log%info(trim(line))
  end subroutine report_balance

  !> What the run holds in memory: bytes per point of each phase (fields, stencil and
  !> per-point work arrays: what the scene's models need, nothing else), the grid
  !> fields of rank 0 per stored node, and the largest peak resident memory over the
  !> ranks with the rank that had it; and what to budget per point: the largest over
  !> the ranks of the peak's growth since the start of the set-up (the libraries and MPI
  !> already loaded) over the rank's points (grid fields and buffers included).
  subroutine report_memory(self)
    class(state_t), intent(in) :: self
    character(len=320) :: line
    integer :: ip, b(2), kib, npts, nr
    real(wp) :: peak(2), budget
    integer(i8) :: nodes, gbytes
    b = 0
    gbytes = 0
    do ip = 1, self%nph
      b(ip) = self%phase(ip)%bytes_per_point()
      gbytes = gbytes + field_bytes(self%phase(ip)%node) + field_bytes(self%phase(ip)%nvel) + &
               field_bytes(self%phase(ip)%vacc) + field_bytes(self%phase(ip)%gacc) + &
               field_bytes(self%phase(ip)%gsol) + field_bytes(self%phase(ip)%gsol2) + &
               field_bytes(self%phase(ip)%glg) + field_bytes(self%phase(ip)%gacc2) + &
               field_bytes(self%phase(ip)%glg2) + field_bytes(self%phase(ip)%nvol)
    end do
    gbytes = gbytes + field_bytes(self%cpl%nporo) + field_bytes(self%cpl%ndrag)
    nodes = product(int(self%dec%ahi - self%dec%alo + 1, i8))
    kib = peak_resident_kib()
    npts = 0
    do ip = 1, self%nph
      npts = npts + self%phase(ip)%pts%n
    end do
    ! (the peak with its rank, by MAXLOC on pairs; the budget by MAX)
    peak = [real(kib, wp), real(self%dec%rank, wp)]
    call MPI_Allreduce(MPI_IN_PLACE, peak, 1, MPI_2DOUBLE_PRECISION, MPI_MAXLOC, self%dec%comm)
    budget = -1.0_wp
    if (kib > 0 .and. self%kib_start > 0 .and. npts > 0) budget = 1024.0_wp*real(kib - self%kib_start, wp)/npts
    call MPI_Allreduce(MPI_IN_PLACE, budget, 1, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    nr = self%dec%nranks
    write (line, '(a,i0,a)') '  memory: ', b(1), ' bytes per solid point'
    if (self%nph == 2) write (line, '(a,a,i0,a)') trim(line), ', ', b(2), ' per fluid point'
    write (line, '(a,a,a,a,i0,a)') trim(line), '; grid fields ', ftoa(real(gbytes, wp)/2.0_wp**20, 1), &
      ' MiB on rank 0 (', gbytes/max(nodes, 1_i8), ' bytes per node)'
    if (peak(1) > 0.0_wp) write (line, '(a,a,a,a,i0,a,i0,a)') trim(line), '; peak resident ', &
      ftoa(peak(1)/1024.0_wp, 1), ' MiB on rank ', nint(peak(2)), ' (the largest of ', nr, ' ranks)'
    call self%log%info(line)
    if (budget > 0.0_wp) then
      write (line, '(a,i0,a)') '  memory to budget: ', nint(budget), ' bytes per point (the largest over the '// &
        'ranks of the peak''s growth since the set-up began, per point of the rank)'
      call self%log%info(line)
    end if
  contains
    integer(i8) function field_bytes(f) result(nb)
      real(wp), allocatable, intent(in) :: f(:, :, :, :)
      nb = 0
      if (allocated(f)) nb = size(f, kind=i8)*storage_size(f)/8
    end function field_bytes
  end subroutine report_memory

  !> Time per step of the run's step loop (rank 0) and its point-updates per second:
  !> the points of rank 0 (every phase) over the time of a step.
  subroutine report_step_cost(self, nsteps)
    class(state_t), intent(in) :: self
    integer(i8), intent(in) :: nsteps
    character(len=256) :: line
    integer :: ip
    real(wp) :: per_step, npts
    if (nsteps <= 0) return
    per_step = self%timers%acc(t_total)/real(nsteps, wp)
    npts = 0.0_wp
    do ip = 1, self%nph
      npts = npts + real(self%phase(ip)%pts%n, wp)
    end do
    write (line, '(a,a,a,i0,a,es10.3,a)') '  time per step ', ftoa(1.0e3_wp*per_step, 3), ' ms over ', nsteps, &
      ' steps; ', npts/max(per_step, tiny(1.0_wp)), ' point-updates/s on rank 0'
    call self%log%info(line)
  end subroutine report_step_cost

  !> Say why the run stopped before t_end and how to continue it.
  subroutine report_stop(self)
    class(state_t), intent(in) :: self
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

end module dpmpm_run_summary
