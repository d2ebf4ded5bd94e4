!> A kernel code or stencil width that a dispatch does not know stops the run with a
!> message naming it, instead of running as the cubic kernel. The argument names the
!> dispatch to call with a bad value; each is a ctest that passes on the message of
!> fatal and fails when the call returns ("went on after").
program test_kernel_refusal
  use dpmpm_kinds, only: wp
  use dpmpm_kernels, only: kernel_width, kernel_ghost_width, kernel_eval_1d, psi_stencils, &
                           kernel_reach, max_stencil
  use dpmpm_transfer, only: p2g
  use dpmpm_stencil, only: stencil_t
  implicit none
  integer, parameter :: bad_kernel = 9
  character(len=32) :: which
  integer :: n, i0, i0s(3, 1), lo(3)
  real(wp) :: w(max_stencil), dw(max_stencil), r, x(2, 1), sw(max_stencil, 3, 1), sdw(max_stencil, 3, 1)
  real(wp) :: mass(0), v(2, 0), vol(0), stress(6, 0), node(5, 0:0, 0:0, 0:0)
  integer :: i0p(3, 0)
  real(wp) :: swp(5, 3, 0), sdwp(5, 3, 0)
  type(stencil_t) :: st
  call get_command_argument(1, which)
  select case (trim(which))
  case ('kernel_width')
    n = kernel_width(bad_kernel)
    print '(a,i0)', 'went on after kernel_width: ', n
  case ('kernel_ghost_width')
    n = kernel_ghost_width(bad_kernel)
    print '(a,i0)', 'went on after kernel_ghost_width: ', n
  case ('kernel_eval_1d')
    call kernel_eval_1d(bad_kernel, 0.3_wp, i0, w, dw)
    print '(a,i0)', 'went on after kernel_eval_1d: ', i0
  case ('psi_stencils')
    x = 0.5_wp
    call psi_stencils(2, bad_kernel, 1, x, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], &
                      i0s, sw, sdw)
    print '(a,i0)', 'went on after psi_stencils: ', i0s(1, 1)
  case ('kernel_reach')
    r = kernel_reach(bad_kernel, 0.0_wp, .false.)
    print '(a,es10.3)', 'went on after kernel_reach: ', r
  case ('stencil_init')
    call st%init(2, bad_kernel)
    print '(a,i0)', 'went on after stencil_init: ', st%nw(1)
  case ('p2g_width')
    ! (no points: the dispatch by width comes before the loop over them)
    lo = 0
    node = 0.0_wp
    call p2g(2, [5, 5, 1], 0, i0p, swp, sdwp, mass, v, vol, stress, .true., lo, node)
    print '(a,es10.3)', 'went on after p2g: ', sum(node)
  case default
    print '(a)', 'went on after an unknown argument '//trim(which)
  end select
end program test_kernel_refusal
