!> Migration of points between the ranks of a Cartesian decomposition.
!>
!> After the positions are updated, every point must live on the rank that owns
!> its cell. migrate sweeps the axes in turn: along axis d, points whose cell
!> lies below clo(d) go to the lower neighbour and points above chi(d) to the
!> upper one (counts first, then the packed points). A point that moved
!> diagonally reaches its owner after the later sweeps. A point travels at most
!> one neighbour per sweep, so a point that jumped further than a neighbour's
!> width, or that left the grid, ends the sweeps on a rank that does not own its
!> cell: it is kept (never dropped) and counted as lost, so that the caller can
!> report its id and position and stop.
!>
!> On nested cuts (decomp_recut_nested) a point leaving this rank's cells along axis d goes
!> to the rank of the adjacent group along d that owns its cells on the axes beyond d,
!> when that rank is one of the neighbours (dec%nbrs); otherwise it moved too far and is
!> kept and counted as lost in the same way. balance_nested splits the grid by nested
!> cuts and sends every point straight to its owner.
module dpmpm_migrate
  use dpmpm_kinds, only: wp
  use dpmpm_decomp, only: decomp_t, balanced_cuts
  use dpmpm_grid, only: cells_of, axis_cells_of, count_cells_outside
  use dpmpm_particles, only: particle_set_t
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER, MPI_SUM, &
                     MPI_DOUBLE_PRECISION, MPI_STATUS_IGNORE, MPI_PROC_NULL, MPI_Request, MPI_Isend, &
                     MPI_Irecv, MPI_Waitall, MPI_STATUSES_IGNORE, MPI_Alltoall, MPI_Alltoallv
  implicit none
  private
  public :: migrate, check_owned, balance_by_points, balance_nested, nested_cuts

  integer, parameter :: tag_count = 21, tag_data = 23

contains

  !> True when cell c lies in the cells owned by this rank.
  pure logical function owns_cell(dec, c) result(yes)
    type(decomp_t), intent(in) :: dec
    integer, intent(in) :: c(3)
    yes = all(c >= dec%clo .and. c <= dec%chi)
  end function owns_cell

  !> Send every point whose cell is not owned here to the rank owning it.
  !> nlost (global, on every rank) counts the points that after the sweeps are
  !> still on a rank that does not own their cell: they moved further than one
  !> neighbour per axis or left the grid. Those points are kept; lost, when
  !> present, returns their local indices on this rank so the caller can report
  !> them. in_grid (default .false.): the caller has kept every point in the grid
  !> (the step's check_inside), so that with one rank holding the whole grid no point
  !> can be lost and the count is 0 without a scan. Collective over dec%comm.
  subroutine migrate(dec, origin, h, ps, nlost, lost, in_grid)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    type(particle_set_t), intent(inout) :: ps
    integer, intent(out) :: nlost
    integer, allocatable, intent(out), optional :: lost(:)
    logical, intent(in), optional :: in_grid
    integer :: d, nkept, nlocal
    logical, allocatable :: gone(:)
    logical :: inside
    ! The points that leave are flagged on each sweep and removed once after the last
    ! (particle_set_t%remove: the last points of the set fill the holes, so that the
    ! removal moves as many points as left). The order of the set changes, and with it
    ! the round-off of the sums over its points, but not what a point carries.
    ! An axis held by one rank has no neighbour on it (the same on every rank); with
    ! none split, no point leaves and there is nothing to flag.
    inside = .false.
    if (present(in_grid)) inside = in_grid
    if (any(dec%dims(1:dec%ndim) > 1)) then
      allocate (gone(ps%n))
      gone = .false.
      nkept = ps%n
      do d = 1, dec%ndim
        if (dec%dims(d) > 1) then
          if (dec%nested) then
            call migrate_axis_nested(dec, origin, h, ps, d, gone)
          else
            call migrate_axis(dec, origin, h, ps, d, gone)
          end if
        end if
      end do
      ! A point that stayed through the sweeps lies in this rank's cells along every
      ! split axis; inside the grid (in_grid), it lies in them along the others as well,
      ! so that only the arrivals that stayed (behind the points of the set before the
      ! sweeps) can be unowned. They are counted before the removal mixes them in. (On
      ! nested cuts a point that moved too far along the axes beyond d stays: all are
      ! looked at.)
      if (.not. inside .or. dec%nested) nkept = 0
      nlocal = count_unowned(dec, origin, h, ps, nkept, gone)
      if (any(gone(1:ps%n))) call ps%remove(gone)
    else if (inside) then
      nlost = 0
      if (present(lost)) allocate (lost(0))
      return
    else
      nlocal = count_cells_outside(origin, h, ps%x, ps%n, dec%ndim, dec%clo, dec%chi)
    end if
    call find_unowned(dec, origin, h, ps, nlost, lost, nlocal)
  end subroutine migrate

  !> Split the grid again so that each rank holds about as many points: along each split
  !> axis, the cuts that share out the points of the slabs across the grid evenly
  !> (balanced_cuts, at least gw cells per rank), the same rank layout and communicator
  !> (decomp_recut); then every point moves to its new owner (migrate until none is left
  !> over, as a point may have to pass several ranks). The points of ps and, when
  !> present, ps2 count alike. changed: the cuts moved (the node fields sized by the
  !> ranges must then be allocated again). Collective; nlost > 0 (points left on ranks
  !> that do not own their cells, or outside the grid) is for the caller to report.
  subroutine balance_by_points(dec, origin, h, gw, ps, ps2, nlost, changed)
    type(decomp_t), intent(inout) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    integer, intent(in) :: gw
    type(particle_set_t), intent(inout) :: ps
    type(particle_set_t), intent(inout), optional :: ps2
    integer, intent(out) :: nlost
    logical, intent(out) :: changed
    integer, allocatable :: cuts(:, :)
    real(wp), allocatable :: w(:)
    integer :: d, k, pass, n, dims(3), ncells(3), nlost2
    dims = dec%dims
    ncells = dec%ncells
    allocate (cuts(0:maxval(dims), 3))
    cuts = 0
    do d = 1, dec%ndim
      n = ncells(d)
      cuts(0:1, d) = [0, n]
      if (dims(d) == 1) cycle
      allocate (w(0:n - 1))
      w = 0.0_wp
      call add_counts(ps)
      if (present(ps2)) call add_counts(ps2)
      call MPI_Allreduce(MPI_IN_PLACE, w, n, MPI_DOUBLE_PRECISION, MPI_SUM, dec%comm)
      cuts(0:dims(d), d) = balanced_cuts(n, dims(d), w, max(gw, 1))
      deallocate (w)
    end do
    nlost = 0
    changed = .false.
    do d = 1, dec%ndim
      changed = changed .or. any(cuts(0:dims(d), d) /= dec%cut(0:dims(d), d))
    end do
    if (.not. changed) return
    call dec%recut(cuts)
    ! A point moves one rank along each axis per call of migrate.
    do pass = 1, maxval(dims)
      call migrate(dec, origin, h, ps, nlost)
      if (present(ps2)) then
        call migrate(dec, origin, h, ps2, nlost2)
        nlost = nlost + nlost2
      end if
      if (nlost == 0) exit
    end do
  contains
    !> The points of a set per slab of cells along axis d, into w.
    subroutine add_counts(set)
      type(particle_set_t), intent(in) :: set
      integer, allocatable :: cell(:)
      allocate (cell(set%n))
      call axis_cells_of(origin, h, set%x, set%n, d, cell)
      do k = 1, set%n
        w(min(max(cell(k), 0), n - 1)) = w(min(max(cell(k), 0), n - 1)) + 1.0_wp
      end do
    end subroutine add_counts
  end subroutine balance_by_points

  !> Nested cuts chosen by the points of ps (and ps2, when present): axis 1 by the points
  !> per cell slab across the grid, as balance_by_points does; axis 2 inside each slab of
  !> axis 1 by the points of that slab per cell layer; axis 3 inside each column (slab,
  !> part of axis 2) by the points of that column per cell. Every part at least minw
  !> cells (balanced_cuts). gcuts(c, d, p1, p2) as decomp_t%gcut. Collective.
  subroutine nested_cuts(dec, origin, h, minw, ps, gcuts, ps2)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    integer, intent(in) :: minw
    type(particle_set_t), intent(in) :: ps
    integer, allocatable, intent(out) :: gcuts(:, :, :, :)
    type(particle_set_t), intent(in), optional :: ps2
    real(wp), allocatable :: w(:, :, :)
    integer :: d, n, p1, p2, dims(3)
    dims = dec%dims
    allocate (gcuts(0:maxval(dims), 3, 0:dims(1) - 1, 0:dims(2) - 1))
    gcuts = 0
    do d = 1, 3
      gcuts(0, d, :, :) = 0
      gcuts(1, d, :, :) = 1
    end do
    do d = 1, dec%ndim
      n = dec%ncells(d)
      gcuts(1, d, :, :) = n
      if (dims(d) == 1) cycle
      ! w(k, p1, p2): the points in cell layer k along d of group (p1, p2)
      allocate (w(0:n - 1, 0:dims(1) - 1, 0:dims(2) - 1))
      w = 0.0_wp
      call add_counts(ps)
      if (present(ps2)) call add_counts(ps2)
      call MPI_Allreduce(MPI_IN_PLACE, w, size(w), MPI_DOUBLE_PRECISION, MPI_SUM, dec%comm)
      do p2 = 0, dims(2) - 1
        do p1 = 0, dims(1) - 1
          if (d == 1) then
            gcuts(0:dims(d), d, p1, p2) = balanced_cuts(n, dims(d), w(:, 0, 0), minw)
          else if (d == 2) then
            gcuts(0:dims(d), d, p1, p2) = balanced_cuts(n, dims(d), w(:, p1, 0), minw)
          else
            gcuts(0:dims(d), d, p1, p2) = balanced_cuts(n, dims(d), w(:, p1, p2), minw)
          end if
        end do
      end do
      deallocate (w)
    end do
  contains
    !> The points of a set per cell along axis d and group of the axes before it, into w
    !> (the cuts of those axes are those of gcuts so far).
    subroutine add_counts(set)
      type(particle_set_t), intent(in) :: set
      integer, allocatable :: cells(:, :)
      integer :: k, q(2), e, c
      allocate (cells(3, set%n))
      call cells_of(origin, h, set%x, set%n, dec%ndim, cells)
      do k = 1, set%n
        q = 0
        do e = 1, min(d - 1, 2)
          q(e) = count(gcuts(1:dims(e) - 1, e, q(1), q(2)) <= cells(e, k))
        end do
        c = min(max(cells(d, k), 0), n - 1)
        w(c, q(1), q(2)) = w(c, q(1), q(2)) + 1.0_wp
      end do
    end subroutine add_counts
  end subroutine nested_cuts

  !> Split the grid by nested cuts (nested_cuts, at least gw cells per part; the same rank
  !> layout and communicator: decomp_recut_nested), then send every point of ps (and ps2)
  !> straight to the rank owning its cell (one all-to-all exchange per set). changed: the
  !> cuts moved (the node fields sized by the ranges must then be allocated again). nlost: the points left outside the cells of their ranks
  !> (outside the grid), for the caller to report. Collective.
  subroutine balance_nested(dec, origin, h, gw, ps, ps2, nlost, changed)
    type(decomp_t), intent(inout) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    integer, intent(in) :: gw
    type(particle_set_t), intent(inout) :: ps
    type(particle_set_t), intent(inout), optional :: ps2
    integer, intent(out) :: nlost
    logical, intent(out) :: changed
    integer, allocatable :: gcuts(:, :, :, :)
    integer :: d, nlost2
    if (present(ps2)) then
      call nested_cuts(dec, origin, h, max(gw, 1), ps, gcuts, ps2)
    else
      call nested_cuts(dec, origin, h, max(gw, 1), ps, gcuts)
    end if
    changed = .false.
    do d = 1, dec%ndim
      changed = changed .or. any(gcuts(0:dec%dims(d), d, :, :) /= dec%gcut(0:dec%dims(d), d, :, :))
    end do
    nlost = 0
    ! (cuts the same in every group as the tensor-product ones before: the same ranges,
    ! now exchanged as nested cuts)
    if (.not. dec%nested) call dec%recut_nested(gcuts)
    if (.not. changed) return
    call dec%recut_nested(gcuts)
    call move_to_owners(dec, origin, h, ps)
    call find_unowned(dec, origin, h, ps, nlost, nlocal=count_cells_outside(origin, h, ps%x, ps%n, &
                                                                          dec%ndim, dec%clo, dec%chi))
    if (present(ps2)) then
      call move_to_owners(dec, origin, h, ps2)
      call find_unowned(dec, origin, h, ps2, nlost2, nlocal=count_cells_outside(origin, h, ps2%x, &
                                                                                ps2%n, dec%ndim, dec%clo, dec%chi))
      nlost = nlost + nlost2
    end if
  end subroutine balance_nested

  !> Send every point of ps to the rank owning its cell (dec%owner_rank; points outside the
  !> grid go to the end ranks), in one all-to-all exchange. The points kept stay in their
  !> order, the arrivals follow by the rank they came from. Collective.
  subroutine move_to_owners(dec, origin, h, ps)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    type(particle_set_t), intent(inout) :: ps
    integer, allocatable :: cells(:, :), dest(:), order(:), scount(:), rcount(:), sdisp(:), rdisp(:)
    integer, allocatable :: sidx(:)
    logical, allocatable :: gone(:)
    real(wp), allocatable :: sbuf(:, :), rbuf(:, :)
    integer :: k, m, r, nsend
    m = ps%nreal_packed()
    allocate (cells(3, ps%n), dest(ps%n), scount(0:dec%nranks - 1), rcount(0:dec%nranks - 1), &
              sdisp(0:dec%nranks - 1), rdisp(0:dec%nranks - 1), gone(ps%n))
    call cells_of(origin, h, ps%x, ps%n, dec%ndim, cells)
    scount = 0
    do k = 1, ps%n
      dest(k) = dec%owner_rank(cells(:, k))
      gone(k) = dest(k) /= dec%rank
      if (gone(k)) scount(dest(k)) = scount(dest(k)) + 1
    end do
    call MPI_Alltoall(scount, 1, MPI_INTEGER, rcount, 1, MPI_INTEGER, dec%comm)
    ! the points leaving, by destination rank and, for each, in the order of the set
    nsend = sum(scount)
    allocate (sidx(nsend), order(0:dec%nranks - 1))
    sdisp(0) = 0
    rdisp(0) = 0
    do r = 1, dec%nranks - 1
      sdisp(r) = sdisp(r - 1) + scount(r - 1)
      rdisp(r) = rdisp(r - 1) + rcount(r - 1)
    end do
    order = sdisp
    do k = 1, ps%n
      if (.not. gone(k)) cycle
      order(dest(k)) = order(dest(k)) + 1
      sidx(order(dest(k))) = k
    end do
    allocate (sbuf(m, nsend), rbuf(m, sum(rcount)))
    call ps%pack_points(sidx, sbuf)
    call MPI_Alltoallv(sbuf, m*scount, m*sdisp, MPI_DOUBLE_PRECISION, rbuf, m*rcount, m*rdisp, &
                       MPI_DOUBLE_PRECISION, dec%comm)
    if (nsend > 0) call ps%remove(gone)
    call ps%unpack_points(rbuf)
  end subroutine move_to_owners

  !> One sweep along axis d on nested cuts: a point whose cell lies below clo(d) (above
  !> chi(d)) goes to the rank of the lower (upper) group along d that owns its cells on the
  !> axes beyond d, when that rank is a neighbour (dec%nbrs(1 or 2, d)); otherwise, and at
  !> the grid faces, it stays. Counts, then the points, with every neighbour; the arrivals
  !> are appended in the order of the neighbour lists. Otherwise as migrate_axis.
  subroutine migrate_axis_nested(dec, origin, h, ps, d, gone)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    type(particle_set_t), intent(inout) :: ps
    integer, intent(in) :: d
    logical, allocatable, intent(inout) :: gone(:)
    type :: pts_buf_t
      real(wp), allocatable :: a(:, :)
    end type pts_buf_t
    type(pts_buf_t), allocatable, asynchronous :: sb(:), rb(:)
    integer, allocatable, asynchronous :: nsend(:), nfrom(:)
    integer, allocatable :: cells(:, :), dest(:), sel(:), nbr_rank(:), q(:)
    logical, allocatable :: grown(:)
    type(MPI_Request), allocatable :: req(:)
    integer :: k, j, m, n0, nn, nlo, nreq, side, qq(3), r
    m = ps%nreal_packed()
    nlo = dec%nbrs(1, d)%n
    nn = nlo + dec%nbrs(2, d)%n
    allocate (nbr_rank(nn))
    nbr_rank(1:nlo) = dec%nbrs(1, d)%rank
    nbr_rank(nlo + 1:nn) = dec%nbrs(2, d)%rank
    allocate (cells(3, ps%n), dest(ps%n))
    call cells_of(origin, h, ps%x, ps%n, dec%ndim, cells)
    ! dest: the place of the receiving rank in nbr_rank, 0 stays
    dest = 0
    do k = 1, ps%n
      if (gone(k)) cycle
      side = 0
      if (cells(d, k) < dec%clo(d) .and. nlo > 0) side = 1
      if (cells(d, k) > dec%chi(d) .and. nn > nlo) side = 2
      if (side == 0) cycle
      qq = dec%owner_in_group(cells(:, k), d, dec%coords(d) + merge(-1, 1, side == 1))
      r = dec%rank_at(qq(1), qq(2), qq(3))
      if (side == 1) then
        q = findloc(nbr_rank(1:nlo), r)
        if (q(1) > 0) dest(k) = q(1)
      else
        q = findloc(nbr_rank(nlo + 1:nn), r)
        if (q(1) > 0) dest(k) = nlo + q(1)
      end if
    end do
    allocate (nsend(nn), nfrom(nn), sb(nn), rb(nn), req(2*nn))
    do j = 1, nn
      sel = pack([(k, k=1, ps%n)], dest(1:ps%n) == j)
      nsend(j) = size(sel)
      allocate (sb(j)%a(m, nsend(j)))
      call ps%pack_points(sel, sb(j)%a)
      gone(sel) = .true.
    end do
    ! Counts with every neighbour, then the points where there are some.
    nfrom = 0
    do j = 1, nn
      ! (tags: the direction of travel, down tag_count, up tag_count + 1)
      call MPI_Irecv(nfrom(j), 1, MPI_INTEGER, nbr_rank(j), tag_count + merge(1, 0, j <= nlo), &
                     dec%comm, req(j))
      call MPI_Isend(nsend(j), 1, MPI_INTEGER, nbr_rank(j), tag_count + merge(0, 1, j <= nlo), &
                     dec%comm, req(nn + j))
    end do
    call MPI_Waitall(2*nn, req, MPI_STATUSES_IGNORE)
    nreq = 0
    do j = 1, nn
      allocate (rb(j)%a(m, nfrom(j)))
      if (nfrom(j) > 0) then
        nreq = nreq + 1
        call MPI_Irecv(rb(j)%a, size(rb(j)%a), MPI_DOUBLE_PRECISION, nbr_rank(j), &
                       tag_data + merge(1, 0, j <= nlo), dec%comm, req(nreq))
      end if
      if (nsend(j) > 0) then
        nreq = nreq + 1
        call MPI_Isend(sb(j)%a, size(sb(j)%a), MPI_DOUBLE_PRECISION, nbr_rank(j), &
                       tag_data + merge(0, 1, j <= nlo), dec%comm, req(nreq))
      end if
    end do
    call MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE)
    n0 = ps%n
    do j = 1, nn
      call ps%unpack_points(rb(j)%a)
    end do
    if (ps%n > size(gone)) then
      allocate (grown(max(ps%n, 2*size(gone))))
      grown(1:n0) = gone(1:n0)
      call move_alloc(grown, gone)
    end if
    gone(n0 + 1:ps%n) = .false.
  end subroutine migrate_axis_nested

  !> Count (globally, on every rank) the points held by ranks that do not own
  !> their cells; bad, when present, returns the local indices on this rank.
  subroutine check_owned(dec, origin, h, ps, nbad, bad)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    type(particle_set_t), intent(in) :: ps
    integer, intent(out) :: nbad
    integer, allocatable, intent(out), optional :: bad(:)
    call find_unowned(dec, origin, h, ps, nbad, bad, &
                      count_cells_outside(origin, h, ps%x, ps%n, dec%ndim, dec%clo, dec%chi))
  end subroutine check_owned

  !> The points of ps after the first nskip (which the caller knows to be owned) that
  !> are not flagged in gone and lie outside the cells of this rank.
  integer function count_unowned(dec, origin, h, ps, nskip, gone) result(nout)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    type(particle_set_t), intent(in) :: ps
    integer, intent(in) :: nskip
    logical, intent(in) :: gone(:)
    integer, allocatable :: idx(:)
    logical, allocatable :: stays(:)
    integer :: k
    if (.not. any(gone(nskip + 1:ps%n))) then
      nout = count_cells_outside(origin, h, ps%x(:, nskip + 1:ps%n), ps%n - nskip, dec%ndim, &
                                 dec%clo, dec%chi)
    else
      stays = .not. gone(nskip + 1:ps%n)
      idx = pack([(k, k=nskip + 1, ps%n)], stays)
      nout = count_cells_outside(origin, h, ps%x(:, idx), size(idx), dec%ndim, dec%clo, dec%chi)
    end if
  end function count_unowned

  !> The global count of the points not in an owned cell, from nlocal, this rank's count;
  !> idx, when present, their local indices on this rank (a scan of the set when
  !> nlocal > 0).
  subroutine find_unowned(dec, origin, h, ps, nglobal, idx, nlocal)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    type(particle_set_t), intent(in) :: ps
    integer, intent(out) :: nglobal
    integer, allocatable, intent(out), optional :: idx(:)
    integer, intent(in) :: nlocal
    logical, allocatable :: bad(:)
    integer, allocatable :: cells(:, :)
    integer :: k
    if (present(idx)) then
      if (nlocal > 0) then
        allocate (bad(ps%n), cells(3, ps%n))
        call cells_of(origin, h, ps%x, ps%n, dec%ndim, cells)
        do k = 1, ps%n
          bad(k) = .not. owns_cell(dec, cells(:, k))
        end do
        idx = pack([(k, k=1, ps%n)], bad)
      else
        allocate (idx(0))
      end if
    end if
    nglobal = nlocal
    call MPI_Allreduce(MPI_IN_PLACE, nglobal, 1, MPI_INTEGER, MPI_SUM, dec%comm)
  end subroutine find_unowned

  !> One sweep along axis d: points below clo(d) go to the lower neighbour,
  !> points above chi(d) to the upper one. At the grid faces there is no
  !> neighbour and points outside the grid stay where they are. Points already
  !> gone (sent on an earlier sweep) are skipped; the points sent now are flagged in
  !> gone, and the arrivals, appended to the set, extend it as staying.
  subroutine migrate_axis(dec, origin, h, ps, d, gone)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(in) :: origin(3), h(3)
    type(particle_set_t), intent(inout) :: ps
    integer, intent(in) :: d
    logical, allocatable, intent(inout) :: gone(:)
    integer, allocatable :: to_lo(:), to_hi(:)
    logical, allocatable :: grown(:)
    ! (the buffers of the nonblocking exchanges)
    real(wp), allocatable, asynchronous :: slo(:, :), shi(:, :), rlo(:, :), rhi(:, :)
    integer, asynchronous :: nfrom_lo, nfrom_hi, nsend(2)
    integer :: k, m, n0, nlo, nhi
    integer, allocatable :: dest(:), cell(:)
    integer :: go_lo, go_hi
    type(MPI_Request) :: req(4)
    integer :: nreq
    m = ps%nreal_packed()
    allocate (dest(ps%n), cell(ps%n))
    ! the cells along d only
    call axis_cells_of(origin, h, ps%x, ps%n, d, cell)
    ! dest: -1 lower neighbour, +1 upper neighbour, 0 stays (in a loop without a branch)
    go_lo = merge(-1, 0, dec%nbr_lo(d) /= MPI_PROC_NULL)
    go_hi = merge(1, 0, dec%nbr_hi(d) /= MPI_PROC_NULL)
    do k = 1, ps%n
      dest(k) = merge(go_lo, 0, cell(k) < dec%clo(d)) + merge(go_hi, 0, cell(k) > dec%chi(d))
    end do
    ! (the points sent on an earlier sweep stay where the set holds them until the end)
    if (any(gone(1:ps%n))) then
      where (gone(1:ps%n)) dest(1:ps%n) = 0
    end if
    nlo = count(dest(1:ps%n) == -1)
    nhi = count(dest(1:ps%n) == 1)
    ! the points leaving, in the order of the set
    allocate (to_lo(nlo), to_hi(nhi))
    nlo = 0
    nhi = 0
    if (size(to_lo) + size(to_hi) > 0) then
      do k = 1, ps%n
        if (dest(k) == -1) then
          nlo = nlo + 1
          to_lo(nlo) = k
          gone(k) = .true.
        else if (dest(k) == 1) then
          nhi = nhi + 1
          to_hi(nhi) = k
          gone(k) = .true.
        end if
      end do
    end if
    allocate (slo(m, size(to_lo)), shi(m, size(to_hi)))
    call ps%pack_points(to_lo, slo)
    call ps%pack_points(to_hi, shi)

    ! Counts, both directions in one round: a missing neighbour (MPI_PROC_NULL) leaves the
    ! receive count at 0. The points themselves go only between neighbours that have some
    ! to send either way (both ends know both counts): in most steps none crosses a cut.
    nfrom_lo = 0
    nfrom_hi = 0
    call MPI_Irecv(nfrom_hi, 1, MPI_INTEGER, dec%nbr_hi(d), tag_count, dec%comm, req(1))
    call MPI_Irecv(nfrom_lo, 1, MPI_INTEGER, dec%nbr_lo(d), tag_count + 1, dec%comm, req(2))
    ! (the counts sent, apart from the counters of the loop above)
    nsend = [nlo, nhi]
    call MPI_Isend(nsend(1), 1, MPI_INTEGER, dec%nbr_lo(d), tag_count, dec%comm, req(3))
    call MPI_Isend(nsend(2), 1, MPI_INTEGER, dec%nbr_hi(d), tag_count + 1, dec%comm, req(4))
    call MPI_Waitall(4, req, MPI_STATUSES_IGNORE)

    allocate (rlo(m, nfrom_lo), rhi(m, nfrom_hi))
    nreq = 0
    if (nlo + nfrom_lo > 0) then
      call MPI_Irecv(rlo, size(rlo), MPI_DOUBLE_PRECISION, dec%nbr_lo(d), tag_data + 1, dec%comm, req(nreq + 1))
      call MPI_Isend(slo, size(slo), MPI_DOUBLE_PRECISION, dec%nbr_lo(d), tag_data, dec%comm, req(nreq + 2))
      nreq = nreq + 2
    end if
    if (nhi + nfrom_hi > 0) then
      call MPI_Irecv(rhi, size(rhi), MPI_DOUBLE_PRECISION, dec%nbr_hi(d), tag_data, dec%comm, req(nreq + 1))
      call MPI_Isend(shi, size(shi), MPI_DOUBLE_PRECISION, dec%nbr_hi(d), tag_data + 1, dec%comm, req(nreq + 2))
      nreq = nreq + 2
    end if
    call MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE)

    n0 = ps%n
    call ps%unpack_points(rlo)
    call ps%unpack_points(rhi)
    if (ps%n > size(gone)) then
      allocate (grown(max(ps%n, 2*size(gone))))
      grown(1:n0) = gone(1:n0)
      call move_alloc(grown, gone)
    end if
    gone(n0 + 1:ps%n) = .false.
  end subroutine migrate_axis

end module dpmpm_migrate
