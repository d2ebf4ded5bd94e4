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
module dpmpm_migrate
  use dpmpm_kinds, only: wp
  use dpmpm_decomp, only: decomp_t, balanced_cuts
  use dpmpm_grid, only: cells_of, axis_cells_of, count_cells_outside
  use dpmpm_particles, only: particle_set_t
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER, MPI_SUM, &
                     MPI_DOUBLE_PRECISION, MPI_STATUS_IGNORE, MPI_PROC_NULL, MPI_Request, MPI_Isend, &
                     MPI_Irecv, MPI_Waitall, MPI_STATUSES_IGNORE
  implicit none
  private
  public :: migrate, check_owned, balance_by_points

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
        if (dec%dims(d) > 1) call migrate_axis(dec, origin, h, ps, d, gone)
      end do
      ! A point that stayed through the sweeps lies in this rank's cells along every
      ! split axis; inside the grid (in_grid), it lies in them along the others as well,
      ! so that only the arrivals that stayed (behind the points of the set before the
      ! sweeps) can be unowned. They are counted before the removal mixes them in.
      if (.not. inside) nkept = 0
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
