!> Rigid bodies driven at a prescribed velocity (&material model = 'rigid', doc/theory.md
!> 6.8): a footing pushed into the soil, a wall moved against it, a plate vibrated on it
!> (a vibration added to the constant velocity, body_velocities). The points of a rigid
!> material carry mass but no stress; every node their grid functions reach moves with
!> the body (the soil there sticks to it), and the force that takes is the drive's
!> reaction, summed over the owned nodes. A body with a frictional contact (bodies_t,
!> doc/theory.md 6.8.1) meets the soil at those nodes by Coulomb friction and adhesion
!> instead (contact_node; the steps around it: dpmpm_contact).
module dpmpm_rigid
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: table_length, table_factor
  use dpmpm_walls, only: walls_t
  use dpmpm_materials, only: material_t, model_rigid
  implicit none
  private
  public :: rigid_p2g, drive_rigid_nodes, hold_rigid_points, body_velocities
  public :: bodies_t, body_p2g, contact_node, motion_factor

  !> The rigid body of a scene with a frictional contact (doc/theory.md 6.8.1; the input
  !> allows one such body, the scene's only rigid one). Without one, on stays .false. and
  !> the scene keeps the stick contact of drive_rigid_nodes.
  type :: bodies_t
    logical :: known = .false.       !< the materials have been looked at (contact_setup)
    logical :: on = .false.          !< the scene's rigid body has a frictional contact
    logical :: free = .false.        !< it moves by its own equation (body_motion = 'free')
    integer :: mat = 0               !< its material
    real(wp) :: mu = 0.0_wp          !< friction coefficient of the contact
    real(wp) :: adhesion = 0.0_wp    !< Pa, shear strength of the contact at no normal stress
    real(wp) :: density = 0.0_wp     !< kg/m^3, of the body (its surface area from its mass gradient)
    real(wp) :: mass = 0.0_wp        !< kg (kg/m in 2D), its points' mass on all ranks
    real(wp) :: load(3) = 0.0_wp     !< N (N/m), the force on a free body (body_load)
    real(wp) :: lstep(3) = 0.0_wp    !< that force in this step (times its table's factor)
    real(wp) :: v(3) = 0.0_wp        !< velocity at the start of the step
    real(wp) :: vstep(3) = 0.0_wp    !< velocity of the step: the body moves by dt vstep
    real(wp) :: force(3) = 0.0_wp    !< the contact's force on the body over the last step
    integer :: iterations = 0        !< passes of the last step's contact solve (free body)
    !> the body points' masses and positions while the body is kept out of the soil's
    !> node fields (contact_hide, contact_move)
    real(wp), allocatable :: msave(:), xsave(:, :)
    !> the soil's share of the node fields as body_p2g forms the body's (the soil's normal)
    real(wp), allocatable :: snode(:, :, :, :)
    !> the contact's impulse on the body since the last record, that record's time, and the
    !> records (time, position of the mass centre (3), velocity (3), mean contact force (3))
    real(wp) :: impulse(3) = 0.0_wp, t0 = 0.0_wp
    real(wp), allocatable :: hist(:, :)
    integer :: nhist = 0
  end type bodies_t

contains

  !> The velocity of each material's body at time t (columns of vb, one per material):
  !> velocity f(t) + A omega cos(omega t) with the factor f of its time table (motion_factor;
  !> velocity itself without one) and the vibration's amplitude A and angular frequency
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
      if (mats(m)%motion_times(1) < 0.0_wp) then
        vb(:, m) = mats(m)%velocity
      else
        vb(:, m) = mats(m)%velocity*motion_factor(mats(m), t)
      end if
      vb(:, m) = vb(:, m) + mats(m)%vibration_amplitude*mats(m)%vibration_omega* &
                 cos(mats(m)%vibration_omega*t)
    end do
  end function body_velocities

  !> The factor of a rigid body's time table at time t (&material motion_times,
  !> motion_factors): linear between its entries, the first before its first time and the
  !> last after its last; 1 without a table.
  pure real(wp) function motion_factor(mat, t) result(f)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: t
    f = 1.0_wp
    if (table_length(mat%motion_times) > 0) f = table_factor(mat%motion_times, mat%motion_factors, t)
  end function motion_factor

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

  !> The share of the node fields of the points with masses bm (body_p2g(..., bm = the
  !> body's points' masses, the others' 0) gives the body's): rnode(1) = sum N m and rnode(2:1+nd) = sum m grad N (grad N_I at
  !> the points points toward node I: at a node on the body's surface the sum points out
  !> of the body; added to, the caller clears rnode).
  subroutine body_p2g(nd, nw, n, i0, sw, sdw, bm, lo, rnode)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :), bm(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: rnode(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3)
    do p = 1, n
      if (bm(p) <= 0.0_wp) cycle
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            nn = sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(1) = sdw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(2) = sw(a, 1, p)*sdw(b, 2, p)*sw(c, 3, p)
            g(3) = sw(a, 1, p)*sw(b, 2, p)*sdw(c, 3, p)
            if (nn <= 0.0_wp .and. all(g(1:nd) == 0.0_wp)) cycle
            rnode(1, i, j, k) = rnode(1, i, j, k) + nn*bm(p)
            rnode(2:1 + nd, i, j, k) = rnode(2:1 + nd, i, j, k) + bm(p)*g(1:nd)
          end do
        end do
      end do
    end do
  end subroutine body_p2g

  !> The frictional contact at one node (doc/theory.md 6.8.1): the soil's new velocity vs
  !> (mass ms) against the body's velocity vb, with the body's outward normal n (a unit
  !> vector; zero where the body's mass has no gradient: the soil there moves with it).
  !> Where the soil approaches the body, (vs - vb) . n < 0, its normal relative velocity is
  !> removed, and its tangential one as far as the friction mu times that normal change plus
  !> the adhesion's share ca/ms allows (ca: the adhesion's impulse on the node, a A dt);
  !> where it moves away, vs stays.
  pure subroutine contact_node(nd, ms, vb, n, mu, ca, vs)
    integer, intent(in) :: nd
    real(wp), intent(in) :: ms, vb(3), n(3), mu, ca
    real(wp), intent(inout) :: vs(3)
    real(wp) :: dv(3), vn, vt(3), st, lim
    if (all(n(1:nd) == 0.0_wp)) then
      vs(1:nd) = vb(1:nd)
      return
    end if
    dv = 0.0_wp
    dv(1:nd) = vs(1:nd) - vb(1:nd)
    vn = dot_product(dv(1:nd), n(1:nd))
    if (vn >= 0.0_wp) return
    vt = dv - vn*n
    st = norm2(vt(1:nd))
    lim = -mu*vn + ca/ms
    if (st <= lim) then
      vs(1:nd) = vb(1:nd)
    else
      vs(1:nd) = vs(1:nd) - vn*n(1:nd) - lim*vt(1:nd)/st
    end if
  end subroutine contact_node

end module dpmpm_rigid
