!> The UMAT wrapper (dpmpm_model_umat) with the Modified Cam-Clay example UMAT
!> (src/materials/umat/umat_cam_clay.f90, linked into this program): through stress_update it gives what
!> the built-in cam_clay gives, to round-off, on random strain paths that load the soil
!> past its yield surface and unload it, in 3D and in plane strain (stress, p_c, void ratio,
!> volume, dissipation, stored energy); and its first call sets p_c and e as the built-in
!> init_state does. Measured differences and bounds: doc/verification.md, "A user's UMAT".
program test_umat_cam_clay
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: material_cfg_t, max_props
  use dpmpm_materials, only: material_t, materials_from_config, stress_update, strain_energy, &
                             init_state
  use dpmpm_assert, only: begin_test, check, check_close
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer, parameter :: npt = 30, nsteps = 300
  real(wp), parameter :: lam = 0.2_wp, kap = 0.05_wp, mcs = 1.0_wp, e0 = 1.2_wp, nu = 0.3_wp
  real(wp), parameter :: pm = 1.0e3_wp, ocr = 1.3_wp
  !> Largest relative difference of each quantity: measured up to 1.3e-14 (the void ratio;
  !> debug build, doc/verification.md); bound 2e-13, 15x.
  real(wp), parameter :: tol = 2.0e-13_wp
  call start_tests()
  call test_cam_clay_umat_matches_cam_clay_in_3d()
  call test_cam_clay_umat_matches_cam_clay_in_plane_strain()
  call test_cam_clay_umat_starts_from_the_stress_and_ocr()
  call end_tests()

contains

  !> Material 1 the built-in cam_clay, material 2 the UMAT with its PROPS (two STATEV).
  subroutine both(mats)
    type(material_t), allocatable, intent(out) :: mats(:)
    real(wp) :: props(max_props)
    props = 0.0_wp
    props(1:9) = [lam, kap, mcs, nu, 0.0_wp, pm, e0, 0.0_wp, ocr]
    call materials_from_config([material_cfg_t(id=1, model='cam_clay', compression_index=lam, &
                                               swelling_index=kap, critical_state_ratio=mcs, &
                                               void_ratio=e0, ocr=ocr, poisson_ratio=nu, &
                                               min_pressure=pm), &
                                material_cfg_t(id=2, model='umat', umat_props=props, umat_nprops=9, &
                                               umat_nstatev=2)], mats)
  end subroutine both

  !> nsteps random steps of npt points of each material from an anisotropic compression of
  !> 50-150 kPa: a velocity gradient of random direction, compressing more than it dilates
  !> in the first half and the reverse in the second (loading past the surface, then
  !> unloading); the largest relative differences of stress, p_c, e, volume, dissipation
  !> and stored energy in d(1:6).
  subroutine random_paths(plane, d)
    logical, intent(in) :: plane
    real(wp), intent(out) :: d(6)
    type(material_t), allocatable :: mats(:)
    real(wp) :: vgrad(9, npt), s1(6, npt), s2(6, npt), v1(npt), v2(npt), v0(npt), st1(2, npt)
    real(wp) :: st2(11, npt), f(9, npt), f1(9, npt), w1, w2, e1, e2, r(6)
    integer :: p, k, pmat1(npt), pmat2(npt)
    integer, allocatable :: seed(:)
    call random_seed(size=k)
    allocate (seed(k))
    seed = 5081
    call random_seed(put=seed)
    call both(mats)
    pmat1 = 1
    pmat2 = 2
    do p = 1, npt
      call random_number(r)
      s1(:, p) = -[1.0e5_wp*(0.5_wp + r(1:3)), 1.0e4_wp*(r(4:6) - 0.5_wp)]
      if (plane) s1(4:5, p) = 0.0_wp
    end do
    s2 = s1
    st1 = 0.0_wp
    call init_state(mats(1), 1, npt, pmat1, s1, st1)
    st2 = 0.0_wp
    st2(10:11, :) = st1
    v0 = 1.0e-3_wp
    v1 = v0
    v2 = v0
    f = spread([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], 2, npt)
    f1 = f
    w1 = 0.0_wp
    w2 = 0.0_wp
    do k = 1, nsteps
      do p = 1, npt
        call random_number(vgrad(:, p))
        vgrad(:, p) = 2.0_wp*vgrad(:, p) - 1.0_wp
        vgrad([1, 5, 9], p) = vgrad([1, 5, 9], p) - merge(0.4_wp, -0.4_wp, 2*k <= nsteps)
        if (plane) vgrad([3, 6, 7, 8, 9], p) = 0.0_wp
      end do
      call stress_update(mats(1), 1, 1.0e-3_wp, npt, pmat1, vgrad, s1, v1, v0, f1, st1, w1, &
                         plane=plane)
      call stress_update(mats(2), 2, 1.0e-3_wp, npt, pmat2, vgrad, s2, v2, v0, f, st2, w2, &
                         plane=plane)
    end do
    d(1) = maxval(abs(s2 - s1))/maxval(abs(s1))
    d(2) = maxval(abs(st2(10, :) - st1(1, :))/st1(1, :))
    d(3) = maxval(abs(st2(11, :) - st1(2, :))/st1(2, :))
    d(4) = maxval(abs(v2 - v1)/v1)
    d(5) = abs(w2 - w1)/w1
    e1 = strain_energy(mats(1), 1, npt, pmat1, s1, v1, v0, f1, st1)
    e2 = strain_energy(mats(2), 2, npt, pmat2, s2, v2, v0, f, st2)
    d(6) = abs(e2 - e1)/e1
    print '(a,l2,a,6es10.2)', '  plane', plane, ': stress, p_c, e, volume, dissipation, energy', d
    print '(a,2es12.4,a,es12.4)', '  p_c from', minval(st1(1, :)), maxval(st1(1, :)), &
      '; dissipation', w1
    call check(maxval(st1(1, :)) > 2.0_wp*ocr*1.5e5_wp .and. w1 > 0.0_wp, &
               'the paths harden the soil')
  end subroutine random_paths

  !> The random paths (plane strain where plane) give both materials the same stress,
  !> p_c, e, volume, dissipation and stored energy to round-off.
  subroutine check_random_paths(plane)
    logical, intent(in) :: plane
    real(wp) :: d(6)
    call random_paths(plane, d)
    call check(all(d <= tol), 'stress, p_c, e, volume, dissipation, energy within round-off')
  end subroutine check_random_paths

  subroutine test_cam_clay_umat_matches_cam_clay_in_3d()
    call begin_test('cam_clay_umat_matches_cam_clay_in_3d')
    call check_random_paths(.false.)
  end subroutine test_cam_clay_umat_matches_cam_clay_in_3d

  subroutine test_cam_clay_umat_matches_cam_clay_in_plane_strain()
    call begin_test('cam_clay_umat_matches_cam_clay_in_plane_strain')
    call check_random_paths(.true.)
  end subroutine test_cam_clay_umat_matches_cam_clay_in_plane_strain

  !> STATEV zero: the UMAT's first call takes p_c = OCR (p + q^2/(M^2 p)) from the stress
  !> and e = e0, as init_state does (a step without spin, so that the stress it is given
  !> is the one init_state saw; the step is small and inside the surface).
  subroutine test_cam_clay_umat_starts_from_the_stress_and_ocr()
    type(material_t), allocatable :: mats(:)
    real(wp) :: s(6, 1), st1(2, 1), st2(11, 1), vgrad(9, 1), v(1), f(9, 1)
    call begin_test('cam_clay_umat_starts_from_the_stress_and_ocr')
    call both(mats)
    s(:, 1) = [-1.2e5_wp, -0.8e5_wp, -0.7e5_wp, 1.0e4_wp, -5.0e3_wp, 2.0e3_wp]
    st1 = 0.0_wp
    call init_state(mats(1), 1, 1, [1], s, st1)
    st2 = 0.0_wp
    vgrad = 0.0_wp
    vgrad(1, 1) = -1.0e-3_wp
    v = 1.0_wp
    f = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [9, 1])
    call stress_update(mats(2), 2, 1.0e-3_wp, 1, [2], vgrad, s, v, [1.0_wp], f, st2)
    call check_close(st2(10, 1), st1(1, 1), 1.0e-14_wp, 0.0_wp, 'p_c from the stress and OCR')
    call check_close(st2(11, 1), (1.0_wp + e0)*(1.0_wp - 1.0e-6_wp) - 1.0_wp, 1.0e-14_wp, 0.0_wp, &
                     'e from e0 and the volume')
  end subroutine test_cam_clay_umat_starts_from_the_stress_and_ocr

end program test_umat_cam_clay
