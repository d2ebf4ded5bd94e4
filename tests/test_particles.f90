!> Tests of the point set (src/particles/dpmpm_particles.f90): particle_set_t%remove
!> leaves exactly the points not flagged, each with every field it had, whatever points
!> are flagged (none, all, the first, the last, points spread over the set), and moves
!> only as many points as left: an unflagged point below the new count keeps its place.
!> Every field of a point is a value of its id and of the field's component, so that a
!> point is checked after the set has been reordered.
program test_particles
  use dpmpm_kinds, only: wp, i8
  use dpmpm_particles, only: particle_set_t
  use dpmpm_assert, only: begin_test, check, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  call start_tests()
  call test_remove_none_flagged()
  call test_remove_all_flagged()
  call test_remove_first_flagged()
  call test_remove_last_flagged()
  call test_remove_spread_keeps_every_field()
  call test_remove_moves_only_as_many_as_left()
  call test_remove_without_optional_fields()
  call end_tests()

contains

  !> The value of component c of field f at the point of the given id.
  pure real(wp) function val(id, f, c)
    integer(i8), intent(in) :: id
    integer, intent(in) :: f, c
    val = real(1000*f + 100*c, wp) + real(id, wp) + 0.25_wp
  end function val

  !> A set of n points, ids 1..n, every field (defgrad, porosity, pressure and kinv, 2
  !> state values when full) set to val of the point's id; without full only the fields
  !> every set stores.
  subroutine make_set(ps, n, full)
    type(particle_set_t), intent(out) :: ps
    integer, intent(in) :: n
    logical, intent(in) :: full
    integer :: k
    integer(i8) :: id
    if (full) then
      call ps%init('solid', 3, .true., capacity=4, has_porosity=.true., has_pressure=.true., &
                   nstate=2)
    else
      call ps%init('solid', 2, .false., capacity=4)
    end if
    do k = 1, n
      id = int(k, i8)
      call ps%append(id, k, [0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp, 1.0_wp, &
                     [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp])
      ps%x(:, k) = field(id, 1, ps%ndim)
      ps%x0(:, k) = field(id, 2, ps%ndim)
      ps%v(:, k) = field(id, 3, ps%ndim)
      ps%mass(k) = val(id, 4, 1)
      ps%vol(k) = val(id, 5, 1)
      ps%vol0(k) = val(id, 6, 1)
      ps%stress(:, k) = field(id, 7, 6)
      if (full) then
        ps%defgrad(:, k) = field(id, 8, 9)
        ps%porosity(k) = val(id, 9, 1)
        ps%pressure(k) = val(id, 10, 1)
        ps%kinv(k) = val(id, 11, 1)
        ps%state(:, k) = field(id, 12, 2)
      end if
    end do
  end subroutine make_set

  !> The m components of field f at the point of the given id.
  pure function field(id, f, m) result(a)
    integer(i8), intent(in) :: id
    integer, intent(in) :: f, m
    real(wp) :: a(m)
    integer :: c
    do c = 1, m
      a(c) = val(id, f, c)
    end do
  end function field

  !> True when point k carries every field of its id (and its material, the id as made).
  logical function intact(ps, k) result(ok)
    type(particle_set_t), intent(in) :: ps
    integer, intent(in) :: k
    integer(i8) :: id
    id = ps%id(k)
    ok = ps%mat(k) == int(id) .and. all(ps%x(:, k) == field(id, 1, ps%ndim)) .and. &
         all(ps%x0(:, k) == field(id, 2, ps%ndim)) .and. all(ps%v(:, k) == field(id, 3, ps%ndim)) .and. &
         ps%mass(k) == val(id, 4, 1) .and. ps%vol(k) == val(id, 5, 1) .and. &
         ps%vol0(k) == val(id, 6, 1) .and. all(ps%stress(:, k) == field(id, 7, 6))
    if (ps%has_defgrad) ok = ok .and. all(ps%defgrad(:, k) == field(id, 8, 9))
    if (ps%has_porosity) ok = ok .and. ps%porosity(k) == val(id, 9, 1)
    if (ps%has_pressure) ok = ok .and. ps%pressure(k) == val(id, 10, 1) .and. &
                              ps%kinv(k) == val(id, 11, 1)
    if (ps%nstate > 0) ok = ok .and. all(ps%state(:, k) == field(id, 12, ps%nstate))
  end function intact

  !> Remove the points of ps (ids 1..n) flagged in gone and check that the set holds the
  !> others, each once and intact, and no more.
  subroutine remove_and_check(ps, gone, what)
    type(particle_set_t), intent(inout) :: ps
    logical, intent(in) :: gone(:)
    character(len=*), intent(in) :: what
    integer :: k, n0
    integer, allocatable :: seen(:)
    logical :: ok
    n0 = ps%n
    call ps%remove(gone)
    call check_equal_int(ps%n, count(.not. gone(1:n0)), what//': the count of the survivors')
    allocate (seen(n0))
    seen = 0
    ok = .true.
    do k = 1, ps%n
      if (ps%id(k) < 1 .or. ps%id(k) > n0) then
        ok = .false.
        cycle
      end if
      seen(ps%id(k)) = seen(ps%id(k)) + 1
      ok = ok .and. intact(ps, k)
    end do
    call check(ok, what//': every point kept carries every field of its id')
    call check(all(merge(0, 1, gone(1:n0)) == seen), what//': each survivor once, no departed point')
  end subroutine remove_and_check

  subroutine test_remove_none_flagged()
    type(particle_set_t) :: ps
    logical :: gone(7)
    integer :: k
    call begin_test('remove_none_flagged')
    call make_set(ps, 7, .true.)
    gone = .false.
    call remove_and_check(ps, gone, 'none flagged')
    call check(all(ps%id(1:7) == [(int(k, i8), k=1, 7)]), 'none flagged: the order is kept')
  end subroutine test_remove_none_flagged

  subroutine test_remove_all_flagged()
    type(particle_set_t) :: ps
    logical :: gone(7)
    call begin_test('remove_all_flagged')
    call make_set(ps, 7, .true.)
    gone = .true.
    call remove_and_check(ps, gone, 'all flagged')
    call check_equal_int(ps%n, 0, 'all flagged: the set is empty')
  end subroutine test_remove_all_flagged

  !> The first point leaves: the last one takes its place, the others stay.
  subroutine test_remove_first_flagged()
    type(particle_set_t) :: ps
    logical :: gone(7)
    call begin_test('remove_first_flagged')
    call make_set(ps, 7, .true.)
    gone = .false.
    gone(1) = .true.
    call remove_and_check(ps, gone, 'first flagged')
    call check(all(ps%id(1:ps%n) == [7_i8, 2_i8, 3_i8, 4_i8, 5_i8, 6_i8]), &
               'first flagged: the last point fills the hole')
  end subroutine test_remove_first_flagged

  !> The last point leaves: nothing moves.
  subroutine test_remove_last_flagged()
    type(particle_set_t) :: ps
    logical :: gone(7)
    integer :: k
    call begin_test('remove_last_flagged')
    call make_set(ps, 7, .true.)
    gone = .false.
    gone(7) = .true.
    call remove_and_check(ps, gone, 'last flagged')
    call check(all(ps%id(1:ps%n) == [(int(k, i8), k=1, 6)]), 'last flagged: the others in place')
  end subroutine test_remove_last_flagged

  !> Points flagged over the whole set, runs of them at both ends and in the middle.
  subroutine test_remove_spread_keeps_every_field()
    type(particle_set_t) :: ps
    logical :: gone(40)
    integer :: k
    call begin_test('remove_spread_keeps_every_field')
    call make_set(ps, 40, .true.)
    gone = [(mod(k*7, 5) == 0 .or. k <= 3 .or. k >= 37 .or. (k >= 18 .and. k <= 22), k=1, 40)]
    call remove_and_check(ps, gone, 'spread')
    ! Removing again from the reordered set.
    gone(1:ps%n) = [(mod(k, 3) == 1, k=1, ps%n)]
    call remove_and_check_ids(ps, gone(1:ps%n))
  end subroutine test_remove_spread_keeps_every_field

  !> A second removal, from a set whose ids are no longer 1..n in order: the ids left
  !> are those not flagged, and each point is intact.
  subroutine remove_and_check_ids(ps, gone)
    type(particle_set_t), intent(inout) :: ps
    logical, intent(in) :: gone(:)
    integer(i8), allocatable :: before(:), want(:)
    logical, allocatable :: stays(:)
    integer :: k
    logical :: ok
    before = ps%id(1:ps%n)
    stays = .not. gone
    want = pack(before, stays)
    call ps%remove(gone)
    call check_equal_int(ps%n, size(want), 'again: the count of the survivors')
    ok = .true.
    do k = 1, ps%n
      ok = ok .and. count(want == ps%id(k)) == 1 .and. intact(ps, k)
    end do
    do k = 1, size(want)
      ok = ok .and. count(ps%id(1:ps%n) == want(k)) == 1
    end do
    call check(ok, 'again: exactly the survivors, each intact')
  end subroutine remove_and_check_ids

  !> Only the holes below the new count are filled: a point below it that was not
  !> flagged keeps its index, and the points that move are the last survivors of the set.
  subroutine test_remove_moves_only_as_many_as_left()
    type(particle_set_t) :: ps
    logical :: gone(20)
    integer :: k, m
    logical :: stays
    call begin_test('remove_moves_only_as_many_as_left')
    call make_set(ps, 20, .true.)
    gone = .false.
    gone([2, 5, 11, 19]) = .true.
    call remove_and_check(ps, gone, 'four flagged')
    m = 16
    stays = .true.
    do k = 1, m
      if (.not. gone(k)) stays = stays .and. ps%id(k) == int(k, i8)
    end do
    call check(stays, 'unflagged points below the new count keep their places')
    call check(all(ps%id([2, 5, 11]) == [20_i8, 18_i8, 17_i8]), &
               'the holes take the last survivors, the last first')
  end subroutine test_remove_moves_only_as_many_as_left

  !> A set without deformation gradient, porosity, pressure or state values.
  subroutine test_remove_without_optional_fields()
    type(particle_set_t) :: ps
    logical :: gone(9)
    call begin_test('remove_without_optional_fields')
    call make_set(ps, 9, .false.)
    gone = [.true., .false., .true., .false., .false., .false., .true., .false., .true.]
    call remove_and_check(ps, gone, 'plain set')
    call check(.not. (allocated(ps%defgrad) .or. allocated(ps%porosity) .or. allocated(ps%pressure) &
                      .or. allocated(ps%state)), 'plain set: no optional field allocated')
  end subroutine test_remove_without_optional_fields

end program test_particles
