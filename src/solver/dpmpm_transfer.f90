!> Transfers between the points and the grid (doc/theory.md 3.5 and 4): p2g of mass,
!> momentum and internal force, g2p (FLIP/PIC velocity, position, velocity
!> gradient), point velocity gradients and divergences, the MUSL momentum remap, nodal scalars
!> interpolated to the points, and the two-phase terms that the points carry to
!> the grid (pore-pressure forces, drag coefficient, porosity sums, interphase
!> force, mixture flux). Every kernel works on plain arrays: a point's stencil is
!> its first node i0(:, p) and its weights sw(:, axis, p) and derivatives
!> sdw(:, axis, p) per axis (tensor products), nodes are addressed from lo.
!> In 2D, and in 3D for p2g, g2p, the point gradients and divergences, the momentum
!> remap, the point volume and the two-phase sums, each public kernel calls its form of
!> fixed stencil width through the table of that dimension and width (fixed_forms: the
!> procedures of dpmpm_transfer_w2, _w3, _w4, filled once; a width without a module is
!> refused); the loops here, with the width read at run time, serve 1D and the general
!> form with a third axis of one node.
module dpmpm_transfer
  use dpmpm_kinds, only: wp
  use dpmpm_tensor, only: voigt_to_tensor
  use dpmpm_drag, only: gravity_drag
  use dpmpm_kernels, only: refuse_width, max_stencil
  use dpmpm_transfer_set, only: transfer_set_t
  use dpmpm_transfer_w2, only: sets_w2 => fixed_width_sets
  use dpmpm_transfer_w3, only: sets_w3 => fixed_width_sets
  use dpmpm_transfer_w4, only: sets_w4 => fixed_width_sets
  implicit none
  private
  public :: p2g, g2p, g2p_remap, point_gradient, point_divergences, momentum_p2g, momentum_project_p2g
  public :: interp_two_values
  public :: fluid_p2g, interphase_p2g, solid_porosity_p2g, porous_p2g, mixture_flux, reaches_thin_node
  public :: body_force_work, volume_p2g
  public :: fixed_width_status

  !> The forms of fixed width by dimension (2, 3) and stencil width, each a table of
  !> procedures that its module dpmpm_transfer_wN fills (fill_fixed, on the first lookup);
  !> a width without a module keeps width 0 and is refused.
  type(transfer_set_t), target :: fixed(2:3, max_stencil)
  logical :: fixed_filled = .false.

contains

  !> The table of the forms of fixed width: one line per module of a width.
  subroutine fill_fixed()
    call sets_w2(fixed(2, 2), fixed(3, 2))
    call sets_w3(fixed(2, 3), fixed(3, 3))
    call sets_w4(fixed(2, 4), fixed(3, 4))
    fixed_filled = .true.
  end subroutine fill_fixed

  !> 0 when a module of fixed width has filled the forms of dimension nd (2 or 3) and
  !> stencil width nw (nodes per axis); 1 when no module has that width, 2 when nd is
  !> neither 2 nor 3.
  integer function fixed_width_status(nd, nw) result(stat)
    integer, intent(in) :: nd, nw
    if (.not. fixed_filled) call fill_fixed()
    stat = 0
    if (nd < 2 .or. nd > 3) then
      stat = 2
    else if (nw < 1 .or. nw > max_stencil) then
      stat = 1
    else if (fixed(nd, nw)%width /= nw) then
      stat = 1
    end if
  end function fixed_width_status

  !> Whether the forms of fixed width take stencils of nw nodes per axis in nd
  !> dimensions: 2D (the third axis of one node), and 3D with one width on every axis.
  pure logical function has_fixed_forms(nd, nw)
    integer, intent(in) :: nd, nw(3)
    has_fixed_forms = nd == 2 .or. (nd == 3 .and. all(nw == nw(1)))
  end function has_fixed_forms

  !> The forms of fixed width for dimension nd and stencil width nw; a width that no
  !> module has stops the run.
  function fixed_forms(nd, nw) result(fs)
    integer, intent(in) :: nd, nw
    type(transfer_set_t), pointer :: fs
    fs => null()
    if (fixed_width_status(nd, nw) /= 0) then
      call refuse_width(nw, 'dpmpm_transfer')
      return
    end if
    fs => fixed(nd, nw)
  end function fixed_forms

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
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      ! (An absent optional array cannot be passed on to a contiguous dummy.)
      if (present(bacc)) then
        call fw%p2g_body(n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, bacc)
      else
        call fw%p2g(n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node)
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

  !> p2g of a porous skeleton's points (as p2g, without body accelerations) and their
  !> porosity sums (as solid_porosity_p2g) in one pass where a kernel of fixed dimension
  !> takes both (2D; 3D of one width); otherwise the two kernels in turn. The same sums
  !> either way.
  subroutine porous_p2g(nd, nw, n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, poro, kinv, sporo)
    integer, intent(in) :: nd, nw(3), n
    logical, intent(in) :: point_forces
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), stress(:, :), poro(:), kinv(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):), sporo(:, lo(1):, lo(2):, lo(3):)
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      call fw%porous_p2g(n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, poro, kinv, sporo)
    else
      call p2g(nd, nw, n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node)
      call solid_porosity_p2g(nw, n, i0, sw, mass, poro, kinv, lo, sporo)
    end if
  end subroutine porous_p2g

  !> Grid to particle: FLIP/PIC blend of the velocity, position update with the
  !> new nodal velocity, and the velocity gradient from the new nodal velocity (USL).
  !> gradient = .false. (MUSL, whose remap replaces the gradient) leaves vgrad as it is;
  !> without vgrad (the fluid points, which keep divergences: point_divergences) no
  !> gradient is formed.
  subroutine g2p(nd, nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, gradient, gf, gv)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: flip, dt
    real(wp), contiguous, intent(inout) :: v(:, :), x(:, :)
    real(wp), contiguous, intent(inout), optional :: vgrad(:, :)
    logical, intent(in), optional :: gradient
    !> With gf: gv(1:nd, p) = sum_I N_I(x_p) gf(1:nd, I), another nodal vector field at the
    !> points in the same pass (the locked velocity of the MUSL remap, momentum_project_p2g),
    !> summed in the order interp_two_values sums.
    real(wp), contiguous, intent(in), optional :: gf(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout), optional :: gv(:, :)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, g(3), dv(3), vn(3), lg(3, 3), gs(3)
    real(wp) :: none(1, 1), nograd(1, 1)
    logical :: grad, gather
    grad = present(vgrad)
    if (present(gradient)) grad = grad .and. gradient
    gather = present(gf) .and. present(gv)
    if (has_fixed_forms(nd, nw)) then
      ! (An absent optional array cannot be passed on to a contiguous dummy: without vgrad
      ! the kernels get a stand-in they do not touch.)
      if (present(vgrad)) then
        call g2p_fixed(vgrad)
      else
        call g2p_fixed(nograd)
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

  contains

    !> The forms of fixed dimension and stencil width, the gradients into vg.
    subroutine g2p_fixed(vg)
      real(wp), contiguous, intent(inout) :: vg(:, :)
      ! (Without gf the kernels get nvel and a dummy they do not touch.)
      if (gather) then
        call g2p_by_width(vg, gf, gv)
      else
        call g2p_by_width(vg, nvel, none)
      end if
    end subroutine g2p_fixed

    !> The kernel of the dimension and stencil width, gfa and gva as its gf and gv.
    subroutine g2p_by_width(vg, gfa, gva)
      real(wp), contiguous, intent(inout) :: vg(:, :)
      real(wp), contiguous, intent(in) :: gfa(:, lo(1):, lo(2):, lo(3):)
      real(wp), contiguous, intent(inout) :: gva(:, :)
      type(transfer_set_t), pointer :: fw
      fw => fixed_forms(nd, nw(1))
      call fw%g2p(n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vg, grad, gfa, gva, gather)
    end subroutine g2p_by_width

  end subroutine g2p

  !> g2p of the MUSL remap (velocities and positions, no gradient) and the remap's
  !> momentum of the new velocities, node(2:1+nd) += sum_p N_I m_p v_p (momentum_p2g),
  !> in one pass over the points: each point's stencil is scattered to while its nodes
  !> are at hand. With gf: gv = f at the points as g2p gathers it, and the momentum of its
  !> projection into the force slots (momentum_project_p2g). The sums are those of the
  !> separate kernels, in their order.
  subroutine g2p_remap(nd, nw, n, i0, sw, sdw, lo, nvel, flip, dt, mass, v, x, node, gf, gv)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :), mass(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: flip, dt
    real(wp), contiguous, intent(inout) :: v(:, :), x(:, :), node(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(in), optional :: gf(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout), optional :: gv(:, :)
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      if (present(gf) .and. present(gv)) then
        call fw%g2p_remap_project(n, i0, sw, lo, nvel, flip, dt, mass, v, x, node, gf, gv)
      else
        call fw%g2p_remap(n, i0, sw, lo, nvel, flip, dt, mass, v, x, node)
      end if
    else if (present(gf) .and. present(gv)) then
      call g2p(nd, nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, gradient=.false., gf=gf, gv=gv)
      call momentum_project_p2g(nd, nw, n, i0, sw, mass, v, lo, gv, node)
    else
      call g2p(nd, nw, n, i0, sw, sdw, lo, nvel, flip, dt, v, x, gradient=.false.)
      call momentum_p2g(nd, nw, n, i0, sw, mass, v, lo, node)
    end if
  end subroutine g2p_remap

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
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      call fw%point_gradient(n, i0, sw, sdw, lo, nvel, vgrad)
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

  !> Divergences of two nodal velocity fields at the points in one pass: div from
  !> nvel(nd+1:2nd), div2 from nvel2 (the fluid points' divergences of the fluid's and
  !> the skeleton's velocity, all the pore-pressure update reads of their gradients).
  !> Each diagonal component is summed over the stencil as point_gradient sums it, and
  !> the trace is formed from them in the order 1, 2, 3.
  subroutine point_divergences(nd, nw, n, i0, sw, sdw, lo, nvel, nvel2, div, div2)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), nvel2(:, lo(1):, lo(2):, lo(3):)
    real(wp), contiguous, intent(inout) :: div(:), div2(:)
    integer :: p, a, b, c, i, j, k, d
    real(wp) :: nn, g(3), ld(3), ld2(3)
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      call fw%point_divergences(n, i0, sw, sdw, lo, nvel, nvel2, div, div2)
      return
    end if
    do p = 1, n
      ld = 0.0_wp
      ld2 = 0.0_wp
#include "dpmpm_stencil_do_3d.inc"
#include "dpmpm_stencil_grad_3d.inc"
      do d = 1, nd
        ld(d) = ld(d) + nvel(nd + d, i, j, k)*g(d)
        ld2(d) = ld2(d) + nvel2(nd + d, i, j, k)*g(d)
      end do
#include "dpmpm_stencil_end_3d.inc"
      div(p) = ld(1) + ld(2) + ld(3)
      div2(p) = ld2(1) + ld2(2) + ld2(3)
    end do
  end subroutine point_divergences

  !> The MUSL remap with the locked velocity f in one pass over the points of a phase:
  !> the momenta node(2:1+nd) += sum N_I m_p v_p (as momentum_p2g) and the momentum of
  !> f's projection through this point set, node(2+nd:1+2nd) += sum_p N_I m_p fp_p (the
  !> force slots, free in the remap), where fp_p = sum_J N_J f_J is f at the points (g2p
  !> gathers it in its pass). Divided by the nodal mass it is P f.
  subroutine momentum_project_p2g(nd, nw, n, i0, sw, mass, v, lo, fp, node)
    integer, intent(in) :: nd, nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), v(:, :), fp(:, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, c, i, j, k
    real(wp) :: nn, vc(3)
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      call fw%momentum_project_p2g(n, i0, sw, mass, v, lo, fp, node)
      return
    end if
    do p = 1, n
      vc(1:nd) = mass(p)*fp(1:nd, p)
#include "dpmpm_stencil_do_3d.inc"
      node(2:1 + nd, i, j, k) = node(2:1 + nd, i, j, k) + nn*mass(p)*v(:, p)
      node(2 + nd:1 + 2*nd, i, j, k) = node(2 + nd:1 + 2*nd, i, j, k) + nn*vc(1:nd)
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
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      call fw%momentum_p2g(n, i0, sw, mass, v, lo, node)
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
    ! (2D: a third axis of one node; 3D: the same width on every axis; 1D takes the loop
    ! below)
    type(transfer_set_t), pointer :: fw
    if (nw(1) > 1 .and. nw(2) == nw(1) .and. (nw(3) == 1 .or. nw(3) == nw(1))) then
      fw => fixed_forms(merge(2, 3, nw(3) == 1), nw(1))
      call fw%volume_p2g(n, i0, sw, vol, lo, nvol)
      return
    end if
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
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      call fw%interp_two_values(n, i0, sw, lo, f, comp, val, val2)
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
    type(transfer_set_t), pointer :: fw
    if (has_fixed_forms(nd, nw)) then
      fw => fixed_forms(nd, nw(1))
      call fw%fluid_p2g(n, i0, sw, sdw, mass, v, vol, poro, pres, kinv, momentum, point_forces, lo, &
        node_s, node_f, drag, fvol)
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
    type(transfer_set_t), pointer :: fw
    if (nw(3) == 1 .and. nw(2) > 1) then
      fw => fixed_forms(2, nw(1))
      call fw%solid_porosity_p2g(n, i0, sw, mass, poro, kinv, lo, sporo)
      return
    end if
    if (nw(3) > 1 .and. all(nw == nw(1))) then
      fw => fixed_forms(3, nw(1))
      call fw%solid_porosity_p2g(n, i0, sw, mass, poro, kinv, lo, sporo)
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
    type(transfer_set_t), pointer :: fw
    hi = huge(1)
    hi(1:nd) = ncells(1:nd)
    ! Where the fluid fills every node inside the grid that this rank stores (a
    ! saturated body that fills the grid), no point reaches a thin one.
    if (.not. any_thin_node(nd, lo, f, hi, vmin)) then
      flag(1:n) = .false.
      return
    end if
    if (nd == 2) then
      fw => fixed_forms(2, nw(1))
      call fw%reaches_thin_node(n, i0, sw, lo, f, hi, vmin, flag)
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

  !> Whether a node of f (stored from lo) inside the grid (0 < index < hi on each axis of
  !> nd) has f(1) < vmin.
  logical function any_thin_node(nd, lo, f, hi, vmin) result(thin)
    integer, intent(in) :: nd, lo(3), hi(3)
    real(wp), contiguous, intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in) :: vmin
    integer :: a(3), b(3), i, j, k
    a = [lbound(f, 2), lbound(f, 3), lbound(f, 4)]
    b = [ubound(f, 2), ubound(f, 3), ubound(f, 4)]
    a(1:nd) = max(a(1:nd), 1)
    b(1:nd) = min(b(1:nd), hi(1:nd) - 1)
    thin = .false.
    do k = a(3), b(3)
      do j = a(2), b(2)
        do i = a(1), b(1)
          if (f(1, i, j, k) < vmin) thin = .true.
        end do
      end do
      if (thin) return
    end do
  end function any_thin_node

end module dpmpm_transfer
