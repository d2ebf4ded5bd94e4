!> Transfers between the points and the grid (doc/theory.md 3.5 and 4): p2g of mass,
!> momentum and internal force, g2p (FLIP/PIC velocity, position, velocity
!> gradient), point velocity gradients, the MUSL momentum remap, nodal scalars
!> interpolated to the points, and the two-phase terms that the points carry to
!> the grid (pore-pressure forces, drag coefficient, porosity sums, interphase
!> force, mixture flux). Every kernel works on plain arrays: a point's stencil is
!> its first node i0(:, p) and its weights sw(:, axis, p) and derivatives
!> sdw(:, axis, p) per axis (tensor products), nodes are addressed from lo.
module dpmpm_transfer
  use dpmpm_kinds, only: wp
  use dpmpm_materials, only: voigt_to_tensor
  use dpmpm_drag, only: gravity_drag
  implicit none
  private
  public :: p2g, g2p, point_gradient, momentum_p2g, interp_scalar, interp_value
  public :: fluid_p2g, interphase_p2g, solid_porosity_p2g, mixture_flux

contains

  !> Particle to grid: mass, momentum and internal force -sum_p V_p sigma_p grad N_I.
  !> Point quadrature of the stress (point_forces) is skipped when the forces
  !> come from Gauss points; bacc adds a body acceleration per point as m_p N_I b_p.
  subroutine p2g(nd, nw, n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, bacc)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :)
    real(wp), intent(in) :: mass(:), v(:, :), vol(:), stress(:, :)
    logical, intent(in) :: point_forces
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in), optional :: bacc(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), s(3, 3), mv(3), fs(3), mb(3)
    do p = 1, n
      s = 0.0_wp
      if (point_forces) s = voigt_to_tensor(stress(:, p))
      mv = 0.0_wp
      mv(1:nd) = mass(p)*v(:, p)
      mb = 0.0_wp
      if (present(bacc)) mb(1:nd) = mass(p)*bacc(:, p)
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
            fs = nn*mb - vol(p)*matmul(s, g)
            node(1, i, j, k) = node(1, i, j, k) + nn*mass(p)
            node(2:1 + nd, i, j, k) = node(2:1 + nd, i, j, k) + nn*mv(1:nd)
            node(2 + nd:1 + 2*nd, i, j, k) = node(2 + nd:1 + 2*nd, i, j, k) + fs(1:nd)
          end do
        end do
      end do
    end do
  end subroutine p2g

  !> Grid to particle: FLIP/PIC blend of the velocity, position update with the
  !> new nodal velocity, and the velocity gradient from the new nodal velocity (USL).
  subroutine g2p(nd, nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), flip, dt
    real(wp), intent(inout) :: v(:, :), x(:, :), vgrad(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), dv(3), vn(3), lg(3, 3)
    do p = 1, n
      dv = 0.0_wp; vn = 0.0_wp; lg = 0.0_wp
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
            vn(1:nd) = vn(1:nd) + nn*nvel(nd + 1:2*nd, i, j, k)
            dv(1:nd) = dv(1:nd) + nn*(nvel(nd + 1:2*nd, i, j, k) - nvel(1:nd, i, j, k))
            lg(1:nd, 1) = lg(1:nd, 1) + nvel(nd + 1:2*nd, i, j, k)*g(1)
            lg(1:nd, 2) = lg(1:nd, 2) + nvel(nd + 1:2*nd, i, j, k)*g(2)
            lg(1:nd, 3) = lg(1:nd, 3) + nvel(nd + 1:2*nd, i, j, k)*g(3)
          end do
        end do
      end do
      v(:, p) = flip*(v(:, p) + dv(1:nd)) + (1.0_wp - flip)*vn(1:nd)
      x(:, p) = x(:, p) + dt*vn(1:nd)
      vgrad(:, p) = reshape(lg, [9])
    end do
  end subroutine g2p

  !> Velocity gradients of the points, sum_I v_I (x) grad N_I from the new nodal
  !> velocities nvel(nd+1:2nd), as 3x3 column-major.
  subroutine point_gradient(nd, nw, n, i0, sw, sdw, lo, nvel, vgrad)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: vgrad(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: g(3), lg(3, 3)
    do p = 1, n
      lg = 0.0_wp
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            g(1) = sdw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(2) = sw(a, 1, p)*sdw(b, 2, p)*sw(c, 3, p)
            g(3) = sw(a, 1, p)*sw(b, 2, p)*sdw(c, 3, p)
            lg(1:nd, 1) = lg(1:nd, 1) + nvel(nd + 1:2*nd, i, j, k)*g(1)
            lg(1:nd, 2) = lg(1:nd, 2) + nvel(nd + 1:2*nd, i, j, k)*g(2)
            lg(1:nd, 3) = lg(1:nd, 3) + nvel(nd + 1:2*nd, i, j, k)*g(3)
          end do
        end do
      end do
      vgrad(:, p) = reshape(lg, [9])
    end do
  end subroutine point_gradient

  !> Momentum of the points to the grid again (MUSL remap): node(2:1+nd) = sum N_I m_p v_p,
  !> on zeroed slots; the masses node(1) stay those of the step.
  subroutine momentum_p2g(nd, nw, n, i0, sw, mass, v, lo, node)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), mass(:), v(:, :)
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn
    do p = 1, n
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            nn = sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            node(2:1 + nd, i, j, k) = node(2:1 + nd, i, j, k) + nn*mass(p)*v(:, p)
          end do
        end do
      end do
    end do
  end subroutine momentum_p2g

  !> grad n . (v_f - v_s) at the fluid points from the new nodal velocities (the
  !> porosity-gradient term of eq. 10), discretised so that the whole bracket of
  !> eq. 10 is the divergence of the nodal mixture flux,
  !>   sum_I grad N_I . (n_I v_f,I + (1 - n_I) v_s,I),
  !> that is sum_I grad N_I . ((n_I - n_p)(v_f,I - v_s,I)). The flux form keeps
  !> one constraint per cell at steady seepage; the product grad n . w of two
  !> interpolated fields asks for a different one at each point of the cell
  !> where n jumps, and their pressures then drift apart.
  subroutine mixture_flux(nd, nw, n, i0, sw, sdw, lo, poro, nporo, nvel_f, nvel_s, gnrel)
    integer, intent(in) :: nd, nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), sdw(:, :, :), poro(:)
    integer, intent(in) :: lo(3)
    real(wp), intent(in) :: nporo(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: nvel_f(:, lo(1):, lo(2):, lo(3):), nvel_s(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(out) :: gnrel(:)
    integer :: p, a, b, c, i, j, k
    real(wp) :: g(3), np
    do p = 1, n
      np = poro(p)
      gnrel(p) = 0.0_wp
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            g(1) = sdw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)
            g(2) = sw(a, 1, p)*sdw(b, 2, p)*sw(c, 3, p)
            g(3) = sw(a, 1, p)*sw(b, 2, p)*sdw(c, 3, p)
            gnrel(p) = gnrel(p) + (nporo(1, i, j, k) - np)* &
                       dot_product(g(1:nd), nvel_f(nd + 1:2*nd, i, j, k) - nvel_s(nd + 1:2*nd, i, j, k))
          end do
        end do
      end do
    end do
  end subroutine mixture_flux

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

  !> Interpolate component comp of the nodal field f to the points (value only).
  subroutine interp_value(nw, n, i0, sw, lo, f, comp, val)
    integer, intent(in) :: nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
    integer, intent(in) :: comp
    real(wp), intent(out) :: val(:)
    integer :: p, a, b, c, i, j, k
    do p = 1, n
      val(p) = 0.0_wp
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            val(p) = val(p) + sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)*f(comp, i, j, k)
          end do
        end do
      end do
    end do
  end subroutine interp_value

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

  !> Porous solid points to the grid (porosity > 0): sum N_I m n_f, sum N_I m and
  !> sum N_I m / k, from which nodal_porosity takes the nodal porosity and 1/k
  !> (doc/theory.md 3.5); points of porosity 0 are not porous and take no part.
  subroutine solid_porosity_p2g(nw, n, i0, sw, mass, poro, kinv, lo, sporo)
    integer, intent(in) :: nw(3), n
    integer, intent(in) :: i0(:, :)
    real(wp), intent(in) :: sw(:, :, :), mass(:), poro(:), kinv(:)
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: sporo(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn
    do p = 1, n
      if (.not. poro(p) > 0.0_wp) cycle
      do c = 1, nw(3)
        k = i0(3, p) + c - 1
        do b = 1, nw(2)
          j = i0(2, p) + b - 1
          do a = 1, nw(1)
            i = i0(1, p) + a - 1
            nn = sw(a, 1, p)*sw(b, 2, p)*sw(c, 3, p)*mass(p)
            sporo(1, i, j, k) = sporo(1, i, j, k) + nn*poro(p)
            sporo(2, i, j, k) = sporo(2, i, j, k) + nn
            sporo(3, i, j, k) = sporo(3, i, j, k) + nn*kinv(p)
          end do
        end do
      end do
    end do
  end subroutine solid_porosity_p2g

end module dpmpm_transfer
