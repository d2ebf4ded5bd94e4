!> MLS inside the time step: Standard MPM is the linear-kernel, constant-basis
!> MLS path; the Gauss-point quadrature with the transposed strain operator
!> (doc/theory.md 3.6) keeps the energy of a long elastic run; the manufactured
!> solution M1 at B = 0.05 cracks Standard MPM but not the MLS pair, which
!> converges at second order; a point that has just entered a cell at its corner
!> does not give a node that it barely reaches the force of the whole cell; linear grid
!> functions with one Gauss point per cell whose weight reaches just the cell keep Standard
!> MPM's error at small deformation and do not crack at large, in 3D with a box weight.
!> Bounds are measured values with the margins in doc/verification.md.
program test_mls_solver
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, region_cfg_t, material_cfg_t, bc_fixed, bc_roller
  use dpmpm_test_scenes, only: grid_scene
  use dpmpm_simulation, only: simulation_t
  use dpmpm_phase, only: solid_phase, fluid_phase
  use dpmpm_quadrature, only: gauss_point_gradients
  use dpmpm_benchmarks, only: benchmark_errors
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_test_compare, only: reldiff
  implicit none
  call start_tests()
  call test_standard_mpm_is_linear_constant_mls()
  call test_transposed_pair_keeps_energy()
  call test_mms_crack_and_convergence()
  call test_mms_body_force_work_is_booked()
  call test_pair_thin_node_takes_no_force()
  call test_cell_gauss_point_keeps_standard_mpm_accuracy()
  call test_box_gauss_point_keeps_standard_mpm_accuracy_3d()
  call end_tests()

contains

  !> A neo-Hookean block with scattered points thrown onto a fixed floor under gravity.
  function block_scene() result(cfg)
    type(config_t) :: cfg
    cfg = grid_scene('mls_block', [16, 12], [1.6_wp, 1.2_wp], 0.3_wp, nmat=1, nreg=1, nload=0, &
                     cfl=0.4_wp, flip=0.95_wp, gravity=[0.0_wp, -10.0_wp])
    cfg%materials(1) = material_cfg_t(id=1, model='neo_hookean', density=1000.0_wp, &
                                      youngs_modulus=1.0e5_wp, poisson_ratio=0.3_wp)
    cfg%regions(1) = region_cfg_t(lo=[0.25_wp, 0.0_wp, 0.0_wp], hi=[1.05_wp, 0.7_wp, 0.0_wp], &
                                  placement='random', seed=5, velocity=[1.0_wp, 0.5_wp, 0.0_wp])
    cfg%bc(3) = bc_fixed
    cfg%bc(1:2) = bc_roller
  end function block_scene

  !> M1 on a unit square with ncells^2 cells and amplitude b; mls selects the pair.
  function mms_scene(ncells, b, pair) result(cfg)
    integer, intent(in) :: ncells
    real(wp), intent(in) :: b
    logical, intent(in) :: pair
    type(config_t) :: cfg
    cfg%name = 'mms'
    cfg%ndim = 2
    cfg%ncells = [ncells, ncells, 1]
    cfg%length = 1.0_wp
    cfg%t_end = 0.02_wp
    cfg%cfl = 0.2_wp
    cfg%diag_every = 1
    allocate (cfg%materials(1), cfg%regions(1), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model='neo_hookean', density=1.0_wp, &
                                      youngs_modulus=1.0e4_wp, poisson_ratio=0.3_wp)
    cfg%regions(1)%lo = 0.0_wp
    cfg%regions(1)%hi = 1.0_wp
    cfg%bc(1:4) = bc_roller
    cfg%benchmark = 'mms'
    cfg%amplitude = b
    if (pair) call use_pair(cfg)
  end function mms_scene

  !> The pair of doc/theory.md 3.6: cubic grid functions, Gauss points, Wendland C2 stresses.
  subroutine use_pair(cfg)
    type(config_t), intent(inout) :: cfg
    cfg%kernel = 'cubic'
    cfg%quadrature = 'gauss'
    cfg%field_kernel = 'wendland_c2'
    cfg%field_radius = 2.0_wp
  end subroutine use_pair

  subroutine run(cfg, ids, x, v, s, drift)
    type(config_t), intent(in) :: cfg
    integer(i8), allocatable, intent(out) :: ids(:)
    real(wp), allocatable, intent(out) :: x(:, :), v(:, :), s(:, :)
    real(wp), intent(out) :: drift
    type(simulation_t) :: sim
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    call sim%gather_points(ids, x, v, s)
    drift = sim%energy_drift
    call sim%free()
  end subroutine run

  !> The projection v_I = sum N m v / sum N m of Standard MPM and the MLS path with
  !> the linear tensor weight, constant basis and mass weights give the same run.
  subroutine test_standard_mpm_is_linear_constant_mls()
    type(config_t) :: cfg
    integer(i8), allocatable :: id1(:), id2(:)
    real(wp), allocatable :: x1(:, :), v1(:, :), s1(:, :), x2(:, :), v2(:, :), s2(:, :)
    real(wp) :: e1, e2, dev
    call begin_test('standard_mpm_is_linear_constant_mls')
    cfg = block_scene()
    call run(cfg, id1, x1, v1, s1, e1)
    cfg%velocity_kernel = 'linear'
    cfg%velocity_basis = 'constant'
    call run(cfg, id2, x2, v2, s2, e2)
    call check(all(id1 == id2), 'same points')
    dev = max(reldiff(x2, x1), reldiff(v2, v1), reldiff(s2, s1))
    print '(a,es10.3)', '  largest relative deviation: ', dev
    ! Round-off only: measured 0 to 1e-15 over 100 steps.
    call check(dev <= 1.0e-12_wp, 'MLS linear/constant equals the projection to round-off')
  end subroutine test_standard_mpm_is_linear_constant_mls

  !> A linear-elastic square with scattered points vibrating between rollers for
  !> about 8 periods: the energy of the transposed Gauss-point pair stays put.
  subroutine test_transposed_pair_keeps_energy()
    type(config_t) :: cfg
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), s(:, :)
    real(wp) :: drift_std, drift_pair
    call begin_test('transposed_pair_keeps_energy')
    cfg = mms_scene(8, 0.0_wp, .false.)
    cfg%benchmark = 'none'
    cfg%materials(1)%model = 'linear_elastic'
    cfg%regions(1)%placement = 'random'
    cfg%regions(1)%seed = 3
    cfg%regions(1)%velocity = [0.3_wp, -0.2_wp, 0.0_wp]
    cfg%t_end = 0.16_wp
    cfg%diag_every = 5
    call run(cfg, ids, x, v, s, drift_std)
    call use_pair(cfg)
    call run(cfg, ids, x, v, s, drift_pair)
    print '(a,2es10.3)', '  energy change, Standard MPM and pair: ', drift_std, drift_pair
    ! Measured (doc/verification.md): pair 5.0e-2, Standard MPM 3.3e-2 (MUSL); bound
    ! with 20 % margin. An inconsistent force/strain pair gains energy many-fold.
    call check(drift_pair <= 6.0e-2_wp, 'the pair keeps the energy over about 8 periods')
  end subroutine test_transposed_pair_keeps_energy

  !> The run monitor books the work of the manufactured body forces: M1 at B = 0.05,
  !> h = 1/8, Standard MPM, run to 0.1 s (12 transits of the elastic wave); the largest
  !> (kinetic + stored) / (work + initial) stays near 1 and the balance error small.
  !> Measured: 1.039 and 0.039 (1 and 2 ranks); with the work left out, 3.39 and 2.39.
  !> Bounds: 1.2 (0.8 below) and 0.1.
  subroutine test_mms_body_force_work_is_booked()
    type(config_t) :: cfg
    type(simulation_t) :: sim
    call begin_test('mms_body_force_work_is_booked')
    cfg = mms_scene(8, 0.05_wp, .false.)
    cfg%t_end = 0.1_wp
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    print '(a,2es11.4)', '  largest energy / (work + initial), balance error: ', sim%mon%ratio, sim%mon%balance
    call check(sim%mon%ratio < 1.2_wp .and. sim%mon%ratio > 0.8_wp, 'energy within 20 % of what the body was given')
    call check(sim%mon%balance < 0.1_wp, 'balance error below 0.1')
    call sim%free()
  end subroutine test_mms_body_force_work_is_booked

  !> A saturated linear-elastic square (porosity 0.4, k = 1e-2 m/s, implicit drag) under
  !> an effective pressure of 10 kPa and a pore pressure of 10 kPa, its points 2 x 2 per
  !> cell (0.2 m < x, y < 0.6 m, h = 0.1 m), with the pair; the solid point at its upper
  !> right corner is moved just past the corner, 1 mm into the next cell on the diagonal,
  !> and the fluid point there 10 mm (as the soil point on the face below the crest in
  !> slope_into_water_2d that had just entered a cell). That cell's Gauss points carry the
  !> square's stresses to the nodes two cells on, which the points reach with 2.8e-14
  !> (solid) and 2.8e-8 (fluid) of their mass. Without the thin-node rule those nodes
  !> took the force of the cell over that sliver, the drag's corrections of the remap
  !> kept the relative velocity, and after one step the largest |L| dt of the points was
  !> 14.7 and the monitor stopped the run (energy ratio 2.3e9). With it: 1.9e-4 (ratio
  !> 1.04); bound 1e-3. The fluid points keep only the divergences of the fluid's and
  !> the skeleton's velocity, held to the same bound (largest |div v| dt 3.9e-4); the
  !> fluid's full gradient is formed again after the step by the same transposed
  !> operator from the step's fields (largest |L| dt 3.7e-5).
  subroutine test_pair_thin_node_takes_no_force()
    type(config_t) :: cfg
    type(simulation_t) :: sim
    integer :: pc, ip
    real(wp) :: lmax, ls, lff, ldiv
    real(wp), allocatable :: lf(:, :)
    call begin_test('pair_thin_node_takes_no_force')
    cfg = grid_scene('thin_node', [10, 10], [1.0_wp, 1.0_wp], 1.0_wp, nmat=2, nreg=1, nload=0, &
                     cfl=0.4_wp, max_steps=1, gravity=[0.0_wp, 0.0_wp, 0.0_wp])
    cfg%drag = 'implicit'
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2650.0_wp, &
                                      youngs_modulus=2.0e7_wp, poisson_ratio=0.3_wp, conductivity=1.0e-2_wp)
    cfg%materials(2) = material_cfg_t(id=2, model='fluid', density=1000.0_wp, bulk_modulus=2.2e7_wp)
    cfg%regions(1) = region_cfg_t(lo=[0.2_wp, 0.2_wp, 0.0_wp], hi=[0.6_wp, 0.6_wp, 0.0_wp], &
                                  material=1, fluid_material=2, phase='saturated', porosity=0.4_wp)
    cfg%regions(1)%stress(1:3) = -1.0e4_wp
    cfg%regions(1)%pore_pressure = 1.0e4_wp
    call use_pair(cfg)
    cfg%gauss_points = 3
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    do ip = 1, 2
      associate (ps => sim%phase(ip)%pts)
        pc = maxloc(ps%x(1, 1:ps%n) + ps%x(2, 1:ps%n), dim=1)
        ps%x(1:2, pc) = [0.601_wp, 0.601_wp] + (ip - 1)*0.009_wp
      end associate
    end do
    call sim%run()
    associate (s => sim%phase(solid_phase))
      ls = maxval(abs(s%vgrad(:, 1:s%pts%n)))*sim%time
    end associate
    associate (f => sim%phase(fluid_phase))
      allocate (lf(9, f%pts%n))
      lf = 0.0_wp
      call gauss_point_gradients(sim, f, f%gsol, f%nvel, lf)
      lff = maxval(abs(lf))*sim%time
      ldiv = max(maxval(abs(f%divf(1:f%pts%n))), maxval(abs(f%divs(1:f%pts%n))))*sim%time
    end associate
    lmax = max(ls, lff, ldiv)
    print '(a,3es10.3,a,es10.3)', '  largest |L| dt after one step (solid, fluid), |div v| dt at the fluid points: ', &
      ls, lff, ldiv, '; energy ratio ', sim%mon%ratio
    call check(sim%exit_code == 0, 'the run takes its step')
    call check(lmax < 1.0e-3_wp, 'no point takes a velocity gradient from a node it barely reaches')
    call sim%free()
  end subroutine test_pair_thin_node_takes_no_force

  !> M1 at B = 0.05, h = 1/8 and 1/16: Standard MPM opens (gap ratio 1.16 and 1.25)
  !> and its velocity error does not fall; the pair stays closed (gap ratio 1.06,
  !> 1.02) and e_u(T) falls at second order.
  subroutine test_mms_crack_and_convergence()
    real(wp) :: e(5, 2, 2)
    integer :: k, m
    real(wp) :: order
    call begin_test('mms_crack_and_convergence')
    do m = 1, 2
      do k = 1, 2
        e(:, k, m) = mms_run(mms_scene(8*k, 0.05_wp, m == 2))
      end do
    end do
    print '(a,4es11.3)', '  gap ratio std 1/8 1/16, pair 1/8 1/16: ', e(4, :, 1), e(4, :, 2)
    print '(a,4es11.3)', '  e_u(T)    std 1/8 1/16, pair 1/8 1/16: ', e(2, :, 1), e(2, :, 2)
    order = log(e(2, 1, 2)/e(2, 2, 2))/log(2.0_wp)
    print '(a,f6.3)', '  order of e_u(T) of the pair: ', order
    call check(e(4, 2, 1) >= 1.2_wp, 'Standard MPM opens a gap at h = 1/16 (measured 1.25)')
    call check(e(4, 2, 2) <= 1.03_wp, 'the pair stays closed at h = 1/16 (measured 1.02)')
    call check(order >= 1.9_wp, 'the pair converges at second order (measured 2.16)')
  end subroutine test_mms_crack_and_convergence

  !> Linear grid functions with the stresses at one Gauss point per cell, reconstructed
  !> with the radial linear hat of radius 0.75 cells (every place of the cell within
  !> reach, half its diagonal being 0.71 cells; none of the neighbours' points with 2 x 2
  !> regular points per cell, 0.79 cells away), against Standard MPM on M1 at h = 1/16.
  !> B = 1e-4: e_u(T) 2.420e-6 for both (ratio 1.000; bound 1.05), where the tensor-product
  !> hat of one cell (radius 0) reaches the neighbours' points and has 4.536e-6 (ratio
  !> 1.87; the check asks for 1.5). B = 0.05: 1.601e-3 against Standard MPM's cracked
  !> 6.532e-3 (ratio 4.08; bound 2.1e-3, + 30 %, and a ratio of at least 3).
  subroutine test_cell_gauss_point_keeps_standard_mpm_accuracy()
    real(wp) :: std_small, cell_small, hat_small, std_large, cell_large
    call begin_test('cell_gauss_point_keeps_standard_mpm_accuracy')
    std_small = m1_error(16, 1.0e-4_wp, -1.0_wp)
    cell_small = m1_error(16, 1.0e-4_wp, 0.75_wp)
    hat_small = m1_error(16, 1.0e-4_wp, 0.0_wp)
    std_large = m1_error(16, 0.05_wp, -1.0_wp)
    cell_large = m1_error(16, 0.05_wp, 0.75_wp)
    print '(a,3es11.4)', '  B = 1e-4, e_u(T): Standard MPM, radius 0.75, radius 0: ', std_small, cell_small, hat_small
    print '(a,2es11.4)', '  B = 0.05, e_u(T): Standard MPM, radius 0.75: ', std_large, cell_large
    call check(cell_small <= 1.05_wp*std_small, 'small deformation: the error of Standard MPM')
    call check(hat_small >= 1.5_wp*std_small, 'small deformation: the weight of one cell each way has more')
    call check(cell_large <= 2.1e-3_wp, 'large deformation: error within bound')
    call check(std_large >= 3.0_wp*cell_large, 'large deformation: Standard MPM (cracked) far worse')
  end subroutine test_cell_gauss_point_keeps_standard_mpm_accuracy

  !> In 3D a radial weight cannot both reach every place of a cell from its centre (0.87
  !> cells) and miss the neighbours' regular points (0.83 cells away); a box of half-width
  !> 0.65 cells along each axis does both (the cell's places lie within 0.5, the neighbours'
  !> points 0.75 away along an axis). The axial bar as a 3D column of 40 x 2 x 2 cells,
  !> largest displacement error over 0.4 s: Standard MPM 1.4370e-3, the box 1.4364e-3 (ratio
  !> 1.000; bound 1.02), the ball of 0.9 1.9790e-3 (ratio 1.38; the check asks for 1.2).
  subroutine test_box_gauss_point_keeps_standard_mpm_accuracy_3d()
    real(wp) :: std, box, ball
    call begin_test('box_gauss_point_keeps_standard_mpm_accuracy_3d')
    std = bar3d_error(-1.0_wp, 'ball')
    box = bar3d_error(0.65_wp, 'box')
    ball = bar3d_error(0.9_wp, 'ball')
    print '(a,3es11.4)', '  3D bar, largest e_u: Standard MPM, box 0.65, ball 0.9: ', std, box, ball
    call check(box <= 1.02_wp*std, 'the box: the error of Standard MPM')
    call check(ball >= 1.2_wp*std, 'the ball that reaches the whole cell takes neighbours and has more')
  end subroutine test_box_gauss_point_keeps_standard_mpm_accuracy_3d

  !> Largest displacement error over the run of the axial bar (inputs/axial_bar.nml) as a 3D
  !> column of 40 x 2 x 2 cells with rollers on the side faces: Standard MPM for radius < 0,
  !> else linear grid functions with one Gauss point per cell and the linear hat of that
  !> radius and support as the field weight.
  real(wp) function bar3d_error(radius, support) result(e)
    real(wp), intent(in) :: radius
    character(len=*), intent(in) :: support
    type(config_t) :: cfg
    type(simulation_t) :: sim
    cfg = grid_scene('bar3d', [40, 2, 2], [1.25_wp, 0.0625_wp, 0.0625_wp], 0.4_wp, nmat=1, nreg=1, &
                     nload=0, cfl=0.2_wp, flip=1.0_wp)
    cfg%diag_every = 10
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=1.0_wp, &
                                      youngs_modulus=100.0_wp, poisson_ratio=0.0_wp)
    cfg%regions(1)%lo = 0.0_wp
    cfg%regions(1)%hi = [1.0_wp, 0.0625_wp, 0.0625_wp]
    cfg%bc(1) = bc_fixed
    cfg%bc(3:6) = bc_roller
    cfg%benchmark = 'axial_bar'
    cfg%amplitude = 0.01_wp
    if (radius >= 0.0_wp) call use_cell_gauss_point(cfg, radius, support)
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    e = maxval(sim%err_hist(3, 1:sim%nerr))
    call sim%free()
  end function bar3d_error

  !> Linear grid functions with the stresses at one Gauss point per cell, reconstructed with
  !> the linear hat of the given radius (cells) and support (ball or box) as the field weight.
  subroutine use_cell_gauss_point(cfg, radius, support)
    type(config_t), intent(inout) :: cfg
    real(wp), intent(in) :: radius
    character(len=*), intent(in) :: support
    cfg%quadrature = 'gauss'
    cfg%gauss_points = 1
    cfg%field_kernel = 'linear'
    cfg%field_radius = radius
    cfg%field_support = support
  end subroutine use_cell_gauss_point

  !> e_u(T) of M1 with ncells^2 cells and amplitude b: Standard MPM for radius < 0, else
  !> linear grid functions with one Gauss point per cell and the linear hat of that radius
  !> (cells; 0: the tensor-product hat of one cell) as the field weight.
  real(wp) function m1_error(ncells, b, radius) result(e)
    integer, intent(in) :: ncells
    real(wp), intent(in) :: b, radius
    type(config_t) :: cfg
    real(wp) :: err(5)
    cfg = mms_scene(ncells, b, .false.)
    if (radius >= 0.0_wp) call use_cell_gauss_point(cfg, radius, 'ball')
    err = mms_run(cfg)
    e = err(2)
  end function m1_error

  !> Errors of one M1 run (cfg) at its end: velocity, displacement, mean velocity,
  !> largest gap ratio over the run, empty cells.
  function mms_run(cfg) result(err)
    type(config_t), intent(in) :: cfg
    real(wp) :: err(5)
    type(simulation_t) :: sim
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    err = sim%err_hist(2:6, sim%nerr)
    err(4) = maxval(sim%err_hist(5, 1:sim%nerr))
    call sim%free()
  end function mms_run

end program test_mls_solver
