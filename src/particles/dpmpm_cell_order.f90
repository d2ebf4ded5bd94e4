!> The points of a set in the order of the grid cells that hold them. The transfers
!> between points and nodes then read and write the node fields nearly in the order
!> they are stored, as they do for the points as generated; points of a flowing body
!> lose that order as they move, and the transfers slow down with the cache misses.
module dpmpm_cell_order
  use dpmpm_kinds, only: wp, i8
  use dpmpm_particles, only: particle_set_t
  use dpmpm_grid, only: cells_of
  implicit none
  private
  public :: cell_order, sort_by_cell

contains

  !> The permutation that sorts points 1..n of ps by the cell holding each (cells
  !> clo..chi, the first axis fastest; a position outside them counts in the nearest)
  !> and, within a cell, by id. It depends on the points' positions and ids only, not
  !> on their order before, so that runs that reach the same points in another order
  !> (a restart) continue in the same order.
  function cell_order(ps, origin, h, clo, chi) result(order)
    type(particle_set_t), intent(in) :: ps
    real(wp), intent(in) :: origin(3), h(3)
    integer, intent(in) :: clo(3), chi(3)
    integer, allocatable :: order(:)
    integer, allocatable :: key(:), next(:), cells(:, :)
    integer :: n, nd, p, d, c, w(3), ncell, k, m, q, first
    integer(i8) :: idq
    n = ps%n
    nd = ps%ndim
    w = 1
    w(1:nd) = chi(1:nd) - clo(1:nd) + 1
    ncell = product(w)
    allocate (key(n), order(n), next(ncell + 1), cells(3, n))
    call cells_of(origin, h, ps%x, n, nd, cells)
    do p = 1, n
      c = 0
      do d = nd, 1, -1
        c = c*w(d) + min(max(cells(d, p), clo(d)), chi(d)) - clo(d)
      end do
      key(p) = c + 1
    end do
    ! Counting sort by cell (stable): next(c) is where the next point of cell c goes.
    next = 0
    do p = 1, n
      next(key(p) + 1) = next(key(p) + 1) + 1
    end do
    next(1) = 1
    do c = 2, ncell + 1
      next(c) = next(c) + next(c - 1)
    end do
    do p = 1, n
      order(next(key(p))) = p
      next(key(p)) = next(key(p)) + 1
    end do
    ! Within each cell by id (insertion sort: a cell holds a few points). Cell c now
    ! ends at next(c) - 1.
    first = 1
    do c = 1, ncell
      do k = first + 1, next(c) - 1
        q = order(k)
        idq = ps%id(q)
        m = k - 1
        do while (m >= first)
          if (ps%id(order(m)) <= idq) exit
          order(m + 1) = order(m)
          m = m - 1
        end do
        order(m + 1) = q
      end do
      first = next(c)
    end do
  end function cell_order

  !> Put the points of ps in cell order (cell_order).
  subroutine sort_by_cell(ps, origin, h, clo, chi)
    type(particle_set_t), intent(inout) :: ps
    real(wp), intent(in) :: origin(3), h(3)
    integer, intent(in) :: clo(3), chi(3)
    if (ps%n < 2) return
    call ps%permute(cell_order(ps, origin, h, clo, chi))
  end subroutine sort_by_cell

end module dpmpm_cell_order
