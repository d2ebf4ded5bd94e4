!> The check of the state after each step (check_state, doc/theory.md "Invalid state"):
!> the saturated column of dpmpm_test_scenes, set up and then damaged at one point of
!> rank 0; the check must stop the run (exit code 4) on every rank, and must pass the
!> undamaged state. The damage is written into the fields directly, so that no
!> arithmetic on it runs before the check (the debug build traps invalid operations).
!> A non-finite stress carried into a step (as a non-finite load gives it) makes the
!> positions non-finite within the step: the check before the migration must stop the run
!> with the monitor's exit code on every rank count, not migration (which loses such points).
program test_state_check
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, region_cfg_t, material_cfg_t, bc_fixed
  use dpmpm_simulation, only: simulation_t
  use dpmpm_state, only: exit_monitor
  use dpmpm_energy, only: check_state
  use dpmpm_test_scenes, only: grid_scene, column_scene
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer :: rank
  call start_tests(rank)
  call test_undamaged_state_passes()
  call test_negative_volume_stops_the_run()
  call test_nonfinite_stress_stops_the_run()
  call test_nonfinite_pore_pressure_stops_the_run()
  call test_nonfinite_stress_stops_the_step_before_migration()
  call end_tests()

contains

  !> The column set up, its state checked with the given damage applied first on rank 0
  !> (0 none, 1 a solid point's volume -1, 2 a solid point's stress NaN, 3 a fluid
  !> point's pore pressure NaN); the exit code the check leaves.
  integer function code_after(damage) result(code)
    integer, intent(in) :: damage
    type(simulation_t) :: sim
    real(wp) :: nan
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    call sim%init(column_scene(20, 1.0e-5_wp, 3.0e6_wp, 1.0_wp, 'implicit'), MPI_COMM_WORLD, &
                  write_output=.false.)
    call check(sim%exit_code == 0, 'the column is set up')
    if (rank == 0) then
      associate (s => sim%phase(1)%pts, f => sim%phase(2)%pts)
        call check(s%n > 0 .and. f%n > 0, 'rank 0 holds points of both sets')
        select case (damage)
        case (1)
          s%vol(s%n) = -1.0_wp
        case (2)
          s%stress(2, 1) = nan
        case (3)
          f%pressure(f%n) = nan
        end select
      end associate
    end if
    call check_state(sim)
    code = sim%exit_code
    call sim%free()
  end function code_after

  subroutine test_undamaged_state_passes()
    call begin_test('undamaged_state_passes')
    call check(code_after(0) == 0, 'exit code 0')
  end subroutine test_undamaged_state_passes

  subroutine test_negative_volume_stops_the_run()
    call begin_test('negative_volume_stops_the_run')
    call check(code_after(1) == exit_monitor, 'exit code of the monitor on every rank')
  end subroutine test_negative_volume_stops_the_run

  subroutine test_nonfinite_stress_stops_the_run()
    call begin_test('nonfinite_stress_stops_the_run')
    call check(code_after(2) == exit_monitor, 'exit code of the monitor on every rank')
  end subroutine test_nonfinite_stress_stops_the_run

  subroutine test_nonfinite_pore_pressure_stops_the_run()
    call begin_test('nonfinite_pore_pressure_stops_the_run')
    call check(code_after(3) == exit_monitor, 'exit code of the monitor on every rank')
  end subroutine test_nonfinite_pore_pressure_stops_the_run

  !> A block of soil on a fixed floor over the two halves of the grid (one per rank on two).
  function block_scene() result(cfg)
    type(config_t) :: cfg
    cfg = grid_scene('block', [8, 8], [1.0_wp, 1.0_wp], 1.0_wp, nmat=1, nreg=1, nload=0, &
                     max_steps=3, gravity=[0.0_wp, -9.81_wp])
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=1000.0_wp, &
                                      youngs_modulus=1.0e6_wp, poisson_ratio=0.3_wp)
    cfg%regions(1) = region_cfg_t(lo=[0.125_wp, 0.0_wp, 0.0_wp], hi=[0.875_wp, 0.5_wp, 1.0_wp], &
                                  material=1)
    cfg%bc(3) = bc_fixed
  end function block_scene

  subroutine test_nonfinite_stress_stops_the_step_before_migration()
    type(simulation_t) :: sim
    call begin_test('nonfinite_stress_stops_the_step_before_migration')
    call sim%init(block_scene(), MPI_COMM_WORLD, write_output=.false.)
    call check(sim%exit_code == 0, 'the block is set up')
    if (rank == 0) then
      call check(sim%phase(1)%pts%n > 0, 'rank 0 holds points')
      sim%phase(1)%pts%stress(2, 1) = ieee_value(1.0_wp, ieee_quiet_nan)
    end if
    call sim%run()
    call check(sim%exit_code == exit_monitor, 'exit code of the monitor on every rank')
    call check(sim%step == 1, 'stopped in the first step')
    call sim%free()
  end subroutine test_nonfinite_stress_stops_the_step_before_migration

end program test_state_check
