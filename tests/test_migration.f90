!> Point migration tests on 1, 2 or 4 ranks: after random moves of up to 0.9
!> cells per axis, migrate must keep every point exactly once (count, mass,
!> momentum, the set of ids, the data of each point) and leave each point on the
!> rank owning its cell. Points pushed out of the grid, or further than one
!> neighbouring rank, must be kept and counted in nlost. The same on nested cuts
!> (decomp_recut_nested), and balance_nested: every point on its owner, none lost or doubled.
program test_migration
  use mpi_f08, only: MPI_COMM_WORLD, MPI_COMM_SELF, MPI_Comm_size, MPI_Allreduce, MPI_Gather, &
                     MPI_Gatherv, MPI_IN_PLACE, MPI_SUM, MPI_MAX, MPI_MIN, MPI_INTEGER, &
                     MPI_DOUBLE_PRECISION, MPI_INTEGER8
  use dpmpm_kinds, only: wp, i8
  use dpmpm_decomp, only: decomp_t, split_extent, balanced_cuts
  use dpmpm_particles, only: particle_set_t
  use dpmpm_migrate, only: migrate, check_owned, balance_by_points, balance_nested
  use dpmpm_cell_order, only: cell_order, sort_by_cell
  use dpmpm_grid, only: grid_t, cell_of, axis_cells_of
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use, intrinsic :: ieee_exceptions, only: ieee_get_halting_mode, ieee_set_halting_mode, ieee_invalid, &
                                           ieee_set_flag
  use dpmpm_test_layouts, only: layouts_for, nested_test_cuts
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int, am_root
  use dpmpm_test_sort, only: ascending_order
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none

  !> Grid used by every test: different origin and cell size per axis, odd cell counts.
  real(wp), parameter :: origin(3) = [-0.3_wp, 1.1_wp, 0.7_wp]
  real(wp), parameter :: h(3) = [0.25_wp, 0.5_wp, 0.2_wp]
  integer, parameter :: ncells(3) = [13, 7, 9]

  !> Park-Miller generator state, one stream per rank.
  integer(i8) :: seed = 1_i8
  integer :: nranks, rank

  call start_tests(rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  call test_cell_of()
  call test_axis_cells_match_cell_of()
  call test_all_inside_agrees_with_inside()
  call test_owner_coord_matches_split()
  call test_balanced_cuts_share_the_weight()
  call test_balance_by_points_spreads_a_corner()
  call test_random_moves_1d()
  call test_random_moves_2d()
  call test_random_moves_3d()
  call test_random_moves_nested_2d()
  call test_random_moves_nested_3d()
  call test_point_jumping_past_nested_neighbours_is_counted()
  call test_balance_nested_spreads_a_wedge()
  call test_point_below_grid_is_kept()
  call test_point_above_grid_is_kept()
  call test_point_jumping_past_neighbour_is_counted()
  call test_sort_by_cell_orders_cells_then_ids()
  call end_tests()

contains

  !> sort_by_cell puts the points in the order of their cells (first axis fastest) and,
  !> within a cell, of their ids; every field goes along with its point; the order
  !> does not depend on the order before (the same points reversed sort the same).
  subroutine test_sort_by_cell_orders_cells_then_ids()
    type(decomp_t) :: dec
    type(particle_set_t) :: a, b
    integer, allocatable :: order(:), rev(:)
    integer :: k, c(3), key, prev, n
    logical :: sorted, carried
    call begin_test('sort_by_cell_orders_cells_then_ids')
    call dec%init(MPI_COMM_SELF, 2, ncells, 1, [1, 1, 1])
    call make_points(dec, a, 400)
    ! Several points share each cell: ids interleave across cells.
    n = a%n
    call sort_by_cell(a, origin, h, dec%clo, dec%chi)
    call check(a%n == n, 'no point lost or added')
    sorted = .true.
    prev = -1
    do k = 1, a%n
      c = cell_of(origin, h, a%x(:, k), 2)
      key = c(1) + ncells(1)*c(2)
      if (k > 1) then
        if (key < prev) sorted = .false.
        if (key == prev .and. a%id(k) <= a%id(k - 1)) sorted = .false.
      end if
      prev = key
    end do
    carried = all(point_intact(a))
    call check(sorted, 'cells in order, ids in order within a cell')
    call check(carried, 'every field goes with its point')
    ! The same points in reverse order sort to the same order.
    call make_points(dec, b, 400)
    rev = [(b%n + 1 - k, k=1, b%n)]
    call b%permute(rev)
    order = cell_order(b, origin, h, dec%clo, dec%chi)
    call check(all(b%id(order) == a%id(1:a%n)), 'the order does not depend on the order before')
  end subroutine test_sort_by_cell_orders_cells_then_ids

  subroutine test_cell_of()
    integer :: c(3)
    call begin_test('cell_of')
    c = cell_of(origin, h, [-0.3_wp + 2.5_wp*0.25_wp, 1.1_wp - 0.1_wp, 99.0_wp], 2)
    call check(all(c == [2, -1, 0]), 'cells 2, -1 and 0 on the unused axis')
    c = cell_of(origin, h, [origin(1), origin(2), origin(3)], 3)
    call check(all(c == 0), 'the origin lies in cell 0')
    c = cell_of(origin, h, [1.0e300_wp, -1.0e300_wp, 0.7_wp + 0.2_wp*8.5_wp], 3)
    call check(c(1) > ncells(1) .and. c(2) < 0 .and. c(3) == 8, 'far positions clamp, no overflow')
  end subroutine test_cell_of

  !> axis_cells_of, the binning of a migration sweep, gives floor((x - origin) / h), as
  !> cell_of does, along its axis for 64 positions (long enough for the loop's vector path): inside, on the
  !> faces of cells, below the origin, far away (clamped) and NaN (the lowest clamp).
  subroutine test_axis_cells_match_cell_of()
    real(wp) :: x(2, 64)
    integer :: c(64), k, want(3), nbad
    logical :: halt
    call begin_test('axis_cells_match_cell_of')
    ! (a comparison with NaN raises the invalid flag, which the debug build traps)
    call ieee_get_halting_mode(ieee_invalid, halt)
    call ieee_set_halting_mode(ieee_invalid, .false.)
    do k = 1, 64
      x(1, k) = 0.0_wp
      x(2, k) = origin(2) + h(2)*real(k - 20, wp)*0.37_wp
    end do
    ! on a cell face, just below one, and far away
    x(2, 7) = origin(2) + 3.0_wp*h(2)
    x(2, 8) = origin(2) + 3.0_wp*h(2) - 1.0e-12_wp
    x(2, 11) = origin(2) - 2.0_wp*h(2)
    x(2, 30) = 1.0e300_wp
    x(2, 31) = -1.0e300_wp
    x(2, 40:64:9) = ieee_value(1.0_wp, ieee_quiet_nan)
    call axis_cells_of(origin, h, x, 64, 2, c)
    nbad = 0
    do k = 1, 64
      if (abs(x(2, k)) < 1.0e6_wp) then
        want(1) = floor((x(2, k) - origin(2))/h(2))
        if (c(k) /= want(1)) nbad = nbad + 1
      end if
      want = cell_of(origin, h, [0.0_wp, x(2, k), 0.0_wp], 2)
      if (c(k) /= want(2)) nbad = nbad + 1
    end do
    call check_equal_int(nbad, 0, 'cells along the axis: floor of the position in cells, as cell_of')
    call check(all(c([7, 8, 11]) == [3, 2, -2]), 'a face belongs to the cell above it')
    call check(c(30) > ncells(2) .and. c(31) < 0 .and. all(c(40:64:9) == c(31)), &
               'far positions clamp; NaN takes the lowest clamp')
    call ieee_set_flag(ieee_invalid, .false.)
    call ieee_set_halting_mode(ieee_invalid, halt)
  end subroutine test_axis_cells_match_cell_of

  !> grid_all_inside, the step's one pass over a set, agrees with grid_inside of each
  !> point in 1D, 2D and 3D: 70 points inside (long enough for the loop's vector path),
  !> then one of them on the lower face (inside), on the upper face or just below the
  !> lower one (outside), along each axis in turn.
  subroutine test_all_inside_agrees_with_inside()
    type(grid_t) :: g
    real(wp), allocatable :: x(:, :)
    integer :: nd, d, k, trial, nbad
    real(wp) :: hi
    call begin_test('all_inside_agrees_with_inside')
    nbad = 0
    do nd = 1, 3
      g%ndim = nd
      g%ncells = 1
      g%ncells(1:nd) = ncells(1:nd)
      g%origin = 0.0_wp
      g%origin(1:nd) = origin(1:nd)
      g%h = 1.0_wp
      g%h(1:nd) = h(1:nd)
      allocate (x(nd, 70))
      do trial = 0, 3*nd
        do k = 1, 70
          do d = 1, nd
            x(d, k) = origin(d) + h(d)*ncells(d)*real(mod(17*k + 5*d, 70), wp)/70.0_wp
          end do
        end do
        if (trial > 0) then
          d = (trial - 1)/3 + 1
          hi = g%origin(d) + g%h(d)*g%ncells(d)
          select case (mod(trial - 1, 3))
          case (0)
            x(d, 41) = g%origin(d)
          case (1)
            x(d, 41) = hi
          case default
            x(d, 41) = g%origin(d) - 1.0e-12_wp
          end select
        end if
        if (g%all_inside(x, 70) .neqv. all([(g%inside(x(:, k)), k=1, 70)])) nbad = nbad + 1
        if (trial > 0 .and. mod(trial - 1, 3) > 0 .and. g%all_inside(x, 70)) nbad = nbad + 1
        ! only the first 40 points: the moved one is not looked at
        if (.not. g%all_inside(x, 40)) nbad = nbad + 1
      end do
      deallocate (x)
    end do
    call check_equal_int(nbad, 0, 'all_inside as inside of each point; a face point above, outside')
  end subroutine test_all_inside_agrees_with_inside

  !> owner_coord (used to find a cell's rank) agrees with the split of the cells
  !> for many cell and rank counts; cells outside the grid map to the end ranks.
  subroutine test_owner_coord_matches_split()
    type(decomp_t) :: dec
    integer :: n, p, c, k, nwrong
    call begin_test('owner_coord_matches_split')
    nwrong = 0
    do n = 1, 23
      do p = 1, min(n, 7)
        dec%ncells(1) = n
        dec%dims(1) = p
        if (allocated(dec%cut)) deallocate (dec%cut)
        allocate (dec%cut(0:p, 3))
        dec%cut(:, 1) = [(split_extent(n, p, c), c=0, p)]
        do c = -3, n + 2
          k = 0
          do while (k < p - 1)
            if (c < split_extent(n, p, k + 1)) exit
            k = k + 1
          end do
          if (dec%owner_coord(1, c) /= k) nwrong = nwrong + 1
        end do
      end do
    end do
    call check_equal_int(nwrong, 0, 'cells whose owner differs from the split')
  end subroutine test_owner_coord_matches_split

  !> balanced_cuts: even weights give split_extent's cuts; a weight in the first tenth of
  !> the cells puts the cuts inside that tenth; no weight splits evenly; every part keeps
  !> minw cells, also where all the weight lies in one cell.
  subroutine test_balanced_cuts_share_the_weight()
    real(wp) :: w(0:99)
    integer :: c
    call begin_test('balanced_cuts_share_the_weight')
    w = 1.0_wp
    call check(all(balanced_cuts(12, 3, w, 1) == [0, 4, 8, 12]), 'even weights: even cuts')
    call check(all(balanced_cuts(100, 4, w, 1) == [(split_extent(100, 4, c), c=0, 4)]), &
               'even weights: the cuts of split_extent')
    w = 0.0_wp
    w(0:9) = 3.0_wp
    call check(all(balanced_cuts(100, 2, w, 1) == [0, 5, 100]), 'weight in cells 0-9: cut at 5')
    call check(all(balanced_cuts(100, 2, w, 8) == [0, 8, 100]), 'the same, at least 8 cells a part')
    call check(all(balanced_cuts(100, 4, w, 2) == [0, 2, 5, 7, 100]), &
               'four parts of 30: cuts nearest 7.5, 15, 22.5 (6, 9, 6, 9 and the empty rest)')
    w = 0.0_wp
    call check(all(balanced_cuts(10, 3, w, 2) == [(split_extent(10, 3, c), c=0, 3)]), &
               'no weight: even cuts')
    w(0) = 1.0_wp
    call check(all(balanced_cuts(10, 3, w, 2) == [0, 2, 4, 10]), 'all in cell 0: parts of minw cells')
  end subroutine test_balanced_cuts_share_the_weight

  !> A box of points in the lower corner of the grid, each on the rank owning it under the
  !> even split (there: on one or few ranks): after balance_by_points every point is on the
  !> rank owning its cell, none is lost or doubled, and the ranks hold about as many (the
  !> box is a product of uniform spacings, so that balanced slabs balance the ranks).
  subroutine test_balance_by_points_spreads_a_corner()
    type(decomp_t) :: dec
    type(particle_set_t) :: ps
    integer :: il, nd, i, j, k, nlost, nbad, nmax, nmin, c(3), nx(3)
    integer(i8) :: n0, id
    integer, allocatable :: layouts(:, :)
    real(wp) :: x(3)
    real(wp), parameter :: zero(6) = 0.0_wp
    character(len=80) :: tag
    logical :: changed
    call begin_test('balance_by_points_spreads_a_corner')
    do nd = 2, 3
      call layouts_for(nd, nranks, layouts)
      do il = 1, size(layouts, 2)
        call dec%init(MPI_COMM_WORLD, nd, ncells, 1, layouts(:, il))
        write (tag, '(a,i0,a,3(1x,i0))') 'ndim=', nd, ' dims=', dec%dims
        call ps%init('solid', nd, .true.)
        ! 12 x 12 (x 12) points over the lower 5 (and 4, 4) cells of each axis
        nx = 1
        nx(1:nd) = 12
        id = 0
        do k = 1, nx(3)
          do j = 1, nx(2)
            do i = 1, nx(1)
              id = id + 1
              x = origin + ([i, j, k] - 0.5_wp)/12.0_wp*[5.0_wp, 4.0_wp, 4.0_wp]*h
              c = cell_of(origin, h, x, nd)
              if (any(c(1:nd) < dec%clo(1:nd) .or. c(1:nd) > dec%chi(1:nd))) cycle
              call ps%append(id, 1, x, zero(1:3), 1.0_wp, 0.01_wp, zero)
            end do
          end do
        end do
        n0 = global_count(dec, ps)
        call balance_by_points(dec, origin, h, 1, ps, nlost=nlost, changed=changed)
        call check_equal_int(nlost, 0, trim(tag)//': no point lost')
        call check(changed .eqv. nranks > 1, trim(tag)//': the cuts moved (on more than one rank)')
        call check(global_count(dec, ps) == n0, trim(tag)//': every point kept once')
        call check_owned(dec, origin, h, ps, nbad)
        call check_equal_int(nbad, 0, trim(tag)//': every point on its owner')
        call MPI_Allreduce(ps%n, nmax, 1, MPI_INTEGER, MPI_MAX, dec%comm)
        call MPI_Allreduce(ps%n, nmin, 1, MPI_INTEGER, MPI_MIN, dec%comm)
        ! a cell of the box holds at most 3 points per axis: a part is off by a slab at most
        call check(real(nmax, wp) <= real(n0, wp)/nranks + real(3*product(nx(2:nd)), wp) .and. &
                   real(nmin, wp) >= real(n0, wp)/nranks - real(3*product(nx(2:nd)), wp), &
                   trim(tag)//': the ranks hold about as many points')
        call ps%free()
        call dec%free()
      end do
    end do
  end subroutine test_balance_by_points_spreads_a_corner

  subroutine test_random_moves_1d()
    call begin_test('random_moves_1d')
    call random_moves_all_layouts(1)
  end subroutine test_random_moves_1d

  subroutine test_random_moves_2d()
    call begin_test('random_moves_2d')
    call random_moves_all_layouts(2)
  end subroutine test_random_moves_2d

  subroutine test_random_moves_3d()
    call begin_test('random_moves_3d')
    call random_moves_all_layouts(3)
  end subroutine test_random_moves_3d

  subroutine test_random_moves_nested_2d()
    call begin_test('random_moves_nested_2d')
    call random_moves_all_layouts(2, nested=.true.)
  end subroutine test_random_moves_nested_2d

  subroutine test_random_moves_nested_3d()
    call begin_test('random_moves_nested_3d')
    call random_moves_all_layouts(3, nested=.true.)
  end subroutine test_random_moves_nested_3d

  !> On nested cuts with two axes split, a point of the rank at the lower corner moved
  !> into the upper slab and, along axis 2, into the cells of that slab's last part that
  !> lie beyond this rank's ghost cells (no neighbour owns them): it must be kept and
  !> counted as lost.
  subroutine test_point_jumping_past_nested_neighbours_is_counted()
    type(decomp_t) :: dec
    type(particle_set_t) :: ps
    integer, allocatable :: gcuts(:, :, :, :)
    integer :: c(3), owner
    call begin_test('point_jumping_past_nested_neighbours_is_counted')
    if (nranks /= 4) return
    call dec%init(MPI_COMM_WORLD, 2, ncells, 1, [2, 2, 1])
    ! slab 0: axis 2 cut at 2; slab 1: at 5 (ncells(2) = 7)
    allocate (gcuts(0:2, 3, 0:1, 0:1))
    gcuts = 0
    gcuts(0:2, 1, :, :) = reshape([0, 6, 13, 0, 6, 13, 0, 6, 13, 0, 6, 13], [3, 2, 2])
    gcuts(0:2, 2, 0, :) = reshape([0, 2, 7, 0, 2, 7], [3, 2])
    gcuts(0:2, 2, 1, :) = reshape([0, 5, 7, 0, 5, 7], [3, 2])
    gcuts(0:1, 3, :, :) = reshape([0, 1, 0, 1, 0, 1, 0, 1], [2, 2, 2])
    call dec%recut_nested(gcuts)
    call make_points(dec, ps, 20)
    ! (rank_at(0, 0, 0) holds cells 0..5 x 0..1; cell (6, 6) is owned by the rank at
    ! (1, 1), which is not a neighbour: its cells along axis 2 start at 5 > 1 + 1)
    c = [6, 6, 0]
    owner = dec%owner_rank(c)
    call check(owner == dec%rank_at(1, 1, 0), 'cell (6, 6) owned by the rank at (1, 1)')
    call check(all(dec%nbrs(2, 1)%rank /= owner) .or. dec%rank /= dec%rank_at(0, 0, 0), &
               'which is no neighbour of the rank at (0, 0)')
    if (dec%rank == dec%rank_at(0, 0, 0)) ps%x(1:2, 1) = origin(1:2) + ([6, 6] + 0.5_wp)*h(1:2)
    call expect_one_lost(dec, ps, int(dec%rank_at(0, 0, 0), i8)*100000_i8 + 1_i8, 'beyond the nested neighbours')
    call ps%free()
    call dec%free()
  end subroutine test_point_jumping_past_nested_neighbours_is_counted

  !> A wedge of points (a triangle in 2D, a prism of it in 3D; the points per row fall along
  !> axis 1), each on the rank owning it under the even split: after balance_nested every
  !> point is on the rank owning its cell, none is lost or doubled, and the busiest rank
  !> holds no more than under balance_by_points (tensor-product cuts).
  subroutine test_balance_nested_spreads_a_wedge()
    type(decomp_t) :: dec
    type(particle_set_t) :: ps
    integer :: il, nd, nlost, nbad, nmax(2), mode, i, j, k, c(3), nx(3)
    integer(i8) :: n0, id
    integer, allocatable :: layouts(:, :)
    real(wp) :: x(3)
    real(wp), parameter :: zero(6) = 0.0_wp
    character(len=80) :: tag
    logical :: changed
    call begin_test('balance_nested_spreads_a_wedge')
    do nd = 2, 3
      call layouts_for(nd, nranks, layouts)
      do il = 1, size(layouts, 2)
        do mode = 1, 2
          call dec%init(MPI_COMM_WORLD, nd, ncells, 1, layouts(:, il))
          write (tag, '(a,i0,a,3(1x,i0))') 'ndim=', nd, ' dims=', dec%dims
          call ps%init('solid', nd, .true.)
          ! 26 x 14 (x 9) points, 2 per cell; row j of axis 2 holds the first 26 - j*26/14
          nx = 1
          nx(1:nd) = [26, 14, 9]
          id = 0
          do k = 1, nx(3)
            do j = 1, nx(2)
              do i = 1, nx(1)
                id = id + 1
                if (i > 26 - (j - 1)*26/14) cycle
                x = origin + ([i, j, k] - 0.5_wp)/real(nx, wp)*real(ncells, wp)*h
                c = cell_of(origin, h, x, nd)
                if (any(c(1:nd) < dec%clo(1:nd) .or. c(1:nd) > dec%chi(1:nd))) cycle
                call ps%append(id, 1, x, zero(1:3), 1.0_wp, 0.01_wp, zero)
              end do
            end do
          end do
          n0 = global_count(dec, ps)
          if (mode == 1) then
            call balance_by_points(dec, origin, h, 1, ps, nlost=nlost, changed=changed)
          else
            call balance_nested(dec, origin, h, 1, ps, nlost=nlost, changed=changed)
            call check_equal_int(nlost, 0, trim(tag)//': no point lost')
            call check(global_count(dec, ps) == n0, trim(tag)//': every point kept once')
            call check_owned(dec, origin, h, ps, nbad)
            call check_equal_int(nbad, 0, trim(tag)//': every point on its owner')
          end if
          call MPI_Allreduce(ps%n, nmax(mode), 1, MPI_INTEGER, MPI_MAX, dec%comm)
          call ps%free()
          call dec%free()
        end do
        if (am_root) print '(a,a,2i6)', trim(tag), ': busiest rank, points and nested:', nmax
        call check(nmax(2) <= nmax(1), trim(tag)//': the busiest rank holds no more than by points')
      end do
    end do
  end subroutine test_balance_nested_spreads_a_wedge

  !> One point of rank 0 (which owns cell 0 on every axis) is moved below the
  !> lower face of axis 1: it must stay on some rank and count as lost.
  !> Its id is 1 (rank 0, first point).
  subroutine test_point_below_grid_is_kept()
    type(decomp_t) :: dec
    type(particle_set_t) :: ps
    integer :: ndim
    call begin_test('point_below_grid_is_kept')
    do ndim = 1, 3
      call dec%init(MPI_COMM_WORLD, ndim, ncells, 1, [0, 0, 0])
      call make_points(dec, ps, 20)
      if (dec%rank == 0) ps%x(1, 1) = origin(1) - 0.5_wp*h(1)
      call expect_one_lost(dec, ps, 1_i8, 'below axis 1')
      call ps%free()
      call dec%free()
    end do
  end subroutine test_point_below_grid_is_kept

  !> One point of the last rank is moved above the upper face of the last axis
  !> and, on the other axes, into the neighbouring rank's cells (a diagonal
  !> move): it must reach that rank's column and still count as lost.
  subroutine test_point_above_grid_is_kept()
    type(decomp_t) :: dec
    type(particle_set_t) :: ps
    integer :: ndim, last, d
    call begin_test('point_above_grid_is_kept')
    do ndim = 1, 3
      call dec%init(MPI_COMM_WORLD, ndim, ncells, 1, [0, 0, 0])
      call make_points(dec, ps, 20)
      last = dec%nranks - 1
      if (dec%rank == last) then
        ps%x(ndim, 1) = origin(ndim) + (ncells(ndim) + 0.3_wp)*h(ndim)
        do d = 1, ndim - 1
          if (dec%clo(d) > 0) ps%x(d, 1) = origin(d) + (dec%clo(d) - 0.5_wp)*h(d)
        end do
      end if
      call expect_one_lost(dec, ps, int(last, i8)*100000_i8 + 1_i8, 'above the last axis')
      call ps%free()
      call dec%free()
    end do
  end subroutine test_point_above_grid_is_kept

  !> On 4 ranks in a row, a point of rank 0 jumps into rank 2's cells: one sweep
  !> takes it only as far as rank 1, so it must be counted as lost, not dropped.
  subroutine test_point_jumping_past_neighbour_is_counted()
    type(decomp_t) :: dec
    type(particle_set_t) :: ps
    call begin_test('point_jumping_past_neighbour_is_counted')
    if (nranks < 3) return
    call dec%init(MPI_COMM_WORLD, 1, ncells, 1, [nranks, 1, 1])
    call make_points(dec, ps, 20)
    ! rank 0 has coords 0 (no reordering); rank 2's first cell is split_extent(.., 2)
    if (dec%rank == 0) ps%x(1, 1) = origin(1) + (split_extent(ncells(1), nranks, 2) + 0.5_wp)*h(1)
    call expect_one_lost(dec, ps, 1_i8, 'two ranks away')
    call ps%free()
    ! The same with the step's promise that every point is in the grid (in_grid): it
    ! spares the count on one rank only, never a point lost between ranks.
    call make_points(dec, ps, 20)
    if (dec%rank == 0) ps%x(1, 1) = origin(1) + (split_extent(ncells(1), nranks, 2) + 0.5_wp)*h(1)
    call expect_one_lost(dec, ps, 1_i8, 'two ranks away, in_grid', in_grid=.true.)
    call ps%free()
    call dec%free()
  end subroutine test_point_jumping_past_neighbour_is_counted

  !> Migrate once and check that exactly one point, with id lost_id (the same
  !> on every rank), is lost, that exactly one rank holds it and that no point
  !> disappeared.
  subroutine expect_one_lost(dec, ps, lost_id, what, in_grid)
    type(decomp_t), intent(in) :: dec
    type(particle_set_t), intent(inout) :: ps
    integer(i8), intent(in) :: lost_id
    character(len=*), intent(in) :: what
    logical, intent(in), optional :: in_grid
    integer(i8) :: n0, n1
    integer :: nlost, nbad, nheld, nmatch
    integer, allocatable :: lost(:)
    n0 = global_count(dec, ps)
    call migrate(dec, origin, h, ps, nlost, lost, in_grid)
    n1 = global_count(dec, ps)
    call check_equal_int(nlost, 1, trim(what)//': nlost')
    call check(n1 == n0, trim(what)//': no point dropped')
    call check_owned(dec, origin, h, ps, nbad)
    call check_equal_int(nbad, 1, trim(what)//': check_owned agrees')
    nheld = size(lost)
    nmatch = count(ps%id(lost) == lost_id)
    call MPI_Allreduce(MPI_IN_PLACE, nheld, 1, MPI_INTEGER, MPI_SUM, dec%comm)
    call MPI_Allreduce(MPI_IN_PLACE, nmatch, 1, MPI_INTEGER, MPI_SUM, dec%comm)
    call check_equal_int(nheld, 1, trim(what)//': lost point held by one rank')
    call check_equal_int(nmatch, 1, trim(what)//': the lost point is the one moved')
  end subroutine expect_one_lost

  !> Random moves in every rank layout, several rounds each.
  subroutine random_moves_all_layouts(ndim, nested)
    integer, intent(in) :: ndim
    logical, intent(in), optional :: nested
    integer, allocatable :: layouts(:, :)
    integer :: il
    call layouts_for(ndim, nranks, layouts)
    do il = 1, size(layouts, 2)
      call random_moves(ndim, layouts(:, il), 6, nested)
    end do
  end subroutine random_moves_all_layouts

  !> Create points in each rank's cells, then nround times move all of them by up
  !> to 0.9 cells per axis and migrate, checking conservation and ownership.
  subroutine random_moves(ndim, dims_in, nround, nested)
    integer, intent(in) :: ndim, dims_in(3), nround
    logical, intent(in), optional :: nested
    integer, allocatable :: gcuts(:, :, :, :)
    type(decomp_t) :: dec
    type(particle_set_t) :: ps
    integer :: round, k, d, nlost, nbad
    integer(i8) :: n0
    real(wp) :: m0, p0(3), pscale, lo, hi
    integer(i8), allocatable :: ids0(:)
    character(len=80) :: tag
    call dec%init(MPI_COMM_WORLD, ndim, ncells, 1, dims_in)
    write (tag, '(a,i0,a,3(1x,i0))') 'ndim=', ndim, ' dims=', dec%dims
    if (present(nested)) then
      if (nested) then
        call nested_test_cuts(dec, 1, gcuts)
        call dec%recut_nested(gcuts)
        tag = trim(tag)//' nested'
      end if
    end if
    call make_points(dec, ps, 40 + 13*dec%rank)
    call check_owned(dec, origin, h, ps, nbad)
    call check_equal_int(nbad, 0, trim(tag)//': points start in owned cells')
    n0 = global_count(dec, ps)
    call totals(dec, ps, m0, p0, pscale)
    call gather_sorted_ids(dec, ps, ids0)
    if (dec%rank == 0) call check(all(ids0(2:) > ids0(:size(ids0) - 1)), trim(tag)//': ids unique at start')
    do round = 1, nround
      do k = 1, ps%n
        do d = 1, ndim
          lo = origin(d) + 1.0e-9_wp*h(d)
          hi = origin(d) + (ncells(d) - 1.0e-9_wp)*h(d)
          ps%x(d, k) = max(lo, min(hi, ps%x(d, k) + 0.9_wp*h(d)*(2.0_wp*uniform() - 1.0_wp)))
        end do
      end do
      ! (every other round as the step calls it, with the points inside the grid: only
      ! the arrivals are then checked for ownership)
      call migrate(dec, origin, h, ps, nlost, in_grid=mod(round, 2) == 0)
      call check_round(dec, ps, tag, round, n0, m0, p0, pscale, ids0, nlost)
    end do
    call ps%free()
    call dec%free()
  end subroutine random_moves

  !> All checks after one round of moves.
  subroutine check_round(dec, ps, tag, round, n0, m0, p0, pscale, ids0, nlost)
    type(decomp_t), intent(in) :: dec
    type(particle_set_t), intent(in) :: ps
    character(len=*), intent(in) :: tag
    integer, intent(in) :: round, nlost
    integer(i8), intent(in) :: n0
    real(wp), intent(in) :: m0, p0(3), pscale
    integer(i8), intent(in) :: ids0(:)
    character(len=120) :: what
    real(wp) :: m1, p1(3), s1
    integer(i8), allocatable :: ids1(:)
    integer :: nbad, d, nintact
    write (what, '(a,a,i0)') trim(tag), ' round ', round
    call check_equal_int(nlost, 0, trim(what)//': nlost')
    call check(global_count(dec, ps) == n0, trim(what)//': global count')
    call totals(dec, ps, m1, p1, s1)
    call check_close(m1, m0, 1.0e-12_wp, 0.0_wp, trim(what)//': total mass')
    do d = 1, dec%ndim
      call check_close(p1(d), p0(d), 1.0e-12_wp, 1.0e-12_wp*pscale, trim(what)//': momentum')
    end do
    call check_owned(dec, origin, h, ps, nbad)
    call check_equal_int(nbad, 0, trim(what)//': every point in an owned cell')
    nintact = count(.not. point_intact(ps))
    call MPI_Allreduce(MPI_IN_PLACE, nintact, 1, MPI_INTEGER, MPI_SUM, dec%comm)
    call check_equal_int(nintact, 0, trim(what)//': point data intact')
    call gather_sorted_ids(dec, ps, ids1)
    if (dec%rank == 0) then
      call check(size(ids1) == size(ids0), trim(what)//': as many ids as at start')
      if (size(ids1) == size(ids0)) call check(all(ids1 == ids0), trim(what)//': same ids, each once')
    end if
  end subroutine check_round

  !> Points of this rank: n points uniformly in the owned cells, id rank*100000+k,
  !> with mass, velocity and stress derived from the id (see point_intact).
  subroutine make_points(dec, ps, n)
    type(decomp_t), intent(in) :: dec
    type(particle_set_t), intent(inout) :: ps
    integer, intent(in) :: n
    integer :: k, d
    integer(i8) :: id
    real(wp) :: x(3), v(3), stress(6)
    seed = 1234567_i8 + 7919_i8*dec%rank
    call ps%init('solid', dec%ndim, .true.)
    do k = 1, n
      id = int(dec%rank, i8)*100000_i8 + int(k, i8)
      x = 0.0_wp
      do d = 1, dec%ndim
        x(d) = origin(d) + (dec%clo(d) + (0.001_wp + 0.998_wp*uniform()) &
                            *(dec%chi(d) - dec%clo(d) + 1))*h(d)
      end do
      v = velocity_of(id)
      stress = real(id, wp)*[1.0_wp, 2.0_wp, 3.0_wp, 4.0_wp, 5.0_wp, 6.0_wp]
      call ps%append(id, 1 + int(mod(id, 3_i8)), x, v, mass_of(id), 0.01_wp, stress)
    end do
  end subroutine make_points

  !> Mass of point id (any deterministic, id-dependent value).
  pure real(wp) function mass_of(id) result(m)
    integer(i8), intent(in) :: id
    m = 0.5_wp + real(mod(7_i8*id, 101_i8), wp)/101.0_wp
  end function mass_of

  !> Velocity of point id, components of both signs.
  pure function velocity_of(id) result(v)
    integer(i8), intent(in) :: id
    real(wp) :: v(3)
    v = [real(mod(id, 17_i8), wp) - 8.0_wp, real(mod(id, 11_i8), wp) - 5.0_wp, &
         real(mod(id, 5_i8), wp) - 2.0_wp]/3.0_wp
  end function velocity_of

  !> True for each point whose travelling data still match its id.
  function point_intact(ps) result(ok)
    type(particle_set_t), intent(in) :: ps
    logical :: ok(ps%n)
    integer :: k
    real(wp) :: v(3)
    do k = 1, ps%n
      v = velocity_of(ps%id(k))
      ok(k) = ps%mass(k) == mass_of(ps%id(k)) .and. all(ps%v(:, k) == v(1:ps%ndim)) &
              .and. ps%stress(1, k) == real(ps%id(k), wp) .and. ps%stress(6, k) == 6.0_wp*real(ps%id(k), wp) &
              .and. ps%mat(k) == 1 + int(mod(ps%id(k), 3_i8)) .and. ps%vol0(k) == 0.01_wp &
              .and. ps%defgrad(1, k) == 1.0_wp .and. ps%defgrad(2, k) == 0.0_wp
    end do
  end function point_intact

  !> Global number of points.
  integer(i8) function global_count(dec, ps) result(n)
    type(decomp_t), intent(in) :: dec
    type(particle_set_t), intent(in) :: ps
    n = int(ps%n, i8)
    call MPI_Allreduce(MPI_IN_PLACE, n, 1, MPI_INTEGER8, MPI_SUM, dec%comm)
  end function global_count

  !> Global total mass, momentum and a momentum scale sum(m |v|) for tolerances.
  subroutine totals(dec, ps, m, p, pscale)
    type(decomp_t), intent(in) :: dec
    type(particle_set_t), intent(in) :: ps
    real(wp), intent(out) :: m, p(3), pscale
    real(wp) :: buf(5)
    integer :: d
    buf = 0.0_wp
    buf(1) = sum(ps%mass(1:ps%n))
    do d = 1, ps%ndim
      buf(1 + d) = sum(ps%mass(1:ps%n)*ps%v(d, 1:ps%n))
      buf(5) = buf(5) + sum(ps%mass(1:ps%n)*abs(ps%v(d, 1:ps%n)))
    end do
    call MPI_Allreduce(MPI_IN_PLACE, buf, 5, MPI_DOUBLE_PRECISION, MPI_SUM, dec%comm)
    m = buf(1)
    p = buf(2:4)
    pscale = buf(5)
  end subroutine totals

  !> All ids gathered on rank 0 and sorted (empty on the other ranks).
  subroutine gather_sorted_ids(dec, ps, ids)
    type(decomp_t), intent(in) :: dec
    type(particle_set_t), intent(in) :: ps
    integer(i8), allocatable, intent(out) :: ids(:)
    integer, allocatable :: counts(:), displs(:)
    integer :: r
    allocate (counts(0:dec%nranks - 1), displs(0:dec%nranks - 1))
    call MPI_Gather(ps%n, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, 0, dec%comm)
    if (dec%rank == 0) then
      displs(0) = 0
      do r = 1, dec%nranks - 1
        displs(r) = displs(r - 1) + counts(r - 1)
      end do
      allocate (ids(sum(counts)))
    else
      allocate (ids(0))
    end if
    call MPI_Gatherv(ps%id(1:ps%n), ps%n, MPI_INTEGER8, ids, counts, displs, MPI_INTEGER8, &
                     0, dec%comm)
    ! (the ids of a test, below 2**53, are exact as reals)
    if (dec%rank == 0) ids = ids(ascending_order(real(ids, wp)))
  end subroutine gather_sorted_ids

  !> Uniform number in [0, 1) from the Park-Miller minimal standard generator.
  real(wp) function uniform() result(u)
    seed = mod(16807_i8*seed, 2147483647_i8)
    u = real(seed - 1_i8, wp)/2147483646.0_wp
  end function uniform

end program test_migration
