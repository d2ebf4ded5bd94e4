!> A body loaded on a face and cut by a plane that no point couples across
!> (dpmpm_load_path): the search for the uncovered edges, and the check of a run on
!> columns with and without an empty cell layer.
program test_load_path
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, load_cfg_t, bc_fixed
  use dpmpm_kernels, only: kernel_linear, kernel_quadratic, kernel_cubic
  use dpmpm_load_path, only: uncovered_run, first_node
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  call start_tests()
  call test_uncovered_run_from_either_end()
  call test_covered_span_has_no_run()
  call test_first_node_of_each_kernel()
  call test_empty_cell_cuts_linear_column()
  call test_quadratic_bridges_one_empty_cell()
  call test_unbroken_column_is_not_cut()
  call test_empty_row_cuts_2d_block()
  call test_hole_does_not_cut_2d_block()
  call end_tests()

contains

  subroutine test_uncovered_run_from_either_end()
    integer(i8), parameter :: cover(9) = [0_i8, 2_i8, 3_i8, 0_i8, 0_i8, 4_i8, 0_i8, 1_i8, 0_i8]
    integer :: run(2)
    call begin_test('uncovered_run_from_either_end')
    run = uncovered_run(cover, from_high=.false.)
    call check_equal_int(run(1), 4, 'from the low end: first uncovered edge')
    call check_equal_int(run(2), 5, 'from the low end: last uncovered edge')
    run = uncovered_run(cover, from_high=.true.)
    call check_equal_int(run(1), 7, 'from the high end: first uncovered edge')
    call check_equal_int(run(2), 7, 'from the high end: last uncovered edge')
  end subroutine test_uncovered_run_from_either_end

  subroutine test_covered_span_has_no_run()
    integer(i8), parameter :: cover(6) = [0_i8, 0_i8, 1_i8, 5_i8, 1_i8, 0_i8]
    integer(i8), parameter :: none(4) = 0_i8
    integer :: run(2)
    call begin_test('covered_span_has_no_run')
    run = uncovered_run(cover, from_high=.false.)
    call check(run(1) > run(2), 'no run from the low end (empty ends are not cuts)')
    run = uncovered_run(cover, from_high=.true.)
    call check(run(1) > run(2), 'no run from the high end')
    run = uncovered_run(none, from_high=.false.)
    call check(run(1) > run(2), 'nothing covered: no run')
  end subroutine test_covered_span_has_no_run

  !> The first node reached by a point, against the supports of the B-splines
  !> (linear 1 cell, quadratic 1.5, cubic 2 cells each side).
  subroutine test_first_node_of_each_kernel()
    call begin_test('first_node_of_each_kernel')
    call check_equal_int(first_node(kernel_linear, 4.3_wp), 4, 'linear')
    call check_equal_int(first_node(kernel_quadratic, 4.3_wp), 3, 'quadratic, lower half of the cell')
    call check_equal_int(first_node(kernel_quadratic, 4.7_wp), 4, 'quadratic, upper half')
    call check_equal_int(first_node(kernel_cubic, 4.3_wp), 3, 'cubic')
  end subroutine test_first_node_of_each_kernel

  !> Two steps of a dry elastic body on a grid of ncells cells (one load, regions to add).
  function two_steps(nd, ncells, length, kernel) result(cfg)
    integer, intent(in) :: nd, ncells(3)
    real(wp), intent(in) :: length(3)
    character(len=*), intent(in) :: kernel
    type(config_t) :: cfg
    cfg%name = 'load_path'
    cfg%ndim = nd
    cfg%ncells = ncells
    cfg%length = length
    cfg%t_end = 1.0e-3_wp
    cfg%max_steps = 2
    cfg%kernel = kernel
    allocate (cfg%materials(1), cfg%loads(1))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2000.0_wp, &
                                      youngs_modulus=1.0e7_wp, poisson_ratio=0.0_wp)
  end function two_steps

  !> A dry elastic column of 20 cells (h = 0.1 m), loaded on x- and fixed at x+: one
  !> region, or two with the cell [gap, gap + 0.1] left empty.
  function column(kernel, gap) result(cfg)
    character(len=*), intent(in) :: kernel
    real(wp), intent(in) :: gap
    type(config_t) :: cfg
    cfg = two_steps(1, [20, 1, 1], [2.0_wp, 1.0_wp, 1.0_wp], kernel)
    if (gap > 0.0_wp) then
      allocate (cfg%regions(2))
      cfg%regions(1)%lo = 0.0_wp
      cfg%regions(1)%hi = [gap, 1.0_wp, 1.0_wp]
      cfg%regions(2)%lo = [gap + 0.1_wp, 0.0_wp, 0.0_wp]
      cfg%regions(2)%hi = [2.0_wp, 1.0_wp, 1.0_wp]
    else
      allocate (cfg%regions(1))
      cfg%regions(1)%lo = 0.0_wp
      cfg%regions(1)%hi = [2.0_wp, 1.0_wp, 1.0_wp]
    end if
    cfg%loads(1) = load_cfg_t(face=1, traction=[1.0e3_wp, 0.0_wp, 0.0_wp])
    cfg%bc(2) = bc_fixed
  end function column

  !> cut_time of face f after a short run of cfg.
  real(wp) function cut_time(cfg, f) result(t)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: f
    type(simulation_t) :: sim
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    t = sim%cut_time(f)
    call sim%free()
  end function cut_time

  !> Linear grid functions: the nodes on either side of an empty cell share no point.
  subroutine test_empty_cell_cuts_linear_column()
    call begin_test('empty_cell_cuts_linear_column')
    call check(cut_time(column('linear', 0.8_wp), 1) == 0.0_wp, 'cut found at the start')
  end subroutine test_empty_cell_cuts_linear_column

  !> Quadratic B-splines reach 1.5 cells: points 0.25 cells from the empty cell on
  !> both sides (2 per cell, regular) both reach the two nodes of the empty cell.
  subroutine test_quadratic_bridges_one_empty_cell()
    call begin_test('quadratic_bridges_one_empty_cell')
    call check(cut_time(column('quadratic', 0.8_wp), 1) < 0.0_wp, 'no cut')
  end subroutine test_quadratic_bridges_one_empty_cell

  subroutine test_unbroken_column_is_not_cut()
    call begin_test('unbroken_column_is_not_cut')
    call check(cut_time(column('linear', 0.0_wp), 1) < 0.0_wp, 'no cut')
  end subroutine test_unbroken_column_is_not_cut

  !> A 2D block of 4 x 20 cells loaded on y+ and fixed at y-: the row 1.0 <= y <= 1.1
  !> left empty over the whole width (cut), or all but its first cell (a hole the
  !> points of that cell bridge: no cut).
  function block(bridge) result(cfg)
    logical, intent(in) :: bridge
    type(config_t) :: cfg
    cfg = two_steps(2, [4, 20, 1], [0.4_wp, 2.0_wp, 1.0_wp], 'linear')
    allocate (cfg%regions(merge(3, 2, bridge)))
    cfg%regions(1)%lo = 0.0_wp
    cfg%regions(1)%hi = [0.4_wp, 1.0_wp, 1.0_wp]
    cfg%regions(2)%lo = [0.0_wp, 1.1_wp, 0.0_wp]
    cfg%regions(2)%hi = [0.4_wp, 2.0_wp, 1.0_wp]
    if (bridge) then
      cfg%regions(3)%lo = [0.0_wp, 1.0_wp, 0.0_wp]
      cfg%regions(3)%hi = [0.1_wp, 1.1_wp, 1.0_wp]
    end if
    cfg%loads(1) = load_cfg_t(face=4, traction=[0.0_wp, -1.0e3_wp, 0.0_wp])
    cfg%bc(3) = bc_fixed
  end function block

  subroutine test_empty_row_cuts_2d_block()
    call begin_test('empty_row_cuts_2d_block')
    call check(cut_time(block(.false.), 4) == 0.0_wp, 'cut found at the start')
  end subroutine test_empty_row_cuts_2d_block

  subroutine test_hole_does_not_cut_2d_block()
    call begin_test('hole_does_not_cut_2d_block')
    call check(cut_time(block(.true.), 4) < 0.0_wp, 'no cut')
  end subroutine test_hole_does_not_cut_2d_block

end program test_load_path
