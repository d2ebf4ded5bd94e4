!> Cartesian domain decomposition of a regular grid of cells, with ghost nodes.
!>
!> Cells 0..ncells(d)-1 along each axis are split as evenly as possible (the
!> remainder goes to the first ranks). A rank owns the cells clo..chi and the
!> nodes with the same indices; the first and last rank along an axis also own
!> the gw exterior nodes beyond the grid faces that wide kernels reach. Every
!> rank stores the nodes clo-gw .. chi+gw. halo_sum adds ghost values into their
!> owners; halo_copy copies owners' values to the ghosts. Both sweep the axes in
!> turn over the full extent of the other axes, so edges and corners are exact.
module dpmpm_decomp
  use dpmpm_kinds, only: wp
  use mpi_f08, only: MPI_Comm, MPI_Comm_dup, MPI_Comm_free, MPI_Comm_rank, MPI_Comm_size, &
                     MPI_Dims_create, MPI_Cart_create, MPI_Cart_coords, MPI_Cart_shift, &
                     MPI_Sendrecv, MPI_STATUS_IGNORE, MPI_PROC_NULL, MPI_COMM_NULL, &
                     MPI_DOUBLE_PRECISION, operator(/=)
  implicit none
  private
  public :: decomp_t, split_extent, balanced_cuts

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
    integer :: nbr_lo(3), nbr_hi(3)         !< neighbour ranks, MPI_PROC_NULL at the grid faces
    !> cut(c, d): first cell of part c along axis d (c = 0 .. dims(d); cut(dims(d), d) = ncells(d))
    integer, allocatable :: cut(:, :)
  contains
    procedure :: init => decomp_init
    procedure :: free => decomp_free
    procedure :: recut => decomp_recut
    procedure :: owner_coord => decomp_owner_coord
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
    integer :: d, c
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
    call self%recut(first)
  end subroutine decomp_init

  !> The owned and stored ranges from new cuts (cuts(c, d), c = 0 .. dims(d), the first
  !> cell of part c along axis d; axes beyond ndim are left one cell), with the same rank
  !> layout and communicator. Every node field sized by the old ranges must be allocated
  !> again, and every point migrated (balance_by_points).
  subroutine decomp_recut(self, cuts)
    class(decomp_t), intent(inout) :: self
    integer, intent(in) :: cuts(0:, :)
    integer :: d, c
    do d = 1, self%ndim
      do c = 0, self%dims(d)
        self%cut(c, d) = cuts(c, d)
      end do
    end do
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
    integer :: d
    do d = 1, self%ndim
      call exchange_axis(self, f, d, .true.)
    end do
  end subroutine decomp_halo_sum

  !> Owner -> ghost: copy owners' values into the ghost nodes of the neighbours.
  subroutine decomp_halo_copy(self, f)
    class(decomp_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    integer :: d
    do d = 1, self%ndim
      call exchange_axis(self, f, d, .false.)
    end do
  end subroutine decomp_halo_copy

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

end module dpmpm_decomp
