!> The drag between the phases (doc/theory.md 4.2 and 7.2): the coefficient's gravity, the
!> relaxation of a MUSL-remapped pair, and the explicit-drag time-step limit. The
!> coefficient itself is carried to the nodes by fluid_p2g (dpmpm_transfer); the per-node
!> solve of the coupled accelerations (drag_solve) and the dissipation are in the nodal
!> update (dpmpm_nodal_update).
module dpmpm_drag
  use dpmpm_kinds, only: wp
  use dpmpm_face_loads, only: face_loads_t
  implicit none
  private
  public :: gravity_drag, drag_relax, drag_limit, nodal_drag_limit, relax_remapped, sliver_node
  public :: locked_velocity, remove_split

  !> Gravity in the drag coefficient n_f^2 rho_f g / k (k is a hydraulic conductivity,
  !> defined with the standard gravity whatever the scene's body force).
  real(wp), parameter :: gravity_drag = 9.81_wp

  !> A node where one phase's mass is below this fraction of the other's is a sliver
  !> node: explicit drag there would need a step of about 2 m_small / D, far below the
  !> step of the rest of the grid (doc/theory.md 7.2).
  real(wp), parameter :: sliver_fraction = 1.0e-2_wp

contains

  !> Relative velocity of a MUSL-remapped pair made consistent with the step's
  !> implicit drag. vs, vf are the remapped nodal velocities (each phase projected
  !> from its own points), wstep = v_f - v_s of the nodal update itself. The two
  !> point sets project the same nodal increments with their own masses, so the
  !> remap adds a relative velocity w_R - wstep that no drag has acted on. The
  !> implicit drag shrinks a relative velocity in one step by
  !> f = ms mf / (ms mf + dt d (ms + mf)); where it locks the phases (f < f_lock)
  !> the added part is shrunk the same way, w = wstep + g (w_R - wstep) with
  !> g = f + (1 - f) f / f_lock, which is 1 (the plain remap) from f = f_lock on.
  !> Where the drag is moderate the nodal update's own relative velocity can be
  !> large at a node one phase barely reaches, and the plain remap is kept. The
  !> momentum of the pair is kept (doc/verification.md, "Long runs").
  pure subroutine drag_relax(ms, mf, d, dt, wstep, vs, vf)
    real(wp), intent(in) :: ms, mf, d, dt, wstep
    real(wp), intent(inout) :: vs, vf
    real(wp), parameter :: f_lock = 0.1_wp
    real(wp) :: mix, w, f, g
    if (ms <= 0.0_wp .or. mf <= 0.0_wp .or. d <= 0.0_wp) return
    f = ms*mf/(ms*mf + dt*d*(ms + mf))
    if (f >= f_lock) return
    g = f + (1.0_wp - f)*f/f_lock
    mix = (ms*vs + mf*vf)/(ms + mf)
    w = wstep + g*(vf - vs - wstep)
    vs = mix - mf/(ms + mf)*w
    vf = mix + ms/(ms + mf)*w
  end subroutine drag_relax

  !> True at a node with both phases where one has less than sliver_fraction of the
  !> other's mass. With explicit drag such a node takes the drag implicitly and does not
  !> limit the step: the drag locks the sliver to the other phase within one step, as the
  !> physics does, instead of forcing the step of every node down to its tiny mass.
  pure logical function sliver_node(ms, mf)
    real(wp), intent(in) :: ms, mf
    sliver_node = ms > 0.0_wp .and. mf > 0.0_wp .and. min(ms, mf) < sliver_fraction*max(ms, mf)
  end function sliver_node

  !> Largest stable step of forward Euler on the relative motion of the two
  !> phases at a node, 2 / (d (1/ms + 1/mf)) (doc/theory.md 7.2, the binding limit of
  !> explicit drag); huge where a phase or the drag is absent.
  pure real(wp) function drag_limit(ms, mf, d) result(dt)
    real(wp), intent(in) :: ms, mf, d
    dt = huge(1.0_wp)
    if (ms > 0.0_wp .and. mf > 0.0_wp .and. d > 0.0_wp) dt = 2.0_wp/(d*(1.0_wp/ms + 1.0_wp/mf))
  end function drag_limit

  !> Largest stable step of explicit drag over the nodes olo..ohi (this rank's owned
  !> nodes) from the summed solid and fluid node fields and the drag coefficient;
  !> sliver nodes, which take the drag implicitly, are left out.
  pure real(wp) function nodal_drag_limit(lo, olo, ohi, node_s, node_f, ndrag) result(dtmin)
    integer, intent(in) :: lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: ndrag(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k
    dtmin = huge(1.0_wp)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        do i = olo(1), ohi(1)
          if (sliver_node(node_s(1, i, j, k), node_f(1, i, j, k))) cycle
          dtmin = min(dtmin, drag_limit(node_s(1, i, j, k), node_f(1, i, j, k), ndrag(1, i, j, k)))
        end do
      end do
    end do
  end function nodal_drag_limit

  !> The MUSL-remapped velocities of the nodes where both phases move freely
  !> (owned nodes, new-velocity slots): where the drag locks the phases, the
  !> relative velocity the remap adds to that of the nodal update (wstep) is
  !> shrunk as the step's implicit drag would (drag_relax).
  !> Each point set projects the same nodal increments with its own masses, so
  !> the plain remap leaves a relative velocity of the phases that no drag has
  !> acted on; fed to the strain and pore-pressure rates it makes the
  !> amplification of the step exceed 1 once the drag couples the phases.
  subroutine relax_remapped(nd, lo, olo, ohi, faces, mbc, node_s, node_f, ndrag, dt, wstep, nvel_s, nvel_f)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    type(face_loads_t), intent(in) :: faces
    integer, intent(in) :: mbc(6)            !< the fluid's mirror conditions
    real(wp), intent(in) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: ndrag(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: dt
    real(wp), intent(in) :: wstep(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: nvel_s(:, lo(1):, lo(2):, lo(3):), nvel_f(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k, c, ilo(3), ihi(3)
    logical :: free(3), row_near
    call faces%inner_nodes(ilo, ihi)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        row_near = j < ilo(2) .or. j > ihi(2) .or. k < ilo(3) .or. k > ihi(3)
        do i = olo(1), ohi(1)
          if (node_s(1, i, j, k) <= 0.0_wp .or. node_f(1, i, j, k) <= 0.0_wp) cycle
          free = .true.
          if (row_near .or. i < ilo(1) .or. i > ihi(1)) free = free_components(faces, mbc, [i, j, k])
          do c = 1, nd
            if (.not. free(c)) cycle
            call drag_relax(node_s(1, i, j, k), node_f(1, i, j, k), &
                            ndrag(1, i, j, k), dt, wstep(c, i, j, k), nvel_s(nd + c, i, j, k), &
                            nvel_f(nd + c, i, j, k))
          end do
        end do
      end do
    end do
  end subroutine relax_remapped

  !> True for the components of node (i, j, k) that both phases move freely (not held
  !> by a face condition of either, not tied).
  function free_components(faces, mbc, idx) result(free)
    type(face_loads_t), intent(in) :: faces
    integer, intent(in) :: mbc(6), idx(3)
    logical :: free(3)
    free = .true.
    if (.not. faces%near_face(idx)) return
    free = .not. (faces%walls%constrained(idx) .or. faces%walls%constrained(idx, mbc) .or. &
                  faces%fluid_ties(idx))
  end function free_components

  !> The velocity increment that the step's implicit drag makes common to the two
  !> phases, at the owned nodes (0 elsewhere): (1 - f) times the increment of the
  !> mixture velocity in the nodal update (new minus start-of-step slots of nvel),
  !> f = ms mf / (ms mf + dt d (ms + mf)) the factor by which the drag shrinks a
  !> relative velocity in one step (1 where it is absent, so c = 0 there), on the
  !> components both phases move freely.
  subroutine locked_velocity(nd, lo, olo, ohi, faces, mbc, node_s, node_f, ndrag, dt, nvel_s, nvel_f, c)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    type(face_loads_t), intent(in) :: faces
    integer, intent(in) :: mbc(6)            !< the fluid's mirror conditions
    real(wp), intent(in) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: ndrag(:, lo(1):, lo(2):, lo(3):), dt
    real(wp), intent(in) :: nvel_s(:, lo(1):, lo(2):, lo(3):), nvel_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(out) :: c(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k, ilo(3), ihi(3)
    real(wp) :: ms, mf, f
    logical :: free(3), row_near
    c = 0.0_wp
    call faces%inner_nodes(ilo, ihi)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        row_near = j < ilo(2) .or. j > ihi(2) .or. k < ilo(3) .or. k > ihi(3)
        do i = olo(1), ohi(1)
          ms = node_s(1, i, j, k); mf = node_f(1, i, j, k)
          if (ms <= 0.0_wp .or. mf <= 0.0_wp .or. ndrag(1, i, j, k) <= 0.0_wp) cycle
          f = ms*mf/(ms*mf + dt*ndrag(1, i, j, k)*(ms + mf))
          c(:, i, j, k) = (1.0_wp - f)*(ms*(nvel_s(nd + 1:2*nd, i, j, k) - nvel_s(1:nd, i, j, k)) + &
                                        mf*(nvel_f(nd + 1:2*nd, i, j, k) - nvel_f(1:nd, i, j, k)))/(ms + mf)
          if (.not. (row_near .or. i < ilo(1) .or. i > ihi(1))) cycle
          free = free_components(faces, mbc, [i, j, k])
          where (.not. free(1:nd)) c(:, i, j, k) = 0.0_wp
        end do
      end do
    end do
  end subroutine locked_velocity

  !> Take from the MUSL-remapped pair (new slots of nvel_s, nvel_f, owned nodes) the
  !> relative velocity that the two point sets' projections make of one common
  !> velocity c: ps and pf hold the momenta sum_p N_I m_p (sum_J N_J c_J) of each set
  !> (momentum_project_p2g), so that P_s c = ps / m_s and P_f c = pf / m_f, and the split P_f c - P_s c is
  !> removed from v_f - v_s with the momentum of the pair kept, on the components
  !> both phases move freely. On points at the same places P_s = P_f and nothing
  !> changes.
  subroutine remove_split(nd, lo, olo, ohi, faces, mbc, node_s, node_f, ps, pf, nvel_s, nvel_f)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    type(face_loads_t), intent(in) :: faces
    integer, intent(in) :: mbc(6)
    real(wp), intent(in) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: ps(:, lo(1):, lo(2):, lo(3):), pf(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: nvel_s(:, lo(1):, lo(2):, lo(3):), nvel_f(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k, ilo(3), ihi(3)
    real(wp) :: ms, mf, split(3)
    logical :: free(3), row_near
    call faces%inner_nodes(ilo, ihi)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        row_near = j < ilo(2) .or. j > ihi(2) .or. k < ilo(3) .or. k > ihi(3)
        do i = olo(1), ohi(1)
          ms = node_s(1, i, j, k); mf = node_f(1, i, j, k)
          if (ms <= 0.0_wp .or. mf <= 0.0_wp) cycle
          split(1:nd) = pf(1:nd, i, j, k)/mf - ps(1:nd, i, j, k)/ms
          if (row_near .or. i < ilo(1) .or. i > ihi(1)) then
            free = free_components(faces, mbc, [i, j, k])
            where (.not. free(1:nd)) split(1:nd) = 0.0_wp
          end if
          nvel_s(nd + 1:2*nd, i, j, k) = nvel_s(nd + 1:2*nd, i, j, k) + mf/(ms + mf)*split(1:nd)
          nvel_f(nd + 1:2*nd, i, j, k) = nvel_f(nd + 1:2*nd, i, j, k) - ms/(ms + mf)*split(1:nd)
        end do
      end do
    end do
  end subroutine remove_split

end module dpmpm_drag
