!> The pore-pressure update of the fluid points (doc/theory.md 4.6, the paper's eq. 10)
!> and what goes with it: the nodal porosity from the solid points' sums, the
!> skeleton's porosity from its volume change, the semi-implicit pressure update
!> from the new velocity divergences (with the mixture-flux term of dpmpm_transfer),
!> and the fluid volume and stress from the new pressure. Drained faces load the
!> nodes in dpmpm_face_loads. Signs: pore pressure positive in compression.
module dpmpm_pore_pressure
  use dpmpm_kinds, only: wp, i8
  use dpmpm_materials, only: material_t
  use dpmpm_cell_smoothing, only: cell_mean
  use dpmpm_grid, only: axis_cells_of
  implicit none
  private
  public :: nodal_porosity, skeleton_porosity, skeleton_kinv, point_cells, local_cell, smooth_pressure_change
  public :: pressure_update, fluid_density, fluid_state, &
            fluid_pressure_step

contains

  !> Nodal fields of the porous skeleton on the nodes olo..ohi: on entry the sums
  !> sum N m n, sum N m and sum N m / k over the porous solid points (solid_porosity_p2g);
  !> on return the nodal porosity n_I (1 where no porous solid reaches: free water), the
  !> porous mass, and the mass-weighted 1/k (0 there: no drag). Bodies that are not
  !> porous (porosity 0) take no part, so water beside them is free water.
  pure subroutine nodal_porosity(lo, olo, ohi, nporo)
    integer, intent(in) :: lo(3), olo(3), ohi(3)
    real(wp), intent(inout) :: nporo(:, lo(1):, lo(2):, lo(3):)
    integer :: i, j, k
    real(wp) :: ms
    do k = olo(3), ohi(3)
      do j = olo(2), ohi(2)
        do i = olo(1), ohi(1)
          ms = nporo(2, i, j, k)
          if (ms > 0.0_wp) then
            nporo(1, i, j, k) = nporo(1, i, j, k)/ms
            nporo(3, i, j, k) = nporo(3, i, j, k)/ms
          else
            nporo(1, i, j, k) = 1.0_wp
            nporo(3, i, j, k) = 0.0_wp
          end if
        end do
      end do
    end do
  end subroutine nodal_porosity

  !> Porosity of the porous skeleton points from their volume change with
  !> incompressible grains, n' = 1 - (1 - n) V / V' (volb the volumes before the stress
  !> update). Points of porosity 0 (bodies that are not porous) keep it.
  pure subroutine skeleton_porosity(n, volb, vol, poro)
    integer, intent(in) :: n
    real(wp), intent(in) :: volb(:), vol(:)
    real(wp), intent(inout) :: poro(:)
    where (poro(1:n) > 0.0_wp) poro(1:n) = 1.0_wp - (1.0_wp - poro(1:n))*volb/vol(1:n)
  end subroutine skeleton_porosity

  !> 1/k of each solid point (s/m): that of its material, 0 for a body that is not
  !> porous or a material without conductivity; with the Kozeny-Carman law k scales
  !> as n^3 / (1 - n)^2 against the initial porosity n0 = 1 - (1 - n) V / V0.
  pure subroutine skeleton_kinv(n, mats, mat, poro, vol, vol0, kinv)
    integer, intent(in) :: n
    type(material_t), intent(in) :: mats(:)
    integer, intent(in) :: mat(:)
    real(wp), intent(in) :: poro(:), vol(:), vol0(:)
    real(wp), intent(out) :: kinv(:)
    integer :: p
    real(wp) :: n0, np
    do p = 1, n
      kinv(p) = 0.0_wp
      associate (mt => mats(mat(p)))
        if (poro(p) <= 0.0_wp .or. .not. mt%conductivity > 0.0_wp) cycle
        kinv(p) = 1.0_wp/mt%conductivity
        if (mt%kozeny_carman) then
          np = min(max(poro(p), 1.0e-3_wp), 0.999_wp)
          n0 = min(max(1.0_wp - (1.0_wp - poro(p))*vol(p)/vol0(p), 1.0e-3_wp), 0.999_wp)
          kinv(p) = kinv(p)*(n0/np)**3*((1.0_wp - np)/(1.0_wp - n0))**2
        end if
      end associate
    end do
  end subroutine skeleton_kinv

  !> The pore pressure of the fluid points over one step (eq. 10) with the bulk
  !> modulus of each point's fluid; divf, divs the divergences of the fluid and solid
  !> velocities at the fluid points, gnrel the mixture-flux term (zero without it). With cell
  !> (point_cells), ncell and vol the change is smoothed over each cell
  !> (smooth_pressure_change). The pressure is then cut at pcav (cavitation: water does
  !> not carry a tension below it); ncut counts the points cut.
  subroutine fluid_pressure_step(n, dt, mats, mat, poro, divf, divs, gnrel, pcav, pres, ncut, &
                                 cell, ncell, vol)
    integer, intent(in) :: n
    real(wp), intent(in) :: dt, pcav
    integer(i8), intent(inout) :: ncut
    integer, intent(in), optional :: cell(:), ncell
    real(wp), intent(in), optional :: vol(:)
    type(material_t), intent(in) :: mats(:)
    integer, intent(in) :: mat(:)
    real(wp), intent(in) :: poro(:), divf(:), divs(:), gnrel(:)
    real(wp), intent(inout) :: pres(:)
    real(wp), allocatable :: kf(:), pold(:)
    integer :: m
    allocate (kf(n))
    do m = 1, n
      kf(m) = mats(mat(m))%bulk_fluid
    end do
    if (present(cell)) pold = pres(1:n)
    call pressure_update(n, dt, kf, poro, divf, divs, gnrel, pres)
    if (present(cell)) call smooth_pressure_change(n, ncell, cell, vol, pold, pres)
    ncut = ncut + count(pres(1:n) < pcav)
    pres(1:n) = max(pres(1:n), pcav)
  end subroutine fluid_pressure_step

  !> Local index (1-based, over this rank's cells clo..chi) of the cell holding each of
  !> the n points at x; points just outside the block count to its edge cell.
  pure subroutine point_cells(nd, n, x, origin, h, clo, chi, cell)
    integer, intent(in) :: nd, n
    real(wp), intent(in) :: x(:, :), origin(3), h(3)
    integer, intent(in) :: clo(3), chi(3)
    integer, intent(out) :: cell(:)
    integer :: p, d, stride
    integer, allocatable :: c(:)
    ! (axis by axis, the cells of one axis in a loop of dpmpm_grid that vectorises)
    allocate (c(n))
    cell(1:n) = 1
    stride = 1
    do d = 1, nd
      call axis_cells_of(origin, h, x, n, d, c)
      do p = 1, n
        cell(p) = cell(p) + stride*(min(max(c(p), clo(d)), chi(d)) - clo(d))
      end do
      stride = stride*(chi(d) - clo(d) + 1)
    end do
  end subroutine point_cells

  !> Cell of this rank's block clo..chi holding x, as offsets from clo (0 on the axes
  !> beyond nd); a point just outside the block counts to its edge cell.
  pure function local_cell(nd, x, origin, h, clo, chi) result(c)
    integer, intent(in) :: nd
    real(wp), intent(in) :: x(:), origin(3), h(3)
    integer, intent(in) :: clo(3), chi(3)
    integer :: c(3), d
    c = 0
    do d = 1, nd
      c(d) = min(max(floor((x(d) - origin(d))/h(d)), clo(d)), chi(d)) - clo(d)
    end do
  end function local_cell

  !> Strain smoothing of the pore pressure: the step's pressure change of each fluid
  !> point replaced by the volume-weighted mean change of the fluid points in its cell
  !> (cell from point_cells; pold the pressures before the step). A cell's points then
  !> move together, which removes the point-to-point scatter of the pressure without
  !> touching its cell means.
  pure subroutine smooth_pressure_change(n, ncell, cell, vol, pold, pres)
    integer, intent(in) :: n, ncell
    integer, intent(in) :: cell(:)
    real(wp), intent(in) :: vol(:), pold(:)
    real(wp), intent(inout) :: pres(:)
    real(wp), allocatable :: dp(:), mean(:)
    allocate (mean(n))
    dp = pres(1:n) - pold(1:n)
    call cell_mean(n, ncell, cell, vol, dp, mean)
    pres(1:n) = pold(1:n) + mean
  end subroutine smooth_pressure_change

  !> The volume each fluid point represents at its new pressure, V = m / (n rho_f(p)),
  !> and the stress -p I it exerts.
  subroutine fluid_state(n, mats, mat, mass, poro, pres, vol, stress)
    integer, intent(in) :: n
    type(material_t), intent(in) :: mats(:)
    integer, intent(in) :: mat(:)
    real(wp), intent(in) :: mass(:), poro(:), pres(:)
    real(wp), intent(inout) :: vol(:), stress(:, :)
    integer :: m
    do m = 1, n
      associate (mt => mats(mat(m)))
        vol(m) = mass(m)/(poro(m)*fluid_density(mt%density, mt%bulk_fluid, pres(m)))
      end associate
      stress(1:3, m) = -pres(m)
    end do
  end subroutine fluid_state

  !> Semi-implicit pore-pressure update at the fluid points (paper eq. 10) with
  !> the divergences of the new nodal velocities at the points, divf (fluid) and
  !> divs (solid):
  !> p += -(K_f dt / n) [grad n . (v_f - v_s) + (1 - n) div v_s + n div v_f].
  !> gn_rel stands for grad n . (v_f - v_s) per point: the rest of the divergence
  !> of the nodal mixture flux (mixture_flux in dpmpm_transfer), zero when the
  !> porosity-gradient term is off.
  pure subroutine pressure_update(n, dt, kf, poro, divf, divs, gn_rel, pres)
    integer, intent(in) :: n
    real(wp), intent(in) :: dt, kf(:), poro(:), divf(:), divs(:), gn_rel(:)
    real(wp), intent(inout) :: pres(:)
    integer :: p
    do p = 1, n
      pres(p) = pres(p) - kf(p)*dt/poro(p)*(gn_rel(p) + (1.0_wp - poro(p))*divs(p) + poro(p)*divf(p))
    end do
  end subroutine pressure_update

  !> Intrinsic fluid density at pore pressure p for a linear compressible fluid,
  !> d rho / rho = dp / K_f integrated exactly.
  pure elemental real(wp) function fluid_density(rho0, kf, p) result(rho)
    real(wp), intent(in) :: rho0, kf, p
    rho = rho0*exp(p/kf)
  end function fluid_density

end module dpmpm_pore_pressure
