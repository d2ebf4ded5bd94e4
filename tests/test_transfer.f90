!> Transfer kernels (dpmpm_transfer) on a small 2D and 3D grid with scattered
!> points, for the three B-spline grid functions: p2g conserves mass and momentum,
!> the internal force of a uniform stress sums to zero, g2p and the point gradient
!> reproduce a linear nodal velocity field and its gradient, the MUSL momentum
!> remap of a uniform velocity gives that velocity back at the nodes, and the
!> nodal porosity of a uniform porosity interpolates back to it with no gradient;
!> g2p without the gradient (MUSL) moves the points as g2p with it, and the 2D
!> forms of the kernels (p2g, g2p, gradients, remap, scalar interpolation, fluid
!> forces and drag) equal the general form with a third axis of one node; the
!> one-pass projection of a nodal field through a point set (in momentum_project_p2g)
!> equals its interpolation to the points followed by the momentum map, and the
!> fused passes equal the kernels they join (the fluid points' divergences the traces
!> of the point gradients, the skeleton's p2g with its porosity sums the two kernels
!> in turn, the MUSL remap's g2p with its scatter g2p and the momentum map in turn); the
!> 3D forms of p2g and g2p (compiled per stencil width)
!> equal sums over the nodes written out from the tensor-product weights.
program test_transfer
  use dpmpm_kinds, only: wp
  use dpmpm_kernels, only: kernel_width, kernel_names, ngrid_kernels, max_stencil
  use dpmpm_stencil, only: psi_stencil, tensor_weights, stencil_offsets
  use dpmpm_tensor, only: voigt_to_tensor
  use dpmpm_transfer, only: p2g, g2p, point_gradient, momentum_p2g, fluid_p2g, point_divergences, &
                            momentum_project_p2g, interp_two_values, solid_porosity_p2g, porous_p2g, &
                            g2p_remap, volume_p2g
  use dpmpm_drag, only: gravity_drag
  use dpmpm_assert, only: begin_test, check, check_close
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer, parameter :: npt = 40         !< points of a test set
  integer, parameter :: ncell = 6        !< cells per axis; points stay two cells from the edges
  real(wp), parameter :: h(3) = [0.5_wp, 0.25_wp, 0.4_wp]
  call start_tests()
  call test_p2g_conserves_mass_and_momentum()
  call test_uniform_stress_has_no_net_force()
  call test_g2p_reproduces_linear_velocity()
  call test_point_gradient_of_linear_velocity()
  call test_remap_of_uniform_velocity()
  call test_interp_two_values_partition_of_unity()
  call test_g2p_without_gradient_moves_points_alike()
  call test_two_d_forms_match_general_form()
  call test_projection_is_interpolation_then_momentum_map()
  call test_fused_passes_match_separate_kernels()
  call test_porous_p2g_is_p2g_and_porosity_sums()
  call test_g2p_remap_is_g2p_then_momentum_map()
  call test_three_d_forms_match_direct_sums()
  call test_three_d_remap_and_two_phase_forms_match_direct_sums()
  call test_volume_sums_match_node_by_node_sums()
  call end_tests()

contains

  !> Stencils of n points scattered (reproducibly) in the inner cells of the grid.
  subroutine make_points(nd, kernel, n, x, i0, sw, sdw, nw)
    integer, intent(in) :: nd, kernel, n
    real(wp), intent(out) :: x(:, :)
    integer, intent(out) :: i0(:, :), nw(3)
    real(wp), intent(out) :: sw(:, :, :), sdw(:, :, :)
    integer :: p, d
    real(wp) :: y(3)
    nw = 1
    nw(1:nd) = kernel_width(kernel)
    x = 0.0_wp
    do p = 1, n
      y = 0.0_wp
      do d = 1, nd
        ! A low-discrepancy scatter over cells 2 .. ncell - 2.
        y(d) = 2.0_wp + real(ncell - 4, wp)*modulo(0.5_wp + real(p, wp)*sqrt(real(d + 1, wp)), 1.0_wp)
        x(d, p) = y(d)*h(d)
      end do
      call psi_stencil(nd, kernel, y, h, i0(:, p), sw(:, :, p), sdw(:, :, p))
    end do
  end subroutine make_points

  !> Node arrays over nodes -1 .. ncell + 1 (a ghost layer each side).
  subroutine make_nodes(nd, ncomp, lo, f)
    integer, intent(in) :: nd, ncomp
    integer, intent(out) :: lo(3)
    real(wp), allocatable, intent(out) :: f(:, :, :, :)
    integer :: hi(3)
    lo = 0
    hi = 0
    lo(1:nd) = -1
    hi(1:nd) = ncell + 1
    allocate (f(ncomp, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
    f = 0.0_wp
  end subroutine make_nodes

  !> Position of node (i, j, k).
  pure function node_x(i, j, k) result(x)
    integer, intent(in) :: i, j, k
    real(wp) :: x(3)
    x = [i, j, k]*h
  end function node_x

  subroutine test_p2g_conserves_mass_and_momentum()
    integer :: nd, kernel, p, lo(3), nw(3), i0(3, npt)
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v(3, npt), stress(6, npt)
    real(wp), allocatable :: node(:, :, :, :)
    character(len=32) :: tag
    call begin_test('p2g_conserves_mass_and_momentum')
    do nd = 2, 3
      do kernel = 1, ngrid_kernels
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        do p = 1, npt
          mass(p) = 1.0_wp + 0.1_wp*real(mod(p, 7), wp)
          vol(p) = 0.01_wp
          v(:, p) = [0.3_wp, -1.2_wp, 0.7_wp] + 0.05_wp*real(p, wp)
        end do
        stress = 0.0_wp
        call make_nodes(nd, 1 + 2*nd, lo, node)
        call p2g(nd, nw, npt, i0, sw, sdw, mass, v(1:nd, :), vol, stress, .true., lo, node)
        tag = case_tag(kernel, nd)
        call check_close(sum(node(1, :, :, :)), sum(mass), 1.0e-14_wp, 0.0_wp, trim(tag)//' mass')
        do p = 1, nd
          call check_close(sum(node(1 + p, :, :, :)), sum(mass*v(p, :)), 1.0e-14_wp, 1.0e-14_wp, &
                           trim(tag)//' momentum')
          call check_close(sum(node(1 + nd + p, :, :, :)), 0.0_wp, 0.0_wp, 1.0e-14_wp, &
                           trim(tag)//' no force without stress')
        end do
      end do
    end do
  end subroutine test_p2g_conserves_mass_and_momentum

  !> The internal forces of a uniform stress are internal: they sum to zero over the nodes.
  subroutine test_uniform_stress_has_no_net_force()
    integer :: nd, kernel, p, lo(3), nw(3), i0(3, npt)
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v(3, npt), stress(6, npt)
    real(wp), allocatable :: node(:, :, :, :)
    call begin_test('uniform_stress_has_no_net_force')
    do nd = 2, 3
      do kernel = 1, ngrid_kernels
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        mass = 1.0_wp
        vol = 0.02_wp
        v = 0.0_wp
        do p = 1, npt
          stress(:, p) = [1.0e3_wp, -2.0e3_wp, 5.0e2_wp, 3.0e2_wp, -4.0e2_wp, 7.0e2_wp]
        end do
        call make_nodes(nd, 1 + 2*nd, lo, node)
        call p2g(nd, nw, npt, i0, sw, sdw, mass, v(1:nd, :), vol, stress, .true., lo, node)
        do p = 1, nd
          call check_close(sum(node(1 + nd + p, :, :, :)), 0.0_wp, 0.0_wp, 1.0e-10_wp, &
                           trim(kernel_names(kernel))//' net internal force')
        end do
      end do
    end do
  end subroutine test_uniform_stress_has_no_net_force

  !> Nodal velocities v(x) = b + A x (old and new alike): PIC g2p gives v(x_p) at the
  !> points, moves them by dt v(x_p), and the velocity gradient is A.
  subroutine test_g2p_reproduces_linear_velocity()
    integer :: nd, kernel, p, lo(3), nw(3), i0(3, npt), c
    real(wp) :: x(3, npt), x1(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt)
    real(wp) :: v(3, npt), vgrad(9, npt), a(3, 3), b(3), ve(3)
    real(wp), parameter :: dt = 1.0e-3_wp
    real(wp), allocatable :: nvel(:, :, :, :)
    call begin_test('g2p_reproduces_linear_velocity')
    call linear_field(a, b)
    do nd = 2, 3
      do kernel = 1, ngrid_kernels
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        call make_nodes(nd, 2*nd, lo, nvel)
        call fill_linear(nd, lo, a, b, nvel)
        v = 0.0_wp
        x1 = x
        call g2p(nd, nw, npt, i0, sw, sdw, lo, nvel, 0.0_wp, dt, v(1:nd, :), x1(1:nd, :), vgrad)
        do p = 1, npt
          ve = b + matmul(a, x(:, p))
          do c = 1, nd
            call check_close(v(c, p), ve(c), 1.0e-13_wp, 1.0e-13_wp, trim(kernel_names(kernel))//' velocity')
            call check_close(x1(c, p), x(c, p) + dt*ve(c), 1.0e-14_wp, 1.0e-14_wp, &
                             trim(kernel_names(kernel))//' position')
          end do
          call check_gradient(nd, vgrad(:, p), a, trim(kernel_names(kernel))//' g2p gradient')
        end do
      end do
    end do
  end subroutine test_g2p_reproduces_linear_velocity

  subroutine test_point_gradient_of_linear_velocity()
    integer :: nd, kernel, p, lo(3), nw(3), i0(3, npt)
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), vgrad(9, npt), a(3, 3), b(3)
    real(wp), allocatable :: nvel(:, :, :, :)
    call begin_test('point_gradient_of_linear_velocity')
    call linear_field(a, b)
    do nd = 2, 3
      do kernel = 1, ngrid_kernels
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        call make_nodes(nd, 2*nd, lo, nvel)
        call fill_linear(nd, lo, a, b, nvel)
        call point_gradient(nd, nw, npt, i0, sw, sdw, lo, nvel, vgrad)
        do p = 1, npt
          call check_gradient(nd, vgrad(:, p), a, trim(kernel_names(kernel))//' point gradient')
        end do
      end do
    end do
  end subroutine test_point_gradient_of_linear_velocity

  !> Points of one velocity: the remapped nodal momentum over the nodal mass is that velocity.
  subroutine test_remap_of_uniform_velocity()
    integer :: nd, kernel, p, lo(3), nw(3), i0(3, npt), i, j, k, c
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v(3, npt), stress(6, npt), u(3)
    real(wp), allocatable :: node(:, :, :, :)
    call begin_test('remap_of_uniform_velocity')
    u = [0.4_wp, -0.9_wp, 1.3_wp]
    do nd = 2, 3
      do kernel = 1, ngrid_kernels
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        do p = 1, npt
          mass(p) = 0.5_wp + 0.25_wp*real(mod(p, 5), wp)
          v(:, p) = u
        end do
        vol = 0.01_wp
        stress = 0.0_wp
        call make_nodes(nd, 1 + 2*nd, lo, node)
        call p2g(nd, nw, npt, i0, sw, sdw, mass, v(1:nd, :), vol, stress, .true., lo, node)
        node(2:1 + 2*nd, :, :, :) = 0.0_wp
        call momentum_p2g(nd, nw, npt, i0, sw, mass, v(1:nd, :), lo, node)
        do k = lbound(node, 4), ubound(node, 4)
          do j = lbound(node, 3), ubound(node, 3)
            do i = lbound(node, 2), ubound(node, 2)
              if (node(1, i, j, k) <= 1.0e-12_wp) cycle
              do c = 1, nd
                call check_close(node(1 + c, i, j, k)/node(1, i, j, k), u(c), 1.0e-13_wp, 0.0_wp, &
                                 trim(kernel_names(kernel))//' remapped velocity')
              end do
            end do
          end do
        end do
      end do
    end do
  end subroutine test_remap_of_uniform_velocity

  !> Uniform nodal fields interpolate to themselves (partition of unity), the second
  !> component as the value of the second output.
  subroutine test_interp_two_values_partition_of_unity()
    integer :: nd, kernel, p, lo(3), nw(3), i0(3, npt)
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), val(npt)
    real(wp) :: val2(npt)
    real(wp), allocatable :: f(:, :, :, :)
    call begin_test('interp_two_values_partition_of_unity')
    do nd = 2, 3
      do kernel = 1, ngrid_kernels
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        call make_nodes(nd, 2, lo, f)
        f(1, :, :, :) = 0.35_wp
        f(2, :, :, :) = -2.5_wp
        call interp_two_values(nd, nw, npt, i0, sw, lo, f, 2, val, val2)
        do p = 1, npt
          call check_close(val(p), 0.35_wp, 1.0e-14_wp, 0.0_wp, trim(kernel_names(kernel))//' value')
          call check_close(val2(p), -2.5_wp, 1.0e-14_wp, 0.0_wp, trim(kernel_names(kernel))//' second value')
        end do
      end do
    end do
  end subroutine test_interp_two_values_partition_of_unity

  !> Scattered nodal velocities (old and new differ), different at every node.
  subroutine fill_scattered(lo, nvel)
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: nvel(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k, c
    do k = lbound(nvel, 4), ubound(nvel, 4)
      do j = lbound(nvel, 3), ubound(nvel, 3)
        do i = lbound(nvel, 2), ubound(nvel, 2)
          do c = 1, size(nvel, 1)
            nvel(c, i, j, k) = sin(1.3_wp*i + 0.7_wp*j - 0.4_wp*k + 0.9_wp*c)
          end do
        end do
      end do
    end do
  end subroutine fill_scattered

  !> MUSL: g2p without the velocity gradient gives the same velocities and positions
  !> as with it, and leaves the gradients as they were. The release build sums the
  !> two loops in another order: measured 2.2e-16 relative (2D), equal elsewhere and in
  !> the debug build; the tolerance 2e-15 is 9 times that. Without the gradient array
  !> (the fluid points) g2p moves them as with gradient = .false., bit for bit.
  subroutine test_g2p_without_gradient_moves_points_alike()
    integer :: nd, kernel, p, lo(3), nw(3), i0(3, npt)
    real(wp) :: x(3, npt), x1(3, npt), x2(3, npt), x3(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt)
    real(wp) :: v1(3, npt), v2(3, npt), v3(3, npt), vgrad1(9, npt), vgrad2(9, npt)
    real(wp), parameter :: dt = 1.0e-3_wp, flip = 0.99_wp
    real(wp), allocatable :: nvel(:, :, :, :)
    character(len=32) :: tag
    call begin_test('g2p_without_gradient_moves_points_alike')
    do nd = 1, 3
      do kernel = 1, ngrid_kernels
        tag = case_tag(kernel, nd)
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        call make_nodes(nd, 2*nd, lo, nvel)
        call fill_scattered(lo, nvel)
        do p = 1, npt
          v1(:, p) = [0.3_wp, -0.1_wp, 0.2_wp]*real(mod(p, 3) + 1, wp)
        end do
        v2 = v1
        v3 = v1
        x1 = x
        x2 = x
        x3 = x
        vgrad2 = -7.0_wp
        call g2p(nd, nw, npt, i0, sw, sdw, lo, nvel, flip, dt, v1(1:nd, :), x1(1:nd, :), vgrad1)
        call g2p(nd, nw, npt, i0, sw, sdw, lo, nvel, flip, dt, v2(1:nd, :), x2(1:nd, :), vgrad2, &
                 gradient=.false.)
        call check_close(maxval(abs(v1(1:nd, :) - v2(1:nd, :)))/maxval(abs(v1(1:nd, :))), 0.0_wp, 0.0_wp, 2.0e-15_wp, &
                         trim(tag)//' velocities (relative)')
        call check_close(maxval(abs(x1(1:nd, :) - x2(1:nd, :)))/maxval(abs(x1(1:nd, :))), 0.0_wp, 0.0_wp, 2.0e-15_wp, &
                         trim(tag)//' positions (relative)')
        call check(all(vgrad2 == -7.0_wp), trim(tag)//' gradients untouched')
        call g2p(nd, nw, npt, i0, sw, sdw, lo, nvel, flip, dt, v3(1:nd, :), x3(1:nd, :))
        call check(all(v3 == v2) .and. all(x3 == x2), trim(tag)//' without the gradient array: the same motion')
      end do
    end do
  end subroutine test_g2p_without_gradient_moves_points_alike

  !> The 2D forms (nd = 2) against the general form (nd = 3) of the same points with a
  !> third axis of one node of weight 1: p2g (a plane stress state with sigma_zz),
  !> g2p, the point gradient, the point divergences of two fields and the momentum remap
  !> agree to rounding; so do the fluid's pore forces, drag and its mass and momentum
  !> summed in fluid_p2g's own pass, which also equal the fluid's p2g (no stress).
  subroutine test_two_d_forms_match_general_form()
    integer :: kernel, p, lo2(3), lo3(3), nw2(3), nw3(3), i0(3, npt), c
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v2(3, npt), v3(3, npt), x2(3, npt), x3(3, npt), stress(6, npt), g2(9, npt), g3(9, npt)
    real(wp) :: s2(npt), s3(npt), dv2(npt), dv3(npt), dw2(npt), dw3(npt)
    real(wp), allocatable :: sc2(:, :, :, :), sc3(:, :, :, :)
    real(wp), allocatable :: n2(:, :, :, :), n3(:, :, :, :), vel2(:, :, :, :), vel3(:, :, :, :)
    real(wp), allocatable :: fl2(:, :, :, :), fl3(:, :, :, :), d2(:, :, :, :), d3(:, :, :, :)
    real(wp), allocatable :: m2(:, :, :, :), m3(:, :, :, :)
    real(wp), parameter :: dt = 1.0e-3_wp, flip = 0.95_wp
    real(wp) :: scale
    !> The 2D forms sum by rows of the stencil (factored by axis), the general form node by
    !> node: measured largest relative difference 3.4e-16 (release) and 5.0e-16 (debug);
    !> 4x margin.
    real(wp), parameter :: tol_rel = 2.0e-15_wp
    integer, parameter :: comp3(5) = [1, 2, 3, 5, 6], vcomp3(4) = [1, 2, 4, 5]
    call begin_test('two_d_forms_match_general_form')
    do kernel = 1, ngrid_kernels
      call make_points(2, kernel, npt, x, i0, sw, sdw, nw2)
      nw3 = nw2
      do p = 1, npt
        mass(p) = 1.0_wp + 0.1_wp*real(mod(p, 7), wp)
        vol(p) = 0.01_wp*(1.0_wp + 0.05_wp*real(mod(p, 3), wp))
        v2(:, p) = [0.3_wp, -1.2_wp, 0.0_wp] + 0.05_wp*real(p, wp)*[1.0_wp, 0.5_wp, 0.0_wp]
        stress(:, p) = [1.0e3_wp, -2.0e3_wp, 5.0e2_wp, 0.0_wp, 0.0_wp, 7.0e2_wp]*real(1 + mod(p, 4), wp)
      end do
      v2(3, :) = 0.0_wp
      v3 = v2
      call make_nodes(2, 5, lo2, n2)
      call make_nodes(3, 7, lo3, n3)
      call p2g(2, nw2, npt, i0, sw, sdw, mass, v2(1:2, :), vol, stress, .true., lo2, n2)
      call p2g(3, nw3, npt, i0, sw, sdw, mass, v3, vol, stress, .true., lo3, n3)
      do c = 1, 5
        scale = maxval(abs(n2(c, :, :, :)))
        call check_close(maxval(abs(n2(c, :, :, 0) - n3(comp3(c), :, :, 0)))/scale, 0.0_wp, 0.0_wp, &
                         tol_rel, trim(kernel_names(kernel))//' p2g node field (relative)')
      end do
      call make_nodes(2, 4, lo2, vel2)
      call make_nodes(3, 6, lo3, vel3)
      call fill_scattered(lo2, vel2)
      do c = 1, 4
        vel3(vcomp3(c), :, :, 0) = vel2(c, :, :, 0)
      end do
      x2 = x
      x3 = x
      call g2p(2, nw2, npt, i0, sw, sdw, lo2, vel2, flip, dt, v2(1:2, :), x2(1:2, :), g2)
      call g2p(3, nw3, npt, i0, sw, sdw, lo3, vel3, flip, dt, v3, x3, g3)
      call check_close(maxval(abs(v2(1:2, :) - v3(1:2, :)))/maxval(abs(v3)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' g2p velocity')
      call check_close(maxval(abs(x2(1:2, :) - x3(1:2, :)))/maxval(abs(x3)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' g2p position')
      call check_close(maxval(abs(g2 - g3))/maxval(abs(g3)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' g2p gradient (relative)')
      call point_gradient(2, nw2, npt, i0, sw, sdw, lo2, vel2, g2)
      call point_gradient(3, nw3, npt, i0, sw, sdw, lo3, vel3, g3)
      call check_close(maxval(abs(g2 - g3))/maxval(abs(g3)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' point gradient (relative)')
      ! (the second field of the divergence pass: another nodal velocity)
      sc2 = 1.7_wp*vel2 - 0.3_wp
      sc3 = 1.7_wp*vel3 - 0.3_wp
      call point_divergences(2, nw2, npt, i0, sw, sdw, lo2, vel2, sc2, dv2, dw2)
      call point_divergences(3, nw3, npt, i0, sw, sdw, lo3, vel3, sc3, dv3, dw3)
      call check_close(maxval(abs(dv2 - dv3))/maxval(abs(dv3)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' point divergence (relative)')
      call check_close(maxval(abs(dw2 - dw3))/maxval(abs(dw3)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' point divergence of the second field (relative)')
      n2(2:5, :, :, :) = 0.0_wp
      n3(2:7, :, :, :) = 0.0_wp
      call momentum_p2g(2, nw2, npt, i0, sw, mass, v2(1:2, :), lo2, n2)
      call momentum_p2g(3, nw3, npt, i0, sw, mass, v3, lo3, n3)
      do c = 2, 3
        scale = maxval(abs(n2(c, :, :, :)))
        call check_close(maxval(abs(n2(c, :, :, 0) - n3(c, :, :, 0)))/scale, 0.0_wp, 0.0_wp, tol_rel, &
                         trim(kernel_names(kernel))//' remapped momentum (relative)')
      end do
      ! A nodal scalar at the points, and a second component's value.
      sc2 = vel2(3:4, :, :, :)
      sc3 = vel3(4:5, :, :, :)
      call interp_two_values(2, nw2, npt, i0, sw, lo2, sc2, 2, vol, s2)
      call interp_two_values(3, nw3, npt, i0, sw, lo3, sc3, 2, mass, s3)
      call check_close(maxval(abs(vol - mass))/maxval(abs(mass)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' interpolated scalar (relative)')
      call check_close(maxval(abs(s2 - s3))/maxval(abs(s3)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' interpolated second component (relative)')
      ! Pore-pressure forces and drag coefficients of fluid points.
      do p = 1, npt
        vol(p) = 0.01_wp*(1.0_wp + 0.05_wp*real(mod(p, 3), wp))
        mass(p) = 3.0_wp + 0.1_wp*real(mod(p, 7), wp)
        stress(1, p) = 1.0e4_wp*(1.0_wp + 0.1_wp*real(mod(p, 5), wp))
        stress(2, p) = 0.3_wp + 0.01_wp*real(mod(p, 4), wp)
        stress(3, p) = 1.0e5_wp*real(1 + mod(p, 2), wp)
      end do
      call make_nodes(2, 5, lo2, n2)
      call make_nodes(3, 7, lo3, n3)
      call make_nodes(2, 5, lo2, fl2)
      call make_nodes(3, 7, lo3, fl3)
      call make_nodes(2, 1, lo2, d2)
      call make_nodes(3, 1, lo3, d3)
      v3(3, :) = 0.0_wp
      v3(1:2, :) = v2(1:2, :)
      call fluid_p2g(2, nw2, npt, i0, sw, sdw, mass, v2(1:2, :), vol, stress(2, :), stress(1, :), stress(3, :), &
                     .true., .true., lo2, n2, fl2, d2)
      call fluid_p2g(3, nw3, npt, i0, sw, sdw, mass, v3, vol, stress(2, :), stress(1, :), stress(3, :), &
                     .true., .true., lo3, n3, fl3, d3)
      ! The fluid's mass and momentum of the same pass against p2g's (no stress: the fluid's
      ! p2g), in 2D and 3D.
      call make_nodes(2, 5, lo2, m2)
      call make_nodes(3, 7, lo3, m3)
      call p2g(2, nw2, npt, i0, sw, sdw, mass, v2(1:2, :), vol, stress, .false., lo2, m2)
      call p2g(3, nw3, npt, i0, sw, sdw, mass, v3, vol, stress, .false., lo3, m3)
      do c = 1, 3
        call check_close(maxval(abs(fl2(c, :, :, :) - m2(c, :, :, :)))/maxval(abs(m2(c, :, :, :))), 0.0_wp, &
                         0.0_wp, tol_rel, trim(kernel_names(kernel))//' fluid mass and momentum, 2D (relative)')
        call check_close(maxval(abs(fl3(c, :, :, :) - m3(c, :, :, :)))/maxval(abs(m3(c, :, :, :))), 0.0_wp, &
                         0.0_wp, tol_rel, trim(kernel_names(kernel))//' fluid mass and momentum, 3D (relative)')
      end do
      do c = 1, 2
        call check_close(maxval(abs(n2(3 + c, :, :, 0) - n3(4 + c, :, :, 0)))/maxval(abs(n2(3 + c, :, :, :))), &
                         0.0_wp, 0.0_wp, tol_rel, trim(kernel_names(kernel))//' solid pore force (relative)')
        call check_close(maxval(abs(fl2(3 + c, :, :, 0) - fl3(4 + c, :, :, 0)))/ &
                         maxval(abs(fl2(3 + c, :, :, :))), 0.0_wp, 0.0_wp, tol_rel, &
                         trim(kernel_names(kernel))//' fluid pore force (relative)')
      end do
      call check_close(maxval(abs(d2(1, :, :, 0) - d3(1, :, :, 0)))/maxval(abs(d2)), 0.0_wp, 0.0_wp, tol_rel, &
                       trim(kernel_names(kernel))//' drag coefficient (relative)')
    end do
  end subroutine test_two_d_forms_match_general_form

  !> The projection of the remap correction of two-phase MUSL: the locked velocity
  !> gathered at the points in g2p's pass (gf, gv) against the field interpolated per
  !> component (interp_two_values), and momentum_project_p2g of those point values against
  !> momentum_p2g of the same points moving with them, in 1D, 2D and 3D with every
  !> B-spline. The gather sums node by node, interp_two_values in 3D by rows of the
  !> stencil: measured largest relative difference 4.9e-16 (release and debug builds),
  !> tolerance 2e-15 (4x). The projection of the gathered values against momentum_p2g of
  !> the interpolated ones: measured 1.3e-16 (release) and 2.3e-16 (debug), the same
  !> tolerance. The momenta of the same fused pass against momentum_p2g's: the same bound.
  subroutine test_projection_is_interpolation_then_momentum_map()
    integer :: nd, kernel, p, c, lo(3), nw(3), i0(3, npt)
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vc(npt)
    real(wp) :: v0(npt), vt(3, npt), xt(3, npt), gt(9, npt)
    real(wp), allocatable :: f(:, :, :, :), one(:, :, :, :), two(:, :, :, :), vp(:, :), mom(:, :, :, :)
    real(wp), allocatable :: nv(:, :, :, :), gp(:, :)
    character(len=32) :: tag
    real(wp) :: rel, worst, worstg
    call begin_test('projection_is_interpolation_then_momentum_map')
    worst = 0.0_wp
    worstg = 0.0_wp
    do nd = 1, 3
      do kernel = 1, ngrid_kernels
        tag = case_tag(kernel, nd)
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        do p = 1, npt
          mass(p) = 1.0_wp + 0.1_wp*real(mod(p, 7), wp)
        end do
        call make_nodes(nd, nd, lo, f)
        call fill_scattered(lo, f)
        if (allocated(vp)) deallocate (vp, gp)
        allocate (vp(nd, npt), gp(nd, npt))
        do c = 1, nd
          call interp_two_values(nd, nw, npt, i0, sw, lo, f, c, v0, vc)
          vp(c, :) = vc
        end do
        ! the gather of g2p's pass (nodal velocities of no importance here)
        call make_nodes(nd, 2*nd, lo, nv)
        vt = 0.0_wp
        xt = x
        gp = 0.0_wp
        call g2p(nd, nw, npt, i0, sw, sdw, lo, nv, 1.0_wp, 1.0e-3_wp, vt(1:nd, :), xt(1:nd, :), gt, &
                 gradient=.false., gf=f, gv=gp)
        rel = maxval(abs(gp - vp))/maxval(abs(vp))
        worstg = max(worstg, rel)
        call check_close(rel, 0.0_wp, 0.0_wp, 2.0e-15_wp, trim(tag)//' gathered in g2p (relative)')
        call make_nodes(nd, 1 + nd, lo, one)
        call momentum_p2g(nd, nw, npt, i0, sw, mass, vp, lo, one)
        ! (the projection in the force slots of the node field)
        call make_nodes(nd, 1 + 2*nd, lo, mom)
        call momentum_project_p2g(nd, nw, npt, i0, sw, mass, vp, lo, gp, mom)
        two = mom(2 + nd:1 + 2*nd, :, :, :)
        call same_values(pack(mom(2:1 + nd, :, :, :), .true.), pack(one(2:1 + nd, :, :, :), .true.), &
                         trim(tag)//' remapped momentum', worst)
        rel = maxval(abs(one(2:1 + nd, :, :, :) - two))/maxval(abs(two))
        worst = max(worst, rel)
        call check_close(rel, 0.0_wp, 0.0_wp, 2.0e-15_wp, trim(tag)//' projected momenta (relative)')
        call check(maxval(abs(two)) > 0.0_wp, trim(tag)//' nonzero projection')
      end do
    end do
    print '(a,es10.3,a,es10.3)', '  largest relative difference ', worst, '; of the gather ', worstg
  end subroutine test_projection_is_interpolation_then_momentum_map

  !> The fused divergence pass of the two-phase step against the kernel it stands for, in
  !> 1D, 2D and 3D with every B-spline: point_divergences against the trace
  !> (L11 + L22) + L33 of point_gradient of each field (the fused remap,
  !> momentum_project_p2g, is held in the projection test above). Both sum by rows of the
  !> stencil; the divergence adds the three axes' row sums in its own order: measured
  !> largest relative difference 2.4e-16 (release) and 0 (debug), tolerance 2e-15 (8x).
  subroutine test_fused_passes_match_separate_kernels()
    integer :: nd, kernel, lo(3), nw(3), i0(3, npt)
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt)
    real(wp) :: ga(9, npt), gb(9, npt), fa(npt), fb(npt)
    real(wp), allocatable :: u1(:, :, :, :), u2(:, :, :, :)
    character(len=32) :: tag
    real(wp) :: worst
    call begin_test('fused_passes_match_separate_kernels')
    worst = 0.0_wp
    do nd = 1, 3
      do kernel = 1, ngrid_kernels
        tag = case_tag(kernel, nd)
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        ! two velocity fields (old and new slots)
        call make_nodes(nd, 2*nd, lo, u1)
        call fill_scattered(lo, u1)
        call make_nodes(nd, 2*nd, lo, u2)
        call fill_scattered(lo, u2)
        u2 = 1.7_wp*u2 - 0.3_wp
        ga = 0.0_wp; gb = 0.0_wp; fa = 0.0_wp; fb = 0.0_wp
        call point_gradient(nd, nw, npt, i0, sw, sdw, lo, u1, ga)
        call point_gradient(nd, nw, npt, i0, sw, sdw, lo, u2, gb)
        call point_divergences(nd, nw, npt, i0, sw, sdw, lo, u1, u2, fa, fb)
        call same_values(fa, ga(1, :) + ga(5, :) + ga(9, :), trim(tag)//' divergence of the first field', worst)
        call same_values(fb, gb(1, :) + gb(5, :) + gb(9, :), trim(tag)//' divergence of the second field', worst)
      end do
    end do
    print '(a,es10.3)', '  largest relative difference ', worst
  end subroutine test_fused_passes_match_separate_kernels

  !> The skeleton's p2g with its porosity sums in one pass (porous_p2g) against p2g and
  !> solid_porosity_p2g in turn, in 1D, 2D and 3D with every B-spline, with and without
  !> point forces, on points of which every fourth has no porosity (it adds nothing to
  !> the sums): the same numbers, bit for bit.
  subroutine test_porous_p2g_is_p2g_and_porosity_sums()
    integer :: nd, kernel, lo(3), nw(3), i0(3, npt), p, pass
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v(3, npt), stress(6, npt), poro(npt), kinv(npt)
    real(wp), allocatable :: na(:, :, :, :), nb(:, :, :, :), sa(:, :, :, :), sb(:, :, :, :)
    character(len=40) :: tag
    call begin_test('porous_p2g_is_p2g_and_porosity_sums')
    call point_data(mass, vol, v)
    do p = 1, npt
      stress(:, p) = [1.0e3_wp, -2.0e3_wp, 5.0e2_wp, -3.0e2_wp, 4.0e2_wp, 7.0e2_wp]*real(1 + mod(p, 4), wp)
      poro(p) = 0.3_wp + 0.01_wp*real(mod(p, 9), wp)
      if (mod(p, 4) == 0) poro(p) = 0.0_wp
      kinv(p) = 1.0e5_wp*(1.0_wp + 0.1_wp*real(mod(p, 5), wp))
    end do
    do nd = 1, 3
      do kernel = 1, ngrid_kernels
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        do pass = 1, 2
          write (tag, '(a,1x,i0,a,a)') trim(kernel_names(kernel)), nd, 'D', &
            trim(merge(' with point forces', '                  ', pass == 1))
          call make_nodes(nd, 1 + 2*nd, lo, na)
          call make_nodes(nd, 1 + 2*nd, lo, nb)
          call make_nodes(nd, 3, lo, sa)
          call make_nodes(nd, 3, lo, sb)
          call p2g(nd, nw, npt, i0, sw, sdw, mass, v(1:nd, :), vol, stress, pass == 1, lo, na)
          call solid_porosity_p2g(nw, npt, i0, sw, mass, poro, kinv, lo, sa)
          call porous_p2g(nd, nw, npt, i0, sw, sdw, mass, v(1:nd, :), vol, stress, pass == 1, lo, nb, poro, &
                          kinv, sb)
          call check(all(nb == na), trim(tag)//': mass, momentum and forces')
          call check(all(sb == sa) .and. maxval(sa) > 0.0_wp, trim(tag)//': porosity sums')
        end do
      end do
    end do
  end subroutine test_porous_p2g_is_p2g_and_porosity_sums

  !> The MUSL remap's g2p with the scatter of the new momenta in the same pass (g2p_remap)
  !> against g2p without the gradient followed by momentum_p2g, and with a gathered field
  !> (the locked velocity) against g2p's gather followed by momentum_project_p2g, in 1D,
  !> 2D and 3D with every B-spline: the same sums in the same order. The release build
  !> contracts them into FMAs alike except in g2p's cubic 3D form with the gather (a
  !> run-time switch there): measured largest relative difference 2.1e-16 (release), 0
  !> (debug); tolerance 2e-15 (10x), as the other fused passes.
  subroutine test_g2p_remap_is_g2p_then_momentum_map()
    integer :: nd, kernel, lo(3), nw(3), i0(3, npt), pass
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v(3, npt), va(3, npt), vb(3, npt), xa(3, npt), xb(3, npt), ga(3, npt), gb(3, npt)
    real(wp), parameter :: dt = 1.0e-3_wp, flip = 0.95_wp
    real(wp), allocatable :: nvel(:, :, :, :), f(:, :, :, :), na(:, :, :, :), nb(:, :, :, :)
    character(len=40) :: tag
    real(wp) :: worst
    call begin_test('g2p_remap_is_g2p_then_momentum_map')
    worst = 0.0_wp
    call point_data(mass, vol, v)
    do nd = 1, 3
      do kernel = 1, ngrid_kernels
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        call make_nodes(nd, 2*nd, lo, nvel)
        call fill_scattered(lo, nvel)
        call make_nodes(nd, nd, lo, f)
        call fill_scattered(lo, f)
        f = 0.5_wp*f + 0.2_wp
        do pass = 1, 2
          write (tag, '(a,1x,i0,a,a)') trim(kernel_names(kernel)), nd, 'D', &
            trim(merge(' with the gather', '                ', pass == 2))
          va = v; vb = v; xa = x; xb = x; ga = 0.0_wp; gb = 0.0_wp
          call make_nodes(nd, 1 + 2*nd, lo, na)
          call make_nodes(nd, 1 + 2*nd, lo, nb)
          if (pass == 1) then
            call g2p(nd, nw, npt, i0, sw, sdw, lo, nvel, flip, dt, va(1:nd, :), xa(1:nd, :), gradient=.false.)
            call momentum_p2g(nd, nw, npt, i0, sw, mass, va(1:nd, :), lo, na)
            call g2p_remap(nd, nw, npt, i0, sw, sdw, lo, nvel, flip, dt, mass, vb(1:nd, :), xb(1:nd, :), nb)
          else
            call g2p(nd, nw, npt, i0, sw, sdw, lo, nvel, flip, dt, va(1:nd, :), xa(1:nd, :), gradient=.false., &
                     gf=f, gv=ga(1:nd, :))
            call momentum_project_p2g(nd, nw, npt, i0, sw, mass, va(1:nd, :), lo, ga(1:nd, :), na)
            call g2p_remap(nd, nw, npt, i0, sw, sdw, lo, nvel, flip, dt, mass, vb(1:nd, :), xb(1:nd, :), nb, &
                           gf=f, gv=gb(1:nd, :))
            call same_values(pack(gb(1:nd, :), .true.), pack(ga(1:nd, :), .true.), trim(tag)//': gathered values', &
                             worst)
          end if
          call check(any(va /= v), trim(tag)//': the points moved')
          call same_values(pack(vb(1:nd, :), .true.), pack(va(1:nd, :), .true.), trim(tag)//': velocities', worst)
          call same_values(pack(xb(1:nd, :), .true.), pack(xa(1:nd, :), .true.), trim(tag)//': positions', worst)
          call same_values(pack(nb, .true.), pack(na, .true.), trim(tag)//': node fields', worst)
        end do
      end do
    end do
    print '(a,es10.3)', '  largest relative difference ', worst
  end subroutine test_g2p_remap_is_g2p_then_momentum_map

  !> b against a, relative to the largest |a| (which must not be 0); worst keeps the largest.
  subroutine same_values(b, a, label, worst)
    real(wp), intent(in) :: b(:), a(:)
    character(len=*), intent(in) :: label
    real(wp), intent(inout) :: worst
    real(wp) :: rel
    rel = maxval(abs(b - a))/max(maxval(abs(a)), tiny(1.0_wp))
    worst = max(worst, rel)
    call check_close(rel, 0.0_wp, 0.0_wp, 2.0e-15_wp, label//' (relative)')
    call check(maxval(abs(a)) > 0.0_wp, label//' nonzero')
  end subroutine same_values

  !> A velocity field b + A x with every component of A different.
  subroutine linear_field(a, b)
    real(wp), intent(out) :: a(3, 3), b(3)
    a = reshape([0.1_wp, -0.3_wp, 0.25_wp, 0.7_wp, -0.2_wp, 0.05_wp, -0.45_wp, 0.15_wp, 0.35_wp], [3, 3])
    b = [1.0_wp, -2.0_wp, 0.5_wp]
  end subroutine linear_field

  !> Old and new nodal velocities both b + A x_I (the nd leading components).
  subroutine fill_linear(nd, lo, a, b, nvel)
    integer, intent(in) :: nd, lo(3)
    real(wp), intent(in) :: a(3, 3), b(3)
    real(wp), intent(inout) :: nvel(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k
    real(wp) :: xn(3), vn(3)
    do k = lbound(nvel, 4), ubound(nvel, 4)
      do j = lbound(nvel, 3), ubound(nvel, 3)
        do i = lbound(nvel, 2), ubound(nvel, 2)
          xn = node_x(i, j, k)
          if (nd < 3) xn(3) = 0.0_wp
          vn = b + matmul(a, xn)
          nvel(1:nd, i, j, k) = vn(1:nd)
          nvel(nd + 1:2*nd, i, j, k) = vn(1:nd)
        end do
      end do
    end do
  end subroutine fill_linear

  !> The point gradient (3x3 column-major) against A on the nd x nd block.
  subroutine check_gradient(nd, lg, a, what)
    integer, intent(in) :: nd
    real(wp), intent(in) :: lg(9), a(3, 3)
    character(len=*), intent(in) :: what
    real(wp) :: l(3, 3)
    integer :: r, c
    l = reshape(lg, [3, 3])
    do c = 1, nd
      do r = 1, nd
        call check_close(l(r, c), a(r, c), 1.0e-12_wp, 1.0e-12_wp, what)
      end do
    end do
  end subroutine check_gradient

  !> In 3D, p2g (mass, momentum, body force and the internal force of a full stress) and
  !> g2p (FLIP blend, position, velocity gradient) against the same sums written out node
  !> by node from tensor_weights, for each stencil width: p2g and g2p run the forms of
  !> fixed width (dpmpm_transfer_w2/3/4), the reference none of the transfer kernels.
  subroutine test_three_d_forms_match_direct_sums()
    integer, parameter :: nd = 3
    real(wp), parameter :: tol_rel = 1.0e-13_wp, flip = 0.7_wp, dt = 1.0e-3_wp
    integer :: kernel, p, lo(3), nw(3), i0(3, npt), m, nq, c, i, j, k
    integer, allocatable :: off(:, :)
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v(3, npt), bacc(3, npt), stress(6, npt), s(3, 3), w(64), dw(3, 64)
    real(wp) :: v1(3, npt), x1(3, npt), vgrad(9, npt), vn(3), dv(3), lg(3, 3)
    real(wp), allocatable :: node(:, :, :, :), ref(:, :, :, :), nvel(:, :, :, :)
    character(len=32) :: tag
    call begin_test('three_d_forms_match_direct_sums')
    do kernel = 1, ngrid_kernels
      tag = case_tag(kernel, nd)
      call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
      call stencil_offsets(nw, nq, off)
      call point_data(mass, vol, v)
      do p = 1, npt
        bacc(:, p) = [1.5_wp, -9.8_wp, 0.4_wp] - 0.02_wp*real(p, wp)
        stress(:, p) = [-3.0_wp, -5.0_wp, -4.0_wp, 0.7_wp, -0.3_wp, 1.1_wp]*(1.0_wp + 0.03_wp*real(p, wp))
      end do
      call make_nodes(nd, 1 + 2*nd, lo, node)
      call make_nodes(nd, 1 + 2*nd, lo, ref)
      call p2g(nd, nw, npt, i0, sw, sdw, mass, v, vol, stress, .true., lo, node, bacc)
      do p = 1, npt
        call tensor_weights(nw, sw(:, :, p), sdw(:, :, p), w(1:nq), dw(:, 1:nq))
        s = voigt_to_tensor(stress(:, p))
        do m = 1, nq
          i = i0(1, p) + off(1, m); j = i0(2, p) + off(2, m); k = i0(3, p) + off(3, m)
          ref(1, i, j, k) = ref(1, i, j, k) + w(m)*mass(p)
          ref(2:4, i, j, k) = ref(2:4, i, j, k) + w(m)*mass(p)*v(:, p)
          ref(5:7, i, j, k) = ref(5:7, i, j, k) + w(m)*mass(p)*bacc(:, p) - vol(p)*matmul(s, dw(:, m))
        end do
      end do
      do c = 1, 7
        call check_close(maxval(abs(node(c, :, :, :) - ref(c, :, :, :)))/maxval(abs(ref(c, :, :, :))), 0.0_wp, &
                         0.0_wp, tol_rel, trim(tag)//' p2g slot (relative)')
      end do
      ! g2p: old and new nodal velocities of no particular form.
      call make_nodes(nd, 2*nd, lo, nvel)
      do k = lbound(nvel, 4), ubound(nvel, 4)
        do j = lbound(nvel, 3), ubound(nvel, 3)
          do i = lbound(nvel, 2), ubound(nvel, 2)
            do c = 1, 2*nd
              nvel(c, i, j, k) = sin(0.7_wp*real(i, wp) + 1.3_wp*real(j, wp) - 0.4_wp*real(k, wp) + real(c, wp))
            end do
          end do
        end do
      end do
      v1 = v
      x1 = x
      call g2p(nd, nw, npt, i0, sw, sdw, lo, nvel, flip, dt, v1, x1, vgrad)
      do p = 1, npt
        call tensor_weights(nw, sw(:, :, p), sdw(:, :, p), w(1:nq), dw(:, 1:nq))
        vn = 0.0_wp; dv = 0.0_wp; lg = 0.0_wp
        do m = 1, nq
          i = i0(1, p) + off(1, m); j = i0(2, p) + off(2, m); k = i0(3, p) + off(3, m)
          vn = vn + w(m)*nvel(4:6, i, j, k)
          dv = dv + w(m)*(nvel(4:6, i, j, k) - nvel(1:3, i, j, k))
          do c = 1, 3
            lg(:, c) = lg(:, c) + nvel(4:6, i, j, k)*dw(c, m)
          end do
        end do
        do c = 1, 3
          call check_close(v1(c, p), flip*(v(c, p) + dv(c)) + (1.0_wp - flip)*vn(c), 1.0e-13_wp, 1.0e-13_wp, &
                           trim(tag)//' g2p velocity')
          call check_close(x1(c, p), x(c, p) + dt*vn(c), 1.0e-14_wp, 1.0e-14_wp, trim(tag)//' g2p position')
        end do
        call check_close(maxval(abs(vgrad(:, p) - reshape(lg, [9]))), 0.0_wp, 0.0_wp, 1.0e-12_wp, &
                         trim(tag)//' g2p velocity gradient')
      end do
    end do
  end subroutine test_three_d_forms_match_direct_sums

  !> In 3D, the point gradient, the two divergences, the momentum remap (with and without
  !> the projection of a point field), the fluid's p2g (momentum, drag, fluid volume,
  !> pressure forces on both phases) and the skeleton's porosity sums against the same
  !> sums written out node by node from tensor_weights, for each stencil width (the
  !> kernels run their forms of fixed width, dpmpm_transfer_w2/3/4).
  subroutine test_three_d_remap_and_two_phase_forms_match_direct_sums()
    integer, parameter :: nd = 3
    integer :: kernel, p, lo(3), nw(3), i0(3, npt), m, nq, c, i, j, k
    integer, allocatable :: off(:, :)
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v(3, npt), fp(3, npt), poro(npt), pres(npt), kinv(npt), w(64), dw(3, 64)
    real(wp) :: vgrad(9, npt), div(npt), div2(npt), lg(3, 3), d1, d2
    real(wp), allocatable :: nvel(:, :, :, :), nvel2(:, :, :, :), node(:, :, :, :), ref(:, :, :, :)
    real(wp), allocatable :: rproj(:, :, :, :), ns(:, :, :, :), rs(:, :, :, :)
    real(wp), allocatable :: drag(:, :, :, :), rdrag(:, :, :, :), fvol(:, :, :, :), rfvol(:, :, :, :)
    character(len=32) :: tag
    call begin_test('three_d_remap_and_two_phase_forms_match_direct_sums')
    do kernel = 1, ngrid_kernels
      tag = case_tag(kernel, nd)
      call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
      call stencil_offsets(nw, nq, off)
      call point_data(mass, vol, v)
      do p = 1, npt
        fp(:, p) = [-0.4_wp, 0.9_wp, 0.2_wp] - 0.03_wp*real(p, wp)
        poro(p) = 0.3_wp + 0.01_wp*real(mod(p, 9), wp)
        pres(p) = 1.0e4_wp*(1.0_wp + 0.02_wp*real(p, wp))
        kinv(p) = 1.0e5_wp*(1.0_wp + 0.1_wp*real(mod(p, 4), wp))
      end do
      ! gradient and divergences of nodal velocities of no particular form
      call make_nodes(nd, 2*nd, lo, nvel)
      call make_nodes(nd, 2*nd, lo, nvel2)
      do k = lbound(nvel, 4), ubound(nvel, 4)
        do j = lbound(nvel, 3), ubound(nvel, 3)
          do i = lbound(nvel, 2), ubound(nvel, 2)
            do c = 1, 2*nd
              nvel(c, i, j, k) = sin(0.7_wp*real(i, wp) + 1.3_wp*real(j, wp) - 0.4_wp*real(k, wp) + real(c, wp))
              nvel2(c, i, j, k) = cos(0.3_wp*real(i, wp) - 0.8_wp*real(j, wp) + 1.1_wp*real(k, wp) + real(c, wp))
            end do
          end do
        end do
      end do
      call point_gradient(nd, nw, npt, i0, sw, sdw, lo, nvel, vgrad)
      call point_divergences(nd, nw, npt, i0, sw, sdw, lo, nvel, nvel2, div, div2)
      do p = 1, npt
        call tensor_weights(nw, sw(:, :, p), sdw(:, :, p), w(1:nq), dw(:, 1:nq))
        lg = 0.0_wp; d1 = 0.0_wp; d2 = 0.0_wp
        do m = 1, nq
          i = i0(1, p) + off(1, m); j = i0(2, p) + off(2, m); k = i0(3, p) + off(3, m)
          do c = 1, 3
            lg(:, c) = lg(:, c) + nvel(4:6, i, j, k)*dw(c, m)
          end do
          d1 = d1 + dot_product(nvel(4:6, i, j, k), dw(:, m))
          d2 = d2 + dot_product(nvel2(4:6, i, j, k), dw(:, m))
        end do
        call check_close(maxval(abs(vgrad(:, p) - reshape(lg, [9]))), 0.0_wp, 0.0_wp, 1.0e-12_wp, &
                         trim(tag)//' point gradient')
        call check_close(div(p), d1, 1.0e-12_wp, 1.0e-12_wp, trim(tag)//' divergence of nvel')
        call check_close(div2(p), d2, 1.0e-12_wp, 1.0e-12_wp, trim(tag)//' divergence of nvel2')
      end do
      ! the momentum remap, alone and with the projection of fp
      call make_nodes(nd, 1 + 2*nd, lo, node)
      call make_nodes(nd, 1 + 2*nd, lo, ref)
      call make_nodes(nd, nd, lo, rproj)
      call momentum_p2g(nd, nw, npt, i0, sw, mass, v, lo, node)
      do p = 1, npt
        call tensor_weights(nw, sw(:, :, p), sdw(:, :, p), w(1:nq), dw(:, 1:nq))
        do m = 1, nq
          i = i0(1, p) + off(1, m); j = i0(2, p) + off(2, m); k = i0(3, p) + off(3, m)
          ref(2:4, i, j, k) = ref(2:4, i, j, k) + w(m)*mass(p)*v(:, p)
          rproj(:, i, j, k) = rproj(:, i, j, k) + w(m)*mass(p)*fp(:, p)
        end do
      end do
      call same_slots(node(2:4, :, :, :), ref(2:4, :, :, :), trim(tag)//' momentum remap')
      node = 0.0_wp
      call momentum_project_p2g(nd, nw, npt, i0, sw, mass, v, lo, fp, node)
      call same_slots(node(2:4, :, :, :), ref(2:4, :, :, :), trim(tag)//' remap with projection: momentum')
      call same_slots(node(5:7, :, :, :), rproj, trim(tag)//' remap with projection: projection')
      ! the fluid's p2g and the skeleton's porosity sums
      call make_nodes(nd, 1 + 2*nd, lo, ns)
      call make_nodes(nd, 1 + 2*nd, lo, rs)
      call make_nodes(nd, 3, lo, drag)
      call make_nodes(nd, 3, lo, rdrag)
      call make_nodes(nd, 1, lo, fvol)
      call make_nodes(nd, 1, lo, rfvol)
      node = 0.0_wp
      ref = 0.0_wp
      call fluid_p2g(nd, nw, npt, i0, sw, sdw, mass, v, vol, poro, pres, kinv, .true., .true., lo, ns, node, &
                     drag, fvol)
      do p = 1, npt
        call tensor_weights(nw, sw(:, :, p), sdw(:, :, p), w(1:nq), dw(:, 1:nq))
        do m = 1, nq
          i = i0(1, p) + off(1, m); j = i0(2, p) + off(2, m); k = i0(3, p) + off(3, m)
          ref(1, i, j, k) = ref(1, i, j, k) + w(m)*mass(p)
          ref(2:4, i, j, k) = ref(2:4, i, j, k) + w(m)*mass(p)*v(:, p)
          ref(5:7, i, j, k) = ref(5:7, i, j, k) + vol(p)*pres(p)*poro(p)*dw(:, m)
          rs(5:7, i, j, k) = rs(5:7, i, j, k) + vol(p)*pres(p)*(1.0_wp - poro(p))*dw(:, m)
          rdrag(1, i, j, k) = rdrag(1, i, j, k) + w(m)*mass(p)*poro(p)*gravity_drag*kinv(p)
          rfvol(1, i, j, k) = rfvol(1, i, j, k) + w(m)*vol(p)
        end do
      end do
      call same_slots(node, ref, trim(tag)//' fluid p2g: fluid')
      call same_slots(ns(5:7, :, :, :), rs(5:7, :, :, :), trim(tag)//' fluid p2g: skeleton force')
      call same_slots(drag(1:1, :, :, :), rdrag(1:1, :, :, :), trim(tag)//' fluid p2g: drag')
      call same_slots(fvol, rfvol, trim(tag)//' fluid p2g: fluid volume')
      drag = 0.0_wp
      rdrag = 0.0_wp
      call solid_porosity_p2g(nw, npt, i0, sw, mass, poro, kinv, lo, drag)
      do p = 1, npt
        call tensor_weights(nw, sw(:, :, p), sdw(:, :, p), w(1:nq), dw(:, 1:nq))
        do m = 1, nq
          i = i0(1, p) + off(1, m); j = i0(2, p) + off(2, m); k = i0(3, p) + off(3, m)
          rdrag(:, i, j, k) = rdrag(:, i, j, k) + w(m)*mass(p)*[poro(p), 1.0_wp, kinv(p)]
        end do
      end do
      call same_slots(drag, rdrag, trim(tag)//' porosity sums')
    end do
  end subroutine test_three_d_remap_and_two_phase_forms_match_direct_sums

  !> Masses, volumes and velocities of the npt points of the 3D tests, varied from point to point.
  !> The point volume of the nodes (volume_p2g: the forms of fixed width in 2D and 3D, the
  !> general loop in 1D) against sum_p V_p N_I(x_p) written out node by node in the
  !> general loop's order, N_I = w1 w2 w3: bit for bit, in 1D, 2D and 3D with every
  !> B-spline.
  subroutine test_volume_sums_match_node_by_node_sums()
    integer :: nd, kernel, p, lo(3), nw(3), i0(3, npt), a, b, c
    real(wp) :: x(3, npt), sw(max_stencil, 3, npt), sdw(max_stencil, 3, npt), mass(npt), vol(npt)
    real(wp) :: v(3, npt)
    real(wp), allocatable :: nvol(:, :, :, :), ref(:, :, :, :)
    character(len=32) :: tag
    call begin_test('volume_sums_match_node_by_node_sums')
    do nd = 1, 3
      do kernel = 1, ngrid_kernels
        tag = case_tag(kernel, nd)
        call make_points(nd, kernel, npt, x, i0, sw, sdw, nw)
        call point_data(mass, vol, v)
        call make_nodes(nd, 1, lo, nvol)
        call make_nodes(nd, 1, lo, ref)
        call volume_p2g(nw, npt, i0, sw, vol, lo, nvol)
        do p = 1, npt
          do c = 1, nw(3)
            do b = 1, nw(2)
              do a = 1, nw(1)
                associate (r => ref(1, i0(1, p) + a - 1, i0(2, p) + b - 1, i0(3, p) + c - 1))
                  r = r + sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)*vol(p)
                end associate
              end do
            end do
          end do
        end do
        call check(all(nvol == ref) .and. maxval(ref) > 0.0_wp, trim(tag)//': the node-by-node sums')
      end do
    end do
  end subroutine test_volume_sums_match_node_by_node_sums

  !> The label of a case: the kernel's name and the dimension ("linear 2D").
  function case_tag(kernel, nd) result(tag)
    integer, intent(in) :: kernel, nd
    character(len=32) :: tag
    write (tag, '(a,1x,i0,a)') trim(kernel_names(kernel)), nd, 'D'
  end function case_tag

  subroutine point_data(mass, vol, v)
    real(wp), intent(out) :: mass(npt), vol(npt), v(3, npt)
    integer :: p
    do p = 1, npt
      mass(p) = 1.0_wp + 0.1_wp*real(mod(p, 7), wp)
      vol(p) = 0.01_wp + 1.0e-4_wp*real(mod(p, 5), wp)
      v(:, p) = [0.3_wp, -1.2_wp, 0.7_wp] + 0.05_wp*real(p, wp)
    end do
  end subroutine point_data

  !> Node fields b against a slot by slot, relative to each slot's largest |a|.
  subroutine same_slots(b, a, label)
    real(wp), intent(in) :: b(:, :, :, :), a(:, :, :, :)
    character(len=*), intent(in) :: label
    integer :: c
    do c = 1, size(a, 1)
      call check(maxval(abs(a(c, :, :, :))) > 0.0_wp, label//' nonzero')
      call check_close(maxval(abs(b(c, :, :, :) - a(c, :, :, :)))/max(maxval(abs(a(c, :, :, :))), tiny(1.0_wp)), &
                       0.0_wp, 0.0_wp, 1.0e-13_wp, label//' (relative)')
    end do
  end subroutine same_slots

end program test_transfer
