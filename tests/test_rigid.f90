!> Rigid bodies (&material model = 'rigid', dpmpm_rigid): a rigid plate pushed into an
!> elastic column confined by rollers compresses it oedometrically, the drive force
!> following E_c A u / H, and the plate's points move at the prescribed velocity; on a
!> saturated column (undrained) the force follows the mixture's modulus E_c + K_f / n_f
!> and the pore pressure its share K_f / n_f.
program test_rigid
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, region_cfg_t, material_cfg_t, bc_roller, bc_fixed, fbc_impermeable
  use dpmpm_test_scenes, only: grid_scene
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, check_close, am_root
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  real(wp), parameter :: e = 1.0e7_wp, nu = 0.3_wp, v0 = 0.01_wp, t_end = 0.3_wp
  call start_tests()
  call test_plate_compresses_column_oedometrically()
  call test_plate_compresses_saturated_column_undrained()
  call test_smoothed_footing_on_tresca_soil_nears_prandtl()
  call end_tests()

contains

  !> A column 0.2 m wide and 1 m high (4 x 20 cells of 0.05 m, E = 10 MPa, nu = 0.3,
  !> rho = 2000) between rollers on a fixed base, under a rigid plate 0.1 m thick pushed
  !> down at 0.01 m/s from t = 0; no gravity. The plate's lowest node row is the column's
  !> top, so the column shortens by u = v t and carries sigma_yy = E_c u / H with
  !> E_c = E (1 - nu) / ((1 + nu)(1 - 2 nu)); the drive pushes with F = sigma_yy A.
  function press() result(cfg)
    type(config_t) :: cfg
    cfg = grid_scene('rigid_press', [4, 24], [0.2_wp, 1.2_wp], t_end, cfl=0.5_wp)
    cfg%bc(1:2) = bc_roller
    cfg%bc(3) = bc_fixed
    allocate (cfg%materials(2), cfg%regions(2), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2000.0_wp, &
                                      youngs_modulus=e, poisson_ratio=nu)
    cfg%materials(2) = material_cfg_t(id=2, model='rigid', density=2000.0_wp, &
                                      velocity=[0.0_wp, -v0, 0.0_wp])
    cfg%regions(1) = region_cfg_t(lo=0.0_wp, hi=[0.2_wp, 1.0_wp, 1.0_wp], material=1)
    cfg%regions(2)%lo = [0.0_wp, 1.0_wp, 0.0_wp]
    cfg%regions(2)%hi = [0.2_wp, 1.1_wp, 1.0_wp]
    cfg%regions(2)%material = 2
  end function press

  !> Measured over 0.3 s (1 and 2 ranks): the drive force grows at -26 839 N/m/s against
  !> E_c A v / H = -26 923 N/m/s (-0.31 %); the last record alone is 2.0 % off (the column
  !> rings from the sudden start, +-rho c v A = 330 N/m). Tolerance 1 %; taking the force
  !> with the rigid points' mass at the node instead of the node's whole mass gives
  !> -14 609 N/m/s and fails. The plate's points are 3 mm lower, exactly v t (1e-12), and
  !> move at v.
  subroutine test_plate_compresses_column_oedometrically()
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), st(:, :), x0(:, :)
    real(wp) :: ec, force, dmax
    integer :: p
    call begin_test('plate_compresses_column_oedometrically')
    call sim%init(press(), MPI_COMM_WORLD, write_output=.false.)
    call sim%gather_points(ids, x0, v, st)
    call sim%run()
    ec = e*(1.0_wp - nu)/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
    call check(sim%ndrive > 1, 'drive force recorded')
    call check_close(force_rate(sim), -ec*v0/1.0_wp*0.2_wp, 1.0e-2_wp, 0.0_wp, &
                     'rate of the drive force against E_c A v / H')
    force = sim%drive_hist(3, sim%ndrive)
    call check(abs(sim%drive_hist(2, sim%ndrive)) < 1.0e-6_wp*abs(force), 'no force along x')
    call sim%gather_points(ids, x, v, st)
    if (am_root) then
      dmax = 0.0_wp
      do p = 1, size(ids)
        if (x0(2, p) < 1.0_wp) cycle
        dmax = max(dmax, abs(x(2, p) - x0(2, p) + v0*sim%time), abs(x(1, p) - x0(1, p)), &
                   abs(v(2, p) + v0), abs(v(1, p)))
      end do
      call check(dmax < 1.0e-12_wp, 'plate points moved by v t at v')
    end if
    call sim%free()
  end subroutine test_plate_compresses_column_oedometrically

  !> The column of press() saturated with water (n_f = 0.4, K_f = 22 MPa, k = 1e-8 m/s,
  !> grains rho = 2650, implicit drag, impermeable base): over 0.3 s the water barely
  !> drains (sqrt(c_v t) = 2 mm with c_v = 1.3e-5 m^2/s), so the column is compressed undrained.
  !> With incompressible grains the pore pressure rises by (K_f / n_f) u / H and the total
  !> stress by (E_c + K_f / n_f) u / H, which the drive must supply: 6.85e7 Pa against
  !> E_c = 1.35e7 Pa for the skeleton alone.
  !> Measured (1 and 2 ranks alike): rate of the drive force -1.36727e5 N/m/s against
  !> -(E_c + K_f / n_f) A v / H = -1.36923e5 (-0.14 %); below the top cell, mean pore pressure
  !> over mean effective stress sigma'_yy 4.0949 against K_f / (n_f E_c) = 4.0857 (+0.22 %),
  !> mean pore pressure 1.6547e5 Pa against (K_f / n_f) v t / H = 1.65e5 (+0.28 %; the
  !> ringing of the sudden start, rho c v = 3.7 kPa, moves it by up to 2.2 %). Tolerances
  !> 1 %, 1 % and 3 %; with the skeleton's modulus alone the force would be 80 % off.
  subroutine test_plate_compresses_saturated_column_undrained()
    type(simulation_t) :: sim
    type(config_t) :: cfg
    real(wp), parameter :: kf = 2.2e7_wp, n = 0.4_wp
    real(wp) :: ec, rate, acc(4), pmean, smean
    integer :: p
    call begin_test('plate_compresses_saturated_column_undrained')
    cfg = press()
    cfg%name = 'rigid_press_saturated'
    cfg%drag = 'implicit'
    deallocate (cfg%materials)
    allocate (cfg%materials(3))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2650.0_wp, &
                                      youngs_modulus=e, poisson_ratio=nu, conductivity=1.0e-8_wp)
    cfg%materials(2) = material_cfg_t(id=2, model='rigid', density=2000.0_wp, &
                                      velocity=[0.0_wp, -v0, 0.0_wp])
    cfg%materials(3) = material_cfg_t(id=3, model='fluid', density=1000.0_wp, bulk_modulus=kf)
    cfg%regions(1)%phase = 'saturated'
    cfg%regions(1)%fluid_material = 3
    cfg%regions(1)%porosity = n
    cfg%fluid_bc(3) = fbc_impermeable
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    ec = e*(1.0_wp - nu)/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
    call check(sim%ndrive > 1, 'drive force recorded')
    rate = force_rate(sim)
    if (am_root) print '(a,es14.6,a,es14.6)', 'drive force rate ', rate, ' against ', -(ec + kf/n)*v0*0.2_wp
    call check_close(rate, -(ec + kf/n)*v0/1.0_wp*0.2_wp, 1.0e-2_wp, 0.0_wp, &
                     'rate of the drive force against (E_c + K_f / n_f) A v / H')
    ! Below the top cell (whose water drains into the plate's nodes): the mean pore
    ! pressure of the fluid points and the mean effective stress sigma'_yy of the soil
    ! points. The column rings from the sudden start (rho c v = 3.7 kPa, 2 % of p), in
    ! both alike: their ratio is the undrained split K_f / (n_f E_c).
    acc = 0.0_wp
    associate (f => sim%phase(2)%pts, s => sim%phase(1)%pts)
      do p = 1, f%n
        if (f%x(2, p) > 0.95_wp) cycle
        acc(1:2) = acc(1:2) + [f%pressure(p), 1.0_wp]
      end do
      do p = 1, s%n
        if (s%x(2, p) > 0.95_wp) cycle
        acc(3:4) = acc(3:4) + [s%stress(2, p), 1.0_wp]
      end do
    end associate
    call MPI_Allreduce(MPI_IN_PLACE, acc, 4, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD)
    pmean = acc(1)/acc(2)
    smean = acc(3)/acc(4)
    if (am_root) print '(a,2es14.6,a,es14.6)', 'mean p, sigma_yy: ', pmean, smean, ' ratio ', -pmean/smean
    call check_close(-pmean/smean, kf/(n*ec), 1.0e-2_wp, 0.0_wp, 'pore pressure over effective stress')
    call check_close(pmean, kf/n*v0*t_end/1.0_wp, 3.0e-2_wp, 0.0_wp, 'mean pore pressure')
    call sim%free()
  end subroutine test_plate_compresses_saturated_column_undrained

  !> inputs/footing_prandtl_2d.nml with volumetric_smoothing = 'cell': half of a rough
  !> rigid strip footing B = 1 m wide pushed at 0.05 m/s into weightless Tresca soil
  !> (c = 10 kPa, phi = psi = 0, E = 10 MPa, nu = 0.3), h = 0.1 m, 2 x 2 points per cell,
  !> flip 1, to 0.1 B. The bearing pressure over 5-10 % of B against Prandtl's (2 + pi) c.
  !> Measured (release, doc/verification.md "Rigid footing"): q/c = 5.735, +11.5 %; without
  !> the smoothing 6.349, +23.5 % (volumetric locking). Bounds: above (2 + pi) c (the
  !> grid's excess, first order in h, stays) and below +15 % (the measured +11.5 % and 3.5
  !> points of margin), which the locked footing fails. 1 and 2 ranks.
  subroutine test_smoothed_footing_on_tresca_soil_nears_prandtl()
    real(wp), parameter :: c = 1.0e4_wp, vf = 0.05_wp, b = 1.0_wp, nc = 2.0_wp + acos(-1.0_wp)
    type(config_t) :: cfg
    type(simulation_t) :: sim
    real(wp) :: qsum, s
    integer :: p, nq
    call begin_test('smoothed_footing_on_tresca_soil_nears_prandtl')
    cfg = grid_scene('footing_prandtl', [50, 36], [5.0_wp, 3.6_wp], 0.1_wp*b/vf, cfl=0.5_wp)
    cfg%volumetric_smoothing = 'cell'
    cfg%bc(1:3) = [bc_roller, bc_roller, bc_fixed]
    allocate (cfg%materials(2), cfg%regions(2), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model='mohr_coulomb', density=2000.0_wp, youngs_modulus=1.0e7_wp, &
                                      poisson_ratio=0.3_wp, friction_angle=0.0_wp, dilatancy_angle=0.0_wp, &
                                      cohesion=c)
    cfg%materials(2) = material_cfg_t(id=2, model='rigid', density=2000.0_wp, velocity=[0.0_wp, -vf, 0.0_wp])
    cfg%regions(1) = region_cfg_t(lo=0.0_wp, hi=[5.0_wp, 3.0_wp, 1.0_wp], material=1)
    cfg%regions(2)%lo = [0.0_wp, 3.0_wp, 0.0_wp]
    cfg%regions(2)%hi = [0.5_wp, 3.2_wp, 1.0_wp]
    cfg%regions(2)%material = 2
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    qsum = 0.0_wp
    nq = 0
    do p = 1, sim%ndrive
      s = vf*sim%drive_hist(1, p)/b
      if (s < 0.05_wp .or. s > 0.1_wp + 1.0e-9_wp) cycle
      qsum = qsum - sim%drive_hist(3, p)/(0.5_wp*b)
      nq = nq + 1
    end do
    call check(nq > 5, 'drive force recorded over 5-10 % of B')
    if (nq > 0) then
      call check(qsum/nq/c > nc, say_q('q/c above (2 + pi)', qsum/nq/c))
      call check(qsum/nq/c < 1.15_wp*nc, say_q('q/c below 1.15 (2 + pi)', qsum/nq/c))
    end if
    call sim%free()
  end subroutine test_smoothed_footing_on_tresca_soil_nears_prandtl

  function say_q(what, q) result(t)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: q
    character(len=:), allocatable :: t
    character(len=32) :: buf
    write (buf, '(f10.4)') q
    t = what//' (measured '//trim(adjustl(buf))//')'
  end function say_q

  !> Rate k of the drive force along y, least squares over the records of sim. Each record
  !> is the mean force over the interval since the one before: against the ramp k t, the
  !> mean is k at the interval's midpoint. The fit leaves out the ringing of the sudden
  !> start.
  real(wp) function force_rate(sim) result(k)
    type(simulation_t), intent(in) :: sim
    real(wp) :: sft, stt, tm
    integer :: p
    sft = 0.0_wp; stt = 0.0_wp
    do p = 2, sim%ndrive
      tm = 0.5_wp*(sim%drive_hist(1, p - 1) + sim%drive_hist(1, p))
      sft = sft + sim%drive_hist(3, p)*tm
      stt = stt + tm*tm
    end do
    k = sft/stt
  end function force_rate

end program test_rigid
