!> The equilibrium phase (&run equilibrium_time): gravity ramped over its first half with
!> local damping brings a dry column from zero stress to rest in its geostatic state; the
!> velocities are zeroed at its end and the column stays at rest without damping after it.
program test_equilibrium
  use dpmpm_mpi_start, only: start_mpi
  use mpi_f08, only: MPI_Finalize, MPI_COMM_WORLD, MPI_Comm_rank
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, bc_fixed
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, finish_tests, am_root
  implicit none
  integer :: status, rank
  call start_mpi()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  am_root = rank == 0
  call test_dry_column_settles_under_ramped_gravity()
  status = finish_tests(MPI_COMM_WORLD)
  call MPI_Finalize()
  if (status /= 0) stop 1, quiet = .true.

contains

  !> A 5 m dry column (50 cells, linear, 2 points per cell, E = 10 MPa, rho = 2000
  !> kg/m^3, one period of its first mode 0.28 s) on a fixed base, from zero stress;
  !> equilibrium phase of 4 s with damping alpha, then 0.5 s without.
  function column(alpha) result(cfg)
    real(wp), intent(in) :: alpha
    type(config_t) :: cfg
    cfg%name = 'equilibrium'
    cfg%ndim = 1
    cfg%ncells = [50, 1, 1]
    cfg%length = [5.0_wp, 1.0_wp, 1.0_wp]
    cfg%t_end = 4.5_wp
    cfg%gravity = [-9.81_wp, 0.0_wp, 0.0_wp]
    cfg%equilibrium_time = 4.0_wp
    cfg%equilibrium_damping = alpha
    allocate (cfg%materials(1), cfg%regions(1), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, density=2000.0_wp, youngs_modulus=1.0e7_wp, &
                                      poisson_ratio=0.0_wp)
    cfg%regions(1)%lo = 0.0_wp
    cfg%regions(1)%hi = [5.0_wp, 1.0_wp, 1.0_wp]
    cfg%regions(1)%ppc = 2
    cfg%bc(1) = bc_fixed
  end function column

  !> Largest speed at the end, and the median and largest |sigma - sigma_geostatic| over
  !> rho g H at the points, on rank 0.
  subroutine run(cfg, vmax, emed, emax)
    type(config_t), intent(in) :: cfg
    real(wp), intent(out) :: vmax, emed, emax
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), st(:, :), e(:)
    integer :: i, j, n
    real(wp) :: t
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    call sim%gather_points(ids, x, v, st)
    call sim%free()
    vmax = 0.0_wp; emed = 0.0_wp; emax = 0.0_wp
    if (.not. am_root) return
    vmax = maxval(abs(v))
    n = size(x, 2)
    e = abs(st(1, :) + 2000.0_wp*9.81_wp*(5.0_wp - x(1, :)))/(2000.0_wp*9.81_wp*5.0_wp)
    emax = maxval(e)
    do i = 2, n
      t = e(i)
      do j = i - 1, 1, -1
        if (e(j) <= t) exit
        e(j + 1) = e(j)
      end do
      e(j + 1) = t
    end do
    emed = e((n + 1)/2)
  end subroutine run

  !> Measured (doc/verification.md, "Equilibrium phase"): with alpha = 0.8 the largest
  !> speed 0.5 s after the phase is 3.1e-4 m/s (1 rank) and 2.6e-4 m/s (2 ranks: the sign
  !> of the damping force follows round-off where a velocity is near zero), the stress
  !> within 5.4e-3 rho g H (median; 4.1e-2 at points near the top that crossed a cell face
  !> back and forth, the cell-crossing error of linear grid functions); without damping
  !> (the slow ramp alone) 4.3e-3 m/s, 4.8e-3 and 1.5e-2. Bounds: measured + 50 %; the
  !> undamped control must stay above 5 times the damped speed (measured 14 and 17).
  subroutine test_dry_column_settles_under_ramped_gravity()
    real(wp) :: v, emed, emax, v0, emed0, emax0
    call begin_test('dry_column_settles_under_ramped_gravity')
    call run(column(0.8_wp), v, emed, emax)
    call run(column(0.0_wp), v0, emed0, emax0)
    if (am_root) then
      print '(a,3es11.3)', '  damped: speed, median and largest stress error:', v, emed, emax
      print '(a,3es11.3)', '  undamped:                                       ', v0, emed0, emax0
      call check(v <= 4.6e-4_wp, 'at rest after the phase')
      call check(emed <= 8.1e-3_wp .and. emax <= 6.1e-2_wp, 'geostatic stress')
      call check(v0 >= 5.0_wp*v, 'without damping the column still moves (control)')
    end if
  end subroutine test_dry_column_settles_under_ramped_gravity

end program test_equilibrium
