!> Halo exchange tests for decomp_t on 1, 2 or 4 ranks: halo_sum and halo_copy
!> must be exact (integer-valued reals, compared with ==) in 1D, 2D and 3D, for
!> ghost widths 1 and 2, uneven splits, MPI-chosen and forced rank layouts, and
!> at edges and corners. The expected values are computed independently from
!> every rank's stored node range (gathered with MPI_Allgather). The same on nested cuts
!> (decomp_recut_nested, cuts of each axis that differ from part to part of the axes before
!> it), and nested cuts equal in every group against the tensor-product exchange.
program test_halo
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Comm_size, MPI_Allreduce, MPI_IN_PLACE, &
                     MPI_DOUBLE_PRECISION, MPI_MAX
  use dpmpm_kinds, only: wp
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer :: nranks, rank
  call start_tests(rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  call test_halo_sum_1d()
  call test_halo_sum_2d()
  call test_halo_sum_3d()
  call test_halo_copy_1d()
  call test_halo_copy_2d()
  call test_halo_copy_3d()
  call test_halo_sum_nested_2d()
  call test_halo_sum_nested_3d()
  call test_halo_copy_nested_2d()
  call test_halo_copy_nested_3d()
  call test_nested_with_equal_cuts_matches_tensor_product()
  call end_tests()

contains

  subroutine test_halo_sum_1d()
    call begin_test('halo_sum_1d')
    call run_all_layouts(1, .true.)
  end subroutine test_halo_sum_1d

  subroutine test_halo_sum_2d()
    call begin_test('halo_sum_2d')
    call run_all_layouts(2, .true.)
  end subroutine test_halo_sum_2d

  subroutine test_halo_sum_3d()
    call begin_test('halo_sum_3d')
    call run_all_layouts(3, .true.)
  end subroutine test_halo_sum_3d

  subroutine test_halo_copy_1d()
    call begin_test('halo_copy_1d')
    call run_all_layouts(1, .false.)
  end subroutine test_halo_copy_1d

  subroutine test_halo_copy_2d()
    call begin_test('halo_copy_2d')
    call run_all_layouts(2, .false.)
  end subroutine test_halo_copy_2d

  subroutine test_halo_copy_3d()
    call begin_test('halo_copy_3d')
    call run_all_layouts(3, .false.)
  end subroutine test_halo_copy_3d

  subroutine test_halo_sum_nested_2d()
    call begin_test('halo_sum_nested_2d')
    call run_all_layouts(2, .true., nested=.true.)
  end subroutine test_halo_sum_nested_2d

  subroutine test_halo_sum_nested_3d()
    call begin_test('halo_sum_nested_3d')
    call run_all_layouts(3, .true., nested=.true.)
  end subroutine test_halo_sum_nested_3d

  subroutine test_halo_copy_nested_2d()
    call begin_test('halo_copy_nested_2d')
    call run_all_layouts(2, .false., nested=.true.)
  end subroutine test_halo_copy_nested_2d

  subroutine test_halo_copy_nested_3d()
    call begin_test('halo_copy_nested_3d')
    call run_all_layouts(3, .false., nested=.true.)
  end subroutine test_halo_copy_nested_3d

  !> Every rank layout worth testing for ndim axes on this many ranks, for ghost
  !> widths 1 and 2. Cell counts are odd, so most splits are uneven, and large
  !> enough that every rank has at least gw cells per axis. nested: on the nested cuts
  !> of nested_test_cuts (more cells, so that the groups' cuts differ).
  subroutine run_all_layouts(ndim, sum_mode, nested)
    use dpmpm_test_layouts, only: layouts_for
    integer, intent(in) :: ndim
    logical, intent(in) :: sum_mode
    logical, intent(in), optional :: nested
    integer, allocatable :: layouts(:, :)
    integer :: gw, il, ncells(3)
    logical :: nest
    nest = .false.
    if (present(nested)) nest = nested
    call layouts_for(ndim, nranks, layouts)
    do gw = 1, 2
      if (gw == 1) then
        ncells = [7, 5, 9]
        if (nest) ncells = [11, 9, 13]
      else
        ncells = [9, 11, 13]
        if (nest) ncells = [13, 15, 17]
      end if
      do il = 1, size(layouts, 2)
        if (sum_mode) then
          call check_halo_sum(ndim, ncells, gw, layouts(:, il), nest)
        else
          call check_halo_copy(ndim, ncells, gw, layouts(:, il), nest)
        end if
      end do
    end do
  end subroutine run_all_layouts

  !> Nested cuts on dec (nested_test_cuts, at least gw cells a part), with a check that
  !> they are nested indeed where two axes are split (the second axis cut differently in
  !> the first two slabs).
  subroutine make_nested(dec, gw, label)
    use dpmpm_decomp, only: decomp_t
    use dpmpm_test_layouts, only: nested_test_cuts
    type(decomp_t), intent(inout) :: dec
    integer, intent(in) :: gw
    character(len=*), intent(in) :: label
    integer, allocatable :: gcuts(:, :, :, :)
    integer :: d, p1, p2, c
    logical :: wide
    call nested_test_cuts(dec, gw, gcuts)
    call dec%recut_nested(gcuts)
    wide = .true.
    do d = 1, dec%ndim
      do p2 = 0, dec%dims(2) - 1
        do p1 = 0, dec%dims(1) - 1
          do c = 0, dec%dims(d) - 1
            wide = wide .and. gcuts(c + 1, d, p1, p2) - gcuts(c, d, p1, p2) >= gw
          end do
        end do
      end do
    end do
    call check(wide, 'nested parts of at least gw cells: '//label)
    if (dec%ndim >= 2 .and. dec%dims(1) > 1 .and. dec%dims(2) > 1) &
      call check(any(gcuts(:, 2, 0, 0) /= gcuts(:, 2, 1, 0)), 'the slabs cut differently: '//label)
  end subroutine make_nested

  !> Nested cuts that are the same in every group (the even split) give the sums of the
  !> tensor-product exchange to round-off (a field of non-integer values, summed in
  !> another order) and the same copies to the bit, in 2D and 3D, gw 1 and 2.
  subroutine test_nested_with_equal_cuts_matches_tensor_product()
    use dpmpm_decomp, only: decomp_t
    type(decomp_t) :: a, b
    real(wp), allocatable :: fa(:, :, :, :), fb(:, :, :, :)
    integer, allocatable :: gcuts(:, :, :, :)
    integer :: nd, gw, i, j, k, c, p1, p2
    real(wp) :: err, scale
    character(len=80) :: label
    call begin_test('nested_with_equal_cuts_matches_tensor_product')
    do nd = 2, 3
      do gw = 1, 2
        call a%init(MPI_COMM_WORLD, nd, [9, 11, 13], gw, [0, 0, 0])
        call b%init(MPI_COMM_WORLD, nd, [9, 11, 13], gw, [0, 0, 0])
        allocate (gcuts(0:maxval(b%dims), 3, 0:b%dims(1) - 1, 0:b%dims(2) - 1))
        do p2 = 0, b%dims(2) - 1
          do p1 = 0, b%dims(1) - 1
            gcuts(:, :, p1, p2) = b%cut
          end do
        end do
        call b%recut_nested(gcuts)
        write (label, '(a,i0,a,i0,a,3(1x,i0))') 'ndim=', nd, ' gw=', gw, ' dims=', a%dims
        call check(all(a%alo == b%alo .and. a%ahi == b%ahi .and. a%olo == b%olo .and. a%ohi == b%ohi), &
                   'the same ranges: '//trim(label))
        allocate (fa(2, a%alo(1):a%ahi(1), a%alo(2):a%ahi(2), a%alo(3):a%ahi(3)))
        do k = a%alo(3), a%ahi(3)
          do j = a%alo(2), a%ahi(2)
            do i = a%alo(1), a%ahi(1)
              do c = 1, 2
                fa(c, i, j, k) = sin(0.37_wp*gfun(c, i, j, k) + 1.3_wp*a%rank)
              end do
            end do
          end do
        end do
        fb = fa
        call a%halo_sum(fa)
        call b%halo_sum(fb)
        err = maxval(abs(fa - fb))
        scale = maxval(abs(fa))
        call MPI_Allreduce(MPI_IN_PLACE, err, 1, MPI_DOUBLE_PRECISION, MPI_MAX, MPI_COMM_WORLD)
        call check(err <= 1.0e-14_wp*max(scale, 1.0_wp), 'the same sums to round-off: '//trim(label))
        ! (the same owned values on both, from the tensor-product sums)
        fb = fa
        call a%halo_copy(fa)
        call b%halo_copy(fb)
        call check(all(fa == fb), 'the same copies: '//trim(label))
        deallocate (fa, fb, gcuts)
        call a%free()
        call b%free()
      end do
    end do
  end subroutine test_nested_with_equal_cuts_matches_tensor_product

  !> Integer-valued test field, different per component, exact in double precision.
  pure real(wp) function gfun(c, i, j, k) result(g)
    integer, intent(in) :: c, i, j, k
    g = real(100000*c + (i + 5) + 37*(j + 5) + 37*37*(k + 5), wp)
  end function gfun

  !> Label naming one case, for failure messages.
  function case_label(ndim, ncells, gw, dims) result(s)
    integer, intent(in) :: ndim, ncells(3), gw, dims(3)
    character(len=:), allocatable :: s
    character(len=160) :: buf
    write (buf, '(a,i0,a,3(1x,i0),a,i0,a,3(1x,i0))') 'ndim=', ndim, ' ncells=', ncells, &
      ' gw=', gw, ' dims=', dims
    s = trim(buf)
  end function case_label

  !> Every rank sets all its stored nodes to (rank+1)*g; after halo_sum an owned
  !> node must hold g times the sum of (r+1) over the ranks r storing it, and a
  !> ghost node must hold 0.
  subroutine check_halo_sum(ndim, ncells, gw, dims_in, nested)
    use dpmpm_decomp, only: decomp_t
    integer, intent(in) :: ndim, ncells(3), gw, dims_in(3)
    logical, intent(in) :: nested
    type(decomp_t) :: dec
    real(wp), allocatable :: f(:, :, :, :)
    integer, allocatable :: lo(:, :), hi(:, :)
    integer :: i, j, k, c, r, nwrong, n(3)
    real(wp) :: w, expect
    logical :: owned
    call dec%init(MPI_COMM_WORLD, ndim, ncells, gw, dims_in)
    call check(layout_fits(dec, gw), 'layout fits: '//case_label(ndim, ncells, gw, dec%dims))
    if (nested) call make_nested(dec, gw, case_label(ndim, ncells, gw, dec%dims))
    call gather_ranges(dec, lo, hi)
    allocate (f(3, dec%alo(1):dec%ahi(1), dec%alo(2):dec%ahi(2), dec%alo(3):dec%ahi(3)))
    do k = dec%alo(3), dec%ahi(3)
      do j = dec%alo(2), dec%ahi(2)
        do i = dec%alo(1), dec%ahi(1)
          do c = 1, 3
            f(c, i, j, k) = real(dec%rank + 1, wp)*gfun(c, i, j, k)
          end do
        end do
      end do
    end do
    call dec%halo_sum(f)
    nwrong = 0
    do k = dec%alo(3), dec%ahi(3)
      do j = dec%alo(2), dec%ahi(2)
        do i = dec%alo(1), dec%ahi(1)
          n = [i, j, k]
          owned = all(n >= dec%olo .and. n <= dec%ohi)
          w = 0.0_wp
          do r = 0, dec%nranks - 1
            if (all(n >= lo(:, r) .and. n <= hi(:, r))) w = w + real(r + 1, wp)
          end do
          do c = 1, 3
            expect = 0.0_wp
            if (owned) expect = w*gfun(c, i, j, k)
            if (f(c, i, j, k) /= expect) then
              if (nwrong == 0) write (*, '(a,i0,a,4(i0,1x),a,2es14.6)') 'rank ', dec%rank, &
                ' first wrong node c,i,j,k=', c, i, j, k, ' got/expected ', f(c, i, j, k), expect
              nwrong = nwrong + 1
            end if
          end do
        end do
      end do
    end do
    call check(nwrong == 0, 'halo_sum exact: '//case_label(ndim, ncells, gw, dec%dims)// &
               trim(merge(' nested', '       ', nested)))
    call dec%free()
  end subroutine check_halo_sum

  !> Owned nodes hold g, ghosts -1e30; after halo_copy every stored node holds g.
  subroutine check_halo_copy(ndim, ncells, gw, dims_in, nested)
    use dpmpm_decomp, only: decomp_t
    integer, intent(in) :: ndim, ncells(3), gw, dims_in(3)
    logical, intent(in) :: nested
    type(decomp_t) :: dec
    real(wp), allocatable :: f(:, :, :, :)
    integer :: i, j, k, c, nwrong, n(3)
    call dec%init(MPI_COMM_WORLD, ndim, ncells, gw, dims_in)
    call check(layout_fits(dec, gw), 'layout fits: '//case_label(ndim, ncells, gw, dec%dims))
    if (nested) call make_nested(dec, gw, case_label(ndim, ncells, gw, dec%dims))
    allocate (f(3, dec%alo(1):dec%ahi(1), dec%alo(2):dec%ahi(2), dec%alo(3):dec%ahi(3)))
    do k = dec%alo(3), dec%ahi(3)
      do j = dec%alo(2), dec%ahi(2)
        do i = dec%alo(1), dec%ahi(1)
          n = [i, j, k]
          do c = 1, 3
            if (all(n >= dec%olo .and. n <= dec%ohi)) then
              f(c, i, j, k) = gfun(c, i, j, k)
            else
              f(c, i, j, k) = -1.0e30_wp
            end if
          end do
        end do
      end do
    end do
    call dec%halo_copy(f)
    nwrong = 0
    do k = dec%alo(3), dec%ahi(3)
      do j = dec%alo(2), dec%ahi(2)
        do i = dec%alo(1), dec%ahi(1)
          do c = 1, 3
            if (f(c, i, j, k) /= gfun(c, i, j, k)) then
              if (nwrong == 0) write (*, '(a,i0,a,4(i0,1x),a,2es14.6)') 'rank ', dec%rank, &
                ' first wrong node c,i,j,k=', c, i, j, k, ' got/expected ', f(c, i, j, k), &
                gfun(c, i, j, k)
              nwrong = nwrong + 1
            end if
          end do
        end do
      end do
    end do
    call check(nwrong == 0, 'halo_copy exact: '//case_label(ndim, ncells, gw, dec%dims)// &
               trim(merge(' nested', '       ', nested)))
    call dec%free()
  end subroutine check_halo_copy

  !> Every rank's stored node range, lo(:, r) and hi(:, r) for rank r of dec%comm.
  subroutine gather_ranges(dec, lo, hi)
    use mpi_f08, only: MPI_Allgather, MPI_INTEGER
    use dpmpm_decomp, only: decomp_t
    type(decomp_t), intent(in) :: dec
    integer, allocatable, intent(out) :: lo(:, :), hi(:, :)
    allocate (lo(3, 0:dec%nranks - 1), hi(3, 0:dec%nranks - 1))
    call MPI_Allgather(dec%alo, 3, MPI_INTEGER, lo, 3, MPI_INTEGER, dec%comm)
    call MPI_Allgather(dec%ahi, 3, MPI_INTEGER, hi, 3, MPI_INTEGER, dec%comm)
  end subroutine gather_ranges

  !> True when every rank has at least gw cells on every used axis (a precondition
  !> of the decomposition, checked here so that a bad test setup is visible).
  logical function layout_fits(dec, gw) result(ok)
    use dpmpm_decomp, only: decomp_t, split_extent
    type(decomp_t), intent(in) :: dec
    integer, intent(in) :: gw
    integer :: d, p
    ok = .true.
    do d = 1, dec%ndim
      do p = 0, dec%dims(d) - 1
        if (split_extent(dec%ncells(d), dec%dims(d), p + 1) - &
            split_extent(dec%ncells(d), dec%dims(d), p) < gw) ok = .false.
      end do
    end do
  end function layout_fits

end program test_halo
