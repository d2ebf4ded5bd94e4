!> Time per point of dpmpm's grid transfers on one core, called directly on the block of
!> scripts/bench.py (2D: 360 cells per axis, a block of 0.4 x 0.4 with 2 x 2 points per
!> cell, 82 944 points; 3D: 64 cells per axis, a cube of edge 0.375, 110 592 points),
!> with every grid kernel. A step's stages run as separate calls on the same data, so
!> their costs come without the rest of the step, and the smallest time of many short
!> repetitions is steady on a shared machine where whole runs scatter by tens of per cent.
!>
!> Usage: dpmpm_kernel_bench [--quick] [--rounds N]
!> Output, one line per measurement (lines starting with # are comments):
!>   ndim kernel stage points ns_per_point_min ns_per_point_median
!> stage: p2g (mass, momentum, stress forces), g2p_usl (velocities, positions and the
!> velocity gradient), g2p (without the gradient, as the MUSL remap calls it),
!> momentum_p2g (the remap's momenta), point_gradient (the remap's gradient), stencils
!> (weights and derivatives of every point), g2p_gather (g2p without the gradient that
!> also gathers a second nodal vector, the locked velocity of the two-phase remap),
!> fluid_p2g (the fluid's mass, momentum, drag and pore-pressure forces on both phases)
!> point_divergences (the fluid points' divergences of both phases' velocities),
!> interp_two_values (two components of a nodal field at the points: the porosity and
!> 1/k of the fluid points), stress (the neo-Hookean update of the bench block's
!> points from their velocity gradients, plane strain in 2D; the same for every kernel),
!> g2p_remap (g2p without the gradient and the remap's momenta in one pass, as the MUSL
!> step runs them) and g2p_remap_gather (the same with the gather of the locked velocity
!> and the momenta of its projection).
program dpmpm_kernel_bench
  use, intrinsic :: iso_fortran_env, only: output_unit, int64
  use dpmpm_kinds, only: wp
  use dpmpm_stats, only: median
  use dpmpm_kernels, only: psi_stencils, kernel_width, kernel_names, kernel_linear, kernel_cubic
  use dpmpm_transfer, only: p2g, g2p, momentum_p2g, point_gradient, fluid_p2g, point_divergences, &
                            interp_two_values, g2p_remap
  use dpmpm_materials, only: material_t, model_neo_hookean, stress_update
  implicit none

  !> Lower corner of the block along every axis (scripts/bench.py puts its block of the
  !> same size elsewhere in the grid; the place does not change the cost).
  real(wp), parameter :: x0 = 0.3_wp
  integer :: nround, nd, kernel, narg, iarg
  character(len=32) :: arg
  logical :: quick

  quick = .false.
  nround = 9
  narg = command_argument_count()
  iarg = 1
  do while (iarg <= narg)
    call get_command_argument(iarg, arg)
    select case (trim(arg))
    case ('--quick')
      quick = .true.
      nround = 2
    case ('--rounds')
      iarg = iarg + 1
      call get_command_argument(iarg, arg)
      read (arg, *) nround
      if (nround < 1) then
        write (output_unit, '(a)') 'dpmpm_kernel_bench: --rounds needs a number of at least 1'
        stop 2
      end if
    case default
      write (output_unit, '(a)') 'usage: dpmpm_kernel_bench [--quick] [--rounds N]'
      stop 2
    end select
    iarg = iarg + 1
  end do

  write (output_unit, '(a,i0,a)') '# dpmpm_kernel_bench: one core, ', nround, &
    ' rounds; nanoseconds per point and call, smallest and median over the rounds'
  write (output_unit, '(a)') '# ndim kernel stage points ns_min ns_median'
  do nd = 2, 3
    do kernel = kernel_linear, kernel_cubic
      call measure(nd, kernel)
    end do
  end do

contains

  !> Every stage for one dimension and grid kernel: the block's points and stencils, node
  !> fields of the grid, then each stage timed over nround rounds of ncall calls.
  subroutine measure(nd, kernel)
    integer, intent(in) :: nd, kernel
    integer :: cells, per_axis, n, nw(3), lo(3), hi(3), p, d, q(3), s, r, ncall, c
    integer(int64) :: c0, c1, rate
    real(wp) :: origin(3), h(3), edge, t(nround)
    integer, allocatable :: i0(:, :)
    real(wp), allocatable :: x(:, :), sw(:, :, :), sdw(:, :, :), mass(:), v(:, :), vol(:), stress(:, :)
    real(wp), allocatable :: vgrad(:, :), node(:, :, :, :), nvel(:, :, :, :), node2(:, :, :, :)
    real(wp), allocatable :: drag(:, :, :, :), poro(:), pres(:), kinv(:), gv(:, :), div(:), div2(:)
    real(wp), allocatable :: defgrad(:, :), vol0(:)
    integer, allocatable :: pmat(:)
    type(material_t) :: neo
    character(len=*), parameter :: stages(13) = [character(len=17) :: 'stencils', 'p2g', 'g2p_usl', &
                                                  'g2p', 'momentum_p2g', 'point_gradient', 'g2p_gather', &
                                                  'fluid_p2g', 'point_divergences', 'interp_two_values', &
                                                  'stress', 'g2p_remap', 'g2p_remap_gather']
    if (nd == 2) then
      cells = 360; edge = 0.4_wp
    else
      cells = 64; edge = 0.375_wp
    end if
    if (quick) cells = cells/4
    h = 1.0_wp/cells
    h(nd + 1:) = 1.0_wp
    origin = 0.0_wp
    per_axis = 2*nint(edge*cells)
    n = per_axis**nd
    nw = 1
    nw(1:nd) = kernel_width(kernel)
    allocate (i0(3, n), x(nd, n), sw(nw(1), 3, n), sdw(nw(1), 3, n), mass(n), v(nd, n), vol(n), &
              stress(6, n), vgrad(9, n))
    ! points in the order the generator makes them (axis 1 fastest), two per cell and axis
    q = 0
    do p = 1, n
      do d = 1, nd
        x(d, p) = x0 + (q(d) + 0.5_wp)*0.5_wp*h(d)
      end do
      do d = 1, nd
        q(d) = q(d) + 1
        if (q(d) < per_axis) exit
        q(d) = 0
      end do
    end do
    sw = 0.0_wp; sdw = 0.0_wp
    sw(1, nd + 1:3, :) = 1.0_wp
    i0 = 0
    call psi_stencils(nd, kernel, n, x, origin, h, i0, sw, sdw)
    lo = 0; hi = 0
    lo(1:nd) = -1; hi(1:nd) = cells + 1
    allocate (node(1 + 2*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), &
              node2(1 + 2*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), &
              drag(1, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), nvel(2*nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
    allocate (poro(n), pres(n), kinv(n), gv(nd, n), div(n), div2(n))
    poro = 0.3_wp; pres = 1.0e4_wp; kinv = 1.0e5_wp
    node2 = 0.0_wp; drag = 0.0_wp
    mass = 1.0e-3_wp; vol = 1.0e-6_wp
    v = 0.01_wp
    do p = 1, n
      stress(:, p) = [1.0_wp, 2.0_wp, 3.0_wp, 0.4_wp, 0.5_wp, 0.6_wp]*real(mod(p, 7) + 1, wp)
    end do
    node = 0.0_wp
    ! the same old and new velocities: g2p leaves the point velocities as they are
    nvel = 0.02_wp
    ! the block's material (E = 1 MPa, nu = 0.3) with F = I, and velocity gradients of a
    ! few per cent per second that differ from point to point
    neo = material_t(model=model_neo_hookean, mu=1.0e6_wp/2.6_wp, lambda=0.3e6_wp/(1.3_wp*0.4_wp))
    allocate (defgrad(9, n), vol0(n), pmat(n))
    defgrad = 0.0_wp
    defgrad([1, 5, 9], :) = 1.0_wp
    vol0 = vol
    pmat = 1
    ncall = max(1, 2000000/n)
    if (quick) ncall = 1
    do s = 1, size(stages)
      if (s == 11) then
        do p = 1, n
          vgrad(:, p) = 0.01_wp*[1.0_wp, 0.2_wp, 0.0_wp, -0.3_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]* &
                        real(mod(p, 5) + 1, wp)
          if (nd == 3) vgrad(9, p) = 0.005_wp*real(mod(p, 3) + 1, wp)
        end do
      end if
      do r = 1, nround
        call system_clock(c0, rate)
        do c = 1, ncall
          select case (s)
          case (1)
            call psi_stencils(nd, kernel, n, x, origin, h, i0, sw, sdw)
          case (2)
            call p2g(nd, nw, n, i0, sw, sdw, mass, v, vol, stress, .true., lo, node)
          case (3)
            call g2p(nd, nw, n, i0, sw, sdw, lo, nvel, 1.0_wp, 0.0_wp, v, x, vgrad, .true.)
          case (4)
            call g2p(nd, nw, n, i0, sw, sdw, lo, nvel, 1.0_wp, 0.0_wp, v, x)
          case (5)
            call momentum_p2g(nd, nw, n, i0, sw, mass, v, lo, node)
          case (6)
            call point_gradient(nd, nw, n, i0, sw, sdw, lo, nvel, vgrad)
          case (7)
            call g2p(nd, nw, n, i0, sw, sdw, lo, nvel, 1.0_wp, 0.0_wp, v, x, gf=nvel, gv=gv)
          case (8)
            call fluid_p2g(nd, nw, n, i0, sw, sdw, mass, v, vol, poro, pres, kinv, .true., .true., lo, &
                           node2, node, drag)
          case (9)
            call point_divergences(nd, nw, n, i0, sw, sdw, lo, nvel, nvel, div, div2)
          case (10)
            call interp_two_values(nd, nw, n, i0, sw, lo, nvel, 3, div, div2)
          case (12)
            call g2p_remap(nd, nw, n, i0, sw, sdw, lo, nvel, 1.0_wp, 0.0_wp, mass, v, x, node)
          case (13)
            call g2p_remap(nd, nw, n, i0, sw, sdw, lo, nvel, 1.0_wp, 0.0_wp, mass, v, x, node2, gf=nvel, gv=gv)
          case default
            call stress_update(neo, 1, 1.0e-4_wp, n, pmat, vgrad, stress, vol, vol0, defgrad, plane=nd == 2)
          end select
        end do
        call system_clock(c1)
        t(r) = real(c1 - c0, wp)/real(rate, wp)/ncall
      end do
      write (output_unit, '(i0,1x,a,1x,a,1x,i0,2f10.2)') nd, trim(kernel_names(kernel)), trim(stages(s)), n, &
        1.0e9_wp*minval(t)/n, 1.0e9_wp*median(t)/n
    end do
  end subroutine measure

end program dpmpm_kernel_bench
