!> Plain-array kernels of the double-point two-phase step (physics.md 5 and 6):
!> the fluid points' contributions to the grid (pore-pressure forces on both
!> phases, drag coefficient), the solid points' porosity sums, the per-node drag
!> solve (explicit Euler or the implicit 2x2 system), interpolation of the nodal
!> porosity to the fluid points, and the semi-implicit pore-pressure update
!> (the paper's eq. 10). Signs: stress positive in tension, pore pressure positive
!> in compression, total stress sigma' - p I.
module dpmpm_two_phase
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: fluid_p2g, interphase_p2g, solid_porosity_p2g, drag_solve, drag_limit, interp_scalar, drag_relax
  public :: pressure_update
  public :: fluid_density, gravity_drag

  !> Gravity in the drag coefficient n_f^2 rho_f g / k (k is a hydraulic conductivity,
  !> defined with the standard gravity whatever the scene's body force).
  real(wp), parameter :: gravity_drag = 9.81_wp

contains

  !> Fluid points to the grid: the pore-pressure forces of the weak form (paper eq. 5),
  !> f_f,I += V n_f p grad N_I and f_s,I += V (1 - n_f) p grad N_I (point quadrature,
  !> only when point_forces), and the drag coefficient D_I += N_I m n_f g / k.
  subroutine fluid_p2g(nd, nw, n, i0, sw, sdw, mass, vol, poro, pres, kinv, point_forces, lo, &
                       node_s, node_f, drag)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :)
    real(wp), intent(in) :: mass(:), vol(:), poro(:), pres(:), kinv(:)
    logical, intent(in) :: point_forces
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: drag(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), pv, dp
    do p = 1, n
      pv = 0.0_wp
      if (point_forces) pv = vol(p)*pres(p)
      dp = mass(p)*poro(p)*gravity_drag*kinv(p)
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            nn = sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            drag(1, i, j, k) = drag(1, i, j, k) + nn*dp
            if (.not. point_forces) cycle
            g(1) = sdw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(2) = sw(a, 1, p)*sdw(b, 2, p)*sw(c, 3, p)
            g(3) = sw(a, 1, p)*sw(b, 2, p)*sdw(c, 3, p)
            node_f(2 + nd:1 + 2*nd, i, j, k) = node_f(2 + nd:1 + 2*nd, i, j, k) + &
                                               pv*poro(p)*g(1:nd)
            node_s(2 + nd:1 + 2*nd, i, j, k) = node_s(2 + nd:1 + 2*nd, i, j, k) + &
                                               pv*(1.0_wp - poro(p))*g(1:nd)
          end do
        end do
      end do
    end do
  end subroutine fluid_p2g

  !> Fluid points to the grid: the interphase force p grad n_f of eq. 2 (point
  !> quadrature), force_I += N_I V p grad n at each fluid point. The weak form of
  !> eq. 5 integrates n_f p against grad N_I, which is -grad(n_f p) = -n_f grad p
  !> - p grad n_f on the fluid; adding p grad n_f to the fluid and taking it from
  !> the solid restores -n_f grad p and -(1 - n_f) grad p of eq. 1 where the
  !> porosity varies.
  subroutine interphase_p2g(nd, nw, n, i0, sw, vol, pres, ngrad, lo, force)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), vol(:), pres(:), ngrad(:, :)
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: force(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: f(3)
    do p = 1, n
      f(1:nd) = vol(p)*pres(p)*ngrad(1:nd, p)
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            force(1:nd, i, j, k) = force(1:nd, i, j, k) + sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)*f(1:nd)
          end do
        end do
      end do
    end do
  end subroutine interphase_p2g

  !> Solid points to the grid: sum N_I m n_f (the nodal porosity is this over the
  !> nodal solid mass, physics.md 6 step 3).
  subroutine solid_porosity_p2g(nw, n, i0, sw, mass, poro, lo, sporo)
    integer, intent(in) :: nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), mass(:), poro(:)
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: sporo(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    do p = 1, n
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            sporo(1, i, j, k) = sporo(1, i, j, k) + sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)*mass(p)*poro(p)
          end do
        end do
      end do
    end do
  end subroutine solid_porosity_p2g

  !> Accelerations of one velocity component at a node with both phases, masses
  !> ms, mf, forces fs, ff (everything but drag), drag coefficient d and the
  !> velocities vs, vf at the start of the step. Explicit: forward Euler on the
  !> drag, m_s a_s = f_s + d (v_f - v_s), m_f a_f = f_f - d (v_f - v_s). Implicit
  !> (physics.md 5.4): the drag at the new velocities, the 2x2 system
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

  !> Largest stable step of forward Euler on the relative motion of the two
  !> phases at a node, 2 / (d (1/ms + 1/mf)) (physics.md 5, the binding limit of
  !> explicit drag); huge where a phase or the drag is absent.
  pure real(wp) function drag_limit(ms, mf, d) result(dt)
    real(wp), intent(in) :: ms, mf, d
    dt = huge(1.0_wp)
    if (ms > 0.0_wp .and. mf > 0.0_wp .and. d > 0.0_wp) dt = 2.0_wp/(d*(1.0_wp/ms + 1.0_wp/mf))
  end function drag_limit

  !> Interpolate the nodal scalar f(1, :) to the points: value and gradient.
  subroutine interp_scalar(nd, nw, n, i0, sw, sdw, lo, f, val, grad)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(out) :: val(:), grad(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: g(3)
    do p = 1, n
      val(p) = 0.0_wp
      grad(:, p) = 0.0_wp
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            g(1) = sdw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(2) = sw(a, 1, p)*sdw(b, 2, p)*sw(c, 3, p)
            g(3) = sw(a, 1, p)*sw(b, 2, p)*sdw(c, 3, p)
            val(p) = val(p) + sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)*f(1, i, j, k)
            grad(1:nd, p) = grad(1:nd, p) + g(1:nd)*f(1, i, j, k)
          end do
        end do
      end do
    end do
  end subroutine interp_scalar

  !> Semi-implicit pore-pressure update at the fluid points (paper eq. 10) with
  !> the velocity gradients of the new nodal velocities, lf (fluid) and ls (solid),
  !> each 3x3 column-major:
  !> p += -(K_f dt / n) [grad n . (v_f - v_s) + (1 - n) div v_s + n div v_f].
  !> gn_rel stands for grad n . (v_f - v_s) per point: the rest of the divergence
  !> of the nodal mixture flux (relative_flux in dpmpm_simulation), zero when the
  !> porosity-gradient term is off.
  pure subroutine pressure_update(n, dt, kf, poro, lf, ls, gn_rel, pres)
    integer, intent(in) :: n
    real(wp), intent(in) :: dt, kf(:), poro(:), lf(:, :), ls(:, :), gn_rel(:)
    real(wp), intent(inout) :: pres(:)
    integer :: p
    real(wp) :: divf, divs
    do p = 1, n
      divf = lf(1, p) + lf(5, p) + lf(9, p)
      divs = ls(1, p) + ls(5, p) + ls(9, p)
      pres(p) = pres(p) - kf(p)*dt/poro(p)*(gn_rel(p) + (1.0_wp - poro(p))*divs + poro(p)*divf)
    end do
  end subroutine pressure_update

  !> Intrinsic fluid density at pore pressure p for a linear compressible fluid,
  !> d rho / rho = dp / K_f integrated exactly.
  pure elemental real(wp) function fluid_density(rho0, kf, p) result(rho)
    real(wp), intent(in) :: rho0, kf, p
    rho = rho0*exp(p/kf)
  end function fluid_density

end module dpmpm_two_phase
