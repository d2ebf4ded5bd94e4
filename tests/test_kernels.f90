!> Kernel tests: partition of unity and zero gradient sum, in 1D, 2D and 3D
!> (tensor products), at many positions across a cell; the stencils of many points at
!> once (psi_stencils) are those of each point alone, their first nodes the intrinsic
!> floor's.
program test_kernels
  use dpmpm_kinds, only: wp
  use dpmpm_kernels, only: bspline_1d, kernel_eval_1d, kernel_width, max_stencil, kernel_linear, &
                           kernel_quadratic, kernel_cubic, kernel_names, ngrid_kernels, &
                           kernel_weight, kernel_radial, kernel_reach, kernel_wendland_c2, &
                           kernel_wendland_c4, psi_stencils
  use dpmpm_assert, only: begin_test, check_close, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  call start_tests()
  call test_partition_of_unity_1d()
  call test_stencil_matches_piecewise_bspline()
  call test_stencils_of_many_points_match_one_point()
  call test_tensor_partition_of_unity_3d()
  call test_gradient_matches_finite_difference()
  call test_linear_field_reproduced()
  call test_weight_gradient_matches_finite_difference()
  call test_radial_profiles_vanish_at_support()
  call test_box_weight_is_a_product_of_profiles()
  call end_tests()

contains

  subroutine test_partition_of_unity_1d()
    integer :: k, j, i0
    real(wp) :: s, w(max_stencil), dw(max_stencil)
    call begin_test('partition_of_unity_1d')
    do k = 1, ngrid_kernels
      do j = 0, 200
        s = 3.0_wp + real(j, wp)/200.0_wp*0.999999_wp
        call kernel_eval_1d(k, s, i0, w, dw)
        call check_close(sum(w), 1.0_wp, 0.0_wp, 1.0e-14_wp, trim(kernel_names(k))//' sum of weights')
        call check_close(sum(dw), 0.0_wp, 0.0_wp, 1.0e-13_wp, trim(kernel_names(k))//' sum of gradients')
        call check(all(w(1:kernel_width(k)) >= 0.0_wp), trim(kernel_names(k))//' weights non-negative')
      end do
    end do
  end subroutine test_partition_of_unity_1d

  !> The stencil weights (written out per node) are the piecewise B-spline of each
  !> node at its offset, also at cell faces and kernel joints.
  subroutine test_stencil_matches_piecewise_bspline()
    integer :: k, j, i0, a
    real(wp) :: s, w(max_stencil), dw(max_stencil), wr, dwr
    call begin_test('stencil_matches_piecewise_bspline')
    do k = 1, ngrid_kernels
      do j = 0, 400
        ! Quarter points hit the faces and joints of every kernel exactly. Measured largest
        ! difference 2.8e-17 (cubic weight); the tolerance is 2 ulp of 1.
        s = -2.0_wp + real(j, wp)/40.0_wp
        call kernel_eval_1d(k, s, i0, w, dw)
        do a = 1, kernel_width(k)
          call bspline_1d(k, s - real(i0 + a - 1, wp), wr, dwr)
          call check_close(w(a), wr, 0.0_wp, 4.0e-16_wp, trim(kernel_names(k))//' weight')
          call check_close(dw(a), dwr, 0.0_wp, 4.0e-16_wp, trim(kernel_names(k))//' derivative')
        end do
        call check(all(w(kernel_width(k) + 1:) == 0.0_wp), trim(kernel_names(k))//' unused slots zero')
      end do
    end do
  end subroutine test_stencil_matches_piecewise_bspline

  !> psi_stencils over a set of points (in cell units from -2.5 to 6, on cell faces and
  !> kernel joints, and a point below the origin) against kernel_eval_1d of each point
  !> and axis: the same first node, which is the intrinsic floor (floor(s) linear,
  !> floor(s - 1/2) quadratic, floor(s) - 1 cubic), and the same weights and derivatives
  !> over h, bit for bit, in 1D, 2D and 3D.
  subroutine test_stencils_of_many_points_match_one_point()
    integer, parameter :: n = 341
    integer :: k, nd, p, d, i0(3, n), j0, first, nw
    real(wp) :: x(3, n), w(max_stencil), dw(max_stencil)
    real(wp), allocatable :: sw(:, :, :), sdw(:, :, :)
    real(wp) :: origin(3), h(3), s
    call begin_test('stencils_of_many_points_match_one_point')
    origin = [0.1_wp, -0.2_wp, 0.3_wp]
    h = [0.5_wp, 0.25_wp, 2.0_wp]
    do p = 1, n
      do d = 1, 3
        ! (axis d offset by d/7 of a cell, so that the axes differ)
        x(d, p) = origin(d) + h(d)*(-2.5_wp + real(p - 1, wp)/40.0_wp + real(d - 1, wp)/7.0_wp)
      end do
    end do
    do k = 1, ngrid_kernels
      nw = kernel_width(k)
      if (allocated(sw)) deallocate (sw, sdw)
      allocate (sw(nw, 3, n), sdw(nw, 3, n))
      do nd = 1, 3
        i0 = 0; sw = 0.0_wp; sdw = 0.0_wp
        call psi_stencils(nd, k, n, x(1:nd, :), origin, h, i0, sw, sdw)
        do p = 1, n
          do d = 1, nd
            s = (x(d, p) - origin(d))/h(d)
            call kernel_eval_1d(k, s, j0, w, dw)
            select case (k)
            case (kernel_linear)
              first = floor(s)
            case (kernel_quadratic)
              first = floor(s - 0.5_wp)
            case default
              first = floor(s) - 1
            end select
            call check(i0(d, p) == j0 .and. j0 == first, trim(kernel_names(k))//' first node')
            call check(all(sw(:, d, p) == w(1:nw)), trim(kernel_names(k))//' weights')
            call check(all(sdw(:, d, p) == dw(1:nw)/h(d)), &
                       trim(kernel_names(k))//' derivatives')
          end do
        end do
      end do
    end do
  end subroutine test_stencils_of_many_points_match_one_point

  subroutine test_tensor_partition_of_unity_3d()
    integer :: k, j, a, b, c, i0(3)
    real(wp) :: s(3), w(max_stencil, 3), dw(max_stencil, 3), tot, g(3)
    call begin_test('tensor_partition_of_unity_3d')
    do k = 1, ngrid_kernels
      do j = 1, 50
        s = [1.0_wp + 0.0137_wp*j, 2.0_wp + 0.0191_wp*j, 5.0_wp + 0.0173_wp*j]
        do a = 1, 3
          call kernel_eval_1d(k, s(a), i0(a), w(:, a), dw(:, a))
        end do
        tot = 0.0_wp; g = 0.0_wp
        do c = 1, kernel_width(k)
          do b = 1, kernel_width(k)
            do a = 1, kernel_width(k)
              tot = tot + w(a, 1)*w(b, 2)*w(c, 3)
              g = g + [dw(a, 1)*w(b, 2)*w(c, 3), w(a, 1)*dw(b, 2)*w(c, 3), w(a, 1)*w(b, 2)*dw(c, 3)]
            end do
          end do
        end do
        call check_close(tot, 1.0_wp, 0.0_wp, 1.0e-14_wp, trim(kernel_names(k))//' 3D sum')
        call check_close(maxval(abs(g)), 0.0_wp, 0.0_wp, 1.0e-13_wp, trim(kernel_names(k))//' 3D gradient sum')
      end do
    end do
  end subroutine test_tensor_partition_of_unity_3d

  subroutine test_gradient_matches_finite_difference()
    integer :: k, j, i0, i0p, i0m, n
    real(wp) :: s, w(max_stencil), dw(max_stencil), wp_(max_stencil), wm(max_stencil), tmp(max_stencil)
    real(wp), parameter :: eps = 1.0e-6_wp
    call begin_test('gradient_matches_finite_difference')
    do k = 1, ngrid_kernels
      n = kernel_width(k)
      do j = 1, 97
        s = 4.0_wp + real(j, wp)/98.0_wp
        call kernel_eval_1d(k, s, i0, w, dw)
        call kernel_eval_1d(k, s + eps, i0p, wp_, tmp)
        call kernel_eval_1d(k, s - eps, i0m, wm, tmp)
        if (i0p /= i0 .or. i0m /= i0) cycle     ! stencil shifts exactly at a breakpoint
        call check(maxval(abs((wp_(1:n) - wm(1:n))/(2*eps) - dw(1:n))) < 1.0e-8_wp, &
                   trim(kernel_names(k))//' derivative vs central difference')
      end do
    end do
  end subroutine test_gradient_matches_finite_difference

  subroutine test_linear_field_reproduced()
    ! Both kernels reproduce linear fields: sum_i N_i(s) x_i = s, sum_i dN_i(s) x_i = 1.
    integer :: k, j, i0, i, n
    real(wp) :: s, w(max_stencil), dw(max_stencil), f, df
    call begin_test('linear_field_reproduced')
    do k = kernel_linear, kernel_cubic
      n = kernel_width(k)
      do j = 0, 100
        s = 7.0_wp + real(j, wp)/101.0_wp
        call kernel_eval_1d(k, s, i0, w, dw)
        f = 0.0_wp; df = 0.0_wp
        do i = 1, n
          f = f + w(i)*real(i0 + i - 1, wp)
          df = df + dw(i)*real(i0 + i - 1, wp)
        end do
        call check_close(f, s, 1.0e-14_wp, 0.0_wp, trim(kernel_names(k))//' reproduces x')
        call check_close(df, 1.0_wp, 1.0e-13_wp, 0.0_wp, trim(kernel_names(k))//' reproduces dx/dx')
      end do
    end do
  end subroutine test_linear_field_reproduced

  subroutine test_weight_gradient_matches_finite_difference()
    ! kernel_weight's gradient against central differences, 1D-3D: radial (every other
    ! offset), a box of half-width 1.9 and, for the B-splines, the tensor product of natural
    ! support (radius 0).
    integer :: k, nd, j, m
    logical :: radial
    real(wp) :: d(3), e(3), w, dw(3), wp_, wm, tmp(3), fd, radius
    real(wp), parameter :: eps = 1.0e-6_wp
    call begin_test('weight_gradient_matches_finite_difference')
    do k = 1, size(kernel_names)
      do nd = 1, 3
        do j = 1, 40
          radial = mod(j, 2) == 0
          radius = 1.9_wp
          if (mod(j, 4) == 1 .and. k <= ngrid_kernels) radius = 0.0_wp
          d = [0.61_wp*sin(1.3_wp*j), 0.57_wp*cos(0.7_wp*j), 0.43_wp*sin(2.1_wp*j + 0.3_wp)]
          call kernel_weight(k, radius, radial, nd, d(1:nd), w, dw(1:nd))
          call check(w >= 0.0_wp, trim(kernel_names(k))//' weight non-negative')
          do m = 1, nd
            e = d
            e(m) = d(m) + eps
            call kernel_weight(k, radius, radial, nd, e(1:nd), wp_, tmp(1:nd))
            e(m) = d(m) - eps
            call kernel_weight(k, radius, radial, nd, e(1:nd), wm, tmp(1:nd))
            fd = (wp_ - wm)/(2*eps)
            call check(abs(fd - dw(m)) < 1.0e-7_wp, trim(kernel_names(k))//' weight gradient')
          end do
        end do
      end do
    end do
  end subroutine test_weight_gradient_matches_finite_difference

  subroutine test_radial_profiles_vanish_at_support()
    ! Every radial profile is positive inside r < 1, zero (value and slope) at r = 1,
    ! and kernel_reach bounds the support.
    integer :: k
    real(wp) :: w, dwdr
    call begin_test('radial_profiles_vanish_at_support')
    do k = 1, size(kernel_names)
      call kernel_radial(k, 0.999_wp, w, dwdr)
      call check(w > 0.0_wp, trim(kernel_names(k))//' positive inside the support')
      call kernel_radial(k, 1.0_wp, w, dwdr)
      call check(w == 0.0_wp .and. dwdr == 0.0_wp, trim(kernel_names(k))//' zero at r = 1')
      call check_close(kernel_reach(k, 2.5_wp, .true.), 2.5_wp, 0.0_wp, 0.0_wp, 'radial reach')
    end do
    call kernel_radial(kernel_wendland_c2, 0.0_wp, w, dwdr)
    call check_close(w, 1.0_wp, 1.0e-15_wp, 0.0_wp, 'Wendland C2 at 0')
    call kernel_radial(kernel_wendland_c4, 0.0_wp, w, dwdr)
    call check_close(w, 1.0_wp, 1.0e-15_wp, 0.0_wp, 'Wendland C4 at 0')
  end subroutine test_radial_profiles_vanish_at_support

  subroutine test_box_weight_is_a_product_of_profiles()
    ! A box weight of half-width R is the product over the axes of the profile at |d_k| / R:
    ! zero once one offset reaches R, non-zero in the corners the ball of radius R misses, and,
    ! with the half-width of a B-spline's natural support, that tensor-product B-spline.
    integer :: k, j
    real(wp) :: d(3), w, dw(3), wb, dwb(3), p1, p2, p3, dpr
    real(wp), parameter :: natural(3) = [1.0_wp, 1.5_wp, 2.0_wp]
    call begin_test('box_weight_is_a_product_of_profiles')
    do k = 1, size(kernel_names)
      d = [0.3_wp, -0.45_wp, 0.2_wp]
      call kernel_weight(k, 0.7_wp, .false., 3, d, w, dw)
      call kernel_radial(k, 0.3_wp/0.7_wp, p1, dpr)
      call kernel_radial(k, 0.45_wp/0.7_wp, p2, dpr)
      call kernel_radial(k, 0.2_wp/0.7_wp, p3, dpr)
      call check_close(w, p1*p2*p3, 1.0e-15_wp, 0.0_wp, trim(kernel_names(k))//' box weight')
      call check_close(kernel_reach(k, 0.7_wp, .false.), 0.7_wp, 0.0_wp, 0.0_wp, 'box reach')
      ! one offset at the half-width: outside; the corner (0.6, 0.6) inside the box, outside
      ! the ball of the same radius
      call kernel_weight(k, 0.7_wp, .false., 2, [0.7_wp, 0.1_wp], w, dw(1:2))
      call check(w == 0.0_wp, trim(kernel_names(k))//' box ends at its half-width')
      call kernel_weight(k, 0.7_wp, .false., 2, [0.6_wp, 0.6_wp], w, dw(1:2))
      call kernel_weight(k, 0.7_wp, .true., 2, [0.6_wp, 0.6_wp], wb, dwb(1:2))
      call check(w > 0.0_wp .and. wb == 0.0_wp, trim(kernel_names(k))//' box reaches the corner, ball not')
      if (k > 3) cycle
      do j = 1, 20
        d = [0.9_wp*sin(1.7_wp*j), 1.1_wp*cos(0.9_wp*j), 0.8_wp*sin(2.3_wp*j + 0.4_wp)]*natural(k)/1.2_wp
        call kernel_weight(k, 0.0_wp, .false., 3, d, w, dw)
        call kernel_weight(k, natural(k), .false., 3, d, wb, dwb)
        call check_close(wb, w, 1.0e-14_wp, 1.0e-15_wp, trim(kernel_names(k))//' natural box = B-spline')
        call check(all(abs(dwb - dw) <= 1.0e-13_wp), trim(kernel_names(k))//' natural box gradient')
      end do
    end do
  end subroutine test_box_weight_is_a_product_of_profiles

end program test_kernels
