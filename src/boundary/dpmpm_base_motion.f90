!> The rigid base of a shaken scene (&motion base): the nodes of one grid face follow the
!> velocity of the recorded motion, in every component and in both phases, from the end of
!> the equilibrium phase on (the motion's time zero; the face is fixed before). The face is
!> a fixed face whose held velocity is the motion's instead of zero: the nodes take the
!> base's velocity at the start of the step in the old-velocity slots and at its end in the
!> new ones, so that FLIP hands the points near the base the base's change of velocity, as a
!> fixed face hands them none. The face stays where the grid has it (small displacements:
!> the base moves by the record's displacement, which must stay well within a cell).
module dpmpm_base_motion
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: node_slots_t, node_slots
  use dpmpm_config, only: config_t, face_index
  use dpmpm_motion, only: motion_velocity
  implicit none
  private
  public :: base_face, compliant_face, base_velocity, shake_base

contains

  !> The face of the rigid base (index into face_names), 0 without one.
  pure integer function base_face(cfg)
    type(config_t), intent(in) :: cfg
    base_face = 0
    if (len_trim(cfg%motion_base) > 0) base_face = face_index(cfg%motion_base)
    ! an absorbing base is compliant (compliant_face): its nodes are free
    if (base_face > 0) then
      if (cfg%absorbing(base_face) /= 0) base_face = 0
    end if
  end function base_face

  !> The face of the compliant base (&motion base on an absorbing face; index into
  !> face_names), 0 without one: its dashpots take the rock's impedance and the motion
  !> enters as the traction of the rock's dashpots at the outcrop velocity (doc/theory.md
  !> 6.6).
  pure integer function compliant_face(cfg)
    type(config_t), intent(in) :: cfg
    compliant_face = 0
    if (len_trim(cfg%motion_base) > 0) compliant_face = face_index(cfg%motion_base)
    if (compliant_face > 0) then
      if (cfg%absorbing(compliant_face) == 0) compliant_face = 0
    end if
  end function compliant_face

  !> The base's velocity at run time t: the &motion histories at the motion time
  !> t - equilibrium_time; at rest before it.
  pure function base_velocity(cfg, t) result(v)
    type(config_t), intent(in) :: cfg
    real(wp), intent(in) :: t
    real(wp) :: v(3)
    integer :: d
    v = 0.0_wp
    if (t < cfg%equilibrium_time) return
    do d = 1, cfg%ndim
      v(d) = motion_velocity(cfg%motion(d), t - cfg%equilibrium_time)
    end do
  end function base_velocity

  !> The nodes of face (index into face_names; the grid has ncells cells) among olo..ohi that
  !> hold mass take the base's velocity: vb1 in the new-velocity slots of nvel, and with
  !> both vb0 in the old ones (the nodal update; the remap sets only the new ones). With
  !> both, the work over the step of the base's force on them (the momentum change that
  !> their own forces node(2+nd:1+2nd) and gravity do not make) and of gravity on them is
  !> added to work: the nodal update held these nodes at rest, so it booked neither; a
  !> vertical motion lifts and lowers their mass.
  subroutine shake_base(nd, lo, olo, ohi, face, ncells, vb0, vb1, node, nvel, both, gravity, &
                        dt, work)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3), face, ncells(3)
    real(wp), intent(in) :: vb0(3), vb1(3)
    real(wp), intent(in) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: nvel(:, lo(1):, lo(2):, lo(3):)
    logical, intent(in) :: both
    real(wp), intent(in) :: gravity(3), dt
    real(wp), intent(inout) :: work
    integer :: a, i, j, k, flo(3), fhi(3)
    real(wp) :: m, fb(3)
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    a = (face + 1)/2
    flo = olo
    fhi = ohi
    flo(a) = 0
    if (mod(face, 2) == 0) flo(a) = ncells(a)
    fhi(a) = flo(a)
    if (flo(a) < olo(a) .or. flo(a) > ohi(a)) return
    do k = flo(3), fhi(3)
      do j = flo(2), fhi(2)
        do i = flo(1), fhi(1)
          m = node(1, i, j, k)
          if (m <= 0.0_wp) cycle
          nvel(sl%new_lo:sl%new_hi, i, j, k) = vb1(1:nd)
          if (.not. both) cycle
          nvel(sl%old_lo:sl%old_hi, i, j, k) = vb0(1:nd)
          fb(1:nd) = m*(vb1(1:nd) - vb0(1:nd))/dt - node(sl%force_lo:sl%force_hi, i, j, k) - m*gravity(1:nd)
          work = work + 0.5_wp*dt*dot_product(fb(1:nd) + m*gravity(1:nd), vb0(1:nd) + vb1(1:nd))
        end do
      end do
    end do
  end subroutine shake_base

end module dpmpm_base_motion
