!> Records at points (&output nprobes, probe_x, probe_y, probe_z, probe_every): the grid
!> node nearest to each point, its velocity (the solid's, at the end of each step) and its
!> acceleration (the change of that velocity over the step), kept every probe_every steps
!> and written at the end of the run as /probes (doc/output.md). The rank that owns a node
!> gives its values and a sum over the ranks hands them to every rank, so that all ranks keep
!> the same records and write them together. A node without mass records zero.
module dpmpm_probes
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t
  use dpmpm_grid, only: grid_t
  use dpmpm_output, only: output_t
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM
  implicit none
  private
  public :: probes_t

  !> The probes of a run and their records so far.
  type :: probes_t
    integer :: n = 0                          !< probes
    integer :: nd = 1
    integer :: every = 1
    integer, allocatable :: node(:, :)        !< (3, n): the nearest node's indices
    real(wp), allocatable :: vprev(:)         !< (nd n): the velocities after the last step
    integer :: nrec = 0
    real(wp), allocatable :: t(:), step(:)    !< (records)
    real(wp), allocatable :: vel(:, :), acc(:, :) !< (nd n, records): probe k, axis d at nd (k - 1) + d
  contains
    procedure :: init => probes_init
    procedure :: sample => probes_sample
    procedure :: write => probes_write
  end type probes_t

contains

  !> The probes of cfg on grid (none when nprobes = 0).
  subroutine probes_init(self, cfg, grid)
    class(probes_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: grid
    real(wp) :: x(3)
    integer :: k, d
    self%n = max(0, cfg%nprobes)
    self%nd = cfg%ndim
    self%every = max(1, cfg%probe_every)
    self%nrec = 0
    if (allocated(self%node)) deallocate (self%node, self%vprev, self%t, self%step, self%vel, self%acc)
    if (self%n == 0) return
    allocate (self%node(3, self%n), self%vprev(self%nd*self%n), self%t(64), self%step(64), &
              self%vel(self%nd*self%n, 64), self%acc(self%nd*self%n, 64))
    self%node = 0
    self%vprev = 0.0_wp
    do k = 1, self%n
      x = [cfg%probe_x(k), cfg%probe_y(k), cfg%probe_z(k)]
      do d = 1, self%nd
        self%node(d, k) = min(grid%ncells(d), max(0, nint((x(d) - grid%origin(d))/grid%h(d))))
      end do
    end do
  end subroutine probes_init

  !> After step (at time t, of length dt): the velocities of the probes' nodes from nvel (the
  !> new-velocity slots; nodes lo.., owned olo..ohi), their change over the step, and every
  !> `every` steps a record. Collective over comm.
  subroutine probes_sample(self, nvel, lo, olo, ohi, comm, t, step, dt)
    class(probes_t), intent(inout) :: self
    integer, intent(in) :: lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: t, dt
    integer(i8), intent(in) :: step
    real(wp) :: v(self%nd*self%n)
    integer :: k, nd
    nd = self%nd
    v = 0.0_wp
    do k = 1, self%n
      associate (i => self%node(:, k))
        if (all(i >= olo .and. i <= ohi)) v(nd*(k - 1) + 1:nd*k) = nvel(nd + 1:2*nd, i(1), i(2), i(3))
      end associate
    end do
    call MPI_Allreduce(MPI_IN_PLACE, v, size(v), MPI_DOUBLE_PRECISION, MPI_SUM, comm)
    if (mod(step, int(self%every, i8)) == 0) then
      if (self%nrec == size(self%t)) call grow(self)
      self%nrec = self%nrec + 1
      self%t(self%nrec) = t
      self%step(self%nrec) = real(step, wp)
      self%vel(:, self%nrec) = v
      self%acc(:, self%nrec) = (v - self%vprev)/dt
    end if
    self%vprev = v
  end subroutine probes_sample

  !> Twice the room for records.
  subroutine grow(self)
    type(probes_t), intent(inout) :: self
    real(wp), allocatable :: t(:), s(:), v(:, :), a(:, :)
    integer :: m
    m = self%nrec
    allocate (t(2*m), s(2*m), v(size(self%vel, 1), 2*m), a(size(self%vel, 1), 2*m))
    t(1:m) = self%t(1:m)
    s(1:m) = self%step(1:m)
    v(:, 1:m) = self%vel(:, 1:m)
    a(:, 1:m) = self%acc(:, 1:m)
    call move_alloc(t, self%t)
    call move_alloc(s, self%step)
    call move_alloc(v, self%vel)
    call move_alloc(a, self%acc)
  end subroutine grow

  !> /probes of out (collective): time and step of each record, velocity and acceleration
  !> (records x nd n), and the nodes' positions (n x nd).
  subroutine probes_write(self, out, grid)
    class(probes_t), intent(in) :: self
    type(output_t), intent(inout) :: out
    type(grid_t), intent(in) :: grid
    real(wp) :: pos(self%nd, self%n)
    integer :: k, m
    if (self%n == 0) return
    m = self%nd*self%n
    do k = 1, self%n
      pos(:, k) = grid%origin(1:self%nd) + real(self%node(1:self%nd, k), wp)*grid%h(1:self%nd)
    end do
    call out%write_verification('time', self%t(1:self%nrec), group='probes')
    call out%write_verification('step', self%step(1:self%nrec), group='probes')
    call out%write_verification('velocity', reshape(self%vel(:, 1:self%nrec), [m*self%nrec]), &
                                group='probes', columns=m)
    call out%write_verification('acceleration', reshape(self%acc(:, 1:self%nrec), [m*self%nrec]), &
                                group='probes', columns=m)
    call out%write_verification('position', reshape(pos, [m]), group='probes', columns=self%nd)
  end subroutine probes_write

end module dpmpm_probes
