!> Cartesian domain decomposition of a regular grid of cells, with ghost nodes.
!>
!> Cells 0..ncells(d)-1 along each axis are split as evenly as possible (the
!> remainder goes to the first ranks). A rank owns the cells clo..chi and the
!> nodes with the same indices; the first and last rank along an axis also own
!> the gw exterior nodes beyond the grid faces that wide kernels reach. Every
!> rank stores the nodes clo-gw .. chi+gw. halo_sum adds ghost values into their
!> owners; halo_copy copies owners' values to the ghosts. Both sweep the axes in
!> turn over the full extent of the other axes, so edges and corners are exact.
!>
!> Nested cuts (decomp_recut_nested, &grid balance = 'nested'): axis 1 is cut once for the
!> whole grid, axis 2 separately inside each slab of axis 1, axis 3 separately inside each
!> column (slab, part of axis 2); the rank layout and coordinates stay. Along axis d the
!> neighbours are then the ranks with the same coords(1:d-1) and coords(d) +- 1, several
!> where their cuts of the axes beyond d differ from this rank's; nbrs keeps those whose
!> ranges meet this rank's on the axes beyond d. halo_sum then sweeps the axes from the
!> last to the first, each over the stored extent of the axes before it and the owned
!> extent of the axes after it, split by the owners there; halo_copy sweeps from the first
!> to the last, each over the stored extent of the other axes, every part from its owner.
module dpmpm_decomp
  use dpmpm_kinds, only: wp
  use mpi_f08, only: MPI_Comm, MPI_Comm_dup, MPI_Comm_free, MPI_Comm_rank, MPI_Comm_size, &
                     MPI_Dims_create, MPI_Cart_create, MPI_Cart_coords, MPI_Cart_shift, &
                     MPI_Sendrecv, MPI_STATUS_IGNORE, MPI_PROC_NULL, MPI_COMM_NULL, &
                     MPI_DOUBLE_PRECISION, MPI_Cart_rank, MPI_Request, MPI_Isend, MPI_Irecv, &
                     MPI_Waitall, MPI_STATUSES_IGNORE, operator(/=)
  implicit none
  private
  public :: decomp_t, nbr_list_t, split_extent, balanced_cuts

  !> The ranks of the adjacent group along one axis and side that exchange with this rank
  !> (nested cuts), with their owned and stored node ranges.
  type :: nbr_list_t
    integer :: n = 0
    integer, allocatable :: rank(:)
    integer, allocatable :: olo(:, :), ohi(:, :), alo(:, :), ahi(:, :)  !< (3, n)
  end type nbr_list_t

  !> One message of a nested exchange.
  type :: msg_t
    real(wp), allocatable :: a(:)
  end type msg_t

  !> Decomposition of the grid over the ranks of one communicator.
  type :: decomp_t
    type(MPI_Comm) :: comm = MPI_COMM_NULL  !< Cartesian communicator (owned)
    integer :: rank = 0, nranks = 1, ndim = 1
    integer :: dims(3) = 1, coords(3) = 0
    integer :: ncells(3) = 1                !< global cells per axis (1 on unused axes)
    integer :: gw(3) = 0                    !< ghost width per axis (0 on unused axes)
    integer :: clo(3) = 0, chi(3) = 0       !< owned cells (global, 0-based)
    integer :: olo(3) = 0, ohi(3) = 0       !< owned nodes, exterior nodes included
    integer :: alo(3) = 0, ahi(3) = 0       !< stored nodes (owned + ghosts)
    !> neighbour ranks, MPI_PROC_NULL at the grid faces (nested cuts: one of those along the
    !> axis, MPI_Cart_shift's; nbrs lists them all)
    integer :: nbr_lo(3), nbr_hi(3)
    !> cut(c, d): first cell of part c along axis d (c = 0 .. dims(d); cut(dims(d), d) = ncells(d))
    !> (nested cuts: the cuts of this rank's group along each axis)
    integer, allocatable :: cut(:, :)
    !> The cuts are nested (decomp_recut_nested): those of axis d depend on coords(1:d-1).
    logical :: nested = .false.
    !> gcut(c, d, p1, p2): first cell of part c along axis d in the group with coords(1) = p1
    !> (axes 2 and 3) and coords(2) = p2 (axis 3); the same for every p1, p2 that the axis
    !> does not depend on (tensor-product cuts: the same everywhere).
    integer, allocatable :: gcut(:, :, :, :)
    !> rank_at(p1, p2, p3): the rank at those coordinates
    integer, allocatable :: rank_at(:, :, :)
    !> nbrs(side, d): nested cuts, the neighbours along axis d below (side 1) and above (2)
    type(nbr_list_t) :: nbrs(2, 3)
  contains
    procedure :: init => decomp_init
    procedure :: free => decomp_free
    procedure :: recut => decomp_recut
    procedure :: recut_nested => decomp_recut_nested
    procedure :: owner_coord => decomp_owner_coord
    procedure :: owner_rank => decomp_owner_rank
    procedure :: owner_in_group => decomp_owner_in_group
    procedure :: ranges_of => decomp_ranges_of
    procedure :: halo_sum => decomp_halo_sum
    procedure :: halo_copy => decomp_halo_copy
  end type decomp_t

contains

  !> First cell of part c (0-based) when n cells are split into p parts, remainder first.
  pure integer function split_extent(n, p, c) result(first)
    integer, intent(in) :: n, p, c
    first = c*(n/p) + min(c, mod(n, p))
  end function split_extent

  !> Cuts of n cells into p parts of about equal weight: first(c) is the first cell of
  !> part c (first(0) = 0, first(p) = n), w(k) the weight of cell k (0-based; the points
  !> in the cells of a slab across the grid). Part c starts at the cell boundary nearest
  !> c/p of the total (a cell goes to the upper part when the running sum at its middle
  !> reaches c/p of the total), then every part is widened to at least minw cells
  !> (n >= p minw). With no weight at all the cells are split evenly.
  pure function balanced_cuts(n, p, w, minw) result(first)
    integer, intent(in) :: n, p, minw
    real(wp), intent(in) :: w(0:)
    integer :: first(0:p)
    real(wp) :: total, run
    integer :: c, k
    total = sum(w(0:n - 1))
    do c = 0, p
      first(c) = split_extent(n, p, c)
    end do
    if (total > 0.0_wp) then
      k = 0
      run = 0.0_wp
      do c = 1, p - 1
        do while (k < n .and. run + 0.5_wp*w(min(k, n - 1)) < total*real(c, wp)/real(p, wp))
          run = run + w(k)
          k = k + 1
        end do
        first(c) = k
      end do
    end if
    ! at least minw cells per part, from the lower end, then from the upper one
    do c = 1, p - 1
      first(c) = max(first(c), first(c - 1) + minw)
    end do
    do c = p - 1, 1, -1
      first(c) = min(first(c), first(c + 1) - minw)
    end do
  end function balanced_cuts

  !> Build the decomposition. dims_in(d) = 0 lets MPI_Dims_create choose.
  !> The caller has checked that every rank gets at least gw cells per axis. The cells
  !> are split evenly (split_extent); decomp_recut sets other cuts later.
  subroutine decomp_init(self, comm, ndim, ncells, gw, dims_in)
    class(decomp_t), intent(inout) :: self
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: ndim, ncells(3), gw
    integer, intent(in) :: dims_in(3)
    logical :: periods(3)
    integer :: d, c, i, j, k
    integer, allocatable :: first(:, :)
    call self%free()
    self%ndim = ndim
    call MPI_Comm_size(comm, self%nranks)
    self%dims = 1
    self%dims(1:ndim) = dims_in(1:ndim)
    call MPI_Dims_create(self%nranks, ndim, self%dims(1:ndim))
    periods = .false.
    call MPI_Cart_create(comm, ndim, self%dims(1:ndim), periods(1:ndim), .false., self%comm)
    call MPI_Comm_rank(self%comm, self%rank)
    self%coords = 0
    call MPI_Cart_coords(self%comm, self%rank, ndim, self%coords(1:ndim))
    self%ncells = 1
    self%ncells(1:ndim) = ncells(1:ndim)
    self%gw = 0
    self%gw(1:ndim) = gw
    self%nbr_lo = MPI_PROC_NULL
    self%nbr_hi = MPI_PROC_NULL
    do d = 1, 3
      if (d <= ndim) call MPI_Cart_shift(self%comm, d - 1, 1, self%nbr_lo(d), self%nbr_hi(d))
    end do
    if (allocated(self%cut)) deallocate (self%cut)
    allocate (self%cut(0:maxval(self%dims), 3), first(0:maxval(self%dims), 3))
    first = 0
    do d = 1, 3
      do c = 0, self%dims(d)
        first(c, d) = split_extent(self%ncells(d), self%dims(d), c)
      end do
    end do
    self%cut = first
    if (allocated(self%rank_at)) deallocate (self%rank_at)
    allocate (self%rank_at(0:self%dims(1) - 1, 0:self%dims(2) - 1, 0:self%dims(3) - 1))
    do k = 0, self%dims(3) - 1
      do j = 0, self%dims(2) - 1
        do i = 0, self%dims(1) - 1
          call MPI_Cart_rank(self%comm, [i, j, k], self%rank_at(i, j, k))
        end do
      end do
    end do
    if (allocated(self%gcut)) deallocate (self%gcut)
    allocate (self%gcut(0:maxval(self%dims), 3, 0:self%dims(1) - 1, 0:self%dims(2) - 1))
    self%nested = .false.
    call self%recut(first)
  end subroutine decomp_init

  !> The owned and stored ranges from new cuts (cuts(c, d), c = 0 .. dims(d), the first
  !> cell of part c along axis d; axes beyond ndim are left one cell), with the same rank
  !> layout and communicator. Every node field sized by the old ranges must be allocated
  !> again, and every point migrated (balance_by_points).
  subroutine decomp_recut(self, cuts)
    class(decomp_t), intent(inout) :: self
    integer, intent(in) :: cuts(0:, :)
    integer :: d, c, i, j
    do d = 1, self%ndim
      do c = 0, self%dims(d)
        self%cut(c, d) = cuts(c, d)
      end do
    end do
    if (allocated(self%gcut)) then
      self%nested = .false.
      do j = 0, self%dims(2) - 1
        do i = 0, self%dims(1) - 1
          self%gcut(:, :, i, j) = self%cut
        end do
      end do
    end if
    do d = 1, 3
      if (d <= self%ndim) then
        self%clo(d) = self%cut(self%coords(d), d)
        self%chi(d) = self%cut(self%coords(d) + 1, d) - 1
      else
        self%clo(d) = 0
        self%chi(d) = 0
      end if
      self%alo(d) = self%clo(d) - self%gw(d)
      self%ahi(d) = self%chi(d) + self%gw(d)
      self%olo(d) = self%clo(d)
      self%ohi(d) = self%chi(d)
      if (self%coords(d) == 0) self%olo(d) = self%alo(d)
      if (self%coords(d) == self%dims(d) - 1) self%ohi(d) = self%ahi(d)
    end do
  end subroutine decomp_recut

  !> Nested cuts: gcuts(c, d, p1, p2) as gcut (the first cell of part c along axis d in the
  !> group coords(1) = p1, coords(2) = p2; filled for every p1, p2). The owned and stored
  !> ranges of this rank, and the neighbours along each axis, from them; the same rank
  !> layout and communicator. As after decomp_recut, every node field must be allocated
  !> again and every point moved to its owner.
  subroutine decomp_recut_nested(self, gcuts)
    class(decomp_t), intent(inout) :: self
    integer, intent(in) :: gcuts(0:, :, 0:, 0:)
    integer :: d, side, r, q(3), slo(3), shi(3), qlo(3), qhi(3), tlo(3), thi(3), n, e
    integer :: glo(3), ghi(3)
    logical :: meets
    integer, allocatable :: keep(:)
    self%nested = .true.
    self%gcut = 0
    do d = 1, self%ndim
      self%gcut(0:self%dims(d), d, :, :) = gcuts(0:self%dims(d), d, 0:self%dims(1) - 1, 0:self%dims(2) - 1)
    end do
    do d = 1, self%ndim
      self%cut(0:self%dims(d), d) = self%gcut(0:self%dims(d), d, self%coords(1), self%coords(2))
    end do
    call self%ranges_of(self%coords, self%clo, self%chi, self%olo, self%ohi, self%alo, self%ahi)
    ! The neighbours: the ranks of the adjacent group along d whose owned nodes meet this
    ! rank's stored ones, or whose stored nodes meet this rank's owned ones, on every
    ! axis beyond d (the two are the same relation seen from either end).
    allocate (keep(self%nranks))
    do d = 1, 3
      do side = 1, 2
        n = 0
        if (d <= self%ndim) then
          do r = 0, self%nranks - 1
            q = coords_of(self, r)
            if (any(q(1:d - 1) /= self%coords(1:d - 1))) cycle
            if (q(d) /= self%coords(d) + merge(-1, 1, side == 1)) cycle
            call self%ranges_of(q, slo, shi, qlo, qhi, tlo, thi)
            meets = .true.
            do e = d + 1, self%ndim
              glo(e) = max(qlo(e), self%alo(e)); ghi(e) = min(qhi(e), self%ahi(e))
              if (glo(e) > ghi(e)) then
                glo(e) = max(tlo(e), self%olo(e)); ghi(e) = min(thi(e), self%ohi(e))
              end if
              meets = meets .and. glo(e) <= ghi(e)
            end do
            if (.not. meets) cycle
            n = n + 1
            keep(n) = r
          end do
        end if
        associate (nb => self%nbrs(side, d))
          if (allocated(nb%rank)) deallocate (nb%rank, nb%olo, nb%ohi, nb%alo, nb%ahi)
          nb%n = n
          allocate (nb%rank(n), nb%olo(3, n), nb%ohi(3, n), nb%alo(3, n), nb%ahi(3, n))
          do r = 1, n
            nb%rank(r) = keep(r)
            call self%ranges_of(coords_of(self, keep(r)), slo, shi, nb%olo(:, r), nb%ohi(:, r), &
                                nb%alo(:, r), nb%ahi(:, r))
          end do
        end associate
      end do
    end do
  end subroutine decomp_recut_nested

  !> The coordinates of rank r (from the table of ranks).
  pure function coords_of(self, r) result(q)
    type(decomp_t), intent(in) :: self
    integer, intent(in) :: r
    integer :: q(3)
    integer :: i, j, k
    q = 0
    do k = 0, self%dims(3) - 1
      do j = 0, self%dims(2) - 1
        do i = 0, self%dims(1) - 1
          if (self%rank_at(i, j, k) == r) q = [i, j, k]
        end do
      end do
    end do
  end function coords_of

  !> The owned cells, owned nodes and stored nodes of the rank at coordinates q, from gcut.
  pure subroutine decomp_ranges_of(self, q, clo, chi, olo, ohi, alo, ahi)
    class(decomp_t), intent(in) :: self
    integer, intent(in) :: q(3)
    integer, intent(out) :: clo(3), chi(3), olo(3), ohi(3), alo(3), ahi(3)
    integer :: d
    do d = 1, 3
      if (d <= self%ndim) then
        clo(d) = self%gcut(q(d), d, q(1), q(2))
        chi(d) = self%gcut(q(d) + 1, d, q(1), q(2)) - 1
      else
        clo(d) = 0
        chi(d) = 0
      end if
      alo(d) = clo(d) - self%gw(d)
      ahi(d) = chi(d) + self%gw(d)
      olo(d) = clo(d)
      ohi(d) = chi(d)
      if (q(d) == 0) olo(d) = alo(d)
      if (q(d) == self%dims(d) - 1) ohi(d) = ahi(d)
    end do
  end subroutine decomp_ranges_of

  !> The coordinates of the rank that owns cell c among the ranks with coords(1:d-1) of
  !> this rank and coords(d) = p (cells outside the grid map to the end ranks): along the
  !> axes beyond d by the cuts of that group.
  pure function decomp_owner_in_group(self, c, d, p) result(q)
    class(decomp_t), intent(in) :: self
    integer, intent(in) :: c(3), d, p
    integer :: q(3)
    integer :: e
    q = 0
    q(1:d - 1) = self%coords(1:d - 1)
    q(d) = p
    do e = d + 1, self%ndim
      q(e) = count(self%gcut(1:self%dims(e) - 1, e, q(1), q(2)) <= c(e))
    end do
  end function decomp_owner_in_group

  !> The rank that owns cell c (cells outside the grid map to the end ranks).
  pure integer function decomp_owner_rank(self, c) result(r)
    class(decomp_t), intent(in) :: self
    integer, intent(in) :: c(3)
    integer :: q(3)
    q = self%owner_in_group(c, 1, count(self%gcut(1:self%dims(1) - 1, 1, 0, 0) <= c(1)))
    r = self%rank_at(q(1), q(2), q(3))
  end function decomp_owner_rank

  !> Release the Cartesian communicator.
  subroutine decomp_free(self)
    class(decomp_t), intent(inout) :: self
    if (self%comm /= MPI_COMM_NULL) call MPI_Comm_free(self%comm)
    self%comm = MPI_COMM_NULL
  end subroutine decomp_free

  !> Coordinate along axis d of the rank owning global cell c (cells outside the grid
  !> map to the end ranks).
  pure integer function decomp_owner_coord(self, d, c) result(k)
    class(decomp_t), intent(in) :: self
    integer, intent(in) :: d, c
    k = count(self%cut(1:self%dims(d) - 1, d) <= c)
  end function decomp_owner_coord

  !> Ghost -> owner: add every ghost node's value into its owner, then zero the ghosts.
  !> f(ncomp, alo(1):ahi(1), alo(2):ahi(2), alo(3):ahi(3)).
  subroutine decomp_halo_sum(self, f)
    class(decomp_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    call halo_exchange(self, f, .true.)
  end subroutine decomp_halo_sum

  !> Owner -> ghost: copy owners' values into the ghost nodes of the neighbours.
  subroutine decomp_halo_copy(self, f)
    class(decomp_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    call halo_exchange(self, f, .false.)
  end subroutine decomp_halo_copy

  !> The axis by axis exchange of decomp_halo_sum (add = .true.) and decomp_halo_copy: a
  !> nested split sums its axes last to first (the reverse of its copy), a slab split takes
  !> them in order.
  subroutine halo_exchange(self, f, add)
    class(decomp_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    logical, intent(in) :: add
    integer :: d
    if (self%nested .and. add) then
      do d = self%ndim, 1, -1
        call exchange_axis_nested(self, f, d, add)
      end do
    else if (self%nested) then
      do d = 1, self%ndim
        call exchange_axis_nested(self, f, d, add)
      end do
    else
      do d = 1, self%ndim
        call exchange_axis(self, f, d, add)
      end do
    end if
  end subroutine halo_exchange

  !> One axis of a halo exchange. For a sum, the ghost slabs travel to the
  !> neighbour that owns them and are added there; for a copy, the owned edge
  !> slabs travel to the neighbour's ghosts and overwrite them.
  subroutine exchange_axis(self, f, d, add)
    type(decomp_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    integer, intent(in) :: d
    logical, intent(in) :: add
    integer :: g, dir, send_to, recv_from
    integer :: slo(3), shi(3), rlo(3), rhi(3), n
    real(wp), allocatable :: sbuf(:), rbuf(:)
    g = self%gw(d)
    if (g == 0) return
    do dir = 1, 2
      slo = self%alo; shi = self%ahi
      rlo = self%alo; rhi = self%ahi
      if (dir == 1) then        ! towards the lower neighbour
        send_to = self%nbr_lo(d); recv_from = self%nbr_hi(d)
        if (add) then
          slo(d) = self%clo(d) - g; shi(d) = self%clo(d) - 1
          rlo(d) = self%chi(d) - g + 1; rhi(d) = self%chi(d)
        else
          slo(d) = self%clo(d); shi(d) = self%clo(d) + g - 1
          rlo(d) = self%chi(d) + 1; rhi(d) = self%chi(d) + g
        end if
      else                      ! towards the upper neighbour
        send_to = self%nbr_hi(d); recv_from = self%nbr_lo(d)
        if (add) then
          slo(d) = self%chi(d) + 1; shi(d) = self%chi(d) + g
          rlo(d) = self%clo(d); rhi(d) = self%clo(d) + g - 1
        else
          slo(d) = self%chi(d) - g + 1; shi(d) = self%chi(d)
          rlo(d) = self%clo(d) - g; rhi(d) = self%clo(d) - 1
        end if
      end if
      n = size(f, 1)*product(shi - slo + 1)
      allocate (sbuf(n), rbuf(n))
      if (send_to /= MPI_PROC_NULL) then
        sbuf = reshape(f(:, slo(1):shi(1), slo(2):shi(2), slo(3):shi(3)), [n])
      else
        sbuf = 0.0_wp
      end if
      call MPI_Sendrecv(sbuf, n, MPI_DOUBLE_PRECISION, send_to, 7 + dir, &
                        rbuf, n, MPI_DOUBLE_PRECISION, recv_from, 7 + dir, self%comm, &
                        MPI_STATUS_IGNORE)
      if (add .and. send_to /= MPI_PROC_NULL) f(:, slo(1):shi(1), slo(2):shi(2), slo(3):shi(3)) = 0.0_wp
      if (recv_from /= MPI_PROC_NULL) then
        if (add) then
          f(:, rlo(1):rhi(1), rlo(2):rhi(2), rlo(3):rhi(3)) = &
            f(:, rlo(1):rhi(1), rlo(2):rhi(2), rlo(3):rhi(3)) + &
            reshape(rbuf, [size(f, 1), rhi(1) - rlo(1) + 1, rhi(2) - rlo(2) + 1, rhi(3) - rlo(3) + 1])
        else
          f(:, rlo(1):rhi(1), rlo(2):rhi(2), rlo(3):rhi(3)) = &
            reshape(rbuf, [size(f, 1), rhi(1) - rlo(1) + 1, rhi(2) - rlo(2) + 1, rhi(3) - rlo(3) + 1])
        end if
      end if
      deallocate (sbuf, rbuf)
    end do
  end subroutine exchange_axis

  !> One axis of a halo exchange on nested cuts, with every neighbour of nbrs(:, d).
  !> A sum (axes swept from the last to the first): the ghost layers along d, over the
  !> stored extent of the axes before d and the owned extent of the axes after it (where
  !> the earlier sweeps left every value), split by the receivers' owned ranges there, are
  !> added into the receivers' owned layers at the same nodes, then zeroed. A copy (axes
  !> swept from the first to the last): the ghost layers along d, over the stored extent
  !> of every other axis, each part from the neighbour that owns it on the axes after d.
  !> The ranks of the adjacent group have the same ranges on the axes before d.
  subroutine exchange_axis_nested(self, f, d, add)
    type(decomp_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    integer, intent(in) :: d
    logical, intent(in) :: add
    integer :: g, side, k, nreq, nm, m, e
    integer :: slo(3), shi(3), rlo(3), rhi(3), qolo(3), qohi(3), qalo(3), qahi(3)
    integer, allocatable :: plo(:, :), phi(:, :)
    type(msg_t), allocatable, asynchronous :: sb(:), rb(:)
    type(MPI_Request), allocatable :: req(:)
    logical :: empty
    g = self%gw(d)
    if (g == 0) return
    nm = self%nbrs(1, d)%n + self%nbrs(2, d)%n
    allocate (sb(nm), rb(nm), req(2*nm), plo(3, nm), phi(3, nm))
    nreq = 0
    m = 0
    do side = 1, 2
      do k = 1, self%nbrs(side, d)%n
        m = m + 1
        ! the node box sent to neighbour k (slo..shi) and received from it (rlo..rhi)
        slo = self%alo; shi = self%ahi
        rlo = self%alo; rhi = self%ahi
        qolo = self%nbrs(side, d)%olo(:, k); qohi = self%nbrs(side, d)%ohi(:, k)
        qalo = self%nbrs(side, d)%alo(:, k); qahi = self%nbrs(side, d)%ahi(:, k)
        do e = d + 1, self%ndim
          if (add) then
            slo(e) = max(self%olo(e), qolo(e)); shi(e) = min(self%ohi(e), qohi(e))
            rlo(e) = slo(e); rhi(e) = shi(e)
          else
            slo(e) = max(self%olo(e), qalo(e)); shi(e) = min(self%ohi(e), qahi(e))
            rlo(e) = max(self%alo(e), qolo(e)); rhi(e) = min(self%ahi(e), qohi(e))
          end if
        end do
        if (side == 1) then
          if (add) then
            slo(d) = self%clo(d) - g; shi(d) = self%clo(d) - 1
            rlo(d) = self%clo(d); rhi(d) = self%clo(d) + g - 1
          else
            slo(d) = self%clo(d); shi(d) = self%clo(d) + g - 1
            rlo(d) = self%clo(d) - g; rhi(d) = self%clo(d) - 1
          end if
        else
          if (add) then
            slo(d) = self%chi(d) + 1; shi(d) = self%chi(d) + g
            rlo(d) = self%chi(d) - g + 1; rhi(d) = self%chi(d)
          else
            slo(d) = self%chi(d) - g + 1; shi(d) = self%chi(d)
            rlo(d) = self%chi(d) + 1; rhi(d) = self%chi(d) + g
          end if
        end if
        plo(:, m) = rlo; phi(:, m) = rhi
        ! (an empty box on either end is empty on both: no message)
        empty = any(shi < slo)
        if (.not. empty) then
          allocate (sb(m)%a(size(f, 1)*product(shi - slo + 1)))
          sb(m)%a = reshape(f(:, slo(1):shi(1), slo(2):shi(2), slo(3):shi(3)), [size(sb(m)%a)])
          nreq = nreq + 1
          ! (tag: the direction of travel, down 41, up 42)
          call MPI_Isend(sb(m)%a, size(sb(m)%a), MPI_DOUBLE_PRECISION, &
                         self%nbrs(side, d)%rank(k), 40 + side, self%comm, req(nreq))
        end if
        if (all(rhi >= rlo)) then
          allocate (rb(m)%a(size(f, 1)*product(rhi - rlo + 1)))
          nreq = nreq + 1
          call MPI_Irecv(rb(m)%a, size(rb(m)%a), MPI_DOUBLE_PRECISION, &
                         self%nbrs(side, d)%rank(k), 43 - side, self%comm, req(nreq))
        end if
      end do
    end do
    call MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE)
    ! A sum zeroes the ghost layers sent (the whole layers: the rest of them was sent and
    ! zeroed on the earlier sweeps), then adds what came, neighbour by neighbour.
    if (add) then
      if (self%nbrs(1, d)%n > 0) then
        slo = self%alo; shi = self%ahi
        slo(d) = self%clo(d) - g; shi(d) = self%clo(d) - 1
        f(:, slo(1):shi(1), slo(2):shi(2), slo(3):shi(3)) = 0.0_wp
      end if
      if (self%nbrs(2, d)%n > 0) then
        slo = self%alo; shi = self%ahi
        slo(d) = self%chi(d) + 1; shi(d) = self%chi(d) + g
        f(:, slo(1):shi(1), slo(2):shi(2), slo(3):shi(3)) = 0.0_wp
      end if
    end if
    do m = 1, nm
      if (.not. allocated(rb(m)%a)) cycle
      rlo = plo(:, m); rhi = phi(:, m)
      if (add) then
        f(:, rlo(1):rhi(1), rlo(2):rhi(2), rlo(3):rhi(3)) = &
          f(:, rlo(1):rhi(1), rlo(2):rhi(2), rlo(3):rhi(3)) + &
          reshape(rb(m)%a, [size(f, 1), rhi(1) - rlo(1) + 1, rhi(2) - rlo(2) + 1, rhi(3) - rlo(3) + 1])
      else
        f(:, rlo(1):rhi(1), rlo(2):rhi(2), rlo(3):rhi(3)) = &
          reshape(rb(m)%a, [size(f, 1), rhi(1) - rlo(1) + 1, rhi(2) - rlo(2) + 1, rhi(3) - rlo(3) + 1])
      end if
    end do
  end subroutine exchange_axis_nested

end module dpmpm_decomp
