!> Moving Least Squares (MLS) reconstruction (doc/theory.md 3.3 and 3.4).
!>
!> The basis is shifted to the evaluation point x and scaled by the cell size h:
!> a site at s contributes pv = p(y), y = (s - x)/h, so p(x) becomes e_1 and the moment
!> matrix Mhat = sum_p w_p pv_p pv_p^T stays well scaled whatever the position of x.
!> With gamma = Mhat^{-1} e_1 the shape functions are Phi_p = w_p gamma . pv_p.
!>
!> Bases are nested: pv = [1, y_1..y_nd, y_1 y_1, y_1 y_2, .., y_1 y_nd, y_2 y_2, .., y_nd y_nd]
!> (constant, linear, quadratic), so a lower level is the leading block of a higher one and
!> the moments of a lower level are the first packed_size(m) entries of the packed moments.
!>
!> Fallback policy (doc/theory.md 3.4), applied per evaluation point in mls_gamma:
!> 1. mom(1) <= 0 (no site in range): gamma = 0, level -1 (counted nempty).
!> 2. The requested level is accepted when count >= basis size, the Cholesky factor of Mhat
!>    exists (pivots of the diagonally equilibrated matrix above nb*epsilon) and a 1-norm
!>    reciprocal condition estimate of Mhat (cell units) is >= mls_rcond_min
!>    (counted nfull; the constant basis taken directly counts as nfull).
!> 3. Otherwise quadratic falls to linear and the same test is made (counted nreduced).
!> 4. If the linear level fails too but count >= 2: linear with Tikhonov regularisation
!>    Mhat + eps I, eps = 1e-6 trace(Mhat)/nb (counted nregularised).
!> 5. If that is not positive definite either, or count < 2: the constant basis (Shepard),
!>    gamma(1) = 1/mom(1) (counted nconstant).
!> Exactly one counter is incremented per evaluation point, so their sum is the number of
!> evaluation points.
module dpmpm_mls
  use dpmpm_kinds, only: wp, i8
  use dpmpm_kernels, only: kernel_weight
  implicit none
  private
  public :: basis_constant, basis_linear, basis_quadratic, basis_names
  public :: mls_max_basis, mls_max_packed, mls_rcond_min, mls_tikhonov
  public :: basis_from_name, basis_size, packed_size, basis_eval, moment_add
  public :: mls_stats_t, mls_stats_add, mls_stats_total
  public :: mls_gamma, mls_shape_functions

  integer, parameter :: basis_constant = 0, basis_linear = 1, basis_quadratic = 2
  character(len=9), parameter :: basis_names(0:2) = ['constant ', 'linear   ', 'quadratic']
  !> Largest basis (quadratic in 3D) and its packed moment size: fixed-size work arrays.
  integer, parameter :: mls_max_basis = 10, mls_max_packed = 55
  !> Smallest accepted reciprocal condition estimate of the equilibrated moment matrix.
  real(wp), parameter :: mls_rcond_min = 1.0e-8_wp
  !> Tikhonov factor: eps = mls_tikhonov * trace(Mhat)/nb (doc/theory.md 3.4).
  real(wp), parameter :: mls_tikhonov = 1.0e-6_wp

  !> How often each fallback path was taken (one counter per evaluation point), and
  !> how many Gauss points widened their reach to find points (dpmpm_quadrature; their
  !> solves are counted by path as well).
  type :: mls_stats_t
    integer(i8) :: nfull = 0, nreduced = 0, nregularised = 0, nconstant = 0, nempty = 0
    integer(i8) :: nwidened = 0
  end type mls_stats_t

  integer, parameter :: path_full = 1, path_reduced = 2, path_regularised = 3, &
                        path_constant = 4, path_empty = 5

contains

  !> Basis id from its name ('constant', 'linear', 'quadratic'), -1 if unknown.
  pure integer function basis_from_name(name) result(b)
    character(len=*), intent(in) :: name
    integer :: j
    b = -1
    do j = 0, 2
      if (trim(adjustl(name)) == trim(basis_names(j))) b = j
    end do
  end function basis_from_name

  !> Number of basis functions: 1, 1 + nd, 1 + nd + nd(nd+1)/2.
  pure integer function basis_size(basis, nd) result(nb)
    integer, intent(in) :: basis, nd
    select case (basis)
    case (basis_constant)
      nb = 1
    case (basis_linear)
      nb = 1 + nd
    case default
      nb = 1 + nd + nd*(nd + 1)/2
    end select
  end function basis_size

  !> Entries of a packed upper triangle of an nb x nb symmetric matrix.
  pure integer function packed_size(nb)
    integer, intent(in) :: nb
    packed_size = nb*(nb + 1)/2
  end function packed_size

  !> Basis values pv(1:basis_size) at shifted, scaled coordinates y = (x_site - x_eval)/h,
  !> in nested order [1, y, quadratic terms y_i y_j (i <= j, i outer)].
  pure subroutine basis_eval(basis, nd, y, pv)
    integer, intent(in) :: basis, nd
    real(wp), intent(in) :: y(nd)
    real(wp), intent(out) :: pv(:)
    integer :: i, j, k
    pv(1) = 1.0_wp
    if (basis < basis_linear) return
    pv(2:1 + nd) = y
    if (basis < basis_quadratic) return
    k = 1 + nd
    do i = 1, nd
      do j = i, nd
        k = k + 1
        pv(k) = y(i)*y(j)
      end do
    end do
  end subroutine basis_eval

  !> mom += w pv pv^T on the packed upper triangle: (i,j), i <= j, at j(j-1)/2 + i.
  pure subroutine moment_add(nb, pv, w, mom)
    integer, intent(in) :: nb
    real(wp), intent(in) :: pv(:), w
    real(wp), intent(inout) :: mom(:)
    integer :: i, j, k
    real(wp) :: wj
    k = 0
    do j = 1, nb
      wj = w*pv(j)
      do i = 1, j
        k = k + 1
        mom(k) = mom(k) + wj*pv(i)
      end do
    end do
  end subroutine moment_add

  !> a += b, counter by counter (to add up the statistics of threads or ranks).
  pure subroutine mls_stats_add(a, b)
    type(mls_stats_t), intent(inout) :: a
    type(mls_stats_t), intent(in) :: b
    a%nfull = a%nfull + b%nfull
    a%nreduced = a%nreduced + b%nreduced
    a%nregularised = a%nregularised + b%nregularised
    a%nconstant = a%nconstant + b%nconstant
    a%nempty = a%nempty + b%nempty
    a%nwidened = a%nwidened + b%nwidened
  end subroutine mls_stats_add

  !> Number of evaluation points counted in s.
  pure integer(i8) function mls_stats_total(s) result(n)
    type(mls_stats_t), intent(in) :: s
    n = s%nfull + s%nreduced + s%nregularised + s%nconstant + s%nempty
  end function mls_stats_total

  !> gamma = Mhat^{-1} e_1 for the basis level the fallback policy selects (module header).
  !> mom: packed moments of the requested basis; count: sites with w_p > 0 (real, as it may be
  !> summed over ranks). gamma(basis_size(basis, nd)), zero beyond the level used; level is
  !> the basis used (-1: no site in range). The counter of the path taken is incremented.
  pure subroutine mls_gamma(basis, nd, mom, count, gamma, level, stats)
    integer, intent(in) :: basis, nd
    real(wp), intent(in) :: mom(:), count
    real(wp), intent(out) :: gamma(:)
    integer, intent(out) :: level
    type(mls_stats_t), intent(inout) :: stats
    real(wp) :: u(mls_max_packed), sc(mls_max_basis), rhs(mls_max_basis)
    integer :: path, m
    call mls_factor(basis, nd, mom, count, u, sc, level, path)
    call count_path(path, stats)
    gamma(1:basis_size(basis, nd)) = 0.0_wp
    if (level < 0) return
    m = basis_size(level, nd)
    rhs(1:m) = 0.0_wp
    rhs(1) = 1.0_wp
    call scaled_solve(m, u, sc, rhs(1:m), gamma(1:m))
  end subroutine mls_gamma

  !> MLS shape functions of scattered sites at x and their gradients (doc/theory.md 3.3).
  !> x(nd): evaluation point; sites(nd, n); weight(n) multiplies each kernel weight (volume or
  !> mass; ones for plain MLS); kernel offsets are (x - sites(:,p))/h in cell units, radius and
  !> radial as in kernel_weight. phi(n) = Phi_p(x), dphi(nd, n) = d Phi_p / d x (per metre).
  !> The fallback path is the one of mls_gamma; with Tikhonov regularisation eps is held fixed
  !> in the gradient. No allocation: phi and dphi hold the weights between the two passes.
  pure subroutine mls_shape_functions(nd, basis, kernel, radius, radial, h, x, n, sites, &
                                      weight, phi, dphi, level, stats)
    integer, intent(in) :: nd, basis, kernel, n
    real(wp), intent(in) :: radius, h, x(nd), sites(nd, n), weight(n)
    logical, intent(in) :: radial
    real(wp), intent(out) :: phi(n), dphi(nd, n)
    integer, intent(out) :: level
    type(mls_stats_t), intent(inout) :: stats
    real(wp) :: mom(mls_max_packed), dmom(mls_max_packed, 3), u(mls_max_packed)
    real(wp) :: sc(mls_max_basis), pv(mls_max_basis), gam(mls_max_basis)
    real(wp) :: dgam(mls_max_basis, 3), rhs(mls_max_basis), y(nd), wk, dwk(nd), cnt, g
    integer :: nb, np, m, p, k, path, i, j, ij
    nb = basis_size(basis, nd)
    np = packed_size(nb)
    mom(1:np) = 0.0_wp
    dmom(1:np, 1:nd) = 0.0_wp
    cnt = 0.0_wp
    ! Pass 1: weights (kept in phi, dphi) and the moments with their x-derivatives.
    do p = 1, n
      call kernel_weight(kernel, radius, radial, nd, (x - sites(:, p))/h, wk, dwk)
      phi(p) = weight(p)*wk
      dphi(:, p) = weight(p)*dwk/h
      if (phi(p) <= 0.0_wp .and. all(dphi(:, p) == 0.0_wp)) cycle
      if (phi(p) > 0.0_wp) cnt = cnt + 1.0_wp
      y = (sites(:, p) - x)/h
      call basis_eval(basis, nd, y, pv)
      call moment_add(nb, pv, phi(p), mom)
      do k = 1, nd
        call moment_add(nb, pv, dphi(k, p), dmom(:, k))
      end do
    end do
    call mls_factor(basis, nd, mom, cnt, u, sc, level, path)
    call count_path(path, stats)
    if (level < 0) then
      phi = 0.0_wp
      dphi = 0.0_wp
      return
    end if
    m = basis_size(level, nd)
    rhs(1:m) = 0.0_wp
    rhs(1) = 1.0_wp
    call scaled_solve(m, u, sc, rhs(1:m), gam(1:m))
    ! Unshifted form with the basis origin held at x: d gamma/dx_k = M^{-1}(dp(x)/dx_k -
    ! dM/dx_k gamma), where dp(x)/dx_k = e_{1+k}/h (the linear terms; quadratic ones vanish).
    do k = 1, nd
      do i = 1, m
        g = 0.0_wp
        do j = 1, m
          ij = merge(j*(j - 1)/2 + i, i*(i - 1)/2 + j, i <= j)
          g = g + dmom(ij, k)*gam(j)
        end do
        rhs(i) = -g
      end do
      if (level >= basis_linear) rhs(1 + k) = rhs(1 + k) + 1.0_wp/h
      call scaled_solve(m, u, sc, rhs(1:m), dgam(1:m, k))
    end do
    ! Pass 2: Phi_p = w_p gamma.pv_p, dPhi_p = w_p dgamma.pv_p + (gamma.pv_p) dw_p.
    do p = 1, n
      if (phi(p) <= 0.0_wp .and. all(dphi(:, p) == 0.0_wp)) then
        phi(p) = 0.0_wp
        dphi(:, p) = 0.0_wp
        cycle
      end if
      y = (sites(:, p) - x)/h
      call basis_eval(level, nd, y, pv)
      g = dot_product(gam(1:m), pv(1:m))
      do k = 1, nd
        dphi(k, p) = phi(p)*dot_product(dgam(1:m, k), pv(1:m)) + g*dphi(k, p)
      end do
      phi(p) = phi(p)*g
    end do
  end subroutine mls_shape_functions

  ! ---------------------------------------------------------------------------------------
  ! Internals: level selection, Cholesky of the equilibrated packed matrix, condition estimate.

  !> Apply the fallback policy to the packed moments of the requested basis. On return,
  !> u holds the packed Cholesky factor U (U^T U = S A S) of the matrix A used at the chosen
  !> level (Mhat, or Mhat + eps I) and sc the equilibration S = diag(sc); path names the case.
  pure subroutine mls_factor(basis, nd, mom, count, u, sc, level, path)
    integer, intent(in) :: basis, nd
    real(wp), intent(in) :: mom(:), count
    real(wp), intent(out) :: u(:), sc(:)
    integer, intent(out) :: level, path
    integer :: lev, m, i
    logical :: ok
    real(wp) :: eps, rc
    if (.not. (mom(1) > 0.0_wp)) then
      level = -1
      path = path_empty
      return
    end if
    if (basis == basis_constant) then
      call constant_factor(mom, u, sc)
      level = basis_constant
      path = path_full
      return
    end if
    ! Requested level, then (quadratic only) linear.
    do lev = basis, basis_linear, -1
      m = basis_size(lev, nd)
      if (count < real(m, wp) - 0.5_wp) cycle
      call equilibrated_cholesky(m, mom, 0.0_wp, u, sc, ok)
      if (.not. ok) cycle
      rc = rcond_estimate(m, mom, u, sc)
      if (rc >= mls_rcond_min) then
        level = lev
        path = merge(path_full, path_reduced, lev == basis)
        return
      end if
    end do
    ! Linear with Tikhonov regularisation.
    if (count >= 2.0_wp - 0.5_wp) then
      m = basis_size(basis_linear, nd)
      eps = 0.0_wp
      do i = 1, m
        eps = eps + mom(i*(i + 1)/2)
      end do
      eps = mls_tikhonov*eps/real(m, wp)
      call equilibrated_cholesky(m, mom, eps, u, sc, ok)
      if (ok) then
        level = basis_linear
        path = path_regularised
        return
      end if
    end if
    call constant_factor(mom, u, sc)
    level = basis_constant
    path = path_constant
  end subroutine mls_factor

  !> Factor of the 1 x 1 constant-basis moment: solves give b/mom(1) (Shepard).
  pure subroutine constant_factor(mom, u, sc)
    real(wp), intent(in) :: mom(:)
    real(wp), intent(out) :: u(:), sc(:)
    u(1) = 1.0_wp
    sc(1) = 1.0_wp/sqrt(mom(1))
  end subroutine constant_factor

  !> Cholesky U^T U = S (A + eps I) S of the leading m x m block of packed A, with
  !> S = diag(1/sqrt(A_ii + eps)) so that the factored matrix has a unit diagonal (its
  !> condition then measures the geometry, not the scale of the basis terms).
  !> ok is false when a pivot is not above m*epsilon: such a matrix is not numerically positive
  !> definite (its condition exceeds 1/(m epsilon)), and the floor keeps the solves finite.
  pure subroutine equilibrated_cholesky(m, a, eps, u, sc, ok)
    integer, intent(in) :: m
    real(wp), intent(in) :: a(:), eps
    real(wp), intent(out) :: u(:), sc(:)
    logical, intent(out) :: ok
    integer :: i, j, k, ii, jj
    real(wp) :: s
    ok = .false.
    do i = 1, m
      s = a(i*(i + 1)/2) + eps
      if (.not. (s > 0.0_wp)) return
      sc(i) = 1.0_wp/sqrt(s)
    end do
    do j = 1, m
      jj = j*(j - 1)/2
      do i = 1, j
        ii = i*(i - 1)/2
        s = a(jj + i)*sc(i)*sc(j)
        if (i == j) s = s + eps*sc(i)*sc(i)
        do k = 1, i - 1
          s = s - u(ii + k)*u(jj + k)
        end do
        if (i < j) then
          u(jj + i) = s/u(ii + i)
        else
          if (.not. (s > real(m, wp)*epsilon(1.0_wp))) return
          u(jj + j) = sqrt(s)
        end if
      end do
    end do
    ok = .true.
  end subroutine equilibrated_cholesky

  !> Solve U^T U z = b for the packed upper factor U of order m, in place.
  pure subroutine cholesky_solve(m, u, z)
    integer, intent(in) :: m
    real(wp), intent(in) :: u(:)
    real(wp), intent(inout) :: z(:)
    integer :: i, k, ii
    do i = 1, m
      ii = i*(i - 1)/2
      do k = 1, i - 1
        z(i) = z(i) - u(ii + k)*z(k)
      end do
      z(i) = z(i)/u(ii + i)
    end do
    do i = m, 1, -1
      do k = i + 1, m
        z(i) = z(i) - u(k*(k - 1)/2 + i)*z(k)
      end do
      z(i) = z(i)/u(i*(i + 1)/2)
    end do
  end subroutine cholesky_solve

  !> Solve A x = b with U^T U = S A S: x = S (U^T U)^{-1} S b.
  pure subroutine scaled_solve(m, u, sc, b, x)
    integer, intent(in) :: m
    real(wp), intent(in) :: u(:), sc(:), b(:)
    real(wp), intent(out) :: x(:)
    x(1:m) = sc(1:m)*b(1:m)
    call cholesky_solve(m, u, x)
    x(1:m) = sc(1:m)*x(1:m)
  end subroutine scaled_solve

  !> Reciprocal 1-norm condition estimate 1/(|A|_1 |A^{-1}|_1) of the moment matrix A itself
  !> (shifted basis in cell units, not the equilibrated one: equilibration would hide a cloud
  !> that is nearly flat on the scale of h, whose gradients are then huge). |A^{-1}|_1 comes
  !> from Hager's estimator with solves through the factor (A symmetric: A^{-T} = A^{-1}).
  pure real(wp) function rcond_estimate(m, a, u, sc) result(rc)
    integer, intent(in) :: m
    real(wp), intent(in) :: a(:), u(:), sc(:)
    real(wp) :: v(mls_max_basis), sg(mls_max_basis), z(mls_max_basis), colsum, anorm, ainv
    integer :: i, j, it, jmax
    anorm = 0.0_wp
    do j = 1, m
      colsum = 0.0_wp
      do i = 1, m
        colsum = colsum + abs(a(merge(j*(j - 1)/2 + i, i*(i - 1)/2 + j, i <= j)))
      end do
      anorm = max(anorm, colsum)
    end do
    v(1:m) = 1.0_wp/real(m, wp)
    ainv = 0.0_wp
    do it = 1, 5
      call scaled_solve(m, u, sc, v, z)
      ainv = max(ainv, sum(abs(z(1:m))))
      do i = 1, m
        sg(i) = sign(1.0_wp, z(i))
      end do
      call scaled_solve(m, u, sc, sg, z)
      ! z = A^{-1} sign(A^{-1} v); stop when no unit vector improves on v (Hager 1984).
      jmax = maxloc(abs(z(1:m)), dim=1)
      if (it > 1 .and. abs(z(jmax)) <= dot_product(z(1:m), v(1:m))) exit
      v(1:m) = 0.0_wp
      v(jmax) = 1.0_wp
    end do
    rc = 1.0_wp/(anorm*ainv)
  end function rcond_estimate

  !> Increment the counter of one path.
  pure subroutine count_path(path, stats)
    integer, intent(in) :: path
    type(mls_stats_t), intent(inout) :: stats
    select case (path)
    case (path_full)
      stats%nfull = stats%nfull + 1
    case (path_reduced)
      stats%nreduced = stats%nreduced + 1
    case (path_regularised)
      stats%nregularised = stats%nregularised + 1
    case (path_constant)
      stats%nconstant = stats%nconstant + 1
    case (path_empty)
      stats%nempty = stats%nempty + 1
    end select
  end subroutine count_path

end module dpmpm_mls
