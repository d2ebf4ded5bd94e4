!> Error measures of a two-phase (saturated) run against the analytical references of the
!> column benchmarks: the 1D shock in a saturated column (W1-W3, dpmpm_biot_column) and
!> Terzaghi consolidation (T1, dpmpm_terzaghi).
!>
!> Scene convention: the column lies along x (1D, or 2D/3D with roller side faces). The first
!> &region with phase = 'saturated' is the column: its top x_top = lo(1) is the loaded, drained
!> face x-, its length L = hi(1) - lo(1), depth z = x - x_top. The load q is traction(1) of the
!> &load groups on face x- (positive = compression, pushing in +x); the bottom face x+ is fixed
!> and impermeable. The soil is the region's material (density = grain density rho_s,
!> constrained modulus E_c, conductivity k), the pore fluid its fluid_material (density rho_f,
!> K_f). Signs as in the references: sigma' = stress(1, p) of the solid points, tension
!> positive; p = pressure of the fluid points, compression positive; velocities and
!> displacements positive in +x (down the column).
!>
!> Column ('biot_column'), compared with biot_column_solve at the points' current depths:
!> - error_sigma_eff: volume-weighted RMS over the solid points of sigma'_p - sigma'_ref, / q;
!> - error_pore_pressure: the same over the fluid points for p;
!> - error_v_s, error_v_f: volume-weighted RMS of v_p - v_ref per phase, divided by the largest
!>   |v_ref| of that phase over the column (its points and the grid-cell centres);
!> - overshoot_sigma_eff: largest |sigma'_p - sigma'_ref| [Pa] over the solid points behind the
!>   fast front, z_p < c_u t - 3 h (c_u from biot_wave_speeds, h = cell size along x);
!> - total_stress_behind_front: mean over the grid cells whose centre lies behind the front and
!>   that hold solid and fluid points of (cell mean sigma' - cell mean p) [Pa], cell means
!>   weighted by point volume; -q where the reference total stress is -q;
!> - total_stress_error: largest |cell total stress - reference total stress at the cell
!>   centre depth| over those cells [Pa].
!> Terzaghi ('terzaghi'), compared with the series at the same time:
!> - error_pore_pressure: largest |p_p - p_ref(z_p)| over the fluid points / p_0;
!> - error_displacement: largest |u_p - u_ref(Z_p)| over the solid points / (q H/E_c), with
!>   u_p = x_p - x0_p along x and Z_p the reference depth;
!> - error_settlement: |u_top - s_ref(t)| / (q H/E_c), u_top from a least-squares line through
!>   (Z_p, u_p) of the solid points of the top cell, extrapolated to Z = 0;
!> - time_factor: T_v = c_v t/H^2.
!> At time <= 0 (nothing loaded yet) every measure and profile is zero.
module dpmpm_two_phase_verify
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, face_index
  use dpmpm_materials, only: material_t
  use dpmpm_particles, only: particle_set_t
  use dpmpm_biot_column, only: biot_column_t, biot_column_solve, biot_wave_speeds
  use dpmpm_terzaghi, only: terzaghi_t, terzaghi_pressure, terzaghi_settlement, &
                            terzaghi_time_factor, terzaghi_p0, terzaghi_nterms
  use dpmpm_gather, only: gather_columns
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, &
                     MPI_Bcast, MPI_DOUBLE_PRECISION
  implicit none
  private
  public :: two_phase_column, terzaghi_from_scene, two_phase_errors, two_phase_profiles
  public :: terzaghi_displacement, two_phase_error_names, error_name_len

  !> Length of the error names.
  integer, parameter :: error_name_len = 32
  !> Measures of the column benchmark, in the order of the values.
  character(len=error_name_len), parameter :: column_names(7) = &
    [character(len=error_name_len) :: 'error_sigma_eff', 'error_pore_pressure', 'error_v_s', &
     'error_v_f', 'overshoot_sigma_eff', 'total_stress_behind_front', 'total_stress_error']
  !> Measures of the Terzaghi benchmark, in the order of the values.
  character(len=error_name_len), parameter :: terzaghi_names(4) = &
    [character(len=error_name_len) :: 'error_pore_pressure', 'error_displacement', &
     'error_settlement', 'time_factor']
  !> Points behind the fast front are those with z < c_u t - front_margin h.
  real(wp), parameter :: front_margin = 3.0_wp
  real(wp), parameter :: pi = acos(-1.0_wp)
  !> Rows of the gathered point table: x(1), x0(1), volume, sigma'_xx or p, v(1), x(2:ndim).
  integer, parameter :: row_x = 1, row_x0 = 2, row_vol = 3, row_field = 4, row_v = 5

contains

  !> Names of the error measures of a two-phase benchmark (empty for other benchmarks), in the
  !> order two_phase_errors returns them.
  function two_phase_error_names(benchmark) result(names)
    character(len=*), intent(in) :: benchmark
    character(len=error_name_len), allocatable :: names(:)
    select case (trim(benchmark))
    case ('biot_column')
      names = column_names
    case ('terzaghi')
      names = terzaghi_names
    case default
      allocate (names(0))
    end select
  end function two_phase_error_names

  !> The saturated column of the scene as a biot_column_t (header: scene convention), and the
  !> position x_top of its loaded top. ok = .false. (col, x_top unset) without a saturated
  !> region, its materials, or a load along x on face x-.
  subroutine two_phase_column(cfg, mats, col, x_top, ok)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(biot_column_t), intent(out) :: col
    real(wp), intent(out) :: x_top
    logical, intent(out) :: ok
    integer :: ireg, isoil, ifluid
    real(wp) :: q
    call find_column(cfg, mats, ireg, isoil, ifluid, q, ok)
    if (.not. ok) return
    associate (reg => cfg%regions(ireg))
      col = biot_column_t(length=reg%hi(1) - reg%lo(1), porosity=reg%porosity, &
                          rho_s=mats(isoil)%density, rho_f=mats(ifluid)%density, &
                          e_c=mats(isoil)%pwave, k_f=mats(ifluid)%bulk_fluid, &
                          conductivity=mats(isoil)%conductivity, load=q)
      x_top = reg%lo(1)
    end associate
  end subroutine two_phase_column

  !> The consolidation problem of the scene (layer height H = column length, same materials and
  !> load as two_phase_column) and x_top; ok as there.
  subroutine terzaghi_from_scene(cfg, mats, ter, x_top, ok)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(terzaghi_t), intent(out) :: ter
    real(wp), intent(out) :: x_top
    logical, intent(out) :: ok
    type(biot_column_t) :: col
    call two_phase_column(cfg, mats, col, x_top, ok)
    if (.not. ok) return
    ter = terzaghi_t(height=col%length, porosity=col%porosity, e_c=col%e_c, k_f=col%k_f, &
                     conductivity=col%conductivity, rho_f=col%rho_f, gravity=col%gravity, &
                     load=col%load)
  end subroutine terzaghi_from_scene

  !> Settlement profile of Terzaghi consolidation: the displacement u(z,t) (positive down) at
  !> depth z in [0, H]. Quasi-statically sigma' = p - q, so the strain is (p - q)/E_c and
  !> with u(H) = 0, u(z) = int_z^H (q - p)/E_c dz'. Term by term, int_z^H sin(M_m z'/H) dz' =
  !> (H/M_m) cos(M_m z/H) (cos M_m = 0), hence
  !> u = [q (H - z) - p_0 H sum (2/M_m^2) cos(M_m z/H) exp(-M_m^2 T_v)]/E_c.
  !> The series starts from the undrained split p_0 (compressible fluid), so u(0,t) is
  !> terzaghi_settlement(t) = s_u + (p_0 H/E_c) U. At t <= 0 the sum is 1 - z/H (undrained).
  pure function terzaghi_displacement(ter, z, t) result(u)
    type(terzaghi_t), intent(in) :: ter
    real(wp), intent(in) :: z, t
    real(wp) :: u, tv, mm, acc
    integer :: m
    if (t <= 0.0_wp) then
      acc = 1.0_wp - z/ter%height
    else
      tv = terzaghi_time_factor(ter, t)
      acc = 0.0_wp
      do m = terzaghi_nterms(tv) - 1, 0, -1          ! smallest terms first
        mm = 0.5_wp*pi*real(2*m + 1, wp)
        acc = acc + 2.0_wp/mm**2*cos(mm*z/ter%height)*exp(-mm**2*tv)
      end do
    end if
    u = (ter%load*(ter%height - z) - terzaghi_p0(ter)*ter%height*acc)/ter%e_c
  end function terzaghi_displacement

  !> Error measures of the two-phase benchmark cfg%benchmark at time (module header) over the
  !> solid and fluid points of all ranks of comm. Collective; names and values are the same on
  !> every rank (computed on rank 0). Other benchmarks: empty arrays. All values are zero at
  !> time <= 0 or when the scene has no loaded saturated column.
  subroutine two_phase_errors(cfg, mats, solid, fluid, time, comm, names, values)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(in) :: solid, fluid
    real(wp), intent(in) :: time
    type(MPI_Comm), intent(in) :: comm
    character(len=error_name_len), allocatable, intent(out) :: names(:)
    real(wp), allocatable, intent(out) :: values(:)
    real(wp), allocatable :: sol(:, :), flu(:, :)
    type(biot_column_t) :: col
    real(wp) :: x_top
    logical :: ok
    integer :: rank
    names = two_phase_error_names(cfg%benchmark)
    allocate (values(size(names)))
    values = 0.0_wp
    if (size(names) == 0 .or. .not. time > 0.0_wp) return
    call two_phase_column(cfg, mats, col, x_top, ok)
    if (.not. ok) return
    call gather_points(solid, .false., comm, sol)
    call gather_points(fluid, .true., comm, flu)
    call MPI_Comm_rank(comm, rank)
    if (rank == 0) then
      if (trim(cfg%benchmark) == 'biot_column') then
        call column_errors(cfg, col, x_top, sol, flu, time, values)
      else
        call terzaghi_errors(cfg, col, x_top, sol, flu, time, values)
      end if
    end if
    call MPI_Bcast(values, size(values), MPI_DOUBLE_PRECISION, 0, comm)
  end subroutine two_phase_errors

  !> Reference fields of the scene's benchmark at time on nz >= 2 depths z = 0 ... L (uniform):
  !> fields(:, i) = (p, sigma', v_s, v_f) at z(i). Column: biot_column_solve; Terzaghi: the
  !> series p, sigma' = p - q and zero velocities. Zero at time <= 0, for other benchmarks and
  !> without a loaded saturated column (z then from 0 to 0).
  subroutine two_phase_profiles(cfg, mats, time, nz, z, fields)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    real(wp), intent(in) :: time
    integer, intent(in) :: nz
    real(wp), intent(out) :: z(nz), fields(4, nz)
    type(biot_column_t) :: col
    type(terzaghi_t) :: ter
    real(wp) :: x_top, len, p(nz, 1), sig(nz, 1), vs(nz, 1), vf(nz, 1)
    logical :: ok
    integer :: i
    call two_phase_column(cfg, mats, col, x_top, ok)
    len = 0.0_wp
    if (ok) len = col%length
    z = [(len*real(i - 1, wp)/real(max(nz - 1, 1), wp), i=1, nz)]
    fields = 0.0_wp
    if (.not. (ok .and. time > 0.0_wp)) return
    select case (trim(cfg%benchmark))
    case ('biot_column')
      call biot_column_solve(col, time, nz, z, 1, [time], p, sig, vs, vf)
      fields = transpose(reshape([p, sig, vs, vf], [nz, 4]))
    case ('terzaghi')
      call terzaghi_from_scene(cfg, mats, ter, x_top, ok)
      do i = 1, nz
        fields(1, i) = terzaghi_pressure(ter, z(i), time)
        fields(2, i) = fields(1, i) - ter%load
      end do
    end select
  end subroutine two_phase_profiles

  ! ---------------------------------------------------------------------------------------------

  !> Indices of the column's region, soil and fluid materials (into cfg%regions and mats) and
  !> the load q = sum of traction(1) over the &load groups on face x-; ok = .false. if any is
  !> missing or q = 0.
  subroutine find_column(cfg, mats, ireg, isoil, ifluid, q, ok)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    integer, intent(out) :: ireg, isoil, ifluid
    real(wp), intent(out) :: q
    logical, intent(out) :: ok
    integer :: k
    ok = .false.
    ireg = 0; isoil = 0; ifluid = 0
    q = 0.0_wp
    if (.not. allocated(cfg%regions)) return
    do k = 1, size(cfg%regions)
      if (trim(cfg%regions(k)%phase) == 'saturated') then
        ireg = k
        exit
      end if
    end do
    if (ireg == 0 .or. size(mats) == 0) return
    isoil = findloc(mats%id, cfg%regions(ireg)%material, dim=1)
    ifluid = findloc(mats%id, cfg%regions(ireg)%fluid_material, dim=1)
    if (allocated(cfg%loads)) then
      do k = 1, size(cfg%loads)
        if (cfg%loads(k)%face == face_index('x-')) q = q + cfg%loads(k)%traction(1)
      end do
    end if
    ok = isoil > 0 .and. ifluid > 0 .and. q /= 0.0_wp
  end subroutine find_column

  !> Gather the point table (rows row_x ... row_v, then x(2:ndim)) of one set on rank 0 of
  !> comm; field is the pore pressure when pressure is true, sigma'_xx otherwise. Other ranks
  !> get an empty table.
  subroutine gather_points(ps, pressure, comm, all)
    type(particle_set_t), intent(in) :: ps
    logical, intent(in) :: pressure
    type(MPI_Comm), intent(in) :: comm
    real(wp), allocatable, intent(out) :: all(:, :)
    real(wp), allocatable :: buf(:, :)
    integer :: nrow, ntot, nd
    nd = max(ps%ndim, 1)
    nrow = row_v + nd - 1
    allocate (buf(nrow, ps%n))
    if (ps%n > 0) then
      buf(row_x, :) = ps%x(1, 1:ps%n)
      buf(row_x0, :) = ps%x0(1, 1:ps%n)
      buf(row_vol, :) = ps%vol(1:ps%n)
      if (pressure) then
        buf(row_field, :) = ps%pressure(1:ps%n)
      else
        buf(row_field, :) = ps%stress(1, 1:ps%n)
      end if
      buf(row_v, :) = ps%v(1, 1:ps%n)
      if (nd > 1) buf(row_v + 1:, :) = ps%x(2:nd, 1:ps%n)
    end if
    call gather_columns(buf, ps%n, comm, all, ntot)
  end subroutine gather_points

  !> The column measures (module header) from the gathered tables sol and flu.
  subroutine column_errors(cfg, col, x_top, sol, flu, time, values)
    type(config_t), intent(in) :: cfg
    type(biot_column_t), intent(in) :: col
    real(wp), intent(in) :: x_top, sol(:, :), flu(:, :), time
    real(wp), intent(out) :: values(:)
    real(wp), allocatable :: z(:), p(:, :), sig(:, :), vs(:, :), vf(:, :), zc(:)
    real(wp) :: h, front, c_fast, c_slow
    integer :: ns, nf, nc, ix
    ns = size(sol, 2)
    nf = size(flu, 2)
    h = cfg%length(1)/real(cfg%ncells(1), wp)
    ! Depths of the centres of the grid columns along x (clipped to the column).
    nc = cfg%ncells(1)
    zc = clamp_depth([(cfg%origin(1) + (real(ix, wp) + 0.5_wp)*h - x_top, ix=0, nc - 1)], &
                     col%length)
    ! One reference solve at every depth needed: solid points, fluid points, cell centres.
    z = [clamp_depth(sol(row_x, :) - x_top, col%length), &
         clamp_depth(flu(row_x, :) - x_top, col%length), zc]
    allocate (p(ns + nf + nc, 1), sig(ns + nf + nc, 1), vs(ns + nf + nc, 1), vf(ns + nf + nc, 1))
    call biot_column_solve(col, time, size(z), z, 1, [time], p, sig, vs, vf)
    associate (sref => sig(1:ns, 1), pref => p(ns + 1:ns + nf, 1))
      values(1) = weighted_rms(sol(row_field, :) - sref, sol(row_vol, :))/abs(col%load)
      values(2) = weighted_rms(flu(row_field, :) - pref, flu(row_vol, :))/abs(col%load)
      values(3) = weighted_rms(sol(row_v, :) - vs(1:ns, 1), sol(row_vol, :)) &
                  /velocity_scale(vs(:, 1))
      values(4) = weighted_rms(flu(row_v, :) - vf(ns + 1:ns + nf, 1), flu(row_vol, :)) &
                  /velocity_scale(vf(:, 1))
      call biot_wave_speeds(col, c_fast, c_slow)
      front = c_fast*time - front_margin*h
      values(5) = maxval(abs(sol(row_field, :) - sref), mask=z(1:ns) < front)
      if (.not. any(z(1:ns) < front)) values(5) = 0.0_wp
    end associate
    call cell_total_stress(cfg, x_top, sol, flu, sig(ns + nf + 1:, 1) - p(ns + nf + 1:, 1), &
                           front, values(6), values(7))
  end subroutine column_errors

  !> Total stress per grid cell, sigma'_cell - p_cell with volume-weighted cell means, over the
  !> cells that hold solid and fluid points and whose centre depth is below front: its mean
  !> (mean_total) and its largest distance to the reference total stress ref_total(ix + 1)
  !> given at the centre depth of each grid column ix = 0 ... ncells(1) - 1 along x
  !> (max_error). Both 0 without such cells.
  subroutine cell_total_stress(cfg, x_top, sol, flu, ref_total, front, mean_total, max_error)
    type(config_t), intent(in) :: cfg
    real(wp), intent(in) :: x_top, sol(:, :), flu(:, :), ref_total(:), front
    real(wp), intent(out) :: mean_total, max_error
    real(wp), allocatable :: acc(:, :)
    real(wp) :: h, total, zcell
    integer :: nd, ncell, k, ic, ix, ncount
    nd = size(sol, 1) - row_v + 1
    ncell = product(cfg%ncells(1:nd))
    allocate (acc(4, 0:ncell - 1))
    acc = 0.0_wp
    do k = 1, size(sol, 2)
      ic = cell_of(cfg, nd, sol(:, k))
      acc(1:2, ic) = acc(1:2, ic) + sol(row_vol, k)*[1.0_wp, sol(row_field, k)]
    end do
    do k = 1, size(flu, 2)
      ic = cell_of(cfg, nd, flu(:, k))
      acc(3:4, ic) = acc(3:4, ic) + flu(row_vol, k)*[1.0_wp, flu(row_field, k)]
    end do
    h = cfg%length(1)/real(cfg%ncells(1), wp)
    mean_total = 0.0_wp
    max_error = 0.0_wp
    ncount = 0
    do ic = 0, ncell - 1
      if (.not. (acc(1, ic) > 0.0_wp .and. acc(3, ic) > 0.0_wp)) cycle
      ix = mod(ic, cfg%ncells(1))
      zcell = cfg%origin(1) + (real(ix, wp) + 0.5_wp)*h - x_top
      if (.not. zcell < front) cycle
      total = acc(2, ic)/acc(1, ic) - acc(4, ic)/acc(3, ic)
      mean_total = mean_total + total
      max_error = max(max_error, abs(total - ref_total(ix + 1)))
      ncount = ncount + 1
    end do
    if (ncount > 0) mean_total = mean_total/real(ncount, wp)
  end subroutine cell_total_stress

  !> The Terzaghi measures (module header) from the gathered tables sol and flu.
  subroutine terzaghi_errors(cfg, col, x_top, sol, flu, time, values)
    type(config_t), intent(in) :: cfg
    type(biot_column_t), intent(in) :: col
    real(wp), intent(in) :: x_top, sol(:, :), flu(:, :), time
    real(wp), intent(out) :: values(:)
    type(terzaghi_t) :: ter
    real(wp) :: s_final, z, u_top, h
    integer :: k
    ter = terzaghi_t(height=col%length, porosity=col%porosity, e_c=col%e_c, k_f=col%k_f, &
                     conductivity=col%conductivity, rho_f=col%rho_f, gravity=col%gravity, &
                     load=col%load)
    s_final = abs(ter%load)*ter%height/ter%e_c
    values = 0.0_wp
    do k = 1, size(flu, 2)
      z = clamp_depth1(flu(row_x, k) - x_top, ter%height)
      values(1) = max(values(1), abs(flu(row_field, k) - terzaghi_pressure(ter, z, time)))
    end do
    values(1) = values(1)/abs(terzaghi_p0(ter))
    do k = 1, size(sol, 2)
      z = clamp_depth1(sol(row_x0, k) - x_top, ter%height)
      values(2) = max(values(2), abs(sol(row_x, k) - sol(row_x0, k) - &
                                     terzaghi_displacement(ter, z, time)))
    end do
    values(2) = values(2)/s_final
    h = cfg%length(1)/real(cfg%ncells(1), wp)
    u_top = top_displacement(sol(row_x0, :) - x_top, sol(row_x, :) - sol(row_x0, :), h)
    values(3) = abs(u_top - terzaghi_settlement(ter, time))/s_final
    values(4) = terzaghi_time_factor(ter, time)
  end subroutine terzaghi_errors

  !> Displacement at depth 0 extrapolated by a least-squares line u = a + b z through the points
  !> with depth z < h (one cell); the band grows by h until it holds two distinct depths (all
  !> points at the most). One depth only: the mean of u. No points: 0.
  pure function top_displacement(z, u, h) result(u_top)
    real(wp), intent(in) :: z(:), u(:), h
    real(wp) :: u_top, band, zm, um, szz
    logical :: near(size(z))
    integer :: n
    u_top = 0.0_wp
    if (size(z) == 0) return
    band = h
    do
      near = z < band
      n = count(near)
      if (n >= 2) then
        if (maxval(z, mask=near) > minval(z, mask=near)) exit
      end if
      if (n == size(z)) exit
      band = band + h
    end do
    zm = sum(z, mask=near)/n
    um = sum(u, mask=near)/n
    szz = sum((z - zm)**2, mask=near)
    u_top = um
    if (szz > 0.0_wp) u_top = um - zm*sum((z - zm)*(u - um), mask=near)/szz
  end function top_displacement

  !> sqrt(sum w d^2 / sum w); 0 for no points or zero weights.
  pure function weighted_rms(d, w) result(r)
    real(wp), intent(in) :: d(:), w(:)
    real(wp) :: r
    r = 0.0_wp
    if (sum(w) > 0.0_wp) r = sqrt(sum(w*d**2)/sum(w))
  end function weighted_rms

  !> Largest |v| of a reference velocity profile, or 1 where it is zero (no normalisation).
  pure function velocity_scale(v) result(s)
    real(wp), intent(in) :: v(:)
    real(wp) :: s
    s = 1.0_wp
    if (size(v) > 0) s = maxval(abs(v))
    if (.not. s > 0.0_wp) s = 1.0_wp
  end function velocity_scale

  !> Depths clipped to [0, len]: the reference is defined only inside the column.
  pure function clamp_depth(z, len) result(zc)
    real(wp), intent(in) :: z(:), len
    real(wp) :: zc(size(z))
    zc = min(max(z, 0.0_wp), len)
  end function clamp_depth

  !> One depth clipped to [0, len].
  pure function clamp_depth1(z, len) result(zc)
    real(wp), intent(in) :: z, len
    real(wp) :: zc
    zc = min(max(z, 0.0_wp), len)
  end function clamp_depth1

  !> Zero-based index of the grid cell holding the point of a gathered table column (x in row
  !> row_x, the other coordinates from row row_v + 1), x fastest; clipped to the grid.
  pure function cell_of(cfg, nd, col) result(ic)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: nd
    real(wp), intent(in) :: col(:)
    integer :: ic, d, i
    real(wp) :: xd
    ic = 0
    do d = nd, 1, -1
      xd = col(row_x)
      if (d > 1) xd = col(row_v + d - 1)
      i = floor((xd - cfg%origin(d))/(cfg%length(d)/real(cfg%ncells(d), wp)))
      i = max(0, min(cfg%ncells(d) - 1, i))
      ic = ic*cfg%ncells(d) + i
    end do
  end function cell_of

end module dpmpm_two_phase_verify
