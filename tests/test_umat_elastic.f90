!> The UMAT wrapper (dpmpm_model_umat) with the linear-elastic example UMAT
!> (src/materials/umat/umat_linear_elastic.f, linked into this program): through stress_update it gives
!> what the built-in linear_elastic gives, to round-off, on random strain paths in 3D and
!> in plane strain (stress, volume, stored energy), and it keeps the total strain STRAN.
!> Measured differences and bounds: doc/verification.md, "A user's UMAT".
program test_umat_elastic
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: material_cfg_t, max_props
  use dpmpm_materials, only: material_t, materials_from_config, stress_update, strain_energy
  use dpmpm_assert, only: begin_test, check, check_close
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer, parameter :: npt = 40, nsteps = 200
  real(wp), parameter :: young = 2.0e7_wp, nu = 0.3_wp
  !> Largest relative difference of stress, volume and stored energy: measured 2.9e-15 (3D) and 1.4e-15 (plane strain)
  !> (doc/verification.md); bound 1e-13, round-off with a margin.
  real(wp), parameter :: tol = 1.0e-13_wp
  call start_tests()
  call test_elastic_umat_matches_linear_elastic_in_3d()
  call test_elastic_umat_matches_linear_elastic_in_plane_strain()
  call test_umat_keeps_the_total_strain()
  call end_tests()

contains

  !> Material 1 the built-in linear_elastic, material 2 the UMAT with PROPS = E, nu.
  subroutine both(mats)
    type(material_t), allocatable, intent(out) :: mats(:)
    real(wp) :: props(max_props)
    props = 0.0_wp
    props(1:2) = [young, nu]
    call materials_from_config([material_cfg_t(id=1, model='linear_elastic', youngs_modulus=young, &
                                               poisson_ratio=nu), &
                                material_cfg_t(id=2, model='umat', youngs_modulus=young, &
                                               poisson_ratio=nu, umat_props=props, umat_nprops=2)], &
                               mats)
  end subroutine both

  !> A random velocity gradient (1/s) of size about rate, with the third row and column
  !> zero when plane.
  subroutine random_gradient(rate, plane, lv)
    real(wp), intent(in) :: rate
    logical, intent(in) :: plane
    real(wp), intent(out) :: lv(9)
    call random_number(lv)
    lv = rate*(2.0_wp*lv - 1.0_wp)
    if (plane) lv([3, 6, 7, 8, 9]) = 0.0_wp
  end subroutine random_gradient

  !> nsteps random steps of npt points of each material; the largest relative differences
  !> of stress, volume and stored energy between them.
  subroutine random_paths(plane, ds, dv, de)
    logical, intent(in) :: plane
    real(wp), intent(out) :: ds, dv, de
    type(material_t), allocatable :: mats(:)
    real(wp) :: vgrad(9, npt), s1(6, npt), s2(6, npt), v1(npt), v2(npt), v0(npt), st(9, npt)
    real(wp) :: f(9, npt), w, e1, e2
    integer :: p, k, pmat1(npt), pmat2(npt)
    integer, allocatable :: seed(:)
    call random_seed(size=k)
    allocate (seed(k))
    seed = 20261128
    call random_seed(put=seed)
    call both(mats)
    pmat1 = 1
    pmat2 = 2
    do p = 1, npt
      call random_number(s1(:, p))
      s1(:, p) = -1.0e5_wp*s1(:, p)
      if (plane) s1(4:5, p) = 0.0_wp
    end do
    s2 = s1
    v0 = 1.0e-3_wp
    v1 = v0
    v2 = v0
    st = 0.0_wp
    f = spread([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], 2, npt)
    w = 0.0_wp
    do k = 1, nsteps
      do p = 1, npt
        call random_gradient(1.0_wp, plane, vgrad(:, p))
      end do
      call stress_update(mats(1), 1, 1.0e-4_wp, npt, pmat1, vgrad, s1, v1, v0, plane=plane)
      call stress_update(mats(2), 2, 1.0e-4_wp, npt, pmat2, vgrad, s2, v2, v0, f, st, w, &
                         plane=plane)
    end do
    ds = maxval(abs(s2 - s1))/maxval(abs(s1))
    dv = maxval(abs(v2 - v1)/v1)
    e1 = strain_energy(mats(1), 1, npt, pmat1, s1, v1, v0)
    e2 = strain_energy(mats(2), 2, npt, pmat2, s2, v2, v0, f, st)
    de = abs(e2 - e1)/e1
    print '(a,l2,a,3es10.2)', '  plane', plane, ': stress, volume, energy', ds, dv, de
    call check(w == 0.0_wp, 'no dissipation')
  end subroutine random_paths

  !> The random paths (plane strain where plane) give both materials the same stress,
  !> volume and stored energy to round-off.
  subroutine check_random_paths(plane)
    logical, intent(in) :: plane
    real(wp) :: ds, dv, de
    call random_paths(plane, ds, dv, de)
    call check_close(ds, 0.0_wp, 0.0_wp, tol, 'stress')
    call check_close(dv, 0.0_wp, 0.0_wp, tol, 'volume')
    call check_close(de, 0.0_wp, 0.0_wp, tol, 'stored energy')
  end subroutine check_random_paths

  subroutine test_elastic_umat_matches_linear_elastic_in_3d()
    call begin_test('elastic_umat_matches_linear_elastic_in_3d')
    call check_random_paths(.false.)
  end subroutine test_elastic_umat_matches_linear_elastic_in_3d

  subroutine test_elastic_umat_matches_linear_elastic_in_plane_strain()
    call begin_test('elastic_umat_matches_linear_elastic_in_plane_strain')
    call check_random_paths(.true.)
  end subroutine test_elastic_umat_matches_linear_elastic_in_plane_strain

  !> Without spin, STRAN (state 1:6, dpmpm's order, engineering shears) is the sum of the
  !> increments dt D, and the stress of a shear xy alone is sigma_xy = G gamma_xy: the
  !> order and the engineering shear of the conversion.
  subroutine test_umat_keeps_the_total_strain()
    type(material_t), allocatable :: mats(:)
    real(wp) :: vgrad(9, 1), s(6, 1), v(1), st(9, 1), f(9, 1), g
    integer :: k
    call begin_test('umat_keeps_the_total_strain')
    call both(mats)
    ! L = [[a, b, 0], [b, c, d], [0, d, e]]: symmetric, no spin
    vgrad(:, 1) = [1.0_wp, 2.0_wp, 0.0_wp, 2.0_wp, -3.0_wp, 4.0_wp, 0.0_wp, 4.0_wp, 0.5_wp]
    s = 0.0_wp
    v = 1.0_wp
    st = 0.0_wp
    f = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [9, 1])
    do k = 1, 10
      call stress_update(mats(2), 2, 1.0e-5_wp, 1, [2], vgrad, s, v, [1.0_wp], f, st)
    end do
    ! xx yy zz, then yz = 2 d, xz = 0, xy = 2 b, each times 10 dt
    call check(maxval(abs(st(1:6, 1) - 1.0e-4_wp*[1.0_wp, -3.0_wp, 0.5_wp, 8.0_wp, 0.0_wp, &
                                                  4.0_wp])) <= 1.0e-18_wp, 'STRAN summed')
    g = young/(2.0_wp*(1.0_wp + nu))
    call check_close(s(6, 1), g*4.0e-4_wp, 1.0e-14_wp, 0.0_wp, 'sigma_xy = G gamma_xy')
    call check_close(s(4, 1), g*8.0e-4_wp, 1.0e-14_wp, 0.0_wp, 'sigma_yz = G gamma_yz')
    call check(s(5, 1) == 0.0_wp, 'sigma_xz = 0')
  end subroutine test_umat_keeps_the_total_strain

end program test_umat_elastic
