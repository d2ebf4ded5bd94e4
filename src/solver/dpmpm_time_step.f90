!> The time step: the stable step of the wave CFL (the undrained mixture wave in
!> two-phase scenes) and the report of which limit (wave or explicit drag, whose
!> node-wise limit is in dpmpm_drag) set it.
module dpmpm_time_step
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use dpmpm_kinds, only: wp, i8
  use dpmpm_strings, only: i8toa
  use dpmpm_materials, only: wave_speeds, point_moduli, model_mohr_coulomb, model_drucker_prager
  use dpmpm_materials, only: model_mu_i
  use dpmpm_state, only: state_t, exit_bad_input, exit_monitor
  use dpmpm_particles, only: particle_set_t
  use dpmpm_damping, only: rayleigh_coefficients, damped_step_factor
  use mpi_f08, only: MPI_Allreduce, MPI_Bcast, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_2DOUBLE_PRECISION, &
                     MPI_MAXLOC
  implicit none
  private
  public :: stable_dt, report_governing

contains

  !> Stable step: Courant number times the smallest cell size over the fastest
  !> signal (wave speed plus point speed). In two-phase scenes every porous skeleton
  !> point (saturated or dry soil) carries the undrained wave at its own porosity;
  !> the porosity a fluid point uses is a weighted mean of these, so its K_f / n is
  !> covered. Bodies that are not porous (porosity 0) carry their own wave. A fixed dt above the critical step
  !> (Courant number 1) is refused, and a non-finite speed stops the run (collective:
  !> exit_code set on every rank, dt = 0). Rayleigh damping's stiffness-proportional part
  !> lowers the critical step by damped_step_factor (doc/theory.md 7.3). Each time the step falls another decade
  !> below the run's first one, the point of the fastest signal is named (dt_falls).
  real(wp) function stable_dt(self) result(dt)
    class(state_t), intent(inout) :: self
    real(wp) :: rate, crit, best(2), alpha, beta
    character(len=256) :: line
    rate = 0.0_wp
    call fastest_signal(self, 1, rate)
    if (self%two_phase) call fastest_signal(self, 2, rate)
    best = [rate, real(self%dec%rank, wp)]
    call MPI_Allreduce(MPI_IN_PLACE, best, 1, MPI_2DOUBLE_PRECISION, MPI_MAXLOC, self%dec%comm)
    rate = best(1)
    if (.not. ieee_is_finite(rate)) then
      call self%log%error('non-finite wave speed or velocity at step '//i8toa(self%step)// &
                          '; the run became unstable')
      self%exit_code = exit_monitor
      dt = 0.0_wp
      return
    end if
    crit = minval(self%grid%h(1:self%nd))/rate
    call rayleigh_coefficients(self%cfg, alpha, beta)
    if (beta > 0.0_wp) then
      if (self%dt_first <= 0.0_wp) then
        write (line, '(a,es10.3,a,es10.3,a,f6.3,a)') 'Rayleigh damping: alpha ', alpha, ' 1/s, beta ', beta, &
          ' s; the stable step is ', damped_step_factor(beta, crit), ' of the undamped one (doc/theory.md 7.3)'
        call self%log%info(trim(line))
      end if
      crit = crit*damped_step_factor(beta, crit)
    end if
    if (self%cfg%dt > 0.0_wp) then
      if (self%cfg%dt > crit) then
        write (line, '(a,es11.4,a,es11.4,a,i0,a)') '&run dt = ', self%cfg%dt, &
          ' s is above the stable time step ', crit, ' s (Courant number 1) at step ', self%step, &
          '; use a smaller dt or dt = 0 for the automatic step'
        call self%log%error(line)
        self%exit_code = exit_bad_input
        dt = 0.0_wp
        return
      end if
      dt = self%cfg%dt
    else
      dt = self%cfg%cfl*crit
    end if
    self%dt_wave = dt
    if (self%dt_first <= 0.0_wp) self%dt_first = dt
    if (dt < self%dt_first*10.0_wp**(-self%dt_drops - 1)) call dt_falls(self, dt, rate, nint(best(2)))
  end function stable_dt

  !> rate raised to the fastest signal of the points of set is (1 solid, 2 fluid), point
  !> by point in their order: signal_speed's value, with the wave speeds taken a
  !> chunk of points at a time (one call per chunk instead of one per point).
  subroutine fastest_signal(self, is, rate)
    class(state_t), intent(in) :: self
    integer, intent(in) :: is
    real(wp), intent(inout) :: rate
    integer, parameter :: chunk = 256
    real(wp) :: c(chunk), s(chunk), pw(chunk), nfs(chunk), cu(chunk), kf, rhof, cf(size(self%mats))
    integer :: p0, m, k
    logical :: drained
    if (is == 2) then
      do k = 1, size(self%mats)
        ! (materials of no fluid point may have no fluid bulk modulus)
        cf(k) = 0.0_wp
        if (self%mats(k)%density > 0.0_wp .and. self%mats(k)%bulk_fluid >= 0.0_wp) &
          cf(k) = sqrt(self%mats(k)%bulk_fluid/self%mats(k)%density)
      end do
    end if
    kf = self%kf_max
    rhof = self%rhof_min
    associate (ps => self%phase(is)%pts)
      do p0 = 1, ps%n, chunk
        m = min(chunk, ps%n - p0 + 1)
        if (is == 1) then
          ! (the porous points of two-phase scenes take the undrained speed below instead)
          drained = .not. self%two_phase
          if (.not. drained) drained = .not. all(ps%porosity(p0:p0 + m - 1) > 0.0_wp)
          if (drained .and. self%pressure_dependent) then
            call wave_speeds(self%mats, m, ps%mat(p0:p0 + m - 1), ps%mass(p0:p0 + m - 1), ps%vol(p0:p0 + m - 1), c, &
                             ps%stress(:, p0:p0 + m - 1), ps%state(:, p0:p0 + m - 1))
          else if (drained) then
            call wave_speeds(self%mats, m, ps%mat(p0:p0 + m - 1), ps%mass(p0:p0 + m - 1), ps%vol(p0:p0 + m - 1), c)
          end if
          if (self%two_phase) then
            ! (without a branch, so that the loop vectorises: n = 1 stands in where n = 0)
            if (self%pressure_dependent) then
              call point_moduli(self%mats, m, ps%mat(p0:p0 + m - 1), ps%stress(:, p0:p0 + m - 1), &
                                ps%state(:, p0:p0 + m - 1), pw)
            else
              do k = 1, m
                pw(k) = self%mats(ps%mat(p0 + k - 1))%pwave
              end do
            end if
            nfs(1:m) = merge(ps%porosity(p0:p0 + m - 1), 1.0_wp, ps%porosity(p0:p0 + m - 1) > 0.0_wp)
            cu(1:m) = sqrt((pw(1:m) + kf/nfs(1:m))/(ps%mass(p0:p0 + m - 1)/ps%vol(p0:p0 + m - 1) + &
                                                     nfs(1:m)*rhof))
            where (ps%porosity(p0:p0 + m - 1) > 0.0_wp) c(1:m) = cu(1:m)
          end if
        else
          ! the fluid's wave speed is its material's (one per material, as signal_speed has it)
          do k = 1, m
            c(k) = cf(ps%mat(p0 + k - 1))
          end do
        end if
        ! wave plus point speed, the norm from the squares in a loop the compiler
        ! vectorises; a chunk with a square that overflows (+Inf) or a NaN takes norm2
        ! point by point instead
        select case (size(ps%v, 1))
        case (1)
          s(1:m) = c(1:m) + abs(ps%v(1, p0:p0 + m - 1))
        case (2)
          s(1:m) = c(1:m) + sqrt(ps%v(1, p0:p0 + m - 1)**2 + ps%v(2, p0:p0 + m - 1)**2)
        case default
          s(1:m) = c(1:m) + sqrt(ps%v(1, p0:p0 + m - 1)**2 + ps%v(2, p0:p0 + m - 1)**2 + &
                                 ps%v(3, p0:p0 + m - 1)**2)
        end select
        if (all(s(1:m) <= huge(1.0_wp))) then
          rate = max(rate, maxval(s(1:m)))
        else
          do k = 1, m
            rate = max(rate, c(k) + norm2(ps%v(:, p0 + k - 1)))
          end do
        end if
      end do
    end associate
  end subroutine fastest_signal

  !> The fastest signal at point p of set is (1 solid, 2 fluid): wave speed plus point
  !> speed. In two-phase scenes a porous skeleton point carries the undrained wave of
  !> the mixture, c_u^2 = (E_c + K_f/n) / rho_sat (doc/theory.md 7.1).
  real(wp) function signal_speed(self, is, p) result(r)
    class(state_t), intent(in) :: self
    integer, intent(in) :: is, p
    real(wp) :: c, rho, nf, pw(1)
    if (is == 1) then
      associate (ps => self%phase(1)%pts)
        rho = ps%mass(p)/ps%vol(p)
        if (self%pressure_dependent) then
          call point_moduli(self%mats, 1, ps%mat(p:p), ps%stress(:, p:p), ps%state(:, p:p), pw)
        else
          pw(1) = self%mats(ps%mat(p))%pwave
        end if
        c = sqrt(pw(1)/rho)
        if (self%two_phase) then
          nf = ps%porosity(p)
          if (nf > 0.0_wp) c = sqrt((pw(1) + self%kf_max/nf)/(rho + nf*self%rhof_min))
        end if
      end associate
    else
      associate (mat => self%mats(self%phase(2)%pts%mat(p)))
        c = sqrt(mat%bulk_fluid/mat%density)
      end associate
    end if
    r = c + point_speed(self%phase(is)%pts%v(:, p))
  end function signal_speed

  !> |v| as fastest_signal takes it: the root of the sum of squares, or norm2 where
  !> that is not finite.
  pure real(wp) function point_speed(v) result(r)
    real(wp), intent(in) :: v(:)
    r = sqrt(sum(v**2))
    if (.not. r <= huge(1.0_wp)) r = norm2(v)
  end function point_speed

  !> The wave step dt has fallen another decade below the run's first: log the point
  !> of the fastest signal (rank owner, set is, local index p), its speed, and its
  !> volume against its initial one, and for a plastic soil point dilated more than
  !> twice with no max_dilation, that bound (collective).
  subroutine dt_falls(self, dt, rate, owner)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: dt, rate
    integer, intent(in) :: owner
    real(wp) :: info(9), r, rmax
    character(len=640) :: line
    integer :: is, p, k, js
    do while (dt < self%dt_first*10.0_wp**(-self%dt_drops - 1))
      self%dt_drops = self%dt_drops + 1
    end do
    info = 0.0_wp
    is = 1
    p = 0
    if (self%dec%rank == owner) then
      ! the point of the fastest signal: the largest on the rank that holds the largest
      rmax = -1.0_wp
      do js = 1, merge(2, 1, self%two_phase)
        do k = 1, self%phase(js)%pts%n
          r = signal_speed(self, js, k)
          if (r > rmax) then
            rmax = r
            is = js
            p = k
          end if
        end do
      end do
      if (p > 0) call describe(self%phase(is)%pts)
      info(9) = real(is, wp)
    end if
    call MPI_Bcast(info, 9, MPI_DOUBLE_PRECISION, owner, self%dec%comm)
    is = nint(info(9))
    write (line, '(a,i0,a,es10.3,a,i0,a,es10.3,a,a,a,i0,a,3es11.3,a,es10.3,a,es10.3,a,es10.3,a)') &
      'step ', self%step, ': time step ', dt, ' s, below 10^-', self%dt_drops, ' of the first (', &
      self%dt_first, ' s); the fastest signal is at ', trim(merge('solid', 'fluid', is == 1)), &
      ' point id ', nint(info(1), i8), ' at x =', info(2:4), ': wave speed ', info(5), ' m/s, speed ', &
      info(6), ' m/s, volume ', info(7), ' times its initial one'
    call self%log%warning(trim(line))
    if (nint(info(8)) == 1) call self%log%warning('  a Mohr-Coulomb, Drucker-Prager or mu(I) point keeps '// &
                                               'its stiffness '// &
                                               'however far it dilates; &material max_dilation bounds its volume '// &
                                               '(doc/input.md)')
  contains
    subroutine describe(ps)
      type(particle_set_t), intent(in) :: ps
      real(wp) :: v
      info(1) = real(ps%id(p), wp)
      info(2:1 + self%nd) = ps%x(:, p)
      v = norm2(ps%v(:, p))
      info(6) = v
      info(5) = rate - v
      info(7) = ps%vol(p)/ps%vol0(p)
      ! A dilated plastic point without a bound on its volume: name the bound.
      if (is == 1 .and. info(7) > 2.0_wp) then
        if (any(self%mats(ps%mat(p))%model == [model_mohr_coulomb, model_drucker_prager, model_mu_i]) .and. &
            self%mats(ps%mat(p))%max_dilation == 0.0_wp) &
          info(8) = 1.0_wp
      end if
    end subroutine describe
  end subroutine dt_falls

  !> Log which limit sets the time step when it changes (wave CFL or the drag
  !> limit of explicit drag), with both values.
  subroutine report_governing(self, dt)
    class(state_t), intent(inout) :: self
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

end module dpmpm_time_step
