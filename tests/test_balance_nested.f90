!> The column collapse of inputs/c1_a2.nml (its path is the argument), shortened to the
!> first 0.12 s of flow, on 4 ranks with &grid balance = 'nested' (split again every 20
!> steps) and with balance = 'cells': the same points by id, positions, velocities and
!> stresses that agree to round-off (the sums over the nodes run in another order; the
!> bound and the measured difference: doc/parallel.md, "Nested cuts"), and a busiest rank
!> that holds fewer points.
program test_balance_nested
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER, MPI_MAX
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t
  use dpmpm_input, only: read_input
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_test_compare, only: reldiff
  implicit none
  integer :: rank
  character(len=512) :: path
  call start_tests(rank)
  call get_command_argument(1, path)
  call test_nested_split_runs_the_column_as_the_even_one()
  call end_tests()

contains

  !> Run the column with the given balance; the points gathered on rank 0 (by id), the
  !> steps, and the busiest rank's points at the start and at the end.
  subroutine run_with(balance, ids, x, v, s, steps, nmax)
    character(len=*), intent(in) :: balance
    integer(i8), allocatable, intent(out) :: ids(:)
    real(wp), allocatable, intent(out) :: x(:, :), v(:, :), s(:, :)
    integer(i8), intent(out) :: steps
    integer, intent(out) :: nmax(2)
    type(config_t) :: cfg
    type(simulation_t) :: sim
    integer :: st
    call read_input(trim(path), MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, 0, 'the column input reads')
    cfg%t_end = 0.12_wp
    cfg%balance = balance
    cfg%balance_every = 20
    cfg%balance_tolerance = 0.05_wp
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    nmax(1) = sim%phase(1)%pts%n
    call sim%run()
    nmax(2) = sim%phase(1)%pts%n
    call MPI_Allreduce(MPI_IN_PLACE, nmax, 2, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD)
    call sim%gather_points(ids, x, v, s)
    steps = sim%step
    call sim%free()
  end subroutine run_with

  subroutine test_nested_split_runs_the_column_as_the_even_one()
    integer(i8), allocatable :: ida(:), idb(:)
    real(wp), allocatable :: xa(:, :), va(:, :), sa(:, :), xb(:, :), vb(:, :), sb(:, :)
    integer(i8) :: stepa, stepb
    integer :: na(2), nb(2)
    real(wp) :: dx, dv, ds
    call begin_test('nested_split_runs_the_column_as_the_even_one')
    call run_with('cells', ida, xa, va, sa, stepa, na)
    call run_with('nested', idb, xb, vb, sb, stepb, nb)
    if (rank /= 0) return
    call check(size(idb) == size(ida), 'the same number of points')
    if (size(idb) /= size(ida)) return
    call check(all(idb == ida), 'the same ids')
    call check(stepb == stepa, 'the same number of steps')
    ! positions relative to the grid's origin (0), velocities and stresses, normwise
    dx = reldiff(xb, xa)
    dv = reldiff(vb, va)
    ds = reldiff(sb, sa)
    print '(a,3es10.3)', '  relative difference, positions, velocities, stresses: ', dx, dv, ds
    print '(a,2i7,a,2i7,a,i0,a,i0)', '  busiest rank, start and end: cells', na, ', nested', nb, &
      '; points ', size(ida), ', steps ', stepa
    call check(max(dx, dv, ds) <= 1.0e-11_wp, 'positions, velocities and stresses agree to 1e-11')
    call check(nb(1) < na(1) .and. nb(2) < na(2), 'the busiest rank holds fewer points')
  end subroutine test_nested_split_runs_the_column_as_the_even_one

end program test_balance_nested
