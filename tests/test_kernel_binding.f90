!> The binding of shape functions: a grid kernel is looked up once in grid_kernel_table
!> (dpmpm_kernels) and its transfers of fixed width in the table of procedures of its
!> width (dpmpm_transfer). An unknown code or width comes back as an error code from the
!> lookups (the binding that stops the run on it is test_kernel_refusal); every grid kernel
!> has a row whose width, ghost layer and reach are those of its B-spline, and a 2D and 3D
!> table of transfers of its width.
program test_kernel_binding
  use dpmpm_kinds, only: wp
  use dpmpm_kernels, only: grid_kernel_t, grid_kernel_table, grid_kernel_lookup, bspline_1d, &
                           kernel_eval_1d, kernel_names, ngrid_kernels, max_stencil, kernel_linear, &
                           kernel_quadratic, kernel_cubic, kernel_wendland_c2, kernel_wendland_c4
  use dpmpm_stencil, only: stencil_t
  use dpmpm_transfer, only: fixed_width_status
  use dpmpm_assert, only: begin_test, check, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  call start_tests()
  call test_unknown_kernel_code_is_not_bound()
  call test_grid_kernels_bound_to_their_bspline()
  call test_bspline_support_is_the_bound_reach()
  call test_unknown_width_has_no_transfers()
  call test_every_grid_kernel_has_transfers()
  call test_stencils_take_the_bound_width()
  call end_tests()

contains

  !> Codes that are no grid kernel (0, past the list, the Wendland weights of MLS) are
  !> not found: status 1 and an unbound row.
  subroutine test_unknown_kernel_code_is_not_bound()
    integer, parameter :: codes(5) = [0, -1, 6, kernel_wendland_c2, kernel_wendland_c4]
    type(grid_kernel_t) :: gk
    integer :: j, stat
    call begin_test('unknown_kernel_code_is_not_bound')
    do j = 1, size(codes)
      call grid_kernel_lookup(codes(j), gk, stat)
      call check_equal_int(stat, 1, 'lookup status of code')
      call check_equal_int(gk%width, 0, 'width of an unbound row')
    end do
  end subroutine test_unknown_kernel_code_is_not_bound

  !> The B-spline of degree k (linear 1, quadratic 2, cubic 3) spans k + 1 nodes, reaches
  !> (k + 1)/2 cells from its centre, and needs ceiling((k + 1)/2) ghost nodes.
  subroutine test_grid_kernels_bound_to_their_bspline()
    integer, parameter :: codes(3) = [kernel_linear, kernel_quadratic, kernel_cubic], degree(3) = [1, 2, 3]
    type(grid_kernel_t) :: gk
    integer :: j, stat
    call begin_test('grid_kernels_bound_to_their_bspline')
    call check_equal_int(size(grid_kernel_table), ngrid_kernels, 'rows of the table')
    do j = 1, size(codes)
      call grid_kernel_lookup(codes(j), gk, stat)
      call check_equal_int(stat, 0, trim(kernel_names(codes(j)))//' found')
      call check_equal_int(gk%kernel, codes(j), trim(kernel_names(codes(j)))//' code')
      call check_equal_int(gk%width, degree(j) + 1, trim(kernel_names(codes(j)))//' width')
      call check(gk%reach == 0.5_wp*real(degree(j) + 1, wp), trim(kernel_names(codes(j)))//' reach')
      call check_equal_int(gk%ghost, (degree(j) + 2)/2, trim(kernel_names(codes(j)))//' ghost')
      call check(gk%width <= max_stencil, trim(kernel_names(codes(j)))//' width within max_stencil')
    end do
  end subroutine test_grid_kernels_bound_to_their_bspline

  !> Each row's reach is where its B-spline ends (non-zero just inside, zero beyond), and
  !> kernel_eval_1d fills exactly the row's width of weights.
  subroutine test_bspline_support_is_the_bound_reach()
    integer :: j, i0, k
    real(wp) :: w, dw, ws(max_stencil), dws(max_stencil), s
    call begin_test('bspline_support_is_the_bound_reach')
    do j = 1, size(grid_kernel_table)
      associate (gk => grid_kernel_table(j))
        call bspline_1d(gk%kernel, gk%reach - 1.0e-3_wp, w, dw)
        call check(w > 0.0_wp, trim(kernel_names(gk%kernel))//' positive inside the reach')
        call bspline_1d(gk%kernel, gk%reach + 1.0e-3_wp, w, dw)
        call check(w == 0.0_wp, trim(kernel_names(gk%kernel))//' zero beyond the reach')
        do k = 0, 20
          ! (off the nodes, where every weight of the stencil is positive)
          s = 5.0_wp + (real(k, wp) + 0.37_wp)/21.0_wp
          call kernel_eval_1d(gk%kernel, s, i0, ws, dws)
          call check(all(ws(1:gk%width) > 0.0_wp), trim(kernel_names(gk%kernel))//' width weights positive')
          call check(all(ws(gk%width + 1:) == 0.0_wp), trim(kernel_names(gk%kernel))//' none past the width')
        end do
      end associate
    end do
  end subroutine test_bspline_support_is_the_bound_reach

  !> Widths without a module of fixed width (1, 5, 0, past max_stencil) and dimensions
  !> other than 2 and 3 are not found by the transfers' lookup.
  subroutine test_unknown_width_has_no_transfers()
    call begin_test('unknown_width_has_no_transfers')
    call check_equal_int(fixed_width_status(2, 5), 1, '2D width 5')
    call check_equal_int(fixed_width_status(3, 5), 1, '3D width 5')
    call check_equal_int(fixed_width_status(2, 1), 1, '2D width 1')
    call check_equal_int(fixed_width_status(2, 0), 1, '2D width 0')
    call check_equal_int(fixed_width_status(3, max_stencil + 1), 1, '3D width past max_stencil')
    call check_equal_int(fixed_width_status(1, 2), 2, '1D')
    call check_equal_int(fixed_width_status(4, 2), 2, '4D')
  end subroutine test_unknown_width_has_no_transfers

  !> A grid kernel in the table whose width has no module of fixed width would be refused
  !> at its first transfer: every row has its 2D and 3D transfers.
  subroutine test_every_grid_kernel_has_transfers()
    integer :: j
    call begin_test('every_grid_kernel_has_transfers')
    do j = 1, size(grid_kernel_table)
      associate (gk => grid_kernel_table(j))
        call check_equal_int(fixed_width_status(2, gk%width), 0, trim(kernel_names(gk%kernel))//' 2D')
        call check_equal_int(fixed_width_status(3, gk%width), 0, trim(kernel_names(gk%kernel))//' 3D')
      end associate
    end do
  end subroutine test_every_grid_kernel_has_transfers

  !> stencil_init binds the kernel once: the stencils keep its row and size their
  !> per-axis weights to its width on the axes in use.
  subroutine test_stencils_take_the_bound_width()
    type(stencil_t) :: st
    call begin_test('stencils_take_the_bound_width')
    call st%init(2, kernel_quadratic)
    call check_equal_int(st%gk%kernel, kernel_quadratic, 'bound kernel')
    call check_equal_int(st%nw(1), 3, 'width axis 1')
    call check_equal_int(st%nw(2), 3, 'width axis 2')
    call check_equal_int(st%nw(3), 1, 'width axis 3 (unused)')
    call check_equal_int(size(st%sw, 1), 3, 'rows of the weights')
    call st%init(3, kernel_cubic)
    call check_equal_int(st%gk%ghost, 2, 'ghost of the cubic')
    call check(all(st%nw == 4), 'cubic widths in 3D')
    call st%free()
  end subroutine test_stencils_take_the_bound_width

end program test_kernel_binding
