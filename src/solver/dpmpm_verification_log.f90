!> The verification log: the errors of a run against its benchmark (one-phase
!> benchmarks at each diagnostics record, two-phase references at each frame),
!> written to /verification at the end with the counts of the MLS solves.
module dpmpm_verification_log
  use dpmpm_kinds, only: wp, i8
  use dpmpm_timer, only: t_total
  use dpmpm_strings, only: i8toa
  use dpmpm_benchmarks, only: benchmark_errors, benchmark_error_names, benchmark_nerr, nbench_err
  use dpmpm_two_phase_verify, only: two_phase_errors, two_phase_profiles, error_name_len
  use dpmpm_state, only: state_t
  use dpmpm_contact, only: record_body, write_body
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER8, MPI_DOUBLE_PRECISION, MPI_SUM
  implicit none
  private
  public :: two_phase_benchmark, record_two_phase_errors, record_benchmark_errors, write_verification, &
            report_mls, record_drive

contains

  !> Does the run compare with a two-phase reference (column or Terzaghi)?
  logical function two_phase_benchmark(self)
    class(state_t), intent(in) :: self
    two_phase_benchmark = self%two_phase .and. (self%cfg%benchmark == 'biot_column' .or. &
                                                self%cfg%benchmark == 'terzaghi')
  end function two_phase_benchmark

  !> Errors against the two-phase reference at the current frame, kept for the
  !> output and logged (collective).
  subroutine record_two_phase_errors(self)
    class(state_t), intent(inout) :: self
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:)
    character(len=512) :: line
    integer :: k
    call two_phase_errors(self%cfg, self%mats, self%phase(1)%pts, self%phase(2)%pts, self%time, self%dec%comm, &
                          names, values)
    if (.not. allocated(self%ferr)) then
      self%fnames = names
      allocate (self%ferr(1 + size(values), 8))
      self%nferr = 0
    end if
    call append_record(self%ferr, self%nferr, [self%time, values])
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
    class(state_t), intent(inout) :: self
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

  !> /verification of a one-phase benchmark at the end of the run: the errors over the
  !> diagnostics records, their largest, final and mean values, the steps and the
  !> wall time of the step loop; then that of a two-phase benchmark.
  subroutine write_verification(self)
    class(state_t), intent(inout) :: self
    integer :: k
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
    if (self%write_output .and. self%has_rigid .and. self%ndrive > 0) then
      call self%out%write_verification('drive_time', self%drive_hist(1, 1:self%ndrive))
      call self%out%write_verification('drive_force_x', self%drive_hist(2, 1:self%ndrive))
      if (self%nd > 1) call self%out%write_verification('drive_force_y', self%drive_hist(3, 1:self%ndrive))
      if (self%nd > 2) call self%out%write_verification('drive_force_z', self%drive_hist(4, 1:self%ndrive))
    end if
    ! (a body with a frictional contact: its records, dpmpm_contact)
    if (self%write_output .and. self%has_rigid) call write_body(self)
  end subroutine write_verification

  !> The mean force of the rigid bodies' drive since the last record (collective): the
  !> impulse summed over the ranks over the time since then, kept with the record's time
  !> for /verification (drive_time, drive_force_x|y|z) and logged at the end of the run.
  subroutine record_drive(self)
    class(state_t), intent(inout) :: self
    real(wp) :: f(3)
    ! No interval yet: the record at a restart's start would read 0 (at t = 0 it is 0).
    if (self%time <= self%drive_t0 .and. self%time > 0.0_wp) return
    f = self%drive_impulse
    call MPI_Allreduce(MPI_IN_PLACE, f, 3, MPI_DOUBLE_PRECISION, MPI_SUM, self%dec%comm)
    if (self%time > self%drive_t0) then
      f = f/(self%time - self%drive_t0)
    else
      f = 0.0_wp
    end if
    call append_record(self%drive_hist, self%ndrive, [self%time, f])
    call record_body(self)
    self%drive_impulse = 0.0_wp
    self%drive_t0 = self%time
  end subroutine record_drive

  !> Log how often each MLS path was taken (summed over ranks) and store the
  !> counts as attributes of /verification when the run writes one.
  subroutine report_mls(self)
    class(state_t), intent(inout) :: self
    integer(i8) :: c(6), nthin, nwide(1)
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
    nwide = self%mls_stats%nwidened
    call MPI_Allreduce(MPI_IN_PLACE, nwide, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
    if (self%plan%gauss .and. nwide(1) > 0) then
      write (line, '(a,i0,a)') '  Gauss points of occupied cells that widened their reach (no point '// &
        'within field_radius, some within a quarter or half a cell more): ', nwide(1), ' times'
      call self%log%info(line)
    end if
    ! (without MLS velocities every solve is one of a Gauss point of an occupied cell)
    if (self%plan%gauss .and. .not. self%plan%velocity_mls .and. c(5) > 0 .and. self%cfg%field_widen) then
      call self%log%warning('Gauss points of occupied cells found no point even within field_radius '// &
                            '+ 0.5 cells '//i8toa(c(5))//' times: their cells entered the forces with '// &
                            'no stress or pore pressure, which is right where pore water has drained '// &
                            'away but a hole where the points of a body lie scattered apart '// &
                            '(doc/verification.md, "Empty Gauss points of linear + one Gauss point")')
    else if (self%plan%gauss .and. .not. self%plan%velocity_mls .and. c(5) > 0) then
      call self%log%warning('Gauss points of occupied cells found no point within field_radius '// &
                            i8toa(c(5))//' times: their cells entered the forces with no stress or '// &
                            'pore pressure, which is right where pore water has drained away but a hole '// &
                            'where the points of a body lie scattered apart; there &shape field_widen = '// &
                            '.true., field_radius = 1.0 or the pair of doc/theory.md 3.6 reach across '// &
                            'empty cells (doc/verification.md, "Empty Gauss points of linear + one Gauss point")')
    end if
    if (self%plan%gauss) then
      nthin = self%nthin
      call MPI_Allreduce(MPI_IN_PLACE, nthin, 1, MPI_INTEGER8, MPI_SUM, self%dec%comm)
      write (line, '(a,i0)') '  Gauss quadrature: node-steps without internal force (thin nodes): ', nthin
      call self%log%info(line)
    end if
    if (self%write_output .and. self%cfg%benchmark /= 'none') then
      do k = 1, 6
        call self%out%write_verification_attr(trim(names(k)), real(c(k), wp))
      end do
    end if
  end subroutine report_mls

  !> The errors of a one-phase benchmark at the current diagnostics record, kept for
  !> /verification (collective).
  subroutine record_benchmark_errors(self)
    class(state_t), intent(inout) :: self
    real(wp) :: err(nbench_err)
    err = benchmark_errors(self%cfg, self%mats, self%phase(1)%pts, self%time, self%dec%comm)
    call append_record(self%err_hist, self%nerr, [self%time, err])
  end subroutine record_benchmark_errors

  !> Append the column rec to the first n columns of hist, doubling its capacity when full.
  subroutine append_record(hist, n, rec)
    real(wp), allocatable, intent(inout) :: hist(:, :)
    integer, intent(inout) :: n
    real(wp), intent(in) :: rec(:)
    real(wp), allocatable :: tmp(:, :)
    if (n == size(hist, 2)) then
      allocate (tmp(size(hist, 1), 2*n))
      tmp(:, 1:n) = hist
      call move_alloc(tmp, hist)
    end if
    n = n + 1
    hist(:, n) = rec
  end subroutine append_record

end module dpmpm_verification_log
