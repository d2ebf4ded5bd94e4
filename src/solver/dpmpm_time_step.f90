!> The time step: the stable step of the wave CFL (the undrained mixture wave in
!> two-phase scenes) and the report of which limit (wave or explicit drag, whose
!> node-wise limit is in dpmpm_drag) set it.
module dpmpm_time_step
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use dpmpm_kinds, only: wp
  use dpmpm_strings, only: i8toa
  use dpmpm_materials, only: wave_speed
  use dpmpm_state, only: state_t, exit_bad_input, exit_monitor
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_MAX
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
  !> exit_code set on every rank, dt = 0).
  real(wp) function stable_dt(self) result(dt)
    class(state_t), intent(inout) :: self
    real(wp) :: rate, c, crit, rho, nf
    integer :: p
    character(len=256) :: line
    rate = 0.0_wp
    do p = 1, self%phase(1)%pts%n
      rho = self%phase(1)%pts%mass(p)/self%phase(1)%pts%vol(p)
      c = wave_speed(self%mats(self%phase(1)%pts%mat(p)), rho)
      if (self%two_phase) then
        ! Undrained wave of the mixture, c_u^2 = (E_c + K_f/n) / rho_sat (doc/theory.md 7.1).
        nf = self%phase(1)%pts%porosity(p)
        if (nf > 0.0_wp) c = sqrt((self%mats(self%phase(1)%pts%mat(p))%pwave + self%kf_max/nf)/ &
                                  (rho + nf*self%rhof_min))
      end if
      rate = max(rate, c + norm2(self%phase(1)%pts%v(:, p)))
    end do
    do p = 1, merge(self%phase(2)%pts%n, 0, self%two_phase)
      associate (mat => self%mats(self%phase(2)%pts%mat(p)))
        c = sqrt(mat%bulk_fluid/mat%density)
      end associate
      rate = max(rate, c + norm2(self%phase(2)%pts%v(:, p)))
    end do
    call MPI_Allreduce(MPI_IN_PLACE, rate, 1, MPI_DOUBLE_PRECISION, MPI_MAX, self%dec%comm)
    if (.not. ieee_is_finite(rate)) then
      call self%log%error('non-finite wave speed or velocity at step '//i8toa(self%step)// &
                          '; the run became unstable')
      self%exit_code = exit_monitor
      dt = 0.0_wp
      return
    end if
    crit = minval(self%grid%h(1:self%nd))/rate
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
  end function stable_dt

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
