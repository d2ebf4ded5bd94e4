!> Rank layouts (dims) that the MPI tests run through: the layout MPI chooses,
!> every layout with all ranks along one axis, and on 4 ranks in 3D the 2x2
!> layouts of each pair of axes (so that edges and corners are crossed); and nested cuts
!> that differ from group to group, for the tests of &grid balance = 'nested'.
module dpmpm_test_layouts
  implicit none
  private
  public :: layouts_for, nested_test_cuts

contains

  !> layouts(:, l) is the dims_in of layout l for ndim axes and nranks ranks;
  !> the first layout is (0, 0, 0), chosen by MPI_Dims_create.
  subroutine layouts_for(ndim, nranks, layouts)
    integer, intent(in) :: ndim, nranks
    integer, allocatable, intent(out) :: layouts(:, :)
    integer :: tmp(3, 16), n, d
    n = 1
    tmp(:, 1) = 0
    if (nranks > 1 .and. ndim > 1) then
      do d = 1, ndim
        n = n + 1
        tmp(:, n) = 1
        tmp(d, n) = nranks
      end do
    end if
    if (nranks == 4 .and. ndim == 3) then
      tmp(:, n + 1) = [2, 2, 1]
      tmp(:, n + 2) = [1, 2, 2]
      tmp(:, n + 3) = [2, 1, 2]
      n = n + 3
    end if
    layouts = tmp(:, 1:n)
  end subroutine layouts_for

  !> Nested cuts for dec (gcuts as decomp_t%gcut) whose parts differ between groups: the
  !> cuts of balanced_cuts for weights that grow along the axis in groups of even index
  !> and fall along it in the others (the group of axis 2 is the slab p1, that of axis 3
  !> the column p1 + 2 p2), every part at least minw cells. Axis 1 has the rising weights.
  subroutine nested_test_cuts(dec, minw, gcuts)
    use dpmpm_kinds, only: wp
    use dpmpm_decomp, only: decomp_t, balanced_cuts
    type(decomp_t), intent(in) :: dec
    integer, intent(in) :: minw
    integer, allocatable, intent(out) :: gcuts(:, :, :, :)
    real(wp), allocatable :: w(:)
    integer :: d, n, p1, p2, k, group
    allocate (gcuts(0:maxval(dec%dims), 3, 0:dec%dims(1) - 1, 0:dec%dims(2) - 1))
    gcuts = 0
    do d = 1, 3
      gcuts(1, d, :, :) = 1
    end do
    do d = 1, dec%ndim
      n = dec%ncells(d)
      allocate (w(0:n - 1))
      do p2 = 0, dec%dims(2) - 1
        do p1 = 0, dec%dims(1) - 1
          group = 0
          if (d == 2) group = p1
          if (d == 3) group = p1 + 2*p2
          do k = 0, n - 1
            if (mod(group, 2) == 0) then
              w(k) = real((k + 1)**2, wp)
            else
              w(k) = real((n - k)**2, wp)
            end if
          end do
          gcuts(0:dec%dims(d), d, p1, p2) = balanced_cuts(n, dec%dims(d), w, minw)
        end do
      end do
      deallocate (w)
    end do
  end subroutine nested_test_cuts

end module dpmpm_test_layouts
