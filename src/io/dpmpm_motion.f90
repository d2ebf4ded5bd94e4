!> Recorded ground motions (&motion): one history per grid axis read from a file, plain
!> text (time, value per line) or the PEER NGA .AT2 format (four header lines, NPTS and DT
!> on the fourth, accelerations in g, several per line), scaled, optionally corrected for
!> the baseline, and completed to acceleration, velocity and displacement at the samples.
!>
!> Integration is by the trapezoid rule from rest at the first sample; differentiation (a
!> velocity or displacement record) by second-order differences on the record's own,
!> possibly uneven, times. The baseline correction 'linear' subtracts from the record's
!> lowest derivative (the acceleration of an acceleration record, the velocity of a velocity
!> record) a straight line in time, c0 + c1 (t - t1), whose two coefficients are solved so
!> that the velocity and the displacement, integrated by the same trapezoid rule, end at zero
!> (to round-off); a displacement record loses the straight line through its first and last
!> values. A file is refused, with its name and the line, when it is empty, a line cannot
!> be read as numbers, a value is not finite, the times do not increase, or an .AT2 file's
!> count of values is not its NPTS.
module dpmpm_motion
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, motion_series_t, face_index, bc_fixed
  use dpmpm_strings, only: itoa, rtoa, lower, quote
  use dpmpm_posix, only: posix_getcwd
  use dpmpm_input_problems, only: input_problems_t, add_value, add_warning, g_motion, check_finite
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Bcast, MPI_INTEGER, MPI_DOUBLE_PRECISION
  implicit none
  private
  public :: read_motion_file, motion_from_samples, trapezoid, derivative, motion_velocity
  public :: load_motions, bcast_motions, standard_gravity, motion_format_of, check_motion
  public :: absolute_beside
  public :: motion_values_ok

  !> m/s^2 per g: the values of an .AT2 file are in g.
  real(wp), parameter :: standard_gravity = 9.80665_wp

contains

  !> The values of &motion (not the files: load_motions reads them).
  subroutine check_motion(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    character(len=1024) :: files(3)
    character(len=*), parameter :: axes = 'xyz'
    integer :: d
    if (.not. any(cfg%motion_format == [character(len=4) :: 'auto', 'text', 'at2'])) &
      call add_value(pb, g_motion, 1, 'format', quote(cfg%motion_format), &
                     'the formats are auto (at2 for a name ending in .AT2, else text), text, at2')
    if (.not. any(cfg%motion_quantity == [character(len=12) :: 'acceleration', 'velocity', &
                                          'displacement'])) &
      call add_value(pb, g_motion, 1, 'quantity', quote(cfg%motion_quantity), &
                     'the quantities are acceleration (m/s^2), velocity (m/s), displacement (m)')
    if (.not. any(cfg%motion_baseline == [character(len=6) :: 'none', 'linear'])) &
      call add_value(pb, g_motion, 1, 'baseline', quote(cfg%motion_baseline), &
                     'the baseline corrections are none, linear')
    call check_finite(pb, g_motion, 1, 'scale', cfg%motion_scale)
    files = [cfg%motion_fx, cfg%motion_fy, cfg%motion_fz]
    call check_base(pb, cfg, any(len_trim(files) > 0))
    do d = 1, 3
      if (len_trim(files(d)) == 0) cycle
      if (d > cfg%ndim) call add_value(pb, g_motion, 1, 'file_'//axes(d:d), quote(trim(files(d))), &
                                       'the grid has no axis '//axes(d:d)//' (&grid ndim = '// &
                                       itoa(cfg%ndim)//')')
      if (motion_format_of(cfg%motion_format, files(d)) == 'at2' .and. &
          cfg%motion_quantity /= 'acceleration') &
        call add_value(pb, g_motion, 1, 'file_'//axes(d:d), quote(trim(files(d))), &
                       'an .AT2 file holds accelerations (in g): set quantity = ''acceleration'''// &
                       ' or format = ''text''')
    end do
  end subroutine check_motion

  !> The rigid base: a fixed face of the grid, linear grid functions (a wider kernel's
  !> mirror images at the face would have to move with it); a base without a motion, or a
  !> motion without a base, does nothing (warnings).
  subroutine check_base(pb, cfg, has_files)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    logical, intent(in) :: has_files
    integer :: f
    if (len_trim(cfg%motion_base) == 0) then
      if (has_files) call add_warning(pb, g_motion, 1, 'base', "''", 'the motion moves nothing '// &
                                      'without a base (the face that follows it, e.g. base = ''y-'')')
      return
    end if
    f = face_index(cfg%motion_base)
    if (f < 1 .or. f > 2*cfg%ndim) then
      call add_value(pb, g_motion, 1, 'base', quote(trim(cfg%motion_base)), &
                     'must be a face of the grid: x-, x+ (y-, y+ in 2D, z-, z+ in 3D)')
      return
    end if
    if (cfg%absorbing(f) /= 0) then
      ! a compliant base: the rock's dashpots and the incoming wave, one phase only so far
      if (any(cfg%regions%phase /= 'solid')) call add_value(pb, g_motion, 1, 'base', &
        quote(trim(cfg%motion_base)), 'a compliant base (an absorbing base face) takes one phase '// &
        'only so far: every &region phase = ''solid'', or a fixed base face')
    else if (cfg%bc(f) /= bc_fixed) then
      call add_value(pb, g_motion, 1, 'base', quote(trim(cfg%motion_base)), &
        'the base must be a fixed face (a rigid base: &boundary face = '''// &
        trim(adjustl(cfg%motion_base))//''', condition = ''fixed'') or an absorbing one (a '// &
        'compliant base: condition = ''absorbing'', material = the rock)')
    end if
    if (cfg%kernel /= 'linear' .or. .not. any(cfg%velocity_kernel == [character(len=6) :: '', &
                                                                       'linear'])) &
      call add_value(pb, g_motion, 1, 'base', quote(trim(cfg%motion_base)), &
                     'a rigid base needs &shape kernel = ''linear'' and velocity_kernel '''' or '// &
                     '''linear'' (the mirror images of wider grid functions do not follow the base yet)')
    if (.not. has_files) call add_warning(pb, g_motion, 1, 'base', quote(trim(cfg%motion_base)), &
                                          'no file_x, file_y or file_z: the base stays fixed')
  end subroutine check_base

  !> The choices of &motion that reading its files needs are valid.
  pure logical function motion_values_ok(cfg) result(ok)
    type(config_t), intent(in) :: cfg
    ok = any(cfg%motion_format == [character(len=4) :: 'auto', 'text', 'at2']) .and. &
         any(cfg%motion_quantity == [character(len=12) :: 'acceleration', 'velocity', &
                                     'displacement']) .and. &
         any(cfg%motion_baseline == [character(len=6) :: 'none', 'linear'])
  end function motion_values_ok

  !> Read every &motion file of cfg (rank 0), a relative name from the folder of the input
  !> file input_file: a file that is refused is a problem of its variable (file_x, file_y,
  !> file_z) in pb.
  subroutine load_motions(cfg, pb, input_file)
    type(config_t), intent(inout) :: cfg
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: input_file
    character(len=:), allocatable :: err
    character(len=1024) :: files(3)
    character(len=*), parameter :: axes = 'xyz'
    integer :: d
    files = [cfg%motion_fx, cfg%motion_fy, cfg%motion_fz]
    do d = 1, 3
      if (len_trim(files(d)) == 0) cycle
      call read_motion_file(beside(input_file, trim(files(d))), motion_format_of(cfg%motion_format, files(d)), &
                            cfg%motion_quantity, cfg%motion_scale(d), cfg%motion_baseline, &
                            cfg%motion(d), err)
      if (len(err) > 0) call add_value(pb, g_motion, 1, 'file_'//axes(d:d), &
                                       quote(trim(files(d))), err)
    end do
  end subroutine load_motions

  !> The absolute path of file, as load_motions finds it beside input_file (relative paths
  !> from the working directory); '' stays ''. The echo of the input names the files so,
  !> that it reads back from any folder.
  function absolute_beside(input_file, file) result(path)
    character(len=*), intent(in) :: input_file, file
    character(len=:), allocatable :: path
    path = beside(input_file, file)
    if (len(path) == 0) return
    if (path(1:1) /= '/') path = posix_getcwd()//'/'//path
  end function absolute_beside

  !> The path of file: as it is when absolute or when input_file has no folder, else in the
  !> folder of input_file.
  pure function beside(input_file, file) result(path)
    character(len=*), intent(in) :: input_file, file
    character(len=:), allocatable :: path
    integer :: k
    path = file
    if (len(file) == 0) return
    if (file(1:1) == '/') return
    k = index(input_file, '/', back=.true.)
    if (k > 0) path = input_file(1:k)//file
  end function beside

  !> Rank 0's motions on every rank of comm.
  subroutine bcast_motions(cfg, comm)
    type(config_t), intent(inout) :: cfg
    type(MPI_Comm), intent(in) :: comm
    integer :: rank, d, n
    call MPI_Comm_rank(comm, rank)
    do d = 1, 3
      n = 0
      if (rank == 0 .and. allocated(cfg%motion(d)%t)) n = size(cfg%motion(d)%t)
      call MPI_Bcast(n, 1, MPI_INTEGER, 0, comm)
      if (n == 0) cycle
      if (rank /= 0) then
        if (allocated(cfg%motion(d)%t)) deallocate (cfg%motion(d)%t, cfg%motion(d)%a, &
                                                    cfg%motion(d)%v, cfg%motion(d)%d)
        allocate (cfg%motion(d)%t(n), cfg%motion(d)%a(n), cfg%motion(d)%v(n), cfg%motion(d)%d(n))
      end if
      call MPI_Bcast(cfg%motion(d)%t, n, MPI_DOUBLE_PRECISION, 0, comm)
      call MPI_Bcast(cfg%motion(d)%a, n, MPI_DOUBLE_PRECISION, 0, comm)
      call MPI_Bcast(cfg%motion(d)%v, n, MPI_DOUBLE_PRECISION, 0, comm)
      call MPI_Bcast(cfg%motion(d)%d, n, MPI_DOUBLE_PRECISION, 0, comm)
    end do
  end subroutine bcast_motions

  !> The format of a file: format itself, or with 'auto' 'at2' for a name ending in .at2
  !> (any case) and 'text' for any other.
  pure function motion_format_of(format, file) result(f)
    character(len=*), intent(in) :: format, file
    character(len=:), allocatable :: f
    integer :: n
    f = trim(format)
    if (f /= 'auto') return
    f = 'text'
    n = len_trim(file)
    if (n >= 4) then
      if (lower(file(n - 3:n)) == '.at2') f = 'at2'
    end if
  end function motion_format_of

  !> Read one motion file (format 'text' or 'at2'; quantity 'acceleration', 'velocity' or
  !> 'displacement'; baseline 'none' or 'linear') into s, the values times scale. err is
  !> empty when the file was taken, else what is wrong with it, naming the file and line.
  subroutine read_motion_file(path, format, quantity, scale, baseline, s, err)
    character(len=*), intent(in) :: path, format, quantity, baseline
    real(wp), intent(in) :: scale
    type(motion_series_t), intent(out) :: s
    character(len=:), allocatable, intent(out) :: err
    character(len=:), allocatable :: text
    real(wp), allocatable :: t(:), x(:)
    call read_whole(path, text, err)
    if (len(err) > 0) return
    if (format == 'at2') then
      call parse_at2(path, text, t, x, err)
      if (len(err) == 0) x = x*standard_gravity
    else
      call parse_columns(path, text, t, x, err)
    end if
    if (len(err) > 0) return
    call motion_from_samples(quantity, t, scale*x, baseline, s)
  end subroutine read_motion_file

  !> The whole file as text; err says why it could not be read.
  subroutine read_whole(path, text, err)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text, err
    integer :: u, ios, n
    character(len=512) :: msg
    logical :: exists
    err = ''
    allocate (character(len=0) :: text)
    inquire (file=path, exist=exists)
    if (.not. exists) then
      err = path//': file not found'
      return
    end if
    open (newunit=u, file=path, status='old', action='read', access='stream', &
          form='unformatted', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      err = path//': cannot open the file: '//trim(msg)
      return
    end if
    inquire (unit=u, size=n)
    if (n > 0) then
      deallocate (text)
      allocate (character(len=n) :: text)
      read (u, iostat=ios, iomsg=msg) text
      if (ios /= 0) err = path//': cannot read the file: '//trim(msg)
    end if
    close (u)
  end subroutine read_whole

  !> Line number k of text (lines end at LF; a CR before it is dropped) in line; more
  !> false past the end. pos is where the next line starts.
  subroutine next_line(text, pos, line, more)
    character(len=*), intent(in) :: text
    integer, intent(inout) :: pos
    character(len=:), allocatable, intent(out) :: line
    logical, intent(out) :: more
    integer :: e
    more = pos <= len(text)
    if (.not. more) then
      line = ''
      return
    end if
    e = index(text(pos:), new_line('a'))
    if (e == 0) then
      e = len(text) + 1
    else
      e = pos + e - 1
    end if
    line = text(pos:e - 1)
    pos = e + 1
    if (len(line) > 0) then
      if (line(len(line):len(line)) == achar(13)) line = line(1:len(line) - 1)
    end if
  end subroutine next_line

  !> The numbers of one line (comments from '#' or '!' on are dropped; numbers are separated
  !> by blanks, tabs or commas); err names the word that is not a finite number.
  subroutine line_numbers(line, vals, n, err)
    character(len=*), intent(in) :: line
    real(wp), allocatable, intent(inout) :: vals(:)
    integer, intent(out) :: n
    character(len=:), allocatable, intent(out) :: err
    character(len=:), allocatable :: s
    real(wp), allocatable :: tmp(:)
    integer :: i, j, c, ios
    real(wp) :: x
    err = ''
    n = 0
    s = line
    c = scan(s, '#!')
    if (c > 0) s = s(1:c - 1)
    do i = 1, len(s)
      if (s(i:i) == achar(9) .or. s(i:i) == ',') s(i:i) = ' '
    end do
    i = 1
    do
      do while (i <= len(s))
        if (s(i:i) /= ' ') exit
        i = i + 1
      end do
      if (i > len(s)) exit
      j = i
      do while (j < len(s))
        if (s(j + 1:j + 1) == ' ') exit
        j = j + 1
      end do
      ios = 1
      if (too_large(s(i:j))) then
        err = quote(s(i:j))//' is not a finite number'
        return
      end if
      if (verify(s(i:j), '0123456789+-.eEdD') == 0) read (s(i:j), *, iostat=ios) x
      if (ios == 0) then
        if (.not. ieee_is_finite(x)) then
          err = quote(s(i:j))//' is not a finite number'
          return
        end if
      else
        err = quote(s(i:j))//' is not a number'
        if (lower(s(i:j)) == 'nan' .or. index(lower(s(i:j)), 'inf') > 0) &
          err = quote(s(i:j))//' is not a finite number'
        return
      end if
      n = n + 1
      if (n > size(vals)) then
        allocate (tmp(2*size(vals) + 8))
        tmp(1:size(vals)) = vals
        call move_alloc(tmp, vals)
      end if
      vals(n) = x
      i = j + 1
    end do
  end subroutine line_numbers

  !> A number written with a decimal exponent beyond the range of real(wp) (1e999): it
  !> would overflow when read, so it is refused before.
  pure logical function too_large(word)
    character(len=*), intent(in) :: word
    integer :: e, p, k, ios, ex, lead
    too_large = .false.
    e = scan(word, 'eEdD')
    if (e == 0 .or. e == len(word)) return
    if (verify(word(e + 1:), '+-0123456789') /= 0 .or. len(word) - e > 9) return
    read (word(e + 1:), *, iostat=ios) ex
    if (ios /= 0) return
    ! digits of the integer part, leading zeros left out
    p = scan(word(1:e - 1), '.')
    if (p == 0) p = e
    lead = 0
    do k = 1, p - 1
      if (scan(word(k:k), '123456789') > 0 .or. (lead > 0 .and. word(k:k) == '0')) lead = lead + 1
    end do
    too_large = ex + lead > range(1.0_wp)
  end function too_large

  !> A two-column file: time and value on each line that holds numbers; blank lines and
  !> comments ('#' or '!' to the end of the line) are skipped.
  subroutine parse_columns(path, text, t, x, err)
    character(len=*), intent(in) :: path, text
    real(wp), allocatable, intent(out) :: t(:), x(:)
    character(len=:), allocatable, intent(out) :: err
    real(wp), allocatable :: vals(:), tt(:), xx(:)
    integer :: pos, k, n, m, prev_line
    logical :: more
    allocate (vals(8), tt(64), xx(64))
    err = ''
    pos = 1
    k = 0
    m = 0
    prev_line = 0
    do
      call next_numbers(path, text, pos, k, vals, n, more, err)
      if (.not. more) exit
      if (len(err) > 0) return
      if (n == 0) cycle
      if (n /= 2) then
        err = at(path, k)//itoa(n)//' numbers; a line holds two: the time (s) and the value'
        return
      end if
      if (m > 0) then
        if (vals(1) <= tt(m)) then
          err = at(path, k)//'the time '//rtoa(vals(1))//' is not after the time '// &
                rtoa(tt(m))//' of line '//itoa(prev_line)//': times must increase'
          return
        end if
      end if
      m = m + 1
      if (m > size(tt)) then
        tt = [tt, tt]
        xx = [xx, xx]
      end if
      tt(m) = vals(1)
      xx(m) = vals(2)
      prev_line = k
    end do
    if (m == 0) then
      err = path//': no data: a line holds the time (s) and the value'
    else if (m < 2) then
      err = path//': one sample only (line '//itoa(prev_line)//'); a history needs two at least'
    end if
    if (len(err) > 0) return
    t = tt(1:m)
    x = xx(1:m)
  end subroutine parse_columns

  !> A PEER NGA .AT2 file: three lines of text, the fourth with NPTS and DT, written as
  !> 'NPTS=  5590, DT=   .0050 SEC' (NGA-West2) or '5590   .0050   NPTS, DT' (older NGA files),
  !> then NPTS values (in g), several per line; t = 0, DT, 2 DT, ...
  subroutine parse_at2(path, text, t, x, err)
    character(len=*), intent(in) :: path, text
    real(wp), allocatable, intent(out) :: t(:), x(:)
    character(len=:), allocatable, intent(out) :: err
    character(len=:), allocatable :: line, why
    real(wp), allocatable :: vals(:)
    real(wp) :: dt
    integer :: pos, k, n, m, npts, i, last
    logical :: more
    allocate (vals(8))
    err = ''
    pos = 1
    do k = 1, 4
      call next_line(text, pos, line, more)
      if (.not. more) then
        err = path//': the file ends at line '//itoa(k - 1)//', within the four header '// &
              'lines of the .AT2 format'
        return
      end if
    end do
    call header_npts_dt(line, npts, dt, why)
    if (len(why) > 0) then
      err = at(path, 4)//why
      return
    end if
    allocate (x(min(npts, 65536)))
    m = 0
    last = 4
    k = 4
    do
      call next_numbers(path, text, pos, k, vals, n, more, err)
      if (.not. more) exit
      if (len(err) > 0) return
      if (n == 0) cycle
      if (m + n > npts) then
        err = at(path, k)//'value '//itoa(npts + 1)//' beyond the NPTS = '//itoa(npts)// &
              ' of line 4'
        return
      end if
      if (m + n > size(x)) x = [x, x]
      x(m + 1:m + n) = vals(1:n)
      m = m + n
      last = k
    end do
    if (m /= npts) then
      err = at(path, 4)//'NPTS = '//itoa(npts)//' but the file holds '//itoa(m)// &
            ' values (to line '//itoa(last)//')'
      return
    end if
    x = x(1:m)
    t = [(real(i - 1, wp)*dt, i=1, npts)]
  end subroutine parse_at2

  !> The numbers of the next line of text from pos on (line_numbers) in vals(1:n), k counting
  !> the lines; more is .false. past the end; err says what is wrong with the line (with
  !> path and k), empty when nothing is.
  subroutine next_numbers(path, text, pos, k, vals, n, more, err)
    character(len=*), intent(in) :: path, text
    integer, intent(inout) :: pos, k
    real(wp), allocatable, intent(inout) :: vals(:)
    integer, intent(out) :: n
    logical, intent(out) :: more
    character(len=:), allocatable, intent(out) :: err
    character(len=:), allocatable :: line, why
    err = ''
    n = 0
    call next_line(text, pos, line, more)
    if (.not. more) return
    k = k + 1
    call line_numbers(line, vals, n, why)
    if (len(why) > 0) err = at(path, k)//why
  end subroutine next_numbers

  !> NPTS and DT of an .AT2 file's fourth line, in either spelling; why says what is wrong.
  subroutine header_npts_dt(line, npts, dt, why)
    character(len=*), intent(in) :: line
    integer, intent(out) :: npts
    real(wp), intent(out) :: dt
    character(len=:), allocatable, intent(out) :: why
    character(len=:), allocatable :: s
    real(wp), allocatable :: vals(:)
    real(wp) :: x
    integer :: i, ios, n
    character(len=*), parameter :: expected = ': expected ''NPTS= 5590, DT= .0050 SEC'' or '// &
                                   '''5590 .0050 NPTS, DT'''
    why = ''
    npts = 0
    dt = 0.0_wp
    s = lower(line)
    i = index(s, 'npts')
    if (i == 0) then
      why = 'no NPTS on the fourth line'//expected
      return
    end if
    if (index(s(i:), '=') > 0) then
      call value_after(s, 'npts', x, ios)
      if (ios == 0 .and. abs(x) > 1.0e9_wp) ios = 1
      if (ios == 0) npts = nint(x)
      if (ios /= 0 .or. abs(x - npts) > 0.0_wp) then
        why = 'NPTS cannot be read as a whole number'//expected
        return
      end if
      call value_after(s, 'dt', dt, ios)
      if (ios /= 0) then
        why = 'DT cannot be read'//expected
        return
      end if
    else
      allocate (vals(4))
      call line_numbers(s(1:i - 1), vals, n, why)
      if (len(why) > 0 .or. n /= 2) then
        why = 'two numbers, NPTS and DT, must come before ''NPTS, DT'''//expected
        return
      end if
      if (abs(vals(1)) > 1.0e9_wp) then
        why = 'NPTS = '//rtoa(vals(1))//' is too large'
        return
      end if
      npts = nint(vals(1))
      if (abs(vals(1) - npts) > 0.0_wp) then
        why = 'NPTS = '//rtoa(vals(1))//' is not a whole number'
        return
      end if
      dt = vals(2)
    end if
    if (npts < 2) then
      why = 'NPTS = '//itoa(npts)//': a history needs two values at least'
    else if (.not. (dt > 0.0_wp) .or. .not. ieee_is_finite(dt)) then
      why = 'DT = '//rtoa(dt)//': the time step must be > 0'
    end if
  end subroutine header_npts_dt

  !> The number after 'key' and the '=' that follows it in s (lower case), up to a blank or
  !> comma; ios /= 0 when there is none.
  subroutine value_after(s, key, x, ios)
    character(len=*), intent(in) :: s, key
    real(wp), intent(out) :: x
    integer, intent(out) :: ios
    integer :: i, j, e
    x = 0.0_wp
    ios = 1
    i = index(s, key)
    if (i == 0) return
    e = index(s(i:), '=')
    if (e == 0) return
    j = i + e
    do while (j <= len(s))
      if (s(j:j) /= ' ') exit
      j = j + 1
    end do
    if (j > len(s)) return
    e = scan(s(j:), ' ,')
    if (e == 0) then
      e = len(s)
    else
      e = j + e - 2
    end if
    if (verify(s(j:e), '0123456789+-.ed') /= 0) return
    read (s(j:e), *, iostat=ios) x
    if (ios == 0 .and. .not. ieee_is_finite(x)) ios = 1
  end subroutine value_after

  !> "<path>, line <k>: "
  pure function at(path, k) result(s)
    character(len=*), intent(in) :: path
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    s = path//', line '//itoa(k)//': '
  end function at

  !> Acceleration, velocity and displacement at the samples t(:) of a record x of the given
  !> quantity, corrected for the baseline ('none' or 'linear', see the module's comment).
  subroutine motion_from_samples(quantity, t, x, baseline, s)
    character(len=*), intent(in) :: quantity, baseline
    real(wp), intent(in) :: t(:), x(:)
    type(motion_series_t), intent(out) :: s
    real(wp), allocatable :: tau(:), one(:), v1(:), v2(:), d1(:), d2(:)
    real(wp) :: det, c0, c1
    integer :: n
    n = size(t)
    s%t = t
    tau = t - t(1)
    one = tau*0.0_wp + 1.0_wp
    select case (quantity)
    case ('velocity')
      s%v = x
      if (baseline == 'linear') then
        ! v - (c0 + c1 tau) with v(T) = 0 and the trapezoid displacement d(T) = 0.
        d1 = trapezoid(t, one)
        d2 = trapezoid(t, tau)
        s%d = trapezoid(t, s%v)
        det = one(n)*d2(n) - tau(n)*d1(n)
        c0 = (s%v(n)*d2(n) - tau(n)*s%d(n))/det
        c1 = (one(n)*s%d(n) - s%v(n)*d1(n))/det
        s%v = s%v - (c0 + c1*tau)
      end if
      s%d = trapezoid(t, s%v)
      s%a = derivative(t, s%v)
    case ('displacement')
      s%d = x
      if (baseline == 'linear') s%d = s%d - (x(1) + (x(n) - x(1))*tau/tau(n))
      s%v = derivative(t, s%d)
      s%a = derivative(t, s%v)
    case default
      s%a = x
      if (baseline == 'linear') then
        ! a - (c0 + c1 tau) with the trapezoid velocity and displacement zero at the end.
        v1 = trapezoid(t, one)
        v2 = trapezoid(t, tau)
        d1 = trapezoid(t, v1)
        d2 = trapezoid(t, v2)
        s%v = trapezoid(t, s%a)
        s%d = trapezoid(t, s%v)
        det = v1(n)*d2(n) - v2(n)*d1(n)
        c0 = (s%v(n)*d2(n) - v2(n)*s%d(n))/det
        c1 = (v1(n)*s%d(n) - s%v(n)*d1(n))/det
        s%a = s%a - (c0 + c1*tau)
      end if
      s%v = trapezoid(t, s%a)
      s%d = trapezoid(t, s%v)
    end select
  end subroutine motion_from_samples

  !> The running integral of f(t) from t(1) by the trapezoid rule (zero at t(1)).
  pure function trapezoid(t, f) result(g)
    real(wp), intent(in) :: t(:), f(:)
    real(wp) :: g(size(t))
    integer :: i
    g(1) = 0.0_wp
    do i = 2, size(t)
      g(i) = g(i - 1) + 0.5_wp*(t(i) - t(i - 1))*(f(i - 1) + f(i))
    end do
  end function trapezoid

  !> df/dt at the samples t(:) (two at least): the second-order three-point differences of
  !> uneven spacing inside, one-sided three-point at the ends (two-point with two samples);
  !> exact for a quadratic f.
  pure function derivative(t, f) result(g)
    real(wp), intent(in) :: t(:), f(:)
    real(wp) :: g(size(t))
    integer :: i, n
    n = size(t)
    if (n == 2) then
      g = (f(2) - f(1))/(t(2) - t(1))
      return
    end if
    do i = 2, n - 1
      g(i) = d3(t(i - 1), t(i), t(i + 1), f(i - 1), f(i), f(i + 1), t(i))
    end do
    g(1) = d3(t(1), t(2), t(3), f(1), f(2), f(3), t(1))
    g(n) = d3(t(n - 2), t(n - 1), t(n), f(n - 2), f(n - 1), f(n), t(n))
  contains
    !> The slope at x of the parabola through (x0, y0), (x1, y1), (x2, y2).
    pure real(wp) function d3(x0, x1, x2, y0, y1, y2, x)
      real(wp), intent(in) :: x0, x1, x2, y0, y1, y2, x
      d3 = y0*(2.0_wp*x - x1 - x2)/((x0 - x1)*(x0 - x2)) + &
           y1*(2.0_wp*x - x0 - x2)/((x1 - x0)*(x1 - x2)) + &
           y2*(2.0_wp*x - x0 - x1)/((x2 - x0)*(x2 - x1))
    end function d3
  end function derivative

  !> The velocity of s at time t (s of motion time): linear between the samples, the first
  !> sample's before them and the last's after them; 0 where s holds no record.
  pure real(wp) function motion_velocity(s, t) result(v)
    type(motion_series_t), intent(in) :: s
    real(wp), intent(in) :: t
    integer :: lo, hi, mid, n
    v = 0.0_wp
    if (.not. allocated(s%t)) return
    n = size(s%t)
    if (n == 0) return
    if (t <= s%t(1)) then
      v = s%v(1)
      return
    end if
    if (t >= s%t(n)) then
      v = s%v(n)
      return
    end if
    lo = 1
    hi = n
    do while (hi - lo > 1)
      mid = (lo + hi)/2
      if (s%t(mid) <= t) then
        lo = mid
      else
        hi = mid
      end if
    end do
    v = s%v(lo) + (s%v(hi) - s%v(lo))*(t - s%t(lo))/(s%t(hi) - s%t(lo))
  end function motion_velocity

end module dpmpm_motion
