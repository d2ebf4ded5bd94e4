!> Rank layouts (dims) that the MPI tests run through: the layout MPI chooses,
!> every layout with all ranks along one axis, and on 4 ranks in 3D the 2x2
!> layouts of each pair of axes (so that edges and corners are crossed).
module dpmpm_test_layouts
  implicit none
  private
  public :: layouts_for

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

end module dpmpm_test_layouts
