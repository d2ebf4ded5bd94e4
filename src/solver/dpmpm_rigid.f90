!> Rigid bodies driven at a prescribed velocity (&material model = 'rigid', doc/theory.md
!> 6.8): a footing pushed into the soil, a wall moved against it, a plate vibrated on it
!> (a vibration added to the constant velocity, body_velocities). The points of a rigid
!> material carry mass but no stress; every node their grid functions reach moves with
!> the body (the soil there sticks to it), and the force that takes is the drive's
!> reaction, summed over the owned nodes.
module dpmpm_rigid
  use dpmpm_kinds, only: wp
  use dpmpm_walls, only: walls_t
  use dpmpm_materials, only: material_t, model_rigid
  implicit none
  private
  public :: rigid_p2g, drive_rigid_nodes, hold_rigid_points, body_velocities

contains

  !> The velocity of each material's body at time t (columns of vb, one per material):
  !> velocity + A omega cos(omega t) with the vibration's amplitude A and angular frequency
  !> omega (0 for the materials that are not rigid). A step from t to t + dt moves a body by
  !> dt vb(t + dt/2), the midpoint rule of its displacement velocity t + A sin(omega t).
  pure function body_velocities(mats, t) result(vb)
    type(material_t), intent(in) :: mats(:)
    real(wp), intent(in) :: t
    real(wp) :: vb(3, size(mats))
    integer :: m
    do m = 1, size(mats)
      vb(:, m) = 0.0_wp
      if (mats(m)%model /= model_rigid) cycle
      vb(:, m) = mats(m)%velocity + mats(m)%vibration_amplitude*mats(m)%vibration_omega* &
                 cos(mats(m)%vibration_omega*t)
    end do
  end function body_velocities

  !> The rigid points' share of the node fields: rnode(1) = sum N m and
  !> rnode(2:1+nd) = sum N m v_r over the points of rigid materials (v_r = vb(:, material),
  !> the body's velocity in this step); rnode is added to (the caller clears it).
  subroutine rigid_p2g(nd, nw, n, i0, sw, mass, pmat, mats, vb, lo, rnode)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:)
    integer, contiguous, intent(in) :: pmat(:)
    type(material_t), intent(in) :: mats(:)
    real(wp), intent(in) :: vb(:, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: rnode(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn
    do p = 1, n
      if (mats(pmat(p))%model /= model_rigid) cycle
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            nn = sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            if (nn <= 0.0_wp) cycle
            rnode(1, i, j, k) = rnode(1, i, j, k) + nn*mass(p)
            rnode(2:1 + nd, i, j, k) = rnode(2:1 + nd, i, j, k) + nn*mass(p)*vb(1:nd, pmat(p))
          end do
        end do
      end do
    end do
  end subroutine rigid_p2g

  !> At the owned nodes olo..ohi that rigid points reach (rnode(1) > 0): the new
  !> velocity (nvel(nd+1:2nd)) becomes the bodies' (their mass-weighted mean where two
  !> meet), except the components the grid's face conditions hold. With force and work,
  !> the force that takes, m (v_r - v)/dt with m the node's whole mass (node(1)), is
  !> added to force and its work, over the step's mean velocity, to work.
  subroutine drive_rigid_nodes(nd, lo, olo, ohi, node, rnode, walls, dt, nvel, force, work)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: node(:, lo(1):, lo(2):, lo(3):), rnode(:, lo(1):, lo(2):, lo(3):)
    type(walls_t), intent(in) :: walls
    real(wp), intent(in) :: dt
    real(wp), intent(inout) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout), optional :: force(3), work
    integer :: i, j, k
    real(wp) :: vr(3), f(3)
    logical :: fix(3)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        do i = olo(1), ohi(1)
          if (rnode(1, i, j, k) <= 0.0_wp) cycle
          vr = 0.0_wp
          vr(1:nd) = rnode(2:1 + nd, i, j, k)/rnode(1, i, j, k)
          fix = walls%constrained([i, j, k])
          where (fix) vr = 0.0_wp
          if (present(force)) then
            f = 0.0_wp
            f(1:nd) = node(1, i, j, k)*(vr(1:nd) - nvel(nd + 1:2*nd, i, j, k))/dt
            force = force + f
            work = work + 0.5_wp*dt*dot_product(f(1:nd), nvel(1:nd, i, j, k) + vr(1:nd))
          end if
          nvel(nd + 1:2*nd, i, j, k) = vr(1:nd)
        end do
      end do
    end do
  end subroutine drive_rigid_nodes

  !> The points of rigid materials keep their body's velocity vb(:, material) (g2p blends
  !> the nodal change into every point's velocity).
  subroutine hold_rigid_points(nd, n, pmat, mats, vb, v)
    integer, intent(in) :: nd, n
    integer, contiguous, intent(in) :: pmat(:)
    type(material_t), intent(in) :: mats(:)
    real(wp), intent(in) :: vb(:, :)
    real(wp), contiguous, intent(inout) :: v(:, :)
    integer :: p
    do p = 1, n
      if (mats(pmat(p))%model == model_rigid) v(1:nd, p) = vb(1:nd, pmat(p))
    end do
  end subroutine hold_rigid_points

end module dpmpm_rigid
