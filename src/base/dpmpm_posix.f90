!> POSIX services through the small C file beside this module (dpmpm_posix.c): making
!> one directory without a shell, flushing a file to the disk, writing a whole file with the
!> reason of a failure, errno and whether a path is
!> a directory, and the stop signals of batch schedulers (SIGTERM,
!> SIGUSR1), whose handler only sets a flag that the run loop reads between steps.
module dpmpm_posix
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_ptr, c_null_char, c_f_pointer, &
                                         c_associated, c_size_t
  implicit none
  private
  public :: posix_mkdir, posix_strerror, posix_fsync, catch_stop_signals, stop_signal, signal_name
  public :: peak_resident_kib, posix_errno, posix_clear_errno, posix_is_directory
  public :: posix_write_file, posix_getcwd

  interface
    function c_mkdir(path) bind(C, name='dpmpm_mkdir') result(err)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: err
    end function c_mkdir
    function c_fsync(path) bind(C, name='dpmpm_fsync') result(err)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: err
    end function c_fsync
    function c_strerror(err) bind(C, name='dpmpm_strerror') result(p)
      import :: c_int, c_ptr
      integer(c_int), value :: err
      type(c_ptr) :: p
    end function c_strerror
    function c_write_file(path, text, n) bind(C, name='dpmpm_write_file') result(err)
      import :: c_char, c_int, c_size_t
      character(kind=c_char), intent(in) :: path(*), text(*)
      integer(c_size_t), value :: n
      integer(c_int) :: err
    end function c_write_file
    function c_errno() bind(C, name='dpmpm_errno') result(err)
      import :: c_int
      integer(c_int) :: err
    end function c_errno
    subroutine c_clear_errno() bind(C, name='dpmpm_clear_errno')
    end subroutine c_clear_errno
    function c_is_directory(path) bind(C, name='dpmpm_is_directory') result(r)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: r
    end function c_is_directory
    function c_catch_stop_signals() bind(C, name='dpmpm_catch_stop_signals') result(r)
      import :: c_int
      integer(c_int) :: r
    end function c_catch_stop_signals
    function c_stop_signal() bind(C, name='dpmpm_stop_signal') result(sig)
      import :: c_int
      integer(c_int) :: sig
    end function c_stop_signal
    function c_getcwd(buf, n) bind(C, name='dpmpm_getcwd') result(err)
      import :: c_int, c_char, c_size_t
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_size_t), value :: n
      integer(c_int) :: err
    end function c_getcwd
    function c_signal_name(sig) bind(C, name='dpmpm_signal_name') result(p)
      import :: c_int, c_ptr
      integer(c_int), value :: sig
      type(c_ptr) :: p
    end function c_signal_name
  end interface

contains

  !> Make the one directory path (its parent must exist): 0 when made or already there,
  !> otherwise the errno of the failure (see posix_strerror).
  integer function posix_mkdir(path) result(err)
    character(len=*), intent(in) :: path
    err = int(c_mkdir(path//c_null_char))
  end function posix_mkdir

  !> Flush the file or directory path to the disk: 0, or the errno of the failure.
  integer function posix_fsync(path) result(err)
    character(len=*), intent(in) :: path
    err = int(c_fsync(path//c_null_char))
  end function posix_fsync

  !> The system's text for an errno value.
  function posix_strerror(err) result(text)
    integer, intent(in) :: err
    character(len=:), allocatable :: text
    text = c_string(c_strerror(int(err, c_int)))
  end function posix_strerror

  !> Write text to the file path (created or truncated), all of it: 0, or the errno of the
  !> failure (a full disk: ENOSPC, where Fortran's own output may drop the error).
  integer function posix_write_file(path, text) result(err)
    character(len=*), intent(in) :: path, text
    err = int(c_write_file(path//c_null_char, text, int(len(text), c_size_t)))
  end function posix_write_file

  !> errno now: the reason of the last failed system call of this process (0: none since
  !> posix_clear_errno). Read it right after a call that failed.
  integer function posix_errno() result(err)
    err = int(c_errno())
  end function posix_errno

  !> Set errno to 0, before a call whose failure is to be explained by posix_errno.
  subroutine posix_clear_errno()
    call c_clear_errno()
  end subroutine posix_clear_errno

  !> True when path names a directory.
  logical function posix_is_directory(path) result(is_dir)
    character(len=*), intent(in) :: path
    is_dir = c_is_directory(path//c_null_char) /= 0
  end function posix_is_directory

  !> From now on SIGTERM and SIGUSR1 only set the stop flag; false if they cannot be caught.
  logical function catch_stop_signals() result(ok)
    ok = c_catch_stop_signals() == 0
  end function catch_stop_signals

  !> The stop signal received on this process so far, 0 when none.
  integer function stop_signal()
    stop_signal = int(c_stop_signal())
  end function stop_signal

  !> 'SIGTERM' or 'SIGUSR1' for a signal number from stop_signal.
  function signal_name(sig) result(name)
    integer, intent(in) :: sig
    character(len=:), allocatable :: name
    name = c_string(c_signal_name(int(sig, c_int)))
  end function signal_name

  !> The working directory ('' if the system cannot give it in 4096 characters).
  function posix_getcwd() result(path)
    character(len=:), allocatable :: path
    character(kind=c_char) :: buf(4096)
    integer :: n
    path = ''
    if (c_getcwd(buf, int(size(buf), c_size_t)) /= 0) return
    n = 0
    do while (n < size(buf))
      if (buf(n + 1) == c_null_char) exit
      n = n + 1
    end do
    path = transfer(buf(1:n), repeat(' ', n))
  end function posix_getcwd

  !> A Fortran copy of a NUL-terminated C string.
  function c_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: n
    if (.not. c_associated(p)) then
      s = ''
      return
    end if
    call c_f_pointer(p, chars, [4096])
    n = 0
    do while (n < 4096)
      if (chars(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate (character(len=n) :: s)
    do n = 1, len(s)
      s(n:n) = chars(n)
    end do
  end function c_string

  !> Peak resident memory of this process in KiB (VmHWM of /proc/self/status), or -1
  !> where that file is not there (not Linux).
  integer function peak_resident_kib() result(kib)
    integer :: u, ios
    character(len=256) :: line
    kib = -1
    open (newunit=u, file='/proc/self/status', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read (u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (line(1:6) == 'VmHWM:') then
        read (line(7:), *, iostat=ios) kib
        if (ios /= 0) kib = -1
        exit
      end if
    end do
    close (u)
  end function peak_resident_kib

end module dpmpm_posix
