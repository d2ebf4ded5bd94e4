!> Transfers between the points and the grid (doc/theory.md 3.5, 4.3, 4.4): p2g
!> of mass, momentum and internal force, g2p (FLIP/PIC velocity, position,
!> velocity gradient), point velocity gradients, the MUSL momentum remap, nodal
!> scalars interpolated to the points, and the two-phase terms that the points
!> carry to the grid (pore-pressure forces, drag coefficient, porosity sums,
!> interphase force, mixture flux). Every kernel is one loop over the points and
!> their stencil nodes (dpmpm_stencil: weights st%w, gradients st%dw, node
!> st%first(p) + st%qoff(q)); node fields are plain arrays over the stored block
!> (components, node), passed as the block's 4D arrays.
module dpmpm_transfer
  use dpmpm_kinds, only: wp
  use dpmpm_voigt, only: voigt_to_tensor
  use dpmpm_drag, only: gravity_drag
  use dpmpm_stencil, only: stencil_t
  implicit none
  private
  public :: p2g, g2p, point_gradient, momentum_p2g, interp_scalar
  public :: fluid_p2g, interphase_p2g, solid_porosity_p2g, mixture_flux

contains

  !> Particle to grid: mass, momentum and internal force -sum_p V_p sigma_p grad N_I.
  !> Point quadrature of the stress (point_forces) is skipped when the forces
  !> come from Gauss points; bacc adds a body acceleration per point as m_p N_I b_p.
  subroutine p2g(st, n, mass, v, vol, stress, point_forces, node, bacc)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: mass(:), v(:, :), vol(:), stress(:, :)
    logical, intent(in) :: point_forces
    real(wp), intent(inout) :: node(1 + 2*st%nd, st%nnode)
    real(wp), intent(in), optional :: bacc(:, :)
    integer :: p, q, m, nd
    real(wp) :: nn, g(3), s(3, 3), mv(3), fs(3), mb(3)
    nd = st%nd
    g = 0.0_wp
    do p = 1, n
      s = 0.0_wp
      if (point_forces) s = voigt_to_tensor(stress(:, p))
      mv = 0.0_wp
      mv(1:nd) = mass(p)*v(:, p)
      mb = 0.0_wp
      if (present(bacc)) mb(1:nd) = mass(p)*bacc(:, p)
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        nn = st%w(q, p)
        g(1:nd) = st%dw(:, q, p)
        fs = nn*mb - vol(p)*matmul(s, g)
        node(1, m) = node(1, m) + nn*mass(p)
        node(2:1 + nd, m) = node(2:1 + nd, m) + nn*mv(1:nd)
        node(2 + nd:1 + 2*nd, m) = node(2 + nd:1 + 2*nd, m) + fs(1:nd)
      end do
    end do
  end subroutine p2g

  !> Grid to particle: FLIP/PIC blend of the velocity, position update with the
  !> new nodal velocity, and the velocity gradient from the new nodal velocity (USL).
  subroutine g2p(st, n, nvel, flip, dt, v, x, vgrad)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: nvel(2*st%nd, st%nnode), flip, dt
    real(wp), intent(inout) :: v(:, :), x(:, :), vgrad(:, :)
    integer :: p, q, m, d, nd
    real(wp) :: nn, dv(3), vn(3), lg(3, 3)
    nd = st%nd
    do p = 1, n
      dv = 0.0_wp; vn = 0.0_wp; lg = 0.0_wp
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        nn = st%w(q, p)
        vn(1:nd) = vn(1:nd) + nn*nvel(nd + 1:2*nd, m)
        dv(1:nd) = dv(1:nd) + nn*(nvel(nd + 1:2*nd, m) - nvel(1:nd, m))
        do d = 1, nd
          lg(1:nd, d) = lg(1:nd, d) + nvel(nd + 1:2*nd, m)*st%dw(d, q, p)
        end do
      end do
      v(:, p) = flip*(v(:, p) + dv(1:nd)) + (1.0_wp - flip)*vn(1:nd)
      x(:, p) = x(:, p) + dt*vn(1:nd)
      vgrad(:, p) = reshape(lg, [9])
    end do
  end subroutine g2p

  !> Velocity gradients of the points, sum_I v_I (x) grad N_I from the new nodal
  !> velocities nvel(nd+1:2nd), as 3x3 column-major.
  subroutine point_gradient(st, n, nvel, vgrad)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: nvel(2*st%nd, st%nnode)
    real(wp), intent(inout) :: vgrad(:, :)
    integer :: p, q, m, d, nd
    real(wp) :: lg(3, 3)
    nd = st%nd
    do p = 1, n
      lg = 0.0_wp
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        do d = 1, nd
          lg(1:nd, d) = lg(1:nd, d) + nvel(nd + 1:2*nd, m)*st%dw(d, q, p)
        end do
      end do
      vgrad(:, p) = reshape(lg, [9])
    end do
  end subroutine point_gradient

  !> Momentum of the points to the grid again (MUSL remap): node(2:1+nd) = sum N_I m_p v_p,
  !> on zeroed slots; the masses node(1) stay those of the step.
  subroutine momentum_p2g(st, n, mass, v, node)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: mass(:), v(:, :)
    real(wp), intent(inout) :: node(1 + 2*st%nd, st%nnode)
    integer :: p, q, m, nd
    nd = st%nd
    do p = 1, n
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        node(2:1 + nd, m) = node(2:1 + nd, m) + st%w(q, p)*mass(p)*v(:, p)
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
  subroutine mixture_flux(st, n, poro, nporo, nvel_f, nvel_s, gnrel)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: poro(:)
    real(wp), intent(in) :: nporo(1, st%nnode)
    real(wp), intent(in) :: nvel_f(2*st%nd, st%nnode), nvel_s(2*st%nd, st%nnode)
    real(wp), intent(out) :: gnrel(:)
    integer :: p, q, m, nd
    real(wp) :: np
    nd = st%nd
    do p = 1, n
      np = poro(p)
      gnrel(p) = 0.0_wp
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        gnrel(p) = gnrel(p) + (nporo(1, m) - np)* &
                   dot_product(st%dw(:, q, p), nvel_f(nd + 1:2*nd, m) - nvel_s(nd + 1:2*nd, m))
      end do
    end do
  end subroutine mixture_flux

  !> Interpolate the nodal scalar f(1, :) to the points: value and gradient.
  subroutine interp_scalar(st, n, f, val, grad)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: f(1, st%nnode)
    real(wp), intent(out) :: val(:), grad(:, :)
    integer :: p, q, m, nd
    nd = st%nd
    do p = 1, n
      val(p) = 0.0_wp
      grad(:, p) = 0.0_wp
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        val(p) = val(p) + st%w(q, p)*f(1, m)
        grad(1:nd, p) = grad(1:nd, p) + st%dw(:, q, p)*f(1, m)
      end do
    end do
  end subroutine interp_scalar

  !> Fluid points to the grid: the pore-pressure forces of the weak form (paper eq. 5),
  !> f_f,I += V n_f p grad N_I and f_s,I += V (1 - n_f) p grad N_I (point quadrature,
  !> only when point_forces), and the drag coefficient D_I += N_I m n_f g / k.
  subroutine fluid_p2g(st, n, mass, vol, poro, pres, kinv, point_forces, node_s, node_f, drag)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: mass(:), vol(:), poro(:), pres(:), kinv(:)
    logical, intent(in) :: point_forces
    real(wp), intent(inout) :: node_s(1 + 2*st%nd, st%nnode), node_f(1 + 2*st%nd, st%nnode)
    real(wp), intent(inout) :: drag(1, st%nnode)
    integer :: p, q, m, nd
    real(wp) :: pv, dp
    nd = st%nd
    do p = 1, n
      pv = 0.0_wp
      if (point_forces) pv = vol(p)*pres(p)
      dp = mass(p)*poro(p)*gravity_drag*kinv(p)
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        drag(1, m) = drag(1, m) + st%w(q, p)*dp
        if (.not. point_forces) cycle
        node_f(2 + nd:1 + 2*nd, m) = node_f(2 + nd:1 + 2*nd, m) + pv*poro(p)*st%dw(:, q, p)
        node_s(2 + nd:1 + 2*nd, m) = node_s(2 + nd:1 + 2*nd, m) + pv*(1.0_wp - poro(p))*st%dw(:, q, p)
      end do
    end do
  end subroutine fluid_p2g

  !> Fluid points to the grid: the interphase force p grad n_f of eq. 2 (point
  !> quadrature), force_I += N_I V p grad n at each fluid point. The weak form of
  !> eq. 5 integrates n_f p against grad N_I, which is -grad(n_f p) = -n_f grad p
  !> - p grad n_f on the fluid; adding p grad n_f to the fluid and taking it from
  !> the solid restores -n_f grad p and -(1 - n_f) grad p of eq. 1 where the
  !> porosity varies.
  subroutine interphase_p2g(st, n, vol, pres, ngrad, force)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: vol(:), pres(:), ngrad(:, :)
    real(wp), intent(inout) :: force(st%nd, st%nnode)
    integer :: p, q, m, nd
    real(wp) :: f(3)
    nd = st%nd
    do p = 1, n
      f(1:nd) = vol(p)*pres(p)*ngrad(1:nd, p)
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        force(1:nd, m) = force(1:nd, m) + st%w(q, p)*f(1:nd)
      end do
    end do
  end subroutine interphase_p2g

  !> Solid points to the grid: sum N_I m n_f (the nodal porosity is this over the
  !> nodal solid mass, doc/theory.md 2.5).
  subroutine solid_porosity_p2g(st, n, mass, poro, sporo)
    type(stencil_t), intent(in) :: st
    integer, intent(in) :: n
    real(wp), intent(in) :: mass(:), poro(:)
    real(wp), intent(inout) :: sporo(1, st%nnode)
    integer :: p, q, m
    do p = 1, n
      do q = 1, st%nq
        m = st%first(p) + st%qoff(q)
        sporo(1, m) = sporo(1, m) + st%w(q, p)*mass(p)*poro(p)
      end do
    end do
  end subroutine solid_porosity_p2g

end module dpmpm_transfer
