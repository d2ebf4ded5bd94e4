!> Return-mapping tests of the Mohr-Coulomb and Drucker-Prager soil models
!> (src/materials/dpmpm_plasticity.f90). Expected values come from closed forms written
!> out here (yield functions, apexes, one- and two-plane returns in principal axes),
!> from finite differences of the plastic potential, and from invariances (rotation,
!> step size), never from numbers printed by the code under test.
program test_plasticity
  use, intrinsic :: iso_fortran_env, only: int64
  use dpmpm_kinds, only: wp
  use dpmpm_plasticity, only: plastic_params_t, plastic_setup, plastic_return, principal_stresses, &
                              mc_yield, mc_potential, dp_yield, dp_potential, cohesion_at, &
                              elastic_trial, surface_mohr_coulomb, surface_drucker_prager, &
                              dp_plane_strain, dp_outer, dp_inner, ret_elastic, ret_smooth, &
                              ret_edge_right, ret_edge_left, ret_apex
  use dpmpm_particles, only: particle_set_t
  use dpmpm_config, only: material_cfg_t
  use dpmpm_materials, only: material_t, materials_from_config, stress_update
  use dpmpm_kinds, only: i8
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  real(wp), parameter :: youngs = 1.0e7_wp, nu = 0.3_wp
  real(wp), parameter :: kb = youngs/(3.0_wp*(1.0_wp - 2.0_wp*nu))
  real(wp), parameter :: gs = youngs/(2.0_wp*(1.0_wp + nu))
  real(wp), parameter :: zero6(6) = 0.0_wp   !< no strain increment: return the given state
  real(wp), parameter :: lam = kb - 2.0_wp*gs/3.0_wp
  real(wp), parameter :: pi = acos(-1.0_wp), deg = pi/180.0_wp
  real(wp), parameter :: no_cut = 1.0e30_wp
  integer(int64) :: seed = 12345_int64
  call start_tests()
  call test_principal_stresses_reconstruct()
  call test_principal_stresses_plane()
  call test_principal_stresses_repeated()
  call test_mc_random_states_on_surface()
  call test_dp_random_states_on_surface()
  call test_mc_main_plane_closed_form()
  call test_mc_right_edge_closed_form()
  call test_mc_left_edge_closed_form()
  call test_mc_apex()
  call test_dp_cone_closed_form()
  call test_dp_apex()
  call test_mc_flow_follows_potential()
  call test_dp_flow_follows_potential()
  call test_mc_tension_cutoff()
  call test_dp_tension_cutoff()
  call test_objectivity_under_rotation()
  call test_small_steps_converge()
  call test_dp_matches_mc_on_meridians()
  call test_dp_softening_closed_form()
  call test_mc_softening_closed_form()
  call test_points_carry_plastic_strain()
  call test_stress_update_plastic_work()
  call test_dilation_bound()
  call test_cutoff_opening_gains_no_energy()
  call end_tests()

contains

  !> Parameters with the elastic constants of this test (E = 10 MPa, nu = 0.3).
  function params(surface, phi, psi, c, tensile, h, cres, match) result(par)
    integer, intent(in) :: surface
    real(wp), intent(in) :: phi, psi, c, tensile
    real(wp), intent(in), optional :: h, cres
    integer, intent(in), optional :: match
    type(plastic_params_t) :: par
    real(wp) :: hh, cr
    integer :: mt
    hh = 0.0_wp
    cr = c
    mt = dp_plane_strain
    if (present(h)) hh = h
    if (present(cres)) cr = cres
    if (present(match)) mt = match
    par = plastic_setup(surface, kb, gs, phi, psi, c, tensile, hh, cr, mt)
  end function params

  !> Uniform number in [0, 1) from a small linear congruential generator (repeatable).
  real(wp) function urand()
    seed = modulo(1103515245_int64*seed + 12345_int64, 2147483647_int64)
    urand = real(seed, wp)/2147483647.0_wp
  end function urand

  !> Rotation matrix about the unit axis n by the angle a (Rodrigues).
  pure function rotation(n, a) result(r)
    real(wp), intent(in) :: n(3), a
    real(wp) :: r(3, 3), k(3, 3)
    integer :: i
    k = reshape([0.0_wp, n(3), -n(2), -n(3), 0.0_wp, n(1), n(2), -n(1), 0.0_wp], [3, 3])
    r = sin(a)*k + (1.0_wp - cos(a))*matmul(k, k)
    do i = 1, 3
      r(i, i) = r(i, i) + 1.0_wp
    end do
  end function rotation

  pure function to_tensor(sv) result(t)
    real(wp), intent(in) :: sv(6)
    real(wp) :: t(3, 3)
    t = reshape([sv(1), sv(6), sv(5), sv(6), sv(2), sv(4), sv(5), sv(4), sv(3)], [3, 3])
  end function to_tensor

  pure function to_voigt(t) result(sv)
    real(wp), intent(in) :: t(3, 3)
    real(wp) :: sv(6)
    sv = [t(1, 1), t(2, 2), t(3, 3), t(2, 3), t(1, 3), t(1, 2)]
  end function to_voigt

  !> R sigma R^T of a Voigt stress.
  pure function rotate_stress(r, sv) result(out)
    real(wp), intent(in) :: r(3, 3), sv(6)
    real(wp) :: out(6)
    out = to_voigt(matmul(r, matmul(to_tensor(sv), transpose(r))))
  end function rotate_stress

  !> R eps R^T of a Voigt strain with engineering shears.
  pure function rotate_strain(r, ev) result(out)
    real(wp), intent(in) :: r(3, 3), ev(6)
    real(wp) :: out(6)
    out = rotate_stress(r, [ev(1:3), 0.5_wp*ev(4:6)])
    out(4:6) = 2.0_wp*out(4:6)
  end function rotate_strain

  !> Elastic strain C^-1 dsig (engineering shears) of the isotropic law.
  pure function compliance(ds) result(de)
    real(wp), intent(in) :: ds(6)
    real(wp) :: de(6)
    de(1:3) = ((1.0_wp + nu)*ds(1:3) - nu*sum(ds(1:3)))/youngs
    de(4:6) = ds(4:6)/gs
  end function compliance

  !> A stress with principal values s in the axes of rotation(n, a).
  function stress_in_axes(s, n, a) result(sv)
    real(wp), intent(in) :: s(3), n(3), a
    real(wp) :: sv(6)
    sv = rotate_stress(rotation(n/norm2(n), a), [s, 0.0_wp, 0.0_wp, 0.0_wp])
  end function stress_in_axes

  function random_axis() result(n)
    real(wp) :: n(3)
    n = [urand() - 0.5_wp, urand() - 0.5_wp, urand() - 0.5_wp] + [0.01_wp, 0.02_wp, 0.03_wp]
    n = n/norm2(n)
  end function random_axis

  !> A random trial stress of magnitude ~ scale (principal values in [-2, 1] scale).
  function random_stress(scale) result(sv)
    real(wp), intent(in) :: scale
    real(wp) :: sv(6)
    sv = stress_in_axes(scale*[3.0_wp*urand() - 2.0_wp, 3.0_wp*urand() - 2.0_wp, &
                               3.0_wp*urand() - 2.0_wp], random_axis(), 2.0_wp*pi*urand())
  end function random_stress

  !> Central-difference gradient of the plastic potential of par at sv (Voigt; a shear
  !> component moves both symmetric entries, so the result pairs with engineering shears).
  function potential_gradient(par, sv) result(g)
    type(plastic_params_t), intent(in) :: par
    real(wp), intent(in) :: sv(6)
    real(wp) :: g(6), sp(6), sm(6), d
    integer :: k
    d = 1.0e-6_wp*maxval(abs(sv))
    do k = 1, 6
      sp = sv
      sm = sv
      sp(k) = sp(k) + d
      sm(k) = sm(k) - d
      if (par%surface == surface_mohr_coulomb) then
        g(k) = (mc_potential(sp, par%sin_psi) - mc_potential(sm, par%sin_psi))/(2.0_wp*d)
      else
        g(k) = (dp_potential(sp, par%eta_bar) - dp_potential(sm, par%eta_bar))/(2.0_wp*d)
      end if
    end do
  end function potential_gradient

  subroutine test_principal_stresses_reconstruct()
    real(wp) :: sv(6), sig(3), vec(3, 3)
    integer :: k
    call begin_test('principal_stresses_reconstruct')
    do k = 1, 200
      sv = random_stress(1.0e5_wp)
      if (k == 1) sv = [1.0_wp, 1.0_wp, -2.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]*1.0e4_wp
      call principal_stresses(sv, sig, vec)
      call check_reconstruct(sv, sig, vec)
    end do
  end subroutine test_principal_stresses_reconstruct

  !> Plane states (sv(4) = sv(5) = 0): z stays a principal direction with the value sv(3)
  !> exactly, the in-plane pair is m +- sqrt(d^2 + sxy^2) (m, d the mean and half difference
  !> of sxx, syy), and V diag(sigma) V^T gives the stress back.
  subroutine test_principal_stresses_plane()
    real(wp) :: sv(6), sig(3), vec(3, 3), m, d, r, lo, hi
    integer :: k, kz
    call begin_test('principal_stresses_plane')
    do k = 1, 300
      sv = 1.0e5_wp*[3.0_wp*urand() - 2.0_wp, 3.0_wp*urand() - 2.0_wp, 3.0_wp*urand() - 2.0_wp, &
                     0.0_wp, 0.0_wp, urand() - 0.5_wp]
      ! shear far below and far above the normal stresses, and none at all
      if (k == 1) sv(6) = 1.0e-12_wp*sv(6)
      if (k == 2) sv(1:2) = 1.0e-9_wp*sv(1:2)
      if (k == 3) sv(6) = 0.0_wp
      call principal_stresses(sv, sig, vec)
      call check_reconstruct(sv, sig, vec)
      kz = findloc(abs(vec(3, :)), 1.0_wp, dim=1)
      call check(kz > 0, 'one eigenvector is e_z')
      if (kz == 0) cycle
      call check(sig(kz) == sv(3), 'its principal value is sigma_zz exactly')
      call check(all(vec(1:2, kz) == 0.0_wp) .and. all(pack(vec(3, :), [1, 2, 3] /= kz) == 0.0_wp), &
                 'the other eigenvectors lie in the plane')
      m = 0.5_wp*(sv(1) + sv(2)); d = 0.5_wp*(sv(1) - sv(2)); r = sqrt(d*d + sv(6)**2)
      hi = maxval(sig, mask=[1, 2, 3] /= kz); lo = minval(sig, mask=[1, 2, 3] /= kz)
      call check_close(hi, m + r, 1.0e-13_wp, 1.0e-13_wp*maxval(abs(sv)), 'larger in-plane value')
      call check_close(lo, m - r, 1.0e-13_wp, 1.0e-13_wp*maxval(abs(sv)), 'smaller in-plane value')
    end do
  end subroutine test_principal_stresses_plane

  !> Repeated principal values, in the plane and rotated in 3D: two equal, all three
  !> equal, an in-plane value equal to sigma_zz.
  subroutine test_principal_stresses_repeated()
    real(wp) :: sv(6), sig(3), vec(3, 3), want(3)
    real(wp), parameter :: wants(3, 3) = reshape([1.0_wp, 1.0_wp, -2.0_wp, 3.0_wp, -0.5_wp, -0.5_wp, &
                                                  -1.0_wp, -1.0_wp, -1.0_wp], [3, 3])
    integer :: k
    call begin_test('principal_stresses_repeated')
    ! plane: sxx = syy without shear; sxx = syy with shear; in-plane values 1 and 0 with
    ! szz = 1; isotropic
    call check_plane([2.0_wp, 2.0_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [2.0_wp, 2.0_wp, -1.0_wp])
    call check_plane([-1.0_wp, -1.0_wp, -3.0_wp, 0.0_wp, 0.0_wp, 0.5_wp], [-0.5_wp, -1.5_wp, &
                                                                            -3.0_wp])
    call check_plane([0.5_wp, 0.5_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.5_wp], [1.0_wp, 1.0_wp, 0.0_wp])
    call check_plane([-4.0_wp, -4.0_wp, -4.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [-4.0_wp, -4.0_wp, &
                                                                            -4.0_wp])
    ! 3D: two equal values (both orders) and three, in random axes
    do k = 1, 60
      want = wants(:, mod(k, 3) + 1)
      sv = stress_in_axes(1.0e4_wp*want, random_axis(), 2.0_wp*pi*urand())
      call principal_stresses(sv, sig, vec)
      call check_reconstruct(sv, sig, vec)
      call check(maxval(abs(sig - 1.0e4_wp*want)) <= 1.0e-12_wp*1.0e4_wp*maxval(abs(want)), &
                 'repeated values found')
    end do
  end subroutine test_principal_stresses_repeated

  !> principal_stresses of the plane state sv gives the values want.
  subroutine check_plane(sv, want)
    real(wp), intent(in) :: sv(6), want(3)
    real(wp) :: sig(3), vec(3, 3)
    call principal_stresses(sv, sig, vec)
    call check_reconstruct(sv, sig, vec)
    call check(maxval(abs(sig - want)) <= 1.0e-15_wp*maxval(abs(want)), 'plane repeated values')
  end subroutine check_plane

  !> V diag(sigma) V^T = sv, V orthonormal, sigma descending with the trace of sv.
  subroutine check_reconstruct(sv, sig, vec)
    real(wp), intent(in) :: sv(6), sig(3), vec(3, 3)
    real(wp) :: back(3, 3), ident(3, 3)
    integer :: i
    ident = 0.0_wp
    do i = 1, 3
      ident(i, i) = 1.0_wp
    end do
    back = matmul(vec, matmul(reshape([sig(1), 0.0_wp, 0.0_wp, 0.0_wp, sig(2), 0.0_wp, 0.0_wp, &
                                       0.0_wp, sig(3)], [3, 3]), transpose(vec)))
    call check(maxval(abs(to_voigt(back) - sv)) <= 1.0e-13_wp*maxval(abs(sv)), &
               'V diag(sigma) V^T equals the stress')
    call check(maxval(abs(matmul(transpose(vec), vec) - ident)) <= 1.0e-13_wp, &
               'eigenvectors orthonormal')
    call check(sig(1) >= sig(2) .and. sig(2) >= sig(3), 'principal stresses descending')
    call check_close(sum(sig), sv(1) + sv(2) + sv(3), 1.0e-13_wp, 1.0e-9_wp, 'trace kept')
  end subroutine check_reconstruct

  !> Many random trial states: elastic ones come back unchanged, plastic ones lie on the
  !> yield surface; all four MC returns occur.
  subroutine test_mc_random_states_on_surface()
    type(plastic_params_t) :: par
    real(wp) :: sv(6), out(6), epsp, f, scale
    integer :: k, code, seen(0:4)
    logical :: cut
    call begin_test('mc_random_states_on_surface')
    par = params(surface_mohr_coulomb, 30.0_wp, 10.0_wp, 2.0e4_wp, no_cut)
    seen = 0
    do k = 1, 2000
      sv = random_stress(1.0e5_wp)
      if (mod(k, 10) == 0) sv(1:3) = sv(1:3) + 1.5e5_wp   ! more states beyond the apex
      out = sv
      epsp = 0.0_wp
      call plastic_return(par, zero6, out, epsp, code, cut)
      seen(code) = seen(code) + 1
      scale = maxval(abs(sv)) + par%cohesion
      if (code == ret_elastic) then
        call check(all(out == sv), 'elastic state untouched')
        call check(mc_yield(sv, par%sin_phi, par%cos_phi, par%cohesion) <= 1.0e-12_wp*scale, &
                   'elastic only inside the surface')
      else
        f = mc_yield(out, par%sin_phi, par%cos_phi, par%cohesion)
        call check(abs(f) <= 1.0e-10_wp*scale, 'returned stress on the MC surface')
        call check(mc_yield(sv, par%sin_phi, par%cos_phi, par%cohesion) > 0.0_wp, &
                   'plastic only outside the surface')
      end if
      call check(.not. cut, 'no cut-off without one')
    end do
    call check(all(seen > 0), 'elastic, main-plane, both edge and apex returns all occur')
  end subroutine test_mc_random_states_on_surface

  subroutine test_dp_random_states_on_surface()
    type(plastic_params_t) :: par
    real(wp) :: sv(6), out(6), epsp, scale
    integer :: k, code, seen(0:4), match
    logical :: cut
    call begin_test('dp_random_states_on_surface')
    do match = dp_plane_strain, dp_inner
      par = params(surface_drucker_prager, 35.0_wp, 5.0_wp, 1.0e4_wp, no_cut, match=match)
      seen = 0
      do k = 1, 1000
        sv = random_stress(1.0e5_wp)
        if (mod(k, 10) == 0) sv(1:3) = sv(1:3) + 1.5e5_wp
        out = sv
        epsp = 0.0_wp
        call plastic_return(par, zero6, out, epsp, &
                            code, cut)
        seen(code) = seen(code) + 1
        scale = maxval(abs(sv)) + par%cohesion
        if (code == ret_elastic) then
          call check(all(out == sv), 'elastic state untouched')
        else
          call check(abs(dp_yield(out, par%eta, par%xi, par%cohesion)) <= 1.0e-10_wp*scale, &
                     'returned stress on the DP cone')
          call check(dp_yield(sv, par%eta, par%xi, par%cohesion) > 0.0_wp, &
                     'plastic only outside the cone')
        end if
      end do
      call check(seen(ret_elastic) > 0 .and. seen(ret_smooth) > 0 .and. seen(ret_apex) > 0, &
                 'elastic, cone and apex returns occur')
      call check(seen(ret_edge_left) + seen(ret_edge_right) == 0, 'DP has no edges')
    end do
  end subroutine test_dp_random_states_on_surface

  !> Principal-axis trial from a diagonal strain increment: dgamma = f_tr / (4G + 4(K + G/3)
  !> sin phi sin psi), sigma = sigma_tr - dgamma D N, N = (1 + sin psi, 0, -(1 - sin psi)).
  subroutine test_mc_main_plane_closed_form()
    type(plastic_params_t) :: par
    real(wp) :: s0(6), de(6), out(6), tr(3), sphi, spsi, cphi, c, f, dg, ex(3), epsp
    integer :: code
    call begin_test('mc_main_plane_closed_form')
    c = 1.0e4_wp
    par = params(surface_mohr_coulomb, 30.0_wp, 10.0_wp, c, no_cut)
    sphi = sin(30.0_wp*deg); cphi = cos(30.0_wp*deg); spsi = sin(10.0_wp*deg)
    s0 = [-1.0e5_wp, -1.2e5_wp, -1.5e5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    de = [1.0e-2_wp, 0.0_wp, -1.0e-2_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    tr(1) = s0(1) + lam*sum(de(1:3)) + 2.0_wp*gs*de(1)
    tr(2) = s0(2) + lam*sum(de(1:3)) + 2.0_wp*gs*de(2)
    tr(3) = s0(3) + lam*sum(de(1:3)) + 2.0_wp*gs*de(3)
    f = tr(1) - tr(3) + (tr(1) + tr(3))*sphi - 2.0_wp*c*cphi
    call check(f > 0.0_wp, 'trial outside the surface')
    dg = f/(4.0_wp*gs + 4.0_wp*(kb + gs/3.0_wp)*sphi*spsi)
    ex(1) = tr(1) - dg*(2.0_wp*gs*(1.0_wp + spsi) + 2.0_wp*lam*spsi)
    ex(2) = tr(2) - dg*2.0_wp*lam*spsi
    ex(3) = tr(3) - dg*(-2.0_wp*gs*(1.0_wp - spsi) + 2.0_wp*lam*spsi)
    out = s0
    epsp = 0.0_wp
    call plastic_return(par, de, out, epsp, code)
    call check_equal_int(code, ret_smooth, 'main-plane return')
    call check_close(out(1), ex(1), 1.0e-12_wp, 0.0_wp, 'sigma_1')
    call check_close(out(2), ex(2), 1.0e-12_wp, 0.0_wp, 'sigma_2')
    call check_close(out(3), ex(3), 1.0e-12_wp, 0.0_wp, 'sigma_3')
    call check(maxval(abs(out(4:6))) <= 1.0e-9_wp, 'no shear in principal axes')
    call check_close(epsp, 2.0_wp*cphi*dg, 1.0e-12_wp, 0.0_wp, 'epsp = 2 cos(phi) dgamma')
  end subroutine test_mc_main_plane_closed_form

  !> Trial (a, a, b), a > b: the right edge, sigma_1 = sigma_2, by symmetry equal multipliers
  !> on the planes (1,3) and (2,3): sigma = sigma_tr - dgamma D (N_13 + N_23).
  subroutine test_mc_right_edge_closed_form()
    type(plastic_params_t) :: par
    real(wp) :: st(3), sphi, cphi, spsi, c, n(3), dn(3), f, dg, ex(3), out(6), epsp, ax(3)
    integer :: code, i
    call begin_test('mc_right_edge_closed_form')
    c = 5.0e3_wp
    par = params(surface_mohr_coulomb, 30.0_wp, 15.0_wp, c, no_cut)
    sphi = sin(30.0_wp*deg); cphi = cos(30.0_wp*deg); spsi = sin(15.0_wp*deg)
    st = [-2.0e4_wp, -2.0e4_wp, -1.5e5_wp]
    n = [1.0_wp + spsi, 1.0_wp + spsi, -2.0_wp*(1.0_wp - spsi)]
    do i = 1, 3
      dn(i) = lam*sum(n) + 2.0_wp*gs*n(i)
    end do
    f = (1.0_wp + sphi)*st(1) - (1.0_wp - sphi)*st(3) - 2.0_wp*c*cphi
    dg = f/((1.0_wp + sphi)*dn(1) - (1.0_wp - sphi)*dn(3))
    ex = st - dg*dn
    ax = [0.3_wp, -0.5_wp, 0.8_wp]
    out = stress_in_axes(st, ax, 0.7_wp)
    epsp = 0.0_wp
    call plastic_return(par, zero6, out, epsp, code)
    call check_equal_int(code, ret_edge_right, 'right-edge return')
    call check(maxval(abs(out - stress_in_axes(ex, ax, 0.7_wp))) <= 1.0e-10_wp*maxval(abs(st)), &
               'stress of the symmetric two-plane return')
    call check(dg > 0.0_wp, 'positive multipliers')
    call check_close(epsp, 2.0_wp*cphi*2.0_wp*dg, 1.0e-10_wp, 0.0_wp, &
                     'epsp = 2 cos(phi) sum dgamma')
  end subroutine test_mc_right_edge_closed_form

  !> Trial (a, b, b), a > b: the left edge, sigma_2 = sigma_3, planes (1,3) and (1,2).
  subroutine test_mc_left_edge_closed_form()
    type(plastic_params_t) :: par
    real(wp) :: st(3), sphi, cphi, spsi, c, n(3), dn(3), f, dg, ex(3), out(6), epsp, ax(3)
    integer :: code, i
    call begin_test('mc_left_edge_closed_form')
    c = 5.0e3_wp
    par = params(surface_mohr_coulomb, 30.0_wp, 15.0_wp, c, no_cut)
    sphi = sin(30.0_wp*deg); cphi = cos(30.0_wp*deg); spsi = sin(15.0_wp*deg)
    st = [-1.0e4_wp, -1.5e5_wp, -1.5e5_wp]
    n = [2.0_wp*(1.0_wp + spsi), -(1.0_wp - spsi), -(1.0_wp - spsi)]
    do i = 1, 3
      dn(i) = lam*sum(n) + 2.0_wp*gs*n(i)
    end do
    f = (1.0_wp + sphi)*st(1) - (1.0_wp - sphi)*st(3) - 2.0_wp*c*cphi
    dg = f/((1.0_wp + sphi)*dn(1) - (1.0_wp - sphi)*dn(3))
    ex = st - dg*dn
    ax = [-0.2_wp, 0.9_wp, 0.1_wp]
    out = stress_in_axes(st, ax, 1.3_wp)
    epsp = 0.0_wp
    call plastic_return(par, zero6, out, epsp, code)
    call check_equal_int(code, ret_edge_left, 'left-edge return')
    call check(maxval(abs(out - stress_in_axes(ex, ax, 1.3_wp))) <= 1.0e-10_wp*maxval(abs(st)), &
               'stress of the symmetric two-plane return')
    call check(dg > 0.0_wp, 'positive multipliers')
  end subroutine test_mc_left_edge_closed_form

  !> Beyond the apex the stress goes to c cot(phi) I; with c = 0 to zero.
  subroutine test_mc_apex()
    type(plastic_params_t) :: par
    real(wp) :: out(6), epsp, c, apex
    integer :: code
    call begin_test('mc_apex')
    c = 2.0e4_wp
    apex = c/tan(25.0_wp*deg)
    par = params(surface_mohr_coulomb, 25.0_wp, 5.0_wp, c, no_cut)
    out = stress_in_axes([1.3_wp*apex, 1.2_wp*apex, 1.1_wp*apex], [1.0_wp, 1.0_wp, 0.0_wp], 0.4_wp)
    epsp = 0.0_wp
    call plastic_return(par, zero6, out, epsp, code)
    call check_equal_int(code, ret_apex, 'apex return')
    call check(maxval(abs(out - [apex, apex, apex, 0.0_wp, 0.0_wp, 0.0_wp])) <= 1.0e-10_wp*apex, &
               'sigma = c cot(phi) I')
    par = params(surface_mohr_coulomb, 30.0_wp, 0.0_wp, 0.0_wp, no_cut)
    out = [1.0e3_wp, -2.0e2_wp, 5.0e2_wp, 1.0e2_wp, 0.0_wp, -3.0e2_wp]
    epsp = 0.0_wp
    call plastic_return(par, zero6, out, epsp, code)
    call check_equal_int(code, ret_apex, 'apex return of a tensile state without cohesion')
    call check(maxval(abs(out)) <= 1.0e-10_wp, 'sigma = 0 for c = 0')
  end subroutine test_mc_apex

  !> Pure shear from an isotropic state: q_tr = G gamma, dgamma = f_tr / (G + K eta eta_bar),
  !> tau = tau_tr - G dgamma, p = p0 - K eta_bar dgamma.
  subroutine test_dp_cone_closed_form()
    type(plastic_params_t) :: par
    real(wp) :: p0, gam, f, dg, out(6), epsp, c
    integer :: code
    call begin_test('dp_cone_closed_form')
    c = 5.0e3_wp
    par = params(surface_drucker_prager, 30.0_wp, 10.0_wp, c, no_cut)
    p0 = -5.0e4_wp
    gam = 2.0e-2_wp
    f = gs*gam + par%eta*p0 - par%xi*c
    call check(f > 0.0_wp, 'trial outside the cone')
    dg = f/(gs + kb*par%eta*par%eta_bar)
    out = [p0, p0, p0, 0.0_wp, 0.0_wp, 0.0_wp]
    epsp = 0.0_wp
    call plastic_return(par, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, gam], out, epsp, code)
    call check_equal_int(code, ret_smooth, 'cone return')
    call check_close(out(6), gs*gam - gs*dg, 1.0e-12_wp, 0.0_wp, 'tau')
    call check_close(out(1), p0 - kb*par%eta_bar*dg, 1.0e-12_wp, 0.0_wp, 'sigma_xx = p')
    call check_close(out(3), p0 - kb*par%eta_bar*dg, 1.0e-12_wp, 0.0_wp, 'sigma_zz = p')
    call check_close(epsp, par%xi*dg, 1.0e-12_wp, 0.0_wp, 'epsp = xi dgamma')
  end subroutine test_dp_cone_closed_form

  subroutine test_dp_apex()
    type(plastic_params_t) :: par
    real(wp) :: out(6), epsp, c, apex
    integer :: code
    call begin_test('dp_apex')
    c = 1.0e4_wp
    par = params(surface_drucker_prager, 30.0_wp, 0.0_wp, c, no_cut)
    apex = par%xi*c/par%eta
    call check_close(apex, c/tan(30.0_wp*deg), 1.0e-12_wp, 0.0_wp, &
                     'the plane-strain cone has the MC apex c cot(phi)')
    out = [1.5_wp*apex, 1.4_wp*apex, 1.3_wp*apex, 0.01_wp*apex, 0.0_wp, 0.0_wp]
    epsp = 0.0_wp
    call plastic_return(par, zero6, out, epsp, code)
    call check_equal_int(code, ret_apex, 'apex return')
    call check(maxval(abs(out - [apex, apex, apex, 0.0_wp, 0.0_wp, 0.0_wp])) <= 1.0e-10_wp*apex, &
               'sigma = xi c / eta I')
  end subroutine test_dp_apex

  !> The plastic strain d eps - C^-1 d sigma is parallel to dg/dsigma at the returned stress
  !> (finite differences of g), for non-associated flow.
  subroutine test_mc_flow_follows_potential()
    type(plastic_params_t) :: par
    call begin_test('mc_flow_follows_potential')
    par = params(surface_mohr_coulomb, 32.0_wp, 8.0_wp, 1.0e4_wp, no_cut)
    call flow_direction_checks(par)
  end subroutine test_mc_flow_follows_potential

  subroutine test_dp_flow_follows_potential()
    type(plastic_params_t) :: par
    call begin_test('dp_flow_follows_potential')
    par = params(surface_drucker_prager, 32.0_wp, 8.0_wp, 1.0e4_wp, no_cut, match=dp_outer)
    call flow_direction_checks(par)
  end subroutine test_dp_flow_follows_potential

  subroutine flow_direction_checks(par)
    type(plastic_params_t), intent(in) :: par
    real(wp) :: s0(6), de(6), out(6), dep(6), g(6), epsp
    integer :: k, code, nsmooth
    nsmooth = 0
    do k = 1, 300
      s0 = random_stress(5.0e4_wp)
      s0(1:3) = s0(1:3) - 1.0e5_wp
      de = 4.0e-2_wp*[urand() - 0.5_wp, urand() - 0.5_wp, urand() - 0.5_wp, urand() - 0.5_wp, &
                      urand() - 0.5_wp, urand() - 0.5_wp]
      out = s0
      epsp = 0.0_wp
      call plastic_return(par, de, out, epsp, code)
      if (code /= ret_smooth) cycle
      nsmooth = nsmooth + 1
      dep = de - compliance(out - s0)
      g = potential_gradient(par, out)
      call check(norm2(dep/norm2(dep) - g/norm2(g)) <= 1.0e-6_wp, &
                 'plastic strain increment along the potential gradient')
    end do
    call check(nsmooth > 50, 'enough smooth returns sampled')
  end subroutine flow_direction_checks

  !> Rankine cut-off sigma_i <= sigma_t inside the MC surface: one, two and three planes,
  !> with lambda = K - 2G/3 and d = lambda + 2G the principal elasticity.
  subroutine test_mc_tension_cutoff()
    type(plastic_params_t) :: par
    real(wp) :: t, out(6), epsp, d, g1, g2, r1, r2
    integer :: code
    logical :: cut
    call begin_test('mc_tension_cutoff')
    t = 1.0e4_wp
    d = lam + 2.0_wp*gs
    par = params(surface_mohr_coulomb, 30.0_wp, 0.0_wp, 5.0e4_wp, t)
    ! uniaxial tension inside MC
    out = [4.0e4_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    call check(mc_yield(out, par%sin_phi, par%cos_phi, par%cohesion) < 0.0_wp, 'inside MC')
    epsp = 0.0_wp
    call plastic_return(par, zero6, out, epsp, code, cut)
    call check(cut, 'cut-off acts')
    call check_equal_int(code, ret_elastic, 'no shear return')
    ! (each result times exp(-eps_v^p), eps_v^p the sum of the multipliers: the opening)
    g1 = 3.0e4_wp/d
    call check_close(out(1), t*exp(-g1), 1.0e-12_wp, 0.0_wp, 'sigma_1 = sigma_t')
    call check_close(out(2), -lam*g1*exp(-g1), 1.0e-12_wp, 0.0_wp, 'sigma_2 = -lambda dgamma')
    call check_close(out(3), -lam*g1*exp(-g1), 1.0e-12_wp, 0.0_wp, 'sigma_3 = -lambda dgamma')
    call check_close(epsp, 0.0_wp, 0.0_wp, 0.0_wp, 'cut-off leaves epsp')
    ! corner of two planes
    out = [3.0e4_wp, 2.0e4_wp, -5.0e4_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    call check(mc_yield(out, par%sin_phi, par%cos_phi, par%cohesion) < 0.0_wp, 'inside MC')
    call plastic_return(par, zero6, out, epsp, code, cut)
    r1 = 3.0e4_wp - t
    r2 = 2.0e4_wp - t
    g1 = (d*r1 - lam*r2)/(d*d - lam*lam)
    g2 = (d*r2 - lam*r1)/(d*d - lam*lam)
    call check(cut .and. g1 > 0.0_wp .and. g2 > 0.0_wp, 'two planes active')
    call check_close(out(1), t*exp(-g1 - g2), 1.0e-12_wp, 0.0_wp, 'sigma_1 = sigma_t')
    call check_close(out(2), t*exp(-g1 - g2), 1.0e-12_wp, 0.0_wp, 'sigma_2 = sigma_t')
    call check_close(out(3), (-5.0e4_wp - lam*(g1 + g2))*exp(-g1 - g2), 1.0e-12_wp, 0.0_wp, &
                     'sigma_3')
    ! hydrostatic tension below the apex: all three, each multiplier (2e4 - t)/(3K)
    out = [2.0e4_wp, 2.0e4_wp, 2.0e4_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    call plastic_return(par, zero6, out, epsp, code, cut)
    call check(maxval(abs(out - t*exp(-(2.0e4_wp - t)/kb)*[1.0_wp, 1.0_wp, 1.0_wp, 0.0_wp, &
                                                           0.0_wp, 0.0_wp])) <= 1.0e-10_wp*t, &
               'sigma = sigma_t I')
    ! a shear return followed by the cut-off stays inside MC
    out = [6.0e4_wp, -1.0e4_wp, -9.0e4_wp, 2.0e4_wp, 0.0_wp, 0.0_wp]
    call plastic_return(par, zero6, out, epsp, code, cut)
    call check(cut, 'cut-off after the shear return')
    call check(mc_yield(out, par%sin_phi, par%cos_phi, par%cohesion) <= 1.0e-10_wp*1.0e5_wp, &
               'still inside MC after the cut-off')
  end subroutine test_mc_tension_cutoff

  subroutine test_dp_tension_cutoff()
    type(plastic_params_t) :: par
    real(wp) :: t, out(6), s0(6), epsp, a
    integer :: code
    logical :: cut
    call begin_test('dp_tension_cutoff')
    t = 5.0e3_wp
    par = params(surface_drucker_prager, 30.0_wp, 0.0_wp, 2.0e4_wp, t)
    s0 = [1.5e4_wp, 1.0e4_wp, 0.5e4_wp, 1.0e3_wp, 0.0_wp, 0.0_wp]
    call check(dp_yield(s0, par%eta, par%xi, par%cohesion) < 0.0_wp, 'inside the cone')
    out = s0
    epsp = 0.0_wp
    call plastic_return(par, zero6, out, epsp, code, cut)
    call check(cut, 'cut-off acts')
    ! the state times exp(-eps_v^p), eps_v^p = (p - sigma_t)/K the opening
    a = exp(-(1.0e4_wp - t)/kb)
    call check_close(sum(out(1:3))/3.0_wp, t*a, 1.0e-12_wp, 0.0_wp, 'p = sigma_t')
    call check(maxval(abs((out(1:3) - sum(out(1:3))/3.0_wp) - (s0(1:3) - 1.0e4_wp)*a)) &
               <= 1.0e-9_wp .and. maxval(abs(out(4:6) - s0(4:6)*a)) <= 1.0e-9_wp, &
               'deviator unchanged')
  end subroutine test_dp_tension_cutoff

  !> Rotating the state and the increment, returning, and rotating back gives the same stress.
  subroutine test_objectivity_under_rotation()
    type(plastic_params_t) :: par(2)
    real(wp) :: s0(6), de(6), a(6), b(6), r(3, 3), rt(3, 3), ea, eb
    integer :: k, m, ca, cb
    call begin_test('objectivity_under_rotation')
    par(1) = params(surface_mohr_coulomb, 30.0_wp, 10.0_wp, 1.0e4_wp, 5.0e3_wp)
    par(2) = params(surface_drucker_prager, 30.0_wp, 10.0_wp, 1.0e4_wp, 5.0e3_wp)
    do m = 1, 2
      do k = 1, 200
        s0 = random_stress(5.0e4_wp)
        de = 1.0e-2_wp*[urand() - 0.5_wp, urand() - 0.5_wp, urand() - 0.5_wp, urand() - 0.5_wp, &
                        urand() - 0.5_wp, urand() - 0.5_wp]
        r = rotation(random_axis(), 2.0_wp*pi*urand())
        a = s0
        ea = 0.0_wp
        call plastic_return(par(m), de, a, ea, ca)
        b = rotate_stress(r, s0)
        eb = 0.0_wp
        call plastic_return(par(m), rotate_strain(r, de), b, eb, cb)
        rt = transpose(r)
        b = rotate_stress(rt, b)
        call check(maxval(abs(a - b)) <= 1.0e-10_wp*(maxval(abs(s0)) + 1.0e4_wp), &
                   'R^T return(R sigma R^T, R deps R^T) R = return(sigma, deps)')
        call check_close(eb, ea, 1.0e-9_wp, 1.0e-15_wp, 'same plastic strain')
        call check_equal_int(cb, ca, 'same return')
      end do
    end do
  end subroutine test_objectivity_under_rotation

  !> A curved strain path split into n steps: the end stress converges as n grows
  !> (backward Euler, first order: the change halves when n doubles).
  subroutine test_small_steps_converge()
    type(plastic_params_t) :: par(2)
    real(wp) :: s(6, 6), d(5), diff(5)
    integer :: m, j
    call begin_test('small_steps_converge')
    par(1) = params(surface_mohr_coulomb, 30.0_wp, 5.0_wp, 5.0e3_wp, no_cut)
    par(2) = params(surface_drucker_prager, 30.0_wp, 5.0_wp, 5.0e3_wp, no_cut)
    do m = 1, 2
      do j = 1, 6
        s(:, j) = path_end(par(m), 4*2**j)
      end do
      do j = 1, 5
        diff(j) = norm2(s(:, j + 1) - s(:, j))
      end do
      d = diff
      call check(all(d(2:5) < d(1:4)), 'the change decreases as the steps shrink')
      call check(d(5)/d(4) < 0.7_wp .and. d(4)/d(3) < 0.7_wp, 'about first-order convergence')
      call check(d(5) < 1.0e-2_wp*norm2(s(:, 6)), 'converged to 1 percent')
    end do
  end subroutine test_small_steps_converge

  function path_end(par, n) result(sv)
    type(plastic_params_t), intent(in) :: par
    integer, intent(in) :: n
    real(wp) :: sv(6), epsp, t0, t1
    integer :: k
    sv = [-5.0e4_wp, -5.0e4_wp, -5.0e4_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    epsp = 0.0_wp
    do k = 1, n
      t0 = real(k - 1, wp)/n
      t1 = real(k, wp)/n
      call plastic_return(par, strain_path(t1) - strain_path(t0), sv, epsp)
    end do
  end function path_end

  !> A strain path that turns: shear first, then compression and a second shear.
  pure function strain_path(t) result(e)
    real(wp), intent(in) :: t
    real(wp) :: e(6)
    e = [-2.0e-2_wp*t**2, 1.0e-2_wp*t**2, 0.0_wp, 0.0_wp, 1.5e-2_wp*t**3, 3.0e-2_wp*t]
  end function strain_path

  !> The matched cones touch MC where they should: the outer cone on the compressive
  !> meridian (sigma_1 = sigma_2 > sigma_3), the inner on the extension meridian
  !> (sigma_1 > sigma_2 = sigma_3), the plane-strain cone at the out-of-plane stress where
  !> the associated DP flow has no out-of-plane component (dg/dsigma_zz = 0).
  subroutine test_dp_matches_mc_on_meridians()
    type(plastic_params_t) :: po, pi_, pp
    real(wp) :: c, sphi, cphi, p, dd, sv(6), m, r, lo, hi, mid, s2
    integer :: k, it
    call begin_test('dp_matches_mc_on_meridians')
    c = 1.0e4_wp
    sphi = sin(30.0_wp*deg); cphi = cos(30.0_wp*deg)
    po = params(surface_drucker_prager, 30.0_wp, 30.0_wp, c, no_cut, match=dp_outer)
    pi_ = params(surface_drucker_prager, 30.0_wp, 30.0_wp, c, no_cut, match=dp_inner)
    pp = params(surface_drucker_prager, 30.0_wp, 30.0_wp, c, no_cut, match=dp_plane_strain)
    do k = 0, 4
      p = -2.0e4_wp*k
      ! compressive meridian: sigma = (p + d/3, p + d/3, p - 2d/3) on MC
      dd = 6.0_wp*(c*cphi - p*sphi)/(3.0_wp - sphi)
      sv = [p + dd/3.0_wp, p + dd/3.0_wp, p - 2.0_wp*dd/3.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
      call check(abs(mc_yield(sv, sphi, cphi, c)) <= 1.0e-10_wp*(abs(p) + c), 'point on MC')
      call check(abs(dp_yield(sv, po%eta, po%xi, c)) <= 1.0e-10_wp*(abs(p) + c), &
                 'outer cone on the compressive meridian')
      call check(dp_yield(sv, pi_%eta, pi_%xi, c) > 1.0e-6_wp*(abs(p) + c), &
                 'inner cone inside there')
      ! extension meridian: sigma = (p + 2d/3, p - d/3, p - d/3)
      dd = 6.0_wp*(c*cphi - p*sphi)/(3.0_wp + sphi)
      sv = [p + 2.0_wp*dd/3.0_wp, p - dd/3.0_wp, p - dd/3.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
      call check(abs(mc_yield(sv, sphi, cphi, c)) <= 1.0e-10_wp*(abs(p) + c), 'point on MC')
      call check(abs(dp_yield(sv, pi_%eta, pi_%xi, c)) <= 1.0e-10_wp*(abs(p) + c), &
                 'inner cone on the extension meridian')
      ! plane strain: in-plane sigma_1, sigma_3 on MC, sigma_zz from dg/dsigma_zz = 0
      m = p
      r = c*cphi - m*sphi
      lo = m - r
      hi = m + r
      do it = 1, 200
        mid = 0.5_wp*(lo + hi)
        sv = [m + r, m - r, mid, 0.0_wp, 0.0_wp, 0.0_wp]
        if (dgdzz(sv, pp%eta) > 0.0_wp) then
          hi = mid
        else
          lo = mid
        end if
      end do
      s2 = 0.5_wp*(lo + hi)
      sv = [m + r, m - r, s2, 0.0_wp, 0.0_wp, 0.0_wp]
      call check(abs(dp_yield(sv, pp%eta, pp%xi, c)) <= 1.0e-10_wp*(abs(p) + c), &
                 'plane-strain cone at the plane-strain state of MC')
    end do
  end subroutine test_dp_matches_mc_on_meridians

  !> dg/dsigma_zz of the associated DP potential, s_zz / (2 sqrt(J2)) + eta / 3.
  pure real(wp) function dgdzz(sv, eta)
    real(wp), intent(in) :: sv(6), eta
    real(wp) :: p, j2
    p = sum(sv(1:3))/3.0_wp
    j2 = 0.5_wp*sum((sv(1:3) - p)**2)
    dgdzz = (sv(3) - p)/(2.0_wp*sqrt(j2)) + eta/3.0_wp
  end function dgdzz

  !> DP with linear cohesion softening c = c0 - h epsp, epsp += xi dgamma:
  !> dgamma = f_tr / (G + K eta eta_bar - xi^2 h); past the residual c = c_res.
  subroutine test_dp_softening_closed_form()
    type(plastic_params_t) :: par
    real(wp) :: c0, h, cres, p0, gam, f, dg, out(6), epsp, cnew
    call begin_test('dp_softening_closed_form')
    c0 = 2.0e4_wp
    h = 1.0e5_wp
    cres = 5.0e3_wp
    par = params(surface_drucker_prager, 30.0_wp, 10.0_wp, c0, no_cut, h=h, cres=cres)
    p0 = -5.0e4_wp
    gam = 2.0e-2_wp
    call check(gs*gam + par%eta*p0 - par%xi*c0 > 0.0_wp, 'trial outside the cone')
    f = gs*gam + par%eta*p0 - par%xi*c0
    dg = f/(gs + kb*par%eta*par%eta_bar - par%xi**2*h)
    cnew = c0 - h*par%xi*dg
    call check(cnew > cres, 'still above the residual')
    out = [p0, p0, p0, 0.0_wp, 0.0_wp, 0.0_wp]
    epsp = 0.0_wp
    call plastic_return(par, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, gam], out, epsp)
    call check_close(epsp, par%xi*dg, 1.0e-12_wp, 0.0_wp, 'epsp = xi dgamma')
    call check_close(out(6), gs*(gam - dg), 1.0e-12_wp, 0.0_wp, 'tau')
    call check(abs(dp_yield(out, par%eta, par%xi, cnew)) <= 1.0e-10_wp*abs(p0), &
               'on the softened cone')
    ! a large step: the cohesion ends at the residual, the return uses c_res
    out = [p0, p0, p0, 0.0_wp, 0.0_wp, 0.0_wp]
    epsp = 0.0_wp
    call plastic_return(par, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.5_wp], out, epsp)
    call check_close(cohesion_at(par, epsp), cres, 1.0e-12_wp, 0.0_wp, 'at the residual cohesion')
    dg = (gs*0.5_wp + par%eta*p0 - par%xi*cres)/(gs + kb*par%eta*par%eta_bar)
    call check_close(out(6), gs*(0.5_wp - dg), 1.0e-12_wp, 0.0_wp, 'tau with c_res')
    call check(abs(dp_yield(out, par%eta, par%xi, cres)) <= 1.0e-10_wp*abs(p0), &
               'on the residual cone')
  end subroutine test_dp_softening_closed_form

  !> MC main plane with softening: dgamma = f_tr / (a - 4 cos^2(phi) h),
  !> a = 4G + 4(K + G/3) sin phi sin psi; epsp = 2 cos(phi) dgamma.
  subroutine test_mc_softening_closed_form()
    type(plastic_params_t) :: par
    real(wp) :: s0(6), de(6), out(6), tr(3), sphi, spsi, cphi, c0, h, f, dg, epsp
    call begin_test('mc_softening_closed_form')
    c0 = 2.0e4_wp
    h = 2.0e5_wp
    par = params(surface_mohr_coulomb, 30.0_wp, 10.0_wp, c0, no_cut, h=h, cres=0.0_wp)
    sphi = sin(30.0_wp*deg); cphi = cos(30.0_wp*deg); spsi = sin(10.0_wp*deg)
    s0 = [-1.0e5_wp, -1.2e5_wp, -1.5e5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    de = [1.0e-2_wp, 0.0_wp, -1.0e-2_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    tr = s0(1:3) + lam*sum(de(1:3)) + 2.0_wp*gs*de(1:3)
    f = tr(1) - tr(3) + (tr(1) + tr(3))*sphi - 2.0_wp*c0*cphi
    call check(f > 0.0_wp, 'trial outside the surface')
    dg = f/(4.0_wp*gs + 4.0_wp*(kb + gs/3.0_wp)*sphi*spsi - 4.0_wp*cphi**2*h)
    out = s0
    epsp = 0.0_wp
    call plastic_return(par, de, out, epsp)
    call check_close(epsp, 2.0_wp*cphi*dg, 1.0e-12_wp, 0.0_wp, 'epsp = 2 cos(phi) dgamma')
    call check(abs(mc_yield(out, sphi, cphi, c0 - h*epsp)) <= 1.0e-10_wp*1.0e5_wp, &
               'on the softened surface')
    call check(c0 - h*epsp < c0 .and. c0 - h*epsp > 0.0_wp, 'cohesion softened, not exhausted')
    out = elastic_trial(par, s0, de)
    call check(maxval(abs(out(1:3) - tr)) <= 1.0e-9_wp, 'trial stress')
  end subroutine test_mc_softening_closed_form

  !> A set with plastic history packs, unpacks and removes its epsp with the points (the
  !> path of migration and checkpoints); a set without it stores and packs nothing more.
  subroutine test_points_carry_plastic_strain()
    type(particle_set_t) :: a, b, e
    real(wp), allocatable :: buf(:, :)
    logical :: gone(3)
    integer :: k
    call begin_test('points_carry_plastic_strain')
    call a%init('solid', 2, .false., nstate=1)
    call b%init('solid', 2, .false., nstate=1)
    call e%init('solid', 2, .false.)
    do k = 1, 3
      call a%append(int(k, i8), 1, [0.1_wp*k, 0.0_wp], [0.0_wp, 0.0_wp], 1.0_wp, 1.0_wp, &
                    [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp])
      call e%append(int(k, i8), 1, [0.1_wp*k, 0.0_wp], [0.0_wp, 0.0_wp], 1.0_wp, 1.0_wp, &
                    [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp])
    end do
    call check(all(a%state(1, 1:3) == 0.0_wp), 'new points start without plastic strain')
    a%state(1, 1:3) = [1.0e-3_wp, 2.0e-3_wp, 3.0e-3_wp]
    call check_equal_int(a%nreal_packed(), e%nreal_packed() + 1, 'one more packed real')
    call check(.not. allocated(e%state), 'no plastic history without a plastic material')
    allocate (buf(a%nreal_packed(), 2))
    call a%pack_points([3, 1], buf)
    call b%unpack_points(buf)
    call check(b%n == 2 .and. b%state(1, 1) == 3.0e-3_wp .and. b%state(1, 2) == 1.0e-3_wp, &
               'epsp travels with its points')
    gone = [.true., .false., .false.]
    call a%remove(gone)
    ! (the last point fills the hole of the first)
    call check(a%n == 2 .and. all(a%id(1:2) == [3_i8, 2_i8]) .and. a%state(1, 1) == 3.0e-3_wp .and. &
               a%state(1, 2) == 2.0e-3_wp, 'epsp stays with its points when points are removed')
    call a%free()
    call b%free()
    call e%free()
  end subroutine test_points_carry_plastic_strain

  !> stress_update of a drucker_prager material under a pure shear increment gamma from an
  !> isotropic state p0, psi = 0: dgamma = f_tr / G, tau = G (gamma - dgamma), and the
  !> plastic work V (tau_n + tau_n+1)/2 dgamma = V G (gamma - dgamma) dgamma / 2.
  subroutine test_stress_update_plastic_work()
    type(material_t), allocatable :: mats(:)
    real(wp) :: vgrad(9, 1), stress(6, 1), vol(1), vol0(1), epsp(1, 1), work, dt, gam, p0, f, dg
    call begin_test('stress_update_plastic_work')
    call materials_from_config([material_cfg_t(id=1, model='drucker_prager', &
                                               youngs_modulus=youngs, poisson_ratio=nu, &
                                               friction_angle=30.0_wp, cohesion=5.0e3_wp)], mats)
    dt = 1.0e-3_wp
    gam = 2.0e-2_wp
    p0 = -5.0e4_wp
    vgrad = 0.0_wp
    vgrad(2, 1) = 0.5_wp*gam/dt   ! L_yx
    vgrad(4, 1) = 0.5_wp*gam/dt   ! L_xy
    stress(:, 1) = [p0, p0, p0, 0.0_wp, 0.0_wp, 0.0_wp]
    vol = 2.0_wp
    vol0 = 2.0_wp
    epsp = 0.0_wp
    work = 0.0_wp
    call stress_update(mats(1), 1, dt, 1, [1], vgrad, stress, vol, vol0, state=epsp, &
                       dissipation=work)
    f = gs*gam + mats(1)%plastic%eta*p0 - mats(1)%plastic%xi*5.0e3_wp
    dg = f/gs
    call check(f > 0.0_wp, 'plastic step')
    call check_close(stress(6, 1), gs*(gam - dg), 1.0e-12_wp, 0.0_wp, 'tau')
    call check_close(work, 0.5_wp*2.0_wp*gs*(gam - dg)*dg, 1.0e-10_wp, 0.0_wp, 'plastic work')
  end subroutine test_stress_update_plastic_work

  !> A cohesionless point stretched by det(I + dt L) = 1.05^2 per step stays at the apex
  !> (zero stress). Without a bound its volume grows as 1.05^(2n); with max_dilation = 3
  !> it stops at 3 V0 (for Mohr-Coulomb and Drucker-Prager alike), and the first
  !> compression step lowers it from there by 0.95^2.
  !> A point on the tension cut-off (sigma_t = 0, Tresca c = 25 kPa; principal stresses 0, s2
  !> and s3 within Tresca, in random axes) opened along the axis n of its zero principal
  !> stress by d eps = delta (n n + a random rest of 0.1), delta in [1e-4, 1e-3], 2000 times.
  !> The grid does the work W = (sigma_n + sigma_n+1)/2 : d eps per unit of the old volume,
  !> and the new volume is J = det(I + d eps) times the old, so the stored energy may not
  !> grow by more than W: J w(sigma_n+1) - w(sigma_n) - W <= 0, w = sigma : C^-1 : sigma / 2.
  !> Measured, as a fraction of delta w(sigma_n): at most -0.89 with the opening factor,
  !> +1.12 with the Cauchy stress kept through the opening (energy without work)
  !> (doc/verification.md, "Tension cut-off: opening without work").
  subroutine test_cutoff_opening_gains_no_energy()
    type(plastic_params_t) :: par
    real(wp) :: s0(6), out(6), de(6), n(3), e(3, 3), delta, epsp, w0, w1, work, jac, worst, gain
    integer :: k, i, j
    logical :: cut
    call begin_test('cutoff_opening_gains_no_energy')
    par = params(surface_mohr_coulomb, 0.0_wp, 0.0_wp, 2.5e4_wp, 0.0_wp)
    worst = -huge(1.0_wp)
    do k = 1, 2000
      n = random_axis()
      ! principal values 0, s2 and s3 within Tresca (s2 - s3 <= 2c), in random axes
      s0 = stress_in_axes([0.0_wp, -2.5e4_wp*urand(), -2.5e4_wp - 2.5e4_wp*urand()], n, &
                          2.0_wp*pi*urand())
      delta = 1.0e-4_wp + 9.0e-4_wp*urand()
      ! the opening along the principal axis of the zero value
      call opening_axis(s0, n)
      do j = 1, 3
        do i = 1, 3
          e(i, j) = delta*(n(i)*n(j) + 0.1_wp*(urand() - 0.5_wp))
        end do
      end do
      e = 0.5_wp*(e + transpose(e))
      de = [e(1, 1), e(2, 2), e(3, 3), 2.0_wp*e(2, 3), 2.0_wp*e(1, 3), 2.0_wp*e(1, 2)]
      out = s0
      epsp = 0.0_wp
      call plastic_return(par, de, out, epsp, cut=cut)
      call check(cut, 'the cut-off acts')
      do i = 1, 3
        e(i, i) = e(i, i) + 1.0_wp
      end do
      jac = e(1, 1)*(e(2, 2)*e(3, 3) - e(2, 3)*e(3, 2)) &
            - e(1, 2)*(e(2, 1)*e(3, 3) - e(2, 3)*e(3, 1)) &
            + e(1, 3)*(e(2, 1)*e(3, 2) - e(2, 2)*e(3, 1))
      w0 = 0.5_wp*dot_product(s0, compliance(s0))
      w1 = 0.5_wp*dot_product(out, compliance(out))
      work = 0.5_wp*dot_product(s0 + out, de)
      gain = (jac*w1 - w0 - work)/(delta*w0)
      worst = max(worst, gain)
    end do
    print '(a,es10.2)', '  largest energy gain over delta w(sigma_n): ', worst
    call check(worst <= 0.0_wp, 'no energy from an opening at the cut-off')
  end subroutine test_cutoff_opening_gains_no_energy

  !> n: the unit principal axis of the Voigt stress sv whose principal value is closest to 0.
  subroutine opening_axis(sv, n)
    real(wp), intent(in) :: sv(6)
    real(wp), intent(out) :: n(3)
    real(wp) :: sig(3), vec(3, 3)
    call principal_stresses(sv, sig, vec)
    n = vec(:, minloc(abs(sig), dim=1))
  end subroutine opening_axis

  subroutine test_dilation_bound()
    type(material_t), allocatable :: mats(:)
    real(wp) :: vgrad(9, 1), stress(6, 1), vol(1), vol0(1), epsp(1, 1), dt
    integer :: m, step
    character(len=*), parameter :: models(2) = [character(len=16) :: 'mohr_coulomb', 'drucker_prager']
    call begin_test('dilation_bound')
    dt = 1.0e-3_wp
    do m = 1, 2
      call materials_from_config([material_cfg_t(id=1, model=models(m), youngs_modulus=youngs, &
                                                 poisson_ratio=nu, friction_angle=30.0_wp), &
                                  material_cfg_t(id=2, model=models(m), youngs_modulus=youngs, &
                                                 poisson_ratio=nu, friction_angle=30.0_wp, &
                                                 max_dilation=3.0_wp)], mats)
      vgrad = 0.0_wp
      vgrad(1, 1) = 0.05_wp/dt
      vgrad(5, 1) = 0.05_wp/dt
      ! no bound
      stress = 0.0_wp; vol = 1.0e-4_wp; vol0 = 1.0e-4_wp; epsp = 0.0_wp
      do step = 1, 40
        call stress_update(mats(1), 1, dt, 1, [1], vgrad, stress, vol, vol0, state=epsp)
      end do
      call check_close(vol(1)/vol0(1), 1.05_wp**80, 1.0e-12_wp, 0.0_wp, trim(models(m))//' unbounded volume')
      call check(all(abs(stress) < 1.0e-9_wp), trim(models(m))//' stress free without the bound')
      ! bound 3
      stress = 0.0_wp; vol = 1.0e-4_wp; vol0 = 1.0e-4_wp; epsp = 0.0_wp
      do step = 1, 40
        call stress_update(mats(2), 2, dt, 1, [2], vgrad, stress, vol, vol0, state=epsp)
        call check(vol(1) <= 3.0_wp*vol0(1)*(1.0_wp + 1.0e-15_wp), trim(models(m))//' volume within the bound')
      end do
      call check_close(vol(1)/vol0(1), 3.0_wp, 1.0e-15_wp, 0.0_wp, trim(models(m))//' volume at the bound')
      call check(all(abs(stress) < 1.0e-9_wp), trim(models(m))//' stress free at the bound')
      vgrad(1, 1) = -0.05_wp/dt
      vgrad(5, 1) = -0.05_wp/dt
      call stress_update(mats(2), 2, dt, 1, [2], vgrad, stress, vol, vol0, state=epsp)
      call check_close(vol(1)/vol0(1), 3.0_wp*0.95_wp**2, 1.0e-14_wp, 0.0_wp, &
                       trim(models(m))//' compression lowers the volume from the bound')
    end do
  end subroutine test_dilation_bound

end program test_plasticity
