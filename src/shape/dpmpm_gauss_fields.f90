!> MLS fields at Gauss points inside the time step (doc/theory.md 3.6).
!>
!> Force integrals at Gauss points: every grid cell carries ng^nd Gauss points.
!> Stresses are reconstructed there from the points (weights V_p W), and the
!> internal force is f_I = -sum_g w_g sigma_h(x_g) grad Psi_I(x_g) with the grid
!> functions Psi. The point velocity gradient is the transpose of that
!> operator, L_p = sum_g C_gp L_g / sum_g C_gp with C_gp = w_g Phi_p(x_g) and
!> L_g = sum_I v_I (x) grad Psi_I(x_g), so that the discrete stress power equals
!> the nodal force power (doc/theory.md 3.6): the pair neither creates nor
!> destroys energy.
!>
!> Cells take part in the quadrature when they hold a point or lie in a gap of
!> at most 2 r cells between such cells along every axis (a morphological
!> closing of the occupied cells with a box of half-width r, r the field weight's
!> reach in whole cells; gauss_occupancy in dpmpm_quadrature): scattered points
!> leave cells empty inside the body, and those must count, while the closing
!> does not move a free surface.
!>
!> A Gauss point of an occupied cell that finds no point within the weight's reach
!> widens it, by a quarter cell and then by half a cell (widened_radii), instead of
!> entering the forces with a zero field: gauss_accumulate with `only` adds the points
!> within the wider reach to those Gauss points alone, the solution keeps the radius
!> each Gauss point took (gauss_radius_slot), and gauss_strain takes the same wider
!> weights for the transpose, so that the pair stays exact. Only a Gauss point that
!> finds no point within the widest reach keeps the zero field.
!>
!> Cell arrays are indexed like nodes by the cell's lower corner, so they use
!> the same storage bounds and the same halo_sum / halo_copy.
module dpmpm_gauss_fields
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: node_slots_t, node_slots
  use dpmpm_kernels, only: kernel_weight, kernel_reach, kernel_radial, kernel_radial_values, &
                           is_grid_kernel, max_stencil, kernel_width, bspline_1d
  use dpmpm_stencil, only: psi_stencil, stencil_offsets, tensor_weights
  use dpmpm_mls, only: basis_size, packed_size, basis_eval, moment_add, mls_gamma, mls_stats_t
  use dpmpm_tensor, only: voigt_to_tensor
  use dpmpm_gauss_layout, only: gauss_rule, gauss_cover_radius, field_components, stress_voigt_index, fields_of, &
                                gauss_cell_components, gauss_second_field_components, &
                                gauss_solution_components, gauss_radius_slot, widened_radii, &
                                widened_cell_offset, max_reach_of
  implicit none
  private
  public :: gauss_rule, gauss_cover_radius, field_components, stress_voigt_index
  public :: gauss_accumulate, gauss_solve, gauss_forces, gauss_masses, gauss_velocity_gradient, gauss_strain
  public :: occupancy_pass, gauss_cell_components, gauss_solution_components, gauss_second_field_components
  public :: reach_cache_t, reach_cache_entries, reach_cache_bytes
  public :: thin_fraction, thin_node_forces
  public :: widened_radii, widened_cell_offset, gauss_radius_slot

  !> Most Gauss points of one cell (4 per axis in 3D).
  integer, parameter :: max_gauss_cell = 64
  !> Most Gauss points along one axis within reach of a point (radius 4, 4 per cell).
  integer, parameter :: max_lattice = 40
  !> Most Gauss points within reach of a point.
  integer, parameter :: max_reach = max_lattice**3
  !> Bytes of one entry of a reach cache (four integers and a weight).
  integer, parameter :: reach_entry_bytes = 24
  !> Memory a reach cache may take per point set (bytes); beyond it gauss_strain
  !> finds the Gauss points within reach again.
  integer(kind=8), parameter :: reach_cache_budget = 256_8*1024_8*1024_8
  !> The most entries within the budget (the whole entries: an exact division).
  integer(kind=8), parameter :: reach_cache_cap = (reach_cache_budget - mod(reach_cache_budget, &
                                                   int(reach_entry_bytes, 8)))/reach_entry_bytes
  !> A node is thin for a point set when the set's points give it less than this
  !> fraction of the volume its Gauss points give it, sum_p V_p Psi_I(x_p) <
  !> thin_fraction sum_g w_g Psi_I(x_g) (thin_node_forces).
  real(wp), parameter :: thin_fraction = 1.0e-3_wp

  !> The Gauss points within reach of every point of a set and their weights, kept by
  !> gauss_accumulate for gauss_strain in the same step (the same positions), so that
  !> the reach is found once per point and step. Entry q of point p (start(p) <= q <
  !> start(p + 1)): cell idx(1:3, q), Gauss indices along the axes packed in idx(4, q)
  !> (3 bits each), weight w(q). Not valid when it would pass reach_cache_budget.
  type :: reach_cache_t
    logical :: valid = .false.
    integer :: n = 0
    integer, allocatable :: start(:), idx(:, :)
    real(wp), allocatable :: w(:)
  end type reach_cache_t

contains

  ! ----------------------------------------------------------------------------
  ! Gauss-point quadrature

  !> Gauss-point offsets inside a cell (cell units) and weights (cell-volume
  !> fractions) in lexicographic order, ng^nd of them.
  pure subroutine gauss_points_of_cell(nd, ng, yg, wg)
    integer, intent(in) :: nd, ng
    real(wp), intent(out) :: yg(:, :), wg(:)
    real(wp) :: xi(ng), w(ng)
    integer :: a, b, c, g, nb_, nc_
    call gauss_rule(ng, xi, w)
    nb_ = merge(ng, 1, nd >= 2)
    nc_ = merge(ng, 1, nd >= 3)
    g = 0
    do c = 1, nc_
      do b = 1, nb_
        do a = 1, ng
          g = g + 1
          yg(:, g) = 0.0_wp
          yg(1, g) = xi(a)
          wg(g) = w(a)
          if (nd >= 2) then
            yg(2, g) = xi(b)
            wg(g) = wg(g)*w(b)
          end if
          if (nd >= 3) then
            yg(3, g) = xi(c)
            wg(g) = wg(g)*w(c)
          end if
        end do
      end do
    end do
  end subroutine gauss_points_of_cell

  !> Gauss-point lattice along one axis within reach of a point at s (cell units):
  !> for each entry the cell, the Gauss index and the offset (point to Gauss point).
  pure subroutine axis_lattice(s, reach, ncell, ng, xi, nl, cell, ga, off)
    real(wp), intent(in) :: s, reach, xi(:)
    integer, intent(in) :: ncell, ng
    integer, intent(out) :: nl, cell(:), ga(:)
    real(wp), intent(out) :: off(:)
    integer :: i, a
    real(wp) :: dx
    nl = 0
    if (ng == 1 .and. reach <= 1.0_wp) then
      ! One Gauss point per cell within one cell: only the centres of the cells
      ! floor(s - 1/2) and the next can lie within reach (written in any case, kept
      ! when inside the grid and the reach: no branch to mispredict)
      do i = floor(s - 0.5_wp), floor(s - 0.5_wp) + 1
        dx = real(i, wp) + xi(1) - s
        cell(nl + 1) = i
        ga(nl + 1) = 1
        off(nl + 1) = dx
        nl = nl + merge(1, 0, abs(dx) < reach .and. i >= 0 .and. i < ncell)
      end do
      return
    end if
    do i = max(0, floor(s - reach)), min(ncell - 1, floor(s + reach))
      do a = 1, ng
        dx = real(i, wp) + xi(a) - s
        if (abs(dx) >= reach) cycle
        nl = nl + 1
        cell(nl) = i
        ga(nl) = a
        off(nl) = dx
      end do
    end do
  end subroutine axis_lattice

  !> The Gauss points within reach of a point at s, in nd dimensions: their cells,
  !> indices within the cell (lexicographic), offsets (Gauss point minus point, cell
  !> units) and weights (kernel_weight's). Radial weights are evaluated only inside the radius,
  !> all of a point's at once.
  subroutine points_in_reach(nd, s, ncells, ng, xi, kernel, radius, radial, reach, np, &
                                  cells, gidx, offs, w, gax)
    integer, intent(in) :: nd, ncells(3), ng, kernel
    real(wp), intent(in) :: s(3), xi(:), radius, reach
    logical, intent(in) :: radial
    integer, intent(out) :: np, cells(:, :), gidx(:)
    !> The Gauss index along each axis, from 0, packed 3 bits each (reach_cache_t).
    integer, intent(out) :: gax(:)
    real(wp), intent(out) :: offs(:, :), w(:)
    integer :: nl(3), cl(max_lattice, 3), gl(max_lattice, 3), a, b, c, d, m
    real(wp) :: ol(max_lattice, 3), wl(max_lattice, 3), dwl, r2, r2max, wk
    logical :: rad, inside
    rad = radial .or. (radius <= 0.0_wp .and. .not. is_grid_kernel(kernel))
    nl = 1
    cl(1, :) = 0; gl(1, :) = 1; ol(1, :) = 0.0_wp; wl(1, :) = 1.0_wp
    do d = 1, nd
      call axis_lattice(s(d), reach, ncells(d), ng, xi, nl(d), cl(:, d), gl(:, d), ol(:, d))
      if (rad) cycle
      do a = 1, nl(d)
        if (radius > 0.0_wp) then
          ! the box: the kernel's profile of half-width radius along each axis
          call kernel_radial(kernel, abs(ol(a, d))/radius, wl(a, d), dwl)
        else
          call bspline_1d(kernel, ol(a, d), wl(a, d), dwl)
        end if
      end do
    end do
    np = 0
    r2max = radius*radius
    do c = 1, nl(3)
      do b = 1, nl(2)
        do a = 1, nl(1)
          ! Each candidate is written to the next slot and kept when inside (no branch
          ! to mispredict); radial weights have their distance here, the weight below.
          if (rad) then
            r2 = ol(a, 1)**2 + ol(b, 2)**2 + ol(c, 3)**2
            wk = sqrt(r2)/radius
            inside = r2 < r2max
          else
            wk = wl(a, 1)*wl(b, 2)*wl(c, 3)
            inside = wk > 0.0_wp
          end if
          cells(1, np + 1) = cl(a, 1)
          cells(2, np + 1) = cl(b, 2)
          cells(3, np + 1) = cl(c, 3)
          gidx(np + 1) = gl(a, 1) + ng*(gl(b, 2) - 1) + ng*ng*(gl(c, 3) - 1)
          gax(np + 1) = ior(ior(gl(a, 1) - 1, ishft(gl(b, 2) - 1, 3)), ishft(gl(c, 3) - 1, 6))
          offs(1, np + 1) = ol(a, 1)
          offs(2, np + 1) = ol(b, 2)
          offs(3, np + 1) = ol(c, 3)
          w(np + 1) = wk
          np = np + merge(1, 0, inside)
        end do
      end do
    end do
    if (.not. rad) return
    call kernel_radial_values(kernel, np, w)
    ! A weight that rounds to 0 at the rim leaves the list.
    if (all(w(1:np) > 0.0_wp)) return
    m = 0
    do a = 1, np
      if (w(a) <= 0.0_wp) cycle
      m = m + 1
      cells(:, m) = cells(:, a)
      gidx(m) = gidx(a)
      gax(m) = gax(a)
      offs(:, m) = offs(:, a)
      w(m) = w(a)
    end do
    np = m
  end subroutine points_in_reach

  !> Add every point to the point count of its cell and its MLS sums of stress
  !> to the Gauss points within reach. acc per cell: point count, then per
  !> Gauss point: count, packed sum V W p p^T, sum V W p sigma_f (nf fields).
  !> With isotropic, stress(1, :) is the value s of an isotropic field s I, one field.
  subroutine gauss_accumulate(nd, n, x, vol, stress, origin, h, ncells, ng, kernel, radius, &
                              radial, basis, lo, acc, stress2, acc2, cache, isotropic, only, level)
    integer, intent(in) :: nd, n, ncells(3), ng, kernel, basis
    real(wp), intent(in) :: x(:, :), vol(:), stress(:, :), origin(3), h(3), radius
    logical, intent(in) :: radial
    integer, intent(in) :: lo(3)
    real(wp), intent(inout) :: acc(:, lo(1):, lo(2):, lo(3):)
    !> A second field of the same points, summed into acc2 in the same pass: its field
    !> sums alone (gauss_second_field_components), the counts and moments being acc's.
    real(wp), intent(in), optional :: stress2(:, :)
    real(wp), intent(inout), optional :: acc2(:, lo(1):, lo(2):, lo(3):)
    !> Keeps the Gauss points within reach of each point for gauss_strain.
    type(reach_cache_t), intent(inout), optional :: cache
    logical, intent(in), optional :: isotropic
    !> With only and level: add the points to the Gauss points g of cell c with
    !> only(g, c) == level alone (a widened reach, radius = level), not to the point
    !> counts of the cells nor to the cache.
    real(wp), intent(in), optional :: only(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(in), optional :: level
    integer :: p, i, j, k, q, nb, np, nf, ncg, f, cp(3), base, base2, d, nq, nc
    integer, allocatable :: cells(:, :), gidx(:), gax(:)
    real(wp), allocatable :: offs(:, :), wq(:)
    real(wp) :: s(3), dneg(3), w, pv(10), reach, xi(ng), wxi(ng), sig(6), sig2(6)
    logical :: two, keep, widen
    two = present(stress2) .and. present(acc2)
    widen = present(only) .and. present(level)
    keep = present(cache) .and. .not. widen
    if (keep) then
      cache%n = n
      cache%valid = .true.
      if (allocated(cache%start)) then
        if (size(cache%start) < n + 1) deallocate (cache%start)
      end if
      if (.not. allocated(cache%start)) allocate (cache%start(n + 1))
      cache%start(1) = 1
    end if
    nc = 0
    sig2 = 0.0_wp
    nb = basis_size(basis, nd)
    np = packed_size(nb)
    nf = fields_of(nd, isotropic)
    ncg = 1 + np + nb*nf
    call gauss_rule(ng, xi, wxi)
    reach = kernel_reach(kernel, radius, radial)
    allocate (cells(3, max_reach_of(nd, ng, reach)), gidx(max_reach_of(nd, ng, reach)), &
              offs(3, max_reach_of(nd, ng, reach)), wq(max_reach_of(nd, ng, reach)), &
              gax(max_reach_of(nd, ng, reach)))
    do p = 1, n
      s = 0.0_wp
      do d = 1, nd
        s(d) = (x(d, p) - origin(d))/h(d)
      end do
      if (nf == 1) then
        sig(1) = stress(1, p)
        if (two) sig2(1) = stress2(1, p)
      else
        do f = 1, nf
          sig(f) = stress(stress_voigt_index(nd, f), p)
          if (two) sig2(f) = stress2(stress_voigt_index(nd, f), p)
        end do
      end if
      ! Point count of the cell that holds the point (the occupancy of gauss_occupancy).
      cp = 0
      do d = 1, nd
        cp(d) = min(max(floor(s(d)), 0), ncells(d) - 1)
      end do
      if (.not. widen) acc(1, cp(1), cp(2), cp(3)) = acc(1, cp(1), cp(2), cp(3)) + 1.0_wp
      ! MLS sums at the Gauss points.
      call points_in_reach(nd, s, ncells, ng, xi, kernel, radius, radial, reach, nq, cells, gidx, &
                           offs, wq, gax)
      if (keep) then
        if (cache%valid) call keep_reach(cache, p, nc, nq, cells, gax, wq)
      end if
      do q = 1, nq
        i = cells(1, q); j = cells(2, q); k = cells(3, q)
        if (widen) then
          if (only(gidx(q), i, j, k) /= level) cycle
        end if
        w = vol(p)*wq(q)
        base = 1 + (gidx(q) - 1)*ncg
        base2 = (gidx(q) - 1)*nb*nf
        acc(base + 1, i, j, k) = acc(base + 1, i, j, k) + 1.0_wp
        if (nb == 1) then
          ! Constant basis (p = 1): the moment is the weight sum, the field sums w sigma
          ! (with the field counts of 2D and 3D known, so that the sums unroll).
          acc(base + 2, i, j, k) = acc(base + 2, i, j, k) + w
          select case (nf)
          case (6)
            acc(base + 3:base + 8, i, j, k) = acc(base + 3:base + 8, i, j, k) + w*sig
            if (two) acc2(base2 + 1:base2 + 6, i, j, k) = acc2(base2 + 1:base2 + 6, i, j, k) + w*sig2
          case (3)
            acc(base + 3:base + 5, i, j, k) = acc(base + 3:base + 5, i, j, k) + w*sig(1:3)
            if (two) acc2(base2 + 1:base2 + 3, i, j, k) = acc2(base2 + 1:base2 + 3, i, j, k) + w*sig2(1:3)
          case default
            acc(base + 3:base + 2 + nf, i, j, k) = acc(base + 3:base + 2 + nf, i, j, k) + w*sig(1:nf)
            if (two) acc2(base2 + 1:base2 + nf, i, j, k) = acc2(base2 + 1:base2 + nf, i, j, k) + w*sig2(1:nf)
          end select
          cycle
        end if
        dneg = -offs(:, q)
        call basis_eval(basis, nd, dneg(1:nd), pv(1:nb))
        call moment_add(nb, pv(1:nb), w, acc(base + 2:base + 1 + np, i, j, k))
        do f = 1, nf
          acc(base + 2 + np + (f - 1)*nb:base + 1 + np + f*nb, i, j, k) = &
            acc(base + 2 + np + (f - 1)*nb:base + 1 + np + f*nb, i, j, k) + w*sig(f)*pv(1:nb)
        end do
        if (.not. two) cycle
        do f = 1, nf
          acc2(base2 + 1 + (f - 1)*nb:base2 + f*nb, i, j, k) = &
            acc2(base2 + 1 + (f - 1)*nb:base2 + f*nb, i, j, k) + w*sig2(f)*pv(1:nb)
        end do
      end do
    end do
  end subroutine gauss_accumulate

  !> Append the nq Gauss points within reach of point p to the cache (nc entries so
  !> far); the cache becomes invalid when it would pass its memory budget.
  subroutine keep_reach(cache, p, nc, nq, cells, gax, wq)
    type(reach_cache_t), intent(inout) :: cache
    integer, intent(in) :: p, nq, cells(:, :), gax(:)
    integer, intent(inout) :: nc
    real(wp), intent(in) :: wq(:)
    integer :: cap, q
    integer, allocatable :: ti(:, :)
    real(wp), allocatable :: tw(:)
    cap = 0
    if (allocated(cache%w)) cap = size(cache%w)
    if (nc + nq > cap) then
      if (int(nc + nq, 8)*reach_entry_bytes > reach_cache_budget) then
        cache%valid = .false.
        return
      end if
      cap = int(min(max(2_8*int(cap, 8), int(nc + nq, 8), 1024_8), reach_cache_cap))
      allocate (ti(4, cap), tw(cap))
      if (nc > 0) then
        ti(:, 1:nc) = cache%idx(:, 1:nc)
        tw(1:nc) = cache%w(1:nc)
      end if
      call move_alloc(ti, cache%idx)
      call move_alloc(tw, cache%w)
    end if
    do q = 1, nq
      cache%idx(1:3, nc + q) = cells(:, q)
      cache%idx(4, nc + q) = gax(q)
      cache%w(nc + q) = wq(q)
    end do
    nc = nc + nq
    cache%start(p + 1) = nc + 1
  end subroutine keep_reach

  !> Entries of a valid cache (0 otherwise), for the memory report.
  pure integer function reach_cache_entries(cache) result(m)
    type(reach_cache_t), intent(in) :: cache
    m = 0
    if (cache%valid .and. allocated(cache%start)) m = cache%start(cache%n + 1) - 1
  end function reach_cache_entries

  !> Bytes held by a cache.
  pure integer(kind=8) function reach_cache_bytes(cache) result(b)
    type(reach_cache_t), intent(in) :: cache
    b = 0
    if (allocated(cache%w)) b = int(size(cache%w), 8)*reach_entry_bytes
    if (allocated(cache%start)) b = b + int(size(cache%start), 8)*4
  end function reach_cache_bytes

  !> One pass of the occupancy closing on the owned cells clo..chi: dst(1, c) is the
  !> largest (grow) or smallest (shrink) src(1, .) over the cells within r of c
  !> along each of the nd axes that lie in the grid (0..ncells-1), so that the
  !> grid faces neither add nor remove occupied cells. src needs its ghost cells.
  pure subroutine occupancy_pass(nd, r, grow, lo, clo, chi, ncells, src, dst)
    integer, intent(in) :: nd, r, lo(3), clo(3), chi(3), ncells(3)
    logical, intent(in) :: grow
    real(wp), intent(in) :: src(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: dst(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k, d, wlo(3), whi(3), c(3)
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        do i = clo(1), chi(1)
          c = [i, j, k]
          wlo = c
          whi = c
          do d = 1, nd
            wlo(d) = max(c(d) - r, 0)
            whi(d) = min(c(d) + r, ncells(d) - 1)
          end do
          if (grow) then
            dst(1, i, j, k) = maxval(src(1, wlo(1):whi(1), wlo(2):whi(2), wlo(3):whi(3)))
          else
            dst(1, i, j, k) = minval(src(1, wlo(1):whi(1), wlo(2):whi(2), wlo(3):whi(3)))
          end if
        end do
      end do
    end do
  end subroutine occupancy_pass

  !> Solve the Gauss-point reconstructions of the owned cells. sol per cell:
  !> occupied flag (1 or 0), then per Gauss point gamma(nb) and the fields (nf). With
  !> acc2, the field sums of a second field of the same points (gauss_accumulate), its
  !> solution in sol2 (the same layout) from the same gamma.
  subroutine gauss_solve(nd, ng, basis, lo, clo, chi, acc, sol, stats, isotropic, acc2, sol2)
    integer, intent(in) :: nd, ng, basis, lo(3), clo(3), chi(3)
    real(wp), intent(in) :: acc(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: sol(:, lo(1):, lo(2):, lo(3):)
    type(mls_stats_t), intent(inout) :: stats
    !> One isotropic field (gauss_accumulate).
    logical, intent(in), optional :: isotropic
    real(wp), intent(in), optional :: acc2(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout), optional :: sol2(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k, g, nb, np, nf, ncg, ngp, f, level, ba, bs, b2
    real(wp) :: gam(10)
    logical :: two
    two = present(acc2) .and. present(sol2)
    nb = basis_size(basis, nd)
    np = packed_size(nb)
    nf = fields_of(nd, isotropic)
    ncg = 1 + np + nb*nf
    ngp = ng**nd
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        do i = clo(1), chi(1)
          sol(:, i, j, k) = 0.0_wp
          if (two) sol2(:, i, j, k) = 0.0_wp
          if (acc(1, i, j, k) < 0.5_wp) cycle
          sol(1, i, j, k) = 1.0_wp
          do g = 1, ngp
            ba = 1 + (g - 1)*ncg
            bs = 1 + (g - 1)*(nb + nf)
            call mls_gamma(basis, nd, acc(ba + 2:ba + 1 + np, i, j, k), acc(ba + 1, i, j, k), &
                           gam(1:nb), level, stats)
            sol(bs + 1:bs + nb, i, j, k) = gam(1:nb)
            do f = 1, nf
              sol(bs + nb + f, i, j, k) = dot_product(gam(1:nb), &
                acc(ba + 2 + np + (f - 1)*nb:ba + 1 + np + f*nb, i, j, k))
            end do
            if (.not. two) cycle
            b2 = (g - 1)*nb*nf
            sol2(bs + 1:bs + nb, i, j, k) = gam(1:nb)
            do f = 1, nf
              sol2(bs + nb + f, i, j, k) = dot_product(gam(1:nb), acc2(b2 + 1 + (f - 1)*nb:b2 + f*nb, i, j, k))
            end do
          end do
          if (two) sol2(1, i, j, k) = 1.0_wp
        end do
      end do
    end do
  end subroutine gauss_solve

  !> Grid-function gradients (per metre) at the Gauss points of a cell, the same
  !> for every cell: for Gauss point g and stencil node m, the node's offset from
  !> the cell's lower corner (off) and grad Psi (gr). Returns the nodes per point.
  subroutine gauss_psi_table(nd, ng, kernel, h, nn, off, gr, psi)
    integer, intent(in) :: nd, ng, kernel
    real(wp), intent(in) :: h(3)
    integer, intent(out) :: nn
    integer, allocatable, intent(out) :: off(:, :, :)
    real(wp), allocatable, intent(out) :: gr(:, :, :)
    !> Psi_I(x_g) of the same nodes (psi(m, g)).
    real(wp), allocatable, intent(out), optional :: psi(:, :)
    integer :: g, m, i0(3), nw(3)
    integer, allocatable :: qoff(:, :)
    real(wp) :: yg(3, max_gauss_cell), wg(max_gauss_cell), sw(max_stencil, 3), sdw(max_stencil, 3)
    real(wp), allocatable :: w(:)
    nw = 1
    nw(1:nd) = kernel_width(kernel)
    call stencil_offsets(nw, nn, qoff)
    allocate (off(3, nn, ng**nd), gr(3, nn, ng**nd), w(nn))
    call gauss_points_of_cell(nd, ng, yg, wg)
    do g = 1, ng**nd
      call psi_stencil(nd, kernel, yg(:, g), h, i0, sw, sdw)
      call tensor_weights(nw, sw, sdw, w, gr(:, :, g))
      if (present(psi)) then
        if (.not. allocated(psi)) allocate (psi(nn, ng**nd))
        psi(:, g) = w
      end if
      do m = 1, nn
        off(:, m, g) = i0 + qoff(:, m)
      end do
    end do
  end subroutine gauss_psi_table

  !> Internal forces of the owned occupied cells' Gauss points added to node
  !> (components 2+nd:1+2nd): f_I -= w_g sigma_h(x_g) grad Psi_I(x_g). With qvol, the
  !> quadrature volume of the nodes, sum_g w_g Psi_I(x_g), is added to qvol(1, I).
  !> With isotropic, sol holds one field s and the stress is s I.
  subroutine gauss_forces(nd, ng, basis, kernel, h, lo, clo, chi, sol, node, qvol, isotropic)
    integer, intent(in) :: nd, ng, basis, kernel, lo(3), clo(3), chi(3)
    real(wp), intent(in) :: h(3)
    real(wp), intent(in) :: sol(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout), optional :: qvol(:, lo(1):, lo(2):, lo(3):)
    logical, intent(in), optional :: isotropic
    integer :: i, j, k, g, nb, nf, bs, m, nn, f, idx(3)
    integer, allocatable :: off(:, :, :)
    real(wp), allocatable :: gr(:, :, :), psi(:, :)
    real(wp) :: yg(3, max_gauss_cell), wg(max_gauss_cell), vv(6), s(3, 3), fs(3), wq, sv
    logical :: iso
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    nb = basis_size(basis, nd)
    nf = fields_of(nd, isotropic)
    call gauss_points_of_cell(nd, ng, yg, wg)
    call gauss_psi_table(nd, ng, kernel, h, nn, off, gr, psi)
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        do i = clo(1), chi(1)
          if (sol(1, i, j, k) < 0.5_wp) cycle
          do g = 1, ng**nd
            bs = 1 + (g - 1)*(nb + nf)
            wq = wg(g)*product(h(1:nd))
            iso = nf == 1 .and. nd > 1
            if (iso) then
              sv = sol(bs + nb + 1, i, j, k)
            else
              vv = 0.0_wp
              do f = 1, nf
                vv(stress_voigt_index(nd, f)) = sol(bs + nb + f, i, j, k)
              end do
              s = voigt_to_tensor(vv)
            end if
            do m = 1, nn
              idx = [i, j, k] + off(:, m, g)
              if (iso) then
                ! s I . grad Psi = s grad Psi
                fs = -wq*(sv*gr(:, m, g))
              else
                fs = -wq*matmul(s, gr(:, m, g))
              end if
              node(sl%force_lo:sl%force_hi, idx(1), idx(2), idx(3)) = &
                node(sl%force_lo:sl%force_hi, idx(1), idx(2), idx(3)) + fs(1:nd)
              if (present(qvol)) qvol(1, idx(1), idx(2), idx(3)) = &
                qvol(1, idx(1), idx(2), idx(3)) + wq*psi(m, g)
            end do
          end do
        end do
      end do
    end do
  end subroutine gauss_forces

  !> The Gauss-point integral of a density (the first field of sol, one value per
  !> Gauss point) against the grid functions, gm(1, I) += sum_g w_g rho_g Psi_I(x_g):
  !> the nodal masses of the quadrature that integrates the forces (gauss_forces), whose
  !> gravity the forces of a stress at rest balance.
  subroutine gauss_masses(nd, ng, basis, kernel, h, lo, clo, chi, sol, gm, isotropic)
    integer, intent(in) :: nd, ng, basis, kernel, lo(3), clo(3), chi(3)
    real(wp), intent(in) :: h(3)
    real(wp), intent(in) :: sol(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: gm(:, lo(1):, lo(2):, lo(3):)
    logical, intent(in), optional :: isotropic
    integer :: i, j, k, g, nb, nf, bs, m, nn, idx(3)
    integer, allocatable :: off(:, :, :)
    real(wp), allocatable :: gr(:, :, :), psi(:, :)
    real(wp) :: yg(3, max_gauss_cell), wg(max_gauss_cell), wq, sv
    nb = basis_size(basis, nd)
    nf = fields_of(nd, isotropic)
    call gauss_points_of_cell(nd, ng, yg, wg)
    call gauss_psi_table(nd, ng, kernel, h, nn, off, gr, psi)
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        do i = clo(1), chi(1)
          if (sol(1, i, j, k) < 0.5_wp) cycle
          do g = 1, ng**nd
            bs = 1 + (g - 1)*(nb + nf)
            wq = wg(g)*product(h(1:nd))
            sv = sol(bs + nb + 1, i, j, k)
            do m = 1, nn
              idx = [i, j, k] + off(:, m, g)
              gm(1, idx(1), idx(2), idx(3)) = gm(1, idx(1), idx(2), idx(3)) + wq*sv*psi(m, g)
            end do
          end do
        end do
      end do
    end do
  end subroutine gauss_masses

  !> Clear the internal forces (node components 2+nd:1+2nd) of the nodes olo..ohi that
  !> are thin for their point set: nvol(1, I) = sum_p V_p Psi_I(x_p) below thin_fraction
  !> times nvol(2, I) = sum_g w_g Psi_I(x_g). The Gauss points of a cell reach nodes
  !> that its points reach only with the tip of their grid functions (a point that has
  !> just entered a cell at its corner gives a node two cells on a sliver of its mass,
  !> while the cell's Gauss points give that node the force of a whole cell); such a
  !> node moves with the momentum of its points and with gravity and drag, but takes
  !> no internal force, which would give it a velocity of the order of force times
  !> step over a sliver of mass. nthin counts the nodes.
  pure subroutine thin_node_forces(nd, lo, olo, ohi, nvol, node, nthin)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: nvol(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    integer(kind=8), intent(inout) :: nthin
    integer :: i, j, k
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        do i = olo(1), ohi(1)
          if (nvol(1, i, j, k) >= thin_fraction*nvol(2, i, j, k)) cycle
          if (node(1, i, j, k) <= 0.0_wp) cycle
          node(sl%force_lo:sl%force_hi, i, j, k) = 0.0_wp
          nthin = nthin + 1
        end do
      end do
    end do
  end subroutine thin_node_forces

  !> Velocity gradients L_g = sum_I v_I (x) grad Psi_I(x_g) at the Gauss points of
  !> the owned occupied cells, from the nodal velocities nvel(nd+1:2nd).
  !> lg per cell: nd*nd components (column-major) per Gauss point.
  subroutine gauss_velocity_gradient(nd, ng, kernel, h, lo, clo, chi, sol, nvel, lg)
    integer, intent(in) :: nd, ng, kernel, lo(3), clo(3), chi(3)
    real(wp), intent(in) :: h(3)
    real(wp), intent(in) :: sol(:, lo(1):, lo(2):, lo(3):), nvel(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: lg(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k, g, m, nn, d, bl, idx(3)
    integer, allocatable :: off(:, :, :)
    real(wp), allocatable :: gr(:, :, :)
    real(wp) :: l(3, 3), v(3)
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    call gauss_psi_table(nd, ng, kernel, h, nn, off, gr)
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        do i = clo(1), chi(1)
          lg(:, i, j, k) = 0.0_wp
          if (sol(1, i, j, k) < 0.5_wp) cycle
          do g = 1, ng**nd
            l = 0.0_wp
            ! (the sums of 2D and 3D with their sizes known, so that they unroll)
            select case (nd)
            case (3)
              do m = 1, nn
                idx = [i, j, k] + off(:, m, g)
                v = nvel(4:6, idx(1), idx(2), idx(3))
                do d = 1, 3
                  l(1:3, d) = l(1:3, d) + v*gr(d, m, g)
                end do
              end do
            case (2)
              do m = 1, nn
                idx = [i, j, k] + off(:, m, g)
                v(1:2) = nvel(3:4, idx(1), idx(2), idx(3))
                do d = 1, 2
                  l(1:2, d) = l(1:2, d) + v(1:2)*gr(d, m, g)
                end do
              end do
            case default
              do m = 1, nn
                idx = [i, j, k] + off(:, m, g)
                do d = 1, nd
                  l(1:nd, d) = l(1:nd, d) + nvel(sl%new_lo:sl%new_hi, idx(1), idx(2), idx(3))*gr(d, m, g)
                end do
              end do
            end select
            bl = (g - 1)*nd*nd
            ! (column by column: reshape of a run-time shape is a library call per point)
            do d = 1, nd
              lg(bl + (d - 1)*nd + 1:bl + d*nd, i, j, k) = l(1:nd, d)
            end do
          end do
        end do
      end do
    end do
  end subroutine gauss_velocity_gradient

  !> Point velocity gradients by the transpose of the force operator:
  !> L_p = sum_g C_gp L_g / sum_g C_gp, C_gp = w_g V_p W_gp gamma_g . p_gp, with the
  !> positions and volumes of the force evaluation (x, vol), into vgrad (9, n) or, with
  !> div instead, only their traces (the divergences; fluid points). Points whose
  !> effective volume sum_g C_gp is not positive keep their values; nkept counts them.
  subroutine gauss_strain(nd, n, x, vol, origin, h, ncells, ng, kernel, radius, radial, basis, &
                          lo, sol, lg, vt, nkept, vgrad, div, lg2, div2, cache, isotropic)
    integer, intent(in) :: nd, n, ncells(3), ng, kernel, basis, lo(3)
    real(wp), intent(in) :: x(:, :), vol(:), origin(3), h(3), radius
    logical, intent(in) :: radial
    real(wp), intent(in) :: sol(:, lo(1):, lo(2):, lo(3):), lg(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: vt(:)
    integer, intent(out) :: nkept
    real(wp), intent(inout), optional :: vgrad(:, :), div(:)
    !> With div: a second Gauss-point gradient field, its divergences into div2 in the
    !> same pass.
    real(wp), intent(in), optional :: lg2(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout), optional :: div2(:)
    !> The reach kept by gauss_accumulate at the same positions (used when valid).
    type(reach_cache_t), intent(in), optional :: cache
    !> sol holds one isotropic field (gauss_accumulate).
    logical, intent(in), optional :: isotropic
    integer :: p, i, j, k, q, nq, nb, nf, bs, bl, d, q0, g, ga(3), c(3), iw, ngp, lv
    integer, allocatable :: cells(:, :), gidx(:), gax(:)
    real(wp), allocatable :: offs(:, :), wq(:)
    real(wp) :: s(3), dneg(3), pv(10), reach, xi(ng), wxi(ng), yg(3, max_gauss_cell), &
                wg(max_gauss_cell), cgp, ctot, l(9), l2(9), lm(3, 3), wcell, wgt, rw(2)
    logical :: full, two, kept, wide(2)
    full = present(vgrad)
    two = present(div) .and. present(lg2) .and. present(div2) .and. .not. full
    kept = .false.
    if (present(cache)) kept = cache%valid .and. cache%n == n
    nb = basis_size(basis, nd)
    nf = fields_of(nd, isotropic)
    call gauss_rule(ng, xi, wxi)
    call gauss_points_of_cell(nd, ng, yg, wg)
    reach = kernel_reach(kernel, radius, radial)
    allocate (cells(3, max_reach_of(nd, ng, reach)), gidx(max_reach_of(nd, ng, reach)), &
              offs(3, max_reach_of(nd, ng, reach)), wq(max_reach_of(nd, ng, reach)), &
              gax(max_reach_of(nd, ng, reach)))
    wcell = product(h(1:nd))
    nkept = 0
    ! Widened Gauss points (gauss_accumulate's only): which of the two radii occur here.
    ngp = ng**nd
    iw = 1 + ngp*(nb + nf)
    rw = widened_radii(radius)
    wide = .false.
    if (size(sol, 1) >= iw + ngp) then
      wide(1) = any(sol(iw + 1:iw + ngp, :, :, :) == rw(1))
      wide(2) = any(sol(iw + 1:iw + ngp, :, :, :) == rw(2))
    end if
    if (any(wide)) then
      deallocate (cells, gidx, offs, wq, gax)
      reach = max(reach, kernel_reach(kernel, rw(2), radial))
      allocate (cells(3, max_reach_of(nd, ng, reach)), gidx(max_reach_of(nd, ng, reach)), &
                offs(3, max_reach_of(nd, ng, reach)), wq(max_reach_of(nd, ng, reach)), &
                gax(max_reach_of(nd, ng, reach)))
      reach = kernel_reach(kernel, radius, radial)
    end if
    do p = 1, n
      s = 0.0_wp
      do d = 1, nd
        s(d) = (x(d, p) - origin(d))/h(d)
      end do
      if (kept) then
        ! The reach of gauss_accumulate, read in the loop below.
        q0 = cache%start(p) - 1
        nq = cache%start(p + 1) - 1 - q0
      else
        call points_in_reach(nd, s, ncells, ng, xi, kernel, radius, radial, reach, nq, cells, gidx, &
                             offs, wq, gax)
      end if
      ctot = 0.0_wp
      l = 0.0_wp
      l2 = 0.0_wp
      do q = 1, nq
        if (kept) then
          c = cache%idx(1:3, q0 + q)
          ga(1) = iand(cache%idx(4, q0 + q), 7)
          ga(2) = iand(ishft(cache%idx(4, q0 + q), -3), 7)
          ga(3) = ishft(cache%idx(4, q0 + q), -6)
          g = 1 + ga(1) + ng*(ga(2) + ng*ga(3))
          wgt = cache%w(q0 + q)
        else
          c = cells(:, q)
          g = gidx(q)
          wgt = wq(q)
        end if
        i = c(1); j = c(2); k = c(3)
        if (sol(1, i, j, k) < 0.5_wp) cycle
        bs = 1 + (g - 1)*(nb + nf)
        if (nb == 1) then
          cgp = wg(g)*wcell*vol(p)*wgt*sol(bs + 1, i, j, k)
        else
          if (kept) then
            dneg = 0.0_wp
            do d = 1, nd
              dneg(d) = -(real(c(d), wp) + xi(ga(d) + 1) - s(d))
            end do
          else
            dneg = -offs(:, q)
          end if
          call basis_eval(basis, nd, dneg(1:nd), pv(1:nb))
          cgp = wg(g)*wcell*vol(p)*wgt*dot_product(sol(bs + 1:bs + nb, i, j, k), pv(1:nb))
        end if
        bl = (g - 1)*nd*nd
        ctot = ctot + cgp
        ! (the sums of 2D and 3D with their sizes known, so that they unroll; for the
        ! divergences only the diagonal, components 1, 5, 9 in 3D and 1, 4 in 2D)
        select case (nd + merge(0, 3, full))
        case (3)
          l = l + cgp*lg(bl + 1:bl + 9, i, j, k)
        case (2)
          l(1:4) = l(1:4) + cgp*lg(bl + 1:bl + 4, i, j, k)
        case (6)
          l(1:9:4) = l(1:9:4) + cgp*lg(bl + 1:bl + 9:4, i, j, k)
          if (two) l2(1:9:4) = l2(1:9:4) + cgp*lg2(bl + 1:bl + 9:4, i, j, k)
        case (5)
          l(1:4:3) = l(1:4:3) + cgp*lg(bl + 1:bl + 4:3, i, j, k)
          if (two) l2(1:4:3) = l2(1:4:3) + cgp*lg2(bl + 1:bl + 4:3, i, j, k)
        case default
          l(1) = l(1) + cgp*lg(bl + 1, i, j, k)
          if (two) l2(1) = l2(1) + cgp*lg2(bl + 1, i, j, k)
        end select
      end do
      ! The widened Gauss points within their wider reach of the point.
      do lv = 1, 2
        if (.not. wide(lv)) cycle
        call points_in_reach(nd, s, ncells, ng, xi, kernel, rw(lv), radial, &
                             kernel_reach(kernel, rw(lv), radial), nq, cells, gidx, offs, wq, gax)
        do q = 1, nq
          i = cells(1, q); j = cells(2, q); k = cells(3, q)
          g = gidx(q)
          if (sol(1, i, j, k) < 0.5_wp .or. sol(iw + g, i, j, k) /= rw(lv)) cycle
          bs = 1 + (g - 1)*(nb + nf)
          if (nb == 1) then
            cgp = wg(g)*wcell*vol(p)*wq(q)*sol(bs + 1, i, j, k)
          else
            dneg = -offs(:, q)
            call basis_eval(basis, nd, dneg(1:nd), pv(1:nb))
            cgp = wg(g)*wcell*vol(p)*wq(q)*dot_product(sol(bs + 1:bs + nb, i, j, k), pv(1:nb))
          end if
          bl = (g - 1)*nd*nd
          ctot = ctot + cgp
          if (full) then
            l(1:nd*nd) = l(1:nd*nd) + cgp*lg(bl + 1:bl + nd*nd, i, j, k)
          else
            do d = 1, nd
              l((d - 1)*nd + d) = l((d - 1)*nd + d) + cgp*lg(bl + (d - 1)*nd + d, i, j, k)
              if (two) l2((d - 1)*nd + d) = l2((d - 1)*nd + d) + cgp*lg2(bl + (d - 1)*nd + d, i, j, k)
            end do
          end if
        end do
      end do
      vt(p) = ctot
      if (ctot <= 0.0_wp) then
        nkept = nkept + 1
        cycle
      end if
      lm = 0.0_wp
      do d = 1, nd
        lm(1:nd, d) = l((d - 1)*nd + 1:d*nd)/ctot
      end do
      if (full) then
        vgrad(1:3, p) = lm(:, 1); vgrad(4:6, p) = lm(:, 2); vgrad(7:9, p) = lm(:, 3)
      else if (present(div)) then
        div(p) = lm(1, 1) + lm(2, 2) + lm(3, 3)
      end if
      if (.not. two) cycle
      do d = 1, nd
        lm(1:nd, d) = l2((d - 1)*nd + 1:d*nd)/ctot
      end do
      div2(p) = lm(1, 1) + lm(2, 2) + lm(3, 3)
    end do
  end subroutine gauss_strain

end module dpmpm_gauss_fields
