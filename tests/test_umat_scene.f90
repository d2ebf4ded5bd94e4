!> A full scene with the UMAT wrapper (dpmpm_model_umat) and the linear-elastic example
!> UMAT (umat/umat_linear_elastic.f, linked into this program): a column under gravity,
!> released on one side, in 2D (plane strain) and 3D, ends where the same scene with the
!> built-in linear_elastic ends, to round-off (positions, velocities, stresses of every
!> point, and the energy balance), on 1 and 2 ranks. The points of the umat keep STRAN,
!> SSE, SPD, SCD and the UMAT's STATEV. Measured differences and bounds:
!> doc/verification.md, "A user's UMAT".
program test_umat_scene
  use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_COMM_WORLD, MPI_Comm_rank
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, bc_fixed, bc_roller, max_props
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, finish_tests, am_root
  implicit none
  real(wp), parameter :: rho = 2000.0_wp, g = 9.81_wp, height = 0.375_wp, k0 = 0.4_wp
  !> Largest difference relative to the largest value of positions, velocities and
  !> stresses: measured up to 7.1e-15 (velocity, 2D on 2 ranks; doc/verification.md);
  !> bound 1e-13 (14x). The energy balance: measured 8.8e-16 apart, bound 1e-13.
  real(wp), parameter :: tol = 1.0e-13_wp
  integer :: status, rank
  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  am_root = rank == 0
  call test_elastic_umat_column_matches_linear_elastic_in_2d()
  call test_elastic_umat_column_matches_linear_elastic_in_3d()
  status = finish_tests(MPI_COMM_WORLD)
  call MPI_Finalize()
  if (status /= 0) stop 1, quiet = .true.

contains

  !> A column 0.25 m wide and 0.375 m high (E = 1 MPa, nu = 0.3) against a smooth wall on
  !> a rough floor, free on its right side, from sigma_yy = -rho g (H - y) and
  !> sigma_xx = sigma_zz = K0 sigma_yy, for nsteps steps; model 'umat' with PROPS = E, nu
  !> and two STATEV that it leaves alone, or 'linear_elastic'.
  function scene(model, ndim, nsteps) result(cfg)
    character(len=*), intent(in) :: model
    integer, intent(in) :: ndim, nsteps
    type(config_t) :: cfg
    real(wp) :: syy, props(max_props)
    cfg%name = 'umat_scene'
    cfg%ndim = ndim
    cfg%ncells = [16, 8, merge(4, 1, ndim == 3)]
    cfg%length = [1.0_wp, 0.5_wp, merge(0.25_wp, 1.0_wp, ndim == 3)]
    cfg%t_end = 1.0_wp
    cfg%max_steps = nsteps
    cfg%cfl = 0.4_wp
    cfg%gravity = [0.0_wp, -g, 0.0_wp]
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
    cfg%regions(1)%lo = [0.0_wp, 0.0_wp, 0.0_wp]
    cfg%regions(1)%hi = [0.25_wp, height, merge(0.25_wp, 1.0_wp, ndim == 3)]
    cfg%regions(1)%material = 1
    syy = -rho*g*height
    cfg%regions(1)%stress = [k0*syy, syy, k0*syy, 0.0_wp, 0.0_wp, 0.0_wp]
    cfg%regions(1)%stress_gradient(:, 2) = -[k0*syy, syy, k0*syy, 0.0_wp, 0.0_wp, 0.0_wp]/height
    cfg%bc(1) = bc_roller
    cfg%bc(3) = bc_fixed
    if (ndim == 3) cfg%bc(5:6) = bc_roller
  end function scene

  !> Run cfg: the solid points on rank 0 (sorted by id), the energy balance, the state
  !> values per point, and the largest |SSE| and |STATEV| of this rank's points.
  subroutine run(cfg, sx, sv, ss, drift, nstate, sse, statev)
    type(config_t), intent(in) :: cfg
    real(wp), allocatable, intent(out) :: sx(:, :), sv(:, :), ss(:, :)
    real(wp), intent(out) :: drift, sse, statev
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
    statev = 0.0_wp
    if (nstate >= 11 .and. n > 0) then
      sse = maxval(sim%phase(1)%pts%state(7, 1:n))
      statev = maxval(abs(sim%phase(1)%pts%state(10:11, 1:n)))
    end if
    call sim%free()
  end subroutine run

  !> The column with 'umat' and with 'linear_elastic'.
  subroutine compare(ndim, nsteps)
    integer, intent(in) :: ndim, nsteps
    real(wp), allocatable :: ax(:, :), av(:, :), as(:, :), bx(:, :), bv(:, :), bs(:, :)
    real(wp) :: da, db, sse, statev, dx, dv, ds
    integer :: na, nb
    call run(scene('linear_elastic', ndim, nsteps), ax, av, as, da, na, sse, statev)
    call run(scene('umat', ndim, nsteps), bx, bv, bs, db, nb, sse, statev)
    call check(na == 0 .and. nb == 11, 'no state for linear_elastic; 9 + 2 for the umat')
    call check(sse > 0.0_wp .and. statev == 0.0_wp, 'SSE kept, the STATEV left alone')
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
    call compare(2, 300)
  end subroutine test_elastic_umat_column_matches_linear_elastic_in_2d

  subroutine test_elastic_umat_column_matches_linear_elastic_in_3d()
    call begin_test('elastic_umat_column_matches_linear_elastic_in_3d')
    call compare(3, 100)
  end subroutine test_elastic_umat_column_matches_linear_elastic_in_3d

end program test_umat_scene
