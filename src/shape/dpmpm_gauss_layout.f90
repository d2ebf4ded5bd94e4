!> The Gauss-Legendre rule of the cells and the sizes of the Gauss points' per-cell arrays
!> (doc/theory.md 3.6): how many fields a point set reconstructs, the components of a
!> cell's accumulated moments and of its solutions, the slot of the radius a Gauss point
!> took, the widened radii of Gauss points that find no point, and the reach that covers
!> a cell. Set-up arithmetic of dpmpm_gauss_fields, which passes the public names on.
module dpmpm_gauss_layout
  use dpmpm_kinds, only: wp
  use dpmpm_kernels, only: kernel_reach
  use dpmpm_mls, only: basis_size, packed_size
  implicit none
  private
  public :: gauss_rule, gauss_cover_radius, field_components, stress_voigt_index, fields_of, &
            gauss_cell_components, gauss_second_field_components, gauss_solution_components, gauss_radius_slot, &
            widened_radii, widened_cell_offset, max_reach_of

contains

  !> Gauss-Legendre points (in [0, 1]) and weights (summing to 1) of n = 1..4 points.
  pure subroutine gauss_rule(n, xi, w)
    integer, intent(in) :: n
    real(wp), intent(out) :: xi(n), w(n)
    real(wp) :: a, b
    select case (n)
    case (1)
      xi = 0.5_wp; w = 1.0_wp
    case (2)
      a = 0.5_wp/sqrt(3.0_wp)
      xi = [0.5_wp - a, 0.5_wp + a]; w = 0.5_wp
    case (3)
      a = 0.5_wp*sqrt(0.6_wp)
      xi = [0.5_wp - a, 0.5_wp, 0.5_wp + a]
      w = [5.0_wp, 8.0_wp, 5.0_wp]/18.0_wp
    case default
      a = 0.5_wp*sqrt(3.0_wp/7.0_wp - 2.0_wp/7.0_wp*sqrt(1.2_wp))
      b = 0.5_wp*sqrt(3.0_wp/7.0_wp + 2.0_wp/7.0_wp*sqrt(1.2_wp))
      xi = [0.5_wp - b, 0.5_wp - a, 0.5_wp + a, 0.5_wp + b]
      w(2) = 0.25_wp + sqrt(30.0_wp)/72.0_wp
      w(3) = w(2)
      w(1) = 0.5_wp - w(2)
      w(4) = w(1)
    end select
  end subroutine gauss_rule

  !> The distance (cell units) from the Gauss points of a cell, ng per axis, to the
  !> place of the cell farthest from all of them: sqrt(nd) times that distance along one
  !> axis, the larger of the end gaps and half the inner ones. A radial field weight of a
  !> smaller radius leaves points in that part of the cell without a Gauss point of it.
  pure real(wp) function gauss_cover_radius(nd, ng) result(r)
    integer, intent(in) :: nd, ng
    real(wp) :: xi(ng), w(ng)
    integer :: a
    call gauss_rule(ng, xi, w)
    r = max(xi(1), 1.0_wp - xi(ng))
    do a = 1, ng - 1
      r = max(r, 0.5_wp*(xi(a + 1) - xi(a)))
    end do
    r = sqrt(real(nd, wp))*r
  end function gauss_cover_radius

  !> Stress components that enter the force integrals in nd dimensions.
  pure integer function field_components(nd) result(n)
    integer, intent(in) :: nd
    n = nd*(nd + 1)/2
  end function field_components

  !> Voigt index (xx yy zz yz xz xy) of the k-th reconstructed stress component.
  pure integer function stress_voigt_index(nd, k) result(v)
    integer, intent(in) :: nd, k
    integer, parameter :: map2(3) = [1, 2, 6]
    select case (nd)
    case (1)
      v = 1
    case (2)
      v = map2(k)
    case default
      v = k
    end select
  end function stress_voigt_index

  !> Fields reconstructed per Gauss point: the stress components of nd dimensions, or
  !> with isotropic one, the value of an isotropic field s I (the pore pressure's shares).
  pure integer function fields_of(nd, isotropic) result(n)
    integer, intent(in) :: nd
    logical, intent(in), optional :: isotropic
    n = field_components(nd)
    if (present(isotropic)) then
      if (isotropic) n = 1
    end if
  end function fields_of

  !> Components per cell of the Gauss-point sums (gauss_accumulate).
  pure integer function gauss_cell_components(nd, ng, basis, isotropic) result(n)
    integer, intent(in) :: nd, ng, basis
    logical, intent(in), optional :: isotropic
    integer :: nb
    nb = basis_size(basis, nd)
    n = 1 + ng**nd*(1 + packed_size(nb) + nb*fields_of(nd, isotropic))
  end function gauss_cell_components

  !> Components per cell of a second field's sums (gauss_accumulate's acc2): its field
  !> sums alone, since the counts and moments of the same points are those of acc.
  pure integer function gauss_second_field_components(nd, ng, basis, isotropic) result(n)
    integer, intent(in) :: nd, ng, basis
    logical, intent(in), optional :: isotropic
    n = ng**nd*basis_size(basis, nd)*fields_of(nd, isotropic)
  end function gauss_second_field_components

  !> Components per cell of the Gauss-point solution (gauss_solve): the occupied flag,
  !> per Gauss point gamma and the fields, then per Gauss point the radius of a widened
  !> reach (0: the field's own; gauss_radius_slot).
  pure integer function gauss_solution_components(nd, ng, basis, isotropic) result(n)
    integer, intent(in) :: nd, ng, basis
    logical, intent(in), optional :: isotropic
    n = 1 + ng**nd*(basis_size(basis, nd) + fields_of(nd, isotropic)) + ng**nd
  end function gauss_solution_components

  !> The solution's component before the widened radii: Gauss point g's radius is
  !> sol(gauss_radius_slot(...) + g, cell), 0 where it kept the field's own radius.
  pure integer function gauss_radius_slot(nd, ng, basis, isotropic) result(n)
    integer, intent(in) :: nd, ng, basis
    logical, intent(in), optional :: isotropic
    n = 1 + ng**nd*(basis_size(basis, nd) + fields_of(nd, isotropic))
  end function gauss_radius_slot

  !> The radii an empty Gauss point tries in turn: the field's radius plus a quarter
  !> and plus half a cell (0.75 -> 1.0, 1.25).
  pure function widened_radii(radius) result(r)
    real(wp), intent(in) :: radius
    real(wp) :: r(2)
    r = radius + [0.25_wp, 0.5_wp]
  end function widened_radii

  !> The most cells between a point's cell and a cell of a Gauss point within reach of
  !> it (a weight of the given radius, ng Gauss points per axis): widened reaches must
  !> stay within the ghost cells.
  integer function widened_cell_offset(ng, kernel, radius, radial) result(m)
    integer, intent(in) :: ng, kernel
    real(wp), intent(in) :: radius
    logical, intent(in) :: radial
    real(wp) :: xi(ng), w(ng)
    call gauss_rule(ng, xi, w)
    ! A point at the top of cell c reaches the lowest Gauss point of cell c + m when
    ! m + xi(1) - 1 < reach.
    m = ceiling(kernel_reach(kernel, radius, radial) + 1.0_wp - xi(1)) - 1
  end function widened_cell_offset

  !> Size of the per-point Gauss-point lists for a reach (cell units).
  pure integer function max_reach_of(nd, ng, reach) result(m)
    integer, intent(in) :: nd, ng
    real(wp), intent(in) :: reach
    m = ((2*ceiling(reach) + 1)*ng)**nd
  end function max_reach_of

end module dpmpm_gauss_layout
