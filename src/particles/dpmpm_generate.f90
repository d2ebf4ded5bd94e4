!> Filling &region boxes (and 2D polygons) with material points.
!>
!> generate_points fills one point set: the solid set (points of solid regions and the
!> soil skeleton of saturated regions) or the fluid set (points of fluid regions and the
!> pore fluid of saturated regions). Each set on its own fills the region: a point's
!> volume is the mixture volume it stands for, and its mass the mass of its phase in that
!> volume.
!>
!> Placements:
!>  - regular: ppc points per cell and axis at the centres of a regular sub-grid;
!>  - random:  ppc**ndim points per cell, each scattered uniformly in its cell;
!>  - uniform: N points scattered uniformly over the whole region, not per cell, all of
!>    the same volume (see fill_uniform);
!>  - stirred: the regular points moved by an area-preserving map of the region's
!>    bounding box, as points after a large shear (see fill_stirred).
!> Every choice (position, id) depends only on the global cell or the point's number in
!> its region, its slot and the seed, so the points are the same whatever the number of
!> ranks; each rank keeps the points whose cell it owns.
module dpmpm_generate
  use dpmpm_kinds, only: wp, i8
  use dpmpm_error, only: fatal
  use dpmpm_config, only: config_t, region_cfg_t
  use dpmpm_hash, only: hash_uniform
  use dpmpm_grid, only: grid_t, cell_of
  use dpmpm_particles, only: particle_set_t
  use dpmpm_materials, only: material_t
  implicit none
  private
  public :: generate_points, point_in_polygon, in_region

  !> What one region puts into the set being filled.
  type :: fill_t
    integer :: mat = 0              !< material index (into mats) of the points
    real(wp) :: rho = 0.0_wp        !< mass of the phase per mixture volume (kg/m^3)
    real(wp) :: porosity = 0.0_wp   !< n_f stored on the points (when the set keeps it)
    real(wp) :: kinv = 0.0_wp       !< 1/k stored on fluid points (s/m)
    real(wp) :: bulk = 0.0_wp       !< bulk modulus K_f of fluid points (Pa), 0 for solid points
    integer :: seed = 1             !< seed of the random placements
    logical :: solid = .true.       !< solid points take the region's initial stress
  end type fill_t

contains

  !> Append to ps the points of every region that fall in the cells clo..chi (global,
  !> 0-based, per axis: the cells this rank owns; all cells on one rank).
  !> phase = 'solid' (default): points of solid regions (porosity 0, or dry soil of porosity
  !> n and mass (1 - n) rho_s V) and the skeleton of saturated regions (mass (1 - n) rho_s V,
  !> porosity n). phase = 'fluid': points of fluid
  !> regions (mass rho_f V, porosity 1, kinv 0) and the pore fluid of saturated regions
  !> (mass n rho_f V, porosity n, kinv = 1/conductivity of the soil, material = the fluid
  !> material), placed independently of the skeleton with seed fluid_seed (seed + 1 when
  !> fluid_seed = -1). Ids are unique within the set and do not depend on the ranks.
  !> counts(r), when present, is the number of points region r added on this rank.
  subroutine generate_points(cfg, grid, clo, chi, mats, ps, phase, counts)
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: clo(3), chi(3)
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(inout) :: ps
    character(len=*), intent(in), optional :: phase
    integer(i8), intent(out), optional :: counts(:)
    character(len=8) :: which
    integer :: r, n0
    integer(i8) :: base, ncell_total, npc
    type(region_cfg_t) :: reg
    type(fill_t) :: fill
    which = 'solid'
    if (present(phase)) which = phase
    if (which /= 'solid' .and. which /= 'fluid') &
      call fatal('unknown phase '''//trim(which)//''' (solid or fluid)', 'generate_points')
    ncell_total = product(int(grid%ncells, i8))
    base = 0
    do r = 1, size(cfg%regions)
      reg = cfg%regions(r)
      npc = int(reg%ppc, i8)**grid%ndim
      n0 = ps%n
      if (region_fill(reg, mats, which, fill)) then
        if (trim(reg%placement) == 'uniform') then
          call fill_uniform(reg, grid, clo, chi, fill, base, ps)
        else if (trim(reg%placement) == 'stirred') then
          call fill_stirred(reg, grid, clo, chi, fill, base, ps)
        else
          call fill_cells(reg, grid, clo, chi, fill, base, ps)
        end if
      end if
      if (present(counts)) counts(r) = int(ps%n - n0, i8)
      ! Each region owns a range of ids wide enough for either placement, and the same
      ! range in both sets.
      base = base + max(ncell_total*npc, uniform_count(reg, grid))
    end do
  end subroutine generate_points

  !> Does the region put points into the set of this phase, and with what?
  logical function region_fill(reg, mats, which, fill) result(used)
    type(region_cfg_t), intent(in) :: reg
    type(material_t), intent(in) :: mats(:)
    character(len=*), intent(in) :: which
    type(fill_t), intent(out) :: fill
    character(len=*), parameter :: where = 'generate_points'
    integer :: imat, ifl
    real(wp) :: n
    imat = findloc(mats%id, reg%material, dim=1)
    if (imat == 0) call fatal('a region refers to an unknown material', where)
    select case (trim(reg%phase))
    case ('solid')
      used = which == 'solid'
      ! Dry soil (porosity > 0): density is that of the grains, as in saturated soil.
      fill = fill_t(mat=imat, rho=(1.0_wp - reg%porosity)*mats(imat)%density, &
                    porosity=reg%porosity, seed=reg%seed)
    case ('fluid')
      used = which == 'fluid'
      fill = fill_t(mat=imat, rho=mats(imat)%density, porosity=1.0_wp, seed=reg%seed, &
                    bulk=mats(imat)%bulk_fluid, solid=.false.)
    case ('saturated')
      used = .true.
      n = reg%porosity
      if (.not. (n > 0.0_wp .and. n < 1.0_wp)) &
        call fatal('a saturated region needs 0 < porosity < 1', where)
      if (which == 'solid') then
        fill = fill_t(mat=imat, rho=(1.0_wp - n)*mats(imat)%density, porosity=n, &
                      seed=reg%seed)
      else
        ifl = findloc(mats%id, reg%fluid_material, dim=1)
        if (ifl == 0) call fatal('a saturated region refers to an unknown fluid material', where)
        if (.not. mats(imat)%conductivity > 0.0_wp) &
          call fatal('the soil of a saturated region needs a conductivity > 0', where)
        fill = fill_t(mat=ifl, rho=n*mats(ifl)%density, porosity=n, &
                      kinv=1.0_wp/mats(imat)%conductivity, bulk=mats(ifl)%bulk_fluid, &
                      seed=merge(reg%seed + 1, reg%fluid_seed, reg%fluid_seed == -1), &
                      solid=.false.)
      end if
    case default
      used = .false.
      call fatal('unknown region phase '''//trim(reg%phase)//'''', where)
    end select
  end function region_fill

  !> Regular or random placement: ppc**ndim points in every cell of the region's bounding
  !> box within olo..ohi (the owned cells), kept when inside the region; volume = cell
  !> volume / ppc**ndim. Ids: base + (global cell number)*ppc**ndim + slot + 1.
  subroutine fill_cells(reg, grid, olo, ohi, fill, base, ps)
    type(region_cfg_t), intent(in) :: reg
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: olo(3), ohi(3)
    type(fill_t), intent(in) :: fill
    integer(i8), intent(in) :: base
    type(particle_set_t), intent(inout) :: ps
    integer :: d, nd, npc, k, c(3), clo(3), chi(3), c1, c2, c3
    integer(i8) :: lin
    real(wp) :: x(3), u, vol
    logical :: random
    nd = grid%ndim
    npc = reg%ppc**nd
    vol = grid%cell_volume/real(npc, wp)
    random = trim(reg%placement) == 'random'
    ! Cells of the region's bounding box that this rank owns.
    clo = 0; chi = 0
    do d = 1, nd
      clo(d) = max(olo(d), floor((region_bound(reg, d, .false.) - grid%origin(d))/grid%h(d)))
      chi(d) = min(ohi(d), ceiling((region_bound(reg, d, .true.) - grid%origin(d))/grid%h(d)) - 1)
    end do
    do c3 = clo(3), chi(3)
      do c2 = clo(2), chi(2)
        do c1 = clo(1), chi(1)
          c = [c1, c2, c3]
          lin = cell_number(grid, c)
          do k = 0, npc - 1
            if (random) then
              x = 0.0_wp
              do d = 1, nd
                u = hash_uniform(fill%seed, lin, k, d)
                x(d) = grid%origin(d) + grid%h(d)*(real(c(d), wp) + u)
              end do
            else
              x = lattice_point(grid, reg%ppc, c, k)
            end if
            if (.not. in_region(reg, x, nd)) cycle
            call add_point(ps, base + lin*npc + k + 1, reg, fill, x, vol)
          end do
        end do
      end do
    end do
  end subroutine fill_cells

  !> The number of cell c (0-based indices) in the grid's x-fastest order.
  pure integer(i8) function cell_number(grid, c) result(lin)
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: c(3)
    lin = int(c(1), i8) + int(grid%ncells(1), i8)*(int(c(2), i8) + &
          int(grid%ncells(2), i8)*int(c(3), i8))
  end function cell_number

  !> Point k (0 .. ppc**ndim - 1) of the regular lattice of ppc points per cell edge in
  !> cell c: at the middles of the cell's ppc**ndim sub-cells, x fastest.
  pure function lattice_point(grid, ppc, c, k) result(x)
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: ppc, c(3), k
    real(wp) :: x(3)
    integer :: slot(3), d, nd
    nd = grid%ndim
    slot = 0
    slot(1) = mod(k, ppc)
    if (nd >= 2) slot(2) = mod(k/ppc, ppc)
    if (nd >= 3) slot(3) = k/(ppc*ppc)
    x = 0.0_wp
    do d = 1, nd
      x(d) = grid%origin(d) + grid%h(d)*(real(c(d), wp) + (real(slot(d), wp) + 0.5_wp)/real(ppc, wp))
    end do
  end function lattice_point

  !> Uniform placement: N points scattered uniformly over the region, not stratified per
  !> cell. Box: N = nint(region volume / cell volume * ppc**ndim) (at least 1), each of
  !> volume region volume / N, so the volumes add up to the region exactly. Polygon: N
  !> candidates over the bounding box (N from its area), the ones inside the polygon kept,
  !> each of volume cell volume / ppc**2. Point k (0..N-1) lies at
  !> lo + (hi - lo)*hash_uniform(seed, k, 0, d) along axis d: a function of seed and k only.
  !> Every rank draws all N positions and keeps those in its cells olo..ohi. Ids: base + k + 1.
  subroutine fill_uniform(reg, grid, olo, ohi, fill, base, ps)
    type(region_cfg_t), intent(in) :: reg
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: olo(3), ohi(3)
    type(fill_t), intent(in) :: fill
    integer(i8), intent(in) :: base
    type(particle_set_t), intent(inout) :: ps
    integer :: d, nd, c(3)
    integer(i8) :: k, n
    real(wp) :: lo(3), hi(3), x(3), vol
    logical :: polygon
    nd = grid%ndim
    polygon = trim(reg%shape) == 'polygon'
    lo = 0.0_wp; hi = 0.0_wp
    do d = 1, nd
      lo(d) = region_bound(reg, d, .false.)
      hi(d) = region_bound(reg, d, .true.)
    end do
    n = uniform_count(reg, grid)
    if (polygon) then
      vol = grid%cell_volume/real(reg%ppc, wp)**nd
    else
      vol = product(hi(1:nd) - lo(1:nd))/real(n, wp)
    end if
    do k = 0, n - 1
      x = 0.0_wp
      do d = 1, nd
        x(d) = lo(d) + (hi(d) - lo(d))*hash_uniform(fill%seed, k, 0, d)
        ! lo + (hi - lo) u with u < 1 may still round up to hi: keep the region half-open.
        if (x(d) >= hi(d)) x(d) = nearest(hi(d), -1.0_wp)
      end do
      if (polygon) then
        if (.not. point_in_polygon(x(1:2), reg%poly(:, 1:reg%npoly))) cycle
      end if
      call into_grid(grid, x, c)
      if (any(c < olo .or. c > ohi)) cycle
      call add_point(ps, base + k + 1, reg, fill, x, vol)
    end do
  end subroutine fill_uniform

  !> Stirred placement: the points of the regular placement within the region's bounding
  !> box B, moved by stir_rounds rounds of shears, then kept when inside the region and in
  !> the cells olo..ohi. B is taken as periodic (a torus), and each round shifts every axis
  !> a in turn by a sine of the next axis b (b = a + 1, cyclic):
  !>   x_a <- lo_a + mod(x_a - lo_a + A_b sin(2 pi m_b (x_b - lo_b) / L_b + phi), L_a),
  !> L the box's extent, m_b = max(1, nint(L_b / (10 h_b))) waves across it (about ten
  !> cells each), A_b = stir_shear L_b / (2 pi m_b) so that the largest shear strain of a
  !> stage is stir_shear, and phi = 2 pi hash_uniform(seed, round, 0, a). Each stage maps
  !> B onto itself one to one with a Jacobian of one, so the points keep the density of
  !> the lattice on average while rows bend, thin and crowd as after a large shear. In 1D
  !> there is nothing to stir (the input refuses it). Every rank maps all points of B and
  !> keeps those in its cells, so the set is the same on any number of ranks; ids as in
  !> fill_cells, of the point's lattice cell and slot.
  subroutine fill_stirred(reg, grid, olo, ohi, fill, base, ps)
    type(region_cfg_t), intent(in) :: reg
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: olo(3), ohi(3)
    type(fill_t), intent(in) :: fill
    integer(i8), intent(in) :: base
    type(particle_set_t), intent(inout) :: ps
    real(wp), parameter :: two_pi = 8.0_wp*atan(1.0_wp)
    integer :: d, nd, npc, k, c(3), cx(3), clo(3), chi(3), c1, c2, c3
    integer(i8) :: lin
    real(wp) :: x(3), lo(3), hi(3), vol
    nd = grid%ndim
    npc = reg%ppc**nd
    vol = grid%cell_volume/real(npc, wp)
    lo = 0.0_wp; hi = 0.0_wp
    clo = 0; chi = 0
    do d = 1, nd
      lo(d) = region_bound(reg, d, .false.)
      hi(d) = region_bound(reg, d, .true.)
      clo(d) = max(0, floor((lo(d) - grid%origin(d))/grid%h(d)))
      chi(d) = min(grid%ncells(d) - 1, ceiling((hi(d) - grid%origin(d))/grid%h(d)) - 1)
    end do
    do c3 = clo(3), chi(3)
      do c2 = clo(2), chi(2)
        do c1 = clo(1), chi(1)
          c = [c1, c2, c3]
          lin = cell_number(grid, c)
          do k = 0, npc - 1
            x = lattice_point(grid, reg%ppc, c, k)
            if (any(x(1:nd) < lo(1:nd)) .or. any(x(1:nd) >= hi(1:nd))) cycle
            call stir(x)
            if (.not. in_region(reg, x, nd)) cycle
            call into_grid(grid, x, cx)
            if (any(cx < olo .or. cx > ohi)) cycle
            call add_point(ps, base + lin*npc + k + 1, reg, fill, x, vol)
          end do
        end do
      end do
    end do
  contains
    !> The rounds of shears of one position inside B.
    subroutine stir(x)
      real(wp), intent(inout) :: x(3)
      integer :: j, a, b
      real(wp) :: ext(3), waves, amp, phi
      ext = hi - lo
      if (nd < 2) return
      do j = 1, reg%stir_rounds
        do a = 1, nd
          b = mod(a, nd) + 1
          waves = real(max(1, nint(ext(b)/(10.0_wp*grid%h(b)))), wp)
          amp = reg%stir_shear*ext(b)/(two_pi*waves)
          phi = two_pi*hash_uniform(fill%seed, int(j, i8), 0, a)
          x(a) = lo(a) + modulo(x(a) - lo(a) + amp*sin(two_pi*waves*(x(b) - lo(b))/ext(b) + phi), &
                                ext(a))
          ! lo + (a value below L) may still round up to hi: keep B half-open.
          if (x(a) >= hi(a)) x(a) = nearest(hi(a), -1.0_wp)
          if (x(a) < lo(a)) x(a) = lo(a)
        end do
      end do
    end subroutine stir
  end subroutine fill_stirred

  !> Number of points (box) or candidates (polygon) of a uniform placement, 0 otherwise.
  integer(i8) function uniform_count(reg, grid) result(n)
    type(region_cfg_t), intent(in) :: reg
    type(grid_t), intent(in) :: grid
    real(wp) :: v
    integer :: d
    n = 0
    if (trim(reg%placement) /= 'uniform') return
    v = 1.0_wp
    do d = 1, grid%ndim
      v = v*(region_bound(reg, d, .true.) - region_bound(reg, d, .false.))
    end do
    n = max(1_i8, nint(v/grid%cell_volume*real(reg%ppc, wp)**grid%ndim, i8))
  end function uniform_count

  !> The cell holding x, with the cell rule of point migration (floor((x - origin)/h)).
  !> A point on the upper face of the grid, or one the tolerance of the region check let
  !> past a face, is moved just inside so that exactly one rank owns it.
  subroutine into_grid(grid, x, c)
    type(grid_t), intent(in) :: grid
    real(wp), intent(inout) :: x(3)
    integer, intent(out) :: c(3)
    integer :: d
    c = cell_of(grid%origin, grid%h, x, grid%ndim)
    do d = 1, grid%ndim
      if (c(d) < 0) then
        x(d) = grid%origin(d)
      else
        do while (c(d) > grid%ncells(d) - 1)
          x(d) = nearest(min(x(d), grid%origin(d) + grid%h(d)*grid%ncells(d)), -1.0_wp)
          c = cell_of(grid%origin, grid%h, x, grid%ndim)
        end do
      end if
    end do
    c = cell_of(grid%origin, grid%h, x, grid%ndim)
  end subroutine into_grid

  !> Append one point of a region to the set.
  subroutine add_point(ps, id, reg, fill, x, vol)
    type(particle_set_t), intent(inout) :: ps
    integer(i8), intent(in) :: id
    type(region_cfg_t), intent(in) :: reg
    type(fill_t), intent(in) :: fill
    real(wp), intent(in) :: x(3), vol
    real(wp) :: stress(6), p, mass
    integer :: d
    ! The region's initial stress is that of the solid (the effective stress of a
    ! saturated skeleton), its pore pressure that of the fluid points, both linear in x.
    ! A fluid point at pore pressure p holds the mass n rho_f(p) V (fluid_density), so
    ! that the volume the solver derives from it is V.
    stress = 0.0_wp
    p = 0.0_wp
    mass = fill%rho*vol
    if (fill%solid) then
      stress = reg%stress
      do d = 1, 3
        stress = stress + reg%stress_gradient(:, d)*x(d)
      end do
    else
      p = reg%pore_pressure + dot_product(reg%pore_pressure_gradient, x)
      stress(1:3) = -p
      mass = mass*exp(p/fill%bulk)
    end if
    call ps%append(id, fill%mat, x, reg%velocity, mass, vol, stress, &
                   porosity=fill%porosity, pressure=p, kinv=fill%kinv)
  end subroutine add_point

  !> The lower (upper = .false.) or upper bound of region reg along axis d: of its
  !> vertices for a polygon, else its box.
  pure real(wp) function region_bound(reg, d, upper) result(b)
    type(region_cfg_t), intent(in) :: reg
    integer, intent(in) :: d
    logical, intent(in) :: upper
    if (trim(reg%shape) == 'polygon') then
      if (upper) then
        b = maxval(reg%poly(d, 1:reg%npoly))
      else
        b = minval(reg%poly(d, 1:reg%npoly))
      end if
    else if (upper) then
      b = reg%hi(d)
    else
      b = reg%lo(d)
    end if
  end function region_bound

  !> Does region reg hold position x (the first nd coordinates)? The test that keeps a
  !> generated point: a box holds lo <= x < hi, so that boxes meeting at a face share no point.
  pure logical function in_region(reg, x, nd)
    type(region_cfg_t), intent(in) :: reg
    real(wp), intent(in) :: x(3)
    integer, intent(in) :: nd
    if (trim(reg%shape) == 'polygon') then
      in_region = point_in_polygon(x(1:2), reg%poly(:, 1:reg%npoly))
    else
      in_region = all(x(1:nd) >= reg%lo(1:nd)) .and. all(x(1:nd) < reg%hi(1:nd))
    end if
  end function in_region

  !> Even-odd rule: does the ray from x towards +x cross the polygon's edges an odd number of times?
  pure logical function point_in_polygon(x, poly) result(inside)
    real(wp), intent(in) :: x(2), poly(:, :)
    integer :: i, j, n
    real(wp) :: xc
    n = size(poly, 2)
    inside = .false.
    j = n
    do i = 1, n
      if ((poly(2, i) > x(2)) .neqv. (poly(2, j) > x(2))) then
        xc = poly(1, i) + (x(2) - poly(2, i))*(poly(1, j) - poly(1, i))/(poly(2, j) - poly(2, i))
        if (x(1) < xc) inside = .not. inside
      end if
      j = i
    end do
  end function point_in_polygon

end module dpmpm_generate
