!> Checkpoint and restart: a run continued from a checkpoint ends exactly where the
!> same run without a break ends, on the same ranks and (to the rank invariance of the
!> solver) on fewer ranks; a bad checkpoint is refused.
program test_restart
  use mpi_f08, only: MPI_COMM_WORLD, MPI_COMM_SELF, MPI_Comm_size, MPI_Barrier
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, region_cfg_t, material_cfg_t, bc_fixed, bc_roller, fbc_drained
  use dpmpm_test_scenes, only: grid_scene
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests, test_dir
  implicit none
  character(len=:), allocatable :: dir   !< out/test_restart_np<ranks>
  integer :: rank, nranks
  !> &run sort_every of the scene (0: the points are never sorted)
  integer :: sort_interval = 0
  !> the scene is the seepage strip of inflow_scene (fluid points enter at x = 0)
  logical :: inflow = .false.
  !> steps of the run in one go (the checkpoint at half of them)
  integer :: nsteps = 40
  call start_tests(rank)
  dir = test_dir('test_restart')
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  call test_restart_continues_the_run_exactly()
  call test_restart_with_sorted_points_continues_exactly()
  call test_inflow_points_keep_their_ids()
  call end_tests()

contains

  !> A 2D saturated column (linear elastic skeleton) beside a dry neo-Hookean block,
  !> both on a fixed floor under gravity, quadratic grid functions, MUSL, implicit drag,
  !> points scattered in their cells: both point sets, the deformation gradient and the
  !> energy balance go through the checkpoint. (The column's side is drained: its water
  !> flows out over the floor.)
  function scene(max_steps) result(cfg)
    integer, intent(in) :: max_steps
    type(config_t) :: cfg
    cfg = grid_scene('restart', [8, 8], [1.0_wp, 1.0_wp], 1.0_wp, cfl=0.4_wp, max_steps=max_steps, &
                     gravity=[0.0_wp, -9.81_wp])
    cfg%kernel = 'quadratic'
    cfg%drag = 'implicit'
    cfg%output_dir = dir
    cfg%sort_every = sort_interval
    allocate (cfg%materials(3), cfg%regions(2), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2650.0_wp, &
                                      youngs_modulus=1.0e6_wp, poisson_ratio=0.3_wp, &
                                      conductivity=1.0e-3_wp)
    cfg%materials(2) = material_cfg_t(id=2, model='fluid', density=1000.0_wp, bulk_modulus=2.0e7_wp)
    cfg%materials(3) = material_cfg_t(id=3, model='neo_hookean', density=2000.0_wp, &
                                      youngs_modulus=5.0e5_wp, poisson_ratio=0.3_wp)
    cfg%regions(1) = region_cfg_t(lo=[0.0_wp, 0.0_wp, 0.0_wp], hi=[0.375_wp, 0.5_wp, 1.0_wp], &
                                  material=1, fluid_material=2, phase='saturated', &
                                  porosity=0.4_wp, placement='random')
    cfg%regions(2)%lo = [0.625_wp, 0.0_wp, 0.0_wp]
    cfg%regions(2)%hi = [1.0_wp, 0.25_wp, 1.0_wp]
    cfg%regions(2)%material = 3
    cfg%regions(2)%placement = 'random'
    cfg%regions(2)%seed = 7
    cfg%bc(1:2) = bc_roller
    cfg%bc(3) = bc_fixed
  end function scene

  !> A saturated strip 0.4 m long and 1.6 m high (4 x 16 cells, linear, n = 0.3,
  !> k = 1 m/s, K_f = 20 MPa, no gravity) with a pore pressure of 5 kPa on its drained face
  !> x = 0 and 0 on x = 0.4 m: the water flows through along x, fluid points enter at
  !> x = 0 and leave at x = 0.4 m, and the face x = 0 spans the ranks that split the
  !> strip along y.
  function inflow_scene(max_steps) result(cfg)
    integer, intent(in) :: max_steps
    type(config_t) :: cfg
    cfg = grid_scene('restart', [4, 16], [0.4_wp, 1.6_wp], 1.0_wp, nmat=2, nreg=1, nload=0, &
                     max_steps=max_steps)
    cfg%drag = 'implicit'
    cfg%output_dir = dir
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2650.0_wp, &
                                      youngs_modulus=1.0e8_wp, poisson_ratio=0.3_wp, conductivity=1.0_wp)
    cfg%materials(2) = material_cfg_t(id=2, model='fluid', density=1000.0_wp, bulk_modulus=2.0e7_wp)
    cfg%regions(1) = region_cfg_t(lo=0.0_wp, hi=[0.4_wp, 1.6_wp, 1.0_wp], material=1, &
                                  fluid_material=2, phase='saturated', porosity=0.3_wp)
    cfg%bc(1:4) = bc_roller
    cfg%fluid_bc(1:2) = fbc_drained
    cfg%pore_pressure(1) = 5.0e3_wp
  end function inflow_scene

  !> Run cfg on comm and return the points of both sets (rank 0 of comm, sorted by id)
  !> with the end time, step, energy balance and the monitor's largest ratio and balance error.
  subroutine run(cfg, comm_self, sx, sv, ss, fx, fv, fs, t, steps, drift, mon, fids)
    type(config_t), intent(in) :: cfg
    logical, intent(in) :: comm_self
    real(wp), allocatable, intent(out) :: sx(:, :), sv(:, :), ss(:, :), fx(:, :), fv(:, :), fs(:, :)
    real(wp), intent(out) :: t, drift, mon(2)
    integer(i8), intent(out) :: steps
    integer(i8), allocatable, intent(out) :: fids(:)       !< the fluid points' ids, sorted
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    if (comm_self) then
      call sim%init(cfg, MPI_COMM_SELF, write_output=.false.)
    else
      call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    end if
    call sim%run()
    call sim%gather_points(ids, sx, sv, ss)
    call sim%gather_points(fids, fx, fv, fs, fluid=.true.)
    t = sim%time
    steps = sim%step
    drift = sim%energy_drift
    mon = [sim%mon%ratio, sim%mon%balance]
    call sim%free()
  end subroutine run

  !> 40 steps in one go; 20 steps with a checkpoint, then 20 more from it: the same
  !> points to the last bit, the same time, energy balance and monitor. From the same
  !> checkpoint on one rank (when the test runs on more): the same to round-off.
  subroutine test_restart_continues_the_run_exactly()
    call begin_test('restart_continues_the_run_exactly')
    sort_interval = 0
    call restart_matches_one_go()
  end subroutine test_restart_continues_the_run_exactly

  !> The same with the points sorted by cell every 7 steps (&run sort_every): the
  !> checkpoint keeps each rank's order, so the restarted run sorts at the same steps
  !> from the same order.
  subroutine test_restart_with_sorted_points_continues_exactly()
    call begin_test('restart_with_sorted_points_continues_exactly')
    sort_interval = 7
    call restart_matches_one_go()
    sort_interval = 0
  end subroutine test_restart_with_sorted_points_continues_exactly

  !> Fluid points that enter at an inflow face keep their ids through a restart and on
  !> fewer ranks: the seepage strip of inflow_scene, 400 steps in one go against 200, a
  !> checkpoint and 200 more (32 points entered, ids 257 to 288 after the 256 of the start,
  !> on 1, 2 and 3 ranks alike). With ids numbered per rank and counted from the largest
  !> id at the restart, as before, the points that entered after a restart on 3 ranks took
  !> other ids than in the run without a break.
  subroutine test_inflow_points_keep_their_ids()
    call begin_test('inflow_points_keep_their_ids')
    inflow = .true.
    nsteps = 400
    call restart_matches_one_go()
    inflow = .false.
    nsteps = 40
  end subroutine test_inflow_points_keep_their_ids

  !> The scene run to step nsteps in one go and to half of it with a checkpoint, then
  !> restarted from it to nsteps: the same points, with the same ids, to the bit.
  subroutine restart_matches_one_go()
    type(config_t) :: cfg
    real(wp), allocatable :: ax(:, :), av(:, :), as(:, :), afx(:, :), afv(:, :), afs(:, :)
    real(wp), allocatable :: bx(:, :), bv(:, :), bs(:, :), bfx(:, :), bfv(:, :), bfs(:, :)
    real(wp) :: ta, tb, da, db, dev, ma(2), mb(2)
    integer(i8) :: na, nb
    integer(i8), allocatable :: aid(:), bid(:)
    logical :: exists, tmp_left
    call run(the_scene(nsteps), .false., ax, av, as, afx, afv, afs, ta, na, da, ma, aid)
    if (rank == 0 .and. inflow) call check(maxval(aid) > 256_i8, 'fluid points entered (ids above 256)')
    cfg = the_scene(nsteps/2)
    cfg%checkpoint_every = nsteps/2
    call run(cfg, .false., bx, bv, bs, bfx, bfv, bfs, tb, nb, db, mb, bid)
    inquire (file=dir//'/restart.ckpt.h5', exist=exists)
    inquire (file=dir//'/restart.ckpt.h5.tmp', exist=tmp_left)
    call check(exists .and. .not. tmp_left, 'the checkpoint is written, no temporary left')
    cfg = the_scene(nsteps)
    cfg%restart = dir//'/restart.ckpt.h5'
    call run(cfg, .false., bx, bv, bs, bfx, bfv, bfs, tb, nb, db, mb, bid)
    if (rank == 0) then
      print '(a,2i5,2es12.4)', '  steps, energy balance (one go, restarted):', na, nb, da, db
      call check(nb == na .and. tb == ta, 'same step count and time')
      call check(size(bx, 2) == size(ax, 2) .and. size(bfx, 2) == size(afx, 2), 'no point lost')
      call check(size(bid) == size(aid), 'the same number of fluid points')
      if (size(bid) == size(aid)) call check(all(bid == aid), 'the same fluid point ids')
      call check(all(bx == ax) .and. all(bv == av) .and. all(bs == as), 'solid points equal')
      call check(all(bfx == afx) .and. all(bfv == afv) .and. all(bfs == afs), 'fluid points equal')
      ! The work of the loads is summed over the ranks; restarted, the sum so far sits on
      ! rank 0, so the balance agrees to round-off rather than to the bit.
      call check(abs(db - da) <= 1.0e-12_wp*abs(da), 'same energy balance')
      ! The monitor goes on from the checkpoint: measured against what the body was given
      ! since t = 0, not since the restart.
      print '(a,4es12.4)', '  monitor ratio and balance (one go, restarted):', ma, mb
      call check(all(abs(mb - ma) <= 1.0e-12_wp*abs(ma)), 'same monitor ratio and balance')
    end if
    if (nranks > 1) then
      if (rank == 0) then
        call run(cfg, .true., bx, bv, bs, bfx, bfv, bfs, tb, nb, db, mb, bid)
        call check(size(bid) == size(aid), 'restart on fewer ranks: the same number of fluid points')
        if (size(bid) == size(aid)) call check(all(bid == aid), 'restart on fewer ranks: the same ids')
        dev = max(maxval(abs(bx - ax)), maxval(abs(bfx - afx)))/maxval(abs(ax)) + &
              max(maxval(abs(bs - as)), maxval(abs(bfs - afs)))/maxval(abs(as))
        print '(a,es11.3)', '  restarted on 1 rank, relative deviation:', dev
        call check(nb == na .and. dev <= 1.0e-10_wp, 'restart on fewer ranks: same fields')
      end if
      call MPI_Barrier(MPI_COMM_WORLD)
    end if
  end subroutine restart_matches_one_go

  !> The scene of the test: the column and block, or the seepage strip (inflow).
  function the_scene(max_steps) result(cfg)
    integer, intent(in) :: max_steps
    type(config_t) :: cfg
    if (inflow) then
      cfg = inflow_scene(max_steps)
    else
      cfg = scene(max_steps)
    end if
  end function the_scene

end program test_restart
