!> A rigid body's frictional contact with the soil (&material contact = 'frictional',
!> dpmpm_contact; doc/theory.md 6.8.1): a free rigid block on an elastic layer under gravity
!> tilted by theta (the layer horizontal) follows Coulomb's law, sliding at
!> g (sin theta - mu cos theta) - a B / M where that is positive and staying where it is not,
!> with and without adhesion a; 1 and 2 ranks (the block crosses the ranks' border).
!> Measured errors and bounds: doc/verification.md, "A rigid block sliding on soil".
program test_rigid_contact
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, bc_roller, bc_fixed
  use dpmpm_test_scenes, only: grid_scene
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, am_root
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  real(wp), parameter :: g = 9.81_wp, deg = acos(-1.0_wp)/180.0_wp
  !> the block: width B, height, density (mass M per metre), and the run's length
  real(wp), parameter :: bw = 0.4_wp, bh = 0.2_wp, rho = 2000.0_wp
  !> the equilibrium phase, and the time from rest after it
  real(wp), parameter :: te = 0.1_wp, ts = 0.15_wp
  call start_tests()
  call test_block_slides_at_coulomb_rate()
  call test_block_holds_below_friction_angle()
  call test_adhesion_slows_sliding_block()
  call test_adhesion_holds_block_beyond_friction_angle()
  call test_prescribed_body_follows_its_table()
  call test_free_body_takes_pulse_impulse()
  call end_tests()

contains

  !> A layer 2 m long and 0.2 m thick (E = 20 MPa, nu = 0.3, rho = 2000; rollers at its ends,
  !> fixed base) and on it a free rigid block B = 0.4 m wide, 0.2 m high, rho = 2000, from
  !> x = 0.8 m (across the middle of the grid), gravity g at theta from the vertical toward
  !> +x; cells of 0.05 m, 2 x 2 points each, the contact's friction mu and adhesion a.
  function block(theta, mu, a) result(cfg)
    real(wp), intent(in) :: theta, mu, a
    type(config_t) :: cfg
    cfg = grid_scene('rigid_contact_block', [40, 12], [2.0_wp, 0.6_wp], te, nmat=2, nreg=2, nload=0, &
                     cfl=0.5_wp, gravity=g*[sin(theta*deg), -cos(theta*deg)])
    cfg%equilibrium_time = te
    cfg%bc(1:3) = [bc_roller, bc_roller, bc_fixed]
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2000.0_wp, &
                                      youngs_modulus=2.0e7_wp, poisson_ratio=0.3_wp)
    cfg%materials(2) = material_cfg_t(id=2, model='rigid', density=rho, contact='frictional', &
                                      contact_friction=mu, contact_adhesion=a, body_motion='free')
    cfg%regions(1)%lo = 0.0_wp
    cfg%regions(1)%hi = [2.0_wp, 0.2_wp, 1.0_wp]
    cfg%regions(1)%material = 1
    cfg%regions(2)%lo = [0.8_wp, 0.2_wp, 0.0_wp]
    cfg%regions(2)%hi = [0.8_wp + bw, 0.2_wp + bh, 1.0_wp]
    cfg%regions(2)%material = 2
  end function block

  !> The block's mean displacement along x over (te, te + ts) and its mean velocity along x
  !> at te + ts (on the root; the block's points start above y = 0.2): the run of cfg goes to
  !> te with its equilibrium phase (gravity ramped over te/2, the soil damped, every velocity
  !> set to zero at te), then on from rest at the full gravity.
  subroutine run_block(cfg, ux, vx)
    type(config_t), intent(in) :: cfg
    real(wp), intent(out) :: ux, vx
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids0(:), ids(:)
    real(wp), allocatable :: x0(:, :), v0(:, :), s0(:, :), x(:, :), v(:, :), s(:, :)
    integer :: p, nb
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    call sim%gather_points(ids0, x0, v0, s0)
    sim%cfg%t_end = te + ts
    call sim%run()
    call sim%gather_points(ids, x, v, s)
    call sim%free()
    ux = 0.0_wp
    vx = 0.0_wp
    if (.not. am_root) return
    nb = 0
    do p = 1, size(ids)
      if (ids(p) /= ids0(p)) error stop 'the points changed their order'
      if (x0(2, p) < 0.2_wp) cycle
      nb = nb + 1
      ux = ux + x(1, p) - x0(1, p)
      vx = vx + v(1, p)
    end do
    ux = ux/nb
    vx = vx/nb
  end subroutine run_block

  !> The acceleration the block's velocity and displacement after ts from rest stand for,
  !> against the closed form acc, printed; within relv and relu of acc (checked on the root).
  subroutine check_rate(ux, vx, acc, relv, relu, what)
    real(wp), intent(in) :: ux, vx, acc, relv, relu
    character(len=*), intent(in) :: what
    if (.not. am_root) return
    print '(2a,3(a,f9.5))', '  ', what, ': acceleration from v ', vx/ts, ', from u ', &
      2.0_wp*ux/ts**2, ', Coulomb ', acc
    call check(abs(vx/ts - acc) <= relv*acc, what//': v/t at the closed form')
    call check(abs(2.0_wp*ux/ts**2 - acc) <= relu*acc, what//': 2 u/t^2 at the closed form')
  end subroutine check_rate

  !> theta = 30 deg, mu = 0.3: a = g (sin theta - mu cos theta) = 2.356 m/s^2. Measured on 1
  !> and 2 ranks alike: 2.3529 from v (-0.15 %), 2.3594 from u (+0.13 %); bounds 1 %.
  subroutine test_block_slides_at_coulomb_rate()
    real(wp) :: ux, vx
    call begin_test('block_slides_at_coulomb_rate')
    call run_block(block(30.0_wp, 0.3_wp, 0.0_wp), ux, vx)
    call check_rate(ux, vx, g*(sin(30.0_wp*deg) - 0.3_wp*cos(30.0_wp*deg)), 0.01_wp, 0.01_wp, 'sliding')
  end subroutine test_block_slides_at_coulomb_rate

  !> theta = 10 deg < atan 0.3 = 16.7 deg: the block stays (g sin theta alone would move it
  !> 19 mm in ts). Measured: -4.8e-8 m; bound 0.2 mm.
  subroutine test_block_holds_below_friction_angle()
    real(wp) :: ux, vx
    call begin_test('block_holds_below_friction_angle')
    call run_block(block(10.0_wp, 0.3_wp, 0.0_wp), ux, vx)
    if (.not. am_root) return
    print '(a,2es11.3)', '  held: displacement, velocity ', ux, vx
    call check(abs(ux) < 2.0e-4_wp, 'the block stays below its friction angle')
  end subroutine test_block_holds_below_friction_angle

  !> theta = 30 deg, mu = 0.3, a = 500 Pa: a B / M = 500 0.4 / 160 = 1.25 m/s^2 less,
  !> 1.106 m/s^2. Measured: 1.1118 from v (+0.50 %), 1.0557 from u (-4.6 %: the block starts
  !> late, its speed then follows the rate); bounds 2 % and 7 %.
  subroutine test_adhesion_slows_sliding_block()
    real(wp) :: ux, vx
    call begin_test('adhesion_slows_sliding_block')
    call run_block(block(30.0_wp, 0.3_wp, 500.0_wp), ux, vx)
    call check_rate(ux, vx, g*(sin(30.0_wp*deg) - 0.3_wp*cos(30.0_wp*deg)) - 500.0_wp*bw/(rho*bw*bh), &
                    0.02_wp, 0.07_wp, 'sliding with adhesion')
  end subroutine test_adhesion_slows_sliding_block

  !> theta = 30 deg, mu = 0.3, a = 1500 Pa: a B = 600 N/m holds the 377 N/m that friction
  !> leaves of the block's weight along the slope (without it the block would slide 26 mm in
  !> ts). Measured: 1.9e-5 m; bound 0.2 mm.
  subroutine test_adhesion_holds_block_beyond_friction_angle()
    real(wp) :: ux, vx
    call begin_test('adhesion_holds_block_beyond_friction_angle')
    call run_block(block(30.0_wp, 0.3_wp, 1500.0_wp), ux, vx)
    if (.not. am_root) return
    print '(a,2es11.3)', '  held by adhesion: displacement, velocity ', ux, vx
    call check(abs(ux) < 2.0e-4_wp, 'adhesion holds the block')
  end subroutine test_adhesion_holds_block_beyond_friction_angle

  !> A grid of 1 m x 1 m (20 x 20 cells), an elastic layer 0.1 m thick on a fixed base and a
  !> rigid block of 0.2 m x 0.2 m at (0.4, 0.4) (across the middle) that does not reach it,
  !> 200 steps of 1 ms, the block's material mat.
  function air_scene(mat) result(cfg)
    type(material_cfg_t), intent(in) :: mat
    type(config_t) :: cfg
    cfg = grid_scene('rigid_contact_air', [20, 20], [1.0_wp, 1.0_wp], 0.2_wp, nmat=2, nreg=2, nload=0)
    cfg%dt = 1.0e-3_wp
    cfg%bc(3) = bc_fixed
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2000.0_wp, &
                                      youngs_modulus=1.0e6_wp, poisson_ratio=0.3_wp)
    cfg%materials(2) = mat
    cfg%regions(1)%lo = 0.0_wp
    cfg%regions(1)%hi = [1.0_wp, 0.1_wp, 1.0_wp]
    cfg%regions(1)%material = 1
    cfg%regions(2)%lo = [0.4_wp, 0.4_wp, 0.0_wp]
    cfg%regions(2)%hi = [0.6_wp, 0.6_wp, 1.0_wp]
    cfg%regions(2)%material = 2
  end function air_scene

  !> The largest deviation of the block's points (those above y = 0.3) from the displacement
  !> du and velocity vel at the end of the run of cfg (on the root; 0 elsewhere).
  real(wp) function block_deviation(cfg, du, vel) result(dev)
    type(config_t), intent(in) :: cfg
    real(wp), intent(in) :: du(2), vel(2)
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids0(:), ids(:)
    real(wp), allocatable :: x0(:, :), v0(:, :), s0(:, :), x(:, :), v(:, :), s(:, :)
    integer :: p
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%gather_points(ids0, x0, v0, s0)
    call sim%run()
    call sim%gather_points(ids, x, v, s)
    call sim%free()
    dev = 0.0_wp
    if (.not. am_root) return
    do p = 1, size(ids)
      if (x0(2, p) < 0.3_wp) cycle
      dev = max(dev, maxval(abs(x(1:2, p) - x0(1:2, p) - du)), maxval(abs(v(1:2, p) - vel)))
    end do
  end function block_deviation

  !> A prescribed body (frictional contact, so that the table reaches that path too) at
  !> velocity (0.2, -0.1) m/s times the table 0 at 0, 1 at 0.1 s, 1 after: at 0.2 s it has
  !> moved (0.2, -0.1) (0.05 + 0.1) m. The steps take the velocity at their middle, which is
  !> exact on a linear ramp whose kink falls on a step's end. Measured 2.2e-17 m; bound 1e-14.
  subroutine test_prescribed_body_follows_its_table()
    type(material_cfg_t) :: mat
    real(wp) :: dev
    call begin_test('prescribed_body_follows_its_table')
    mat = material_cfg_t(id=2, model='rigid', density=2000.0_wp, contact='frictional')
    mat%velocity(1:2) = [0.2_wp, -0.1_wp]
    mat%motion_times(1:2) = [0.0_wp, 0.1_wp]
    mat%motion_factors(1:2) = [0.0_wp, 1.0_wp]
    dev = block_deviation(air_scene(mat), [0.2_wp, -0.1_wp]*0.15_wp, [0.2_wp, -0.1_wp])
    if (.not. am_root) return
    print '(a,es10.2)', '  prescribed table: largest deviation of the block ', dev
    call check(dev <= 1.0e-14_wp, 'the body moved by the integral of its table')
  end subroutine test_prescribed_body_follows_its_table

  !> A free body (M = 2000 0.2 0.2 = 80 kg/m, no gravity) under a hammer blow: body_load
  !> (0, -8000) N/m times the triangle 0 at 0.02 s, 1 at 0.03 s, 0 at 0.04 s, an impulse of
  !> 80 N s/m: from rest it moves at -1 m/s after the blow, and by -(0.2 - 0.03) m at 0.2 s
  !> (the blow's centroid at 0.03 s) less dt/2 times its change of velocity: each step
  !> moves it by dt times its velocity at the step's end (the semi-implicit Euler step of
  !> doc/theory.md (6.7)). Measured 5.6e-16; bound 1e-13.
  subroutine test_free_body_takes_pulse_impulse()
    type(material_cfg_t) :: mat
    real(wp) :: dev
    call begin_test('free_body_takes_pulse_impulse')
    mat = material_cfg_t(id=2, model='rigid', density=2000.0_wp, contact='frictional', body_motion='free')
    mat%body_load(1:2) = [0.0_wp, -8000.0_wp]
    mat%motion_times(1:3) = [0.02_wp, 0.03_wp, 0.04_wp]
    mat%motion_factors(1:3) = [0.0_wp, 1.0_wp, 0.0_wp]
    dev = block_deviation(air_scene(mat), [0.0_wp, -0.17_wp - 0.5e-3_wp], [0.0_wp, -1.0_wp])
    if (.not. am_root) return
    print '(a,es10.2)', '  hammer blow: largest deviation of the block ', dev
    call check(dev <= 1.0e-13_wp, 'the free body took the impulse of the blow')
  end subroutine test_free_body_takes_pulse_impulse

end program test_rigid_contact
