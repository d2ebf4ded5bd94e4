!> Inflow of pore water through drained faces (doc/theory.md 6.2): new fluid points
!> where the water of a boundary cell flows in and has left a gap, numbered over the
!> ranks so that their ids do not depend on the decomposition or on a restart.
module dpmpm_inflow
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: fbc_drained
  use dpmpm_gather, only: global_places
  use dpmpm_particles, only: particle_set_t
  use dpmpm_state, only: state_t
  use dpmpm_pore_pressure, only: fluid_density, local_cell
  implicit none
  private
  public :: refill_inflow

contains

  !> Inflow through drained faces: where the pore water of a cell next to a drained face
  !> flows in relative to the skeleton there (its mean velocity away from the face
  !> exceeds the skeleton's) and has left a gap worth at least one of its points' volume
  !> (against the skeleton's volume in the cell, or the whole cell where there is no
  !> skeleton), a new fluid point fills it: in the middle of the gap at the centre of
  !> the cell's face, with the mean volume, porosity, 1/k and velocity of the cell's
  !> fluid points, the face's pore pressure, and the mass n rho_f(p) V. A body that moves
  !> away from the face with its water (consolidation under a load) gets none. Called
  !> after migration (points are in this rank's cells).
  subroutine refill_inflow(self, ps, sol)
    class(state_t), intent(inout) :: self
    type(particle_set_t), intent(inout) :: ps
    type(particle_set_t), intent(in) :: sol
    integer :: f, d, side, cb, p, k, nc, w(3), ic, m, c(3), n0, nnew
    real(wp), allocatable :: acc(:, :), sacc(:, :)
    integer, allocatable :: first(:), place(:)
    integer(i8), allocatable :: keys(:)
    real(wp) :: vcell, vt, deficit, vn, x(3), pface, poro, rho, sg, xwide(2)
    if (.not. any(self%bnd%fbc(1:2*self%nd) == fbc_drained)) return
    vcell = product(self%grid%h(1:self%nd))
    n0 = ps%n
    allocate (keys(0))
    do f = 1, 2*self%nd
      if (self%bnd%fbc(f) /= fbc_drained) cycle
      d = (f + 1)/2
      side = 2 - mod(f, 2)
      sg = merge(1.0_wp, -1.0_wp, side == 1)   ! +1: away from the face is +x_d
      cb = merge(0, self%grid%ncells(d) - 1, side == 1)
      if (cb < self%dec%clo(d) .or. cb > self%dec%chi(d)) cycle
      ! the layer's cells: this rank's cells along the other axes, one along d
      w = self%dec%chi - self%dec%clo + 1
      w(d) = 1
      nc = product(w)
      ! Most points are far from the face: a comparison with the layer widened by a cell
      ! on each side (no division) passes over them before the exact cell test.
      xwide = self%grid%origin(d) + [cb - 1, cb + 2]*self%grid%h(d)
      ! Per cell of this rank's boundary layer. Fluid: count, volume, mass, mass x normal
      ! velocity, mass x porosity, mass x 1/k, momentum. Skeleton: volume, mass, mass x
      ! normal velocity.
      allocate (acc(6 + self%nd, nc), sacc(3, nc), first(nc))
      acc = 0.0_wp
      sacc = 0.0_wp
      first = 0
      do p = 1, ps%n
        if (ps%x(d, p) < xwide(1) .or. ps%x(d, p) >= xwide(2)) cycle
        ic = boundary_cell(ps%x(:, p))
        if (ic == 0) cycle
        if (first(ic) == 0) first(ic) = p
        acc(1, ic) = acc(1, ic) + 1.0_wp
        acc(2, ic) = acc(2, ic) + ps%vol(p)
        acc(3, ic) = acc(3, ic) + ps%mass(p)
        acc(4, ic) = acc(4, ic) + ps%mass(p)*ps%v(d, p)
        acc(5, ic) = acc(5, ic) + ps%mass(p)*ps%porosity(p)
        acc(6, ic) = acc(6, ic) + ps%mass(p)*ps%kinv(p)
        acc(7:6 + self%nd, ic) = acc(7:6 + self%nd, ic) + ps%mass(p)*ps%v(:, p)
      end do
      do p = 1, sol%n
        if (sol%x(d, p) < xwide(1) .or. sol%x(d, p) >= xwide(2)) cycle
        ic = boundary_cell(sol%x(:, p))
        if (ic == 0) cycle
        sacc(1, ic) = sacc(1, ic) + sol%vol(p)
        sacc(2, ic) = sacc(2, ic) + sol%mass(p)
        sacc(3, ic) = sacc(3, ic) + sol%mass(p)*sol%v(d, p)
      end do
      do ic = 1, nc
        if (first(ic) == 0) cycle
        vn = sg*acc(4, ic)/acc(3, ic)
        deficit = vcell - acc(2, ic)
        if (sacc(2, ic) > 0.0_wp) then
          vn = vn - sg*sacc(3, ic)/sacc(2, ic)
          deficit = min(sacc(1, ic), vcell) - acc(2, ic)
        end if
        vt = acc(2, ic)/acc(1, ic)
        if (.not. (vn > 0.0_wp .and. deficit >= vt)) cycle
        ! Cell indices of ic (along d the layer's cell), then the point at the centre of
        ! the gap next to the face.
        c(1) = mod(ic - 1, w(1))
        c(2) = mod((ic - 1)/w(1), w(2))
        c(3) = (ic - 1)/(w(1)*w(2))
        c(d) = cb - self%dec%clo(d)
        x = 0.0_wp
        do k = 1, self%nd
          x(k) = self%grid%origin(k) + (c(k) + self%dec%clo(k) + 0.5_wp)*self%grid%h(k)
        end do
        x(d) = self%grid%origin(d) + merge(0.0_wp, self%grid%ncells(d)*self%grid%h(d), side == 1) + &
               sg*0.5_wp*deficit/vcell*self%grid%h(d)
        poro = acc(5, ic)/acc(3, ic)
        pface = self%bnd%faces%pore_pressure_at(self%time, f, x)
        m = ps%mat(first(ic))
        rho = fluid_density(self%mats(m)%density, self%mats(m)%bulk_fluid, pface)
        ! (the key of the face and global cell orders the new points of the step over the
        ! ranks; their ids follow below)
        keys = [keys, int(f - 1, i8)*product(int(self%grid%ncells, i8)) + 1_i8 + &
                int(c(1) + self%dec%clo(1), i8) + int(self%grid%ncells(1), i8)* &
                (int(c(2) + self%dec%clo(2), i8) + int(self%grid%ncells(2), i8)*int(c(3) + self%dec%clo(3), i8))]
        call ps%append(0_i8, m, x, acc(7:6 + self%nd, ic)/acc(3, ic), poro*rho*vt, vt, &
                       [-pface, -pface, -pface, 0.0_wp, 0.0_wp, 0.0_wp], porosity=poro, &
                       pressure=pface, kinv=acc(6, ic)/acc(3, ic))
        self%inflow_mass = self%inflow_mass + poro*rho*vt
      end do
      deallocate (acc, sacc, first)
    end do
    ! Ids above every id of the run's start, numbered over the ranks in the order of the
    ! keys: the same ids on any number of ranks and after a restart (the count is kept).
    allocate (place(size(keys)))
    call global_places(keys, self%dec%comm, place, nnew)
    do k = 1, size(keys)
      ps%id(n0 + k) = self%inflow_id0 + self%ninflow + int(place(k), i8)
    end do
    self%ninflow = self%ninflow + int(nnew, i8)

  contains

    !> Index in the layer of the boundary-layer cell of face f holding xp, 0 for another
    !> layer.
    integer function boundary_cell(xp) result(ic)
      real(wp), intent(in) :: xp(:)
      integer :: cc(3)
      ic = 0
      cc = local_cell(self%nd, xp, self%grid%origin, self%grid%h, self%dec%clo, self%dec%chi)
      if (cc(d) + self%dec%clo(d) /= cb) return
      cc(d) = 0
      ic = 1 + cc(1) + w(1)*(cc(2) + w(2)*cc(3))
    end function boundary_cell
  end subroutine refill_inflow

end module dpmpm_inflow
