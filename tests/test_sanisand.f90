!> SANISAND (dpmpm_model_sanisand) on element paths of the element driver with the paper's
!> Toyoura sand (Dafalias & Manzari 2004): monotonic undrained and drained triaxial
!> compression of a loose and a dense sand, which must end on the critical state line
!> (q/p' = M, e = e_c(p')), with the loose undrained sand softening and the dense one
!> dilating; cyclic undrained triaxial tests at three cyclic stress ratios that must
!> liquefy (r_u >= 0.95) in fewer cycles at a higher ratio, with the butterfly path after;
!> and the integration itself: one large step against many small ones (also across a load
!> reversal), a pure spin that
!> keeps the point on its yield surface, a failure that is reported. Measured values and
!> the margins of the bounds: doc/verification.md, "SANISAND".
program test_sanisand
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_test_stress, only: pq
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: material_cfg_t
  use dpmpm_element_config, only: element_cfg_t
  use dpmpm_element_path, only: element_history_t, run_element, element_ok
  use dpmpm_materials, only: material_t, materials_from_config, init_state, stress_update
  use dpmpm_model_sanisand, only: sanisand_integrate, sanisand_yield
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int
  implicit none
  !> Toyoura sand: M and nu (the other constants are the defaults of &material)
  real(wp), parameter :: mcs = 1.25_wp, nu = 0.05_wp
  real(wp), parameter :: ec0 = 0.934_wp, lamc = 0.019_wp, xi = 0.7_wp, pat = 101.0e3_wp
  call start_tests()
  call test_undrained_loose_softens_to_the_critical_state()
  call test_undrained_dense_dilates_to_the_critical_state()
  call test_drained_loose_contracts_to_the_critical_state()
  call test_drained_dense_peaks_and_dilates_towards_the_critical_state()
  call test_cyclic_undrained_liquefies_sooner_at_higher_stress_ratio()
  call test_one_large_step_matches_many_small_ones()
  call test_reversal_in_one_step_matches_many_small_ones()
  call test_spin_keeps_the_point_on_its_yield_surface()
  call test_failed_integration_is_reported()
  call end_tests()

contains

  !> An element test of Toyoura sand at void ratio e0 from the isotropic p0.
  function sand_test(path, control, e0, p0) result(cfg)
    character(len=*), intent(in) :: path, control
    real(wp), intent(in) :: e0, p0
    type(element_cfg_t) :: cfg
    cfg%material%model = 'sanisand'
    cfg%material%critical_state_ratio = mcs
    cfg%material%poisson_ratio = nu
    cfg%material%void_ratio = e0
    cfg%path = path
    cfg%control = control
    cfg%p0 = p0
    cfg%void_ratio = e0
    ! the stress conditions within the noise of the adaptive substeps (1e-5 by default)
    cfg%tolerance = 1.0e-6_wp
  end function sand_test

  !> The sand of a test as a material.
  function sand(cfg) result(mat)
    type(element_cfg_t), intent(in) :: cfg
    type(material_t) :: mat
    type(material_t), allocatable :: mats(:)
    call materials_from_config([cfg%material], mats)
    mat = mats(1)
  end function sand

  !> Run cfg.
  function run(cfg) result(h)
    type(element_cfg_t), intent(in) :: cfg
    type(element_history_t) :: h
    call run_element(cfg, sand(cfg), h)
  end function run

  !> The critical void ratio at p' (Pa).
  elemental real(wp) function e_crit(p)
    real(wp), intent(in) :: p
    e_crit = ec0 - lamc*(p/pat)**xi
  end function e_crit

  !> The distance of the end of path h from the critical state: |q/p' - M|/M and
  !> |psi| = |e - e_c(p')| with the model's own void ratio; printed.
  subroutine critical_state_distance(h, deta, dpsi)
    type(element_history_t), intent(in) :: h
    real(wp), intent(out) :: deta, dpsi
    integer :: n
    n = h%nrec
    deta = abs(h%q(n)/h%p(n) - mcs)/mcs
    dpsi = abs(h%state(19, n) - e_crit(h%p(n)))
    print '(a,es10.3,a,es10.3,a,es10.3,a,es10.3)', '  end p'' = ', h%p(n), ' Pa, q = ', h%q(n), &
      ' Pa: |q/p''/M - 1| = ', deta, ', |psi| = ', dpsi
  end subroutine critical_state_distance

  !> Undrained triaxial compression of loose sand (e = 0.907, p'0 = 1 MPa, psi0 = +0.07):
  !> the deviator peaks at a small strain, then the sand contracts and softens (static
  !> liquefaction) to the critical state at a much lower p'.
  subroutine test_undrained_loose_softens_to_the_critical_state()
    type(element_cfg_t) :: cfg
    type(element_history_t) :: h
    real(wp) :: deta, dpsi, qmax
    integer :: kmax
    call begin_test('undrained_loose_softens_to_the_critical_state')
    cfg = sand_test('triaxial_undrained', 'strain', 0.907_wp, 1.0e6_wp)
    cfg%axial_strain = 0.3_wp
    cfg%steps = 300
    h = run(cfg)
    call check_equal_int(h%status, element_ok, 'the path is complete')
    kmax = maxloc(h%q(1:h%nrec), dim=1)
    qmax = h%q(kmax)
    print '(a,es10.3,a,f6.4,a,es10.3)', '  peak q = ', qmax, ' Pa at eps_a = ', &
      h%axial_strain(kmax), ', end q = ', h%q(h%nrec)
    ! measured: peak 426 kPa at eps_a = 0.010, end q 213 kPa (half the peak)
    call check(h%axial_strain(kmax) < 0.03_wp, 'the peak comes at a small strain')
    call check(h%q(h%nrec) < 0.6_wp*qmax, 'the sand softens after the peak')
    call check(all(h%p(2:h%nrec) <= h%p(1:h%nrec - 1) + 1.0e-6_wp*cfg%p0), &
               'p'' falls all along (contraction)')
    call critical_state_distance(h, deta, dpsi)
    ! measured 7.3e-5 and 1.0e-5: margins of about 14 and 100
    call check(deta <= 1.0e-3_wp, 'q/p'' = M at the end')
    call check(dpsi <= 1.0e-3_wp, 'e = e_c(p'') at the end')
  end subroutine test_undrained_loose_softens_to_the_critical_state

  !> Undrained triaxial compression of dense sand (e = 0.735, p'0 = 100 kPa, psi0 = -0.18):
  !> p' dips a little to the phase transformation, then the sand dilates and p' and q grow
  !> some thirtyfold to the critical state.
  subroutine test_undrained_dense_dilates_to_the_critical_state()
    type(element_cfg_t) :: cfg
    type(element_history_t) :: h
    real(wp) :: deta, dpsi, pmin
    call begin_test('undrained_dense_dilates_to_the_critical_state')
    cfg = sand_test('triaxial_undrained', 'strain', 0.735_wp, 1.0e5_wp)
    cfg%axial_strain = 0.4_wp
    cfg%steps = 400
    h = run(cfg)
    call check_equal_int(h%status, element_ok, 'the path is complete')
    pmin = minval(h%p(1:h%nrec))
    print '(a,es10.3,a,es10.3)', '  least p'' = ', pmin, ' Pa, end p'' = ', h%p(h%nrec)
    ! measured: least p' 97.2 kPa, end 2.90 MPa
    call check(pmin > 0.9_wp*cfg%p0, 'a shallow dip of p'' to the phase transformation')
    call check(h%p(h%nrec) > 20.0_wp*cfg%p0, 'dilation: p'' grows many times')
    call critical_state_distance(h, deta, dpsi)
    ! measured 1.6e-6 and 4.5e-5: margins of 600 and 22
    call check(deta <= 1.0e-3_wp, 'q/p'' = M at the end')
    call check(dpsi <= 1.0e-3_wp, 'e = e_c(p'') at the end')
  end subroutine test_undrained_dense_dilates_to_the_critical_state

  !> Drained triaxial compression of loose sand (e = 0.93, p'0 = 100 kPa, psi0 = +0.015):
  !> it contracts and hardens, without a peak, to the critical state.
  subroutine test_drained_loose_contracts_to_the_critical_state()
    type(element_cfg_t) :: cfg
    type(element_history_t) :: h
    real(wp) :: deta, dpsi
    call begin_test('drained_loose_contracts_to_the_critical_state')
    cfg = sand_test('triaxial_drained', 'strain', 0.93_wp, 1.0e5_wp)
    cfg%axial_strain = 0.4_wp
    cfg%steps = 400
    h = run(cfg)
    call check_equal_int(h%status, element_ok, 'the path is complete')
    print '(a,es10.3)', '  end eps_v = ', h%volumetric_strain(h%nrec)
    call check(all(h%volumetric_strain(2:h%nrec) > 0.0_wp), 'contraction all along')
    call check(h%q(h%nrec) >= maxval(h%q(1:h%nrec))*(1.0_wp - 1.0e-3_wp), 'no peak')
    call critical_state_distance(h, deta, dpsi)
    ! measured 6.8e-5 and 1.1e-5: margins of about 15 and 90
    call check(deta <= 1.0e-3_wp, 'q/p'' = M at the end')
    call check(dpsi <= 1.0e-3_wp, 'e = e_c(p'') at the end')
  end subroutine test_drained_loose_contracts_to_the_critical_state

  !> Drained triaxial compression of dense sand (e = 0.735, p'0 = 100 kPa): a peak of q/p'
  !> above M at a few per cent strain, dilation, and a slow approach to the critical state
  !> (the dilation fades as psi goes to 0; at eps_a = 0.6 it is not quite there).
  subroutine test_drained_dense_peaks_and_dilates_towards_the_critical_state()
    type(element_cfg_t) :: cfg
    type(element_history_t) :: h
    real(wp) :: deta, dpsi, etamax
    integer :: kmax
    call begin_test('drained_dense_peaks_and_dilates_towards_the_critical_state')
    cfg = sand_test('triaxial_drained', 'strain', 0.735_wp, 1.0e5_wp)
    cfg%axial_strain = 0.6_wp
    cfg%steps = 300
    h = run(cfg)
    call check_equal_int(h%status, element_ok, 'the path is complete')
    kmax = maxloc(h%q(1:h%nrec)/h%p(1:h%nrec), dim=1)
    etamax = h%q(kmax)/h%p(kmax)
    print '(a,f7.4,a,f6.4,a,es10.3)', '  peak q/p'' = ', etamax, ' at eps_a = ', &
      h%axial_strain(kmax), ', end eps_v = ', h%volumetric_strain(h%nrec)
    ! measured 1.474 = 1.18 M at eps_a = 0.03
    call check(etamax > 1.1_wp*mcs, 'a peak stress ratio well above M')
    call check(h%volumetric_strain(h%nrec) < -0.05_wp, 'dilation')
    call critical_state_distance(h, deta, dpsi)
    ! measured 2.6e-3 and 2.2e-3 (still dilating slowly): margins of about 2
    call check(deta <= 5.0e-3_wp, 'q/p'' near M at eps_a = 0.6')
    call check(dpsi <= 4.0e-3_wp, 'e near e_c(p'') at eps_a = 0.6')
  end subroutine test_drained_dense_peaks_and_dilates_towards_the_critical_state

  !> Cyclic undrained triaxial tests of loose sand (e = 0.85, p'0 = 100 kPa), stress
  !> controlled, q = +-2 CSR p'0: the excess pore pressure ratio r_u = u/p'0 reaches 0.95
  !> (liquefaction), in fewer cycles at a higher cyclic stress ratio; after it, the
  !> butterfly: p' near 0 where q crosses 0, regained by dilation where q peaks.
  subroutine test_cyclic_undrained_liquefies_sooner_at_higher_stress_ratio()
    type(element_cfg_t) :: cfg
    type(element_history_t) :: h
    real(wp), parameter :: csr(3) = [0.1_wp, 0.15_wp, 0.2_wp]
    real(wp) :: ncyc(3), ru, pafter
    integer :: j, k, kliq
    call begin_test('cyclic_undrained_liquefies_sooner_at_higher_stress_ratio')
    do j = 1, size(csr)
      cfg = sand_test('triaxial_undrained', 'stress', 0.85_wp, 1.0e5_wp)
      cfg%cycles = 8
      cfg%steps = 100
      cfg%amplitude = 2.0_wp*csr(j)*cfg%p0
      h = run(cfg)
      call check_equal_int(h%status, element_ok, 'the path is complete')
      kliq = 0
      do k = 1, h%nrec
        ru = h%excess_pore_pressure(k)/cfg%p0
        if (ru >= 0.95_wp) then
          kliq = k
          exit
        end if
      end do
      call check(kliq > 0, 'r_u reaches 0.95')
      if (kliq == 0) return
      ncyc(j) = h%cycle(kliq)
      ! the largest p' over the next half cycle after liquefaction
      pafter = maxval(h%p(kliq:min(h%nrec, kliq + cfg%steps/2)))
      print '(a,f5.3,a,f6.3,a,f6.3,a,es10.3)', '  CSR ', csr(j), ': r_u >= 0.95 after ', &
        ncyc(j), ' cycles; max r_u ', maxval(h%excess_pore_pressure(1:h%nrec))/cfg%p0, &
        ', p'' regained in the next half cycle ', pafter
      call check(maxval(h%excess_pore_pressure(1:h%nrec))/cfg%p0 > 0.98_wp, 'r_u near 1')
      call check(pafter > 0.1_wp*cfg%p0, 'the butterfly: dilation regains p'' at the peaks')
    end do
    call check(ncyc(1) > ncyc(2) .and. ncyc(2) > ncyc(3), 'fewer cycles at a higher CSR')
  end subroutine test_cyclic_undrained_liquefies_sooner_at_higher_stress_ratio

  !> One call over an undrained (isochoric) axial strain of 2 % from p'0 = 100 kPa against
  !> 200 calls of 0.01 % at a tight tolerance: the same straight strain path, so the same
  !> end within the error of the substeps, which falls with the tolerance.
  subroutine test_one_large_step_matches_many_small_ones()
    type(element_cfg_t) :: cfg
    type(material_t) :: mat
    real(wp) :: s(6), st(19), sref(6), de(6), w, d(3)
    real(wp), parameter :: tols(3) = [1.0e-4_wp, 1.0e-6_wp, 1.0e-8_wp]
    integer :: code, nsub, k, j
    call begin_test('one_large_step_matches_many_small_ones')
    cfg = sand_test('triaxial_undrained', 'strain', 0.85_wp, 1.0e5_wp)
    cfg%material%integration_tolerance = 1.0e-10_wp
    mat = sand(cfg)
    de = [0.5_wp, 0.5_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]*0.02_wp
    call start(mat, sref, st)
    do k = 1, 200
      call sanisand_integrate(mat, de/200.0_wp, sref, st, code, w, nsub)
      call check_equal_int(code, 0, 'a small step integrates')
    end do
    do j = 1, size(tols)
      mat%sd_tol = tols(j)
      call start(mat, s, st)
      call sanisand_integrate(mat, de, s, st, code, w, nsub)
      call check_equal_int(code, 0, 'the large step integrates')
      d(j) = maxval(abs(s - sref))/1.0e5_wp
      print '(a,es8.1,a,i0,a,es10.3)', '  tolerance ', tols(j), ': ', nsub, &
        ' substeps, largest stress difference over p''0 ', d(j)
    end do
    call check(d(2) < d(1) .and. d(3) < d(2), 'the difference falls with the tolerance')
    ! measured 1.5e-3, 2.6e-7, 2.6e-9: a margin of 4 on the last
    call check(d(3) <= 1.0e-8_wp, 'the large step at tolerance 1e-8 matches')
  end subroutine test_one_large_step_matches_many_small_ones

  !> A load reversal inside one step: after isochoric compression to eps_a = 0.5 %, one
  !> call of eps_a = -1 % unloads through the yield cone (elastic), crosses it on the other
  !> side and loads in extension (alpha_in set at the crossing); 200 calls of the same
  !> strain path at a tight tolerance give the same end.
  subroutine test_reversal_in_one_step_matches_many_small_ones()
    type(element_cfg_t) :: cfg
    type(material_t) :: mat
    real(wp) :: s(6), st(19), sref(6), stref(19), s1(6), st1(19), dload(6), w, d, da
    integer :: code, nsub, k
    call begin_test('reversal_in_one_step_matches_many_small_ones')
    cfg = sand_test('triaxial_undrained', 'strain', 0.85_wp, 1.0e5_wp)
    cfg%material%integration_tolerance = 1.0e-10_wp
    mat = sand(cfg)
    dload = [0.5_wp, 0.5_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]*0.005_wp
    call start(mat, s1, st1)
    call sanisand_integrate(mat, dload, s1, st1, code, w, nsub)
    call check_equal_int(code, 0, 'the loading integrates')
    sref = s1
    stref = st1
    do k = 1, 200
      call sanisand_integrate(mat, -2.0_wp*dload/200.0_wp, sref, stref, code, w, nsub)
      call check_equal_int(code, 0, 'a small step integrates')
    end do
    mat%sd_tol = 1.0e-8_wp
    s = s1
    st = st1
    call sanisand_integrate(mat, -2.0_wp*dload, s, st, code, w, nsub)
    call check_equal_int(code, 0, 'the reversing step integrates')
    d = maxval(abs(s - sref))/1.0e5_wp
    da = maxval(abs(st(1:18) - stref(1:18)))
    print '(a,i0,a,es10.3,a,es10.3,a,f8.3)', '  ', nsub, ' substeps; stress difference over p''0 ', &
      d, ', state ', da, '; q at the end (kPa) ', 1.0e-3_wp*(0.5_wp*(s(1) + s(2)) - s(3))
    call check(0.5_wp*(s(1) + s(2)) - s(3) < 0.0_wp, 'the end is in extension')
    ! measured 1.3e-9 and 1.0e-9 (17741 substeps): margins of about 8 and 10
    call check(d <= 1.0e-8_wp, 'the stress of one step matches')
    call check(da <= 1.0e-8_wp, 'alpha, z and alpha_in of one step match')
  end subroutine test_reversal_in_one_step_matches_many_small_ones

  !> A point on its yield surface (after some undrained shear) turned by a pure spin:
  !> stress and alpha turn together, so the point stays on the surface and keeps p' and q.
  subroutine test_spin_keeps_the_point_on_its_yield_surface()
    type(element_cfg_t) :: cfg
    type(material_t) :: mat
    real(wp) :: s(6), st(19), de(6), w, y(12), vg(9, 1), ss(6, 1), sts(19, 1), vol(1), v0(1), f
    real(wp) :: p0, q0, p1, q1
    integer :: code, nsub
    call begin_test('spin_keeps_the_point_on_its_yield_surface')
    cfg = sand_test('triaxial_undrained', 'strain', 0.85_wp, 1.0e5_wp)
    mat = sand(cfg)
    call start(mat, s, st)
    de = [0.5_wp, 0.5_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]*0.005_wp
    call sanisand_integrate(mat, de, s, st, code, w, nsub)
    call pq(s, p0, q0)
    ! W = (L - L^T)/2 with L(1,3) = -L(3,1) = 0.02 / dt, the rest zero
    vg = 0.0_wp
    vg(7, 1) = 0.02_wp
    vg(3, 1) = -0.02_wp
    ss(:, 1) = s
    sts(:, 1) = st
    vol = 1.0_wp
    v0 = 1.0_wp
    call stress_update(mat, 1, 1.0_wp, 1, [1], vg, ss, vol, v0, state=sts, plane=.false.)
    call pq(ss(:, 1), p1, q1)
    y(1:6) = -ss(:, 1)
    y(7:12) = sts(1:6, 1)
    f = sanisand_yield(mat, y)
    print '(a,es10.3,a,es10.3)', '  f/p'' after the spin ', f/p1, ', |q1/q0 - 1| ', abs(q1/q0 - 1.0_wp)
    ! measured 3e-17 (alpha put back on the surface at the start of the integration) and
    ! 6.0e-4: the Jaumann turn is exact to first order in its angle (0.02 rad); margins of
    ! 1e5 over round-off and 3
    call check(abs(f) <= 1.0e-12_wp*p1, 'on the yield surface')
    call check(abs(s(5)) < 1.0e-12_wp*q0 .and. abs(ss(5, 1)) > 1.0e-3_wp*q0, &
               'the stress has turned')
    call check_close(p1, p0, 1.0e-12_wp, 0.0_wp, 'p'' kept')
    call check_close(q1, q0, 2.0e-3_wp, 0.0_wp, 'q kept (to second order in the angle)')
  end subroutine test_spin_keeps_the_point_on_its_yield_surface

  !> An integration that cannot meet its tolerance (1e-30, below round-off: every substep
  !> is rejected until it is below 1e-12 of the increment) is reported with a code, and the
  !> stress and state come back as they were.
  subroutine test_failed_integration_is_reported()
    type(element_cfg_t) :: cfg
    type(material_t) :: mat
    real(wp) :: s(6), st(19), s0(6), st0(19), de(6), w
    integer :: code, nsub
    call begin_test('failed_integration_is_reported')
    cfg = sand_test('triaxial_undrained', 'strain', 0.85_wp, 1.0e5_wp)
    mat = sand(cfg)
    mat%sd_tol = 1.0e-30_wp
    call start(mat, s, st)
    s0 = s
    st0 = st
    de = [0.5_wp, 0.5_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]*0.01_wp
    call sanisand_integrate(mat, de, s, st, code, w, nsub)
    call check(code /= 0, 'the failure is reported')
    call check(all(s == s0) .and. all(st == st0), 'stress and state unchanged')
  end subroutine test_failed_integration_is_reported

  !> The isotropic stress p'0 = 100 kPa and its initial state.
  subroutine start(mat, s, st)
    type(material_t), intent(in) :: mat
    real(wp), intent(out) :: s(6), st(19)
    real(wp) :: ss(6, 1), sts(19, 1)
    s = [-1.0e5_wp, -1.0e5_wp, -1.0e5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    ss(:, 1) = s
    sts = 0.0_wp
    call init_state(mat, 1, 1, [1], ss, sts)
    st = sts(:, 1)
  end subroutine start

end program test_sanisand
