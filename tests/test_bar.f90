!> Axial vibration of an elastic bar (1D, fixed at x = 0, free at x = L) in its
!> first mode, against the analytical solution: the error falls with the cell
!> size, stays below a bound taken from a measured error (doc/verification.md),
!> and the total energy is conserved within a measured bound.
program test_bar
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, material_cfg_t, region_cfg_t, load_cfg_t, bc_fixed
  use dpmpm_test_scenes, only: grid_scene
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, check_close
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  call start_tests()
  call test_bar_error_decreases_with_cell_size()
  call end_tests()

contains

  !> 1D bar of length 1 in a grid of length 1.25 with ncell_bar cells along the bar.
  function bar_config(ncell_bar, kernel) result(cfg)
    integer, intent(in) :: ncell_bar
    character(len=*), intent(in) :: kernel
    type(config_t) :: cfg
    cfg = grid_scene('bar', [ncell_bar*5/4], [1.25_wp])
    cfg%kernel = kernel
    cfg%t_end = 0.4_wp          ! one period of the first mode (omega = 5 pi)
    cfg%cfl = 0.2_wp
    cfg%flip = 1.0_wp
    cfg%scheme = 'musl'
    allocate (cfg%materials(1), cfg%regions(1), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=1.0_wp, &
                                      youngs_modulus=100.0_wp, poisson_ratio=0.0_wp)
    cfg%regions(1)%lo = [0.0_wp, 0.0_wp, 0.0_wp]
    cfg%regions(1)%hi = [1.0_wp, 0.0_wp, 0.0_wp]
    cfg%regions(1)%ppc = 2
    cfg%bc(1) = bc_fixed
    cfg%benchmark = 'axial_bar'
    cfg%amplitude = 0.01_wp
    cfg%diag_every = 1
  end function bar_config

  subroutine run_bar(ncell_bar, kernel, err_u, err_v, energy_drift)
    integer, intent(in) :: ncell_bar
    character(len=*), intent(in) :: kernel
    real(wp), intent(out) :: err_u, err_v, energy_drift
    type(simulation_t) :: sim
    call sim%init(bar_config(ncell_bar, kernel), MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    err_v = maxval(sim%err_hist(2, 1:sim%nerr))
    err_u = maxval(sim%err_hist(3, 1:sim%nerr))
    energy_drift = sim%energy_drift
    print '(a,a,i4,3(a,es11.4))', kernel, ' cells ', ncell_bar, ' max err_u ', err_u, &
      ' max err_v ', err_v, ' drift ', energy_drift
    call sim%free()
  end subroutine run_bar

  ! Bounds: the errors measured at 16 and 32 cells along the bar (doc/verification.md,
  ! "Axial vibration of a bar") plus a 15 % margin; they hold on 1 and 2 ranks.
  subroutine test_bar_error_decreases_with_cell_size()
    real(wp) :: eu1, ev1, eu2, ev2, de1, de2
    call begin_test('bar_linear_error_decreases_at_second_order')
    call run_bar(16, 'linear', eu1, ev1, de1)
    call run_bar(32, 'linear', eu2, ev2, de2)
    call check(eu1 < 1.15_wp*5.732e-3_wp, 'linear, 16 cells: displacement error below measured bound')
    call check(eu2 < 1.15_wp*1.437e-3_wp, 'linear, 32 cells: displacement error below measured bound')
    call check(eu1/eu2 > 3.4_wp, 'linear: halving h divides the displacement error by more than 3.4')
    call check(ev2 < ev1, 'linear: velocity error falls with h')
    call begin_test('bar_linear_energy_conserved')
    call check(de1 < 1.15_wp*9.898e-3_wp, 'linear, 16 cells: energy change below measured bound')
    call check(de2 < 1.15_wp*5.006e-3_wp, 'linear, 32 cells: energy change below measured bound')
    call begin_test('bar_quadratic_error_decreases_at_second_order')
    call run_bar(16, 'quadratic', eu1, ev1, de1)
    call run_bar(32, 'quadratic', eu2, ev2, de2)
    call check(eu1 < 1.15_wp*1.102e-2_wp, 'quadratic, 16 cells: displacement error below measured bound')
    call check(eu2 < 1.15_wp*2.776e-3_wp, 'quadratic, 32 cells: displacement error below measured bound')
    call check(eu1/eu2 > 3.4_wp, 'quadratic: halving h divides the displacement error by more than 3.4')
    call begin_test('bar_quadratic_energy_conserved')
    call check(de1 < 1.15_wp*9.886e-3_wp, 'quadratic, 16 cells: energy change below measured bound')
    call check(de2 < 1.15_wp*5.004e-3_wp, 'quadratic, 32 cells: energy change below measured bound')
  end subroutine test_bar_error_decreases_with_cell_size

end program test_bar
