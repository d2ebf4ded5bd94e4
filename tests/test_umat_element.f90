!> A user's UMAT through the element-test driver (dpmpm_element_path): every laboratory
!> path of the driver run with an example UMAT linked into this program gives the path of
!> the built-in model it stands for, to round-off, in stress, strain and state. Built twice
!> (tests/CMakeLists.txt): with src/materials/umat/umat_linear_elastic.f against
!> linear_elastic, and with the argument cam_clay, with src/materials/umat/umat_cam_clay.f90
!> against cam_clay (normally consolidated and lightly overconsolidated). The driver's
!> Newton iterations on the stress conditions take their Jacobian from differences of the
!> model's own update, so the two paths may part by more than one update's round-off;
!> measured differences and bounds: doc/verification.md, "A user's UMAT".
program test_umat_element
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: material_cfg_t, max_props
  use dpmpm_element_config, only: element_cfg_t
  use dpmpm_element_path, only: element_history_t, run_element, element_ok
  use dpmpm_materials, only: material_t, materials_from_config
  use dpmpm_assert, only: begin_test, check, check_equal_int
  implicit none
  real(wp), parameter :: youngs = 1.0e7_wp, nu = 0.3_wp
  real(wp), parameter :: lam = 0.2_wp, kap = 0.05_wp, mcs = 1.0_wp, e0 = 1.2_wp, pm = 1.0e3_wp
  !> Largest difference of stress (over the largest stress of the path), strain (over the
  !> largest strain) and state (relative) between the two paths: measured up to 6.5e-14
  !> (the stress-controlled path, whose Newton iterations stop at 1e-12 of the stress;
  !> doc/verification.md, "A user's UMAT"); bound 5e-13 (7.7x).
  real(wp), parameter :: tol = 5.0e-13_wp
  character(len=16) :: arg
  call start_tests()
  call get_command_argument(1, arg)
  if (arg == 'cam_clay') then
    call test_cam_clay_umat_follows_cam_clay_on_every_path()
  else
    call test_elastic_umat_follows_linear_elastic_on_every_path()
  end if
  call end_tests()

contains

  !> The paths of the driver, each as a configuration of the element test with the
  !> material left to the caller: monotonic drained and undrained triaxial compression and
  !> extension, oedometer and isotropic compression under strain control, drained triaxial
  !> to a deviator under stress control, and undrained cyclic simple shear and cyclic
  !> triaxial under strain control.
  function paths(p0, strain) result(cfgs)
    real(wp), intent(in) :: p0, strain
    type(element_cfg_t) :: cfgs(8)
    integer :: k
    do k = 1, size(cfgs)
      cfgs(k)%p0 = p0
      cfgs(k)%steps = 120
      cfgs(k)%tolerance = 1.0e-12_wp
    end do
    cfgs(1)%path = 'triaxial_drained'
    cfgs(1)%axial_strain = strain
    cfgs(2)%path = 'triaxial_undrained'
    cfgs(2)%axial_strain = strain
    cfgs(3)%path = 'triaxial_undrained'
    cfgs(3)%sense = 'extension'
    cfgs(3)%axial_strain = strain
    cfgs(4)%path = 'oedometer'
    cfgs(4)%axial_strain = strain
    cfgs(5)%path = 'isotropic'
    cfgs(5)%volumetric_strain = strain
    cfgs(6)%path = 'triaxial_drained'
    cfgs(6)%control = 'stress'
    cfgs(6)%deviator = 0.6_wp*p0
    cfgs(7)%path = 'simple_shear_undrained'
    cfgs(7)%cycles = 2
    cfgs(7)%amplitude = strain
    cfgs(8)%path = 'triaxial_undrained'
    cfgs(8)%cycles = 2
    cfgs(8)%amplitude = strain
  end function paths

  !> Both paths of cfg, with material a (the built-in model) and b (the UMAT), whose state
  !> values are compared from slot sa and sb on (ns values); the largest differences of
  !> stress, strain and state in d(1:3).
  subroutine compare(cfg, a, b, sa, sb, ns, d)
    type(element_cfg_t), intent(in) :: cfg
    type(material_cfg_t), intent(in) :: a, b
    integer, intent(in) :: sa, sb, ns
    real(wp), intent(out) :: d(3)
    type(element_cfg_t) :: c
    type(material_t), allocatable :: mats(:)
    type(element_history_t) :: ha, hb
    integer :: n, i
    c = cfg
    call materials_from_config([a, b], mats)
    c%material = a
    call run_element(c, mats(1), ha)
    c%material = b
    call run_element(c, mats(2), hb)
    call check_equal_int(ha%status, element_ok, trim(cfg%path)//': the built-in path is complete')
    call check_equal_int(hb%status, element_ok, trim(cfg%path)//': the UMAT path is complete')
    call check_equal_int(hb%nrec, ha%nrec, trim(cfg%path)//': as many records')
    d = huge(1.0_wp)
    if (ha%nrec /= hb%nrec .or. ha%status /= element_ok .or. hb%status /= element_ok) return
    n = ha%nrec
    d(1) = maxval(abs(ha%stress(:, 1:n) - hb%stress(:, 1:n)))/maxval(abs(ha%stress(:, 1:n)))
    d(2) = maxval(abs(ha%strain(:, 1:n) - hb%strain(:, 1:n)))/maxval(abs(ha%strain(:, 1:n)))
    d(3) = 0.0_wp
    do i = 0, ns - 1
      d(3) = max(d(3), maxval(abs(ha%state(sa + i, 1:n) - hb%state(sb + i, 1:n)) &
                              /abs(ha%state(sa + i, 1:n))))
    end do
    print '(2x,a,1x,a,1x,a,3es10.2)', trim(cfg%path), trim(cfg%sense), trim(cfg%control), d
  end subroutine compare

  !> The linear-elastic UMAT (PROPS = E, nu) against linear_elastic on every path.
  subroutine test_elastic_umat_follows_linear_elastic_on_every_path()
    type(element_cfg_t) :: cfgs(8)
    type(material_cfg_t) :: a, b
    real(wp) :: d(3), props(max_props)
    integer :: k
    call begin_test('elastic_umat_follows_linear_elastic_on_every_path')
    a = material_cfg_t(id=1, model='linear_elastic', youngs_modulus=youngs, poisson_ratio=nu)
    props = 0.0_wp
    props(1:2) = [youngs, nu]
    b = material_cfg_t(id=2, model='umat', umat_props=props, umat_nprops=2, &
                       youngs_modulus=youngs, poisson_ratio=nu)
    cfgs = paths(1.0e5_wp, 0.01_wp)
    print '(2x,a)', 'path, then stress, strain, state differences'
    do k = 1, size(cfgs)
      call compare(cfgs(k), a, b, 1, 1, 0, d)
      call check(all(d <= tol), trim(cfgs(k)%path)//': the UMAT follows the built-in model')
    end do
  end subroutine test_elastic_umat_follows_linear_elastic_on_every_path

  !> The Modified Cam-Clay UMAT (PROPS lambda, kappa, M, nu, G, p_m, e0, p_c0, OCR; STATEV
  !> p_c and e after the wrapper's nine values) against cam_clay on every path, normally
  !> consolidated (ocr 1) and lightly overconsolidated (ocr 2: an elastic start).
  subroutine test_cam_clay_umat_follows_cam_clay_on_every_path()
    type(element_cfg_t) :: cfgs(8)
    type(material_cfg_t) :: a, b
    real(wp) :: d(3), props(max_props), ocr
    integer :: k, io
    call begin_test('cam_clay_umat_follows_cam_clay_on_every_path')
    do io = 1, 2
      ocr = real(io, wp)
      a = material_cfg_t(id=1, model='cam_clay', compression_index=lam, swelling_index=kap, &
                         critical_state_ratio=mcs, void_ratio=e0, ocr=ocr, poisson_ratio=nu, &
                         min_pressure=pm)
      props = 0.0_wp
      props(1:9) = [lam, kap, mcs, nu, 0.0_wp, pm, e0, 0.0_wp, ocr]
      b = material_cfg_t(id=2, model='umat', umat_props=props, umat_nprops=9, umat_nstatev=2)
      cfgs = paths(1.0e5_wp, 0.05_wp)
      print '(2x,a,f4.1,a)', 'ocr ', ocr, ': path, then stress, strain, state differences'
      do k = 1, size(cfgs)
        call compare(cfgs(k), a, b, 1, 10, 2, d)
        call check(all(d <= tol), trim(cfgs(k)%path)//': the UMAT follows the built-in model')
      end do
    end do
  end subroutine test_cam_clay_umat_follows_cam_clay_on_every_path

end program test_umat_element
