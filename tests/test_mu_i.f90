!> The mu(I) rheology at one point (dpmpm_model_mu_i) against its closed forms: steady simple
!> shear at constant pressure and shear rate ends on tau = mu(I) p with I = gdot d/sqrt(p/rho_s)
!> (formula written out here, not taken from the module) at inertial numbers 1e-3 to 1,
!> through the return alone and through the update with the Jaumann spin; the plastic work
!> of a steady step is tau gdot dt V; below mu_s p the point stays elastic; a trial in
!> mean tension gives zero stress; the closed-form root solves the scalar equation of the
!> return. Measured errors and margins: doc/verification.md, "The mu(I) rheology at one
!> point".
!> With dilatancy (doc/theory.md 5.9 "Dilatancy"), with the formulas written out here: the
!> return solves p = p_tr + K_b dt x tan(psi), tau = tau_tr - G dt x = (mu(I) + tan(psi)) p
!> with tan(psi) = K (phi - phi_c + a I); sheared at constant volume, a loose point
!> (phi < phi_c) loses pressure down to p* = rho_s (gdot d/I*)^2, I* = (phi_c - phi)/a, and
!> a dense one gains pressure; sheared at constant normal stress, the volume fraction follows
!> d(phi)/d(gamma) = -phi K (phi - phi_eq) (near the logistic curve of a held I) and the
!> stress ratio is mu(I) + tan(psi). Measured errors and margins: doc/verification.md,
!> "The mu(I) rheology with dilatancy".
program test_mu_i
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_test_stress, only: ptau
  use dpmpm_kinds, only: wp
  use dpmpm_materials, only: material_t, materials_from_config, stress_update, init_state
  use dpmpm_config, only: material_cfg_t
  use dpmpm_element_config, only: element_cfg_t
  use dpmpm_element_path, only: element_history_t, run_element, element_ok
  use dpmpm_model_mu_i, only: mu_i_return
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int
  implicit none
  ! glass beads (Jop, Forterre & Pouliquen 2006): mu_s, mu_2, I_0; d = 1 mm, rho_s = 2500,
  ! p = 10 kPa, so that sqrt(p/rho_s) = 2 m/s and gdot = 2000 I (1/s)
  real(wp), parameter :: mus = 0.38_wp, mu2 = 0.64_wp, i0 = 0.279_wp, dg = 1.0e-3_wp
  real(wp), parameter :: rhos = 2500.0_wp, p0 = 1.0e4_wp, young = 1.0e7_wp, nu = 0.3_wp
  real(wp), parameter :: inertial(4) = [1.0e-3_wp, 1.0e-2_wp, 1.0e-1_wp, 1.0_wp]
  ! the dilatancy constants: K = 4, phi_c = 0.6, a = 0.2; the shear rate of the element
  ! paths: gamma = 1 in 2000 steps of 2.5e-6 s
  real(wp), parameter :: kd = 4.0_wp, phic = 0.6_wp, slope = 0.2_wp, rate = 200.0_wp
  call start_tests()
  call test_steady_shear_return_follows_mu_of_i()
  call test_steady_shear_with_spin_follows_mu_of_i()
  call test_steady_shear_dissipates_tau_times_rate()
  call test_below_mu_s_the_point_stays_elastic()
  call test_trial_in_tension_returns_to_zero_stress()
  call test_return_solves_the_scalar_equation()
  call test_volume_apart_stays_at_max_dilation()
  call test_dilatant_return_solves_its_equations()
  call test_loose_shear_at_constant_volume_ends_at_its_steady_pressure()
  call test_dense_shear_at_constant_volume_gains_pressure()
  call test_drained_shear_volume_fraction_follows_the_logistic_curve()
  call test_drained_shear_stress_ratio_is_mu_plus_tan_psi()
  call end_tests()

contains

  !> A mu_i material of the constants above; with phi0, with dilatancy and points of volume
  !> fraction phi0 at V0.
  function beads(phi0) result(mat)
    real(wp), intent(in), optional :: phi0
    type(material_t) :: mat
    type(material_t), allocatable :: mats(:)
    call materials_from_config([beads_cfg(phi0)], mats)
    mat = mats(1)
  end function beads

  type(material_cfg_t) function beads_cfg(phi0) result(c)
    real(wp), intent(in), optional :: phi0
    c = material_cfg_t(id=1, model='mu_i', density=1500.0_wp, grain_density=rhos, &
                       youngs_modulus=young, poisson_ratio=nu, mu_s=mus, mu_2=mu2, i_0=i0, &
                       grain_diameter=dg)
    if (present(phi0)) then
      c%density = phi0*rhos
      c%dilatancy_k = kd
      c%critical_fraction = phic
      c%fraction_slope = slope
    end if
  end function beads_cfg

  !> The closed form: mu(I) = mu_s + (mu_2 - mu_s)/(I_0/I + 1).
  elemental real(wp) function mu_closed(inum)
    real(wp), intent(in) :: inum
    mu_closed = mus + (mu2 - mus)/(i0/inum + 1.0_wp)
  end function mu_closed

  !> Simple shear at the rate of inertial number inum from isotropic p0, nsteps steps of shear
  !> strain 1e-4 each, through mu_i_return (no spin): tau/p and the last I and rate.
  subroutine shear_by_return(inum, ratio, ilast, glast)
    real(wp), intent(in) :: inum
    real(wp), intent(out) :: ratio, ilast, glast
    type(material_t) :: mat
    real(wp) :: s(6), de(6), gdot, dt, p, tau
    integer :: k
    mat = beads()
    gdot = inum*sqrt(p0/rhos)/dg
    dt = 1.0e-4_wp/gdot
    s = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
    de = 0.0_wp
    de(6) = gdot*dt
    do k = 1, 2000
      call mu_i_return(mat, dt, de, s, glast, ilast)
    end do
    call ptau(s, p, tau)
    ratio = tau/p
  end subroutine shear_by_return

  !> Steady simple shear at constant volume (so p = p0) through the return: tau/p = mu(I) of
  !> the imposed rate, and the state's I is that of the rate.
  subroutine test_steady_shear_return_follows_mu_of_i()
    real(wp) :: ratio, ilast, glast, err_mu, err_i
    integer :: j
    call begin_test('steady_shear_return_follows_mu_of_i')
    err_mu = 0.0_wp
    err_i = 0.0_wp
    do j = 1, size(inertial)
      call shear_by_return(inertial(j), ratio, ilast, glast)
      err_mu = max(err_mu, abs(ratio/mu_closed(inertial(j)) - 1.0_wp))
      err_i = max(err_i, abs(ilast/inertial(j) - 1.0_wp))
    end do
    print '(a,2es10.2)', '  steady shear by the return: largest relative error of tau/p, I:', &
      err_mu, err_i
    ! measured 1.1e-16 (tau/p) and 1.2e-15 (I): in steady shear the plastic rate equals the
    ! imposed one exactly; bounds 1e-13 (round-off, 100x)
    call check(err_mu <= 1.0e-13_wp, 'tau/p = mu(I) at I = 1e-3, 1e-2, 0.1, 1')
    call check(err_i <= 1.0e-13_wp, 'the inertial number of the state is that of the rate')
  end subroutine test_steady_shear_return_follows_mu_of_i

  !> Steady simple shear v_x = gdot y through stress_update (the Jaumann spin turns the stress,
  !> the elastic strain takes part of the rate): tau/p against mu(I) of the imposed rate, and
  !> the pressure held (no plastic volume change). In plane strain (2D) and in 3D.
  subroutine test_steady_shear_with_spin_follows_mu_of_i()
    type(material_t) :: mat
    real(wp) :: stress(6, 1), vol(1), state(2, 1), vg(9, 1), gdot, dt, p, tau, err_mu, err_p
    integer :: j, k, dim
    call begin_test('steady_shear_with_spin_follows_mu_of_i')
    mat = beads()
    err_mu = 0.0_wp
    err_p = 0.0_wp
    do dim = 2, 3
      do j = 1, size(inertial)
        gdot = inertial(j)*sqrt(p0/rhos)/dg
        dt = 1.0e-4_wp/gdot
        stress(:, 1) = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        vol = 1.0_wp
        state = 0.0_wp
        vg = 0.0_wp
        vg(4, 1) = gdot   ! L(1, 2) = dv_x/dy (column-major)
        do k = 1, 2000
          call stress_update(mat, 1, dt, 1, [1], vg, stress, vol, [1.0_wp], state=state, &
                             plane=dim == 2)
        end do
        call ptau(stress(:, 1), p, tau)
        err_mu = max(err_mu, abs(tau/p/mu_closed(inertial(j)) - 1.0_wp))
        err_p = max(err_p, abs(p/p0 - 1.0_wp))
      end do
    end do
    print '(a,2es10.2)', '  steady shear with spin: largest relative error of tau/p, p:', &
      err_mu, err_p
    ! measured 8.7e-8 (tau/p; the spin puts a normal deviator of order tau^2/G into the
    ! steady state, which the elastic rate balances) and 0 (p), 2D and 3D alike; bounds 1e-6
    ! and 1e-13
    call check(err_mu <= 1.0e-6_wp, 'tau/p = mu(I) with the spin')
    call check(err_p <= 1.0e-13_wp, 'p held')
  end subroutine test_steady_shear_with_spin_follows_mu_of_i

  !> In steady shear the plastic work of one step is tau gdot dt V (the whole rate is plastic),
  !> and the accumulated plastic shear strain grows by gdot dt.
  subroutine test_steady_shear_dissipates_tau_times_rate()
    type(material_t) :: mat
    real(wp) :: stress(6, 1), vol(1), state(2, 1), vg(9, 1), gdot, dt, p, tau, w, gam
    integer :: k
    call begin_test('steady_shear_dissipates_tau_times_rate')
    mat = beads()
    gdot = 0.1_wp*sqrt(p0/rhos)/dg
    dt = 1.0e-4_wp/gdot
    stress(:, 1) = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
    vol = 2.0e-3_wp
    state = 0.0_wp
    vg = 0.0_wp
    vg(4, 1) = gdot
    do k = 1, 2000
      call stress_update(mat, 1, dt, 1, [1], vg, stress, vol, [2.0e-3_wp], state=state, &
                         plane=.true.)
    end do
    call ptau(stress(:, 1), p, tau)
    gam = state(1, 1)
    w = 0.0_wp
    call stress_update(mat, 1, dt, 1, [1], vg, stress, vol, [2.0e-3_wp], state=state, &
                       dissipation=w, plane=.true.)
    print '(a,2es10.2)', '  steady shear: plastic work and strain of a step, relative errors:', &
      abs(w/(tau*gdot*dt*vol(1)) - 1.0_wp), abs((state(1, 1) - gam)/(gdot*dt) - 1.0_wp)
    ! measured 6.8e-7 and 6.8e-7 (the share of the rate the spin's elastic part takes); bounds
    ! 5e-6 (7x)
    call check_close(w, tau*gdot*dt*vol(1), 5.0e-6_wp, 0.0_wp, 'plastic work tau gdot dt V')
    call check_close(state(1, 1) - gam, gdot*dt, 5.0e-6_wp, 0.0_wp, 'plastic shear strain')
  end subroutine test_steady_shear_dissipates_tau_times_rate

  !> Shear loading from p0 to tau = 0.9 mu_s p at any rate is elastic: tau = G gamma exactly,
  !> no plastic strain, I = 0; one step more, past mu_s p, flows.
  subroutine test_below_mu_s_the_point_stays_elastic()
    type(material_t) :: mat
    real(wp) :: stress(6, 1), vol(1), state(2, 1), vg(9, 1), g, gam, dt, p, tau
    integer :: k
    call begin_test('below_mu_s_the_point_stays_elastic')
    mat = beads()
    g = young/(2.0_wp*(1.0_wp + nu))
    gam = 0.9_wp*mus*p0/g
    stress(:, 1) = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
    vol = 1.0_wp
    state = 0.0_wp
    call init_state(mat, 1, 1, [1], stress, state)
    vg = 0.0_wp
    ! a fast rate (I of order 1 if it flowed), 100 steps, stress rotation left out
    ! (symmetric L: no spin)
    dt = 1.0e-5_wp
    vg(4, 1) = 0.5_wp*gam/(100*dt)
    vg(2, 1) = vg(4, 1)
    do k = 1, 100
      call stress_update(mat, 1, dt, 1, [1], vg, stress, vol, [1.0_wp], state=state, &
                         plane=.true.)
    end do
    call ptau(stress(:, 1), p, tau)
    ! measured 1.5e-15 (tau); bound 1e-13 (round-off)
    call check_close(tau, g*gam, 1.0e-13_wp, 0.0_wp, 'tau = G gamma below mu_s p')
    call check(all(state(:, 1) == 0.0_wp), 'no plastic strain and I = 0')
    ! (a shear increment of gamma/2: the trial is 1.35 mu_s p)
    vg(4, 1) = 0.25_wp*gam/dt
    vg(2, 1) = vg(4, 1)
    call stress_update(mat, 1, dt, 1, [1], vg, stress, vol, [1.0_wp], state=state, plane=.true.)
    call ptau(stress(:, 1), p, tau)
    call check(state(1, 1) > 0.0_wp .and. state(2, 1) > 0.0_wp .and. tau > mus*p, &
               'past mu_s p it flows, tau above mu_s p at a finite rate')
  end subroutine test_below_mu_s_the_point_stays_elastic

  !> A step that takes the mean stress into tension (an expansion) leaves the point at zero
  !> stress: the grains have come apart. A compression afterwards gives it pressure again.
  subroutine test_trial_in_tension_returns_to_zero_stress()
    type(material_t) :: mat
    real(wp) :: s(6), de(6), gd, inum, k
    call begin_test('trial_in_tension_returns_to_zero_stress')
    mat = beads()
    k = young/(3.0_wp*(1.0_wp - 2.0_wp*nu))
    s = [-p0, -p0, -p0, 2.0e3_wp, 0.0_wp, 0.0_wp]
    ! volume strain 2 p0/K: the trial mean stress is +p0 (tension)
    de = [2.0_wp*p0/k/3.0_wp, 2.0_wp*p0/k/3.0_wp, 2.0_wp*p0/k/3.0_wp, 0.0_wp, 0.0_wp, 1.0e-4_wp]
    call mu_i_return(mat, 1.0e-3_wp, de, s, gd, inum)
    call check(all(s == 0.0_wp), 'zero stress after a trial in tension')
    call check(gd == 0.0_wp .and. inum == 0.0_wp, 'no rate, I = 0 while apart')
    de = [-1.0e-4_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    call mu_i_return(mat, 1.0e-3_wp, de, s, gd, inum)
    ! measured exact; bound round-off
    call check_close(-(s(1) + s(2) + s(3))/3.0_wp, k*1.0e-4_wp, 1.0e-14_wp, 0.0_wp, &
                     'a compression from zero stress gives p = K dv again')
  end subroutine test_trial_in_tension_returns_to_zero_stress

  !> Trial stresses from just above mu_s p to 50 mu_s p, at pressures 1 Pa to 1 MPa and steps
  !> 1e-7 s to 1e-2 s: the returned stress has tau = tau_tr - G dt gdot = mu(I) p with the
  !> returned rate, and the same direction as the trial deviator.
  subroutine test_return_solves_the_scalar_equation()
    type(material_t) :: mat
    real(wp) :: s(6), st(6), p, tau, ptr, tautr, gd, inum, dt, g, res, dir, worst, worst_dir
    real(wp), parameter :: over(4) = [1.0001_wp, 1.3_wp, 3.0_wp, 50.0_wp]
    integer :: a, b, c
    call begin_test('return_solves_the_scalar_equation')
    mat = beads()
    g = young/(2.0_wp*(1.0_wp + nu))
    worst = 0.0_wp
    worst_dir = 0.0_wp
    do a = 0, 6
      ptr = 10.0_wp**a
      do b = 1, 4
        tautr = mus*ptr*over(b)
        do c = 0, 5
          dt = 10.0_wp**(-7 + c)
          ! a deviator of xx, yy, zz and xy parts with |s|/sqrt(2) = tautr
          st = [0.3_wp, -0.1_wp, -0.2_wp, 0.0_wp, 0.0_wp, 0.5_wp]
          st = st*tautr/sqrt(0.5_wp*sum(st(1:3)**2) + sum(st(4:6)**2))
          s = st
          s(1:3) = s(1:3) - ptr
          call mu_i_return(mat, dt, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], s, gd, &
                           inum)
          call ptau(s, p, tau)
          ! residual of both forms of tau, over the trial's scale
          res = max(abs(tau - (tautr - g*dt*gd)), abs(tau - mu_closed(gd*dg/sqrt(p/rhos))*p)) &
                /tautr
          worst = max(worst, res)
          dir = maxval(abs((s(4:6))/tau - st(4:6)/tautr))
          worst_dir = max(worst_dir, dir)
          call check(gd > 0.0_wp .and. abs(p - ptr) <= 1.0e-14_wp*ptr, 'flows at p_tr')
        end do
      end do
    end do
    print '(a,2es10.2)', '  return: largest residual of tau = mu(I) p, of the direction:', &
      worst, worst_dir
    ! measured 3.8e-16 and 2.2e-16; bounds 1e-13 and 1e-14 (round-off)
    call check(worst <= 1.0e-13_wp, 'tau = tau_tr - G dt gdot = mu(I) p')
    call check(worst_dir <= 1.0e-14_wp, 'the deviator keeps its direction')
  end subroutine test_return_solves_the_scalar_equation

  !> A point pulled apart (stress-free) keeps growing in volume without a bound, and stays at
  !> max_dilation V0 with one; its stress stays 0.
  subroutine test_volume_apart_stays_at_max_dilation()
    type(material_t), allocatable :: mats(:)
    real(wp) :: stress(6, 1), vol(1), state(2, 1), vg(9, 1)
    integer :: k, b
    call begin_test('volume_apart_stays_at_max_dilation')
    do b = 0, 1
      call materials_from_config([material_cfg_t(id=1, model='mu_i', density=1500.0_wp, &
                                                 youngs_modulus=young, poisson_ratio=nu, &
                                                 mu_s=mus, mu_2=mu2, i_0=i0, grain_diameter=dg, &
                                                 max_dilation=2.0_wp*b)], mats)
      stress = 0.0_wp
      vol = 1.0_wp
      state = 0.0_wp
      vg = 0.0_wp
      vg(1, 1) = 1.0_wp
      vg(5, 1) = 1.0_wp
      ! 100 steps of 0.01 s stretching x and y at 1/s: J = 1.01^200 = 7.3 without the bound
      do k = 1, 100
        call stress_update(mats(1), 1, 0.01_wp, 1, [1], vg, stress, vol, [1.0_wp], state=state, &
                           plane=.true.)
      end do
      if (b == 0) then
        call check_close(vol(1), 1.01_wp**200, 1.0e-12_wp, 0.0_wp, 'no bound: V = J V0')
      else
        call check(vol(1) == 2.0_wp, 'bound: V = max_dilation V0')
      end if
      call check(all(stress == 0.0_wp), 'no stress while apart')
    end do
  end subroutine test_volume_apart_stays_at_max_dilation

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
    c%material = beads_cfg(phi0)
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

end program test_mu_i
