!> Axisymmetry (&grid axisymmetric, doc/theory.md "Axisymmetry"): r along x from the axis at
!> the grid's x- face (x = 0), z along y. Volumes and masses are per radian (V = r A, the
!> ring's 2 pi r A over 2 pi), so every sum of the plane step (masses, momenta, gravity,
!> the in-plane stress divergence) holds as it is; what the ring adds are the two terms
!> here: the hoop strain rate v_r / r at the points and the hoop stress's nodal force
!> -sigma_thth N_I V_p / r_p. Both run over the points of the solid in passes of their own,
!> so that the plane kernels stay as they are when the flag is off. With pore water the
!> same two terms for the pressure -p I of the fluid points: its hoop force on both phases
!> (pressure_hoop_p2g) and v_r / r of both phases in the divergences of the pressure
!> update (hoop_divergences); the free-surface test takes the points' areas in the r-z
!> plane (fluid_area_p2g).
module dpmpm_axisym
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: axisym_point_measures, hoop_force_p2g, hoop_rate, axis_radius, axis_guard
  public :: pressure_hoop_p2g, hoop_divergences, fluid_area_p2g

  !> Points closer to the axis than axis_guard cells take this radius in v_r / r and V / r:
  !> the ring there is thinner than round-off of a cell, and both quotients stay finite.
  real(wp), parameter :: axis_guard = 1.0e-3_wp

contains

  !> The radius of the hoop terms of a point at x1 (the guard of a point next to the axis).
  elemental real(wp) function axis_radius(x1, h1) result(r)
    real(wp), intent(in) :: x1, h1
    r = max(x1, axis_guard*h1)
  end function axis_radius

  !> Volumes and masses per radian of points generated with their cross-section areas A
  !> (the plane measures): V = r A, V0 = r A, m = rho V = r m_plane, r = x(1).
  subroutine axisym_point_measures(n, x, h1, vol, vol0, mass)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(:, :), h1
    real(wp), intent(inout) :: vol(:), vol0(:), mass(:)
    integer :: p
    real(wp) :: r
    do p = 1, n
      r = axis_radius(x(1, p), h1)
      vol(p) = r*vol(p)
      vol0(p) = r*vol0(p)
      mass(p) = r*mass(p)
    end do
  end subroutine axisym_point_measures

  !> The hoop stress's share of the internal force at the nodes of each point's stencil:
  !> f_I,r -= sigma_thth N_I(x_p) V_p / r_p (the virtual power of sigma_thth over the hoop
  !> strain rate delta v_r / r), into node(3 + 1, ...) (2D: mass, momentum r, z, force r, z).
  !> Added before the mirror fold, so that the axis's exterior nodes give their share to
  !> their images with the sign of v_r.
  subroutine hoop_force_p2g(nw, n, i0, sw, x, h1, vol, stress, lo, node)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    real(wp), intent(in) :: x(:, :), h1, vol(:), stress(:, :)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, i, j, k
    real(wp) :: fr
    do p = 1, n
      fr = -stress(3, p)*vol(p)/axis_radius(x(1, p), h1)
      k = i0(3, p)
      do b = 1, nw(2)
        j = i0(2, p) + b - 1
        do a = 1, nw(1)
          i = i0(1, p) + a - 1
          node(4, i, j, k) = node(4, i, j, k) + fr*sw(a, 1, p)*sw(b, 2, p)
        end do
      end do
    end do
  end subroutine hoop_force_p2g

  !> The hoop strain rate L_thth = v_r(x_p) / r_p into vgrad(9, p), v_r interpolated from
  !> the new nodal velocities nvel(3, ...) (2D: old r, z, new r, z) with the stencils of the
  !> in-plane gradient, r_p the point's radius now.
  subroutine hoop_rate(nw, n, i0, sw, x, h1, lo, nvel, vgrad)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    real(wp), intent(in) :: x(:, :), h1
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: vgrad(:, :)
    integer :: p, a, b, i, j, k
    real(wp) :: vr
    do p = 1, n
      vr = 0.0_wp
      k = i0(3, p)
      do b = 1, nw(2)
        j = i0(2, p) + b - 1
        do a = 1, nw(1)
          i = i0(1, p) + a - 1
          vr = vr + sw(a, 1, p)*sw(b, 2, p)*nvel(3, i, j, k)
        end do
      end do
      vgrad(9, p) = vr/axis_radius(x(1, p), h1)
    end do
  end subroutine hoop_rate

  !> The pore pressure's share of the hoop force at the nodes of each fluid point's stencil.
  !> The fluid carries the partial stress -n p I and the skeleton -(1 - n) p I (the shares of
  !> fluid_p2g's gradient term), whose theta-theta components give, as -sigma_thth N V / r
  !> does for the skeleton's effective stress, f_I,r += n p N_I V / r on the fluid
  !> (node_f(4)) and += (1 - n) p N_I V / r on the skeleton (node_s(4)). Added before the
  !> mirror fold.
  subroutine pressure_hoop_p2g(nw, n, i0, sw, x, h1, vol, poro, pres, lo, node_s, node_f)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    real(wp), intent(in) :: x(:, :), h1, vol(:), poro(:), pres(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, i, j, k
    real(wp) :: fr, nn
    do p = 1, n
      fr = pres(p)*vol(p)/axis_radius(x(1, p), h1)
      k = i0(3, p)
      do b = 1, nw(2)
        j = i0(2, p) + b - 1
        do a = 1, nw(1)
          i = i0(1, p) + a - 1
          nn = fr*sw(a, 1, p)*sw(b, 2, p)
          node_f(4, i, j, k) = node_f(4, i, j, k) + poro(p)*nn
          node_s(4, i, j, k) = node_s(4, i, j, k) + (1.0_wp - poro(p))*nn
        end do
      end do
    end do
  end subroutine pressure_hoop_p2g

  !> The hoop parts of the divergences at the fluid points: v_f,r / r into divf and
  !> v_s,r / r into divs, each phase's radial velocity interpolated from its new nodal
  !> velocities (nvel(3, ...)) with the fluid point's stencil, r the point's radius after
  !> its move (the divergence in cylindrical coordinates, dv_r/dr + v_r/r + dv_z/dz).
  subroutine hoop_divergences(nw, n, i0, sw, x, h1, lo, nvel_f, nvel_s, divf, divs)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    real(wp), intent(in) :: x(:, :), h1
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(in) :: nvel_f(:, lo(1):, lo(2):, lo(3):), nvel_s(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: divf(:), divs(:)
    integer :: p, a, b, i, j, k
    real(wp) :: vf, vs, nn, r
    do p = 1, n
      vf = 0.0_wp
      vs = 0.0_wp
      k = i0(3, p)
      do b = 1, nw(2)
        j = i0(2, p) + b - 1
        do a = 1, nw(1)
          i = i0(1, p) + a - 1
          nn = sw(a, 1, p)*sw(b, 2, p)
          vf = vf + nn*nvel_f(3, i, j, k)
          vs = vs + nn*nvel_s(3, i, j, k)
        end do
      end do
      r = axis_radius(x(1, p), h1)
      divf(p) = divf(p) + vf/r
      divs(p) = divs(p) + vs/r
    end do
  end subroutine hoop_divergences

  !> The fluid's area in the r-z plane at the nodes, sum_p N_I V_p / r_p, in place of the
  !> per-radian volume sum_p N_I V_p that fluid_p2g gives the free-surface tests: those
  !> compare it with a fraction of a cell's area h^2, which the per-radian volume next to
  !> the axis (r << h) would never reach. fvol is set, not added to.
  subroutine fluid_area_p2g(nw, n, i0, sw, x, h1, vol, lo, fvol)
    integer, intent(in) :: nw(3), n
    integer, contiguous, intent(in) :: i0(:, :)
    real(wp), contiguous, intent(in) :: sw(:, :, :)
    real(wp), intent(in) :: x(:, :), h1, vol(:)
    integer, intent(in) :: lo(3)
    real(wp), contiguous, intent(inout) :: fvol(:, lo(1):, lo(2):, lo(3):)
    integer :: p, a, b, i, j, k
    real(wp) :: ar
    fvol = 0.0_wp
    do p = 1, n
      ar = vol(p)/axis_radius(x(1, p), h1)
      k = i0(3, p)
      do b = 1, nw(2)
        j = i0(2, p) + b - 1
        do a = 1, nw(1)
          i = i0(1, p) + a - 1
          fvol(1, i, j, k) = fvol(1, i, j, k) + ar*sw(a, 1, p)*sw(b, 2, p)
        end do
      end do
    end do
  end subroutine fluid_area_p2g

end module dpmpm_axisym
