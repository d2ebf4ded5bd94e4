!> Two-phase double-point MPM: the per-node drag solve, the 1D shock in a
!> saturated column (W1, coarse) against the analytical column solution, the
!> agreement of explicit and implicit drag, and Terzaghi consolidation.
program test_two_phase
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, region_cfg_t, material_cfg_t, load_cfg_t, bc_fixed, bc_roller, fbc_drained
  use dpmpm_simulation, only: simulation_t
  use dpmpm_drag, only: drag_limit
  use dpmpm_nodal_update, only: drag_solve
  use dpmpm_biot_column, only: biot_column_t, biot_column_solve
  use dpmpm_terzaghi, only: terzaghi_t, terzaghi_cv, terzaghi_pressure, terzaghi_settlement, &
                            terzaghi_p0
  use dpmpm_two_phase_verify, only: two_phase_errors, error_name_len
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_test_scenes, only: column_scene
  implicit none
  ! Bounds: the measured values of doc/verification.md (two-phase section) plus 30 %;
  ! the total stress behind the front (measured 0.012 Pa off) gets 0.05 Pa.
  ! W1: sigma' and p errors / q measured 0.0555 and 0.0609 (implicit drag);
  ! implicit - explicit RMS 0.021 and 0.023 Pa. W3: 0.0017 Pa, p error 0.042.
  real(wp), parameter :: W1_SIG = 0.072_wp, W1_P = 0.08_wp, W1_TOT = 0.05_wp, W1_DRAG = 0.03_wp
  real(wp), parameter :: W3_DRAG = 0.023_wp, W3_P = 0.055_wp
  ! T1 at T_v = 0.1 and 0.5: largest p error / p0 measured 0.143, 0.048; settlement
  ! error / (q H / E_c) 0.0125, 0.0037.
  real(wp), parameter :: T1_P(2) = [0.19_wp, 0.063_wp], T1_S(2) = [0.017_wp, 0.005_wp]
  ! W1 on the uniform scatter of inputs/w1.nml (seed 1, Courant number 0.3), the
  ! Wendland C2 pair at 3 Gauss points per cell (doc/verification.md, Figure 6 table):
  ! sigma' and p errors / q measured 0.0909 and 0.0956, total stress behind the front
  ! -1.0001 Pa, sigma' error of Standard MPM 3.66 times that of the pair (the
  ! bound asks for 2.8, 30 % below).
  real(wp), parameter :: U1_SIG = 0.118_wp, U1_P = 0.124_wp, U1_TOT = 0.05_wp, U1_GAIN = 2.8_wp
  ! The same as the 2D column of inputs/w1_2d.nml (100 x 2 cells), linear grid functions
  ! with the stresses at one Gauss point per cell (radial linear hat of 0.75 cells):
  ! sigma' and p errors / q measured 0.0585 and 0.0560 (bounds + 30 %), sigma' error of
  ! Standard MPM 3.13 times that of this choice (the bound asks for 2.2, 30 % below).
  real(wp), parameter :: G1_SIG = 0.076_wp, G1_P = 0.073_wp, G1_GAIN = 2.2_wp
  ! Immersed column (pore pressure on the drained top) at 0.2 s: largest |p - p_b| and
  ! |sigma'| measured 1.367e-3 and 1.362e-3 p_b, the undrained split E_c/(E_c + K_f/n_f)
  ! = 1.362e-3 that consolidation has not yet removed; bounds + 30 %. Without the face
  ! pore pressure: 0.95.
  real(wp), parameter :: IMM_P = 1.8e-3_wp, IMM_S = 1.8e-3_wp
  ! Energy balance (largest change of kinetic + stored - external work + drag
  ! dissipation, over the largest kinetic + stored energy): W1 measured 6.94e-3
  ! (implicit drag) and 2.52e-4 (explicit); T1 at T_v = 0.1 and 0.5 1.37e-3 and
  ! 5.18e-4; immersed column 1.35e-3. Bounds + 30 %. With the drag dissipation
  ! counted before the velocities of a held phase were zeroed, T1 and the immersed
  ! column gave 2.1 and 68.
  real(wp), parameter :: EN_W1(2) = [9.0e-3_wp, 3.3e-4_wp], EN_T1(2) = [1.8e-3_wp, 6.7e-4_wp], &
                         EN_IMM = 1.8e-3_wp
  ! Two-layer seepage at 0.5 s (doc/verification.md, "The porosity-gradient term"):
  ! cell means of p / p_b. With the term (the interphase force as the transpose of the
  ! mixture flux), away from the two cells at the interface, measured 2.17e-3 off the
  ! linear profile, and 0.0686 in the two cells (the earlier form of the force, which
  ! grew where water meets dry soil: 5.59e-4 and 0.0757). Without it,
  ! 2.49e-3 off the profile with n p continuous (all cells). Bounds + 30 %. Without
  ! the term the profile is 0.199 p_b off linear (must stay above 0.15).
  real(wp), parameter :: SEEP_TERM = 2.8e-3_wp, SEEP_IFACE = 0.089_wp, SEEP_NOTERM = 3.3e-3_wp, &
                         SEEP_KINK = 0.15_wp
  integer :: rank
  call start_tests(rank)
  call test_drag_solve_conserves_momentum()
  call test_w1_against_reference_and_drag_agreement()
  call test_w1_uniform_scatter_mls_pair_beats_standard_mpm()
  call test_w1_2d_linear_one_gauss_point_beats_standard_mpm()
  call test_w3_drag_agreement()
  call test_immersed_column_pore_pressure_face()
  call test_seepage_with_porosity_gradient_is_linear()
  call test_seepage_without_porosity_gradient_keeps_n_p_continuous()
  call test_t1_terzaghi(0.1_wp)
  call test_t1_terzaghi(0.5_wp)
  call end_tests()

contains

  !> Both drag solves conserve the momentum of the pair; the implicit one tends
  !> to the common acceleration of the mixture for a very large drag; the
  !> explicit limit is 2 / (D (1/m_s + 1/m_f)).
  subroutine test_drag_solve_conserves_momentum()
    real(wp) :: as, af
    call begin_test('drag_solve_conserves_momentum')
    call drag_solve(2.0_wp, 0.5_wp, 3.0_wp, 1.0_wp, -0.4_wp, 0.1_wp, 0.3_wp, 0.01_wp, .false., as, af)
    call check(abs(2.0_wp*as + 0.5_wp*af - 0.6_wp) < 1.0e-14_wp, 'explicit: m_s a_s + m_f a_f = f_s + f_f')
    call check(abs(as - (1.0_wp + 3.0_wp*0.2_wp)/2.0_wp) < 1.0e-14_wp, 'explicit: drag at the old velocities')
    call drag_solve(2.0_wp, 0.5_wp, 3.0_wp, 1.0_wp, -0.4_wp, 0.1_wp, 0.3_wp, 0.01_wp, .true., as, af)
    call check(abs(2.0_wp*as + 0.5_wp*af - 0.6_wp) < 1.0e-14_wp, 'implicit: m_s a_s + m_f a_f = f_s + f_f')
    ! The drag at the new velocities: m_s a_s = f_s + D (w + dt (a_f - a_s)).
    call check(abs(2.0_wp*as - (1.0_wp + 3.0_wp*(0.2_wp + 0.01_wp*(af - as)))) < 1.0e-13_wp, &
               'implicit: drag at the new velocities')
    call drag_solve(2.0_wp, 0.5_wp, 1.0e12_wp, 1.0_wp, -0.4_wp, 0.1_wp, 0.1_wp, 0.01_wp, .true., as, af)
    call check(abs(as - 0.24_wp) < 1.0e-9_wp .and. abs(af - 0.24_wp) < 1.0e-9_wp, &
               'implicit, huge drag: both phases take (f_s + f_f)/(m_s + m_f)')
    call check(abs(drag_limit(2.0_wp, 0.5_wp, 3.0_wp) - 2.0_wp/(3.0_wp*2.5_wp)) < 1.0e-15_wp, &
               'explicit drag limit 2 / (D (1/m_s + 1/m_f))')
  end subroutine test_drag_solve_conserves_momentum

  !> Run a scene on all ranks and return the errors against its two-phase
  !> reference (src/verify/dpmpm_two_phase_verify.f90), the solid and fluid
  !> points (rank 0, sorted by id), the step count and, if asked, the energy
  !> balance (largest change of the total energy / largest kinetic + stored).
  subroutine run_column(cfg, names, values, sx, ss, fx, fs, steps, drift)
    type(config_t), intent(in) :: cfg
    character(len=error_name_len), allocatable, intent(out) :: names(:)
    real(wp), allocatable, intent(out) :: values(:), sx(:, :), ss(:, :), fx(:, :), fs(:, :)
    integer(i8), intent(out) :: steps
    real(wp), intent(out), optional :: drift
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: v(:, :)
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    call two_phase_errors(sim%cfg, sim%mats, sim%phase(1)%pts, sim%phase(2)%pts, sim%time, MPI_COMM_WORLD, &
                          names, values)
    call sim%gather_points(ids, sx, v, ss)
    call sim%gather_points(ids, fx, v, fs, fluid=.true.)
    steps = sim%step
    if (present(drift)) drift = sim%energy_drift
    call sim%free()
  end subroutine run_column

  !> Print the errors of a run.
  subroutine print_errors(tag, names, values, steps)
    character(len=*), intent(in) :: tag
    character(len=*), intent(in) :: names(:)
    real(wp), intent(in) :: values(:)
    integer(i8), intent(in) :: steps
    integer :: k
    if (rank /= 0) return
    print '(a,a,i0,a)', tag, ' (', steps, ' steps):'
    do k = 1, size(names)
      print '(4x,a24,es11.3)', names(k), values(k)
    end do
  end subroutine print_errors

  !> Value of the named error.
  real(wp) function err(names, values, name)
    character(len=*), intent(in) :: names(:), name
    real(wp), intent(in) :: values(:)
    err = values(findloc(names, name, dim=1))
  end function err

  !> W1 (100 cells, 2 points of each phase per cell scattered in each cell) with
  !> implicit drag against algorithm A at 0.05 s, and the same with explicit drag:
  !> the same answer. Bounds: measured values (doc/verification.md) plus 30 %.
  subroutine test_w1_against_reference_and_drag_agreement()
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: vi(:), ve(:), sxi(:, :), ssi(:, :), fxi(:, :), fsi(:, :)
    real(wp), allocatable :: sxe(:, :), sse(:, :), fxe(:, :), fse(:, :)
    integer(i8) :: ni, ne
    real(wp) :: dsig, dp, eni, ene
    call begin_test('w1_against_reference_and_drag_agreement')
    call run_column(column_scene(100, 1.0e-5_wp, 3.0e6_wp, 0.05_wp, 'implicit'), names, vi, &
                    sxi, ssi, fxi, fsi, ni, eni)
    call print_errors('  W1, implicit drag', names, vi, ni)
    call run_column(column_scene(100, 1.0e-5_wp, 3.0e6_wp, 0.05_wp, 'explicit'), names, ve, &
                    sxe, sse, fxe, fse, ne, ene)
    call print_errors('  W1, explicit drag', names, ve, ne)
    if (rank == 0) print '(a,2es11.3)', '  energy balance, implicit and explicit drag:', eni, ene
    if (rank == 0) then
      dsig = sqrt(sum((ssi(1, :) - sse(1, :))**2)/size(ssi, 2))
      dp = sqrt(sum((fsi(1, :) - fse(1, :))**2)/size(fsi, 2))
      print '(a,2es11.3,a,f0.1)', '  implicit - explicit, RMS of sigma_eff and p (Pa):', dsig, dp, &
        '; step ratio ', real(ne, wp)/real(ni, wp)
      call check(err(names, vi, 'error_sigma_eff') <= W1_SIG, 'implicit: sigma_eff error within bound')
      call check(err(names, vi, 'error_pore_pressure') <= W1_P, 'implicit: pore pressure error within bound')
      call check(abs(err(names, vi, 'total_stress_behind_front') + 1.0_wp) <= W1_TOT, &
                 'implicit: total stress behind the front is -1 Pa')
      call check(err(names, ve, 'error_sigma_eff') <= W1_SIG, 'explicit: sigma_eff error within bound')
      call check(max(dsig, dp) <= W1_DRAG, 'implicit and explicit drag agree')
      call check(real(ne, wp)/real(ni, wp) > 50.0_wp, 'implicit drag takes far fewer steps')
      call check(eni <= EN_W1(1), 'implicit: energy balance within bound')
      call check(ene <= EN_W1(2), 'explicit: energy balance within bound')
    end if
  end subroutine test_w1_against_reference_and_drag_agreement

  !> W1 on points scattered uniformly over the column (the Figure 6 scene): Standard
  !> MPM is cut at cells that hold no point of either phase; the MLS pair (Wendland
  !> C2 reconstruction of sigma' and p at 3 Gauss points per cell, cubic grid
  !> functions) reaches the front, carries the 1 Pa behind it and is far closer
  !> to the reference.
  subroutine test_w1_uniform_scatter_mls_pair_beats_standard_mpm()
    type(config_t) :: cfg
    call begin_test('w1_uniform_scatter_mls_pair_beats_standard_mpm')
    cfg = column_scene(100, 1.0e-5_wp, 3.0e6_wp, 0.05_wp, 'implicit')
    call gauss_choice_against_standard_mpm(cfg, 'cubic', 3, 'wendland_c2', 2.0_wp, 'pair', &
                                           U1_SIG, U1_P, U1_GAIN)
  end subroutine test_w1_uniform_scatter_mls_pair_beats_standard_mpm

  !> W1 as the 2D column of inputs/w1_2d.nml (100 x 2 cells, uniform scatter, rollers on
  !> the side faces): linear grid functions with the stresses taken at one Gauss point
  !> per cell (MLS with the radial linear hat of radius 0.75 cells as weight, which
  !> reaches the whole cell and little of its neighbours) are far closer to the reference than
  !> Standard MPM, at the accuracy of the MLS pairs (doc/performance.md, "Speed against
  !> error", where this choice is the cheapest below an error of 0.1 in 2D).
  subroutine test_w1_2d_linear_one_gauss_point_beats_standard_mpm()
    type(config_t) :: cfg
    call begin_test('w1_2d_linear_one_gauss_point_beats_standard_mpm')
    cfg = column_scene(100, 1.0e-5_wp, 3.0e6_wp, 0.05_wp, 'implicit')
    cfg%ndim = 2
    cfg%ncells = [100, 2, 1]
    cfg%length = [10.0_wp, 0.2_wp, 1.0_wp]
    cfg%regions(1)%hi = [10.0_wp, 0.2_wp, 1.0_wp]
    cfg%bc(3:4) = bc_roller
    call gauss_choice_against_standard_mpm(cfg, 'linear', 1, 'linear', 0.75_wp, 'one Gauss point', &
                                           G1_SIG, G1_P, G1_GAIN)
  end subroutine test_w1_2d_linear_one_gauss_point_beats_standard_mpm

  !> The column cfg on the uniform scatter (seed 1, Courant number 0.3) with Standard MPM,
  !> then with Gauss quadrature (grid kernel, Gauss points per cell and axis, MLS field
  !> weight and radius): the Gauss choice's sigma' and p errors within sig and pbound,
  !> its total stress behind the front within U1_TOT of -1 Pa, and Standard MPM's sigma'
  !> error at least gain times the Gauss choice's.
  subroutine gauss_choice_against_standard_mpm(cfg, kernel, ngauss, field_kernel, field_radius, &
                                               label, sig, pbound, gain)
    type(config_t), intent(inout) :: cfg
    character(len=*), intent(in) :: kernel, field_kernel, label
    integer, intent(in) :: ngauss
    real(wp), intent(in) :: field_radius, sig, pbound, gain
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: vs(:), vg(:), sx(:, :), ss(:, :), fx(:, :), fs(:, :)
    integer(i8) :: ns, ng
    cfg%cfl = 0.3_wp
    cfg%regions(1)%placement = 'uniform'
    cfg%regions(1)%seed = 1
    call run_column(cfg, names, vs, sx, ss, fx, fs, ns)
    call print_errors('  W1, uniform scatter, Standard MPM', names, vs, ns)
    cfg%kernel = kernel
    cfg%quadrature = 'gauss'
    cfg%gauss_points = ngauss
    cfg%field_kernel = field_kernel
    cfg%field_radius = field_radius
    call run_column(cfg, names, vg, sx, ss, fx, fs, ng)
    call print_errors('  W1, uniform scatter, '//label, names, vg, ng)
    if (rank /= 0) return
    call check(err(names, vg, 'error_sigma_eff') <= sig, label//': sigma_eff error within bound')
    call check(err(names, vg, 'error_pore_pressure') <= pbound, label//': pore pressure error within bound')
    call check(abs(err(names, vg, 'total_stress_behind_front') + 1.0_wp) <= U1_TOT, &
               label//': total stress behind the front is -1 Pa')
    call check(err(names, vs, 'error_sigma_eff') >= gain*err(names, vg, 'error_sigma_eff'), &
               'Standard MPM is far less accurate on this scatter')
  end subroutine gauss_choice_against_standard_mpm

  !> W3 (real water, k = 1e-4 m/s, 4 ms): explicit and implicit drag give the same
  !> fields; the step counts show the gain (none here: the wave CFL governs).
  subroutine test_w3_drag_agreement()
    character(len=error_name_len), allocatable :: names(:)
    real(wp), allocatable :: vi(:), ve(:), sxi(:, :), ssi(:, :), fxi(:, :), fsi(:, :)
    real(wp), allocatable :: sxe(:, :), sse(:, :), fxe(:, :), fse(:, :)
    integer(i8) :: ni, ne
    real(wp) :: dsig, dp
    call begin_test('w3_drag_agreement')
    call run_column(column_scene(100, 1.0e-4_wp, 2.2e9_wp, 4.0e-3_wp, 'implicit'), names, vi, &
                    sxi, ssi, fxi, fsi, ni)
    call print_errors('  W3, implicit drag', names, vi, ni)
    call run_column(column_scene(100, 1.0e-4_wp, 2.2e9_wp, 4.0e-3_wp, 'explicit'), names, ve, &
                    sxe, sse, fxe, fse, ne)
    call print_errors('  W3, explicit drag', names, ve, ne)
    if (rank == 0) then
      dsig = sqrt(sum((ssi(1, :) - sse(1, :))**2)/size(ssi, 2))
      dp = sqrt(sum((fsi(1, :) - fse(1, :))**2)/size(fsi, 2))
      print '(a,2es11.3,a,f0.2)', '  implicit - explicit, RMS of sigma_eff and p (Pa):', dsig, dp, &
        '; step ratio ', real(ne, wp)/real(ni, wp)
      call check(max(dsig, dp) <= W3_DRAG, 'implicit and explicit drag agree')
      call check(err(names, vi, 'error_pore_pressure') <= W3_P, 'implicit: pore pressure error within bound')
    end if
  end subroutine test_w3_drag_agreement

  !> A column under water: the drained top takes the pore pressure p_b and the
  !> total traction -p_b (both ramped over 0.02 s), so the exact state is p = p_b
  !> and sigma' = 0 everywhere (up to the undrained split, sigma' = -E_c/(E_c + K_f/n_f)
  !> p_b = -0.0014 p_b, that consolidation removes). Without the face pore pressure
  !> the top drains to p = 0 instead: the control run must miss by far more.
  subroutine test_immersed_column_pore_pressure_face()
    real(wp), parameter :: pb = 1.0e3_wp
    type(config_t) :: cfg
    real(wp) :: ep, es, ep0, es0, drift
    call begin_test('immersed_column_pore_pressure_face')
    cfg = column_scene(10, 1.0e-4_wp, 2.2e9_wp, 0.2_wp, 'implicit')
    cfg%length(1) = 1.0_wp
    cfg%regions(1)%hi(1) = 1.0_wp
    cfg%benchmark = 'none'
    cfg%loads(1) = load_cfg_t(face=1, traction=[pb, 0.0_wp, 0.0_wp], ramp_time=0.02_wp)
    cfg%pore_pressure_ramp(1) = 0.02_wp
    cfg%pore_pressure(1) = pb
    call immersed_errors(cfg, pb, ep, es, drift)
    cfg%pore_pressure(1) = 0.0_wp
    call immersed_errors(cfg, pb, ep0, es0)
    if (rank == 0) then
      print '(a,2es11.3,a,2es11.3)', '  largest |p - p_b| / p_b, |sigma''| / p_b:', ep, es, &
        '; without the face pore pressure:', ep0, es0
      call check(ep <= IMM_P, 'pore pressure p_b everywhere')
      call check(es <= IMM_S, 'effective stress 0 everywhere')
      call check(ep0 >= 10.0_wp*IMM_P, 'the face pore pressure is what holds p_b at the top')
      call check(drift <= EN_IMM, 'energy balance with the face pore pressure within bound')
    end if
  end subroutine test_immersed_column_pore_pressure_face

  !> Largest |p - pb| / pb over the fluid points and |sigma'| / pb over the solid
  !> points at the end of scene c (on rank 0).
  subroutine immersed_errors(c, pb, ep, es, drift)
    type(config_t), intent(in) :: c
    real(wp), intent(in) :: pb
    real(wp), intent(out) :: ep, es
    real(wp), intent(out), optional :: drift
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), s(:, :)
    call sim%init(c, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    ep = 0.0_wp; es = 0.0_wp
    call sim%gather_points(ids, x, v, s, fluid=.true.)
    if (rank == 0) ep = maxval(abs(-s(1, :) - pb))/pb
    call sim%gather_points(ids, x, v, s)
    if (rank == 0) es = maxval(abs(s(1, :)))/pb
    if (present(drift)) drift = sim%energy_drift
    call sim%free()
  end subroutine immersed_errors

  !> Steady seepage through two saturated layers (1 m along x, 20 cells, n_f = 0.3
  !> on [0, 0.5] and 0.5 on [0.5, 1], k = 1e-3 m/s, K_f = 22 MPa, regular points),
  !> solid fixed at both ends, both faces drained, p_b = 1 kPa on x- (ramped over
  !> 0.05 s), run to 0.5 s. The Darcy flux n_f (v_f - v_s) = -(k / gamma_w) grad p
  !> is the same in both layers, so with equal k the exact p is linear.
  function seepage_scene(with_term) result(cfg)
    logical, intent(in) :: with_term
    type(config_t) :: cfg
    integer :: r
    cfg = column_scene(20, 1.0e-3_wp, 2.2e7_wp, 0.5_wp, 'implicit')
    cfg%length(1) = 1.0_wp
    cfg%benchmark = 'none'
    cfg%porosity_gradient = with_term
    deallocate (cfg%regions, cfg%loads)
    allocate (cfg%regions(2), cfg%loads(0))
    do r = 1, 2
      cfg%regions(r) = region_cfg_t(lo=[0.5_wp*(r - 1), 0.0_wp, 0.0_wp], &
                                    hi=[0.5_wp*r, 1.0_wp, 1.0_wp], material=1, fluid_material=2, &
                                    phase='saturated', porosity=0.1_wp + 0.2_wp*r, ppc=2, &
                                    placement='regular')
    end do
    cfg%bc(1:2) = bc_fixed
    cfg%fluid_bc(1:2) = fbc_drained
    cfg%pore_pressure(1) = 1.0e3_wp
    cfg%pore_pressure_ramp(1) = 0.05_wp
  end function seepage_scene

  !> Cell means of the pore pressure of the seepage scene at its end (rank 0).
  subroutine seepage_cell_means(with_term, pm)
    logical, intent(in) :: with_term
    real(wp), intent(out) :: pm(:)
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), s(:, :)
    real(wp) :: cnt(size(pm))
    integer :: k, ic, nc
    nc = size(pm)
    call sim%init(seepage_scene(with_term), MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    call sim%gather_points(ids, x, v, s, fluid=.true.)
    call sim%free()
    pm = 0.0_wp; cnt = 0.0_wp
    if (rank /= 0) return
    do k = 1, size(ids)
      ic = min(nc, max(1, int(x(1, k)*nc) + 1))
      pm(ic) = pm(ic) - s(1, k)
      cnt(ic) = cnt(ic) + 1.0_wp
    end do
    pm = pm/cnt
  end subroutine seepage_cell_means

  !> Largest |pm - pref(cell centre)| / p_b over the cells away from the interface
  !> (centre more than one cell from x = 0.5) and over the two cells at it; pref is
  !> the linear profile or, with jump, the profile of a continuous n p (p drops
  !> from 735.3 to 441.2 Pa at the interface).
  subroutine seepage_errors(pm, jump, eaway, eiface)
    real(wp), intent(in) :: pm(:)
    logical, intent(in) :: jump
    real(wp), intent(out) :: eaway, eiface
    real(wp) :: xc, e, c
    integer :: ic, nc
    nc = size(pm)
    ! Continuous n p: 0.3 (p_b - 0.3 c/2) = 0.5 (0.5 c/2), so c = 0.3 p_b/0.17 (grad p = -n c).
    c = 0.3_wp*1.0e3_wp/0.17_wp
    eaway = 0.0_wp; eiface = 0.0_wp
    do ic = 1, nc
      xc = (ic - 0.5_wp)/nc
      if (jump) then
        e = merge(1.0e3_wp - 0.3_wp*c*xc, 0.5_wp*c*(1.0_wp - xc), xc < 0.5_wp)
      else
        e = 1.0e3_wp*(1.0_wp - xc)
      end if
      e = abs(pm(ic) - e)/1.0e3_wp
      if (abs(xc - 0.5_wp) > 1.0_wp/nc) then
        eaway = max(eaway, e)
      else
        eiface = max(eiface, e)
      end if
    end do
  end subroutine seepage_errors

  !> With the porosity-gradient term (flux form of eq. 10 and the interphase force
  !> p grad n_f of eq. 2) the two-layer seepage is linear away from the interface,
  !> and the two cells at it stay within their measured error.
  subroutine test_seepage_with_porosity_gradient_is_linear()
    real(wp) :: pm(20), eaway, eiface
    call begin_test('seepage_with_porosity_gradient_is_linear')
    call seepage_cell_means(.true., pm)
    if (rank == 0) then
      call seepage_errors(pm, .false., eaway, eiface)
      print '(a,2es11.3)', '  cell-mean |p - linear| / p_b away from / at the interface:', eaway, eiface
      call check(eaway <= SEEP_TERM, 'linear pore pressure away from the interface')
      call check(eiface <= SEEP_IFACE, 'interface cells within their measured error')
    end if
  end subroutine test_seepage_with_porosity_gradient_is_linear

  !> Without the term (the paper's choice, grad n_f = 0 in eqs. 5 and 10) the same
  !> scene keeps v_f and n_f p continuous: p follows that profile, and misses the
  !> linear one by far more than the bound above.
  subroutine test_seepage_without_porosity_gradient_keeps_n_p_continuous()
    real(wp) :: pm(20), eaway, eiface, elin, elin2
    call begin_test('seepage_without_porosity_gradient_keeps_n_p_continuous')
    call seepage_cell_means(.false., pm)
    if (rank == 0) then
      call seepage_errors(pm, .true., eaway, eiface)
      call seepage_errors(pm, .false., elin, elin2)
      elin = max(elin, elin2)
      print '(a,3es11.3)', '  cell-mean |p - continuous n p| / p_b away, at the interface; '// &
        'off linear:', eaway, eiface, elin
      call check(max(eaway, eiface) <= SEEP_NOTERM, 'pore pressure with n p continuous')
      call check(elin >= SEEP_KINK, 'without the term the profile is not linear')
    end if
  end subroutine test_seepage_without_porosity_gradient_keeps_n_p_continuous

  !> T1: Terzaghi consolidation of a 1 m layer with real water (doc/theory.md 9.3),
  !> load ramped over 0.02 s; pore pressure and settlement at time factor tv.
  subroutine test_t1_terzaghi(tv)
    real(wp), intent(in) :: tv
    type(simulation_t) :: sim
    type(config_t) :: cfg
    type(terzaghi_t) :: ter
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), s(:, :)
    real(wp) :: t, ep, es, sref, u0
    integer :: k
    character(len=16) :: tag
    write (tag, '(f0.2)') tv
    call begin_test('t1_terzaghi_at_tv_'//trim(tag))
    ter = terzaghi_t(height=1.0_wp, porosity=0.3_wp, e_c=1.0e7_wp, k_f=2.2e9_wp, &
                     conductivity=1.0e-4_wp, load=1.0e3_wp)
    t = tv*ter%height**2/terzaghi_cv(ter)
    cfg = column_scene(10, 1.0e-4_wp, 2.2e9_wp, t, 'implicit')
    cfg%length(1) = 1.0_wp
    cfg%regions(1)%hi(1) = 1.0_wp
    cfg%loads(1) = load_cfg_t(face=1, traction=[1.0e3_wp, 0.0_wp, 0.0_wp], ramp_time=0.02_wp)
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    ! The ramp delays the load by half its length.
    t = sim%time - 0.01_wp
    call sim%gather_points(ids, x, v, s, fluid=.true.)
    if (rank == 0) then
      ep = 0.0_wp
      do k = 1, size(ids)
        ep = max(ep, abs(-s(1, k) - terzaghi_pressure(ter, x(1, k), t)))
      end do
      ep = ep/terzaghi_p0(ter)
      print '(a,es10.3)', '  largest pore-pressure error / p0: ', ep
      call check(ep <= T1_P(merge(1, 2, tv < 0.3_wp)), 'pore pressure within bound')
    end if
    call sim%gather_points(ids, x, v, s)
    if (rank == 0) then
      ! Settlement: the displacement of the solid points nearest the top, extrapolated
      ! to the top with the strain sigma'/E_c there.
      k = minloc(x(1, :), dim=1)
      u0 = displacement_at(sim, ids(k)) - x(1, k)*s(1, k)/1.0e7_wp
      sref = terzaghi_settlement(ter, t)
      es = abs(u0 - sref)/(ter%load*ter%height/ter%e_c)
      print '(a,3es12.4)', '  settlement, reference, error / (q H / E_c): ', u0, sref, es
      call check(es <= T1_S(merge(1, 2, tv < 0.3_wp)), 'settlement within bound')
      call check(sim%energy_drift <= EN_T1(merge(1, 2, tv < 0.3_wp)), &
                 'energy balance (work of the load = stored + dissipated by drag) within bound')
    end if
    call sim%free()
  end subroutine test_t1_terzaghi

  !> Displacement x - x0 of the solid point with global id gid (rank 0 gathers).
  real(wp) function displacement_at(sim, gid) result(u)
    type(simulation_t), intent(in) :: sim
    integer(i8), intent(in) :: gid
    integer :: k
    u = 0.0_wp
    do k = 1, sim%phase(1)%pts%n
      if (sim%phase(1)%pts%id(k) == gid) u = sim%phase(1)%pts%x(1, k) - sim%phase(1)%pts%x0(1, k)
    end do
  end function displacement_at

end program test_two_phase
