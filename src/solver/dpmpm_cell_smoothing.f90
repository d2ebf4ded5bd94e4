!> Cell smoothing of the volumetric response (doc/theory.md 4.5): a cell's points of one
!> set and material change their volume at one rate, and their forces come from the
!> cell's mean of the matching stress, so that the forces' power is the power the update
!> books. For the skeleton (`volumetric_smoothing`) the trace of each point's velocity
!> gradient is replaced by the volume-weighted mean trace of the points of its material in
!> its cell, the deviatoric part left as it is (the rate form of an F-bar step on the
!> cell), and in the internal force each point's mean stress by the cell's mean of it. A
!> grid of linear functions with several points per cell then no longer asks each point
!> to keep its own volume where the plastic flow is isochoric (volumetric locking). The
!> pore fluid's smoothing (`pressure_smoothing`) takes cell_mean from here but lives
!> elsewhere: the pressure change in smooth_pressure_change (dpmpm_pore_pressure), the
!> pressure of the forces in swap_force_fields (dpmpm_step).
module dpmpm_cell_smoothing
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: smooth_volumetric_rate, smoothed_mean_stress, cell_mean

contains

  !> vgrad(9, n) (3x3 column-major per point) of the n points; key the index of each
  !> point's pair of cell and material (1..nkey), vol their volume. The trace over the
  !> first nd axes of each point is set to the volume-weighted mean over the points of its
  !> key by adding the same amount to each of those diagonal entries.
  pure subroutine smooth_volumetric_rate(nd, n, nkey, key, vol, vgrad)
    integer, intent(in) :: nd, n, nkey
    integer, intent(in) :: key(:)
    real(wp), intent(in) :: vol(:)
    real(wp), intent(inout) :: vgrad(:, :)
    real(wp), allocatable :: tr(:), mean(:)
    integer :: p, d
    allocate (tr(n), mean(n))
    tr = 0.0_wp
    do d = 1, nd
      tr = tr + vgrad(4*d - 3, 1:n)
    end do
    call cell_mean(n, nkey, key, vol, tr, mean)
    do d = 1, nd
      do p = 1, n
        vgrad(4*d - 3, p) = vgrad(4*d - 3, p) + (mean(p) - tr(p))/real(nd, wp)
      end do
    end do
  end subroutine smooth_volumetric_rate

  !> The stresses (Voigt, 6 x n) for the internal force: each point's mean of the first
  !> nd normal stresses replaced by the volume-weighted mean over the points of its key
  !> (arguments as in smooth_volumetric_rate).
  pure subroutine smoothed_mean_stress(nd, n, nkey, key, vol, stress, sbar)
    integer, intent(in) :: nd, n, nkey
    integer, intent(in) :: key(:)
    real(wp), intent(in) :: vol(:), stress(:, :)
    real(wp), intent(out) :: sbar(:, :)
    real(wp), allocatable :: sm(:), mean(:)
    integer :: p, d
    allocate (sm(n), mean(n))
    sm = 0.0_wp
    do d = 1, nd
      sm = sm + stress(d, 1:n)/real(nd, wp)
    end do
    call cell_mean(n, nkey, key, vol, sm, mean)
    sbar(:, 1:n) = stress(:, 1:n)
    do p = 1, n
      do d = 1, nd
        sbar(d, p) = sbar(d, p) + (mean(p) - sm(p))
      end do
    end do
  end subroutine smoothed_mean_stress

  !> mean(p): the volume-weighted mean of val over the points with p's key (1..nkey).
  pure subroutine cell_mean(n, nkey, key, vol, val, mean)
    integer, intent(in) :: n, nkey
    integer, intent(in) :: key(:)
    real(wp), intent(in) :: vol(:), val(:)
    real(wp), intent(out) :: mean(:)
    real(wp), allocatable :: sv(:), sx(:)
    integer :: p
    allocate (sv(nkey), sx(nkey))
    sv = 0.0_wp
    sx = 0.0_wp
    do p = 1, n
      sv(key(p)) = sv(key(p)) + vol(p)
      sx(key(p)) = sx(key(p)) + vol(p)*val(p)
    end do
    do p = 1, n
      mean(p) = sx(key(p))/sv(key(p))
    end do
  end subroutine cell_mean

end module dpmpm_cell_smoothing
