!> Filling &region boxes (and 2D polygons) with material points.
!> Each rank fills only its own cells, and every choice (position, id) depends
!> only on the global cell, the point's slot in it and the seed, so the points
!> are the same whatever the number of ranks.
module dpmpm_generate
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, region_cfg_t
  use dpmpm_grid, only: grid_t
  use dpmpm_decomp, only: decomp_t
  use dpmpm_particles, only: particle_set_t
  use dpmpm_materials, only: material_t
  implicit none
  private
  public :: generate_points, hash_uniform, point_in_polygon

contains

  !> Append the points of every region that fall in this rank's cells to ps.
  subroutine generate_points(cfg, grid, dec, mats, ps)
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: grid
    type(decomp_t), intent(in) :: dec
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(inout) :: ps
    integer :: r, d, nd, npc, k, slot(3), c(3), clo(3), chi(3), imat, c1, c2, c3
    integer(i8) :: base, ncell_total, lin
    real(wp) :: x(3), u, vol, rho
    type(region_cfg_t) :: reg
    nd = grid%ndim
    ncell_total = product(int(grid%ncells, i8))
    base = 0
    do r = 1, size(cfg%regions)
      reg = cfg%regions(r)
      npc = reg%ppc**nd
      imat = findloc(mats%id, reg%material, dim=1)
      rho = mats(imat)%density
      vol = grid%cell_volume/real(npc, wp)
      ! Cells of the region's bounding box that this rank owns.
      clo = 0; chi = 0
      do d = 1, nd
        clo(d) = max(dec%clo(d), floor((region_lo(reg, d) - grid%origin(d))/grid%h(d)))
        chi(d) = min(dec%chi(d), ceiling((region_hi(reg, d) - grid%origin(d))/grid%h(d)) - 1)
      end do
      do c3 = clo(3), chi(3)
        do c2 = clo(2), chi(2)
          do c1 = clo(1), chi(1)
            c = [c1, c2, c3]
            lin = int(c(1), i8) + int(grid%ncells(1), i8)*(int(c(2), i8) + &
                  int(grid%ncells(2), i8)*int(c(3), i8))
            do k = 0, npc - 1
              slot = 0
              slot(1) = mod(k, reg%ppc)
              if (nd >= 2) slot(2) = mod(k/reg%ppc, reg%ppc)
              if (nd >= 3) slot(3) = k/(reg%ppc*reg%ppc)
              x = 0.0_wp
              do d = 1, nd
                if (trim(reg%placement) == 'random') then
                  u = hash_uniform(reg%seed, lin, k, d)
                  x(d) = grid%origin(d) + grid%h(d)*(real(c(d), wp) + u)
                else
                  x(d) = grid%origin(d) + grid%h(d)*(real(c(d), wp) + &
                         (real(slot(d), wp) + 0.5_wp)/real(reg%ppc, wp))
                end if
              end do
              if (.not. in_region(reg, x, nd)) cycle
              call ps%append(base + lin*npc + k + 1, imat, x, reg%velocity, rho*vol, vol, &
                             reg%stress)
            end do
          end do
        end do
      end do
      base = base + ncell_total*npc
    end do
  end subroutine generate_points

  pure real(wp) function region_lo(reg, d)
    type(region_cfg_t), intent(in) :: reg
    integer, intent(in) :: d
    if (trim(reg%shape) == 'polygon') then
      region_lo = minval(reg%poly(d, 1:reg%npoly))
    else
      region_lo = reg%lo(d)
    end if
  end function region_lo

  pure real(wp) function region_hi(reg, d)
    type(region_cfg_t), intent(in) :: reg
    integer, intent(in) :: d
    if (trim(reg%shape) == 'polygon') then
      region_hi = maxval(reg%poly(d, 1:reg%npoly))
    else
      region_hi = reg%hi(d)
    end if
  end function region_hi

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

  !> A uniform number in [0, 1) that depends only on (seed, cell, slot, axis):
  !> a 32-bit integer hash (xor-shift and multiply rounds) applied to each input in turn.
  pure real(wp) function hash_uniform(seed, cell, slot, axis) result(u)
    integer, intent(in) :: seed, slot, axis
    integer(i8), intent(in) :: cell
    integer(i8), parameter :: mask32 = 4294967295_i8
    integer(i8) :: h
    h = hash32(iand(int(seed, i8), mask32))
    h = hash32(ieor(h, iand(cell, mask32)))
    h = hash32(ieor(h, iand(ishft(cell, -32), mask32)))
    h = hash32(ieor(h, int(slot, i8)))
    h = hash32(ieor(h, int(axis, i8) + 1779033703_i8))
    u = real(h, wp)/4294967296.0_wp
  contains
    !> One avalanche round on a 32-bit value held in 64 bits.
    pure integer(i8) function hash32(x0) result(x)
      integer(i8), intent(in) :: x0
      x = x0
      x = ieor(x, ishft(x, -16))
      x = mul32(x, 2146121005_i8)
      x = ieor(x, ishft(x, -15))
      x = mul32(x, 2221713035_i8)
      x = ieor(x, ishft(x, -16))
    end function hash32
    !> (x*c) mod 2^32 without 64-bit overflow: multiply by the 16-bit halves of c.
    pure integer(i8) function mul32(x, c)
      integer(i8), intent(in) :: x, c
      mul32 = iand(x*iand(c, 65535_i8) + ishft(iand(x*ishft(c, -16), 65535_i8), 16), mask32)
    end function mul32
  end function hash_uniform

end module dpmpm_generate
