!> Dilatancy of the mu(I) rheology (dpmpm_model_mu_i, doc/theory.md 5.9 "Dilatancy") against
!> its own equations and its closed forms, with the formulas written out here: the return
!> solves p = p_tr + K_b dt x tan(psi), tau = tau_tr - G dt x = (mu(I) + tan(psi)) p with
!> tan(psi) = K (phi - phi_c + a I); sheared at constant volume, a loose point (phi < phi_c)
!> loses pressure down to p* = rho_s (gdot d/I*)^2, I* = (phi_c - phi)/a, and a dense one
!> gains pressure; sheared at constant normal stress, the volume fraction relaxes along
!> the logistic curve of d(phi)/d(gamma) = -phi K (phi - phi_eq) and the stress ratio is
!> mu(I) + tan(psi). Measured errors and margins: doc/verification.md, "The mu(I)
!> rheology with dilatancy".
program test_mu_i_dilatancy
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_test_stress, only: ptau
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: material_cfg_t
  use dpmpm_element_config, only: element_cfg_t
  use dpmpm_element_path, only: element_history_t, run_element, element_ok
  use dpmpm_materials, only: material_t, materials_from_config
  use dpmpm_model_mu_i, only: mu_i_return
  use dpmpm_assert, only: begin_test, check, check_equal_int
  implicit none
  ! glass beads (Jop, Forterre & Pouliquen 2006) with d = 1 mm, rho_s = 2500 kg/m^3; the
  ! dilatancy constants of the tests: K = 4, phi_c = 0.6, a = 0.2
  real(wp), parameter :: mus = 0.38_wp, mu2 = 0.64_wp, i0 = 0.279_wp, dg = 1.0e-3_wp
  real(wp), parameter :: rhos = 2500.0_wp, young = 1.0e7_wp, nu = 0.3_wp
  real(wp), parameter :: kd = 4.0_wp, phic = 0.6_wp, slope = 0.2_wp
  ! the shear rate of the element paths: gamma = 1 in 2000 steps of 2.5e-6 s
  real(wp), parameter :: rate = 200.0_wp
  call start_tests()
  call test_dilatant_return_solves_its_equations()
  call test_loose_shear_at_constant_volume_ends_at_its_steady_pressure()
  call test_dense_shear_at_constant_volume_gains_pressure()
  call test_drained_shear_volume_fraction_follows_the_logistic_curve()
  call test_drained_shear_stress_ratio_is_mu_plus_tan_psi()
  call end_tests()

contains

  !> A mu_i material with dilatancy, points of volume fraction phi0 at V0.
  function beads(phi0) result(mat)
    real(wp), intent(in) :: phi0
    type(material_t) :: mat
    type(material_t), allocatable :: mats(:)
    call materials_from_config([cfg_of(phi0)], mats)
    mat = mats(1)
  end function beads

  type(material_cfg_t) function cfg_of(phi0) result(c)
    real(wp), intent(in) :: phi0
    c = material_cfg_t(id=1, model='mu_i', density=phi0*rhos, grain_density=rhos, &
                       youngs_modulus=young, poisson_ratio=nu, mu_s=mus, mu_2=mu2, i_0=i0, &
                       grain_diameter=dg, dilatancy_k=kd, critical_fraction=phic, &
                       fraction_slope=slope)
  end function cfg_of

  elemental real(wp) function mu_closed(inum)
    real(wp), intent(in) :: inum
    mu_closed = mus + (mu2 - mus)*inum/(i0 + inum)
  end function mu_closed

  !> A pseudo-random number in (0, 1) (the minimal standard generator of Park & Miller,
  !> whose products stay within 64-bit integers: the same draws on every build).
  real(wp) function draw(seed)
    integer(8), intent(inout) :: seed
    seed = modulo(seed*16807_8, 2147483647_8)
    draw = real(seed, wp)/2147483647.0_wp
  end function draw

  !> 2000 trials (stress, strain increment, step and volume fraction drawn, loose and
  !> dense): each return that flows satisfies its three equations, written out here.
  subroutine test_dilatant_return_solves_its_equations()
    type(material_t) :: mat
    real(wp) :: s(6), de(6), sn(6), dt, phi, gdot, inum, ptr, ttr, pn, tn, tpsi, kb, g
    real(wp) :: e1, e2, e3, strial(6), dv
    integer(8) :: seed
    integer :: k, flowed, apart
    call begin_test('dilatant_return_solves_its_equations')
    mat = beads(0.6_wp)
    kb = young/(3.0_wp*(1.0_wp - 2.0_wp*nu))
    g = young/(2.0_wp*(1.0_wp + nu))
    seed = 2026112_8
    e1 = 0.0_wp; e2 = 0.0_wp; e3 = 0.0_wp
    flowed = 0; apart = 0
    do k = 1, 2000
      s(1:3) = -1.0e4_wp*(1.0_wp + draw(seed))
      s(4:6) = 4.0e3_wp*(draw(seed) - 0.5_wp)
      de = 1.0e-3_wp*[draw(seed) - 0.5_wp, draw(seed) - 0.5_wp, draw(seed) - 0.5_wp, &
                      draw(seed) - 0.5_wp, draw(seed) - 0.5_wp, draw(seed) - 0.5_wp]
      dt = 1.0e-6_wp*10.0_wp**(3.0_wp*draw(seed))
      phi = 0.5_wp + 0.2_wp*draw(seed)
      ! the elastic trial, written out
      dv = de(1) + de(2) + de(3)
      strial(1:3) = s(1:3) + 2.0_wp*g*(de(1:3) - dv/3.0_wp) + kb*dv
      strial(4:6) = s(4:6) + g*de(4:6)
      call ptau(strial, ptr, ttr)
      sn = s
      call mu_i_return(mat, dt, de, sn, gdot, inum, phi)
      if (gdot <= 0.0_wp) cycle
      call ptau(sn, pn, tn)
      if (pn <= 0.0_wp) then
        apart = apart + 1
        cycle
      end if
      flowed = flowed + 1
      tpsi = kd*(phi - phic + slope*inum)
      e1 = max(e1, abs(pn - (ptr + kb*dt*gdot*tpsi))/ptr)
      e2 = max(e2, abs(tn - (ttr - g*dt*gdot))/ttr)
      e3 = max(e3, abs(tn - max(mu_closed(inum) + tpsi, 0.0_wp)*pn)/ttr)
      ! and I is the inertial number of its rate and pressure
      e1 = max(e1, abs(inum - gdot*dg*sqrt(rhos/pn))/inum)
    end do
    print '(2x,a,2i6,3es10.2)', 'flowed, apart; pressure, shear, friction errors:', flowed, &
      apart, e1, e2, e3
    call check(flowed > 500, 'most trials flow')
    call check(e1 < 1.0e-12_wp, 'the pressure takes back the plastic volume change')
    call check(e2 < 1.0e-12_wp, 'the shear stress falls by G dt x')
    call check(e3 < 1.0e-12_wp, 'the shear stress is (mu(I) + tan psi) p')
  end subroutine test_dilatant_return_solves_its_equations

  !> An element path of simple shear at rate `rate` to gamma = 1 from p0, at constant
  !> volume (undrained) or constant normal stress (drained).
  subroutine shear(path, phi0, p0, h)
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: phi0, p0
    type(element_history_t), intent(out) :: h
    type(element_cfg_t) :: c
    type(material_t), allocatable :: mats(:)
    c%path = path
    c%control = 'strain'
    c%p0 = p0
    c%shear_strain = 1.0_wp
    c%steps = 2000
    c%dt = 1.0_wp/(2000.0_wp*rate)
    c%tolerance = 1.0e-12_wp
    c%material = cfg_of(phi0)
    call materials_from_config([c%material], mats)
    call run_element(c, mats(1), h)
    call check_equal_int(h%status, element_ok, path//': the path is complete')
  end subroutine shear

  !> Loose, phi = 0.58 < phi_c, from p0 = 20 kPa at constant volume: the pressure falls
  !> to p* = rho_s (gdot d/I*)^2 with I* = (phi_c - phi)/a (0.1: 10 kPa) and the shear
  !> stress to mu(I*) p*. (The driver's constant volume is so to first order in the step:
  !> its symmetric velocity gradient shrinks V by (dgamma/2)^2 a step, 1.25e-4 over the
  !> path, so phi is taken from the volume the point has at the end.)
  subroutine test_loose_shear_at_constant_volume_ends_at_its_steady_pressure()
    type(element_history_t) :: h
    real(wp) :: istar, pstar, tstar, ep, et, phi, p, tau
    integer :: n
    call begin_test('loose_shear_at_constant_volume_ends_at_its_steady_pressure')
    call shear('simple_shear_undrained', 0.58_wp, 2.0e4_wp, h)
    if (h%status /= element_ok) return
    n = h%nrec
    phi = 0.58_wp/h%volume_ratio(n)
    istar = (phic - phi)/slope
    pstar = rhos*(rate*dg/istar)**2
    tstar = mu_closed(istar)*pstar
    call ptau(h%stress(:, n), p, tau)
    ep = abs(p - pstar)/pstar
    et = abs(tau - tstar)/tstar
    print '(2x,a,4es12.4,2es10.2)', 'p, tau at gamma = 1; p*, tau*; errors:', p, tau, pstar, &
      tstar, ep, et
    call check(ep < 5.0e-4_wp, 'the pressure ends at rho_s (gdot d/I*)^2')
    call check(et < 5.0e-4_wp, 'the shear stress ends at mu(I*) p*')
    call check(h%p(n/10) < 1.5e4_wp, 'the pressure falls (contraction)')
  end subroutine test_loose_shear_at_constant_volume_ends_at_its_steady_pressure

  !> Dense, phi = 0.62 > phi_c, from 10 kPa at constant volume: the point would dilate, so
  !> its pressure rises at every record (no steady state: phi_eq(I) < phi_c < phi).
  subroutine test_dense_shear_at_constant_volume_gains_pressure()
    type(element_history_t) :: h
    integer :: n, k
    logical :: rising
    call begin_test('dense_shear_at_constant_volume_gains_pressure')
    call shear('simple_shear_undrained', 0.62_wp, 1.0e4_wp, h)
    if (h%status /= element_ok) return
    n = h%nrec
    rising = .true.
    do k = 2, n
      rising = rising .and. h%p(k) >= h%p(k - 1)
    end do
    print '(2x,a,es12.4)', 'p at gamma = 1:', h%p(n)
    call check(rising, 'the pressure never falls')
    call check(h%p(n) > 5.0e4_wp, 'the pressure gains at least fivefold')
  end subroutine test_dense_shear_at_constant_volume_gains_pressure

  !> Dense, phi0 = 0.62, at constant normal stress 10 kPa: the plastic volume change
  !> y = ln(V/V0) - (elastic part) follows dy/dg = K (phi - phi_c + a I), g the plastic
  !> shear strain and phi = phi0 V0/V, integrated here (Heun, with I and p of the records)
  !> against the point's own volume. With I = 0.1 held, it is the logistic curve
  !> phi(g) = phi_eq/(1 + (phi_eq/phi0 - 1) exp(-K phi_eq g)), phi_eq = phi_c - a I = 0.58,
  !> which the test prints beside it: the lateral stress the confined dilation builds makes
  !> p differ from the normal stress held, so I is not held exactly.
  subroutine test_drained_shear_volume_fraction_follows_the_logistic_curve()
    type(element_history_t) :: h
    real(wp) :: phieq, inum, y, ya, je(2), f1, f2, dg_, phi, ref, e, elog, kb, p0
    integer :: k
    call begin_test('drained_shear_volume_fraction_follows_the_logistic_curve')
    call shear('simple_shear_drained', 0.62_wp, 1.0e4_wp, h)
    if (h%status /= element_ok) return
    kb = young/(3.0_wp*(1.0_wp - 2.0_wp*nu))
    p0 = h%p(1)
    inum = rate*dg/sqrt(1.0e4_wp/rhos)
    phieq = phic - slope*inum
    y = 0.0_wp
    e = 0.0_wp
    elog = 0.0_wp
    do k = 1, h%nrec - 1
      ! the elastic volume ratio exp(-(p - p0)/K_b) at both records
      je = exp(-([h%p(k), h%p(k + 1)] - p0)/kb)
      dg_ = h%state(1, k + 1) - h%state(1, k)
      ! (the step's own I is that of its end record, the friction of the end of the step)
      f1 = kd*(0.62_wp*exp(-y)/je(1) - phic + slope*h%state(2, k + 1))
      ya = y + dg_*f1
      f2 = kd*(0.62_wp*exp(-ya)/je(2) - phic + slope*h%state(2, k + 1))
      y = y + 0.5_wp*dg_*(f1 + f2)
      phi = 0.62_wp/h%volume_ratio(k + 1)
      e = max(e, abs(phi - 0.62_wp*exp(-y)/je(2))/(0.62_wp - phieq))
      ref = phieq/(1.0_wp + (phieq/0.62_wp - 1.0_wp)*exp(-kd*phieq*h%state(1, k + 1)))
      elog = max(elog, abs(phi - ref)/(0.62_wp - phieq))
    end do
    print '(2x,a,3f9.5)', 'phi at gamma = 1: the point, the integrated law, the logistic curve:', &
      0.62_wp/h%volume_ratio(h%nrec), 0.62_wp*exp(-y)/je(2), &
      phieq/(1.0_wp + (phieq/0.62_wp - 1.0_wp)*exp(-kd*phieq*h%state(1, h%nrec)))
    print '(2x,a,2es10.2)', 'largest errors / (phi0 - phi_eq): integrated law, logistic:', e, elog
    call check(e < 2.0e-3_wp, 'phi follows the integrated law of the plastic volume')
    call check(elog < 1.5e-2_wp, 'and stays near the logistic curve of I = 0.1')
  end subroutine test_drained_shear_volume_fraction_follows_the_logistic_curve

  !> The same path: at every step that flows, tau/p = mu(I) + K (phi - phi_c + a I), with
  !> tau and p the invariants of the record, I its inertial number and phi the volume
  !> fraction the step started from (the record before).
  subroutine test_drained_shear_stress_ratio_is_mu_plus_tan_psi()
    type(element_history_t) :: h
    real(wp) :: phi, inum, e, p, tau
    integer :: k, n
    call begin_test('drained_shear_stress_ratio_is_mu_plus_tan_psi')
    call shear('simple_shear_drained', 0.62_wp, 1.0e4_wp, h)
    if (h%status /= element_ok) return
    e = 0.0_wp
    n = 0
    do k = 2, h%nrec
      inum = h%state(2, k)
      if (inum <= 0.0_wp) cycle
      n = n + 1
      phi = 0.62_wp/h%volume_ratio(k - 1)
      call ptau(h%stress(:, k), p, tau)
      e = max(e, abs(tau/p - max(mu_closed(inum) + kd*(phi - phic + slope*inum), 0.0_wp)))
    end do
    print '(2x,a,i6,es10.2)', 'steps that flow, largest |tau/p - (mu(I) + tan psi)|:', n, e
    call check(n > 1900, 'the point flows')
    call check(e < 1.0e-12_wp, 'the stress ratio is mu(I) + tan psi')
  end subroutine test_drained_shear_stress_ratio_is_mu_plus_tan_psi

end program test_mu_i_dilatancy
