!> Order statistics of the benches' rounds (dpmpm_stats): sorted values and the median of
!> odd and even counts, against values worked out by hand.
program test_stats
  use dpmpm_kinds, only: wp
  use dpmpm_stats, only: sorted, median
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  call start_tests()
  call test_sorted_orders_values()
  call test_median_of_odd_and_even_counts()
  call end_tests()

contains

  !> Repeated, negative and already ordered values; one value; none.
  subroutine test_sorted_orders_values()
    real(wp) :: none(0)
    call begin_test('sorted_orders_values')
    call check(all(sorted([3.0_wp, -1.0_wp, 2.0_wp, -1.0_wp, 7.5_wp]) == [-1.0_wp, -1.0_wp, 2.0_wp, 3.0_wp, 7.5_wp]), &
               'five values with a repeat')
    call check(all(sorted([1.0_wp, 2.0_wp, 3.0_wp]) == [1.0_wp, 2.0_wp, 3.0_wp]), 'already in order')
    call check(all(sorted([4.0_wp, 3.0_wp, 2.0_wp, 1.0_wp]) == [1.0_wp, 2.0_wp, 3.0_wp, 4.0_wp]), 'reversed')
    call check(all(sorted([5.0_wp]) == [5.0_wp]), 'one value')
    call check(size(sorted(none)) == 0, 'no value')
  end subroutine test_sorted_orders_values

  !> The middle value of an odd count, the mean of the two middle values of an even one.
  subroutine test_median_of_odd_and_even_counts()
    call begin_test('median_of_odd_and_even_counts')
    call check(median([9.0_wp, 1.0_wp, 5.0_wp]) == 5.0_wp, 'three values')
    call check(median([9.0_wp, 1.0_wp, 5.0_wp, 2.0_wp]) == 3.5_wp, 'four values')
    call check(median([2.5_wp]) == 2.5_wp, 'one value')
  end subroutine test_median_of_odd_and_even_counts

end program test_stats
