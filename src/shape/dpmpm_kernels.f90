!> Kernels of dpmpm. Two uses share one set of functions:
!> - grid functions (linear, quadratic, cubic B-spline) as tensor products on the
!>   regular grid: kernel_eval_1d gives a point's stencil of nodes and weights,
!>   psi_stencil those of every axis and psi_stencils those of a whole point set;
!> - reconstruction weights of MLS (any kernel, radial or as a tensor product of
!>   its profile over a box; the B-splines also of natural support): kernel_weight
!>   gives the weight of a data site at an offset from an evaluation point
!>   (doc/theory.md 3.3).
!> Offsets and radii are in cell units; derivatives are with respect to them.
module dpmpm_kernels
  use dpmpm_kinds, only: wp
  use dpmpm_error, only: fatal
  use dpmpm_strings, only: itoa
  implicit none
  private
  public :: kernel_linear, kernel_quadratic, kernel_cubic, kernel_wendland_c2, kernel_wendland_c4
  public :: kernel_names, kernel_from_name, ngrid_kernels, is_grid_kernel
  public :: kernel_width, kernel_ghost_width, kernel_eval_1d, max_stencil, psi_stencil, psi_stencils
  public :: bspline_1d, kernel_radial, kernel_radial_values, kernel_weight, kernel_reach
  public :: refuse_kernel, refuse_width
  public :: grid_kernel_t, grid_kernel_table, grid_kernel_lookup, bind_grid_kernel

  integer, parameter :: kernel_linear = 1, kernel_quadratic = 2, kernel_cubic = 3
  integer, parameter :: kernel_wendland_c2 = 4, kernel_wendland_c4 = 5
  !> The first ngrid_kernels kernels are B-splines and can serve as grid functions.
  integer, parameter :: ngrid_kernels = 3
  character(len=12), parameter :: kernel_names(5) = ['linear      ', 'quadratic   ', &
                                                     'cubic       ', 'wendland_c2 ', 'wendland_c4 ']
  !> Largest number of nodes per axis of any grid kernel's stencil.
  integer, parameter :: max_stencil = 4

  !> What the grid transfers need of a grid kernel, bound once from its code
  !> (bind_grid_kernel) where the stencils of a phase are set up, so that no loop derives
  !> it from the code again.
  type :: grid_kernel_t
    integer :: kernel = 0          !< kernel code (kernel_linear, ...); 0 while unbound
    integer :: width = 0           !< nodes per axis of a point's stencil
    integer :: ghost = 0           !< ghost layer (nodes) a stencil reaches beyond its cell
    real(wp) :: reach = 0.0_wp     !< half-width of the natural support (cell units)
  end type grid_kernel_t

  !> The grid kernels, one line each (a B-spline of degree k: k + 1 nodes, reach (k + 1)/2).
  type(grid_kernel_t), parameter :: grid_kernel_table(ngrid_kernels) = [ &
                                    grid_kernel_t(kernel_linear, 2, 1, 1.0_wp), &
                                    grid_kernel_t(kernel_quadratic, 3, 2, 1.5_wp), &
                                    grid_kernel_t(kernel_cubic, 4, 2, 2.0_wp)]

contains

  !> Kernel id from its input name, 0 if unknown.
  pure integer function kernel_from_name(name) result(k)
    character(len=*), intent(in) :: name
    integer :: j
    k = 0
    do j = 1, size(kernel_names)
      if (trim(adjustl(name)) == trim(kernel_names(j))) k = j
    end do
  end function kernel_from_name

  !> True for the B-splines, which are a partition of unity on the grid.
  pure logical function is_grid_kernel(kernel)
    integer, intent(in) :: kernel
    is_grid_kernel = kernel >= 1 .and. kernel <= ngrid_kernels
  end function is_grid_kernel

  !> Stop the run on a kernel code that a dispatch does not know: a kernel added to
  !> the list but not wired into every dispatch must not run as another one.
  subroutine refuse_kernel(kernel, where)
    integer, intent(in) :: kernel
    character(len=*), intent(in) :: where
    if (kernel >= 1 .and. kernel <= size(kernel_names)) then
      call fatal('kernel '//trim(kernel_names(kernel))//' (code '//itoa(kernel)// &
                 ') is not handled here', where)
    else
      call fatal('unknown kernel code '//itoa(kernel), where)
    end if
  end subroutine refuse_kernel

  !> Stop the run on a stencil width (nodes per axis) that no transfer of fixed width
  !> has: 2, 3 and 4 are those of the linear, quadratic and cubic B-spline.
  subroutine refuse_width(nw, where)
    integer, intent(in) :: nw
    character(len=*), intent(in) :: where
    call fatal('no grid transfer of stencil width '//itoa(nw)// &
               ' (the widths are 2, 3 and 4 nodes per axis)', where)
  end subroutine refuse_width

  !> The row of grid_kernel_table of a kernel code: stat 0, or 1 (gk unbound) for a code
  !> that is no grid kernel (a kernel of MLS weights only, or unknown).
  pure subroutine grid_kernel_lookup(kernel, gk, stat)
    integer, intent(in) :: kernel
    type(grid_kernel_t), intent(out) :: gk
    integer, intent(out) :: stat
    integer :: j
    stat = 1
    do j = 1, size(grid_kernel_table)
      if (grid_kernel_table(j)%kernel == kernel) then
        gk = grid_kernel_table(j)
        stat = 0
      end if
    end do
  end subroutine grid_kernel_lookup

  !> A grid kernel bound from its code; a code that is no grid kernel stops the run
  !> (where: the caller, named in the message).
  function bind_grid_kernel(kernel, where) result(gk)
    integer, intent(in) :: kernel
    character(len=*), intent(in) :: where
    type(grid_kernel_t) :: gk
    integer :: stat
    call grid_kernel_lookup(kernel, gk, stat)
    if (stat /= 0) call refuse_kernel(kernel, where)
  end function bind_grid_kernel

  !> Nodes per axis in a grid kernel's stencil.
  integer function kernel_width(kernel) result(n)
    integer, intent(in) :: kernel
    type(grid_kernel_t) :: gk
    gk = bind_grid_kernel(kernel, 'kernel_width')
    n = gk%width
  end function kernel_width

  !> Ghost layer (in nodes) that a point inside a rank's cells can reach beyond
  !> them with a grid kernel's stencil.
  integer function kernel_ghost_width(kernel) result(g)
    integer, intent(in) :: kernel
    type(grid_kernel_t) :: gk
    gk = bind_grid_kernel(kernel, 'kernel_ghost_width')
    g = gk%ghost
  end function kernel_ghost_width

  !> Evaluate a 1D grid kernel at s = (x - origin)/h (cell units). Returns the
  !> first stencil node i0 and, for nodes i0..i0+width-1, the weights w and
  !> derivatives dw with respect to s (divide by h for d/dx).
  subroutine kernel_eval_1d(kernel, s, i0, w, dw)
    integer, intent(in) :: kernel
    real(wp), intent(in) :: s
    integer, intent(out) :: i0
    real(wp), intent(out) :: w(max_stencil), dw(max_stencil)
    w = 0.0_wp
    dw = 0.0_wp
    ! (a derivative divided by 1 is the same number)
    select case (kernel)
    case (kernel_linear)
      call linear_1d(s, 1.0_wp, i0, w(1:2), dw(1:2))
    case (kernel_quadratic)
      call quadratic_1d(s, 1.0_wp, i0, w(1:3), dw(1:3))
    case (kernel_cubic)
      call cubic_1d(s, 1.0_wp, i0, w(1:4), dw(1:4))
    case default
      i0 = 0
      call refuse_kernel(kernel, 'kernel_eval_1d')
    end select
  end subroutine kernel_eval_1d

  ! The pieces of bspline_1d written out for the nodes of the stencil, with f the
  ! position from its first node: f in [0, 1) linear, [0.5, 1.5) quadratic, [1, 2) cubic;
  ! the derivatives divided by hd (the cell size for d/dx, 1 for d/ds). Rows of the
  ! kernel's width, small enough to be inlined into the loops over points
  ! (kernel_eval_1d, psi_stencils).

  pure subroutine linear_1d(s, hd, i0, w, dw)
    real(wp), intent(in) :: s, hd
    integer, intent(out) :: i0
    real(wp), intent(out) :: w(2), dw(2)
    real(wp) :: f
    i0 = floor(s)
    f = s - real(i0, wp)
    w(1) = 1.0_wp - f; dw(1) = -1.0_wp/hd
    w(2) = f; dw(2) = 1.0_wp/hd
  end subroutine linear_1d

  pure subroutine quadratic_1d(s, hd, i0, w, dw)
    real(wp), intent(in) :: s, hd
    integer, intent(out) :: i0
    real(wp), intent(out) :: w(3), dw(3)
    real(wp) :: f, a
    i0 = floor(s - 0.5_wp)
    f = s - real(i0, wp)
    a = 1.5_wp - f
    w(1) = 0.5_wp*a*a; dw(1) = (-a)/hd
    a = f - 1.0_wp
    w(2) = 0.75_wp - a*a; dw(2) = (-2.0_wp*a)/hd
    a = f - 0.5_wp
    w(3) = 0.5_wp*a*a; dw(3) = a/hd
  end subroutine quadratic_1d

  pure subroutine cubic_1d(s, hd, i0, w, dw)
    real(wp), intent(in) :: s, hd
    integer, intent(out) :: i0
    real(wp), intent(out) :: w(4), dw(4)
    real(wp) :: f, a, b
    i0 = floor(s) - 1
    f = s - real(i0, wp)
    a = 2.0_wp - f
    w(1) = a*a*a/6.0_wp; dw(1) = (-0.5_wp*a*a)/hd
    a = f - 1.0_wp
    w(2) = 0.5_wp*a*a*a - a*a + 2.0_wp/3.0_wp; dw(2) = (1.5_wp*a*a - 2.0_wp*a)/hd
    b = 2.0_wp - f
    w(3) = 0.5_wp*b*b*b - b*b + 2.0_wp/3.0_wp; dw(3) = (-(1.5_wp*b*b - 2.0_wp*b))/hd
    w(4) = a*a*a/6.0_wp; dw(4) = (0.5_wp*a*a)/hd
  end subroutine cubic_1d

  !> Grid-function weights and gradients (per metre) per axis at a position y in
  !> cell units: first node i0, weights sw(:, d), derivatives sdw(:, d); the
  !> unused axes have one node of weight 1.
  subroutine psi_stencil(nd, kernel, y, h, i0, sw, sdw)
    integer, intent(in) :: nd, kernel
    real(wp), intent(in) :: y(3), h(3)
    integer, intent(out) :: i0(3)
    real(wp), intent(out) :: sw(max_stencil, 3), sdw(max_stencil, 3)
    integer :: d
    do d = 1, 3
      if (d <= nd) then
        call kernel_eval_1d(kernel, y(d), i0(d), sw(:, d), sdw(:, d))
        sdw(:, d) = sdw(:, d)/h(d)
      else
        i0(d) = 0
        sw(:, d) = 0.0_wp
        sw(1, d) = 1.0_wp
        sdw(:, d) = 0.0_wp
      end if
    end do
  end subroutine psi_stencil

  !> psi_stencil of the first n points at positions x (nd, n) on the grid with the given
  !> origin and cell size h (y = (x - origin) / h per axis): first nodes i0(1:nd, p),
  !> weights sw(:, 1:nd, p) and derivatives sdw(:, 1:nd, p), rows of the kernel's width
  !> (2, 3 or 4 values; size(sw, 1) may be larger); the axes beyond nd are left as they
  !> are (stencil_t sets them once). In the module of kernel_eval_1d so that the kernel
  !> is evaluated inline, once per point and axis.
  subroutine psi_stencils(nd, kernel, n, x, origin, h, i0, sw, sdw)
    integer, intent(in) :: nd, kernel, n
    real(wp), intent(in) :: x(:, :), origin(3), h(3)
    integer, contiguous, intent(inout) :: i0(:, :)
    real(wp), contiguous, intent(inout) :: sw(:, :, :), sdw(:, :, :)
    integer :: p, d
    real(wp) :: s
    ! (one loop per kernel, each writing the rows in place)
    select case (kernel)
    case (kernel_linear)
      do p = 1, n
        do d = 1, nd
          s = (x(d, p) - origin(d))/h(d)
          call linear_1d(s, h(d), i0(d, p), sw(1:2, d, p), sdw(1:2, d, p))
        end do
      end do
    case (kernel_quadratic)
      do p = 1, n
        do d = 1, nd
          s = (x(d, p) - origin(d))/h(d)
          call quadratic_1d(s, h(d), i0(d, p), sw(1:3, d, p), sdw(1:3, d, p))
        end do
      end do
    case (kernel_cubic)
      do p = 1, n
        do d = 1, nd
          s = (x(d, p) - origin(d))/h(d)
          call cubic_1d(s, h(d), i0(d, p), sw(1:4, d, p), sdw(1:4, d, p))
        end do
      end do
    case default
      call refuse_kernel(kernel, 'psi_stencils')
    end select
  end subroutine psi_stencils

  !> 1D B-spline of the given order (linear, quadratic, cubic) centred at 0, at
  !> xi in cell units, with its derivative (doc/theory.md 3.3).
  elemental subroutine bspline_1d(kernel, xi, w, dw)
    integer, intent(in) :: kernel
    real(wp), intent(in) :: xi
    real(wp), intent(out) :: w, dw
    real(wp) :: a, sg
    a = abs(xi)
    sg = sign(1.0_wp, xi)
    w = 0.0_wp
    dw = 0.0_wp
    select case (kernel)
    case (kernel_linear)
      ! Closed at |xi| = 1 so that a point on a node keeps its cell's gradient.
      if (a <= 1.0_wp) then
        w = 1.0_wp - a
        dw = -sg
      end if
    case (kernel_quadratic)
      if (a <= 0.5_wp) then
        w = 0.75_wp - a*a
        dw = -2.0_wp*xi
      else if (a < 1.5_wp) then
        w = 0.5_wp*(1.5_wp - a)**2
        dw = -sg*(1.5_wp - a)
      end if
    case (kernel_cubic)
      if (a <= 1.0_wp) then
        w = 0.5_wp*a**3 - a*a + 2.0_wp/3.0_wp
        dw = sg*(1.5_wp*a*a - 2.0_wp*a)
      else if (a < 2.0_wp) then
        w = (2.0_wp - a)**3/6.0_wp
        dw = -sg*0.5_wp*(2.0_wp - a)**2
      end if
    end select
  end subroutine bspline_1d

  !> Radial profile of a kernel on r in [0, 1] (r = distance / support radius),
  !> with dw/dr. B-splines are their 1D shape stretched to unit support;
  !> constant factors are irrelevant in MLS, where they cancel.
  elemental subroutine kernel_radial(kernel, r, w, dwdr)
    integer, intent(in) :: kernel
    real(wp), intent(in) :: r
    real(wp), intent(out) :: w, dwdr
    real(wp) :: q
    w = 0.0_wp
    dwdr = 0.0_wp
    if (r >= 1.0_wp) return
    select case (kernel)
    case (kernel_linear)
      w = 1.0_wp - r
      dwdr = -1.0_wp
    case (kernel_quadratic)
      call bspline_1d(kernel_quadratic, 1.5_wp*r, w, dwdr)
      dwdr = 1.5_wp*dwdr
    case (kernel_cubic)
      call bspline_1d(kernel_cubic, 2.0_wp*r, w, dwdr)
      dwdr = 2.0_wp*dwdr
    case (kernel_wendland_c2)
      ! (1 - r)^4 (1 + 4 r)
      q = 1.0_wp - r
      w = q**4*(1.0_wp + 4.0_wp*r)
      dwdr = -20.0_wp*r*q**3
    case (kernel_wendland_c4)
      ! (1 - r)^6 (35 r^2 + 18 r + 3) / 3
      q = 1.0_wp - r
      w = q**6*(35.0_wp*r*r + 18.0_wp*r + 3.0_wp)/3.0_wp
      dwdr = -(56.0_wp/3.0_wp)*r*(1.0_wp + 5.0_wp*r)*q**5
    end select
  end subroutine kernel_radial

  !> kernel_radial's profile (without its slope) at each r(1:n), in place: the kernel
  !> chosen once for the whole list instead of once per value.
  subroutine kernel_radial_values(kernel, n, r)
    integer, intent(in) :: kernel, n
    real(wp), intent(inout) :: r(:)
    real(wp) :: q, dw
    integer :: k
    select case (kernel)
    case (kernel_linear)
      do k = 1, n
        r(k) = merge(1.0_wp - r(k), 0.0_wp, r(k) < 1.0_wp)
      end do
    case (kernel_wendland_c2)
      do k = 1, n
        q = 1.0_wp - r(k)
        r(k) = merge(q**4*(1.0_wp + 4.0_wp*r(k)), 0.0_wp, r(k) < 1.0_wp)
      end do
    case (kernel_quadratic, kernel_cubic, kernel_wendland_c4)
      do k = 1, n
        q = r(k)
        call kernel_radial(kernel, q, r(k), dw)
      end do
    case default
      call refuse_kernel(kernel, 'kernel_radial_values')
    end select
  end subroutine kernel_radial_values

  !> Reconstruction weight of a data site seen from an evaluation point at
  !> offset d (evaluation point minus site, cell units) and its gradient with
  !> respect to the evaluation point. Radial weights use w(|d|/radius). The tensor
  !> form is the product over the axes of the kernel's profile w(|d_k|/radius), of
  !> half-width radius along each axis (a box); with radius 0 it is the product of
  !> 1D B-splines of natural support (B-splines only). Wendland kernels with
  !> radius 0 are radial (the input refuses them).
  pure subroutine kernel_weight(kernel, radius, radial, nd, d, w, dw)
    integer, intent(in) :: kernel, nd
    real(wp), intent(in) :: radius
    logical, intent(in) :: radial
    real(wp), intent(in) :: d(nd)
    real(wp), intent(out) :: w, dw(nd)
    real(wp) :: r, dwdr, wk(nd), dwk(nd)
    integer :: k
    if (radial .or. (radius <= 0.0_wp .and. .not. is_grid_kernel(kernel))) then
      r = norm2(d)/radius
      call kernel_radial(kernel, r, w, dwdr)
      if (r > 0.0_wp) then
        dw = dwdr*d/(r*radius*radius)
      else
        dw = 0.0_wp
      end if
      return
    end if
    if (radius > 0.0_wp) then
      do k = 1, nd
        call kernel_radial(kernel, abs(d(k))/radius, wk(k), dwdr)
        ! (the hat's kink at 0 is given the mean of its two slopes, 0)
        dwk(k) = 0.0_wp
        if (d(k) /= 0.0_wp) dwk(k) = dwdr*sign(1.0_wp, d(k))/radius
      end do
    else
      call bspline_1d(kernel, d, wk, dwk)
    end if
    w = product(wk)
    do k = 1, nd
      dw(k) = dwk(k)*product(wk(1:k - 1))*product(wk(k + 1:nd))
    end do
  end subroutine kernel_weight

  !> Half-width (cell units) of the region where kernel_weight can be non-zero.
  real(wp) function kernel_reach(kernel, radius, radial) result(reach)
    integer, intent(in) :: kernel
    real(wp), intent(in) :: radius
    logical, intent(in) :: radial
    type(grid_kernel_t) :: gk
    integer :: stat
    if (radial .or. radius > 0.0_wp) then
      reach = radius
      return
    end if
    ! (natural support: the grid kernels' own, from their table; the Wendland kernels have
    ! none, and the input refuses them without a radius)
    call grid_kernel_lookup(kernel, gk, stat)
    if (stat == 0) then
      reach = gk%reach
      return
    end if
    select case (kernel)
    case (kernel_wendland_c2, kernel_wendland_c4)
      reach = radius
    case default
      reach = 0.0_wp
      call refuse_kernel(kernel, 'kernel_reach')
    end select
  end function kernel_reach

end module dpmpm_kernels
