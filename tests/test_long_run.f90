!> Long runs of the two-phase step (doc/verification.md, "Long runs of the
!> two-phase step"): the 1D W1 column for 20 transits of the undrained wave at the
!> default Courant number, its kinetic energy against the physical scale
!> 0.5 M v_u^2 (M the mass of the column, v_u = q / (rho_sat c_u) the particle
!> speed behind the undrained front), and the run monitor's energy ratio.
program test_long_run
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, region_cfg_t, material_cfg_t, load_cfg_t, bc_fixed, bc_roller
  use dpmpm_test_scenes, only: grid_scene
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  ! W1: n_f = 0.3, rho_s = 2650, rho_f = 1000 kg/m^3, E_c = 10 MPa, K_f = 3 MPa, q = 1 Pa.
  real(wp), parameter :: NF = 0.3_wp, RHOS = 2650.0_wp, RHOF = 1000.0_wp, EC = 1.0e7_wp, KF = 3.0e6_wp
  real(wp), parameter :: RHOSAT = (1.0_wp - NF)*RHOS + NF*RHOF
  real(wp), parameter :: CU = sqrt((EC + KF/NF)/RHOSAT), VU = 1.0_wp/(RHOSAT*CU)
  real(wp), parameter :: TRANSITS = 20.0_wp*10.0_wp/CU
  ! Bounds (doc/verification.md, "Tests"): largest kinetic energy / (0.5 M v_u^2) and
  ! the monitor's largest (kinetic + stored) / (work done + initial energy), measured
  ! values + 30 %. Standard MPM, points scattered in each cell: measured 0.988, 1.039.
  ! The pair on the uniform scatter of inputs/w1.nml: measured 0.976, 1.157.
  real(wp), parameter :: STD_KE = 1.29_wp, STD_RATIO = 1.36_wp
  real(wp), parameter :: PAIR_KE = 1.27_wp, PAIR_RATIO = 1.51_wp
  ! The 2D column of inputs/w1_2d.nml (100 x 2 cells, uniform scatter, seed 1), Standard
  ! MPM: measured 1.154 and 1.016 (release build, 2 ranks); bounds + 30 %.
  real(wp), parameter :: STD2_KE = 1.50_wp, STD2_RATIO = 1.33_wp
  ! Without the remap correction the Standard run reaches 7.5e9 times the scale by
  ! 20 transits (release build, measured), the 2D column 6.6e4; the test asks for 100.
  real(wp), parameter :: GROWS = 100.0_wp
  ! W3: K_f = 2.2 GPa, k = 1e-4 m/s; 100 transits. Quadratic B-splines on the uniform
  ! scatter: without the removal of the locked velocity's split (remap_drag as it was
  ! before) the monitor stopped the run at 0.382 s (release build, measured); with it
  ! the run ends, monitor ratio 0.101 (the quadratic column loses energy at its top).
  real(wp), parameter :: KF3 = 2.2e9_wp, CU3 = sqrt((EC + KF3/NF)/RHOSAT)
  real(wp), parameter :: W3_TRANSITS = 100.0_wp*10.0_wp/CU3, W3_RATIO = 1.0_wp
  integer :: rank
  call start_tests(rank)
  call test_w1_standard_bounded_over_20_transits()
  call test_w1_standard_grows_without_remap_drag()
  call test_w1_pair_uniform_scatter_bounded_over_20_transits()
  call test_w1_2d_standard_bounded_over_20_transits()
  call test_w3_quadratic_runs_100_transits()
  call test_w1_2d_standard_grows_without_remap_drag()
  call end_tests()

contains

  !> The W1 column, 100 cells, implicit drag, cfl 0.5, to 20 transits, no output (in 2D
  !> with dims = 2).
  function w1_scene(placement, seed, pair, dims) result(cfg)
    character(len=*), intent(in) :: placement
    integer, intent(in) :: seed
    logical, intent(in) :: pair
    integer, intent(in), optional :: dims
    type(config_t) :: cfg
    cfg = grid_scene('long_run', [100], [10.0_wp], TRANSITS, nmat=2, nreg=1, nload=1, cfl=0.5_wp)
    cfg%drag = 'implicit'
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=RHOS, &
                                      youngs_modulus=EC, poisson_ratio=0.0_wp, conductivity=1.0e-5_wp)
    cfg%materials(2) = material_cfg_t(id=2, model='fluid', density=RHOF, bulk_modulus=KF)
    cfg%regions(1) = region_cfg_t(lo=[0.0_wp, 0.0_wp, 0.0_wp], hi=[10.0_wp, 1.0_wp, 1.0_wp], &
                                  material=1, fluid_material=2, phase='saturated', porosity=NF, &
                                  ppc=2, placement=placement, seed=seed)
    cfg%loads(1) = load_cfg_t(face=1, traction=[1.0_wp, 0.0_wp, 0.0_wp], ramp_time=0.0_wp)
    cfg%bc(2) = bc_fixed
    if (present(dims)) then
      if (dims == 2) then
        ! the column of inputs/w1_2d.nml: two cells wide, rollers on the sides
        cfg%ndim = 2
        cfg%ncells = [100, 2, 1]
        cfg%length = [10.0_wp, 0.2_wp, 1.0_wp]
        cfg%regions(1)%hi = [10.0_wp, 0.2_wp, 1.0_wp]
        cfg%bc(3:4) = bc_roller
      end if
    end if
    if (pair) then
      cfg%kernel = 'cubic'
      cfg%quadrature = 'gauss'
      cfg%gauss_points = 3
      cfg%field_kernel = 'wendland_c2'
      cfg%field_radius = 2.0_wp
    end if
  end function w1_scene

  !> Run cfg; largest kinetic energy over 0.5 M v_u^2, the monitor's ratio, the end time.
  subroutine run(cfg, ke, ratio, t)
    type(config_t), intent(in) :: cfg
    real(wp), intent(out) :: ke, ratio, t
    type(simulation_t) :: sim
    real(wp) :: m
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    m = sum(sim%phase(1)%pts%mass(1:sim%phase(1)%pts%n)) + sum(sim%phase(2)%pts%mass(1:sim%phase(2)%pts%n))
    call MPI_Allreduce(MPI_IN_PLACE, m, 1, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD)
    ke = sim%mon%ke_max/(0.5_wp*m*VU**2)
    ratio = sim%mon%ratio
    t = sim%time
    if (rank == 0) print '(a,es11.3,a,es11.3,a,es11.4)', '  largest KE / (0.5 M v_u^2) ', ke, &
      ', largest (KE + stored) / (work + initial) ', ratio, ', end time ', t
    call sim%free()
  end subroutine run

  !> cfg run over 20 transits: it gets there, its largest kinetic energy at most ke_bound
  !> and its largest energy against the work done and the initial energy at most
  !> ratio_bound.
  subroutine check_bounded(cfg, ke_bound, ratio_bound)
    type(config_t), intent(in) :: cfg
    real(wp), intent(in) :: ke_bound, ratio_bound
    real(wp) :: ke, ratio, t
    call run(cfg, ke, ratio, t)
    call check(t >= TRANSITS*(1.0_wp - 1.0e-12_wp), 'ran 20 transits')
    call check(ke <= ke_bound, 'largest kinetic energy within bound')
    call check(ratio <= ratio_bound, 'energy / (work done + initial energy) within bound')
  end subroutine check_bounded

  !> Standard MPM on 2 + 2 points scattered in each cell (the points of
  !> tests/test_two_phase.f90), 20 transits at cfl 0.5: the energy stays at the
  !> physical level.
  subroutine test_w1_standard_bounded_over_20_transits()
    call begin_test('w1_standard_bounded_over_20_transits')
    call check_bounded(w1_scene('random', 5, .false.), STD_KE, STD_RATIO)
  end subroutine test_w1_standard_bounded_over_20_transits

  !> The same without the remap correction (remap_drag = .false., the monitor off):
  !> the step of the landed main grows; the bound above can fail.
  subroutine test_w1_standard_grows_without_remap_drag()
    type(config_t) :: cfg
    real(wp) :: ke, ratio, t
    call begin_test('w1_standard_grows_without_remap_drag')
    cfg = w1_scene('random', 5, .false.)
    cfg%remap_drag = .false.
    cfg%growth_limit = 0.0_wp
    call run(cfg, ke, ratio, t)
    call check(ke > GROWS, 'kinetic energy grows far beyond the physical level')
  end subroutine test_w1_standard_grows_without_remap_drag

  !> The MLS pair (doc/theory.md 3.6) on the uniform scatter of inputs/w1.nml (seed 1),
  !> 20 transits at cfl 0.5.
  subroutine test_w1_pair_uniform_scatter_bounded_over_20_transits()
    call begin_test('w1_pair_uniform_scatter_bounded_over_20_transits')
    call check_bounded(w1_scene('uniform', 1, .true.), PAIR_KE, PAIR_RATIO)
  end subroutine test_w1_pair_uniform_scatter_bounded_over_20_transits

  !> The 2D column of inputs/w1_2d.nml with Standard MPM over 20 transits at cfl 0.5.
  subroutine test_w1_2d_standard_bounded_over_20_transits()
    call begin_test('w1_2d_standard_bounded_over_20_transits')
    call check_bounded(w1_scene('uniform', 1, .false., dims=2), STD2_KE, STD2_RATIO)
  end subroutine test_w1_2d_standard_bounded_over_20_transits

  !> W3 with quadratic B-splines over 100 transits: ends without a monitor stop.
  subroutine test_w3_quadratic_runs_100_transits()
    type(config_t) :: cfg
    real(wp) :: ke, ratio, t
    call begin_test('w3_quadratic_runs_100_transits')
    cfg = w1_scene('uniform', 1, .false.)
    cfg%materials(1)%conductivity = 1.0e-4_wp
    cfg%materials(2)%bulk_modulus = KF3
    cfg%kernel = 'quadratic'
    cfg%t_end = W3_TRANSITS
    call run(cfg, ke, ratio, t)
    call check(t >= W3_TRANSITS*(1.0_wp - 1.0e-12_wp), 'ran 100 transits (no monitor stop)')
    call check(ratio <= W3_RATIO, 'energy / (work done + initial energy) at most 1')
  end subroutine test_w3_quadratic_runs_100_transits

  !> The same without the remap correction: the bounds above can fail.
  subroutine test_w1_2d_standard_grows_without_remap_drag()
    type(config_t) :: cfg
    real(wp) :: ke, ratio, t
    call begin_test('w1_2d_standard_grows_without_remap_drag')
    cfg = w1_scene('uniform', 1, .false., dims=2)
    cfg%remap_drag = .false.
    cfg%growth_limit = 0.0_wp
    call run(cfg, ke, ratio, t)
    call check(ke > GROWS, 'kinetic energy grows far beyond the physical level')
  end subroutine test_w1_2d_standard_grows_without_remap_drag

end program test_long_run
