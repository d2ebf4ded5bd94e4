!> Tests of the two-phase error measures (dpmpm_two_phase_verify) on 1 or more ranks. Point sets
!> are built by hand with fields that ARE the reference (biot_column_solve or the Terzaghi
!> series at the points' depths): every measure must then vanish up to round-off, or up to the
!> stated interpolation error. Then single fields are perturbed by known amounts and the
!> measures must return exactly those amounts. Points are dealt round-robin to the ranks, so
!> the gathering is exercised too; the results must not depend on the rank count.
program test_two_phase_verify
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Comm_size
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, region_cfg_t, load_cfg_t, face_index
  use dpmpm_materials, only: material_t, materials_from_config
  use dpmpm_particles, only: particle_set_t
  use dpmpm_biot_column, only: biot_column_t, biot_column_solve, biot_wave_speeds
  use dpmpm_terzaghi, only: terzaghi_t, terzaghi_pressure, terzaghi_settlement, terzaghi_p0, &
                            terzaghi_cv, terzaghi_time_factor
  use dpmpm_two_phase_verify, only: two_phase_column, terzaghi_from_scene, two_phase_errors, &
                                    two_phase_profiles, terzaghi_displacement, error_name_len
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer :: nranks, rank
  !> W1 at this time: fast front at 4.82 m, so z < 3.32 m is behind it on the 20-cell grid.
  real(wp), parameter :: t_w1 = 0.05_wp
  call start_tests(rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  call test_scene_gives_column_and_layer()
  call test_column_errors_vanish_on_reference()
  call test_column_errors_measure_known_perturbation()
  call test_column_total_stress_uses_grid_cells_2d()
  call test_errors_zero_before_load_and_for_other_benchmarks()
  call test_terzaghi_displacement_profile()
  call test_terzaghi_errors_vanish_on_reference()
  call test_terzaghi_errors_measure_known_perturbation()
  call test_profiles_are_the_references()
  call end_tests()

contains

  ! ---------------------------------------------------------------------------------- scenes

  !> A column scene along x: grid from origin over glen with nc cells along x (2 cells of
  !> 0.2 m across in 2D), saturated region [lo, lo + len] of a soil (id 1: rho_s = 2650,
  !> E = 10 MPa, nu = 0, conductivity k) and a fluid (id 2: rho_f = 1000, K_f), n_f = 0.3,
  !> load q on face x-.
  subroutine column_scene(ndim, nc, origin, glen, lo, len, k_f, k, q, bench, cfg, mats)
    integer, intent(in) :: ndim, nc
    real(wp), intent(in) :: origin, glen, lo, len, k_f, k, q
    character(len=*), intent(in) :: bench
    type(config_t), intent(out) :: cfg
    type(material_t), allocatable, intent(out) :: mats(:)
    cfg%ndim = ndim
    cfg%ncells = [nc, 2, 1]
    cfg%origin = [origin, 0.0_wp, 0.0_wp]
    cfg%length = [glen, 0.4_wp, 1.0_wp]
    cfg%benchmark = bench
    cfg%materials = [material_cfg_t(id=1, model='linear_elastic', density=2650.0_wp, &
                                    youngs_modulus=10.0e6_wp, poisson_ratio=0.0_wp, &
                                    conductivity=k), &
                     material_cfg_t(id=2, model='fluid', density=1000.0_wp, bulk_modulus=k_f)]
    allocate (cfg%regions(1))
    cfg%regions(1)%lo = [lo, 0.0_wp, 0.0_wp]
    cfg%regions(1)%hi = [lo + len, 0.4_wp, 1.0_wp]
    cfg%regions(1)%material = 1
    cfg%regions(1)%phase = 'saturated'
    cfg%regions(1)%fluid_material = 2
    cfg%regions(1)%porosity = 0.3_wp
    cfg%loads = [load_cfg_t(face=face_index('x-'), traction=[q, 0.0_wp, 0.0_wp])]
    call materials_from_config(cfg%materials, mats)
  end subroutine column_scene

  !> W1 of doc/theory.md 9.1 on a 20-cell grid (h = 0.5 m), 1D or 2D.
  subroutine w1_scene(ndim, cfg, mats)
    integer, intent(in) :: ndim
    type(config_t), intent(out) :: cfg
    type(material_t), allocatable, intent(out) :: mats(:)
    call column_scene(ndim, 20, 0.0_wp, 10.0_wp, 0.0_wp, 10.0_wp, 3.0e6_wp, 1.0e-5_wp, 1.0_wp, &
                      'biot_column', cfg, mats)
  end subroutine w1_scene

  !> T1 (H = 1 m, K_f = 2.2 GPa, k = 1e-4 m/s, q = 1 kPa) with its top at x = 0.25 m inside a
  !> 1.5 m grid of 30 cells (h = 0.05 m), so that depth and position differ.
  subroutine t1_scene(cfg, mats)
    type(config_t), intent(out) :: cfg
    type(material_t), allocatable, intent(out) :: mats(:)
    call column_scene(1, 30, 0.0_wp, 1.5_wp, 0.25_wp, 1.0_wp, 2.2e9_wp, 1.0e-4_wp, 1.0e3_wp, &
                      'terzaghi', cfg, mats)
  end subroutine t1_scene

  ! ---------------------------------------------------------------------------------- points

  !> n depths in (0, len) from the golden-ratio sequence (scattered, not stratified per cell).
  function scattered(n, len, phase) result(z)
    integer, intent(in) :: n
    real(wp), intent(in) :: len, phase
    real(wp) :: z(n)
    integer :: k
    z = [(len*modulo(phase + real(k, wp)*0.6180339887498949_wp, 1.0_wp), k=1, n)]
  end function scattered

  !> Unequal point volumes (they weight the RMS and the cell means).
  function volumes(n, len) result(v)
    integer, intent(in) :: n
    real(wp), intent(in) :: len
    real(wp) :: v(n)
    integer :: k
    v = [(len/real(n, wp)*(1.0_wp + 0.5_wp*sin(real(k, wp))), k=1, n)]
  end function volumes

  !> True when point k belongs to this rank (round-robin).
  logical function mine(k)
    integer, intent(in) :: k
    mine = mod(k - 1, nranks) == rank
  end function mine

  !> Empty solid and fluid sets of a two-phase scene.
  subroutine empty_sets(ndim, solid, fluid)
    integer, intent(in) :: ndim
    type(particle_set_t), intent(out) :: solid, fluid
    call solid%init('solid', ndim, .false., has_porosity=.true.)
    call fluid%init('fluid', ndim, .false., has_porosity=.true., has_pressure=.true.)
  end subroutine empty_sets

  !> Solid and fluid points of a column in pairs (pair k at position x_top + z(k), y(k), volume
  !> vol(k)) carrying the reference fields sig, p, vs, vf; this rank's share only.
  subroutine column_points(ndim, x_top, z, y, vol, sig, p, vs, vf, solid, fluid)
    integer, intent(in) :: ndim
    real(wp), intent(in) :: x_top, z(:), y(:), vol(:), sig(:), p(:), vs(:), vf(:)
    type(particle_set_t), intent(out) :: solid, fluid
    real(wp) :: x(3), zero6(6)
    integer :: k
    call empty_sets(ndim, solid, fluid)
    zero6 = 0.0_wp
    do k = 1, size(z)
      if (.not. mine(k)) cycle
      x = [x_top + z(k), y(k), 0.0_wp]
      call solid%append(int(k, i8), 1, x, [vs(k), 0.0_wp, 0.0_wp], 0.7_wp*2650.0_wp*vol(k), &
                        vol(k), [sig(k), zero6(2:6)], porosity=0.3_wp)
      call fluid%append(int(k, i8), 2, x, [vf(k), 0.0_wp, 0.0_wp], 0.3_wp*1000.0_wp*vol(k), &
                        vol(k), zero6, porosity=0.3_wp, pressure=p(k))
    end do
  end subroutine column_points

  !> Value of the named measure (the names must contain it).
  real(wp) function measure(names, values, name)
    character(len=error_name_len), intent(in) :: names(:)
    real(wp), intent(in) :: values(:)
    character(len=*), intent(in) :: name
    integer :: k
    k = findloc(names, name, dim=1)
    call check(k > 0, 'measure '//name//' is returned')
    measure = huge(1.0_wp)
    if (k > 0) measure = values(k)
  end function measure

  ! ----------------------------------------------------------------------------------- tests

  !> The column and the layer are read off the scene (module header convention); without a
  !> saturated region, without a load on x- or with a load only on x+ there is no column.
  subroutine test_scene_gives_column_and_layer()
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(biot_column_t) :: col
    type(terzaghi_t) :: ter
    real(wp) :: x_top
    logical :: ok
    call begin_test('scene_gives_column_and_layer')
    call t1_scene(cfg, mats)
    call two_phase_column(cfg, mats, col, x_top, ok)
    call check(ok, 'T1 scene has a column')
    call check_close(x_top, 0.25_wp, 0.0_wp, 0.0_wp, 'x_top = lo(1)')
    call check_close(col%length, 1.0_wp, 1.0e-15_wp, 0.0_wp, 'L = hi(1) - lo(1)')
    call check_close(col%porosity, 0.3_wp, 0.0_wp, 0.0_wp, 'porosity')
    call check_close(col%rho_s, 2650.0_wp, 0.0_wp, 0.0_wp, 'rho_s = soil density')
    call check_close(col%rho_f, 1000.0_wp, 0.0_wp, 0.0_wp, 'rho_f = fluid density')
    call check_close(col%e_c, 10.0e6_wp, 1.0e-15_wp, 0.0_wp, 'E_c = E at nu = 0')
    call check_close(col%k_f, 2.2e9_wp, 0.0_wp, 0.0_wp, 'K_f')
    call check_close(col%conductivity, 1.0e-4_wp, 0.0_wp, 0.0_wp, 'k')
    call check_close(col%load, 1.0e3_wp, 0.0_wp, 0.0_wp, 'q = traction(1) on x-')
    call check_close(col%gravity, 9.81_wp, 0.0_wp, 0.0_wp, 'g')
    call terzaghi_from_scene(cfg, mats, ter, x_top, ok)
    call check(ok, 'T1 scene has a layer')
    call check_close(ter%height, 1.0_wp, 1.0e-15_wp, 0.0_wp, 'H = L')
    call check_close(ter%e_c, 10.0e6_wp, 1.0e-15_wp, 0.0_wp, 'layer E_c')
    call check_close(ter%k_f, 2.2e9_wp, 0.0_wp, 0.0_wp, 'layer K_f')
    call check_close(ter%conductivity, 1.0e-4_wp, 0.0_wp, 0.0_wp, 'layer k')
    call check_close(ter%rho_f, 1000.0_wp, 0.0_wp, 0.0_wp, 'layer rho_f')
    call check_close(ter%load, 1.0e3_wp, 0.0_wp, 0.0_wp, 'layer q')
    cfg%loads(1)%face = face_index('x+')
    call two_phase_column(cfg, mats, col, x_top, ok)
    call check(.not. ok, 'no column with the load on x+ only')
    deallocate (cfg%loads)
    call two_phase_column(cfg, mats, col, x_top, ok)
    call check(.not. ok, 'no column without loads')
    call t1_scene(cfg, mats)
    cfg%regions(1)%phase = 'solid'
    call terzaghi_from_scene(cfg, mats, ter, x_top, ok)
    call check(.not. ok, 'no layer without a saturated region')
  end subroutine test_scene_gives_column_and_layer

  !> W1 at 0.05 s, 24 pairs of solid and fluid points scattered over the column (1D), fields
  !> from biot_column_solve at their depths. The point measures use the same solve and must
  !> be round-off (measured: exactly 0). The pairs make each cell's mean sigma' - mean p the
  !> mean of the reference sigma' - p, so the cell total stress behind the front is -q up to
  !> the reference's own total-stress error (7.7e-8 q in test_biot_column, bound 2e-7 q there;
  !> measured here 2.0e-8 q).
  subroutine test_column_errors_vanish_on_reference()
    integer, parameter :: n = 24
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: solid, fluid
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:)
    real(wp) :: z(n), vol(n), p(n, 1), sig(n, 1), vs(n, 1), vf(n, 1)
    type(biot_column_t) :: col
    real(wp) :: x_top
    logical :: ok
    call begin_test('column_errors_vanish_on_reference')
    call w1_scene(1, cfg, mats)
    call two_phase_column(cfg, mats, col, x_top, ok)
    z = scattered(n, 10.0_wp, 0.1_wp)
    vol = volumes(n, 10.0_wp)
    call biot_column_solve(col, t_w1, n, z, 1, [t_w1], p, sig, vs, vf)
    call column_points(1, x_top, z, z, vol, sig(:, 1), p(:, 1), vs(:, 1), vf(:, 1), solid, fluid)
    call two_phase_errors(cfg, mats, solid, fluid, t_w1, MPI_COMM_WORLD, names, values)
    call check_equal_int(size(names), 7, 'seven column measures')
    call check(abs(measure(names, values, 'error_sigma_eff')) < 1.0e-14_wp, 'error_sigma_eff = 0')
    call check(abs(measure(names, values, 'error_pore_pressure')) < 1.0e-14_wp, &
               'error_pore_pressure = 0')
    call check(abs(measure(names, values, 'error_v_s')) < 1.0e-14_wp, 'error_v_s = 0')
    call check(abs(measure(names, values, 'error_v_f')) < 1.0e-14_wp, 'error_v_f = 0')
    call check(abs(measure(names, values, 'overshoot_sigma_eff')) < 1.0e-14_wp, 'overshoot = 0')
    call check_close(measure(names, values, 'total_stress_behind_front'), -1.0_wp, 0.0_wp, &
                     2.0e-7_wp, 'total stress behind the front = -q')
    call check(measure(names, values, 'total_stress_error') < 2.0e-7_wp, &
               'total stress error at the reference level')
  end subroutine test_column_errors_vanish_on_reference

  !> The same points, perturbed. (a) sigma' of one point behind the front (z = 1.4 m, cell 2)
  !> by d1 = 0.01 Pa: error_sigma_eff = d1 sqrt(V_k/sum V)/q, overshoot = d1, and that cell's
  !> total stress moves by d1 V_k/V_cell (the largest total-stress error). (b) p of every fluid
  !> point by d2 = 0.02 Pa and v_s of every solid point by 5 % of the largest reference v_s
  !> over the points and the cell centres: error_pore_pressure = d2, total stress -q - d2 with
  !> error d2, error_v_s = 0.05, error_v_f unchanged (0). Tolerances: the 2e-7 q of the
  !> reference's total stress, 1e-12 relative elsewhere.
  subroutine test_column_errors_measure_known_perturbation()
    integer, parameter :: n = 24, nc = 20
    real(wp), parameter :: d1 = 0.01_wp, d2 = 0.02_wp, eps = 0.05_wp
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: solid, fluid
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:)
    real(wp) :: z(n + nc), vol(n), p(n + nc, 1), sig(n + nc, 1), vs(n + nc, 1), vf(n + nc, 1)
    real(wp) :: sig_k(n), x_top, vcell, vscale
    type(biot_column_t) :: col
    logical :: ok
    integer :: k, i
    call begin_test('column_errors_measure_known_perturbation')
    call w1_scene(1, cfg, mats)
    call two_phase_column(cfg, mats, col, x_top, ok)
    z(1:n) = scattered(n, 10.0_wp, 0.1_wp)
    z(n + 1:) = [(0.5_wp*(real(i, wp) - 0.5_wp), i=1, nc)]      ! cell centres
    vol = volumes(n, 10.0_wp)
    call biot_column_solve(col, t_w1, n + nc, z, 1, [t_w1], p, sig, vs, vf)
    ! (a) one effective stress, at the point nearest to 1.4 m.
    k = minloc(abs(z(1:n) - 1.4_wp), dim=1)
    call check(z(k) > 1.0_wp .and. z(k) < 1.5_wp, 'perturbed point in cell 2 (1 m to 1.5 m)')
    vcell = sum(vol(1:n), mask=z(1:n) >= 1.0_wp .and. z(1:n) < 1.5_wp)
    sig_k = sig(1:n, 1)
    sig_k(k) = sig_k(k) + d1
    call column_points(1, x_top, z(1:n), z(1:n), vol, sig_k, p(1:n, 1), vs(1:n, 1), vf(1:n, 1), &
                       solid, fluid)
    call two_phase_errors(cfg, mats, solid, fluid, t_w1, MPI_COMM_WORLD, names, values)
    call check_close(measure(names, values, 'error_sigma_eff'), d1*sqrt(vol(k)/sum(vol)), &
                     1.0e-12_wp, 0.0_wp, 'error_sigma_eff of one perturbed point')
    call check_close(measure(names, values, 'overshoot_sigma_eff'), d1, 1.0e-12_wp, 0.0_wp, &
                     'overshoot = the perturbation')
    call check_close(measure(names, values, 'total_stress_error'), d1*vol(k)/vcell, 0.0_wp, &
                     2.0e-7_wp, 'total stress error = the cell-mean shift')
    call check(abs(measure(names, values, 'error_pore_pressure')) < 1.0e-14_wp, &
               'pore pressure untouched')
    ! (b) every pore pressure and every solid velocity.
    vscale = maxval(abs(vs(:, 1)))
    call column_points(1, x_top, z(1:n), z(1:n), vol, sig(1:n, 1), p(1:n, 1) + d2, &
                       vs(1:n, 1) + eps*vscale, vf(1:n, 1), solid, fluid)
    call two_phase_errors(cfg, mats, solid, fluid, t_w1, MPI_COMM_WORLD, names, values)
    call check_close(measure(names, values, 'error_pore_pressure'), d2, 1.0e-12_wp, 0.0_wp, &
                     'error_pore_pressure = uniform shift')
    call check_close(measure(names, values, 'total_stress_behind_front'), -1.0_wp - d2, 0.0_wp, &
                     2.0e-7_wp, 'total stress -q - d2')
    call check_close(measure(names, values, 'total_stress_error'), d2, 0.0_wp, 2.0e-7_wp, &
                     'total stress error = d2')
    call check_close(measure(names, values, 'error_v_s'), eps, 1.0e-12_wp, 0.0_wp, &
                     'error_v_s = 5 % of the largest reference v_s')
    call check(abs(measure(names, values, 'error_v_f')) < 1.0e-14_wp, 'v_f untouched')
    call check(abs(measure(names, values, 'error_sigma_eff')) < 1.0e-14_wp, 'sigma'' untouched')
  end subroutine test_column_errors_measure_known_perturbation

  !> 2D (20 x 2 cells): the total stress is taken per grid cell, not per slab along x. Pairs
  !> scattered in x and y with reference fields; the pore pressure of the points in the upper
  !> row of cells (y > 0.2 m) is raised by d = 0.03 Pa. Per cell, the total-stress error is d
  !> in the upper cells and 0 below; a slab average would give less. The upper row holds m of
  !> the n pairs: error_pore_pressure = d sqrt(V_upper/V). Tolerances as above.
  subroutine test_column_total_stress_uses_grid_cells_2d()
    integer, parameter :: n = 30
    real(wp), parameter :: d = 0.03_wp
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: solid, fluid
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:)
    real(wp) :: z(n), y(n), vol(n), p(n, 1), sig(n, 1), vs(n, 1), vf(n, 1), x_top
    type(biot_column_t) :: col
    logical :: ok, upper(n)
    integer :: k
    call begin_test('column_total_stress_uses_grid_cells_2d')
    call w1_scene(2, cfg, mats)
    call two_phase_column(cfg, mats, col, x_top, ok)
    z = scattered(n, 10.0_wp, 0.3_wp)
    ! y from the plastic-number sequence, independent of the golden-ratio depths.
    y = 0.4_wp*modulo(0.05_wp + [(real(k, wp)*0.7548776662466927_wp, k=1, n)], 1.0_wp)
    vol = volumes(n, 10.0_wp)
    upper = y > 0.2_wp
    call check(any(upper .and. z < 3.0_wp) .and. any(.not. upper .and. z < 3.0_wp), &
               'both rows have points behind the front')
    call biot_column_solve(col, t_w1, n, z, 1, [t_w1], p, sig, vs, vf)
    call column_points(2, x_top, z, y, vol, sig(:, 1), merge(p(:, 1) + d, p(:, 1), upper), &
                       vs(:, 1), vf(:, 1), solid, fluid)
    call two_phase_errors(cfg, mats, solid, fluid, t_w1, MPI_COMM_WORLD, names, values)
    call check_close(measure(names, values, 'total_stress_error'), d, 0.0_wp, 2.0e-7_wp, &
                     'largest cell error = d')
    call check_close(measure(names, values, 'error_pore_pressure'), &
                     d*sqrt(sum(vol, mask=upper)/sum(vol)), 1.0e-12_wp, 0.0_wp, &
                     'error_pore_pressure of the upper row')
    call check(abs(measure(names, values, 'error_sigma_eff')) < 1.0e-14_wp, 'sigma'' untouched')
  end subroutine test_column_total_stress_uses_grid_cells_2d

  !> At time 0 nothing is loaded: every measure is 0 (names still given); a benchmark that is
  !> not two-phase gives no measures.
  subroutine test_errors_zero_before_load_and_for_other_benchmarks()
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: solid, fluid
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:)
    call begin_test('errors_zero_before_load_and_for_other_benchmarks')
    call w1_scene(1, cfg, mats)
    call empty_sets(1, solid, fluid)
    call two_phase_errors(cfg, mats, solid, fluid, 0.0_wp, MPI_COMM_WORLD, names, values)
    call check_equal_int(size(values), 7, 'column measures at t = 0')
    call check(all(values == 0.0_wp), 'all zero at t = 0')
    call t1_scene(cfg, mats)
    call two_phase_errors(cfg, mats, solid, fluid, 0.0_wp, MPI_COMM_WORLD, names, values)
    call check_equal_int(size(values), 4, 'Terzaghi measures at t = 0')
    call check(all(values == 0.0_wp), 'all zero at t = 0 (Terzaghi)')
    cfg%benchmark = 'axial_bar'
    call two_phase_errors(cfg, mats, solid, fluid, 1.0_wp, MPI_COMM_WORLD, names, values)
    call check_equal_int(size(names), 0, 'no two-phase measures for axial_bar')
  end subroutine test_errors_zero_before_load_and_for_other_benchmarks

  !> The settlement profile u(z,t) of the layer: u(0,t) is terzaghi_settlement to 1e-10
  !> relative (measured: 4.4e-16 or below) at T_v = 1e-3 ... 2 and at t = 0; u(H,t) = 0; and
  !> u(z,t) is the integral of (q - p)/E_c from z to H (Simpson, 20000 panels on the pressure
  !> series; measured 1.1e-14 relative at z = 0.3 H and 0.7 H, T_v = 0.01 ... 0.5; bound 1e-8
  !> as in test_biot_column).
  subroutine test_terzaghi_displacement_profile()
    integer, parameter :: npanel = 20000
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(terzaghi_t) :: ter
    real(wp) :: tvs(6), t, s_final, x_top, zs(2), h, acc, w
    logical :: ok
    integer :: i, j, k
    call begin_test('terzaghi_displacement_profile')
    call t1_scene(cfg, mats)
    call terzaghi_from_scene(cfg, mats, ter, x_top, ok)
    s_final = ter%load*ter%height/ter%e_c
    tvs = [1.0e-3_wp, 1.0e-2_wp, 0.1_wp, 0.5_wp, 1.0_wp, 2.0_wp]
    call check_close(terzaghi_displacement(ter, 0.0_wp, 0.0_wp), terzaghi_settlement(ter, 0.0_wp), &
                     1.0e-10_wp, 0.0_wp, 'u(0, 0) = undrained settlement')
    zs = [0.3_wp, 0.7_wp]
    do k = 1, size(tvs)
      t = tvs(k)*ter%height**2/terzaghi_cv(ter)
      call check_close(terzaghi_displacement(ter, 0.0_wp, t), terzaghi_settlement(ter, t), &
                       1.0e-10_wp, 0.0_wp, 'u(0, t) = settlement')
      call check(abs(terzaghi_displacement(ter, ter%height, t)) < 1.0e-14_wp*s_final, &
                 'u(H, t) = 0 (fixed bottom)')
      if (tvs(k) < 0.01_wp .or. tvs(k) > 0.5_wp) cycle
      do j = 1, 2
        h = (ter%height - zs(j))/npanel
        acc = 0.0_wp
        do i = 0, npanel
          w = merge(1.0_wp, merge(4.0_wp, 2.0_wp, mod(i, 2) == 1), i == 0 .or. i == npanel)
          acc = acc + w*(ter%load - terzaghi_pressure(ter, zs(j) + i*h, t))/ter%e_c
        end do
        call check_close(terzaghi_displacement(ter, zs(j), t), acc*h/3.0_wp, 1.0e-8_wp, 0.0_wp, &
                         'u(z, t) = integral of the strain')
      end do
    end do
  end subroutine test_terzaghi_displacement_profile

  !> T1 points and fields at T_v = 0.2 (top of the layer at x = 0.25 m in the grid): fluid
  !> points with p = series at their depths, solid points displaced by u_ref of their reference
  !> depth. Pressure measure: round-off (bound 1e-12). Displacements are differences x - x0 of
  !> positions near 1 m for u of about 1e-4 m, so they carry about 1e-16/1e-4 = 1e-12 relative
  !> round-off (measured 1.1e-12); bound 1e-11. The settlement measure is the error of the
  !> straight line through the top cell's points: the test computes that line independently
  !> (normal equations) and checks the measure against it (1e-11), and the line against u(0)
  !> by the extrapolation bound (h^2/2) max|u''| with u'' = (dp/dz)/E_c, dp/dz(0) = 1.245 p_0/H
  !> at T_v = 0.2: 1.6e-3 s_final (measured 2.7e-4, which is (u''/2) z_1 z_2 for the two points
  !> at z_1 = 0.012 m and z_2 = 0.037 m).
  subroutine test_terzaghi_errors_vanish_on_reference()
    integer, parameter :: n = 40
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: solid, fluid
    type(terzaghi_t) :: ter
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:)
    real(wp) :: zs(n), zf(n), t, x_top, s_final, line_top
    logical :: ok
    call begin_test('terzaghi_errors_vanish_on_reference')
    call t1_scene(cfg, mats)
    call terzaghi_from_scene(cfg, mats, ter, x_top, ok)
    t = 0.2_wp/terzaghi_cv(ter)
    s_final = ter%load*ter%height/ter%e_c
    call terzaghi_points(ter, x_top, t, zs, zf, solid, fluid)
    call two_phase_errors(cfg, mats, solid, fluid, t, MPI_COMM_WORLD, names, values)
    call check_equal_int(size(names), 4, 'four Terzaghi measures')
    call check(measure(names, values, 'error_pore_pressure') < 1.0e-12_wp, 'pressure error = 0')
    call check(measure(names, values, 'error_displacement') < 1.0e-11_wp, 'displacement error = 0')
    call check_close(measure(names, values, 'time_factor'), 0.2_wp, 1.0e-14_wp, 0.0_wp, 'T_v')
    line_top = top_line(ter, zs, t, 0.05_wp)
    call check_close(measure(names, values, 'error_settlement'), &
                     abs(line_top - terzaghi_settlement(ter, t))/s_final, 0.0_wp, 1.0e-11_wp, &
                     'settlement error = error of the top-cell line')
    call check(measure(names, values, 'error_settlement') < 1.6e-3_wp, &
               'top-cell line within its curvature bound')
  end subroutine test_terzaghi_errors_vanish_on_reference

  !> The T1 points perturbed: p of one fluid point by 3 % of p_0, u of one solid point below the
  !> top cell by 2 % of q H/E_c, u of every point by 1 % (the line through the top cell moves by
  !> exactly that much). Each measure returns its perturbation (1e-12 for the pressure, 1e-11
  !> for displacements as in the previous test, plus the line error there for the settlement).
  subroutine test_terzaghi_errors_measure_known_perturbation()
    integer, parameter :: n = 40
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: solid, fluid
    type(terzaghi_t) :: ter
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:)
    real(wp) :: zs(n), zf(n), t, x_top, s_final, p0, e_line
    logical :: ok
    integer :: k
    call begin_test('terzaghi_errors_measure_known_perturbation')
    call t1_scene(cfg, mats)
    call terzaghi_from_scene(cfg, mats, ter, x_top, ok)
    t = 0.2_wp/terzaghi_cv(ter)
    s_final = ter%load*ter%height/ter%e_c
    p0 = terzaghi_p0(ter)
    call terzaghi_points(ter, x_top, t, zs, zf, solid, fluid)
    e_line = (top_line(ter, zs, t, 0.05_wp) - terzaghi_settlement(ter, t))/s_final
    do k = 1, fluid%n
      if (fluid%id(k) == 7) fluid%pressure(k) = fluid%pressure(k) + 0.03_wp*p0
    end do
    do k = 1, solid%n
      if (solid%id(k) == 9) solid%x(1, k) = solid%x(1, k) + 0.02_wp*s_final
    end do
    call check(zs(9) > 0.05_wp, 'point 9 lies below the top cell')
    call two_phase_errors(cfg, mats, solid, fluid, t, MPI_COMM_WORLD, names, values)
    call check_close(measure(names, values, 'error_pore_pressure'), 0.03_wp, 1.0e-12_wp, 0.0_wp, &
                     'pressure error = 3 % of p_0')
    call check_close(measure(names, values, 'error_displacement'), 0.02_wp, 0.0_wp, 1.0e-11_wp, &
                     'displacement error = 2 % of q H/E_c')
    call check_close(measure(names, values, 'error_settlement'), abs(e_line), 0.0_wp, 1.0e-11_wp, &
                     'settlement unchanged by a point below the top cell')
    solid%x(1, 1:solid%n) = solid%x(1, 1:solid%n) + 0.01_wp*s_final
    call two_phase_errors(cfg, mats, solid, fluid, t, MPI_COMM_WORLD, names, values)
    call check_close(measure(names, values, 'error_settlement'), abs(e_line + 0.01_wp), 0.0_wp, &
                     1.0e-11_wp, 'settlement error = uniform shift + line error')
  end subroutine test_terzaghi_errors_measure_known_perturbation

  !> Profiles: biot_column gives biot_column_solve on z = 0 ... L (uniform; the plateau p = q/2
  !> behind the front), terzaghi the series with sigma' = p - q and zero velocities; time 0
  !> gives zeros.
  subroutine test_profiles_are_the_references()
    integer, parameter :: nz = 11
    type(config_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(biot_column_t) :: col
    type(terzaghi_t) :: ter
    real(wp) :: z(nz), f(4, nz), p(nz, 1), sig(nz, 1), vs(nz, 1), vf(nz, 1), x_top, t
    logical :: ok
    integer :: i
    call begin_test('profiles_are_the_references')
    call w1_scene(1, cfg, mats)
    call two_phase_column(cfg, mats, col, x_top, ok)
    call two_phase_profiles(cfg, mats, t_w1, nz, z, f)
    call check_close(z(1), 0.0_wp, 0.0_wp, 0.0_wp, 'z starts at the top')
    call check_close(z(nz), 10.0_wp, 1.0e-15_wp, 0.0_wp, 'z ends at the bottom')
    call check_close(z(4) - z(3), 1.0_wp, 1.0e-14_wp, 0.0_wp, 'uniform depths')
    call biot_column_solve(col, t_w1, nz, z, 1, [t_w1], p, sig, vs, vf)
    call check(all(f(1, :) == p(:, 1)) .and. all(f(2, :) == sig(:, 1)) .and. &
               all(f(3, :) == vs(:, 1)) .and. all(f(4, :) == vf(:, 1)), 'column profiles')
    call check_close(f(1, 3), 0.5_wp, 0.0_wp, 2.0e-7_wp, 'p = q/2 at z = 2 m')
    call two_phase_profiles(cfg, mats, 0.0_wp, nz, z, f)
    call check(all(f == 0.0_wp), 'column profiles zero at t = 0')
    call t1_scene(cfg, mats)
    call terzaghi_from_scene(cfg, mats, ter, x_top, ok)
    t = 0.1_wp/terzaghi_cv(ter)
    call two_phase_profiles(cfg, mats, t, nz, z, f)
    do i = 1, nz
      call check_close(f(1, i), terzaghi_pressure(ter, z(i), t), 1.0e-15_wp, 0.0_wp, 'Terzaghi p')
      call check_close(f(2, i), f(1, i) - ter%load, 1.0e-15_wp, 0.0_wp, 'Terzaghi sigma'' = p - q')
    end do
    call check(all(f(3:4, :) == 0.0_wp), 'Terzaghi velocities zero')
    call check_close(terzaghi_time_factor(ter, t), 0.1_wp, 1.0e-14_wp, 0.0_wp, 'T_v = 0.1')
  end subroutine test_profiles_are_the_references

  ! ------------------------------------------------------------------------- Terzaghi helpers

  !> Reference depths of the T1 solid points (two in the top cell of 0.05 m, the rest
  !> scattered) and current depths of the fluid points.
  subroutine terzaghi_depths(zs, zf)
    real(wp), intent(out) :: zs(:), zf(:)
    zs(1:2) = [0.012_wp, 0.037_wp]
    zs(3:) = scattered(size(zs) - 2, 1.0_wp, 0.2_wp)
    zf = scattered(size(zf), 1.0_wp, 0.45_wp)
  end subroutine terzaghi_depths

  !> T1 points at time t carrying the reference: fluid p = series at its depth, solid displaced
  !> by u_ref(Z) from its reference depth Z; this rank's share.
  subroutine terzaghi_points(ter, x_top, t, zs, zf, solid, fluid)
    type(terzaghi_t), intent(in) :: ter
    real(wp), intent(in) :: x_top, t
    real(wp), intent(out) :: zs(:), zf(:)
    type(particle_set_t), intent(out) :: solid, fluid
    real(wp) :: zero6(6), vs(size(zs))
    integer :: k
    call terzaghi_depths(zs, zf)
    vs = volumes(size(zs), 1.0_wp)
    zero6 = 0.0_wp
    call empty_sets(1, solid, fluid)
    do k = 1, size(zs)
      if (.not. mine(k)) cycle
      call solid%append(int(k, i8), 1, [x_top + zs(k)], [0.0_wp], 1.0_wp, vs(k), zero6, &
                        porosity=0.3_wp)
      solid%x(1, solid%n) = x_top + zs(k) + terzaghi_displacement(ter, zs(k), t)
    end do
    do k = 1, size(zf)
      if (.not. mine(k)) cycle
      call fluid%append(int(k, i8), 2, [x_top + zf(k)], [0.0_wp], 1.0_wp, vs(k), zero6, &
                        porosity=0.3_wp, pressure=terzaghi_pressure(ter, zf(k), t))
    end do
  end subroutine terzaghi_points

  !> u at depth 0 of the least-squares line u = a + b Z through the solid points with Z < h,
  !> from the 2x2 normal equations (independent of the module's centred form).
  real(wp) function top_line(ter, zs, t, h) result(a)
    type(terzaghi_t), intent(in) :: ter
    real(wp), intent(in) :: zs(:), t, h
    real(wp) :: s0, s1, s2, r0, r1, u
    integer :: k
    s0 = 0.0_wp; s1 = 0.0_wp; s2 = 0.0_wp; r0 = 0.0_wp; r1 = 0.0_wp
    do k = 1, size(zs)
      if (zs(k) >= h) cycle
      u = terzaghi_displacement(ter, zs(k), t)
      s0 = s0 + 1.0_wp; s1 = s1 + zs(k); s2 = s2 + zs(k)**2
      r0 = r0 + u; r1 = r1 + zs(k)*u
    end do
    a = (s2*r0 - s1*r1)/(s0*s2 - s1**2)
  end function top_line

end program test_two_phase_verify
