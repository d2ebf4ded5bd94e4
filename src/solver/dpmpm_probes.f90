!> Records at points (&output nprobes, probe_x, probe_y, probe_z, probe_every): the grid
!> node nearest to each point, its velocity (the solid's, at the end of each step) and its
!> acceleration (the change of that velocity over the step), kept every probe_every steps
!> and written at the end of the run as /probes (doc/output.md). With each record also the
!> state of the material nearest the point at the start of the run: the solid point nearest
!> to it (the least id among equals) and, in two-phase scenes, the fluid point nearest to it
!> are followed through the run, and their displacement (x - x0), stress (the solid's: the
!> effective stress in saturated soil) and pore pressure are kept. The rank that owns a node
!> or a point gives its values and a sum over the ranks hands them to every rank (the others
!> give zeros, so the sum is exact), so that all ranks keep the same records and write them
!> together. A node without mass records zero, and so does a point no rank holds.
module dpmpm_probes
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t
  use dpmpm_grid, only: grid_t, node_slots_t, node_slots
  use dpmpm_output, only: output_t
  use dpmpm_particles, only: particle_set_t
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM, &
                     MPI_MIN, MPI_INTEGER8
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
    logical :: fluid = .false.                !< two-phase scene: pore pressures are kept
    integer(i8), allocatable :: sid(:), fid(:) !< (n): ids of the followed solid and fluid points
    integer, allocatable :: sloc(:), floc(:)  !< (n): their last local index (0 = not here)
    real(wp), allocatable :: sx0(:, :)        !< (nd, n): the solid points' places at the start
    real(wp), allocatable :: disp(:, :)       !< (nd n, records): the solid point's x - x0, as frames
    real(wp), allocatable :: sig(:, :)        !< (6 n, records): its stress, Voigt xx yy zz yz xz xy
    real(wp), allocatable :: pw(:, :)         !< (n, records): the fluid point's pore pressure
  contains
    procedure :: init => probes_init
    procedure :: sample => probes_sample
    procedure :: write => probes_write
  end type probes_t

contains

  !> The probes of cfg on grid (none when nprobes = 0), and the points they follow: the
  !> solid point of solid (the fluid point of fluid, when given) nearest to each probe's point.
  !> Collective over comm.
  subroutine probes_init(self, cfg, grid, comm, solid, fluid)
    class(probes_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: grid
    type(MPI_Comm), intent(in) :: comm
    type(particle_set_t), intent(in) :: solid
    type(particle_set_t), intent(in), optional :: fluid
    real(wp) :: x(3), places(cfg%ndim, max(0, cfg%nprobes))
    integer :: k, d, j
    self%n = max(0, cfg%nprobes)
    self%nd = cfg%ndim
    self%every = max(1, cfg%probe_every)
    self%nrec = 0
    self%fluid = present(fluid)
    if (allocated(self%node)) deallocate (self%node, self%vprev, self%t, self%step, self%vel, self%acc, &
                                          self%sid, self%fid, self%sloc, self%floc, self%sx0, &
                                          self%disp, self%sig, self%pw)
    if (self%n == 0) return
    allocate (self%node(3, self%n), self%vprev(self%nd*self%n), self%t(64), self%step(64), &
              self%vel(self%nd*self%n, 64), self%acc(self%nd*self%n, 64), self%sid(self%n), &
              self%fid(self%n), self%sloc(self%n), self%floc(self%n), self%sx0(self%nd, self%n), &
              self%disp(self%nd*self%n, 64), self%sig(6*self%n, 64), self%pw(self%n, 64))
    self%node = 0
    self%vprev = 0.0_wp
    do k = 1, self%n
      x = [cfg%probe_x(k), cfg%probe_y(k), cfg%probe_z(k)]
      places(:, k) = x(1:self%nd)
      do d = 1, self%nd
        self%node(d, k) = min(grid%ncells(d), max(0, nint((x(d) - grid%origin(d))/grid%h(d))))
      end do
    end do
    call nearest_points(solid, places, comm, self%sid, self%sloc)
    self%fid = 0
    self%floc = 0
    if (present(fluid)) call nearest_points(fluid, places, comm, self%fid, self%floc)
    ! The followed solid points' places at the start of the run (written with the records).
    self%sx0 = 0.0_wp
    do k = 1, self%n
      j = self%sloc(k)
      if (j > 0) self%sx0(:, k) = solid%x(:, j)
    end do
    call MPI_Allreduce(MPI_IN_PLACE, self%sx0, size(self%sx0), MPI_DOUBLE_PRECISION, MPI_SUM, comm)
  end subroutine probes_init

  !> For each place (nd, n): the id of the point of pts nearest to it over all ranks, the
  !> least id among equally near points (0 when no rank holds a point), and its local index
  !> on this rank (0 elsewhere). The squared distances are the same numbers on every rank,
  !> so the choice does not depend on how the points are split. Collective over comm.
  subroutine nearest_points(pts, places, comm, id, loc)
    type(particle_set_t), intent(in) :: pts
    real(wp), intent(in) :: places(:, :)
    type(MPI_Comm), intent(in) :: comm
    integer(i8), intent(out) :: id(:)
    integer, intent(out) :: loc(:)
    real(wp) :: dmin(size(places, 2)), dist
    integer :: k, j
    dmin = huge(1.0_wp)
    do k = 1, size(places, 2)
      do j = 1, pts%n
        dmin(k) = min(dmin(k), sum((pts%x(:, j) - places(:, k))**2))
      end do
    end do
    call MPI_Allreduce(MPI_IN_PLACE, dmin, size(dmin), MPI_DOUBLE_PRECISION, MPI_MIN, comm)
    id = huge(1_i8)
    do k = 1, size(places, 2)
      do j = 1, pts%n
        dist = sum((pts%x(:, j) - places(:, k))**2)
        if (dist == dmin(k)) id(k) = min(id(k), pts%id(j))
      end do
    end do
    call MPI_Allreduce(MPI_IN_PLACE, id, size(id), MPI_INTEGER8, MPI_MIN, comm)
    where (id == huge(1_i8)) id = 0
    loc = 0
    do k = 1, size(places, 2)
      loc(k) = find_point(pts, id(k), 0)
    end do
  end subroutine nearest_points

  !> The local index of the point with id (0 when this rank holds none); hint, the index
  !> where it was last, is tried first (points move between ranks and are reordered).
  integer function find_point(pts, id, hint) result(j)
    type(particle_set_t), intent(in) :: pts
    integer(i8), intent(in) :: id
    integer, intent(in) :: hint
    j = 0
    if (id == 0) return
    if (hint >= 1 .and. hint <= pts%n) then
      if (pts%id(hint) == id) then
        j = hint
        return
      end if
    end if
    do j = 1, pts%n
      if (pts%id(j) == id) return
    end do
    j = 0
  end function find_point

  !> After step (at time t, of length dt): the velocities of the probes' nodes from nvel (the
  !> new-velocity slots; nodes lo.., owned olo..ohi), their change over the step, and every
  !> `every` steps a record, with the followed points' displacement, stress (of solid) and
  !> pore pressure (of fluid, in two-phase scenes). Collective over comm.
  subroutine probes_sample(self, nvel, lo, olo, ohi, comm, t, step, dt, solid, fluid)
    class(probes_t), intent(inout) :: self
    integer, intent(in) :: lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: t, dt
    integer(i8), intent(in) :: step
    type(particle_set_t), intent(in) :: solid
    type(particle_set_t), intent(in), optional :: fluid
    real(wp) :: v(self%nd*self%n)
    real(wp) :: pv((self%nd + 7)*self%n)
    integer :: k, nd, j, r
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    v = 0.0_wp
    do k = 1, self%n
      associate (i => self%node(:, k))
        if (all(i >= olo .and. i <= ohi)) v(nd*(k - 1) + 1:nd*k) = nvel(sl%new_lo:sl%new_hi, i(1), i(2), i(3))
      end associate
    end do
    call MPI_Allreduce(MPI_IN_PLACE, v, size(v), MPI_DOUBLE_PRECISION, MPI_SUM, comm)
    if (mod(step, int(self%every, i8)) == 0) then
      if (self%nrec == size(self%t)) call grow(self)
      self%nrec = self%nrec + 1
      r = self%nrec
      self%t(r) = t
      self%step(r) = real(step, wp)
      self%vel(:, r) = v
      self%acc(:, r) = (v - self%vprev)/dt
      ! The followed points: displacement (nd), stress (6) and pore pressure (1) of each.
      pv = 0.0_wp
      do k = 1, self%n
        j = find_point(solid, self%sid(k), self%sloc(k))
        self%sloc(k) = j
        if (j > 0) then
          pv(nd*(k - 1) + 1:nd*k) = solid%x(:, j) - solid%x0(:, j)
          pv(nd*self%n + 6*(k - 1) + 1:nd*self%n + 6*k) = solid%stress(:, j)
        end if
        if (present(fluid) .and. self%fluid) then
          j = find_point(fluid, self%fid(k), self%floc(k))
          self%floc(k) = j
          if (j > 0) pv((nd + 6)*self%n + k) = fluid%pressure(j)
        end if
      end do
      call MPI_Allreduce(MPI_IN_PLACE, pv, size(pv), MPI_DOUBLE_PRECISION, MPI_SUM, comm)
      self%disp(:, r) = pv(1:nd*self%n)
      self%sig(:, r) = pv(nd*self%n + 1:(nd + 6)*self%n)
      self%pw(:, r) = pv((nd + 6)*self%n + 1:(nd + 7)*self%n)
    end if
    self%vprev = v
  end subroutine probes_sample

  !> Twice the room for records.
  subroutine grow(self)
    type(probes_t), intent(inout) :: self
    real(wp), allocatable :: t(:), s(:), v(:, :), a(:, :), u(:, :), g(:, :), p(:, :)
    integer :: m
    m = self%nrec
    allocate (t(2*m), s(2*m), v(size(self%vel, 1), 2*m), a(size(self%vel, 1), 2*m), &
              u(size(self%disp, 1), 2*m), g(size(self%sig, 1), 2*m), p(size(self%pw, 1), 2*m))
    t(1:m) = self%t(1:m)
    s(1:m) = self%step(1:m)
    v(:, 1:m) = self%vel(:, 1:m)
    a(:, 1:m) = self%acc(:, 1:m)
    u(:, 1:m) = self%disp(:, 1:m)
    g(:, 1:m) = self%sig(:, 1:m)
    p(:, 1:m) = self%pw(:, 1:m)
    call move_alloc(t, self%t)
    call move_alloc(s, self%step)
    call move_alloc(v, self%vel)
    call move_alloc(a, self%acc)
    call move_alloc(u, self%disp)
    call move_alloc(g, self%sig)
    call move_alloc(p, self%pw)
  end subroutine grow

  !> /probes of out (collective): time and step of each record, velocity and acceleration
  !> (records x nd n), and the nodes' positions (n x nd); the followed points' displacement
  !> (records x nd n), stress (records x 6 n), pore pressure (records x n, two-phase scenes),
  !> their places at the start (n x nd) and ids (n, as floats; 0 = none).
  subroutine probes_write(self, out, grid)
    class(probes_t), intent(in) :: self
    type(output_t), intent(inout) :: out
    type(grid_t), intent(in) :: grid
    real(wp) :: pos(self%nd, self%n)
    integer :: k, m, n
    if (self%n == 0) return
    n = self%n
    m = self%nd*n
    do k = 1, n
      pos(:, k) = grid%origin(1:self%nd) + real(self%node(1:self%nd, k), wp)*grid%h(1:self%nd)
    end do
    call out%write_verification('time', self%t(1:self%nrec), group='probes')
    call out%write_verification('step', self%step(1:self%nrec), group='probes')
    call out%write_verification('velocity', reshape(self%vel(:, 1:self%nrec), [m*self%nrec]), &
                                group='probes', columns=m)
    call out%write_verification('acceleration', reshape(self%acc(:, 1:self%nrec), [m*self%nrec]), &
                                group='probes', columns=m)
    call out%write_verification('position', reshape(pos, [m]), group='probes', columns=self%nd)
    call out%write_verification('displacement', reshape(self%disp(:, 1:self%nrec), [m*self%nrec]), &
                                group='probes', columns=m)
    call out%write_verification('stress', reshape(self%sig(:, 1:self%nrec), [6*n*self%nrec]), &
                                group='probes', columns=6*n)
    call out%write_verification('solid_position', reshape(self%sx0, [m]), group='probes', &
                                columns=self%nd)
    call out%write_verification('solid_id', real(self%sid, wp), group='probes')
    if (self%fluid) then
      call out%write_verification('pore_pressure', reshape(self%pw(:, 1:self%nrec), [n*self%nrec]), &
                                  group='probes', columns=n)
      call out%write_verification('fluid_id', real(self%fid, wp), group='probes')
    end if
  end subroutine probes_write

end module dpmpm_probes
