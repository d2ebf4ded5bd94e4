!> The nodal update (doc/theory.md 4.2): nodal velocities before and
!> after the step from the summed node fields, with gravity, face loads and the
!> boundary conditions, for one phase alone or for the two phases coupled by the
!> drag (drag_solve: here, beside its caller, so that the compiler inlines it; the
!> drag's other parts are in dpmpm_drag) and the dashpots of absorbing faces (the MUSL
!> remap's nodal velocities and the fluid's ties: dpmpm_boundary). Work of the external
!> forces and the drag dissipation are booked here for the energy balance.
module dpmpm_nodal_update
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: node_slots_t, node_slots
  use dpmpm_face_loads, only: face_loads_t
  use dpmpm_drag, only: sliver_node
  use dpmpm_damping, only: rayleigh_mass
  implicit none
  private
  public :: nodal_update, nodal_update_coupled, drag_solve

contains

  !> One phase: nodal velocities before and after the update (nvel, cleared first on
  !> olo..ohi; the caller's node fields are zero beyond), with gravity, tractions and
  !> boundary conditions, on the nodes olo..ohi; the work of the external forces is
  !> added to ext_work.
  subroutine nodal_update(nd, lo, olo, ohi, node, gravity, faces, time, dt, nvel, ext_work, &
                          damping, dissipated, rayleigh)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: gravity(3)
    type(face_loads_t), intent(in) :: faces
    real(wp), intent(in) :: time, dt
    real(wp), intent(inout) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: ext_work
    real(wp), intent(in) :: damping           !< local damping coefficient (0 = none)
    real(wp), intent(inout) :: dissipated     !< energy taken by the local damping and wall friction
    real(wp), intent(in), optional :: rayleigh(4) !< Rayleigh's alpha and reference velocity (dpmpm_damping)
    integer :: i, j, k
    real(wp) :: m, vold(3), vnew(3), fext(3), cd(3), fd(3), ffr(3), wf, vwall(3), fin(3)
    integer :: contact(3)
    logical :: fix(3), near, rough
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    nvel(:, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) = 0.0_wp
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        do i = olo(1), ohi(1)
          m = node(1, i, j, k)
          if (m <= 0.0_wp) cycle
          near = faces%near_face([i, j, k])
          fix = .false.
          if (near) fix = faces%walls%constrained([i, j, k])
          vold = 0.0_wp
          vold(1:nd) = node(sl%mom_lo:sl%mom_hi, i, j, k)/m
          if (near) then
            fext = m*gravity + faces%traction(time, [i, j, k]) + faces%absorbing_static([i, j, k], .false.)
          else
            fext = m*gravity
          end if
          vnew = 0.0_wp
          if (damping > 0.0_wp) then
            ! Local damping: a force against the motion of each component, a fraction of
            ! the unbalanced force (doc/theory.md 6.5).
            fd(1:nd) = -damping*abs(node(sl%force_lo:sl%force_hi, i, j, k) + fext(1:nd))*sign(1.0_wp, vold(1:nd))
            where (vold(1:nd) == 0.0_wp) fd(1:nd) = 0.0_wp
            fext(1:nd) = fext(1:nd) + fd(1:nd)
          end if
          vnew(1:nd) = vold(1:nd) + dt*(node(sl%force_lo:sl%force_hi, i, j, k) + fext(1:nd))/m
          if (present(rayleigh)) call rayleigh_mass(nd, m, dt, rayleigh, fix, vold, vnew, ext_work, dissipated)
          ! Dashpots of absorbing faces, at the new velocity (stable at any step).
          cd = 0.0_wp
          fin = 0.0_wp
          if (near) cd = faces%dashpot([i, j, k], .false.)
          if (any(cd(1:nd) > 0.0_wp)) then
            ! with the incoming force of a compliant base: m (v_new - v*) = dt (f_in - c v_new)
            if (faces%inflow > 0) fin = faces%incoming(time + dt, [i, j, k])
            vnew(1:nd) = (vnew(1:nd)*m + dt*fin(1:nd))/(m + dt*cd(1:nd))
          end if
          rough = near .and. faces%walls%rough
          if (rough) then
            ! A rough wall pushes and rubs but does not pull (doc/theory.md 6.7): it holds
            ! the normal component of a node that runs into it, whose whole normal velocity
            ! it takes (the impulse of the friction), and lets go of one moving away.
            contact = faces%walls%wall_contact([i, j, k], nd, vnew)
            where (contact == 2) fix = .false.
            ffr = vnew
            ! Where the wall holds its nodes whatever their motion (lift_off = .false.),
            ! the impulse is the change of the step (the normal velocity is held at zero).
            vwall = vnew
            if (all(contact == 0)) vwall = vnew - vold
            call faces%walls%wall_friction([i, j, k], nd, fix, vwall, vnew)
            where (contact == 1) vnew = 0.0_wp
            ! The wall's force, normal and friction, m dv/dt.
            ffr = m*(vnew - ffr)/dt
            ! A held normal component keeps its old velocity in nvel, so that the points'
            ! FLIP update takes the normal velocity they carry into the wall away with it.
            where (contact == 1) fix = .false.
          end if
          where (fix) vold = 0.0_wp
          where (fix) vnew = 0.0_wp
          nvel(sl%old_lo:sl%old_hi, i, j, k) = vold(1:nd)
          nvel(sl%new_lo:sl%new_hi, i, j, k) = vnew(1:nd)
          ext_work = ext_work + 0.5_wp*dt*dot_product(fext(1:nd) + fin(1:nd) - cd(1:nd)*vnew(1:nd), &
                                                      vold(1:nd) + vnew(1:nd))
          if (rough) then
            ! The wall's work (the friction's, and the normal force's where the node ran
            ! into the wall): in ext_work and counted as dissipated, as the damping's.
            wf = 0.5_wp*dt*dot_product(ffr(1:nd), vold(1:nd) + vnew(1:nd))
            ext_work = ext_work + wf
            dissipated = dissipated - wf
          end if
          if (damping > 0.0_wp) then
            ! The damping force is no load: its work (in ext_work above, like the drag's)
            ! is the energy it takes.
            dissipated = dissipated - 0.5_wp*dt*dot_product(fd(1:nd), vold(1:nd) + vnew(1:nd))
          end if
        end do
      end do
    end do
  end subroutine nodal_update

  !> Nodal update of both phases on the owned nodes (doc/theory.md 4.2):
  !> forces, gravity, the total-stress traction (on the solid where there is
  !> solid) and the prescribed pore pressure of drained faces, the drag solve
  !> (explicit or implicit) where both phases meet, each phase alone elsewhere,
  !> and the per-phase conditions: solid fixed/roller components are zero; at
  !> impermeable faces the normal fluid velocity is zero (solid held) or the
  !> solid's (solid free: the mixture moves together in that component).
  !> With rnode (rigid_p2g: the rigid points' mass and momentum sums), the solid at
  !> every node a rigid body reaches moves at the body's velocity v_r, and the fluid
  !> there is solved against that moving skeleton; the force this takes (the drive's
  !> reaction: what the solid's own forces and the drag leave to reach v_r) is added to
  !> rforce and its work, over the step's mean solid velocity, to ext_work.
  subroutine nodal_update_coupled(nd, lo, olo, ohi, node_s, node_f, nporo, ndrag, gravity, faces, &
                                  mbc, implicit, time, dt, nvel_s, nvel_f, ext_work, drag_loss, damping, &
                                  rnode, rforce, fvol, thin)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: nporo(:, lo(1):, lo(2):, lo(3):), ndrag(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: gravity(3)
    type(face_loads_t), intent(in) :: faces
    integer, intent(in) :: mbc(6)            !< the fluid's mirror conditions (fluid_mirror_bc)
    logical, intent(in) :: implicit          !< implicit drag
    real(wp), intent(in) :: time, dt
    real(wp), intent(inout) :: nvel_s(:, lo(1):, lo(2):, lo(3):), nvel_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: ext_work, drag_loss
    real(wp), intent(in) :: damping          !< local damping coefficient (0 = none)
    real(wp), intent(in), optional :: rnode(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout), optional :: rforce(3)
    !> With fvol, the pore water's volume at the nodes (sum_p N_Ip V_p), and thin: where the
    !> water fills less than thin of a node's volume inside the grid (node_volume), the
    !> drained faces' pore pressure acts on neither phase there, since the water has left.
    real(wp), intent(in), optional :: fvol(:, lo(1):, lo(2):, lo(3):), thin
    integer :: i, j, k, c
    real(wp) :: ms, mf, dn, vs(3), vf(3), fs(3), ff(3), vsn(3), vfn(3), tr(3), fps(3), fpf(3), v
    real(wp) :: cs(3), cf(3), ts(3), tf(3), fds(3), fdf(3), vr(3)
    real(wp) :: pushs(3), pushf(3), dve(3), vt(3), rp, meff, ffr(3), vs0(3), vf0(3)
    logical :: sfix(3), ffix(3), tie(3), near, rigid(3), imp, rough, row_near, plain
    integer :: ilo(3), ihi(3)
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    nvel_s(:, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) = 0.0_wp
    nvel_f(:, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) = 0.0_wp
    call faces%inner_nodes(ilo, ihi)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        row_near = j < ilo(2) .or. j > ihi(2) .or. k < ilo(3) .or. k > ihi(3)
        do i = olo(1), ohi(1)
          ms = node_s(1, i, j, k)
          mf = node_f(1, i, j, k)
          dn = ndrag(1, i, j, k)
          if (ms <= 0.0_wp .and. mf <= 0.0_wp) cycle
          if (ms <= 0.0_wp .or. mf <= 0.0_wp) dn = 0.0_wp
          ! Explicit drag except at a node that one phase barely reaches (sliver_node):
          ! there it is implicit, which is stable at any step.
          imp = implicit .or. sliver_node(ms, mf)
          near = row_near .or. i < ilo(1) .or. i > ihi(1)
          ! A node that no face condition reaches, without damping or a rigid body, takes
          ! the plain update (update_plain, the same arithmetic without the zero terms).
          plain = .not. (near .or. damping > 0.0_wp)
          if (plain .and. present(rnode)) plain = rnode(1, i, j, k) <= 0.0_wp
          if (plain) then
            call update_plain()
            cycle
          end if
          vs = 0.0_wp; vf = 0.0_wp; fs = 0.0_wp; ff = 0.0_wp
          tr = 0.0_wp; ts = 0.0_wp; tf = 0.0_wp; fps = 0.0_wp; fpf = 0.0_wp
          if (near) then
            tr = faces%traction(time, [i, j, k])
            ! The static load of absorbing faces on each phase.
            ts = faces%absorbing_static([i, j, k], .false.)
            tf = faces%absorbing_static([i, j, k], .true.)
            fps = faces%pore_pressure_force(time, [i, j, k], faces%walls%bc)
            fpf = faces%pore_pressure_force(time, [i, j, k], mbc)
            if (present(fvol) .and. (any(fps /= 0.0_wp) .or. any(fpf /= 0.0_wp))) then
              if (fvol(1, i, j, k) < thin*faces%node_volume([i, j, k])) then
                fps = 0.0_wp
                fpf = 0.0_wp
              end if
            end if
          end if
          if (ms > 0.0_wp) then
            vs(1:nd) = node_s(sl%mom_lo:sl%mom_hi, i, j, k)/ms
            fs(1:nd) = node_s(sl%force_lo:sl%force_hi, i, j, k)
            fs = fs + ms*gravity + tr + nporo(1, i, j, k)*fps + ts
          end if
          if (mf > 0.0_wp) then
            vf(1:nd) = node_f(sl%mom_lo:sl%mom_hi, i, j, k)/mf
            ff(1:nd) = node_f(sl%force_lo:sl%force_hi, i, j, k)
            ff = ff + mf*gravity - nporo(1, i, j, k)*fpf + tf
            ! Where there is no solid the traction (a total stress) loads the water, unless
            ! a drained face's pore pressure already does: for water alone both are the
            ! same load, -p.
            if (ms <= 0.0_wp .and. all(fpf == 0.0_wp)) ff = ff + tr
          end if
          sfix = .false.; ffix = .false.; tie = .false.; cs = 0.0_wp; cf = 0.0_wp
          if (near) then
            sfix = faces%walls%constrained([i, j, k])
            ffix = faces%walls%constrained([i, j, k], mbc)
            tie = faces%fluid_ties([i, j, k])
            cs = faces%dashpot([i, j, k], .false.)
            cf = faces%dashpot([i, j, k], .true.)
          end if
          vsn = 0.0_wp; vfn = 0.0_wp
          fds = 0.0_wp; fdf = 0.0_wp
          rigid = .false.
          if (present(rnode)) then
            if (rnode(1, i, j, k) > 0.0_wp) then
              vr = 0.0_wp
              vr(1:nd) = rnode(sl%mom_lo:sl%mom_hi, i, j, k)/rnode(1, i, j, k)
              rigid(1:nd) = .not. sfix(1:nd)
            end if
          end if
          if (damping > 0.0_wp) then
            ! Local damping of each phase, against its motion (doc/theory.md 6.5).
            if (ms > 0.0_wp) fds(1:nd) = -damping*abs(fs(1:nd))*sign(1.0_wp, vs(1:nd))
            if (mf > 0.0_wp) fdf(1:nd) = -damping*abs(ff(1:nd))*sign(1.0_wp, vf(1:nd))
            where (vs(1:nd) == 0.0_wp) fds(1:nd) = 0.0_wp
            where (vf(1:nd) == 0.0_wp) fdf(1:nd) = 0.0_wp
            fs = fs + fds
            ff = ff + fdf
          end if
          ! A skeleton node on a rough wall (not driven by a rigid body) takes friction, and
          ! its tangential components are solved again from the velocities kept here.
          rough = near .and. faces%walls%rough .and. ms > 0.0_wp .and. .not. any(rigid)
          if (rough) then
            vs0 = vs; vf0 = vf
          end if
          do c = 1, nd
            call solve_component(c, 0.0_wp)
          end do
          ffr = 0.0_wp
          if (rough) then
            ! Coulomb friction of rough walls on the skeleton (doc/theory.md 6.7), from the
            ! effective normal force: what the skeleton pushes against the wall less the
            ! pore pressure's share of it. Where the wall holds the water, that share is
            ! (1 - n)/n of the water's push (both carry the same p); at a drained face it is
            ! the face's pore-pressure load (the skeleton carries the total stress there).
            ! The friction force joins the skeleton's forces and the drag solve is repeated,
            ! so that the water takes its share of the friction as the drag gives it; meff
            ! is the mass that a force on the skeleton moves in that solve, so that a
            ! sticking node comes to rest.
            meff = ms
            if (mf > 0.0_wp .and. imp) meff = (ms*mf + dt*dn*(ms + mf))/(mf + dt*dn)
            dve = 0.0_wp
            do c = 1, nd
              if (.not. sfix(c)) cycle
              if (mf > 0.0_wp .and. ffix(c)) then
                rp = (1.0_wp - nporo(1, i, j, k))/nporo(1, i, j, k)*pushf(c)
              else if (mf > 0.0_wp) then
                rp = fps(c)
              else
                rp = nporo(1, i, j, k)*fps(c)
              end if
              dve(c) = dt*(pushs(c) - rp)/meff
            end do
            vt = vsn
            call faces%walls%wall_friction([i, j, k], nd, sfix, dve, vt)
            ffr(1:nd) = meff*(vt(1:nd) - vsn(1:nd))/dt
            do c = 1, nd
              if (ffr(c) == 0.0_wp) cycle
              vs(c) = vs0(c); vf(c) = vf0(c)
              call solve_component(c, ffr(c))
            end do
          end if
          do c = 1, nd
            ! Energy dissipated by the drag: the drag force (at the old relative
            ! velocity w, or the new one when implicit) times the mid-step w, with
            ! the constrained velocities (a held phase does no work; a tied pair and
            ! a node with one phase, dn = 0, give none).
            v = dt*dn*merge(vfn(c) - vsn(c), vf(c) - vs(c), imp)*0.5_wp*(vf(c) + vfn(c) - vs(c) - vsn(c))
            ext_work = ext_work - v
            drag_loss = drag_loss + v
            ! Work of the dashpots (energy leaving through absorbing faces).
            ext_work = ext_work - 0.5_wp*dt*(merge(cs(c)*vsn(c)*(vs(c) + vsn(c)), 0.0_wp, ms > 0.0_wp) + &
                                             merge(cf(c)*vfn(c)*(vf(c) + vfn(c)), 0.0_wp, mf > 0.0_wp))
            ! The damping forces' and the wall friction's work: taken from ext_work and
            ! counted as dissipated, as the drag's.
            v = 0.5_wp*dt*((fds(c) + ffr(c))*(vs(c) + vsn(c)) + fdf(c)*(vf(c) + vfn(c)))
            ext_work = ext_work + v
            drag_loss = drag_loss - v
          end do
          nvel_s(sl%old_lo:sl%old_hi, i, j, k) = vs(1:nd)
          nvel_s(sl%new_lo:sl%new_hi, i, j, k) = vsn(1:nd)
          nvel_f(sl%old_lo:sl%old_hi, i, j, k) = vf(1:nd)
          nvel_f(sl%new_lo:sl%new_hi, i, j, k) = vfn(1:nd)
          ! Work of the external forces (gravity, tractions, boundary pore pressure).
          if (ms > 0.0_wp) ext_work = ext_work + 0.5_wp*dt*dot_product( &
            ms*gravity(1:nd) + tr(1:nd) + nporo(1, i, j, k)*fps(1:nd) + ts(1:nd), vs(1:nd) + vsn(1:nd))
          if (mf > 0.0_wp) ext_work = ext_work + 0.5_wp*dt*dot_product( &
            mf*gravity(1:nd) - nporo(1, i, j, k)*fpf(1:nd) + tf(1:nd) + &
            merge(tr(1:nd), 0.0_wp*tr(1:nd), ms <= 0.0_wp), vf(1:nd) + vfn(1:nd))
        end do
      end do
    end do
  contains

    !> The update at the node (i, j, k) of the loop where no face condition, damping,
    !> rigid body or wall friction acts: the general update above with its zero loads,
    !> dashpots and constraints left out, the remaining operations in the same order
    !> (so the same results: a zero load added turns a -0 force into +0, hence the
    !> "+ 0.0_wp", and zero terms of the work sums leave them unchanged).
    subroutine update_plain()
      integer :: c
      real(wp) :: as, af, w
      real(wp) :: us(3), uf(3), usn(3), ufn(3)
      us = 0.0_wp; uf = 0.0_wp; usn = 0.0_wp; ufn = 0.0_wp
      if (ms > 0.0_wp .and. mf > 0.0_wp) then
        do c = 1, nd
          us(c) = node_s(sl%mom_lo - 1 + c, i, j, k)/ms
          uf(c) = node_f(sl%mom_lo - 1 + c, i, j, k)/mf
          call drag_solve(ms, mf, dn, node_s(sl%force_lo - 1 + c, i, j, k) + ms*gravity(c) + 0.0_wp, &
                          node_f(sl%force_lo - 1 + c, i, j, k) + mf*gravity(c) + 0.0_wp, us(c), uf(c), dt, imp, as, af)
          usn(c) = us(c) + dt*as
          ufn(c) = uf(c) + dt*af
        end do
      else if (ms > 0.0_wp) then
        do c = 1, nd
          us(c) = node_s(sl%mom_lo - 1 + c, i, j, k)/ms
          usn(c) = us(c) + dt*(node_s(sl%force_lo - 1 + c, i, j, k) + ms*gravity(c) + 0.0_wp)/ms
        end do
      else
        do c = 1, nd
          uf(c) = node_f(sl%mom_lo - 1 + c, i, j, k)/mf
          ufn(c) = uf(c) + dt*(node_f(sl%force_lo - 1 + c, i, j, k) + mf*gravity(c) + 0.0_wp)/mf
        end do
      end if
      do c = 1, nd
        w = dt*dn*merge(ufn(c) - usn(c), uf(c) - us(c), imp)*0.5_wp*(uf(c) + ufn(c) - us(c) - usn(c))
        ext_work = ext_work - w
        drag_loss = drag_loss + w
      end do
      nvel_s(sl%old_lo:sl%old_hi, i, j, k) = us(1:nd)
      nvel_s(sl%new_lo:sl%new_hi, i, j, k) = usn(1:nd)
      nvel_f(sl%old_lo:sl%old_hi, i, j, k) = uf(1:nd)
      nvel_f(sl%new_lo:sl%new_hi, i, j, k) = ufn(1:nd)
      if (ms > 0.0_wp) ext_work = ext_work + 0.5_wp*dt*dot_product(ms*gravity(1:nd), us(1:nd) + usn(1:nd))
      if (mf > 0.0_wp) ext_work = ext_work + 0.5_wp*dt*dot_product(mf*gravity(1:nd), uf(1:nd) + ufn(1:nd))
    end subroutine update_plain

    !> The update of component c at the node (i, j, k) of the loop, with the extra force
    !> fadd on the skeleton: the new velocities vsn(c), vfn(c) (vs(c), vf(c) constrained
    !> as the conditions ask), the rigid drive's reaction, and what each phase pushes
    !> against a wall in this component (pushs, pushf: its forces and the drag with the
    !> constrained velocities).
    subroutine solve_component(c, fadd)
      integer, intent(in) :: c
      real(wp), intent(in) :: fadd
      real(wp) :: msd, mfd, fsd, ffd, as, af, v, r
      ! Dashpots of absorbing faces act at the new velocities (-cs vsn, -cf vfn):
      ! they add dt cs, dt cf to the masses and -cs vs, -cf vf to the forces of
      ! the solve (nothing where cs = cf = 0).
      msd = ms + dt*cs(c); mfd = mf + dt*cf(c)
      fsd = fs(c) - cs(c)*vs(c) + fadd; ffd = ff(c) - cf(c)*vf(c)
      vsn(c) = 0.0_wp; vfn(c) = 0.0_wp
      if (rigid(c)) then
        ! Driven by a rigid body: the solid moves at v_r, the fluid against it
        ! (or with it, normal to an impermeable face); r is the drive's reaction.
        vsn(c) = vr(c)
        if (mf > 0.0_wp .and. tie(c)) then
          v = (ms*vs(c) + mf*vf(c))/(ms + mf)
          vs(c) = v; vf(c) = v
          vfn(c) = vr(c)
          r = (msd + mfd)*(vr(c) - v)/dt - fs(c) - ff(c) + (cs(c) + cf(c))*v
        else if (mf > 0.0_wp) then
          if (imp) then
            af = (ffd - dn*(vf(c) - vr(c)))/(mfd + dt*dn)
            vfn(c) = vf(c) + dt*af
            r = msd*(vr(c) - vs(c))/dt - fsd - dn*(vfn(c) - vr(c))
          else
            af = (ffd - dn*(vf(c) - vs(c)))/mfd
            vfn(c) = vf(c) + dt*af
            r = msd*(vr(c) - vs(c))/dt - fsd - dn*(vf(c) - vs(c))
          end if
        else
          r = msd*(vr(c) - vs(c))/dt - fsd
        end if
        rforce(c) = rforce(c) + r
        ext_work = ext_work + 0.5_wp*dt*r*(vs(c) + vsn(c))
      else if (ms > 0.0_wp .and. mf > 0.0_wp .and. tie(c)) then
        ! The mixture moves together normal to an impermeable face.
        v = (ms*vs(c) + mf*vf(c))/(ms + mf)
        vs(c) = v; vf(c) = v
        v = v + dt*(fs(c) + ff(c) + fadd - (cs(c) + cf(c))*v)/(msd + mfd)
        vsn(c) = v; vfn(c) = v
      else if (ms > 0.0_wp .and. mf > 0.0_wp) then
        if (sfix(c)) then
          ! Solid held: the fluid moves against a resting skeleton.
          vs(c) = 0.0_wp
          af = (ffd - dn*vf(c))/merge(mfd + dt*dn, mfd, imp)
        else
          call drag_solve(msd, mfd, dn, fsd, ffd, vs(c), vf(c), dt, imp, as, af)
          vsn(c) = vs(c) + dt*as
        end if
        vfn(c) = vf(c) + dt*af
      else if (ms > 0.0_wp) then
        vsn(c) = vs(c) + dt*fsd/msd
      else
        vfn(c) = vf(c) + dt*ffd/mfd
      end if
      if (sfix(c)) then
        vs(c) = 0.0_wp; vsn(c) = 0.0_wp
      end if
      if (ffix(c)) then
        vf(c) = 0.0_wp; vfn(c) = 0.0_wp
      end if
      v = dn*merge(vfn(c) - vsn(c), vf(c) - vs(c), imp)
      pushs(c) = fsd + v
      pushf(c) = ffd - v
    end subroutine solve_component

  end subroutine nodal_update_coupled

  !> Accelerations of one velocity component at a node with both phases, masses
  !> ms, mf, forces fs, ff (everything but drag), drag coefficient d and the
  !> velocities vs, vf at the start of the step. Explicit: forward Euler on the
  !> drag, m_s a_s = f_s + d (v_f - v_s), m_f a_f = f_f - d (v_f - v_s). Implicit
  !> (doc/theory.md 4.2): the drag at the new velocities, the 2x2 system
  !> [ms + dt d, -dt d; -dt d, mf + dt d] (a_s, a_f) = (f_s + d w, f_f - d w),
  !> w = v_f - v_s, determinant ms mf + dt d (ms + mf) > 0.
  pure subroutine drag_solve(ms, mf, d, fs, ff, vs, vf, dt, implicit, as, af)
    real(wp), intent(in) :: ms, mf, d, fs, ff, vs, vf, dt
    logical, intent(in) :: implicit
    real(wp), intent(out) :: as, af
    real(wp) :: w, r1, r2, det, e
    w = vf - vs
    r1 = fs + d*w
    r2 = ff - d*w
    if (.not. implicit) then
      as = r1/ms
      af = r2/mf
      return
    end if
    e = dt*d
    det = ms*mf + e*(ms + mf)
    as = ((mf + e)*r1 + e*r2)/det
    af = (e*r1 + (ms + e)*r2)/det
  end subroutine drag_solve

end module dpmpm_nodal_update
