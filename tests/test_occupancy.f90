!> Bookkeeping of the Gauss cells (dpmpm_gauss_fields). Occupancy (occupancy_pass):
!> the closing by a box of half-width r fills gaps of up to 2r empty cells inside a
!> body, leaves wider gaps open, and neither grows a body past its outermost occupied
!> cells nor erodes it at the grid faces. The reach kept by gauss_accumulate gives
!> gauss_strain the same point gradients and divergences as the reach found again; the
!> divergences are the traces of the gradients. An isotropic field reconstructed as one
!> value per Gauss point gives the forces and divergences of its tensor s I. With one
!> Gauss point per cell, the sums are those over every cell centre within the weight. A
!> second field summed and solved with the first's counts and moments is solved as alone.
program test_occupancy
  use dpmpm_kinds, only: wp
  use dpmpm_gauss_fields, only: occupancy_pass, gauss_accumulate, gauss_strain, reach_cache_t, &
                                reach_cache_entries, gauss_cell_components, gauss_solution_components, &
                                gauss_solve, gauss_forces, gauss_second_field_components
  use dpmpm_kernels, only: kernel_wendland_c2, kernel_cubic, kernel_linear
  use dpmpm_mls, only: basis_linear, basis_constant, mls_stats_t
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  !> The grid of the Gauss-field tests: origin and cell size (different along each axis).
  real(wp), parameter :: gorigin(3) = [0.1_wp, -0.2_wp, 0.3_wp], gh(3) = [0.5_wp, 0.25_wp, 0.4_wp]
  call start_tests()
  call test_closing_fills_gaps_up_to_twice_the_width_1d()
  call test_closing_keeps_block_surfaces_2d()
  call test_kept_reach_gives_the_same_gradients()
  call test_isotropic_field_gives_the_forces_of_its_tensor()
  call test_one_gauss_point_reaches_every_centre_within_the_weight()
  call test_second_field_is_solved_as_alone()
  call end_tests()

contains

  !> Closed occupancy of a single-rank grid of ncells cells (ghost width 2, ghost
  !> cells empty) from the flags occ0 of cells 0..ncells-1 (row-major in 2D).
  function closed(nd, ncells, r, occ0) result(occ)
    integer, intent(in) :: nd, ncells(3), r
    real(wp), intent(in) :: occ0(:, :)
    real(wp) :: occ(size(occ0, 1), size(occ0, 2))
    real(wp), allocatable :: a(:, :, :, :), b(:, :, :, :)
    integer :: lo(3), hi(3), clo(3), chi(3)
    lo = 0; hi = 0; clo = 0; chi = 0
    lo(1:nd) = -2
    hi(1:nd) = ncells(1:nd) + 2
    chi(1:nd) = ncells(1:nd) - 1
    allocate (a(1, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), b(1, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
    a = 0.0_wp
    b = 0.0_wp
    a(1, 0:chi(1), 0:chi(2), 0) = occ0
    call occupancy_pass(nd, r, .true., lo, clo, chi, ncells, a, b)
    a = 0.0_wp
    call occupancy_pass(nd, r, .false., lo, clo, chi, ncells, b, a)
    occ = a(1, 0:chi(1), 0:chi(2), 0)
  end function closed

  subroutine test_closing_fills_gaps_up_to_twice_the_width_1d()
    ! Cells 0..19: empty runs of 1 (cell 3), 2 (6-7), 3 (10-12) and 5 (14-18) cells,
    ! and the body ends at cell 19, the last cell of the grid.
    real(wp) :: occ0(20, 1), occ(20, 1), want1(20), want2(20)
    integer :: ncells(3)
    ncells = [20, 1, 1]
    occ0(:, 1) = 1.0_wp
    occ0([3, 6, 7, 10, 11, 12, 14, 15, 16, 17, 18] + 1, 1) = 0.0_wp
    call begin_test('closing_fills_gaps_up_to_twice_the_width_1d')
    want1 = 1.0_wp
    want1([10, 11, 12, 14, 15, 16, 17, 18] + 1) = 0.0_wp
    want2 = 1.0_wp
    want2([14, 15, 16, 17, 18] + 1) = 0.0_wp
    occ = closed(1, ncells, 1, occ0)
    call check(all(occ(:, 1) == want1), 'r = 1 fills the gaps of 1 and 2 cells only')
    occ = closed(1, ncells, 2, occ0)
    call check(all(occ(:, 1) == want2), 'r = 2 fills the gaps of up to 4 cells only')
  end subroutine test_closing_fills_gaps_up_to_twice_the_width_1d

  subroutine test_closing_keeps_block_surfaces_2d()
    ! A 12 x 10 grid: an L-shaped body against the faces x- and y- (cells 0..7 in
    ! x for rows 0..3, cells 0..3 in x for rows 4..6), with two single empty cells
    ! inside it; everything else empty.
    real(wp) :: occ0(12, 10), want(12, 10)
    integer :: ncells(3)
    ncells = [12, 10, 1]
    want = 0.0_wp
    want(1:8, 1:4) = 1.0_wp
    want(1:4, 5:7) = 1.0_wp
    occ0 = want
    occ0(3, 2) = 0.0_wp
    occ0(2, 6) = 0.0_wp
    call begin_test('closing_keeps_block_surfaces_2d')
    call check(all(closed(2, ncells, 1, occ0) == want), 'r = 1: holes filled, L-shape kept')
    call check(all(closed(2, ncells, 2, occ0) == want), 'r = 2: holes filled, L-shape kept')
  end subroutine test_closing_keeps_block_surfaces_2d
  !> gauss_strain with the reach kept by gauss_accumulate against the reach found again
  !> per point: the same point gradients (two fields), divergences (the two fields in
  !> one pass, as the fluid points take them) and effective volumes, bit for bit, in 2D
  !> and 3D with 2 and 3 Gauss points per axis, for the Wendland C2 weight of radius 2
  !> with the linear basis and the cubic B-spline (tensor form) with the constant one.
  !> The divergences equal the traces (L11 + L22) + L33 of the gradients bit for bit.
  !> Scattered points, random fields; the cache is valid and not empty.
  subroutine test_kept_reach_gives_the_same_gradients()
    integer, parameter :: n = 60, nc = 8
    integer :: nd, ng, variant, kernel, basis, lo(3), hi(3), ncells(3), nk1, nk2, nk3, nk4
    real(wp), allocatable :: x(:, :), vol(:), stress(:, :), acc(:, :, :, :), sol(:, :, :, :)
    real(wp), allocatable :: lg(:, :, :, :), lg2(:, :, :, :), va(:, :), vb(:, :), wa(:, :), wb(:, :)
    real(wp), allocatable :: ta(:), tb(:), tc(:), td(:), da(:), db(:), dc(:), dd(:)
    real(wp) :: radius
    logical :: radial
    type(reach_cache_t) :: cache
    character(len=40) :: tag
    call begin_test('kept_reach_gives_the_same_gradients')
    do nd = 2, 3
      do ng = 2, 3
        do variant = 1, 2
          kernel = merge(kernel_wendland_c2, kernel_cubic, variant == 1)
          basis = merge(basis_linear, basis_constant, variant == 1)
          ! (variant 2: the tensor-product cubic B-spline of natural support)
          radius = merge(2.0_wp, 0.0_wp, variant == 1)
          radial = variant == 1
          write (tag, '(i0,a,i0,a,i0)') nd, 'D ng = ', ng, ' variant ', variant
          call test_grid(nd, nc, ncells, lo, hi)
          allocate (x(nd, n), vol(n), stress(6, n), ta(n), tb(n), va(9, n), vb(9, n), wa(9, n), wb(9, n))
          allocate (tc(n), td(n), da(n), db(n), dc(n), dd(n))
          call scattered_points(nd, x, vol)
          call random_number(stress)
          allocate (acc(gauss_cell_components(nd, ng, basis), lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
          allocate (sol(gauss_solution_components(nd, ng, basis), lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
          allocate (lg(ng**nd*nd*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
          allocate (lg2, mold=lg)
          acc = 0.0_wp
          call gauss_accumulate(nd, n, x, vol, stress, gorigin, gh, ncells, ng, kernel, radius, radial, &
                                basis, lo, acc, cache=cache)
          call check(cache%valid .and. reach_cache_entries(cache) > n, trim(tag)//': the reach is kept')
          call random_number(sol)
          sol(1, :, :, :) = 1.0_wp
          call random_number(lg)
          call random_number(lg2)
          va = 0.0_wp; vb = 0.0_wp; wa = 0.0_wp; wb = 0.0_wp
          da = 0.0_wp; db = 0.0_wp; dc = 0.0_wp; dd = 0.0_wp
          call gauss_strain(nd, n, x, vol, gorigin, gh, ncells, ng, kernel, radius, radial, basis, lo, sol, &
                            lg, ta, nk1, vgrad=va)
          call gauss_strain(nd, n, x, vol, gorigin, gh, ncells, ng, kernel, radius, radial, basis, lo, sol, &
                            lg, tb, nk2, vgrad=vb, cache=cache)
          call gauss_strain(nd, n, x, vol, gorigin, gh, ncells, ng, kernel, radius, radial, basis, lo, sol, &
                            lg2, ta, nk1, vgrad=wa)
          call gauss_strain(nd, n, x, vol, gorigin, gh, ncells, ng, kernel, radius, radial, basis, lo, sol, &
                            lg2, tb, nk2, vgrad=wb, cache=cache)
          call check(all(va == vb) .and. all(wa == wb), trim(tag)//': the same point gradients')
          call check(all(ta == tb) .and. nk1 == nk2, trim(tag)//': the same effective volumes')
          call check(maxval(abs(va)) > 0.0_wp .and. minval(ta) > 0.0_wp, trim(tag)//': nonzero gradients')
          call gauss_strain(nd, n, x, vol, gorigin, gh, ncells, ng, kernel, radius, radial, basis, lo, sol, &
                            lg, tc, nk3, div=da, lg2=lg2, div2=db)
          call gauss_strain(nd, n, x, vol, gorigin, gh, ncells, ng, kernel, radius, radial, basis, lo, sol, &
                            lg, td, nk4, div=dc, lg2=lg2, div2=dd, cache=cache)
          call check(all(da == dc) .and. all(db == dd), trim(tag)//': the same point divergences')
          call check(all(tc == ta) .and. all(td == ta) .and. nk3 == nk1 .and. nk4 == nk1, &
                     trim(tag)//': the same effective volumes with the divergences')
          call check(all(da == va(1, :) + va(5, :) + va(9, :)) .and. all(db == wa(1, :) + wa(5, :) + wa(9, :)), &
                     trim(tag)//': the divergences are the traces of the gradients')
          call check(maxval(abs(da)) > 0.0_wp .and. maxval(abs(db)) > 0.0_wp, trim(tag)//': nonzero divergences')
          deallocate (x, vol, stress, ta, tb, va, vb, wa, wb, acc, sol, lg, lg2, tc, td, da, db, dc, dd)
        end do
      end do
    end do
  end subroutine test_kept_reach_gives_the_same_gradients

  !> A field s reconstructed as an isotropic one (one value per Gauss point) against the
  !> tensor s I reconstructed component by component (xx = yy = zz = s, no shear): the
  !> same reconstructed value, the same nodal forces and the same point divergences, bit
  !> for bit, in 2D and 3D with 2 Gauss points per axis, for the Wendland C2 weight of
  !> radius 2 with the constant and with the linear basis; cubic B-spline grid functions.
  !> The isotropic sums take 1 + np + nb of the 1 + np + nb nf components per Gauss point.
  subroutine test_isotropic_field_gives_the_forces_of_its_tensor()
    integer, parameter :: n = 60, nc = 8, ng = 2
    integer :: nd, basis, lo(3), hi(3), clo(3), chi(3), ncells(3), m, nk1, nk2, ib
    real(wp), allocatable :: x(:, :), vol(:), sv(:, :), st(:, :), acci(:, :, :, :), acct(:, :, :, :)
    real(wp), allocatable :: soli(:, :, :, :), solt(:, :, :, :), nodei(:, :, :, :), nodet(:, :, :, :)
    real(wp), allocatable :: lg(:, :, :, :), ti(:), tt(:), di(:), dt(:)
    type(mls_stats_t) :: stats
    character(len=40) :: tag
    call begin_test('isotropic_field_gives_the_forces_of_its_tensor')
    do nd = 2, 3
      do ib = 1, 2
        basis = merge(basis_constant, basis_linear, ib == 1)
        write (tag, '(i0,2a)') nd, 'D, basis ', trim(merge('constant', 'linear  ', ib == 1))
        call test_grid(nd, nc, ncells, lo, hi)
        clo = 0; chi = 0
        chi(1:nd) = nc - 1
        allocate (x(nd, n), vol(n), sv(1, n), st(6, n), ti(n), tt(n), di(n), dt(n))
        call scattered_points(nd, x, vol)
        call random_number(sv)
        sv = sv - 0.5_wp
        st = 0.0_wp
        do m = 1, 3
          st(m, :) = sv(1, :)
        end do
        allocate (acci(gauss_cell_components(nd, ng, basis, isotropic=.true.), lo(1):hi(1), lo(2):hi(2), &
                       lo(3):hi(3)))
        allocate (acct(gauss_cell_components(nd, ng, basis), lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (soli(gauss_solution_components(nd, ng, basis, isotropic=.true.), lo(1):hi(1), &
                       lo(2):hi(2), lo(3):hi(3)))
        allocate (solt(gauss_solution_components(nd, ng, basis), lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (nodei(1 + 2*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), nodet(1 + 2*nd, lo(1):hi(1), &
                  lo(2):hi(2), lo(3):hi(3)), lg(ng**nd*nd*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        call check(size(acci, 1) < size(acct, 1) .and. size(soli, 1) < size(solt, 1), &
                   trim(tag)//': the isotropic sums are smaller')
        acci = 0.0_wp; acct = 0.0_wp; soli = 0.0_wp; solt = 0.0_wp; nodei = 0.0_wp; nodet = 0.0_wp
        call gauss_accumulate(nd, n, x, vol, sv, gorigin, gh, ncells, ng, kernel_wendland_c2, 2.0_wp, &
                              .true., basis, lo, acci, isotropic=.true.)
        call gauss_accumulate(nd, n, x, vol, st, gorigin, gh, ncells, ng, kernel_wendland_c2, 2.0_wp, &
                              .true., basis, lo, acct)
        call gauss_solve(nd, ng, basis, lo, clo, chi, acci, soli, stats, isotropic=.true.)
        call gauss_solve(nd, ng, basis, lo, clo, chi, acct, solt, stats)
        call check(reconstructed_equal(nd, ng, basis, soli, solt), trim(tag)//': the same reconstructed value')
        call gauss_forces(nd, ng, basis, kernel_cubic, gh, lo, clo, chi, soli, nodei, isotropic=.true.)
        call gauss_forces(nd, ng, basis, kernel_cubic, gh, lo, clo, chi, solt, nodet)
        call check(all(nodei == nodet) .and. maxval(abs(nodei)) > 0.0_wp, trim(tag)//': the same nodal forces')
        call random_number(lg)
        ! (a point whose effective volume is not positive keeps its value: 0 here)
        di = 0.0_wp; dt = 0.0_wp
        call gauss_strain(nd, n, x, vol, gorigin, gh, ncells, ng, kernel_wendland_c2, 2.0_wp, .true., basis, &
                          lo, soli, lg, ti, nk1, div=di, isotropic=.true.)
        call gauss_strain(nd, n, x, vol, gorigin, gh, ncells, ng, kernel_wendland_c2, 2.0_wp, .true., basis, &
                          lo, solt, lg, tt, nk2, div=dt)
        call check(all(di == dt) .and. all(ti == tt) .and. nk1 == nk2 .and. maxval(abs(di)) > 0.0_wp, &
                   trim(tag)//': the same divergences and effective volumes')
        deallocate (x, vol, sv, st, ti, tt, di, dt, acci, acct, soli, solt, nodei, nodet, lg)
      end do
    end do
  end subroutine test_isotropic_field_gives_the_forces_of_its_tensor

  !> One Gauss point per cell (the cell's centre) and a weight of reach below one cell
  !> (linear + one Gauss point: the ball of radius 0.75, the box of half-width 0.65): the
  !> sums of gauss_accumulate against sums over every cell centre of the grid, point by
  !> point in the same order, bit for bit: the count of points that reach each centre,
  !> the weight sum and the field sum. 2D and 3D; points scattered over the grid and put
  !> on cell faces, cell centres, the grid's faces and its corners.
  subroutine test_one_gauss_point_reaches_every_centre_within_the_weight()
    integer, parameter :: n = 400, nc = 5
    integer :: nd, variant, lo(3), hi(3), ncells(3), p, i, j, k, m(3)
    real(wp), allocatable :: x(:, :), vol(:), stress(:, :), acc(:, :, :, :), ref(:, :, :, :)
    real(wp) :: radius, s(3), dx(3), w, r, wl(3)
    logical :: radial
    character(len=40) :: tag
    call begin_test('one_gauss_point_reaches_every_centre_within_the_weight')
    do nd = 2, 3
      do variant = 1, 2
        radial = variant == 1
        radius = merge(0.75_wp, 0.65_wp, radial)
        write (tag, '(i0,2a)') nd, 'D, ', trim(merge('ball', 'box ', radial))
        call test_grid(nd, nc, ncells, lo, hi)
        allocate (x(nd, n), vol(n), stress(6, n))
        ! (the volumes; the places, in cell units, over the whole grid, then the special places)
        call scattered_points(nd, x, vol)
        call random_number(x)
        x = nc*x
        x(:, 1) = 0.0_wp
        x(:, 2) = real(nc, wp)
        x(:, 3) = 0.5_wp
        x(:, 4) = 2.0_wp
        x(1, 5) = 1.5_wp
        x(:, 6) = 2.5_wp
        do p = 1, n
          x(:, p) = gorigin(1:nd) + x(:, p)*gh(1:nd)
        end do
        call random_number(stress)
        allocate (acc(gauss_cell_components(nd, 1, basis_constant), lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (ref, mold=acc)
        acc = 0.0_wp
        ref = 0.0_wp
        call gauss_accumulate(nd, n, x, vol, stress, gorigin, gh, ncells, 1, kernel_linear, radius, radial, &
                              basis_constant, lo, acc)
        m = 0
        m(1:nd) = nc - 1
        do p = 1, n
          s = 0.0_wp
          s(1:nd) = (x(:, p) - gorigin(1:nd))/gh(1:nd)
          do k = 0, m(3)
            do j = 0, m(2)
              do i = 0, m(1)
                dx = [real(i, wp), real(j, wp), real(k, wp)] + 0.5_wp - s
                dx(nd + 1:3) = 0.0_wp
                if (any(abs(dx) >= radius)) cycle
                if (radial) then
                  if (dx(1)**2 + dx(2)**2 + dx(3)**2 >= radius*radius) cycle
                  r = sqrt(dx(1)**2 + dx(2)**2 + dx(3)**2)/radius
                  w = 1.0_wp - r
                else
                  wl = 1.0_wp - abs(dx)/radius
                  w = wl(1)*wl(2)*wl(3)
                end if
                if (w <= 0.0_wp) cycle
                ref(2, i, j, k) = ref(2, i, j, k) + 1.0_wp
                ref(3, i, j, k) = ref(3, i, j, k) + vol(p)*w
                ref(4, i, j, k) = ref(4, i, j, k) + vol(p)*w*stress(1, p)
              end do
            end do
          end do
        end do
        call check(all(acc(2:4, :, :, :) == ref(2:4, :, :, :)), trim(tag)//': the same sums')
        call check(sum(ref(2, :, :, :)) > real(n, wp), trim(tag)//': points reach more than one centre')
        deallocate (x, vol, stress, acc, ref)
      end do
    end do
  end subroutine test_one_gauss_point_reaches_every_centre_within_the_weight

  !> The test grid of nc cells along each of nd axes with 2 ghost cells each way.
  !> Two fields of the same points in one pass (gauss_accumulate's acc2 holds the second
  !> field's sums alone) and one solve (gauss_solve's acc2, sol2: the first field's gamma):
  !> the second field's solution equals that of the second field summed and solved
  !> alone, and the first's that of the first alone, bit for bit. 2D and 3D, constant
  !> and linear basis, isotropic fields (the fluid's two shares of p) and stress tensors;
  !> Wendland C2 weight of radius 2, 2 Gauss points per axis.
  subroutine test_second_field_is_solved_as_alone()
    integer, parameter :: n = 60, nc = 8, ng = 2
    integer :: nd, basis, lo(3), hi(3), clo(3), chi(3), ncells(3), icase, nin
    real(wp), allocatable :: x(:, :), vol(:), f1(:, :), f2(:, :), acc(:, :, :, :), acc2(:, :, :, :)
    real(wp), allocatable :: sol(:, :, :, :), sol2(:, :, :, :), acca(:, :, :, :), accb(:, :, :, :)
    real(wp), allocatable :: sola(:, :, :, :), solb(:, :, :, :)
    type(mls_stats_t) :: stats
    logical :: iso
    character(len=48) :: tag
    call begin_test('second_field_is_solved_as_alone')
    do nd = 2, 3
      ! (the four cases: constant or linear basis, isotropic field or tensor)
      do icase = 1, 4
        basis = merge(basis_constant, basis_linear, icase <= 2)
        iso = mod(icase, 2) == 1
        nin = merge(1, 6, iso)
        write (tag, '(i0,4a)') nd, 'D, basis ', trim(merge('constant', 'linear  ', icase <= 2)), ', ', &
            trim(merge('isotropic', 'tensor   ', iso))
        call test_grid(nd, nc, ncells, lo, hi)
        clo = 0; chi = 0
        chi(1:nd) = nc - 1
        allocate (x(nd, n), vol(n), f1(nin, n), f2(nin, n))
        call scattered_points(nd, x, vol)
        call random_number(f1)
        call random_number(f2)
        f2 = f2 - 0.5_wp
        allocate (acc(gauss_cell_components(nd, ng, basis, iso), lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (acc2(gauss_second_field_components(nd, ng, basis, iso), lo(1):hi(1), lo(2):hi(2), &
                         lo(3):hi(3)))
        allocate (sol(gauss_solution_components(nd, ng, basis, iso), lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        allocate (acca, accb, mold=acc)
        allocate (sol2, sola, solb, mold=sol)
        acc = 0.0_wp; acc2 = 0.0_wp; acca = 0.0_wp; accb = 0.0_wp
        sol = 0.0_wp; sol2 = 0.0_wp; sola = 0.0_wp; solb = 0.0_wp
        call gauss_accumulate(nd, n, x, vol, f1, gorigin, gh, ncells, ng, kernel_wendland_c2, 2.0_wp, &
                                .true., basis, lo, acc, f2, acc2, isotropic=iso)
        call gauss_accumulate(nd, n, x, vol, f1, gorigin, gh, ncells, ng, kernel_wendland_c2, 2.0_wp, &
                                .true., basis, lo, acca, isotropic=iso)
        call gauss_accumulate(nd, n, x, vol, f2, gorigin, gh, ncells, ng, kernel_wendland_c2, 2.0_wp, &
                                .true., basis, lo, accb, isotropic=iso)
        call check(size(acc2, 1) < size(accb, 1), trim(tag)//': the second sums are smaller')
        call gauss_solve(nd, ng, basis, lo, clo, chi, acc, sol, stats, iso, acc2, sol2)
        call gauss_solve(nd, ng, basis, lo, clo, chi, acca, sola, stats, iso)
        call gauss_solve(nd, ng, basis, lo, clo, chi, accb, solb, stats, iso)
        call check(all(sol2 == solb) .and. any(solb /= sola), trim(tag)//': the second field as alone')
        call check(all(sol == sola), trim(tag)//': the first field as alone')
        deallocate (x, vol, f1, f2, acc, acc2, sol, sol2, acca, accb, sola, solb)
      end do
    end do
  end subroutine test_second_field_is_solved_as_alone

  subroutine test_grid(nd, nc, ncells, lo, hi)
    integer, intent(in) :: nd, nc
    integer, intent(out) :: ncells(3), lo(3), hi(3)
    ncells = 1
    ncells(1:nd) = nc
    lo = 0; hi = 0
    lo(1:nd) = -2
    hi(1:nd) = nc + 2
  end subroutine test_grid

  !> Points x(nd, :) scattered uniformly over cells 1 to 7 of the test grid along each axis,
  !> with volumes vol between 0.005 and 0.015.
  subroutine scattered_points(nd, x, vol)
    integer, intent(in) :: nd
    real(wp), intent(out) :: x(:, :), vol(:)
    integer :: p
    call random_number(x)
    do p = 1, size(x, 2)
      x(:, p) = gorigin(1:nd) + (1.0_wp + 6.0_wp*x(:, p))*gh(1:nd)
    end do
    call random_number(vol)
    vol = 0.01_wp*(0.5_wp + vol)
  end subroutine scattered_points

  !> The isotropic solution soli against the tensor one solt: per occupied cell and Gauss
  !> point the same gamma and the isotropic value equal to the xx component.
  logical function reconstructed_equal(nd, ng, basis, soli, solt) result(same)
    integer, intent(in) :: nd, ng, basis
    real(wp), intent(in) :: soli(:, :, :, :), solt(:, :, :, :)
    integer :: i, j, k, g, nb, nf
    nb = merge(1, nd + 1, basis == basis_constant)
    nf = nd*(nd + 1)/2
    same = .true.
    do k = 1, size(soli, 4)
      do j = 1, size(soli, 3)
        do i = 1, size(soli, 2)
          same = same .and. soli(1, i, j, k) == solt(1, i, j, k)
          do g = 1, ng**nd
            same = same .and. all(soli(2 + (g - 1)*(nb + 1):1 + (g - 1)*(nb + 1) + nb + 1, i, j, k) == &
                                  solt(2 + (g - 1)*(nb + nf):1 + (g - 1)*(nb + nf) + nb + 1, i, j, k))
          end do
        end do
      end do
    end do
  end function reconstructed_equal

end program test_occupancy
