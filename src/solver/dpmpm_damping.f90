!> Rayleigh damping of the solid, C = alpha M + beta K (doc/theory.md 4.7; &run rayleigh_*).
!> The mass-proportional part is a nodal force -alpha m (v - v_ref), v_ref the rigid base's
!> velocity where &motion base moves the base (zero otherwise), taken implicitly in the
!> nodal update (rayleigh_mass): the rigid motion of the whole body is not damped, and the
!> factor 1/(1 + alpha dt) is stable at any step. The stiffness-proportional part is the
!> viscous stress beta D:eps_dot of the start-of-step velocities, D the linear-elastic
!> stiffness of the point's material (its youngs_modulus and poisson_ratio), whose forces
!> join the internal forces of the step (viscous_forces) without entering the points'
!> stress: the constitutive models see only their own stress. It lowers the stable step
!> (damped_step_factor, applied in dpmpm_time_step).
module dpmpm_damping
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: node_slots_t, node_slots
  use dpmpm_config, only: config_t
  use dpmpm_state, only: state_t
  use dpmpm_phase, only: solid_phase
  use dpmpm_transfer, only: p2g, point_gradient
  use dpmpm_base_motion, only: base_face, base_velocity
  use dpmpm_materials, only: model_rigid
  implicit none
  private
  public :: rayleigh_coefficients, rayleigh_mass_args, rayleigh_mass, damped_step_factor, viscous_forces

contains

  !> alpha (1/s) and beta (s) of the input: from a target ratio xi at f1 and f2 (Hz),
  !> alpha = 2 xi w1 w2/(w1 + w2), beta = 2 xi/(w1 + w2) (w = 2 pi f), so that the ratio
  !> alpha/(2 w) + beta w/2 is xi at both; or as given.
  pure subroutine rayleigh_coefficients(cfg, alpha, beta)
    type(config_t), intent(in) :: cfg
    real(wp), intent(out) :: alpha, beta
    real(wp), parameter :: twopi = 2.0_wp*acos(-1.0_wp)
    real(wp) :: w1, w2
    if (cfg%rayleigh_ratio > 0.0_wp) then
      w1 = twopi*cfg%rayleigh_f1
      w2 = twopi*cfg%rayleigh_f2
      alpha = 2.0_wp*cfg%rayleigh_ratio*w1*w2/(w1 + w2)
      beta = 2.0_wp*cfg%rayleigh_ratio/(w1 + w2)
    else
      alpha = cfg%rayleigh_alpha
      beta = cfg%rayleigh_beta
    end if
  end subroutine rayleigh_coefficients

  !> The mass-proportional damping of a step that ends at time t: alpha and the reference
  !> velocity v_ref (the rigid base's at t; zero without one), as rayleigh_mass takes them.
  pure function rayleigh_mass_args(cfg, t) result(r)
    type(config_t), intent(in) :: cfg
    real(wp), intent(in) :: t
    real(wp) :: r(4), beta
    call rayleigh_coefficients(cfg, r(1), beta)
    r(2:4) = 0.0_wp
    if (r(1) > 0.0_wp .and. base_face(cfg) > 0) r(2:4) = base_velocity(cfg, t)
  end function rayleigh_mass_args

  !> One node of mass m: the new velocity vnew (free components, fix false) damped by the
  !> force -alpha m (v - v_ref) at the new velocity (backward Euler: v_ref + (vnew -
  !> v_ref)/(1 + alpha dt)), args = [alpha, v_ref]; the force's work over the step (vold to
  !> the damped vnew) is added to ext_work and taken from dissipated (as the local damping's).
  pure subroutine rayleigh_mass(nd, m, dt, args, fix, vold, vnew, ext_work, dissipated)
    integer, intent(in) :: nd
    real(wp), intent(in) :: m, dt, args(4)
    logical, intent(in) :: fix(3)
    real(wp), intent(in) :: vold(3)
    real(wp), intent(inout) :: vnew(3), ext_work, dissipated
    real(wp) :: vd(3), fd(3), w
    if (args(1) <= 0.0_wp) return
    vd(1:nd) = args(2:1 + nd) + (vnew(1:nd) - args(2:1 + nd))/(1.0_wp + args(1)*dt)
    where (fix(1:nd)) vd(1:nd) = vnew(1:nd)
    fd(1:nd) = m*(vd(1:nd) - vnew(1:nd))/dt
    w = 0.5_wp*dt*dot_product(fd(1:nd), vold(1:nd) + vd(1:nd))
    ext_work = ext_work + w
    dissipated = dissipated - w
    vnew(1:nd) = vd(1:nd)
  end subroutine rayleigh_mass

  !> The factor of the undamped critical step crit (h/c, Courant number 1) under the
  !> stiffness-proportional damping beta: sqrt(1 + xi^2) - xi with xi = beta omega_max/2,
  !> omega_max = 2 c/h = 2/crit (doc/theory.md 7.3), written as 1/(sqrt(1 + xi^2) + xi).
  pure real(wp) function damped_step_factor(beta, crit) result(f)
    real(wp), intent(in) :: beta, crit
    real(wp) :: xi
    xi = beta/crit
    f = 1.0_wp/(sqrt(1.0_wp + xi*xi) + xi)
  end function damped_step_factor

  !> The forces of the viscous stress beta D:eps_dot on the solid's nodes, added to their
  !> internal forces (node(2+nd:1+2nd) on the owned nodes; called after the halo sum of the
  !> node fields, before the nodal update). eps_dot is the symmetric gradient at the points
  !> of the start-of-step nodal velocities (momentum over mass) with the conditions that
  !> hold them: zero in the components a face holds, the base's velocity on the rigid base,
  !> tied pairs as one. The forces are -sum_p V_p sigma_v grad N (point quadrature, whatever
  !> the quadrature of the other forces); the stress power sum_p V_p sigma_v:eps_dot over
  !> the step is dissipated (taken from ext_work, added to drag_loss). No beta: nothing.
  subroutine viscous_forces(self, blo, bhi, dt)
    class(state_t), intent(inout) :: self
    integer, intent(in) :: blo(3), bhi(3)
    real(wp), intent(in) :: dt
    real(wp), allocatable :: vn(:, :, :, :), fn(:, :, :, :), lg(:, :), sv(:, :), zm(:), zv(:, :)
    real(wp) :: alpha, beta, m, d(6), tr, power, dummy
    integer :: nd, n, i, j, k, p
    logical :: fix(3)
    type(node_slots_t) :: sl
    call rayleigh_coefficients(self%cfg, alpha, beta)
    if (beta <= 0.0_wp) return
    nd = self%nd
    sl = node_slots(nd)
    associate (ph => self%phase(solid_phase), ps => self%phase(solid_phase)%pts, lo => self%dec%alo, &
               olo => self%dec%olo, ohi => self%dec%ohi)
      n = ps%n
      allocate (vn, mold=ph%nvel)
      vn = 0.0_wp
      do k = blo(3), bhi(3)
        do j = blo(2), bhi(2)
          do i = blo(1), bhi(1)
            m = ph%node(1, i, j, k)
            if (m <= 0.0_wp) cycle
            vn(sl%new_lo:sl%new_hi, i, j, k) = ph%node(sl%mom_lo:sl%mom_hi, i, j, k)/m
            if (self%bnd%faces%near_face([i, j, k])) then
              fix = self%bnd%faces%walls%constrained([i, j, k])
              where (fix(1:nd)) vn(sl%new_lo:sl%new_hi, i, j, k) = 0.0_wp
            end if
            vn(sl%old_lo:sl%old_hi, i, j, k) = vn(sl%new_lo:sl%new_hi, i, j, k)
          end do
        end do
      end do
      ! the rigid base at the motion's velocity at the start of the step, tied pairs as one
      dummy = 0.0_wp
      call self%bnd%hold(self%cfg, lo, blo, bhi, ph%node, vn, .false., self%time, 0.0_wp, &
                         self%cfg%gravity, dummy, self%dec%comm)
      call self%dec%halo_copy(vn)
      call self%mirror%unfold(vn, 0, ph%bc)
      allocate (lg(9, max(n, 1)), sv(6, max(n, 1)), zm(max(n, 1)), zv(nd, max(n, 1)))
      call point_gradient(nd, ph%st%nw, n, ph%st%i0, ph%st%sw, ph%st%sdw, lo, vn, lg)
      power = 0.0_wp
      do p = 1, n
        ! symmetric part, Voigt xx yy zz yz xz xy (tensor shears)
        d = [lg(1, p), lg(5, p), lg(9, p), 0.5_wp*(lg(6, p) + lg(8, p)), 0.5_wp*(lg(3, p) + lg(7, p)), &
             0.5_wp*(lg(2, p) + lg(4, p))]
        tr = d(1) + d(2) + d(3)
        associate (mat => self%mats(ps%mat(p)))
          if (mat%model == model_rigid) then
            sv(:, p) = 0.0_wp
          else
            sv(:, p) = beta*2.0_wp*mat%mu*d
            sv(1:3, p) = sv(1:3, p) + beta*mat%lambda*tr
          end if
        end associate
        power = power + ps%vol(p)*(dot_product(sv(1:3, p), d(1:3)) + 2.0_wp*dot_product(sv(4:6, p), d(4:6)))
      end do
      zm = 0.0_wp
      zv = 0.0_wp
      allocate (fn, mold=ph%node)
      fn = 0.0_wp
      call p2g(nd, ph%st%nw, n, ph%st%i0, ph%st%sw, ph%st%sdw, zm, zv, ps%vol, sv, .true., lo, fn)
      call self%mirror%fold(fn, 1, ph%bc)
      call self%dec%halo_sum(fn)
      ph%node(sl%force_lo:sl%force_hi, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) = &
        ph%node(sl%force_lo:sl%force_hi, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3)) + &
        fn(sl%force_lo:sl%force_hi, olo(1):ohi(1), olo(2):ohi(2), olo(3):ohi(3))
      self%ext_work = self%ext_work - dt*power
      self%drag_loss = self%drag_loss + dt*power
    end associate
  end subroutine viscous_forces

end module dpmpm_damping
