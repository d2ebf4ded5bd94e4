!> Cell smoothing (dpmpm_cell_smoothing, doc/theory.md 4.5): the volumetric strain rate of
!> the skeleton's points averaged over the points of one material in one cell, the
!> deviatoric part kept; the forces' mean stress averaged the same way, so that the power
!> of the forces, sum V sigma_bar : L, equals the power the stress update books,
!> sum V sigma : L_bar; the cell means of the pore pressure.
program test_cell_smoothing
  use dpmpm_kinds, only: wp
  use dpmpm_cell_smoothing, only: smooth_volumetric_rate, smoothed_mean_stress, cell_mean
  use dpmpm_assert, only: begin_test, check, check_close
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer, parameter :: n = 12, ncell = 3, nmat = 2
  ! cells and materials of the 12 points: cell 2 holds points of both materials, cell 3
  ! a single point
  integer, parameter :: cell(n) = [1, 1, 1, 2, 2, 2, 2, 2, 1, 3, 1, 2]
  integer, parameter :: mat(n) = [1, 1, 1, 1, 2, 2, 1, 2, 2, 1, 2, 1]
  ! the pair of cell and material of each point, as the step forms it
  integer, parameter :: key(n) = mat + nmat*(cell - 1), nkey = ncell*nmat
  real(wp) :: vol(n), lg(9, n), sig(6, n)
  call start_tests()
  call fill()
  call test_volumetric_rate_is_the_cell_mean_and_the_deviator_stays(2)
  call test_volumetric_rate_is_the_cell_mean_and_the_deviator_stays(3)
  call test_force_stress_keeps_the_deviator_and_takes_the_cell_mean(2)
  call test_force_stress_keeps_the_deviator_and_takes_the_cell_mean(3)
  call test_power_of_the_forces_is_the_booked_power(2)
  call test_power_of_the_forces_is_the_booked_power(3)
  call test_cell_mean_of_one_set()
  call end_tests()

contains

  !> Volumes, velocity gradients and stresses of the points, scattered by a fixed rule.
  subroutine fill()
    integer :: p, k
    do p = 1, n
      vol(p) = 0.5_wp + 0.1_wp*mod(7*p, 5)
      do k = 1, 9
        lg(k, p) = sin(1.3_wp*p + 0.7_wp*k)
      end do
      do k = 1, 6
        sig(k, p) = 1.0e3_wp*cos(0.9_wp*p + 1.1_wp*k) - 2.0e3_wp
      end do
    end do
  end subroutine fill

  !> The volume-weighted mean of a over the points of cell c and material m.
  real(wp) function mean_of(a, c, m)
    real(wp), intent(in) :: a(:)
    integer, intent(in) :: c, m
    mean_of = sum(vol*a, mask=cell == c .and. mat == m)/sum(vol, mask=cell == c .and. mat == m)
  end function mean_of

  real(wp) function trace(l, nd, p)
    real(wp), intent(in) :: l(:, :)
    integer, intent(in) :: nd, p
    integer :: d
    trace = 0.0_wp
    do d = 1, nd
      trace = trace + l(4*d - 3, p)
    end do
  end function trace

  !> Each point's trace over the nd axes becomes the mean of its cell and material (a
  !> single point keeps its own); the off-diagonal entries, the differences of the
  !> diagonal entries and, in 2D, the third row and column stay.
  subroutine test_volumetric_rate_is_the_cell_mean_and_the_deviator_stays(nd)
    integer, intent(in) :: nd
    real(wp) :: l(9, n), tr0(n)
    integer :: p, k
    call begin_test('volumetric_rate_is_the_cell_mean_and_the_deviator_stays_'//achar(48 + nd)//'d')
    l = lg
    do p = 1, n
      tr0(p) = trace(lg, nd, p)
    end do
    call smooth_volumetric_rate(nd, n, nkey, key, vol, l)
    do p = 1, n
      call check_close(trace(l, nd, p), mean_of(tr0, cell(p), mat(p)), 1.0e-13_wp, 1.0e-15_wp, 'trace')
      do k = 1, 9
        if (k == 1 .or. k == 5 .or. (k == 9 .and. nd == 3)) cycle
        call check(l(k, p) == lg(k, p), 'entry off the smoothed diagonal kept')
      end do
      call check_close(l(1, p) - l(5, p), lg(1, p) - lg(5, p), 1.0e-13_wp, 1.0e-15_wp, 'xx - yy')
      if (nd == 3) call check_close(l(5, p) - l(9, p), lg(5, p) - lg(9, p), 1.0e-13_wp, 1.0e-15_wp, 'yy - zz')
    end do
    call check_close(l(1, 10), lg(1, 10), 1.0e-14_wp, 0.0_wp, 'a point alone in its cell keeps its rate')
  end subroutine test_volumetric_rate_is_the_cell_mean_and_the_deviator_stays

  !> The stresses of the forces: the mean of the nd normal stresses is the cell's mean of
  !> it, the shear stresses, the differences of the normal ones and (2D) sigma_zz stay.
  subroutine test_force_stress_keeps_the_deviator_and_takes_the_cell_mean(nd)
    integer, intent(in) :: nd
    real(wp) :: sbar(6, n), m0(n)
    integer :: p
    call begin_test('force_stress_keeps_the_deviator_and_takes_the_cell_mean_'//achar(48 + nd)//'d')
    m0 = sum(sig(1:nd, :), dim=1)/nd
    call smoothed_mean_stress(nd, n, nkey, key, vol, sig, sbar)
    do p = 1, n
      call check_close(sum(sbar(1:nd, p))/nd, mean_of(m0, cell(p), mat(p)), 1.0e-13_wp, 0.0_wp, 'mean stress')
      call check(all(sbar(4:6, p) == sig(4:6, p)), 'shear stresses kept')
      call check_close(sbar(1, p) - sbar(2, p), sig(1, p) - sig(2, p), 1.0e-12_wp, 1.0e-12_wp, 'xx - yy')
      if (nd == 2) call check(sbar(3, p) == sig(3, p), 'sigma_zz of plane strain kept')
    end do
  end subroutine test_force_stress_keeps_the_deviator_and_takes_the_cell_mean

  !> sum_p V sigma_bar : L = sum_p V sigma : L_bar (Voigt shears counted twice): the
  !> internal force with the smoothed stresses does the work the update books with the
  !> smoothed rates. Without smoothing of one of the two the sums differ.
  subroutine test_power_of_the_forces_is_the_booked_power(nd)
    integer, intent(in) :: nd
    real(wp) :: sbar(6, n), lbar(9, n), forces, booked, plain
    call begin_test('power_of_the_forces_is_the_booked_power_'//achar(48 + nd)//'d')
    lbar = lg
    call smooth_volumetric_rate(nd, n, nkey, key, vol, lbar)
    call smoothed_mean_stress(nd, n, nkey, key, vol, sig, sbar)
    forces = power(sbar, lg, nd)
    booked = power(sig, lbar, nd)
    plain = power(sig, lg, nd)
    call check_close(forces, booked, 1.0e-12_wp, 0.0_wp, 'power of the forces against the booked power')
    call check(abs(forces - plain) > 1.0e-6_wp*abs(plain), 'the smoothing changes the power (the test can fail)')
  end subroutine test_power_of_the_forces_is_the_booked_power

  real(wp) function power(s, l, nd)
    real(wp), intent(in) :: s(:, :), l(:, :)
    integer, intent(in) :: nd
    integer :: p
    power = 0.0_wp
    do p = 1, n
      ! the symmetric part of L over the nd axes
      power = power + vol(p)*(s(1, p)*l(1, p) + s(2, p)*l(5, p) + s(6, p)*(l(2, p) + l(4, p)))
      if (nd == 3) power = power + vol(p)*(s(3, p)*l(9, p) + s(4, p)*(l(6, p) + l(8, p)) + &
                                           s(5, p)*(l(3, p) + l(7, p)))
    end do
  end function power

  !> cell_mean over one set (the pore pressure's smoothing): the mean of each cell.
  subroutine test_cell_mean_of_one_set()
    real(wp) :: val(n), mean(n)
    integer :: p
    call begin_test('cell_mean_of_one_set')
    val = sig(1, :)
    call cell_mean(n, ncell, cell, vol, val, mean)
    do p = 1, n
      call check_close(mean(p), sum(vol*val, mask=cell == cell(p))/sum(vol, mask=cell == cell(p)), 1.0e-13_wp, &
                       0.0_wp, 'cell mean')
    end do
  end subroutine test_cell_mean_of_one_set

end program test_cell_smoothing
