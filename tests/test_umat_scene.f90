!> A full scene with the UMAT wrapper (dpmpm_model_umat) and an example UMAT linked into
!> this program: a column under gravity, released on one side, ends where the same scene
!> with the built-in model ends, to round-off (positions, velocities, stresses of every
!> point, and the energy balance), on 1 and 2 ranks. Built twice (tests/CMakeLists.txt):
!> with src/materials/umat/umat_linear_elastic.f against linear_elastic in 2D (plane strain) and 3D, and
!> with the argument cam_clay, with src/materials/umat/umat_cam_clay.f90 against cam_clay in 2D. The
!> points of the umat keep STRAN, SSE, SPD, SCD and the UMAT's STATEV. Measured
!> differences and bounds: doc/verification.md, "A user's UMAT".
program test_umat_scene
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Allreduce, MPI_IN_PLACE, MPI_MAX
  use dpmpm_kinds, only: wp, i8, mpi_wp
  use dpmpm_config, only: config_t, material_cfg_t, bc_roller, max_props
  use dpmpm_test_scenes, only: grid_scene, released_column
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  real(wp), parameter :: rho = 2000.0_wp, g = 9.81_wp, height = 0.375_wp, k0 = 0.4_wp
  !> Largest difference relative to the largest value of positions, velocities and
  !> stresses: measured up to 7.1e-15 (velocity, 2D on 2 ranks; doc/verification.md);
  !> bound 1e-13 (14x). The energy balance: measured 8.8e-16 apart, bound 1e-13.
  real(wp), parameter :: tol = 1.0e-13_wp
  integer :: rank
  character(len=16) :: arg
  call start_tests(rank)
  call get_command_argument(1, arg)
  if (arg == 'cam_clay') then
    call test_cam_clay_umat_column_matches_cam_clay()
  else
    call test_elastic_umat_column_matches_linear_elastic_in_2d()
    call test_elastic_umat_column_matches_linear_elastic_in_3d()
  end if
  call end_tests()

contains

  !> A column 0.25 m wide and 0.375 m high (E = 1 MPa, nu = 0.3) against a smooth wall on
  !> a rough floor, free on its right side, from sigma_yy = -rho g (H - y) and
  !> sigma_xx = sigma_zz = K0 sigma_yy, for nsteps steps; model 'umat' with PROPS = E, nu
  !> and two STATEV that it leaves alone, or 'linear_elastic'.
  function scene(model, ndim, nsteps) result(cfg)
    character(len=*), intent(in) :: model
    integer, intent(in) :: ndim, nsteps
    type(config_t) :: cfg
    integer, parameter :: cells(3) = [16, 8, 4]
    real(wp), parameter :: lengths(3) = [1.0_wp, 0.5_wp, 0.25_wp]
    real(wp) :: props(max_props)
    cfg = grid_scene('umat_scene', cells(1:ndim), lengths(1:ndim), 1.0_wp, cfl=0.4_wp, &
                     max_steps=nsteps, gravity=[0.0_wp, -g])
    cfg%dims = [1, 0, 1]   ! ranks along y: on 2 ranks the column spans both
    props = 0.0_wp
    props(1:2) = [1.0e6_wp, 0.3_wp]
    allocate (cfg%materials(1), cfg%regions(1), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model=model, density=rho, youngs_modulus=1.0e6_wp, &
                                      poisson_ratio=0.3_wp)
    if (model == 'umat') then
      cfg%materials(1)%umat_props = props
      cfg%materials(1)%umat_nprops = 2
      cfg%materials(1)%umat_nstatev = 2
    end if
    call released_column(cfg, rho, g, height, merge(0.25_wp, 1.0_wp, ndim == 3), k0)
    if (ndim == 3) cfg%bc(5:6) = bc_roller
  end function scene

  !> The 2D column of Modified Cam-Clay (lambda = 0.2, kappa = 0.05, M = 1, e0 = 1.2,
  !> nu = 0.3, p_m = 1 kPa, p_c0 = 20 kPa, above the surface through the initial stress at
  !> the base, so that the side released fails and the rest does not), 'cam_clay' or 'umat'
  !> with those PROPS (its STATEV set at the zero-increment call of the start), at a fixed
  !> step of
  !> 5e-4 s (the built-in model's step follows each point's modulus, the umat's
  !> youngs_modulus = 1 MPa, the stiffest the clay gets here).
  function clay_scene(model, nsteps) result(cfg)
    character(len=*), intent(in) :: model
    integer, intent(in) :: nsteps
    type(config_t) :: cfg
    real(wp) :: props(max_props)
    cfg = scene(model, 2, nsteps)
    cfg%dt = 5.0e-4_wp
    if (model == 'umat') then
      props = 0.0_wp
      props(1:9) = [0.2_wp, 0.05_wp, 1.0_wp, 0.3_wp, 0.0_wp, 1.0e3_wp, 1.2_wp, 2.0e4_wp, 1.0_wp]
      cfg%materials(1)%umat_props = props
      cfg%materials(1)%umat_nprops = 9
    else
      cfg%materials(1) = material_cfg_t(id=1, model=model, density=rho, compression_index=0.2_wp, &
                                        swelling_index=0.05_wp, critical_state_ratio=1.0_wp, &
                                        void_ratio=1.2_wp, poisson_ratio=0.3_wp, &
                                        min_pressure=1.0e3_wp, preconsolidation_pressure=2.0e4_wp)
    end if
  end function clay_scene

  !> Run cfg: the solid points on rank 0 (sorted by id), the energy balance, the state
  !> values per point, and the largest SSE and SPD of a umat's points.
  subroutine run(cfg, sx, sv, ss, drift, nstate, sse, spd)
    type(config_t), intent(in) :: cfg
    real(wp), allocatable, intent(out) :: sx(:, :), sv(:, :), ss(:, :)
    real(wp), intent(out) :: drift, sse, spd
    integer, intent(out) :: nstate
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    integer :: n
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    call sim%gather_points(ids, sx, sv, ss)
    drift = sim%energy_drift
    nstate = sim%phase(1)%pts%nstate
    n = sim%phase(1)%pts%n
    sse = 0.0_wp
    spd = 0.0_wp
    if (nstate >= 9 .and. n > 0) sse = maxval(sim%phase(1)%pts%state(7, 1:n))
    if (nstate >= 9 .and. n > 0) spd = maxval(sim%phase(1)%pts%state(8, 1:n))
    call MPI_Allreduce(MPI_IN_PLACE, sse, 1, mpi_wp(), MPI_MAX, MPI_COMM_WORLD)
    call MPI_Allreduce(MPI_IN_PLACE, spd, 1, mpi_wp(), MPI_MAX, MPI_COMM_WORLD)
    call sim%free()
  end subroutine run

  !> The built-in model's scene a and the umat's b (ndim dimensions): points and energy
  !> balance compared within tol; the umat's points keep 9 values and its STATEV, and their
  !> SSE.
  subroutine compare(a, b, ndim)
    type(config_t), intent(in) :: a, b
    integer, intent(in) :: ndim
    real(wp), allocatable :: ax(:, :), av(:, :), as(:, :), bx(:, :), bv(:, :), bs(:, :)
    real(wp) :: da, db, sse, spd, dx, dv, ds
    integer :: na, nb
    call run(a, ax, av, as, da, na, sse, spd)
    call run(b, bx, bv, bs, db, nb, sse, spd)
    call check(nb == 9 + b%materials(1)%umat_nstatev, 'the umat keeps 9 values and its STATEV')
    call check(sse > 0.0_wp, 'SSE kept')
    call check((spd > 0.0_wp) .eqv. (a%materials(1)%model == 'cam_clay'), &
               'plastic dissipation where the soil is plastic')
    if (rank == 0) then
      call check(size(ax, 2) == size(bx, 2), 'the same points')
      if (size(ax, 2) /= size(bx, 2)) return
      dx = maxval(abs(bx - ax))/maxval(abs(ax))
      dv = maxval(abs(bv - av))/maxval(abs(av))
      ds = maxval(abs(bs - as))/maxval(abs(as))
      print '(a,i0,a,3es10.2,a,es11.3,a,es10.2)', '  ', ndim, 'D: position, velocity, stress', dx, &
        dv, ds, '; energy balance', da, ', difference', abs(db - da)
      call check(dx <= tol .and. dv <= tol .and. ds <= tol, 'the umat column ends where '// &
                 'the linear_elastic one does')
      call check(abs(db - da) <= tol, 'the same energy balance')
    end if
  end subroutine compare

  subroutine test_elastic_umat_column_matches_linear_elastic_in_2d()
    call begin_test('elastic_umat_column_matches_linear_elastic_in_2d')
    call compare(scene('linear_elastic', 2, 300), scene('umat', 2, 300), 2)
  end subroutine test_elastic_umat_column_matches_linear_elastic_in_2d

  subroutine test_elastic_umat_column_matches_linear_elastic_in_3d()
    call begin_test('elastic_umat_column_matches_linear_elastic_in_3d')
    call compare(scene('linear_elastic', 3, 100), scene('umat', 3, 100), 3)
  end subroutine test_elastic_umat_column_matches_linear_elastic_in_3d

  subroutine test_cam_clay_umat_column_matches_cam_clay()
    call begin_test('cam_clay_umat_column_matches_cam_clay')
    call compare(clay_scene('cam_clay', 300), clay_scene('umat', 300), 2)
  end subroutine test_cam_clay_umat_column_matches_cam_clay

end program test_umat_scene
