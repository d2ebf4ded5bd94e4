!> PNEWDT in the UMAT wrapper (dpmpm_model_umat), with the test UMAT tests/umat_pnewdt.f90
!> linked into this program: a UMAT that asks for PNEWDT = 0.5 gets the step in 2 substeps,
!> one that asks for less in ceiling(1/PNEWDT) as many, each from the restored stress and
!> state (the refused calls leave no trace), and the result is the elastic update taken in
!> as many steps. With the argument 'refuse' the UMAT refuses every increment, and the run
!> stops naming the point (the ctest test_umat_pnewdt_refused checks the message).
program test_umat_pnewdt
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: material_cfg_t, max_props
  use dpmpm_materials, only: material_t, materials_from_config, stress_update
  use dpmpm_assert, only: begin_test, check, check_close
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  real(wp), parameter :: young = 1.0e7_wp, nu = 0.25_wp, limit = 1.0e-3_wp, dt = 1.0e-3_wp
  character(len=16) :: arg
  call start_tests()
  call get_command_argument(1, arg)
  if (arg == 'refuse') then
    call refused_everywhere()
  else
    call test_pnewdt_half_takes_two_substeps()
    call test_small_pnewdt_takes_ceiling_of_its_inverse()
  end if
  call end_tests()

contains

  !> Material 1 the built-in linear_elastic, material 2 the test UMAT with strain limit lim.
  subroutine both(lim, mats)
    real(wp), intent(in) :: lim
    type(material_t), allocatable, intent(out) :: mats(:)
    real(wp) :: props(max_props)
    props = 0.0_wp
    props(1:3) = [young, nu, lim]
    call materials_from_config([material_cfg_t(id=1, model='linear_elastic', youngs_modulus=young, &
                                               poisson_ratio=nu), &
                                material_cfg_t(id=2, model='umat', youngs_modulus=young, &
                                               poisson_ratio=nu, umat_props=props, umat_nprops=3, &
                                               umat_nstatev=3)], mats)
  end subroutine both

  !> One step of the UMAT with a velocity gradient whose largest strain increment is
  !> ratio times the limit (with spin); against the built-in model in nsub steps of dt/nsub:
  !> the calls kept, DTIME and DSTRAN(1) summed, and the relative difference of the stress.
  subroutine one_step(ratio, nsub, calls, tsum, esum, ds)
    real(wp), intent(in) :: ratio
    integer, intent(in) :: nsub
    real(wp), intent(out) :: calls, tsum, esum, ds
    type(material_t), allocatable :: mats(:)
    real(wp) :: vgrad(9, 1), s1(6, 1), s2(6, 1), v1(1), v2(1), st(12, 1), f(9, 1)
    integer :: k
    call both(limit, mats)
    ! L11 = -1, L22 = 0.4, L12 = 0.6, L21 = -0.2, L33 = 0.3 (times a scale): the largest
    ! increment is dt |L11|
    vgrad(:, 1) = ratio*limit/dt*[-1.0_wp, -0.2_wp, 0.0_wp, 0.6_wp, 0.4_wp, 0.0_wp, 0.0_wp, &
                                  0.0_wp, 0.3_wp]
    s1(:, 1) = [-2.0e4_wp, -1.0e4_wp, -1.5e4_wp, 0.0_wp, 0.0_wp, 4.0e3_wp]
    s2 = s1
    v1 = 1.0_wp
    v2 = 1.0_wp
    st = 0.0_wp
    f = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [9, 1])
    call stress_update(mats(2), 2, dt, 1, [2], vgrad, s2, v2, [1.0_wp], f, st, &
                       time=0.0_wp, step=0_i8, ids=[7_i8])
    do k = 1, nsub
      call stress_update(mats(1), 1, dt/nsub, 1, [1], vgrad, s1, v1, [1.0_wp])
    end do
    calls = st(10, 1)
    tsum = st(11, 1)
    esum = st(12, 1)
    ds = maxval(abs(s2 - s1))/maxval(abs(s1))
    print '(a,f5.2,a,f4.0,a,es10.2)', '  increment', ratio, ' x the limit: calls kept', calls, &
      ', stress against the built-in model in substeps', ds
  end subroutine one_step

  subroutine test_pnewdt_half_takes_two_substeps()
    real(wp) :: calls, tsum, esum, ds
    call begin_test('pnewdt_half_takes_two_substeps')
    call one_step(1.5_wp, 2, calls, tsum, esum, ds)
    call check(calls == 2.0_wp, 'two calls kept (the refused one restored)')
    call check_close(tsum, dt, 1.0e-15_wp, 0.0_wp, 'the substeps cover dt')
    call check_close(esum, -1.5_wp*limit, 1.0e-14_wp, 0.0_wp, 'and the strain of the step')
    ! measured 5.4e-17 (2 substeps) and 3.5e-17 (4); bound 1e-14, round-off
    call check(ds <= 1.0e-14_wp, 'the elastic update in two steps')
  end subroutine test_pnewdt_half_takes_two_substeps

  subroutine test_small_pnewdt_takes_ceiling_of_its_inverse()
    real(wp) :: calls, tsum, esum, ds
    call begin_test('small_pnewdt_takes_ceiling_of_its_inverse')
    ! PNEWDT = 0.9/3.5 = 0.257: ceiling(1/PNEWDT) = 4 substeps of 0.875 times the limit
    call one_step(3.5_wp, 4, calls, tsum, esum, ds)
    call check(calls == 4.0_wp, 'four calls kept')
    call check_close(tsum, dt, 1.0e-15_wp, 0.0_wp, 'the substeps cover dt')
    call check_close(esum, -3.5_wp*limit, 1.0e-14_wp, 0.0_wp, 'and the strain of the step')
    call check(ds <= 1.0e-14_wp, 'the elastic update in four steps')
  end subroutine test_small_pnewdt_takes_ceiling_of_its_inverse

  !> A UMAT that refuses every increment: the wrapper stops the run (MPI_Abort) with the
  !> point's id after max_substeps substeps; this returns only if it did not.
  subroutine refused_everywhere()
    type(material_t), allocatable :: mats(:)
    real(wp) :: vgrad(9, 1), s(6, 1), v(1), st(12, 1), f(9, 1)
    call begin_test('refused_increment_stops_the_run')
    call both(0.0_wp, mats)
    vgrad = 0.0_wp
    vgrad(1, 1) = -1.0_wp
    s = 0.0_wp
    v = 1.0_wp
    st = 0.0_wp
    f = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [9, 1])
    call stress_update(mats(2), 2, dt, 1, [2], vgrad, s, v, [1.0_wp], f, st, ids=[42_i8])
    call check(.false., 'the run went on after a refused increment')
  end subroutine refused_everywhere

end program test_umat_pnewdt
