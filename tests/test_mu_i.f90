!> The mu(I) rheology at one point (dpmpm_model_mu_i) against its closed forms: steady simple
!> shear at constant pressure and shear rate ends on tau = mu(I) p with I = gdot d/sqrt(p/rho_s)
!> (formula written out here, not taken from the module) at inertial numbers 1e-3 to 1,
!> through the return alone and through the update with the Jaumann spin; the plastic work
!> of a steady step is tau gdot dt V; below mu_s p the point stays elastic; a trial in
!> mean tension gives zero stress; the closed-form root solves the scalar equation of the
!> return. Measured errors and margins: doc/verification.md, "The mu(I) rheology at one
!> point".
program test_mu_i
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_test_stress, only: ptau
  use dpmpm_kinds, only: wp
  use dpmpm_materials, only: material_t, materials_from_config, stress_update, init_state
  use dpmpm_config, only: material_cfg_t
  use dpmpm_model_mu_i, only: mu_i_return
  use dpmpm_assert, only: begin_test, check, check_close
  implicit none
  ! glass beads (Jop, Forterre & Pouliquen 2006): mu_s, mu_2, I_0; d = 1 mm, rho_s = 2500,
  ! p = 10 kPa, so that sqrt(p/rho_s) = 2 m/s and gdot = 2000 I (1/s)
  real(wp), parameter :: mus = 0.38_wp, mu2 = 0.64_wp, i0 = 0.279_wp, dg = 1.0e-3_wp
  real(wp), parameter :: rhos = 2500.0_wp, p0 = 1.0e4_wp, young = 1.0e7_wp, nu = 0.3_wp
  real(wp), parameter :: inertial(4) = [1.0e-3_wp, 1.0e-2_wp, 1.0e-1_wp, 1.0_wp]
  call start_tests()
  call test_steady_shear_return_follows_mu_of_i()
  call test_steady_shear_with_spin_follows_mu_of_i()
  call test_steady_shear_dissipates_tau_times_rate()
  call test_below_mu_s_the_point_stays_elastic()
  call test_trial_in_tension_returns_to_zero_stress()
  call test_return_solves_the_scalar_equation()
  call test_volume_apart_stays_at_max_dilation()
  call end_tests()

contains

  !> A mu_i material of the constants above.
  function beads() result(mat)
    type(material_t) :: mat
    type(material_t), allocatable :: mats(:)
    call materials_from_config([material_cfg_t(id=1, model='mu_i', density=1500.0_wp, &
                                               grain_density=rhos, youngs_modulus=young, &
                                               poisson_ratio=nu, mu_s=mus, mu_2=mu2, i_0=i0, &
                                               grain_diameter=dg)], mats)
    mat = mats(1)
  end function beads

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

end program test_mu_i
