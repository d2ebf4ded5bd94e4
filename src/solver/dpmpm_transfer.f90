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
  public :: p2g, g2p, point_gradient, point_gradients, momentum_p2g, momentum_project_p2g
  public :: interp_two_values
  public :: fluid_p2g, interphase_p2g, solid_porosity_p2g, mixture_flux, reaches_thin_node
  public :: body_force_work, volume_p2g

contains

  !> Particle to grid: mass, momentum and internal force -sum_p V_p sigma_p grad N_I.
  !> Point quadrature of the stress (point_forces) is skipped when the forces
  !> come from Gauss points; bacc adds a body acceleration per point as m_p N_I b_p.
  subroutine p2g(nd, nw, n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, bacc)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), stress(:, :)
    logical, intent(in) :: point_forces
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(in), optional :: bacc(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), s(3, 3), mv(3), fs(3), mb(3)
    if (nd == 2) then
      ! (An absent optional array cannot be passed on to a contiguous dummy.)
      if (present(bacc)) then
        call p2g_2d(nw, n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, bacc)
      else
        call p2g_2d(nw, n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node)
      end if
      return
    end if
    do p = 1, n
      s = 0.0_wp
      if (point_forces) s = voigt_to_tensor(stress(:, p))
      mv = 0.0_wp
      mv(1:nd) = mass(p)*v(:, p)
      mb = 0.0_wp
      if (present(bacc)) mb(1:nd) = mass(p)*bacc(:, p)
#include "dpmpm_stencil_do_3d.inc"
#include "dpmpm_stencil_grad_3d.inc"
      fs = nn*mb - vol(p)*matmul(s, g)
      node(1, i, j, k) = node(1, i, j, k) + nn*mass(p)
      node(2:1 + nd, i, j, k) = node(2:1 + nd, i, j, k) + nn*mv(1:nd)
      node(2 + nd:1 + 2*nd, i, j, k) = node(2 + nd:1 + 2*nd, i, j, k) + fs(1:nd)
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine p2g

  !> Grid to particle: FLIP/PIC blend of the velocity, position update with the
  !> new nodal velocity, and the velocity gradient from the new nodal velocity (USL).
  !> gradient = .false. (MUSL, whose remap replaces the gradient) leaves vgrad as it is.
  subroutine g2p(nd, nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, gradient, gf, gv)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: flip, dt
    real(wp), contiguous, intent(inout) :: v(:, :), x(:, :), vgrad(:, :)
    logical, intent(in), optional :: gradient
    !> With gf: gv(1:nd, p) = sum_I N_I(x_p) gf(1:nd, I), another nodal vector field at the
    !> points in the same pass (the locked velocity of the MUSL remap, momentum_project_p2g),
    !> summed in the order interp_two_values sums.
    real(wp), contiguous, intent(in), optional :: gf(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout), optional :: gv(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), dv(3), vn(3), lg(3, 3), gs(3)
    real(wp) :: none(1, 1)
    logical :: grad, gather
    grad = .true.
    if (present(gradient)) grad = gradient
    gather = present(gf) .and. present(gv)
    ! (An absent optional array cannot be passed on to a contiguous dummy: without gf the
    ! kernels get nvel and a dummy they do not touch.)
    if (nd == 2) then
      if (gather) then
        call g2p_2d(nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, grad, gf, gv, .true.)
      else
        call g2p_2d(nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, grad, nvel, none, .false.)
      end if
      return
    else if (nd == 3) then
      if (gather) then
        call g2p_3d(nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, grad, gf, gv, .true.)
      else
        call g2p_3d(nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, grad, nvel, none, .false.)
      end if
      return
    end if
    do p = 1, n
      dv = 0.0_wp; vn = 0.0_wp; lg = 0.0_wp; gs = 0.0_wp
#include "dpmpm_stencil_do_3d.inc"
#include "dpmpm_stencil_grad_3d.inc"
      vn(1:nd) = vn(1:nd) + nn*nvel(nd + 1:2*nd, i, j, k)
      dv(1:nd) = dv(1:nd) + nn*(nvel(nd + 1:2*nd, i, j, k) - nvel(1:nd, i, j, k))
      if (gather) gs(1:nd) = gs(1:nd) + nn*gf(1:nd, i, j, k)
      if (.not. grad) cycle
      lg(1:nd, 1) = lg(1:nd, 1) + nvel(nd + 1:2*nd, i, j, k)*g(1)
      lg(1:nd, 2) = lg(1:nd, 2) + nvel(nd + 1:2*nd, i, j, k)*g(2)
      lg(1:nd, 3) = lg(1:nd, 3) + nvel(nd + 1:2*nd, i, j, k)*g(3)
#include "dpmpm_stencil_end_3d.inc"
      v(:, p) = flip*(v(:, p) + dv(1:nd)) + (1.0_wp - flip)*vn(1:nd)
      x(:, p) = x(:, p) + dt*vn(1:nd)
      if (gather) gv(1:nd, p) = gs(1:nd)
      if (.not. grad) cycle
      vgrad(1:3, p) = lg(:, 1)
      vgrad(4:6, p) = lg(:, 2)
      vgrad(7:9, p) = lg(:, 3)
    end do
  end subroutine g2p

  !> Work over a step of the body accelerations bacc that p2g gave the points:
  !> sum_p m_p b_p . sum_I N_I(x_p) (v_I,old + v_I,new) dt / 2, which is the work of their
  !> nodal forces sum_p N_I m_p b_p over the nodes' mean velocity, as gravity's is booked.
  real(wp) function body_force_work(nd, nw, n, i0, sw, lo, nvel, mass, bacc, dt) result(w)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(in) :: mass(:), bacc(:, :)
    real(wp), intent(in) :: dt
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, vm(3)
    w = 0.0_wp
    do p = 1, n
      vm(1:nd) = 0.0_wp
#include "dpmpm_stencil_do_3d.inc"
      vm(1:nd) = vm(1:nd) + nn*(nvel(1:nd, i, j, k) + nvel(nd + 1:2*nd, i, j, k))
#include "dpmpm_stencil_end_3d.inc"
      w = w + 0.5_wp*dt*mass(p)*dot_product(bacc(:, p), vm(1:nd))
    end do
  end function body_force_work

  !> Velocity gradients of the points, sum_I v_I (x) grad N_I from the new nodal
  !> velocities nvel(nd+1:2nd), as 3x3 column-major.
  subroutine point_gradient(nd, nw, n, i0, sw, sdw, lo, nvel, vgrad)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout) :: vgrad(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), lg(3, 3)
    if (nd == 2) then
      call point_gradient_2d(nw, n, i0, sw, sdw, lo, nvel, vgrad)
      return
    end if
    do p = 1, n
      lg = 0.0_wp
#include "dpmpm_stencil_do_3d.inc"
#include "dpmpm_stencil_grad_3d.inc"
      lg(1:nd, 1) = lg(1:nd, 1) + nvel(nd + 1:2*nd, i, j, k)*g(1)
      lg(1:nd, 2) = lg(1:nd, 2) + nvel(nd + 1:2*nd, i, j, k)*g(2)
      lg(1:nd, 3) = lg(1:nd, 3) + nvel(nd + 1:2*nd, i, j, k)*g(3)
#include "dpmpm_stencil_end_3d.inc"
      vgrad(1:3, p) = lg(:, 1)
      vgrad(4:6, p) = lg(:, 2)
      vgrad(7:9, p) = lg(:, 3)
    end do
  end subroutine point_gradient

  !> point_gradient of two nodal velocity fields in one pass over the points:
  !> vgrad from nvel, vgrad2 from nvel2 (the fluid points' gradients of the fluid's and
  !> the skeleton's velocity), each summed as point_gradient sums it.
  subroutine point_gradients(nd, nw, n, i0, sw, sdw, lo, nvel, nvel2, vgrad, vgrad2)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), nvel2(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout) :: vgrad(:, :), vgrad2(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), lg(3, 3), lg2(3, 3)
    if (nd == 2) then
      call point_gradients_2d(nw, n, i0, sw, sdw, lo, nvel, nvel2, vgrad, vgrad2)
      return
    end if
    do p = 1, n
      lg = 0.0_wp
      lg2 = 0.0_wp
#include "dpmpm_stencil_do_3d.inc"
#include "dpmpm_stencil_grad_3d.inc"
      lg(1:nd, 1) = lg(1:nd, 1) + nvel(nd + 1:2*nd, i, j, k)*g(1)
      lg(1:nd, 2) = lg(1:nd, 2) + nvel(nd + 1:2*nd, i, j, k)*g(2)
      lg(1:nd, 3) = lg(1:nd, 3) + nvel(nd + 1:2*nd, i, j, k)*g(3)
      lg2(1:nd, 1) = lg2(1:nd, 1) + nvel2(nd + 1:2*nd, i, j, k)*g(1)
      lg2(1:nd, 2) = lg2(1:nd, 2) + nvel2(nd + 1:2*nd, i, j, k)*g(2)
      lg2(1:nd, 3) = lg2(1:nd, 3) + nvel2(nd + 1:2*nd, i, j, k)*g(3)
#include "dpmpm_stencil_end_3d.inc"
      vgrad(1:3, p) = lg(:, 1)
      vgrad(4:6, p) = lg(:, 2)
      vgrad(7:9, p) = lg(:, 3)
      vgrad2(1:3, p) = lg2(:, 1)
      vgrad2(4:6, p) = lg2(:, 2)
      vgrad2(7:9, p) = lg2(:, 3)
    end do
  end subroutine point_gradients

  !> The MUSL remap with the locked velocity f in one pass over the points of a phase:
  !> the momenta node(2:1+nd) += sum N_I m_p v_p (as momentum_p2g) and the momentum of
  !> f's projection through this point set, proj(1:nd) += sum_p N_I m_p fp_p, where
  !> fp_p = sum_J N_J f_J is f at the points (g2p gathers it in its pass). Divided by the
  !> nodal mass it is P f.
  subroutine momentum_project_p2g(nd, nw, n, i0, sw, mass, v, lo, fp, node, proj)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), v(:, :), fp(:, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):), proj(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, vc(3)
    if (nd == 2) then
      call momentum_project_p2g_2d(nw, n, i0, sw, mass, v, lo, fp, node, proj)
      return
    end if
    do p = 1, n
      vc(1:nd) = mass(p)*fp(1:nd, p)
#include "dpmpm_stencil_do_3d.inc"
      node(2:1 + nd, i, j, k) = node(2:1 + nd, i, j, k) + nn*mass(p)*v(:, p)
      proj(1:nd, i, j, k) = proj(1:nd, i, j, k) + nn*vc(1:nd)
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine momentum_project_p2g

  !> Momentum of the points to the grid again (MUSL remap): node(2:1+nd) = sum N_I m_p v_p,
  !> on zeroed slots; the masses node(1) stay those of the step.
  subroutine momentum_p2g(nd, nw, n, i0, sw, mass, v, lo, node)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), v(:, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn
    if (nd == 2) then
      call momentum_p2g_2d(nw, n, i0, sw, mass, v, lo, node)
      return
    end if
    do p = 1, n
#include "dpmpm_stencil_do_3d.inc"
      node(2:1 + nd, i, j, k) = node(2:1 + nd, i, j, k) + nn*mass(p)*v(:, p)
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine momentum_p2g

  !> The point volume of the nodes, sum_p V_p N_I(x_p), added to nvol(1, I) (the thin
  !> nodes of Gauss quadrature, thin_node_forces).
  subroutine volume_p2g(nw, n, i0, sw, vol, lo, nvol)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), vol(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: nvol(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn
    do p = 1, n
#include "dpmpm_stencil_do_3d.inc"
      nvol(1, i, j, k) = nvol(1, i, j, k) + nn*vol(p)
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine volume_p2g

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
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :), poro(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nporo(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(in) :: nvel_f(:, lo(1):, lo(2):, lo(3):), nvel_s(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(out) :: gnrel(:)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), np
    do p = 1, n
      np = poro(p)
      gnrel(p) = 0.0_wp
#include "dpmpm_stencil_do_3d.inc"
#include "dpmpm_stencil_grad_3d.inc"
      gnrel(p) = gnrel(p) + (nporo(1, i, j, k) - np)* &
                 dot_product(g(1:nd), nvel_f(nd + 1:2*nd, i, j, k) - nvel_s(nd + 1:2*nd, i, j, k))
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine mixture_flux

  !> Nodal fields to the points in one pass: the components 1 (val) and comp (val2)
  !> of f.
  subroutine interp_two_values(nd, nw, n, i0, sw, lo, f, comp, val, val2)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
    integer, intent(in) :: comp
    real(wp), contiguous, intent(out) :: val(:), val2(:)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn
    if (nd == 2) then
      call interp_two_values_2d(nw, n, i0, sw, lo, f, comp, val, val2)
      return
    end if
    do p = 1, n
      val(p) = 0.0_wp
      val2(p) = 0.0_wp
#include "dpmpm_stencil_do_3d.inc"
      val(p) = val(p) + nn*f(1, i, j, k)
      val2(p) = val2(p) + nn*f(comp, i, j, k)
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine interp_two_values

  !> Fluid points to the grid: the pore-pressure forces of the weak form (paper eq. 5),
  !> f_f,I += V n_f p grad N_I and f_s,I += V (1 - n_f) p grad N_I (point quadrature,
  !> only when point_forces), and the drag coefficient D_I += N_I m n_f g / k.
  subroutine fluid_p2g(nd, nw, n, i0, sw, sdw, mass, v, vol, poro, pres, kinv, momentum, point_forces, lo, &
                       node_s, node_f, drag, fvol)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), poro(:), pres(:), kinv(:)
    !> Also the fluid's mass and momentum, node_f(1:1+nd), as p2g sums them (the fluid
    !> then needs no p2g pass of its own).
    logical, intent(in) :: momentum
    logical, intent(in) :: point_forces
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout) :: drag(:, lo(1):, lo(2):, lo(3):)
    !> The fluid volume at the nodes, sum N_I V (the free-surface test), in the same pass.
    real(wp), contiguous, intent(inout), optional :: fvol(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), pv, dp, mv(3)
    logical :: vols
    if (nd == 2) then
      call fluid_p2g_2d(nw, n, i0, sw, sdw, mass, v, vol, poro, pres, kinv, momentum, point_forces, lo, node_s, &
                        node_f, drag, fvol)
      return
    end if
    vols = present(fvol)
    mv = 0.0_wp
    do p = 1, n
      pv = 0.0_wp
      if (point_forces) pv = vol(p)*pres(p)
      dp = mass(p)*poro(p)*gravity_drag*kinv(p)
      if (momentum) mv(1:nd) = mass(p)*v(:, p)
#include "dpmpm_stencil_do_3d.inc"
      if (momentum) then
        node_f(1, i, j, k) = node_f(1, i, j, k) + nn*mass(p)
        node_f(2:1 + nd, i, j, k) = node_f(2:1 + nd, i, j, k) + nn*mv(1:nd)
      end if
      drag(1, i, j, k) = drag(1, i, j, k) + nn*dp
      if (vols) fvol(1, i, j, k) = fvol(1, i, j, k) + nn*vol(p)
      if (.not. point_forces) cycle
#include "dpmpm_stencil_grad_3d.inc"
      node_f(2 + nd:1 + 2*nd, i, j, k) = node_f(2 + nd:1 + 2*nd, i, j, k) + &
                                         pv*poro(p)*g(1:nd)
      node_s(2 + nd:1 + 2*nd, i, j, k) = node_s(2 + nd:1 + 2*nd, i, j, k) + &
                                         pv*(1.0_wp - poro(p))*g(1:nd)
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine fluid_p2g

  !> Fluid points to the grid: the interphase force p grad n_f of eq. 2 (point
  !> quadrature) in the form that is the transpose of the mixture flux (mixture_flux),
  !> force_I += V p (n_I - n_p) grad N_I at each fluid point. The weak form of eq. 5
  !> integrates n_p p against grad N_I (fluid_p2g); with this term the fluid receives
  !> V p n_I grad N_I and the solid V p (1 - n_I) grad N_I, the negative transpose of
  !> the divergence sum_I grad N_I . (n_I v_f,I + (1 - n_I) v_s,I) of the pressure
  !> update, so that the pressure forces do no work that the pore fluid does not
  !> store (doc/theory.md 2.6). It restores -n_f grad p and -(1 - n_f) grad p of eq. 1
  !> where the porosity varies.
  subroutine interphase_p2g(nd, nw, n, i0, sw, sdw, vol, pres, poro, lo, nporo, force)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :), vol(:), pres(:), poro(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nporo(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout) :: force(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), vp
    do p = 1, n
      vp = vol(p)*pres(p)
#include "dpmpm_stencil_do_3d.inc"
#include "dpmpm_stencil_grad_3d.inc"
      force(1:nd, i, j, k) = force(1:nd, i, j, k) + vp*(nporo(1, i, j, k) - poro(p))*g(1:nd)
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine interphase_p2g

  !> Porous solid points to the grid (porosity > 0): sum N_I m n_f, sum N_I m and
  !> sum N_I m / k, from which nodal_porosity takes the nodal porosity and 1/k
  !> (doc/theory.md 3.5); points of porosity 0 are not porous and take no part.
  subroutine solid_porosity_p2g(nw, n, i0, sw, mass, poro, kinv, lo, sporo)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), poro(:), kinv(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: sporo(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, nm
    if (nw(3) == 1) then
      call solid_porosity_p2g_2d(nw, n, i0, sw, mass, poro, kinv, lo, sporo)
      return
    end if
    do p = 1, n
      if (.not. poro(p) > 0.0_wp) cycle
#include "dpmpm_stencil_do_3d.inc"
      nm = nn*mass(p)
      sporo(1, i, j, k) = sporo(1, i, j, k) + nm*poro(p)
      sporo(2, i, j, k) = sporo(2, i, j, k) + nm
      sporo(3, i, j, k) = sporo(3, i, j, k) + nm*kinv(p)
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine solid_porosity_p2g

  !> Whether each point's grid functions reach (N > 0) a node inside the grid (not on a
  !> face: 0 < index < ncells on the axes 1..nd) whose nodal volume f(1) is below vmin.
  subroutine reaches_thin_node(nd, nw, n, i0, sw, lo, f, ncells, vmin, flag)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
    integer, intent(in) :: ncells(3)
    real(wp), intent(in) :: vmin
    logical, intent(out) :: flag(:)
    integer :: p, a, b, c, i, j, k, hi(3)
    real(wp) :: nn
    hi = huge(1)
    hi(1:nd) = ncells(1:nd)
    if (nd == 2) then
      call reaches_thin_node_2d(nw, n, i0, sw, lo, f, hi, vmin, flag)
      return
    end if
    do p = 1, n
      flag(p) = .false.
#include "dpmpm_stencil_do_3d.inc"
      if (nn > 0.0_wp .and. f(1, i, j, k) < vmin) then
        if (i > 0 .and. i < hi(1) .and. (nd < 2 .or. (j > 0 .and. j < hi(2))) .and. &
            (nd < 3 .or. (k > 0 .and. k < hi(3)))) flag(p) = .true.
      end if
#include "dpmpm_stencil_end_3d.inc"
    end do
  end subroutine reaches_thin_node

  ! Two-dimensional forms of the kernels above (nd = 2: the third axis has one node
  ! of weight 1 and derivative 0, so its factors and the third components drop out).

  subroutine p2g_2d(nw, n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, bacc)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), stress(:, :)
    logical, intent(in) :: point_forces
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(in), optional :: bacc(:, :)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, g1, g2, wb, gb, mp, vp
    ! A point adds nn c0 + g1 c1 + g2 c2 to the five slots (mass, momentum, force) of
    ! each node of its stencil: c0 = (m, m v, m b), c1 = -V (0, 0, 0, s11, s12),
    ! c2 = -V (0, 0, 0, s12, s22).
    real(wp) :: c0(5), c1(5), c2(5)
    logical :: body
    body = present(bacc)
    c0 = 0.0_wp; c1 = 0.0_wp; c2 = 0.0_wp
    do p = 1, n
      mp = mass(p)
      c0(1) = mp
      c0(2) = mp*v(1, p); c0(3) = mp*v(2, p)
      if (body) then
        c0(4) = mp*bacc(1, p); c0(5) = mp*bacc(2, p)
      end if
      if (point_forces) then
        vp = vol(p)
        c1(4) = -vp*stress(1, p); c1(5) = -vp*stress(6, p)
        c2(4) = -vp*stress(6, p); c2(5) = -vp*stress(2, p)
      end if
#include "dpmpm_stencil_do_2d_grad.inc"
      g1 = sdw(a, 1, p)*wb
      g2 = sw(a, 1, p)*gb
      ! (slot by slot: the same sums as node(1:5) + (nn c0 + g1 c1 + g2 c2), in fewer
      ! instructions than the compiler's vector form of the five-element update)
      node(1, i, j, k) = node(1, i, j, k) + (nn*c0(1) + g1*c1(1) + g2*c2(1))
      node(2, i, j, k) = node(2, i, j, k) + (nn*c0(2) + g1*c1(2) + g2*c2(2))
      node(3, i, j, k) = node(3, i, j, k) + (nn*c0(3) + g1*c1(3) + g2*c2(3))
      node(4, i, j, k) = node(4, i, j, k) + (nn*c0(4) + g1*c1(4) + g2*c2(4))
      node(5, i, j, k) = node(5, i, j, k) + (nn*c0(5) + g1*c1(5) + g2*c2(5))
#include "dpmpm_stencil_end_2d.inc"
    end do
  end subroutine p2g_2d

  subroutine g2p_2d(nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, gradient, gf, gv, gather)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), gf(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: flip, dt
    real(wp), contiguous, intent(inout) :: v(:, :), x(:, :), vgrad(:, :), gv(:, :)
    logical, intent(in) :: gradient, gather
    integer :: p, a, b, i, j, k
    real(wp) :: nn, g1, g2, wb, gb, v1, v2, dv1, dv2, vn1, vn2, l11, l21, l12, l22, c1, c2
    do p = 1, n
      dv1 = 0.0_wp; dv2 = 0.0_wp; vn1 = 0.0_wp; vn2 = 0.0_wp
      l11 = 0.0_wp; l21 = 0.0_wp; l12 = 0.0_wp; l22 = 0.0_wp
      c1 = 0.0_wp; c2 = 0.0_wp
#include "dpmpm_stencil_do_2d_grad.inc"
      g1 = sdw(a, 1, p)*wb
      g2 = sw(a, 1, p)*gb
      v1 = nvel(3, i, j, k); v2 = nvel(4, i, j, k)
      vn1 = vn1 + nn*v1; vn2 = vn2 + nn*v2
      dv1 = dv1 + nn*(v1 - nvel(1, i, j, k)); dv2 = dv2 + nn*(v2 - nvel(2, i, j, k))
      if (gather) then
        c1 = c1 + nn*gf(1, i, j, k)
        c2 = c2 + nn*gf(2, i, j, k)
      end if
      if (.not. gradient) cycle
      l11 = l11 + v1*g1; l21 = l21 + v2*g1
      l12 = l12 + v1*g2; l22 = l22 + v2*g2
#include "dpmpm_stencil_end_2d.inc"
      v(1, p) = flip*(v(1, p) + dv1) + (1.0_wp - flip)*vn1
      v(2, p) = flip*(v(2, p) + dv2) + (1.0_wp - flip)*vn2
      x(1, p) = x(1, p) + dt*vn1
      x(2, p) = x(2, p) + dt*vn2
      if (gather) then
        gv(1, p) = c1; gv(2, p) = c2
      end if
      if (.not. gradient) cycle
      vgrad(:, p) = 0.0_wp
      vgrad(1, p) = l11; vgrad(2, p) = l21; vgrad(4, p) = l12; vgrad(5, p) = l22
    end do
  end subroutine g2p_2d

  ! The three-dimensional form of g2p: the same sums, component by component.
  subroutine g2p_3d(nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, gradient, gf, gv, gather)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), gf(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: flip, dt
    real(wp), contiguous, intent(inout) :: v(:, :), x(:, :), vgrad(:, :), gv(:, :)
    logical, intent(in) :: gradient, gather
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), u1, u2, u3, dv1, dv2, dv3, vn1, vn2, vn3, gs(3)
    real(wp) :: l11, l21, l31, l12, l22, l32, l13, l23, l33
    do p = 1, n
      dv1 = 0.0_wp; dv2 = 0.0_wp; dv3 = 0.0_wp; vn1 = 0.0_wp; vn2 = 0.0_wp; vn3 = 0.0_wp
      l11 = 0.0_wp; l21 = 0.0_wp; l31 = 0.0_wp
      l12 = 0.0_wp; l22 = 0.0_wp; l32 = 0.0_wp
      l13 = 0.0_wp; l23 = 0.0_wp; l33 = 0.0_wp
      gs = 0.0_wp
#include "dpmpm_stencil_do_3d.inc"
#include "dpmpm_stencil_grad_3d.inc"
      u1 = nvel(4, i, j, k); u2 = nvel(5, i, j, k); u3 = nvel(6, i, j, k)
      vn1 = vn1 + nn*u1; vn2 = vn2 + nn*u2; vn3 = vn3 + nn*u3
      dv1 = dv1 + nn*(u1 - nvel(1, i, j, k))
      dv2 = dv2 + nn*(u2 - nvel(2, i, j, k))
      dv3 = dv3 + nn*(u3 - nvel(3, i, j, k))
      if (gather) gs = gs + nn*gf(1:3, i, j, k)
      if (.not. gradient) cycle
      l11 = l11 + u1*g(1); l21 = l21 + u2*g(1); l31 = l31 + u3*g(1)
      l12 = l12 + u1*g(2); l22 = l22 + u2*g(2); l32 = l32 + u3*g(2)
      l13 = l13 + u1*g(3); l23 = l23 + u2*g(3); l33 = l33 + u3*g(3)
#include "dpmpm_stencil_end_3d.inc"
      v(1, p) = flip*(v(1, p) + dv1) + (1.0_wp - flip)*vn1
      v(2, p) = flip*(v(2, p) + dv2) + (1.0_wp - flip)*vn2
      v(3, p) = flip*(v(3, p) + dv3) + (1.0_wp - flip)*vn3
      x(1, p) = x(1, p) + dt*vn1
      x(2, p) = x(2, p) + dt*vn2
      x(3, p) = x(3, p) + dt*vn3
      if (gather) gv(1:3, p) = gs
      if (.not. gradient) cycle
      vgrad(1, p) = l11; vgrad(2, p) = l21; vgrad(3, p) = l31
      vgrad(4, p) = l12; vgrad(5, p) = l22; vgrad(6, p) = l32
      vgrad(7, p) = l13; vgrad(8, p) = l23; vgrad(9, p) = l33
    end do
  end subroutine g2p_3d

  subroutine point_gradient_2d(nw, n, i0, sw, sdw, lo, nvel, vgrad)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout) :: vgrad(:, :)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, g1, g2, wb, gb, v1, v2, l11, l21, l12, l22
    do p = 1, n
      l11 = 0.0_wp; l21 = 0.0_wp; l12 = 0.0_wp; l22 = 0.0_wp
#include "dpmpm_stencil_do_2d_grad.inc"
      g1 = sdw(a, 1, p)*wb
      g2 = sw(a, 1, p)*gb
      v1 = nvel(3, i, j, k); v2 = nvel(4, i, j, k)
      l11 = l11 + v1*g1; l21 = l21 + v2*g1
      l12 = l12 + v1*g2; l22 = l22 + v2*g2
#include "dpmpm_stencil_end_2d.inc"
      vgrad(:, p) = 0.0_wp
      vgrad(1, p) = l11; vgrad(2, p) = l21; vgrad(4, p) = l12; vgrad(5, p) = l22
    end do
  end subroutine point_gradient_2d

  subroutine point_gradients_2d(nw, n, i0, sw, sdw, lo, nvel, nvel2, vgrad, vgrad2)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), nvel2(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout) :: vgrad(:, :), vgrad2(:, :)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, g1, g2, wb, gb, v1, v2, l11, l21, l12, l22, u1, u2, m11, m21, m12, m22
    do p = 1, n
      l11 = 0.0_wp; l21 = 0.0_wp; l12 = 0.0_wp; l22 = 0.0_wp
      m11 = 0.0_wp; m21 = 0.0_wp; m12 = 0.0_wp; m22 = 0.0_wp
#include "dpmpm_stencil_do_2d_grad.inc"
      g1 = sdw(a, 1, p)*wb
      g2 = sw(a, 1, p)*gb
      v1 = nvel(3, i, j, k); v2 = nvel(4, i, j, k)
      l11 = l11 + v1*g1; l21 = l21 + v2*g1
      l12 = l12 + v1*g2; l22 = l22 + v2*g2
      u1 = nvel2(3, i, j, k); u2 = nvel2(4, i, j, k)
      m11 = m11 + u1*g1; m21 = m21 + u2*g1
      m12 = m12 + u1*g2; m22 = m22 + u2*g2
#include "dpmpm_stencil_end_2d.inc"
      vgrad(:, p) = 0.0_wp
      vgrad(1, p) = l11; vgrad(2, p) = l21; vgrad(4, p) = l12; vgrad(5, p) = l22
      vgrad2(:, p) = 0.0_wp
      vgrad2(1, p) = m11; vgrad2(2, p) = m21; vgrad2(4, p) = m12; vgrad2(5, p) = m22
    end do
  end subroutine point_gradients_2d

  subroutine momentum_project_p2g_2d(nw, n, i0, sw, mass, v, lo, fp, node, proj)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), v(:, :), fp(:, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):), proj(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, nm, wb, v1, v2, c1, c2
    do p = 1, n
      v1 = v(1, p); v2 = v(2, p)
      c1 = mass(p)*fp(1, p); c2 = mass(p)*fp(2, p)
#include "dpmpm_stencil_do_2d.inc"
      nm = nn*mass(p)
      node(2, i, j, k) = node(2, i, j, k) + nm*v1
      node(3, i, j, k) = node(3, i, j, k) + nm*v2
      proj(1, i, j, k) = proj(1, i, j, k) + nn*c1
      proj(2, i, j, k) = proj(2, i, j, k) + nn*c2
#include "dpmpm_stencil_end_2d.inc"
    end do
  end subroutine momentum_project_p2g_2d

  subroutine momentum_p2g_2d(nw, n, i0, sw, mass, v, lo, node)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), v(:, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, nm, wb, v1, v2
    do p = 1, n
      v1 = v(1, p); v2 = v(2, p)
#include "dpmpm_stencil_do_2d.inc"
      nm = nn*mass(p)
      node(2, i, j, k) = node(2, i, j, k) + nm*v1
      node(3, i, j, k) = node(3, i, j, k) + nm*v2
#include "dpmpm_stencil_end_2d.inc"
    end do
  end subroutine momentum_p2g_2d

  subroutine interp_two_values_2d(nw, n, i0, sw, lo, f, comp, val, val2)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
    integer, intent(in) :: comp
    real(wp), contiguous, intent(out) :: val(:), val2(:)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, wb, s0, t0
    do p = 1, n
      s0 = 0.0_wp; t0 = 0.0_wp
#include "dpmpm_stencil_do_2d.inc"
      s0 = s0 + nn*f(1, i, j, k)
      t0 = t0 + nn*f(comp, i, j, k)
#include "dpmpm_stencil_end_2d.inc"
      val(p) = s0
      val2(p) = t0
    end do
  end subroutine interp_two_values_2d

  subroutine fluid_p2g_2d(nw, n, i0, sw, sdw, mass, v, vol, poro, pres, kinv, momentum, point_forces, lo, &
                          node_s, node_f, drag, fvol)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), poro(:), pres(:), kinv(:)
    logical, intent(in) :: momentum, point_forces
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout) :: drag(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout), optional :: fvol(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, wb, gb, g1, g2, pv, dp, pf, ps, mp, mv1, mv2
    logical :: vols
    vols = present(fvol)
    do p = 1, n
      pv = 0.0_wp
      if (point_forces) pv = vol(p)*pres(p)
      pf = pv*poro(p)
      ps = pv*(1.0_wp - poro(p))
      dp = mass(p)*poro(p)*gravity_drag*kinv(p)
      mp = mass(p)
      mv1 = mp*v(1, p); mv2 = mp*v(2, p)
#include "dpmpm_stencil_do_2d_grad.inc"
      if (momentum) then
        node_f(1, i, j, k) = node_f(1, i, j, k) + nn*mp
        node_f(2, i, j, k) = node_f(2, i, j, k) + nn*mv1
        node_f(3, i, j, k) = node_f(3, i, j, k) + nn*mv2
      end if
      drag(1, i, j, k) = drag(1, i, j, k) + nn*dp
      if (vols) fvol(1, i, j, k) = fvol(1, i, j, k) + nn*vol(p)
      if (.not. point_forces) cycle
      g1 = sdw(a, 1, p)*wb
      g2 = sw(a, 1, p)*gb
      node_f(4, i, j, k) = node_f(4, i, j, k) + pf*g1
      node_f(5, i, j, k) = node_f(5, i, j, k) + pf*g2
      node_s(4, i, j, k) = node_s(4, i, j, k) + ps*g1
      node_s(5, i, j, k) = node_s(5, i, j, k) + ps*g2
#include "dpmpm_stencil_end_2d.inc"
    end do
  end subroutine fluid_p2g_2d

  subroutine solid_porosity_p2g_2d(nw, n, i0, sw, mass, poro, kinv, lo, sporo)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), poro(:), kinv(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: sporo(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, nm, wb, mp, mn, mk
    do p = 1, n
      if (.not. poro(p) > 0.0_wp) cycle
      mp = mass(p); mn = poro(p); mk = kinv(p)
#include "dpmpm_stencil_do_2d.inc"
      nm = nn*mp
      sporo(1, i, j, k) = sporo(1, i, j, k) + nm*mn
      sporo(2, i, j, k) = sporo(2, i, j, k) + nm
      sporo(3, i, j, k) = sporo(3, i, j, k) + nm*mk
#include "dpmpm_stencil_end_2d.inc"
    end do
  end subroutine solid_porosity_p2g_2d

  subroutine reaches_thin_node_2d(nw, n, i0, sw, lo, f, hi, vmin, flag)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
    integer, intent(in) :: hi(3)
    real(wp), intent(in) :: vmin
    logical, intent(out) :: flag(:)
    integer :: p, a, b, i, j, k
    real(wp) :: nn, wb
    do p = 1, n
      flag(p) = .false.
#include "dpmpm_stencil_do_2d.inc"
      if (nn > 0.0_wp .and. f(1, i, j, k) < vmin) then
        if (i > 0 .and. i < hi(1) .and. j > 0 .and. j < hi(2)) flag(p) = .true.
      end if
#include "dpmpm_stencil_end_2d.inc"
    end do
  end subroutine reaches_thin_node_2d

end module dpmpm_transfer
