!> A set of material points (solid or fluid) as a structure of arrays.
!> Only the fields that the scene needs are allocated: the deformation gradient
!> only when a material needs it (neo-Hookean), porosity only in two-phase
!> scenes, pore pressure and inverse conductivity only on fluid points, the state values
!> of the constitutive models (nstate per point, dpmpm_model_table) only when a model of
!> the scene keeps some.
!> Capacity grows geometrically.
module dpmpm_particles
  use dpmpm_kinds, only: wp, i8
  implicit none
  private
  public :: particle_set_t

  !> Structure-of-arrays point set. Point k is column k of every array.
  type :: particle_set_t
    character(len=16) :: name = 'solid'
    integer :: ndim = 0
    integer :: n = 0                         !< points held by this rank
    integer :: cap = 0                       !< allocated capacity
    logical :: has_defgrad = .false.         !< F stored (finite-strain materials)
    logical :: has_porosity = .false.        !< porosity stored (two-phase scenes)
    logical :: has_pressure = .false.        !< pore pressure and 1/k stored (fluid points)
    integer :: nstate = 0                    !< state values per point (the scene's models)
    integer(i8), allocatable :: id(:)        !< global id, unique, never changes
    integer, allocatable :: mat(:)           !< material index (1..nmat) into the scene's materials
    real(wp), allocatable :: x(:, :)         !< position (ndim, cap)
    real(wp), allocatable :: x0(:, :)        !< reference (initial) position (ndim, cap)
    real(wp), allocatable :: v(:, :)         !< velocity (ndim, cap)
    real(wp), allocatable :: mass(:)         !< kg (per unit area in 2D, per unit area^2 in 1D)
    real(wp), allocatable :: vol(:)          !< current volume
    real(wp), allocatable :: vol0(:)         !< initial volume
    real(wp), allocatable :: stress(:, :)    !< Cauchy stress (6, cap), Voigt xx yy zz yz xz xy
    real(wp), allocatable :: defgrad(:, :)   !< deformation gradient (9, cap), column-major 3x3
    real(wp), allocatable :: porosity(:)     !< volume fraction of the pores n_f
    real(wp), allocatable :: pressure(:)     !< pore pressure (Pa, positive in compression)
    real(wp), allocatable :: kinv(:)         !< 1 / hydraulic conductivity (s/m); 0 = no drag
    !> the state values of the points' models (nstate, cap): each model reads its own first
    !> values (dpmpm_model_table); 0 at a new point
    real(wp), allocatable :: state(:, :)
  contains
    procedure :: init => ps_init
    procedure :: reserve => ps_reserve
    procedure :: append => ps_append
    procedure :: nreal_packed => ps_nreal_packed
    procedure :: pack_points => ps_pack
    procedure :: unpack_points => ps_unpack
    procedure :: remove => ps_remove
    procedure :: permute => ps_permute
    procedure :: free => ps_free
    procedure :: bytes_per_point => ps_bytes_per_point
  end type particle_set_t

contains

  !> Empty set for ndim dimensions; has_defgrad allocates F, has_porosity the
  !> porosity, has_pressure the pore pressure and inverse conductivity, nstate (default 0)
  !> the state values of the constitutive models.
  subroutine ps_init(self, name, ndim, has_defgrad, capacity, has_porosity, has_pressure, &
                     nstate)
    class(particle_set_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: ndim
    logical, intent(in) :: has_defgrad
    integer, intent(in), optional :: capacity
    logical, intent(in), optional :: has_porosity, has_pressure
    integer, intent(in), optional :: nstate
    call self%free()
    self%name = name
    self%ndim = ndim
    self%has_defgrad = has_defgrad
    self%has_porosity = .false.
    if (present(has_porosity)) self%has_porosity = has_porosity
    self%has_pressure = .false.
    if (present(has_pressure)) self%has_pressure = has_pressure
    self%nstate = 0
    if (present(nstate)) self%nstate = nstate
    self%n = 0
    self%cap = 0
    if (present(capacity)) then
      call self%reserve(capacity)
    else
      call self%reserve(16)
    end if
  end subroutine ps_init

  !> Release all storage.
  subroutine ps_free(self)
    class(particle_set_t), intent(inout) :: self
    if (allocated(self%id)) deallocate (self%id)
    if (allocated(self%mat)) deallocate (self%mat)
    if (allocated(self%x)) deallocate (self%x)
    if (allocated(self%x0)) deallocate (self%x0)
    if (allocated(self%v)) deallocate (self%v)
    if (allocated(self%mass)) deallocate (self%mass)
    if (allocated(self%vol)) deallocate (self%vol)
    if (allocated(self%vol0)) deallocate (self%vol0)
    if (allocated(self%stress)) deallocate (self%stress)
    if (allocated(self%defgrad)) deallocate (self%defgrad)
    if (allocated(self%porosity)) deallocate (self%porosity)
    if (allocated(self%pressure)) deallocate (self%pressure)
    if (allocated(self%kinv)) deallocate (self%kinv)
    if (allocated(self%state)) deallocate (self%state)
    self%n = 0
    self%cap = 0
  end subroutine ps_free

  !> Bytes of one point in the arrays the set holds (a column of each allocated field).
  integer function ps_bytes_per_point(self) result(b)
    class(particle_set_t), intent(in) :: self
    b = 0
    if (allocated(self%id)) b = b + storage_size(self%id)/8
    if (allocated(self%mat)) b = b + storage_size(self%mat)/8
    if (allocated(self%x)) b = b + size(self%x, 1)*storage_size(self%x)/8
    if (allocated(self%x0)) b = b + size(self%x0, 1)*storage_size(self%x0)/8
    if (allocated(self%v)) b = b + size(self%v, 1)*storage_size(self%v)/8
    if (allocated(self%mass)) b = b + storage_size(self%mass)/8
    if (allocated(self%vol)) b = b + storage_size(self%vol)/8
    if (allocated(self%vol0)) b = b + storage_size(self%vol0)/8
    if (allocated(self%stress)) b = b + size(self%stress, 1)*storage_size(self%stress)/8
    if (allocated(self%defgrad)) b = b + size(self%defgrad, 1)*storage_size(self%defgrad)/8
    if (allocated(self%porosity)) b = b + storage_size(self%porosity)/8
    if (allocated(self%pressure)) b = b + storage_size(self%pressure)/8
    if (allocated(self%kinv)) b = b + storage_size(self%kinv)/8
    if (allocated(self%state)) b = b + size(self%state, 1)*storage_size(self%state)/8
  end function ps_bytes_per_point

  !> Make room for at least m points, keeping the first n.
  subroutine ps_reserve(self, m)
    class(particle_set_t), intent(inout) :: self
    integer, intent(in) :: m
    integer :: newcap
    if (m <= self%cap) return
    newcap = max(m, 2*self%cap, 16)
    call grow_i8(self%id, newcap, self%n)
    call grow_i(self%mat, newcap, self%n)
    call grow_r2(self%x, self%ndim, newcap, self%n)
    call grow_r2(self%x0, self%ndim, newcap, self%n)
    call grow_r2(self%v, self%ndim, newcap, self%n)
    call grow_r1(self%mass, newcap, self%n)
    call grow_r1(self%vol, newcap, self%n)
    call grow_r1(self%vol0, newcap, self%n)
    call grow_r2(self%stress, 6, newcap, self%n)
    if (self%has_defgrad) call grow_r2(self%defgrad, 9, newcap, self%n)
    if (self%has_porosity) call grow_r1(self%porosity, newcap, self%n)
    if (self%has_pressure) then
      call grow_r1(self%pressure, newcap, self%n)
      call grow_r1(self%kinv, newcap, self%n)
    end if
    if (self%nstate > 0) call grow_r2(self%state, self%nstate, newcap, self%n)
    self%cap = newcap
  end subroutine ps_reserve

  !> Append one new point at rest in its reference state (F = I, zero stress);
  !> porosity, pressure and kinv (default 0) fill the fields the set stores; state values 0.
  subroutine ps_append(self, id, mat, x, v, mass, vol, stress, porosity, pressure, kinv)
    class(particle_set_t), intent(inout) :: self
    integer(i8), intent(in) :: id
    integer, intent(in) :: mat
    real(wp), intent(in) :: x(:), v(:), mass, vol, stress(6)
    real(wp), intent(in), optional :: porosity, pressure, kinv
    integer :: k
    if (self%n + 1 > self%cap) call self%reserve(self%n + 1)
    k = self%n + 1
    self%id(k) = id
    self%mat(k) = mat
    self%x(:, k) = x(1:self%ndim)
    self%x0(:, k) = x(1:self%ndim)
    self%v(:, k) = v(1:self%ndim)
    self%mass(k) = mass
    self%vol(k) = vol
    self%vol0(k) = vol
    self%stress(:, k) = stress
    if (self%has_defgrad) self%defgrad(:, k) = [1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, &
                                                0.0_wp, 0.0_wp, 1.0_wp]
    if (self%has_porosity) then
      self%porosity(k) = 0.0_wp
      if (present(porosity)) self%porosity(k) = porosity
    end if
    if (self%has_pressure) then
      self%pressure(k) = 0.0_wp
      if (present(pressure)) self%pressure(k) = pressure
      self%kinv(k) = 0.0_wp
      if (present(kinv)) self%kinv(k) = kinv
    end if
    if (self%nstate > 0) self%state(:, k) = 0.0_wp
    self%n = k
  end subroutine ps_append

  !> Number of reals one packed point occupies (id and material travel as reals).
  pure integer function ps_nreal_packed(self) result(m)
    class(particle_set_t), intent(in) :: self
    m = 2 + 3*self%ndim + 3 + 6
    if (self%has_defgrad) m = m + 9
    if (self%has_porosity) m = m + 1
    if (self%has_pressure) m = m + 2
    m = m + self%nstate
  end function ps_nreal_packed

  !> Pack the points listed in idx into buf(nreal_packed, size(idx)) for migration or checkpoints.
  subroutine ps_pack(self, idx, buf)
    class(particle_set_t), intent(in) :: self
    integer, intent(in) :: idx(:)
    real(wp), intent(out) :: buf(:, :)
    integer :: j, k, o, d
    d = self%ndim
    do j = 1, size(idx)
      k = idx(j)
      buf(1, j) = transfer(self%id(k), 1.0_wp)
      buf(2, j) = real(self%mat(k), wp)
      o = 2
      buf(o + 1:o + d, j) = self%x(:, k); o = o + d
      buf(o + 1:o + d, j) = self%x0(:, k); o = o + d
      buf(o + 1:o + d, j) = self%v(:, k); o = o + d
      buf(o + 1, j) = self%mass(k)
      buf(o + 2, j) = self%vol(k)
      buf(o + 3, j) = self%vol0(k); o = o + 3
      buf(o + 1:o + 6, j) = self%stress(:, k); o = o + 6
      if (self%has_defgrad) then
        buf(o + 1:o + 9, j) = self%defgrad(:, k); o = o + 9
      end if
      if (self%has_porosity) then
        buf(o + 1, j) = self%porosity(k); o = o + 1
      end if
      if (self%has_pressure) then
        buf(o + 1, j) = self%pressure(k)
        buf(o + 2, j) = self%kinv(k); o = o + 2
      end if
      if (self%nstate > 0) buf(o + 1:o + self%nstate, j) = self%state(:, k)
    end do
  end subroutine ps_pack

  !> Append the points packed in buf(nreal_packed, m).
  subroutine ps_unpack(self, buf)
    class(particle_set_t), intent(inout) :: self
    real(wp), intent(in) :: buf(:, :)
    integer :: j, k, o, d
    d = self%ndim
    call self%reserve(self%n + size(buf, 2))
    do j = 1, size(buf, 2)
      k = self%n + j
      self%id(k) = transfer(buf(1, j), 1_i8)
      self%mat(k) = nint(buf(2, j))
      o = 2
      self%x(:, k) = buf(o + 1:o + d, j); o = o + d
      self%x0(:, k) = buf(o + 1:o + d, j); o = o + d
      self%v(:, k) = buf(o + 1:o + d, j); o = o + d
      self%mass(k) = buf(o + 1, j)
      self%vol(k) = buf(o + 2, j)
      self%vol0(k) = buf(o + 3, j); o = o + 3
      self%stress(:, k) = buf(o + 1:o + 6, j); o = o + 6
      if (self%has_defgrad) then
        self%defgrad(:, k) = buf(o + 1:o + 9, j); o = o + 9
      end if
      if (self%has_porosity) then
        self%porosity(k) = buf(o + 1, j); o = o + 1
      end if
      if (self%has_pressure) then
        self%pressure(k) = buf(o + 1, j)
        self%kinv(k) = buf(o + 2, j); o = o + 2
      end if
      if (self%nstate > 0) self%state(:, k) = buf(o + 1:o + self%nstate, j)
    end do
    self%n = self%n + size(buf, 2)
  end subroutine ps_unpack

  !> Reorder the points: the k-th point becomes the one at order(k) before (order a
  !> permutation of 1..n). Every field goes along, through the packed form that
  !> migration sends.
  subroutine ps_permute(self, order)
    class(particle_set_t), intent(inout) :: self
    integer, intent(in) :: order(:)
    real(wp), allocatable :: buf(:, :)
    allocate (buf(self%nreal_packed(), self%n))
    call self%pack_points(order, buf)
    self%n = 0
    call self%unpack_points(buf)
  end subroutine ps_permute

  !> Remove the points flagged in gone(1:n). Every hole among the first m = n - count(gone)
  !> points takes a surviving point from behind m, the last of the set first, so that only
  !> as many points move as left and the cost follows the departed points, not the set.
  !> The order of the others changes (the moved points come forward); sort_by_cell
  !> (dpmpm_cell_order, &run sort_every) puts a set back in cell order.
  subroutine ps_remove(self, gone)
    class(particle_set_t), intent(inout) :: self
    logical, intent(in) :: gone(:)
    integer :: i, j, m
    m = self%n - count(gone(1:self%n))
    ! (as many survivors lie behind m as there are holes up to m)
    j = self%n
    do i = 1, m
      if (.not. gone(i)) cycle
      do while (gone(j))
        j = j - 1
      end do
      call copy_point(self, j, i)
      j = j - 1
    end do
    self%n = m
  end subroutine ps_remove

  !> Point k of the set becomes a copy of point j (every field the set stores).
  subroutine copy_point(self, j, k)
    type(particle_set_t), intent(inout) :: self
    integer, intent(in) :: j, k
    self%id(k) = self%id(j)
    self%mat(k) = self%mat(j)
    self%x(:, k) = self%x(:, j)
    self%x0(:, k) = self%x0(:, j)
    self%v(:, k) = self%v(:, j)
    self%mass(k) = self%mass(j)
    self%vol(k) = self%vol(j)
    self%vol0(k) = self%vol0(j)
    self%stress(:, k) = self%stress(:, j)
    if (self%has_defgrad) self%defgrad(:, k) = self%defgrad(:, j)
    if (self%has_porosity) self%porosity(k) = self%porosity(j)
    if (self%has_pressure) then
      self%pressure(k) = self%pressure(j)
      self%kinv(k) = self%kinv(j)
    end if
    if (self%nstate > 0) self%state(:, k) = self%state(:, j)
  end subroutine copy_point

  subroutine grow_i8(a, newcap, n)
    integer(i8), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: newcap, n
    integer(i8), allocatable :: t(:)
    allocate (t(newcap))
    if (allocated(a)) t(1:n) = a(1:n)
    call move_alloc(t, a)
  end subroutine grow_i8

  subroutine grow_i(a, newcap, n)
    integer, allocatable, intent(inout) :: a(:)
    integer, intent(in) :: newcap, n
    integer, allocatable :: t(:)
    allocate (t(newcap))
    if (allocated(a)) t(1:n) = a(1:n)
    call move_alloc(t, a)
  end subroutine grow_i

  subroutine grow_r1(a, newcap, n)
    real(wp), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: newcap, n
    real(wp), allocatable :: t(:)
    allocate (t(newcap))
    if (allocated(a)) t(1:n) = a(1:n)
    call move_alloc(t, a)
  end subroutine grow_r1

  subroutine grow_r2(a, m, newcap, n)
    real(wp), allocatable, intent(inout) :: a(:, :)
    integer, intent(in) :: m, newcap, n
    real(wp), allocatable :: t(:, :)
    allocate (t(m, newcap))
    if (allocated(a)) t(:, 1:n) = a(:, 1:n)
    call move_alloc(t, a)
  end subroutine grow_r2

end module dpmpm_particles
