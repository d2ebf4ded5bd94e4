!> Occupancy of the Gauss cells (dpmpm_reconstruct occupancy_pass): the closing
!> by a box of half-width r fills gaps of up to 2r empty cells inside a body,
!> leaves wider gaps open, and neither grows a body past its outermost occupied
!> cells nor erodes it at the grid faces.
program test_occupancy
  use dpmpm_mpi_start, only: start_mpi
  use mpi_f08, only: MPI_Finalize
  use dpmpm_kinds, only: wp
  use dpmpm_gauss_fields, only: occupancy_pass
  use dpmpm_assert, only: begin_test, check, finish_tests
  implicit none
  integer :: status
  call start_mpi()
  call test_closing_fills_gaps_up_to_twice_the_width_1d()
  call test_closing_keeps_block_surfaces_2d()
  status = finish_tests()
  call MPI_Finalize()
  if (status /= 0) stop 1, quiet = .true.

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
end program test_occupancy
