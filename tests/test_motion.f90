!> Recorded ground motions (dpmpm_motion): two-column text and PEER .AT2 files read with
!> their comments, scale and units; the trapezoid integration and the differences exact on
!> the polynomials they are exact for (and the trapezoid's known error on the next one);
!> the linear baseline correction ending at rest; the velocity between samples; and every
!> refusal of a malformed file naming the file and the line.
program test_motion
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: motion_series_t
  use dpmpm_motion, only: read_motion_file, motion_from_samples, trapezoid, derivative, &
                          motion_velocity, standard_gravity, motion_format_of
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int, finish_tests
  implicit none
  character(len=*), parameter :: lf = new_line('a')

  call test_columns_with_comments_blank_lines_and_crlf()
  call test_at2_with_the_nga_west2_header()
  call test_at2_with_the_older_npts_dt_header()
  call test_format_auto_takes_at2_by_the_name()
  call test_constant_acceleration_integrates_exactly()
  call test_linear_acceleration_has_the_trapezoid_error()
  call test_velocity_record_differentiates_a_quadratic_exactly()
  call test_displacement_record_gives_velocity_and_acceleration()
  call test_linear_baseline_ends_at_rest()
  call test_linear_baseline_removes_a_linear_acceleration()
  call test_velocity_between_and_beyond_the_samples()
  call test_refuses_a_missing_file()
  call test_refuses_an_empty_file()
  call test_refuses_a_file_of_comments_only()
  call test_refuses_one_sample()
  call test_refuses_times_that_do_not_increase()
  call test_refuses_a_value_that_is_not_finite()
  call test_refuses_a_word_that_is_not_a_number()
  call test_refuses_a_line_of_three_numbers()
  call test_refuses_at2_with_fewer_values_than_npts()
  call test_refuses_at2_with_more_values_than_npts()
  call test_refuses_at2_without_npts()
  call test_refuses_at2_shorter_than_its_header()
  call test_refuses_at2_with_a_bad_dt()
  if (finish_tests() /= 0) stop 1, quiet = .true.

contains

  !> Write text to the file path.
  subroutine write_file(path, text)
    character(len=*), intent(in) :: path, text
    integer :: u
    open (newunit=u, file=path, status='replace', action='write', access='stream', &
          form='unformatted')
    write (u) text
    close (u)
  end subroutine write_file

  !> Read path as it would be read for the run; err the refusal ('' when taken).
  subroutine read_as(path, format, quantity, scale, baseline, s, err)
    character(len=*), intent(in) :: path, format, quantity, baseline
    real(wp), intent(in) :: scale
    type(motion_series_t), intent(out) :: s
    character(len=:), allocatable, intent(out) :: err
    call read_motion_file(path, format, quantity, scale, baseline, s, err)
  end subroutine read_as

  !> A refusal whose message holds expected.
  subroutine check_refused(path, format, text, expected)
    character(len=*), intent(in) :: path, format, text, expected
    type(motion_series_t) :: s
    character(len=:), allocatable :: err
    call write_file(path, text)
    call read_as(path, format, 'acceleration', 1.0_wp, 'none', s, err)
    call check(len(err) > 0, 'the file is refused')
    call check(index(err, expected) > 0, 'the message "'//err//'" holds "'//expected//'"')
    call check(index(err, path) == 1, 'the message names the file first')
  end subroutine check_refused

  subroutine test_columns_with_comments_blank_lines_and_crlf()
    type(motion_series_t) :: s
    character(len=:), allocatable :: err
    call begin_test('columns_with_comments_blank_lines_and_crlf')
    call write_file('test_motion_columns.txt', '# time (s), acceleration (m/s^2)'//lf// &
                    '0.0  0.5'//achar(13)//lf//lf//'0.01'//achar(9)//'-1.5e-1 ! tab'//lf// &
                    '  0.03, 2.0D0   # comma'//lf)
    call read_as('test_motion_columns.txt', 'text', 'acceleration', 2.0_wp, 'none', s, err)
    call check(len(err) == 0, 'taken: '//err)
    if (len(err) > 0) return
    call check_equal_int(size(s%t), 3, 'samples')
    call check_close(s%t(3), 0.03_wp, 0.0_wp, 0.0_wp, 'last time')
    call check_close(s%a(1), 1.0_wp, 0.0_wp, 0.0_wp, 'first value times the scale')
    call check_close(s%a(2), -0.3_wp, 1.0e-15_wp, 0.0_wp, 'second value times the scale')
    call check_close(s%a(3), 4.0_wp, 0.0_wp, 0.0_wp, 'third value times the scale')
  end subroutine test_columns_with_comments_blank_lines_and_crlf

  subroutine test_at2_with_the_nga_west2_header()
    type(motion_series_t) :: s
    character(len=:), allocatable :: err
    call begin_test('at2_with_the_nga_west2_header')
    call write_file('test_motion_west2.AT2', 'PEER NGA STRONG MOTION DATABASE RECORD'//lf// &
                    'Some Event, 1/1/2000, SOME STATION, 90'//lf// &
                    'ACCELERATION TIME SERIES IN UNITS OF G'//lf// &
                    'NPTS=    7, DT=   .0200 SEC'//lf// &
                    '  .1000000E-01  -.2000000E-01   .3000000E-01  -.4000000E-01   .5000000E-01'//lf// &
                    '  -.6000000E-01  .7000000E-01'//lf)
    call read_as('test_motion_west2.AT2', 'at2', 'acceleration', 0.5_wp, 'none', s, err)
    call check(len(err) == 0, 'taken: '//err)
    if (len(err) > 0) return
    call check_equal_int(size(s%t), 7, 'NPTS samples')
    call check_close(s%t(1), 0.0_wp, 0.0_wp, 0.0_wp, 'first time')
    call check_close(s%t(7), 0.12_wp, 1.0e-15_wp, 0.0_wp, 'last time = 6 DT')
    call check_close(s%a(1), 0.5_wp*0.01_wp*standard_gravity, 1.0e-15_wp, 0.0_wp, 'g and the scale')
    call check_close(s%a(7), 0.5_wp*0.07_wp*standard_gravity, 1.0e-15_wp, 0.0_wp, 'last value')
  end subroutine test_at2_with_the_nga_west2_header

  subroutine test_at2_with_the_older_npts_dt_header()
    type(motion_series_t) :: s
    character(len=:), allocatable :: err
    call begin_test('at2_with_the_older_npts_dt_header')
    call write_file('test_motion_old.at2', 'PEER STRONG MOTION DATABASE RECORD'//lf// &
                    'SOME EVENT 01/01/80, STATION, 000 (AGENCY)'//lf// &
                    'ACCELERATION TIME HISTORY IN UNITS OF G'//lf// &
                    '    4    0.00500    NPTS, DT'//lf// &
                    ' 0.1 0.2 0.3'//lf//' 0.4'//lf)
    call read_as('test_motion_old.at2', 'at2', 'acceleration', 1.0_wp, 'none', s, err)
    call check(len(err) == 0, 'taken: '//err)
    if (len(err) > 0) return
    call check_equal_int(size(s%t), 4, 'NPTS samples')
    call check_close(s%t(4), 0.015_wp, 1.0e-15_wp, 0.0_wp, 'last time = 3 DT')
    call check_close(s%a(4), 0.4_wp*standard_gravity, 1.0e-15_wp, 0.0_wp, 'value in g')
  end subroutine test_at2_with_the_older_npts_dt_header

  subroutine test_format_auto_takes_at2_by_the_name()
    call begin_test('format_auto_takes_at2_by_the_name')
    call check(motion_format_of('auto', 'dir/RSN1_X.AT2') == 'at2', '.AT2')
    call check(motion_format_of('auto', 'x.at2') == 'at2', '.at2')
    call check(motion_format_of('auto', 'x.txt') == 'text', '.txt')
    call check(motion_format_of('auto', 'at2') == 'text', 'a name without the dot')
    call check(motion_format_of('text', 'x.AT2') == 'text', 'the format given wins')
  end subroutine test_format_auto_takes_at2_by_the_name

  subroutine test_constant_acceleration_integrates_exactly()
    type(motion_series_t) :: s
    real(wp) :: t(5)
    call begin_test('constant_acceleration_integrates_exactly')
    ! Uneven times: the trapezoid rule is exact for the linear velocity and, on its
    ! running integral, for the quadratic displacement of a constant acceleration
    ! (each step integrates a linear velocity).
    t = [0.0_wp, 0.1_wp, 0.25_wp, 0.3_wp, 0.7_wp]
    call motion_from_samples('acceleration', t, [2.0_wp, 2.0_wp, 2.0_wp, 2.0_wp, 2.0_wp], 'none', s)
    call check(all(abs(s%v - 2.0_wp*t) <= 1.0e-15_wp), 'v = 2 t')
    call check(all(abs(s%d - t**2) <= 1.0e-15_wp), 'd = t^2')
  end subroutine test_constant_acceleration_integrates_exactly

  subroutine test_linear_acceleration_has_the_trapezoid_error()
    type(motion_series_t) :: s
    real(wp) :: t(11), h
    integer :: i
    call begin_test('linear_acceleration_has_the_trapezoid_error')
    ! a = 3 t: v = 3 t^2/2 exactly; the trapezoid sum of that v over steps h exceeds
    ! t^3/2 by (h^3/12) v'' per step: d = t^3/2 + 3 h^2 t/12.
    h = 0.1_wp
    t = [(h*i, i=0, 10)]
    call motion_from_samples('acceleration', t, 3.0_wp*t, 'none', s)
    call check(all(abs(s%v - 1.5_wp*t**2) <= 1.0e-14_wp), 'v = 3 t^2/2')
    call check(all(abs(s%d - (0.5_wp*t**3 + 0.25_wp*h**2*t)) <= 1.0e-14_wp), &
               'd = t^3/2 + h^2 t/4')
  end subroutine test_linear_acceleration_has_the_trapezoid_error

  subroutine test_velocity_record_differentiates_a_quadratic_exactly()
    type(motion_series_t) :: s
    real(wp) :: t(6)
    call begin_test('velocity_record_differentiates_a_quadratic_exactly')
    t = [0.0_wp, 0.05_wp, 0.2_wp, 0.22_wp, 0.5_wp, 0.6_wp]
    call motion_from_samples('velocity', t, 3.0_wp*t**2 - t, 'none', s)
    call check(all(abs(s%a - (6.0_wp*t - 1.0_wp)) <= 1.0e-12_wp), 'a = 6 t - 1 (uneven times)')
    call check(all(abs(s%v - (3.0_wp*t**2 - t)) <= 0.0_wp), 'v as given')
    call check_close(s%d(2), 0.5_wp*0.05_wp*(0.0_wp + 3.0_wp*0.05_wp**2 - 0.05_wp), 1.0e-14_wp, &
                     0.0_wp, 'd by the trapezoid rule')
  end subroutine test_velocity_record_differentiates_a_quadratic_exactly

  subroutine test_displacement_record_gives_velocity_and_acceleration()
    type(motion_series_t) :: s
    real(wp) :: t(8)
    integer :: i
    call begin_test('displacement_record_gives_velocity_and_acceleration')
    t = [(0.1_wp*i, i=0, 7)]
    call motion_from_samples('displacement', t, 2.0_wp*t**2 + t, 'none', s)
    call check(all(abs(s%v - (4.0_wp*t + 1.0_wp)) <= 1.0e-12_wp), 'v = 4 t + 1')
    call check(all(abs(s%a - 4.0_wp) <= 1.0e-10_wp), 'a = 4')
  end subroutine test_displacement_record_gives_velocity_and_acceleration

  subroutine test_linear_baseline_ends_at_rest()
    type(motion_series_t) :: s, raw
    real(wp), allocatable :: t(:), a(:)
    real(wp), parameter :: pi = acos(-1.0_wp)
    integer :: i
    call begin_test('linear_baseline_ends_at_rest')
    ! A sine of 2 Hz over 3.3 s with an offset and a drift: without correction the velocity
    ! and displacement drift; with it both end at zero to round-off.
    t = [(0.005_wp*i, i=0, 660)]
    a = sin(2.0_wp*pi*2.0_wp*t) + 0.05_wp + 0.02_wp*t
    call motion_from_samples('acceleration', t, a, 'none', raw)
    call check(abs(raw%v(size(t))) > 0.1_wp, 'the raw velocity drifts')
    call motion_from_samples('acceleration', t, a, 'linear', s)
    call check(abs(s%v(size(t))) <= 1.0e-13_wp, 'the velocity ends at zero')
    call check(abs(s%d(size(t))) <= 1.0e-13_wp, 'the displacement ends at zero')
    ! on the even times, what was taken away is a straight line: its second differences vanish
    call check(maxval(abs((a(3:) - s%a(3:)) - 2.0_wp*(a(2:size(t) - 1) - s%a(2:size(t) - 1)) + &
                          (a(:size(t) - 2) - s%a(:size(t) - 2)))) <= 1.0e-12_wp, &
               'the correction is c0 + c1 t')
    call motion_from_samples('velocity', t, raw%v, 'linear', s)
    call check(abs(s%v(size(t))) <= 1.0e-13_wp, 'velocity record: the velocity ends at zero')
    call check(abs(s%d(size(t))) <= 1.0e-13_wp, 'velocity record: the displacement ends at zero')
    call motion_from_samples('displacement', t, raw%d, 'linear', s)
    call check(abs(s%d(1)) <= 0.0_wp .and. abs(s%d(size(t))) <= 1.0e-13_wp, &
               'displacement record: starts and ends at zero')
  end subroutine test_linear_baseline_ends_at_rest

  subroutine test_linear_baseline_removes_a_linear_acceleration()
    type(motion_series_t) :: s
    real(wp) :: t(9)
    integer :: i
    call begin_test('linear_baseline_removes_a_linear_acceleration')
    ! A record that is itself c0 + c1 t is the correction: nothing is left.
    t = [(0.125_wp*i, i=0, 8)]
    call motion_from_samples('acceleration', t, 0.3_wp - 0.7_wp*t, 'linear', s)
    call check(maxval(abs(s%a)) <= 1.0e-14_wp, 'a = 0')
    call check(maxval(abs(s%v)) <= 1.0e-14_wp, 'v = 0')
    call check(maxval(abs(s%d)) <= 1.0e-14_wp, 'd = 0')
  end subroutine test_linear_baseline_removes_a_linear_acceleration

  subroutine test_velocity_between_and_beyond_the_samples()
    type(motion_series_t) :: s, none
    call begin_test('velocity_between_and_beyond_the_samples')
    call motion_from_samples('velocity', [1.0_wp, 2.0_wp, 4.0_wp], [0.5_wp, 1.5_wp, -0.5_wp], &
                             'none', s)
    call check_close(motion_velocity(s, 0.0_wp), 0.5_wp, 0.0_wp, 0.0_wp, 'before: the first')
    call check_close(motion_velocity(s, 1.5_wp), 1.0_wp, 1.0e-15_wp, 0.0_wp, 'linear between')
    call check_close(motion_velocity(s, 3.0_wp), 0.5_wp, 1.0e-15_wp, 0.0_wp, 'uneven step')
    call check_close(motion_velocity(s, 9.0_wp), -0.5_wp, 0.0_wp, 0.0_wp, 'after: the last')
    call check_close(motion_velocity(none, 1.0_wp), 0.0_wp, 0.0_wp, 0.0_wp, 'no record: 0')
  end subroutine test_velocity_between_and_beyond_the_samples

  subroutine test_refuses_a_missing_file()
    type(motion_series_t) :: s
    character(len=:), allocatable :: err
    call begin_test('refuses_a_missing_file')
    call read_as('test_motion_no_such_file.txt', 'text', 'acceleration', 1.0_wp, 'none', s, err)
    call check(err == 'test_motion_no_such_file.txt: file not found', err)
  end subroutine test_refuses_a_missing_file

  subroutine test_refuses_an_empty_file()
    call begin_test('refuses_an_empty_file')
    call check_refused('test_motion_empty.txt', 'text', '', 'test_motion_empty.txt: no data')
  end subroutine test_refuses_an_empty_file

  subroutine test_refuses_a_file_of_comments_only()
    call begin_test('refuses_a_file_of_comments_only')
    call check_refused('test_motion_comments.txt', 'text', '# time value'//lf//lf//'! none'//lf, &
                       'no data')
  end subroutine test_refuses_a_file_of_comments_only

  subroutine test_refuses_one_sample()
    call begin_test('refuses_one_sample')
    call check_refused('test_motion_one.txt', 'text', '# one'//lf//'0.0 1.0'//lf, &
                       'one sample only (line 2)')
  end subroutine test_refuses_one_sample

  subroutine test_refuses_times_that_do_not_increase()
    call begin_test('refuses_times_that_do_not_increase')
    call check_refused('test_motion_times.txt', 'text', '0.0 1.0'//lf//'# c'//lf//'0.5 2.0'//lf// &
                       '0.5 3.0'//lf, 'test_motion_times.txt, line 4: the time 0.5 is not '// &
                       'after the time 0.5 of line 3: times must increase')
    call check_refused('test_motion_times.txt', 'text', '0.0 1.0'//lf//'0.5 2.0'//lf// &
                       '0.25 3.0'//lf, 'line 3: the time 0.25 is not after the time 0.5 of line 2')
  end subroutine test_refuses_times_that_do_not_increase

  subroutine test_refuses_a_value_that_is_not_finite()
    call begin_test('refuses_a_value_that_is_not_finite')
    call check_refused('test_motion_nan.txt', 'text', '0.0 1.0'//lf//'0.1 NaN'//lf, &
                       'test_motion_nan.txt, line 2: ''NaN'' is not a finite number')
    call check_refused('test_motion_inf.txt', 'text', '0.0 1.0'//lf//'0.1 -Infinity'//lf, &
                       'line 2: ''-Infinity'' is not a finite number')
    call check_refused('test_motion_huge.txt', 'text', '0.0 1.0'//lf//'0.1 1e999'//lf, &
                       'line 2: ''1e999'' is not')
  end subroutine test_refuses_a_value_that_is_not_finite

  subroutine test_refuses_a_word_that_is_not_a_number()
    call begin_test('refuses_a_word_that_is_not_a_number')
    call check_refused('test_motion_word.txt', 'text', '0.0 1.0'//lf//'0.1 1.0'//lf// &
                       '0.2 abc'//lf, 'test_motion_word.txt, line 3: ''abc'' is not a number')
  end subroutine test_refuses_a_word_that_is_not_a_number

  subroutine test_refuses_a_line_of_three_numbers()
    call begin_test('refuses_a_line_of_three_numbers')
    call check_refused('test_motion_three.txt', 'text', '0.0 1.0'//lf//'0.1 1.0 2.0'//lf, &
                       'line 2: 3 numbers; a line holds two: the time (s) and the value')
  end subroutine test_refuses_a_line_of_three_numbers

  !> An .AT2 file of the NGA-West2 header with npts on its fourth line and the lines after.
  function at2(npts, body) result(text)
    character(len=*), intent(in) :: npts, body
    character(len=:), allocatable :: text
    text = 'PEER NGA STRONG MOTION DATABASE RECORD'//lf//'Event'//lf// &
           'ACCELERATION TIME SERIES IN UNITS OF G'//lf//'NPTS=    '//npts// &
           ', DT=   .0100 SEC'//lf//body
  end function at2

  subroutine test_refuses_at2_with_fewer_values_than_npts()
    call begin_test('refuses_at2_with_fewer_values_than_npts')
    call check_refused('test_motion_few.AT2', 'at2', at2('6', ' .1 .2 .3'//lf//' .4 .5'//lf), &
                       'test_motion_few.AT2, line 4: NPTS = 6 but the file holds 5 values '// &
                       '(to line 6)')
  end subroutine test_refuses_at2_with_fewer_values_than_npts

  subroutine test_refuses_at2_with_more_values_than_npts()
    call begin_test('refuses_at2_with_more_values_than_npts')
    call check_refused('test_motion_many.AT2', 'at2', at2('4', ' .1 .2 .3'//lf//' .4 .5'//lf), &
                       'test_motion_many.AT2, line 6: value 5 beyond the NPTS = 4 of line 4')
  end subroutine test_refuses_at2_with_more_values_than_npts

  subroutine test_refuses_at2_without_npts()
    call begin_test('refuses_at2_without_npts')
    call check_refused('test_motion_nonpts.AT2', 'at2', 'a'//lf//'b'//lf//'c'//lf// &
                       '  .0100 SEC'//lf//' .1 .2'//lf, &
                       'test_motion_nonpts.AT2, line 4: no NPTS on the fourth line: expected')
  end subroutine test_refuses_at2_without_npts

  subroutine test_refuses_at2_shorter_than_its_header()
    call begin_test('refuses_at2_shorter_than_its_header')
    call check_refused('test_motion_short.AT2', 'at2', 'a'//lf//'b'//lf, &
                       'test_motion_short.AT2: the file ends at line 2, within the four header')
  end subroutine test_refuses_at2_shorter_than_its_header

  subroutine test_refuses_at2_with_a_bad_dt()
    call begin_test('refuses_at2_with_a_bad_dt')
    call check_refused('test_motion_dt.AT2', 'at2', 'a'//lf//'b'//lf//'c'//lf// &
                       'NPTS=  2, DT=   -.0100 SEC'//lf//' .1 .2'//lf, &
                       'line 4: DT = -0.01: the time step must be > 0')
    call check_refused('test_motion_dt.AT2', 'at2', 'a'//lf//'b'//lf//'c'//lf// &
                       'NPTS=  2.5, DT=   .0100 SEC'//lf//' .1 .2'//lf, &
                       'line 4: NPTS cannot be read as a whole number')
    call check_refused('test_motion_dt.AT2', 'at2', 'a'//lf//'b'//lf//'c'//lf// &
                       '  1e30  .0100  NPTS, DT'//lf//' .1 .2'//lf, &
                       'line 4: NPTS = 1.0e30 is too large')
  end subroutine test_refuses_at2_with_a_bad_dt

end program test_motion
