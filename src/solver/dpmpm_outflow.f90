!> Points that leave the model through an opening of a fixed or roller face (&boundary
!> opening_lo, opening_hi): which points crossed a face there, and the energy they carry
!> out, so that the energy balance (kinetic + strain - external work) keeps its value when
!> they are removed: the carried energy is booked as negative external work.
module dpmpm_outflow
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: grid_t
  use dpmpm_walls, only: walls_t
  use dpmpm_materials, only: material_t, strain_energy, model_fluid
  use dpmpm_particles, only: particle_set_t
  implicit none
  private
  public :: left_through_opening, carried_energy

contains

  !> Whether a point at x lies beyond a face of grid (below its lower or at or above its
  !> upper end along the face's axis) that has an opening, inside the opening's box.
  pure logical function left_through_opening(walls, grid, x) result(gone)
    type(walls_t), intent(in) :: walls
    type(grid_t), intent(in) :: grid
    real(wp), intent(in) :: x(:)
    integer :: f, d
    real(wp) :: wall
    gone = .false.
    do f = 1, 2*walls%ndim
      if (.not. walls%opened(f)) cycle
      d = (f + 1)/2
      if (mod(f, 2) == 1) then
        wall = grid%origin(d)
        if (.not. x(d) < wall) cycle
      else
        wall = grid%origin(d) + grid%ncells(d)*grid%h(d)
        if (.not. x(d) >= wall) cycle
      end if
      if (walls%through_opening(f, x)) then
        gone = .true.
        return
      end if
    end do
  end function left_through_opening

  !> Kinetic and strain energy of the points of ps marked gone (this rank's).
  real(wp) function carried_energy(mats, ps, gone) result(e)
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(in) :: ps
    logical, intent(in) :: gone(:)
    integer, allocatable :: idx(:)
    integer :: p, m, n
    idx = pack([(p, p=1, ps%n)], gone(1:ps%n))
    n = size(idx)
    e = 0.0_wp
    do p = 1, n
      e = e + 0.5_wp*ps%mass(idx(p))*sum(ps%v(:, idx(p))**2)
    end do
    do m = 1, size(mats)
      if (mats(m)%model == model_fluid) cycle
      if (allocated(ps%defgrad) .and. allocated(ps%state)) then
        e = e + strain_energy(mats(m), m, n, ps%mat(idx), ps%stress(:, idx), ps%vol(idx), &
                              ps%vol0(idx), ps%defgrad(:, idx), ps%state(:, idx))
      else if (allocated(ps%state)) then
        e = e + strain_energy(mats(m), m, n, ps%mat(idx), ps%stress(:, idx), ps%vol(idx), &
                              ps%vol0(idx), state=ps%state(:, idx))
      else
        e = e + strain_energy(mats(m), m, n, ps%mat(idx), ps%stress(:, idx), ps%vol(idx), &
                              ps%vol0(idx))
      end if
    end do
  end function carried_energy

end module dpmpm_outflow
