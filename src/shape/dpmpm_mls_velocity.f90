!> MLS nodal velocities (doc/theory.md 3.3 and 3.5): the moment sums of every
!> node, sum_p m_p W p p^T and sum_p m_p W p v_p, are accumulated from the points
!> like masses, pass through the halo exchange (halo_sum) and the mirror walls
!> (velocity_fold_signs), and are solved node by node (dpmpm_mls, with its
!> fallbacks) for the nodal velocities of one or two phases alike.
module dpmpm_mls_velocity
  use dpmpm_kinds, only: wp
  use dpmpm_kernels, only: kernel_weight, kernel_reach
  use dpmpm_mls, only: basis_size, packed_size, basis_eval, moment_add, mls_gamma, mls_stats_t
  implicit none
  private
  public :: velocity_accumulate, velocity_solve, velocity_fold_signs

contains

  !> Index range of nodes (or cell-centre lattice, shift 0.5) within reach of s.
  pure subroutine reach_range(s, reach, shift, lo, hi)
    real(wp), intent(in) :: s, reach, shift
    integer, intent(out) :: lo, hi
    lo = ceiling(s - shift - reach)
    hi = floor(s - shift + reach)
  end subroutine reach_range

  ! ----------------------------------------------------------------------------
  ! Nodal velocities

  !> Add every point's MLS moment sums to the nodes within reach of its weight.
  !> acc(1 + packed + nb*nd, nodes): count of sites, packed sum m W p p^T,
  !> then sum m W p v_c for each velocity component c.
  subroutine velocity_accumulate(nd, n, x, mass, v, origin, h, kernel, radius, radial, basis, &
                                 lo, acc)
    integer, intent(in) :: nd, n, kernel, basis
    real(wp), intent(in) :: x(:, :), mass(:), v(:, :), origin(3), h(3), radius
    logical, intent(in) :: radial
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: acc(:, lo(1):, lo(2):, lo(3):)
    integer :: p, i, j, k, nb, np, c, ilo(3), ihi(3), d
    real(wp) :: s(3), dcell(3), dneg(3), wk, dwk(3), w, pv(10), reach
    nb = basis_size(basis, nd)
    np = packed_size(nb)
    reach = kernel_reach(kernel, radius, radial)
    ilo = 0; ihi = 0
    do p = 1, n
      s = 0.0_wp
      do d = 1, nd
        s(d) = (x(d, p) - origin(d))/h(d)
        call reach_range(s(d), reach, 0.0_wp, ilo(d), ihi(d))
      end do
      do k = ilo(3), ihi(3)
        do j = ilo(2), ihi(2)
          do i = ilo(1), ihi(1)
            dcell = real([i, j, k], wp) - s
            call kernel_weight(kernel, radius, radial, nd, dcell(1:nd), wk, dwk(1:nd))
            if (wk <= 0.0_wp) cycle
            w = mass(p)*wk
            dneg = -dcell
            call basis_eval(basis, nd, dneg(1:nd), pv(1:nb))
            acc(1, i, j, k) = acc(1, i, j, k) + 1.0_wp
            call moment_add(nb, pv(1:nb), w, acc(2:1 + np, i, j, k))
            do c = 1, nd
              acc(2 + np + (c - 1)*nb:1 + np + c*nb, i, j, k) = &
                acc(2 + np + (c - 1)*nb:1 + np + c*nb, i, j, k) + w*v(c, p)*pv(1:nb)
            end do
          end do
        end do
      end do
    end do
  end subroutine velocity_accumulate

  !> Signs of the velocity moment components under a reflection across a plane
  !> normal to axis d, with the velocity component signs vsign(nd): the basis
  !> monomials odd in y_d change sign.
  pure subroutine velocity_fold_signs(nd, basis, d, vsign, sg)
    integer, intent(in) :: nd, basis, d
    real(wp), intent(in) :: vsign(nd)
    real(wp), intent(out) :: sg(:)
    real(wp) :: y(nd), sb(10)
    integer :: nb, np, i, j, c
    nb = basis_size(basis, nd)
    np = packed_size(nb)
    y = 1.0_wp
    y(d) = -1.0_wp
    call basis_eval(basis, nd, y, sb(1:nb))
    sg(1) = 1.0_wp
    do j = 1, nb
      do i = 1, j
        sg(1 + j*(j - 1)/2 + i) = sb(i)*sb(j)
      end do
    end do
    do c = 1, nd
      sg(2 + np + (c - 1)*nb:1 + np + c*nb) = vsign(c)*sb(1:nb)
    end do
  end subroutine velocity_fold_signs

  !> Nodal velocities of the owned nodes [olo, ohi] from the summed moments;
  !> the momentum slots of node (2:1+nd) become m_I v_I.
  subroutine velocity_solve(nd, basis, lo, olo, ohi, acc, node, stats)
    integer, intent(in) :: nd, basis, lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: acc(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    type(mls_stats_t), intent(inout) :: stats
    integer :: i, j, k, nb, np, c, level
    real(wp) :: gam(10)
    nb = basis_size(basis, nd)
    np = packed_size(nb)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        do i = olo(1), ohi(1)
          if (node(1, i, j, k) <= 0.0_wp) cycle
          call mls_gamma(basis, nd, acc(2:1 + np, i, j, k), acc(1, i, j, k), gam(1:nb), level, stats)
          do c = 1, nd
            node(1 + c, i, j, k) = node(1, i, j, k)* &
              dot_product(gam(1:nb), acc(2 + np + (c - 1)*nb:1 + np + c*nb, i, j, k))
          end do
        end do
      end do
    end do
  end subroutine velocity_solve

end module dpmpm_mls_velocity
