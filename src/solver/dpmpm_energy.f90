!> Energy and the run monitor (doc/verification.md, "Long runs"): the global
!> diagnostics record (kinetic and stored energy, work of the loads, drag
!> dissipation, momentum), the energy balance, the growth monitor and the check
!> of every point's state after a step. Collective; a stop sets exit_code.
module dpmpm_energy
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use dpmpm_kinds, only: wp, i8
  use dpmpm_diagnostics, only: diag_record_t
  use dpmpm_particles, only: particle_set_t
  use dpmpm_materials, only: strain_energy, model_fluid
  use dpmpm_verification_log, only: record_benchmark_errors, record_drive
  use dpmpm_state, only: state_t, exit_monitor
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_MAX, MPI_Wtime, &
                     MPI_MAXLOC, MPI_2DOUBLE_PRECISION, MPI_Bcast, MPI_LOGICAL, MPI_LAND
  implicit none
  private
  public :: diagnostics, monitor_stopped, check_state, monitor_state, set_monitor_state, end_equilibrium
  public :: state_valid

contains

  !> Global diagnostics at the current step (collective): energies, momentum, the
  !> energy balance, the run monitor and the benchmark errors. A monitor stop sets
  !> exit_code and growth_stop (the caller writes the last frame).
  subroutine diagnostics(self)
    class(state_t), intent(inout) :: self
    type(diag_record_t) :: rec
    real(wp) :: s(11), vmax, fm(4)
    integer :: p, m
    s = 0.0_wp
    do p = 1, self%phase(1)%pts%n
      s(1) = s(1) + 0.5_wp*self%phase(1)%pts%mass(p)*sum(self%phase(1)%pts%v(:, p)**2)
      s(4) = s(4) + self%phase(1)%pts%mass(p)
      s(5:4 + self%nd) = s(5:4 + self%nd) + self%phase(1)%pts%mass(p)*self%phase(1)%pts%v(:, p)
    end do
    do m = 1, size(self%mats)
      if (self%mats(m)%model == model_fluid) cycle
      s(2) = s(2) + strain_energy(self%mats(m), m, self%phase(1)%pts%n, self%phase(1)%pts%mat, self%phase(1)%pts%stress, &
                                  self%phase(1)%pts%vol, self%phase(1)%pts%vol0, self%phase(1)%pts%defgrad, &
                                  self%phase(1)%pts%state)
    end do
    if (self%two_phase) then
      do p = 1, self%phase(2)%pts%n
        s(1) = s(1) + 0.5_wp*self%phase(2)%pts%mass(p)*sum(self%phase(2)%pts%v(:, p)**2)
        s(4) = s(4) + self%phase(2)%pts%mass(p)
        s(5:4 + self%nd) = s(5:4 + self%nd) + self%phase(2)%pts%mass(p)*self%phase(2)%pts%v(:, p)
        ! Stored energy of the compressed pore fluid, n p^2 / (2 K_f) per mixture volume.
        s(2) = s(2) + 0.5_wp*self%phase(2)%pts%porosity(p)*self%phase(2)%pts%pressure(p)**2/ &
               self%mats(self%phase(2)%pts%mat(p))%bulk_fluid*self%phase(2)%pts%vol(p)
      end do
      s(8) = s(8) + real(self%phase(2)%pts%n, wp)
    end if
    s(3) = self%ext_work
    s(8) = s(8) + real(self%phase(1)%pts%n, wp)
    s(9) = self%drag_loss
    s(10) = self%inflow_mass
    s(11) = self%outflow_mass
    call MPI_Allreduce(MPI_IN_PLACE, s, 11, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    do m = 1, 4
      fm(m) = field_max(self, m)
    end do
    call MPI_Allreduce(MPI_IN_PLACE, fm, 4, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    ! the largest point speed of both sets: the largest of the two sets' maxima
    vmax = max(fm(1), fm(2))
    rec%step = self%step
    rec%npoints = nint(s(8), i8)
    rec%values = [self%time, self%dt, s(1), s(2), s(3), vmax, MPI_Wtime() - self%wall_start, &
                  s(4), s(5), s(6), s(7), s(10), s(11)]
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
    if (self%cfg%benchmark /= 'none') call record_benchmark_errors(self)
    if (self%has_rigid) call record_drive(self)
  end subroutine diagnostics

  !> Largest value over this rank's points of monitored field m: 1 speed of the
  !> solid points, 2 speed of the fluid points, 3 largest |component| of the
  !> effective stress, 4 |pore pressure| (0 where a set is absent).
  real(wp) function field_max(self, m) result(f)
    class(state_t), intent(in) :: self
    integer, intent(in) :: m
    integer :: p
    f = 0.0_wp
    select case (m)
    case (1)
      f = largest_speed(self%phase(1)%pts)
    case (2)
      if (.not. self%two_phase) return
      f = largest_speed(self%phase(2)%pts)
    case (3)
      do p = 1, self%phase(1)%pts%n
        f = max(f, maxval(abs(self%phase(1)%pts%stress(:, p))))
      end do
    case (4)
      if (.not. self%two_phase) return
      do p = 1, self%phase(2)%pts%n
        f = max(f, abs(self%phase(2)%pts%pressure(p)))
      end do
    end select
  end function field_max

  !> The largest norm2 of the point velocities of ps (0 without points). The sum of the
  !> absolute components bounds the norm from above; norm2 is taken only where that
  !> bound reaches the running maximum (within 1e-12, for the rounding of the sum), so
  !> the result is the same as norm2 at every point.
  real(wp) function largest_speed(ps) result(f)
    type(particle_set_t), intent(in) :: ps
    integer :: p
    f = 0.0_wp
    do p = 1, ps%n
      if (sum(abs(ps%v(:, p)))*(1.0_wp + 1.0e-12_wp) <= f) cycle
      f = max(f, norm2(ps%v(:, p)))
    end do
  end function largest_speed

  !> The run monitor at a diagnostics record (collective; ke, se, w, d global sums
  !> of kinetic and stored energy, work of loads and gravity, drag dissipation
  !> since t = 0; fm the field maxima of field_max). The scale is what the body
  !> was given: its kinetic + stored energy at the first record plus the largest
  !> |work of the loads| since then. Kinetic + stored energy above growth_limit
  !> times that scale cannot come from the loads: the run is stopped, with a
  !> warning first at a fifth of it.
  subroutine monitor_energy(self, ke, se, w, d, fm)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: ke, se, w, d, fm(4)
    real(wp) :: ratio, wl, dl
    self%mon%ke_max = max(self%mon%ke_max, ke)
    if (.not. self%mon%started) then
      self%mon%started = .true.
      self%mon%e0 = ke + se
      self%mon%w0 = w
      self%mon%d0 = d
      self%mon%input = ke + se
      self%mon%prev = fm
      self%mon%prev_time = self%time
      return
    end if
    wl = w - self%mon%w0
    dl = d - self%mon%d0
    self%mon%input = max(self%mon%input, self%mon%e0 + abs(wl))
    if (self%mon%input <= 0.0_wp) then
      self%mon%prev = fm
      self%mon%prev_time = self%time
      return
    end if
    ratio = (ke + se)/self%mon%input
    self%mon%ratio = max(self%mon%ratio, ratio)
    self%mon%balance = max(self%mon%balance, abs(ke + se + dl - wl - self%mon%e0)/(self%mon%input + dl))
    if (self%cfg%growth_limit > 0.0_wp) then
      if (ratio > self%cfg%growth_limit) then
        call report_growth(self, fm, ratio, .true.)
        return
      else if (ratio > 0.2_wp*self%cfg%growth_limit .and. .not. self%mon%warned) then
        self%mon%warned = .true.
        call report_growth(self, fm, ratio, .false.)
      end if
    end if
    self%mon%prev = fm
    self%mon%prev_time = self%time
  end subroutine monitor_energy

  !> The end of the equilibrium phase (&run equilibrium_time; collective): report what
  !> kinetic energy is left, against the work of gravity and the loads so far, and the
  !> largest speed; then set every point's velocity to zero (the damping is off from here).
  subroutine end_equilibrium(self)
    class(state_t), intent(inout) :: self
    real(wp) :: s(3), vmax
    integer :: ip, p
    character(len=400) :: line
    s = [0.0_wp, self%ext_work + self%drag_loss, 0.0_wp]
    vmax = 0.0_wp
    do ip = 1, self%nph
      associate (ps => self%phase(ip)%pts)
        do p = 1, ps%n
          s(1) = s(1) + 0.5_wp*ps%mass(p)*sum(ps%v(:, p)**2)
          vmax = max(vmax, norm2(ps%v(:, p)))
        end do
        ps%v(:, 1:ps%n) = 0.0_wp
      end associate
    end do
    call MPI_Allreduce(MPI_IN_PLACE, s, 3, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    call MPI_Allreduce(MPI_IN_PLACE, vmax, 1, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    write (line, '(a,es12.5,a,i0,a,es10.3,a,es10.3,a,es10.3,a)') 'dpmpm: equilibrium phase over at t = ', &
      self%time, ' (step ', self%step, '): kinetic energy ', s(1), ' J, ', &
      s(1)/max(abs(s(2)), tiny(1.0_wp)), ' of the work of gravity and loads; largest speed ', vmax, &
      ' m/s; damping off, velocities set to zero'
    call self%log%info(trim(line))
  end subroutine end_equilibrium

  !> The run monitor's state as numbers, for a checkpoint (set_monitor_state reads them
  !> back), so that a continued run measures against what the body was given since t = 0.
  pure function monitor_state(self) result(a)
    class(state_t), intent(in) :: self
    real(wp) :: a(14)
    a = [merge(1.0_wp, 0.0_wp, self%mon%started), self%mon%e0, self%mon%w0, self%mon%d0, &
         self%mon%input, self%mon%ratio, self%mon%ke_max, self%mon%balance, &
         merge(1.0_wp, 0.0_wp, self%mon%warned), self%mon%prev, self%mon%prev_time]
  end function monitor_state

  pure subroutine set_monitor_state(self, a)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: a(14)
    self%mon%started = a(1) > 0.5_wp
    self%mon%e0 = a(2)
    self%mon%w0 = a(3)
    self%mon%d0 = a(4)
    self%mon%input = a(5)
    self%mon%ratio = a(6)
    self%mon%ke_max = a(7)
    self%mon%balance = a(8)
    self%mon%warned = a(9) > 0.5_wp
    self%mon%prev = a(10:13)
    self%mon%prev_time = a(14)
  end subroutine set_monitor_state

  !> Name the growing field (the monitored field whose maximum grew most since
  !> the previous record), the point that holds its largest value (id, set,
  !> position, cell) and the time; warn, or (stop) set exit_code to 4 (collective;
  !> the caller writes a last frame and ends the run: monitor_stopped).
  subroutine report_growth(self, fm, ratio, stop)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: fm(4), ratio
    logical, intent(in) :: stop
    character(len=*), parameter :: fnames(4) = [character(len=20) :: 'velocity', 'velocity', &
      'effective stress', 'pore pressure']
    real(wp) :: growth(4), val, best(2), info(8)
    integer :: m, p, ip
    character(len=640) :: line
    character(len=40) :: cells
    do m = 1, 4
      growth(m) = 0.0_wp
      if (fm(m) > 0.0_wp) growth(m) = fm(m)/max(self%mon%prev(m), fm(m)*1.0e-30_wp)
    end do
    m = maxloc(growth, 1)
    ! The largest value of field m on this rank, then the rank that holds it.
    best = [-1.0_wp, real(self%dec%rank, wp)]
    info = 0.0_wp
    ! Fields 1 and 3 are the solid's, 2 and 4 the fluid's.
    ip = merge(1, 2, m == 1 .or. m == 3)
    if (ip <= self%nph) then
      associate (ps => self%phase(ip)%pts)
        do p = 1, ps%n
          select case (m)
          case (1, 2)
            val = norm2(ps%v(:, p))
          case (3)
            val = maxval(abs(ps%stress(:, p)))
          case default
            val = abs(ps%pressure(p))
          end select
          if (val > best(1)) then
            best(1) = val
            info = point_info(self, ps, p)
          end if
        end do
      end associate
    end if
    call MPI_Allreduce(MPI_IN_PLACE, best, 1, MPI_2DOUBLE_PRECISION, MPI_MAXLOC, self%dec%comm)
    call MPI_Bcast(info, 8, MPI_DOUBLE_PRECISION, nint(best(2)), self%dec%comm)
    write (cells, '(3(1x,i0))') nint(info(5:4 + self%nd))
    write (line, '(a,es11.4,a,i0,a,es11.3e3,a,a,a,a,a,es11.3e3,a,es11.3e3,a,es11.4,a,i0,a,3es12.4,a)') &
      'monitor: at t = ', self%time, ' s (step ', self%step, ') kinetic + stored energy is ', ratio, &
      ' times the work done + initial energy; growing field: ', trim(fnames(m)), ' of the ', &
      trim(merge('solid', 'fluid', m == 1 .or. m == 3)), ' points, largest ', best(1), ' (', &
      min(growth(m), huge(1.0_wp)), ' times its value at t = ', self%mon%prev_time, ') at point id ', &
      nint(info(1), i8), ', x =', info(2:4), ', cell'
    line = trim(line)//trim(cells)//' (from 0 at the grid origin)'
    call self%log%error(trim(line))
    if (.not. stop) then
      call self%log%error('monitor: warning; the run stops when the ratio exceeds growth_limit = '// &
                          trim(rtoa_short(self%cfg%growth_limit)))
      return
    end if
    ! The last frame, the output closed and the final message: monitor_stopped, by the run.
    self%exit_code = exit_monitor
    self%mon%growth_stop = .true.
  end subroutine report_growth

  !> The end of a run the monitor stopped for growth: the output closed after the
  !> last frame (written by the caller), and how to go on.
  subroutine monitor_stopped(self)
    class(state_t), intent(inout) :: self
    if (self%write_output) call self%out%close()
    call self%log%error('monitor: the run is unstable and was stopped; last frame written at t = '// &
                        trim(rtoa_short(self%time))//' s (raise growth_limit, or 0 to switch the monitor off)')
  end subroutine monitor_stopped

  !> id, position (3) and cell indices (3, from 0) of point p of ps, as reals.
  function point_info(self, ps, p) result(info)
    class(state_t), intent(in) :: self
    type(particle_set_t), intent(in) :: ps
    integer, intent(in) :: p
    real(wp) :: info(8)
    integer :: d
    info = 0.0_wp
    info(1) = real(ps%id(p), wp)
    info(2:1 + self%nd) = ps%x(:, p)
    ! (the cell of a finite position only: a non-finite one has none)
    do d = 1, self%nd
      if (.not. ieee_is_finite(ps%x(d, p))) cycle
      if (abs(ps%x(d, p) - self%grid%origin(d)) < 1.0e9_wp*self%grid%h(d)) &
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
  !> present, pore pressure, porosity) finite, volumes positive. det F needs no test of
  !> its own: every model that carries F sets V = V0 det F from it (V0 > 0), so a
  !> positive finite V is a positive finite det F.
  !> Otherwise the first bad point is named with its field and the run stops with
  !> code 4 before a frame of the bad state is written (collective: exit_code set).
  subroutine check_state(self)
    class(state_t), intent(inout) :: self
    character(len=48) :: field
    real(wp) :: bad(2), info(8), value
    character(len=640) :: line
    integer :: iset
    character(len=*), parameter :: fields(6) = [character(len=24) :: 'position', 'velocity', &
      'stress', 'volume', 'pore pressure', 'porosity']
    ! (the step found every point valid before its migration, which changes no value)
    if (self%checked_valid) then
      self%checked_valid = .false.
      return
    end if
    bad = [0.0_wp, real(self%dec%rank, wp)]
    info = 0.0_wp
    value = 0.0_wp
    iset = 0
    ! The search for the first bad point runs only in a set that fails the count.
    if (.not. set_valid(self%phase(1)%pts)) call scan_set(self%phase(1)%pts, 1)
    if (self%two_phase .and. bad(1) == 0.0_wp) then
      if (.not. set_valid(self%phase(2)%pts)) call scan_set(self%phase(2)%pts, 2)
    end if
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
    self%exit_code = exit_monitor
  contains
    subroutine scan_set(ps, is)
      type(particle_set_t), intent(in) :: ps
      integer, intent(in) :: is
      integer :: p, code
      real(wp) :: v
      do p = 1, ps%n
        code = 0
        if (.not. all(ieee_is_finite(ps%x(:, p)))) then
          code = 1; v = sum(ps%x(:, p))
        else if (.not. all(ieee_is_finite(ps%v(:, p)))) then
          code = 2; v = sum(ps%v(:, p))
        else if (.not. all(ieee_is_finite(ps%stress(:, p)))) then
          code = 3; v = sum(ps%stress(:, p))
        else if (.not. ieee_is_finite(ps%vol(p))) then
          code = 4; v = ps%vol(p)
        else if (ps%vol(p) <= 0.0_wp) then
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

  !> Collective: every point of every set on every rank passes the tests of check_state.
  !> The step asks it before the migration, which would lose a point whose position is not
  !> finite (on more than one rank) before check_state could name it.
  logical function state_valid(self) result(ok)
    class(state_t), intent(in) :: self
    ok = set_valid(self%phase(1)%pts)
    if (self%two_phase .and. ok) ok = set_valid(self%phase(2)%pts)
    call MPI_Allreduce(MPI_IN_PLACE, ok, 1, MPI_LOGICAL, MPI_LAND, self%dec%comm)
  end function state_valid

  !> Whether every point of ps passes the tests of check_state's scan_set: the bad
  !> values counted field by field in loops without a branch, which the compiler
  !> vectorises (scan_set, with a branch per point, then names the first bad point).
  logical function set_valid(ps) result(ok)
    type(particle_set_t), intent(in) :: ps
    integer :: p, n, nb
    n = ps%n
    nb = count_nonfinite(size(ps%x, 1)*n, ps%x) + count_nonfinite(size(ps%v, 1)*n, ps%v) + &
         count_nonfinite(size(ps%stress, 1)*n, ps%stress)
    ! (positive and finite: the non-finite counted, then the others compared with 0, a
    ! non-finite one replaced by 1 first: a comparison with NaN traps in the debug build)
    nb = nb + count_nonfinite(n, ps%vol)
    do p = 1, n
      nb = nb + merge(0, 1, merge(ps%vol(p), 1.0_wp, ieee_is_finite(ps%vol(p))) > 0.0_wp)
    end do
    if (ps%has_pressure) nb = nb + count_nonfinite(n, ps%pressure)
    if (ps%has_porosity) nb = nb + count_nonfinite(n, ps%porosity)
    ok = nb == 0
  end function set_valid

  !> How many of a(1:m) are not finite.
  pure integer function count_nonfinite(m, a) result(nb)
    integer, intent(in) :: m
    real(wp), intent(in) :: a(*)
    integer :: k
    nb = 0
    do k = 1, m
      nb = nb + merge(0, 1, ieee_is_finite(a(k)))
    end do
  end function count_nonfinite

end module dpmpm_energy
