!> Verification case P1 (doc/theory.md 9.5): MLS reconstruction of MATLAB's "peaks" function
!> from a jittered grid of data sites, measured on the 49 x 49 peaks grid.
!> Sites: the regular grid of spacing h on [-3, 3]^2, interior sites moved by up to
!> +-0.25 h per axis with hash_uniform (fixed seed), boundary sites left on the grid.
!> Error: e = |f_h - f|_2 / |f|_2 over the evaluation grid.
module dpmpm_peaks
  use dpmpm_kinds, only: wp, i8
  use dpmpm_kernels, only: kernel_weight, kernel_reach, kernel_wendland_c2, kernel_wendland_c4
  use dpmpm_mls, only: basis_constant, basis_linear, basis_size, packed_size, &
                       basis_eval, moment_add, mls_gamma, mls_stats_t, mls_max_basis, &
                       mls_max_packed
  use dpmpm_hash, only: hash_uniform
  implicit none
  private
  public :: peaks, peaks_seed, peaks_lo, peaks_hi, peaks_neval, peaks_jitter
  public :: peaks_nside, peaks_sites, peaks_eval_grid, peaks_case, peaks_reconstruct
  public :: relative_l2_error, peaks_error

  !> Seed of the jitter draw (any fixed value; a different draw changes the error digits).
  integer, parameter :: peaks_seed = 20250101
  !> The square [peaks_lo, peaks_hi]^2 and MATLAB's default 49 x 49 evaluation grid.
  real(wp), parameter :: peaks_lo = -3.0_wp, peaks_hi = 3.0_wp
  integer, parameter :: peaks_neval = 49
  !> Largest displacement of an interior site per axis, in units of h.
  real(wp), parameter :: peaks_jitter = 0.25_wp

contains

  !> MATLAB's peaks function (doc/theory.md 9.5).
  elemental real(wp) function peaks(x, y) result(f)
    real(wp), intent(in) :: x, y
    f = 3.0_wp*(1.0_wp - x)**2*exp(-x*x - (y + 1.0_wp)**2) &
        - 10.0_wp*(x/5.0_wp - x**3 - y**5)*exp(-x*x - y*y) &
        - exp(-(x + 1.0_wp)**2 - y*y)/3.0_wp
  end function peaks

  !> Sites per side of the jittered grid of spacing h (6/h must be an integer).
  pure integer function peaks_nside(h) result(ns)
    real(wp), intent(in) :: h
    ns = nint((peaks_hi - peaks_lo)/h) + 1
  end function peaks_nside

  !> The jittered site set: sites(2, ns*ns), site (i, j) (0-based grid indices) at column
  !> 1 + i + j*ns. Interior sites move by (2u - 1) peaks_jitter h per axis, u from
  !> hash_uniform(seed, cell = column - 1, slot 0, axis).
  pure subroutine peaks_sites(h, seed, sites)
    real(wp), intent(in) :: h
    integer, intent(in) :: seed
    real(wp), intent(out) :: sites(:, :)
    integer :: ns, i, j, a, c
    real(wp) :: u
    ns = peaks_nside(h)
    do j = 0, ns - 1
      do i = 0, ns - 1
        c = 1 + i + j*ns
        sites(:, c) = peaks_lo + h*real([i, j], wp)
        if (i == 0 .or. j == 0 .or. i == ns - 1 .or. j == ns - 1) cycle
        do a = 1, 2
          u = hash_uniform(seed, int(c - 1, i8), 0, a)
          sites(a, c) = sites(a, c) + (2.0_wp*u - 1.0_wp)*peaks_jitter*h
        end do
      end do
    end do
  end subroutine peaks_sites

  !> The 49 x 49 evaluation grid (x fastest): xe(2, 49*49).
  pure subroutine peaks_eval_grid(xe)
    real(wp), intent(out) :: xe(:, :)
    integer :: i, j
    real(wp) :: dx
    dx = (peaks_hi - peaks_lo)/real(peaks_neval - 1, wp)
    do j = 0, peaks_neval - 1
      do i = 0, peaks_neval - 1
        xe(:, 1 + i + j*peaks_neval) = peaks_lo + dx*real([i, j], wp)
      end do
    end do
  end subroutine peaks_eval_grid

  !> Kernel support of the P1 table for a basis: the constant basis uses the B-splines as
  !> tensor products of natural support and the Wendland kernels radially with R = 2h; the
  !> linear basis radial kernels with R = 2.5h, the quadratic basis with R = 3h.
  !> radius is in units of h.
  pure subroutine peaks_case(basis, kernel, radius, radial)
    integer, intent(in) :: basis, kernel
    real(wp), intent(out) :: radius
    logical, intent(out) :: radial
    select case (basis)
    case (basis_constant)
      radial = kernel == kernel_wendland_c2 .or. kernel == kernel_wendland_c4
      ! (radius 0: the B-splines' tensor products of natural support)
      radius = merge(2.0_wp, 0.0_wp, radial)
    case (basis_linear)
      radial = .true.
      radius = 2.5_wp
    case default
      radial = .true.
      radius = 3.0_wp
    end select
  end subroutine peaks_case

  !> MLS reconstruction fh(k) = dot(gamma, sum_p w_p pv_p f_p) at the points xe(2, :) from
  !> values f at the jittered sites of spacing h (peaks_sites layout, which bounds the
  !> search: site (i, j) lies within peaks_jitter h of its grid position).
  subroutine peaks_reconstruct(basis, kernel, radius, radial, h, sites, f, xe, fh, stats)
    integer, intent(in) :: basis, kernel
    real(wp), intent(in) :: radius, h, sites(:, :), f(:), xe(:, :)
    logical, intent(in) :: radial
    real(wp), intent(out) :: fh(:)
    type(mls_stats_t), intent(inout) :: stats
    real(wp) :: mom(mls_max_packed), rhs(mls_max_basis), gam(mls_max_basis), pv(mls_max_basis)
    real(wp) :: reach, w, dw(2), cnt
    integer :: ns, nb, k, i, j, c, lo(2), hi(2), level
    ns = peaks_nside(h)
    nb = basis_size(basis, 2)
    reach = kernel_reach(kernel, radius, radial) + peaks_jitter
    do k = 1, size(xe, 2)
      lo = max(0, ceiling((xe(:, k) - peaks_lo)/h - reach))
      hi = min(ns - 1, floor((xe(:, k) - peaks_lo)/h + reach))
      mom(1:packed_size(nb)) = 0.0_wp
      rhs(1:nb) = 0.0_wp
      cnt = 0.0_wp
      do j = lo(2), hi(2)
        do i = lo(1), hi(1)
          c = 1 + i + j*ns
          call kernel_weight(kernel, radius, radial, 2, (xe(:, k) - sites(:, c))/h, w, dw)
          if (.not. (w > 0.0_wp)) cycle
          cnt = cnt + 1.0_wp
          call basis_eval(basis, 2, (sites(:, c) - xe(:, k))/h, pv)
          call moment_add(nb, pv, w, mom)
          rhs(1:nb) = rhs(1:nb) + (w*f(c))*pv(1:nb)
        end do
      end do
      call mls_gamma(basis, 2, mom, cnt, gam, level, stats)
      fh(k) = dot_product(gam(1:nb), rhs(1:nb))
    end do
  end subroutine peaks_reconstruct

  !> Relative L2 error |fh - f|_2 / |f|_2.
  pure real(wp) function relative_l2_error(fh, f) result(e)
    real(wp), intent(in) :: fh(:), f(:)
    e = norm2(fh - f)/norm2(f)
  end function relative_l2_error

  !> P1 error for one kernel, basis and spacing h with the supports of peaks_case.
  !> Optionally returns the reconstruction on the evaluation grid (49*49 values); seed
  !> (default peaks_seed) selects another jitter draw, to see how much the draw matters.
  subroutine peaks_error(kernel, basis, h, err, stats, fh_out, seed)
    integer, intent(in) :: kernel, basis
    real(wp), intent(in) :: h
    real(wp), intent(out) :: err
    type(mls_stats_t), intent(inout) :: stats
    real(wp), intent(out), optional :: fh_out(:)
    integer, intent(in), optional :: seed
    real(wp), allocatable :: sites(:, :), f(:), xe(:, :), fe(:), fh(:)
    real(wp) :: radius
    logical :: radial
    integer :: ns
    ns = peaks_nside(h)
    allocate (sites(2, ns*ns), f(ns*ns), xe(2, peaks_neval**2), fe(peaks_neval**2), &
              fh(peaks_neval**2))
    if (present(seed)) then
      call peaks_sites(h, seed, sites)
    else
      call peaks_sites(h, peaks_seed, sites)
    end if
    f = peaks(sites(1, :), sites(2, :))
    call peaks_eval_grid(xe)
    fe = peaks(xe(1, :), xe(2, :))
    call peaks_case(basis, kernel, radius, radial)
    call peaks_reconstruct(basis, kernel, radius, radial, h, sites, f, xe, fh, stats)
    err = relative_l2_error(fh, fe)
    if (present(fh_out)) fh_out = fh
  end subroutine peaks_error

end module dpmpm_peaks
