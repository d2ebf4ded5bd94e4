!> The output directory is made without a shell: a name with shell syntax in it becomes a
!> directory of that literal name and runs nothing; missing parents are made in turn; an
!> existing directory is accepted.
program test_make_dir
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use dpmpm_h5, only: make_dir
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  character(len=*), parameter :: top = 'out/test_make_dir'
  interface
    function c_rmdir(path) bind(C, name='rmdir') result(r)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: r
    end function c_rmdir
  end interface
  call start_tests()
  call test_shell_syntax_is_a_literal_name()
  call test_parents_are_made_in_turn()
  call end_tests()

contains

  logical function is_dir(path)
    character(len=*), intent(in) :: path
    inquire (file=path//'/.', exist=is_dir)
  end function is_dir

  logical function is_file(path)
    character(len=*), intent(in) :: path
    inquire (file=path, exist=is_file)
  end function is_file

  !> Remove a file left by an earlier run (none when absent).
  subroutine remove_file(path)
    character(len=*), intent(in) :: path
    integer :: u, ios
    if (.not. is_file(path)) return
    open (newunit=u, file=path, status='old', iostat=ios)
    if (ios == 0) close (u, status='delete')
  end subroutine remove_file

  !> Remove empty directories, deepest first, so that each run starts without them.
  subroutine remove_dirs(paths)
    character(len=*), intent(in) :: paths(:)
    integer :: k, r
    do k = 1, size(paths)
      r = c_rmdir(trim(paths(k))//c_null_char)
    end do
  end subroutine remove_dirs

  !> Command substitution, a quote-and-semicolon break-out and backquotes in the name: each
  !> name is made as it is written and no file appears that a shell would have made.
  subroutine test_shell_syntax_is_a_literal_name()
    character(len=*), parameter :: names(3) = [character(len=80) :: &
      top//'/x$(touch '//top//'/INJECTED)y', &
      top//'/a";touch '//top//'/INJECTED;"b', &
      top//'/c`touch '//top//'/INJECTED`d']
    integer :: k
    call begin_test('shell_syntax_is_a_literal_name')
    call remove_file(top//'/INJECTED')
    call remove_dirs([character(len=80) :: names(1), top//'/x$(touch '//top, names(2), &
                      top//'/a";touch '//top, names(3), top//'/c`touch '//top])
    do k = 1, size(names)
      call check(.not. is_dir(trim(names(k))), 'no directory before: '//trim(names(k)))
      call make_dir(trim(names(k)))
      call check(is_dir(trim(names(k))), 'made with its literal name: '//trim(names(k)))
    end do
    call check(.not. is_file(top//'/INJECTED'), 'no command ran')
  end subroutine test_shell_syntax_is_a_literal_name

  !> Three missing levels under an existing one, written with a doubled and a trailing
  !> slash; then the same again (it exists).
  subroutine test_parents_are_made_in_turn()
    character(len=*), parameter :: deep = top//'/p//q/r/'
    call begin_test('parents_are_made_in_turn')
    call remove_dirs([character(len=80) :: top//'/p/q/r', top//'/p/q', top//'/p'])
    call check(.not. is_dir(top//'/p'), 'no parent before')
    call make_dir(deep)
    call check(is_dir(top//'/p/q/r'), 'every level made')
    call make_dir(deep)
    call check(is_dir(top//'/p/q/r'), 'an existing directory is accepted')
  end subroutine test_parents_are_made_in_turn

end program test_make_dir
