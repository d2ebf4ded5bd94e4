!> Gathers to rank 0: the points of a set, sorted by their ids, for comparisons
!> between runs (tests, rank invariance) and for output on one rank.
module dpmpm_gather
  use dpmpm_kinds, only: wp, i8
  use dpmpm_particles, only: particle_set_t
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Comm_size, MPI_Gather, MPI_Gatherv, MPI_INTEGER, &
                     MPI_INTEGER8, MPI_DOUBLE_PRECISION, MPI_Allgather, MPI_Allgatherv
  implicit none
  private
  public :: gather_points, gather_columns, gather_layout, sort_index, global_places

contains

  !> Gather the points of ps from all ranks of comm on rank 0, sorted by id: ids,
  !> positions, velocities and stresses (for comparisons between runs; the fluid's
  !> stress is -p I). Other ranks, and a set never made (ndim 0), get empty arrays.
  subroutine gather_points(ps, nd, comm, ids, x, v, stress)
    type(particle_set_t), intent(in) :: ps
    integer, intent(in) :: nd
    type(MPI_Comm), intent(in) :: comm
    integer(i8), allocatable, intent(out) :: ids(:)
    real(wp), allocatable, intent(out) :: x(:, :), v(:, :), stress(:, :)
    integer, allocatable :: counts(:), displs(:), order(:)
    integer(i8), allocatable :: gid(:)
    real(wp), allocatable :: buf(:, :), gbuf(:, :)
    integer :: m, ntot, rank
    if (ps%ndim == 0) then
      allocate (ids(0), x(nd, 0), v(nd, 0), stress(6, 0))
      return
    end if
    m = 2*nd + 6
    call MPI_Comm_rank(comm, rank)
    call gather_layout(ps%n, comm, counts, displs, ntot)
    allocate (gid(max(ntot, 1)), gbuf(m, max(ntot, 1)), buf(m, ps%n))
    buf(1:nd, :) = ps%x(:, 1:ps%n)
    buf(nd + 1:2*nd, :) = ps%v(:, 1:ps%n)
    buf(2*nd + 1:m, :) = ps%stress(:, 1:ps%n)
    call MPI_Gatherv(ps%id, ps%n, MPI_INTEGER8, gid, counts, displs, MPI_INTEGER8, &
                     0, comm)
    call MPI_Gatherv(buf, m*ps%n, MPI_DOUBLE_PRECISION, gbuf, m*counts, m*displs, &
                     MPI_DOUBLE_PRECISION, 0, comm)
    if (rank /= 0) then
      allocate (ids(0), x(nd, 0), v(nd, 0), stress(6, 0))
      return
    end if
    order = sort_index(gid(1:ntot))
    ids = gid(order)
    x = gbuf(1:nd, order)
    v = gbuf(nd + 1:2*nd, order)
    stress = gbuf(2*nd + 1:m, order)
  end subroutine gather_points

  !> Layout of a gather of n items per rank to rank 0 of comm: counts(r) items of rank r
  !> at offset displs(r), ntot in all (on rank 0; the other ranks get zeros).
  subroutine gather_layout(n, comm, counts, displs, ntot)
    integer, intent(in) :: n
    type(MPI_Comm), intent(in) :: comm
    integer, allocatable, intent(out) :: counts(:), displs(:)
    integer, intent(out) :: ntot
    integer :: nr, rank, k
    call MPI_Comm_size(comm, nr)
    call MPI_Comm_rank(comm, rank)
    allocate (counts(nr), displs(nr))
    counts = 0
    displs = 0
    call MPI_Gather(n, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, 0, comm)
    ntot = 0
    if (rank /= 0) return
    do k = 2, nr
      displs(k) = displs(k - 1) + counts(k - 1)
    end do
    ntot = sum(counts)
  end subroutine gather_layout

  !> The columns buf(:, 1:n) of every rank of comm on rank 0, in rank order: all(m, ntot)
  !> with m = size(buf, 1). The other ranks get all(m, 0) and ntot = 0.
  subroutine gather_columns(buf, n, comm, all, ntot)
    real(wp), intent(in) :: buf(:, :)
    integer, intent(in) :: n
    type(MPI_Comm), intent(in) :: comm
    real(wp), allocatable, intent(out) :: all(:, :)
    integer, intent(out) :: ntot
    integer, allocatable :: counts(:), displs(:)
    integer :: m
    m = size(buf, 1)
    call gather_layout(n, comm, counts, displs, ntot)
    allocate (all(m, ntot))
    call MPI_Gatherv(buf, m*n, MPI_DOUBLE_PRECISION, all, m*counts, m*displs, &
                     MPI_DOUBLE_PRECISION, 0, comm)
  end subroutine gather_columns

  !> The place (1-based) of each of this rank's keys among the keys of all ranks of comm
  !> in ascending order, and how many keys there are in all (on every rank). Keys are
  !> unique over the ranks, so the places do not depend on how the keys are spread.
  subroutine global_places(keys, comm, place, ntot)
    integer(i8), intent(in) :: keys(:)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(out) :: place(:)
    integer, intent(out) :: ntot
    integer, allocatable :: counts(:), displs(:), order(:)
    integer(i8), allocatable :: all(:)
    integer :: nr, rank, j, k
    call MPI_Comm_size(comm, nr)
    call MPI_Comm_rank(comm, rank)
    allocate (counts(nr), displs(nr))
    call MPI_Allgather(size(keys), 1, MPI_INTEGER, counts, 1, MPI_INTEGER, comm)
    displs(1) = 0
    do k = 2, nr
      displs(k) = displs(k - 1) + counts(k - 1)
    end do
    ntot = sum(counts)
    if (ntot == 0) return
    allocate (all(ntot))
    call MPI_Allgatherv(keys, size(keys), MPI_INTEGER8, all, counts, displs, MPI_INTEGER8, comm)
    order = sort_index(all)
    do j = 1, ntot
      k = order(j) - displs(rank + 1)
      if (k >= 1 .and. k <= size(keys)) place(k) = j
    end do
  end subroutine global_places

  !> Permutation that sorts a (merge sort, stable).
  function sort_index(a) result(idx)
    integer(i8), intent(in) :: a(:)
    integer, allocatable :: idx(:), tmp(:)
    integer :: n, width, lo, mid, hi, i, j, k
    n = size(a)
    idx = [(k, k=1, n)]
    allocate (tmp(n))
    width = 1
    do while (width < n)
      lo = 1
      do while (lo <= n)
        mid = min(lo + width - 1, n)
        hi = min(lo + 2*width - 1, n)
        i = lo; j = mid + 1; k = lo
        do while (k <= hi)
          if (j > hi) then
            tmp(k) = idx(i); i = i + 1
          else if (i > mid) then
            tmp(k) = idx(j); j = j + 1
          else if (a(idx(j)) < a(idx(i))) then
            tmp(k) = idx(j); j = j + 1
          else
            tmp(k) = idx(i); i = i + 1
          end if
          k = k + 1
        end do
        lo = lo + 2*width
      end do
      idx = tmp
      width = 2*width
    end do
  end function sort_index

end module dpmpm_gather
