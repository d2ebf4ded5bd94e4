!> Steady seepage through a rectangular dam (doc/verification.md, "Seepage through a
!> rectangular dam"): the scene of inputs/dam_seepage_2d.nml on a grid of 0.1 m against
!> the steady free-boundary problem, solved here on its own by Baiocchi's transformation.
program test_dam_seepage
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_MAX, &
                     MPI_SUM
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, material_cfg_t, bc_fixed, bc_roller, fbc_drained, resolve_geostatic
  use dpmpm_test_scenes, only: grid_scene
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer, parameter :: ncol = 10             !< cells across the dam (h = 0.1 m)
  integer, parameter :: nref = 40             !< intervals of the reference over 1 m
  real(wp), parameter :: rho_g = 9810.0_wp
  call start_tests()
  call test_reference_free_surface()
  call test_dam_reaches_the_steady_free_surface()
  call test_drained_face_loads_only_the_water_there()
  call end_tests()

contains

  !> The reference itself: on 40 intervals the free surface at x = 0.25, 0.5, 0.75 and
  !> 0.9 m is 0.916, 0.795, 0.633, 0.503 m (scripts/dam_seepage.py: 0.9163, 0.7954,
  !> 0.6330, 0.5030 on 40 intervals, the same to 0.002 on 80 and 160), above Dupuit's
  !> parabola (0.866, 0.707, 0.5, 0.316 m), and it meets the reservoir at 1 m.
  subroutine test_reference_free_surface()
    real(wp) :: w(0:nref, 0:nref), h(0:nref)
    real(wp), parameter :: want(4) = [0.9163_wp, 0.7954_wp, 0.6330_wp, 0.5030_wp]
    real(wp), parameter :: at(4) = [0.25_wp, 0.5_wp, 0.75_wp, 0.9_wp]
    integer :: m
    call begin_test('reference_free_surface')
    call baiocchi(w, h)
    do m = 1, 4
      call check(abs(surface_at(h, at(m)) - want(m)) < 2.0e-3_wp, &
                 say('h(x) at x (m) =', at(m), surface_at(h, at(m)), want(m)))
    end do
    call check(abs(h(0) - 1.0_wp) < 1.0e-9_wp, say('h(x) at x (m) =', 0.0_wp, h(0), 1.0_wp))
  end subroutine test_reference_free_surface

  !> The dam of 10 x 12 cells of 0.1 m with the scene's choices (linear grid functions with
  !> the fields reconstructed at one Gauss point per cell, 2 x 2 points per cell and phase,
  !> flip 0.9, cell smoothing of the pore pressure, no tension in the water) from the
  !> saturated start to 6 s, counting the fluid points at 4 s on the way. Measured (1 and
  !> 2 ranks alike): free surface (the highest water point of each column of cells plus a
  !> quarter cell) minus the reference at the column's centre 0.021 mean and 0.084 largest;
  !> pore pressure of the water points more than a cell below the reference surface minus
  !> the reference, RMS 0.076 of rho_f g H; 339 and 343 fluid points at 4 and 6 s (400 at
  !> the start). Bounds: surface mean 0.04 (1.9 times) and largest 0.13 (+54 %), pressure
  !> 0.11 (+45 %), the count within 10 of its value at 4 s.
  subroutine test_dam_reaches_the_steady_free_surface()
    type(simulation_t) :: sim
    real(wp) :: w(0:nref, 0:nref), h(0:nref), err(ncol), rms, nf4, nf6
    call begin_test('dam_reaches_the_steady_free_surface')
    call baiocchi(w, h)
    call run_dam(4.0_wp, .true., sim)
    nf4 = fluid_count(sim)
    ! the same run on to 6 s (its step at 4 s shortened to end there)
    sim%cfg%t_end = 6.0_wp
    call sim%run()
    nf6 = fluid_count(sim)
    call surface_and_pressure(sim, w, h, err, rms)
    call sim%free()
    call check(abs(sum(err)/ncol) < 0.04_wp, say('free surface - reference, mean (m), t =', &
                                                  6.0_wp, sum(err)/ncol, 0.04_wp))
    call check(maxval(abs(err)) < 0.13_wp, say('free surface - reference, largest (m), t =', &
                                                6.0_wp, maxval(abs(err)), 0.13_wp))
    call check(rms < 0.11_wp, say('pore pressure - reference, RMS / (rho_f g H), t =', 6.0_wp, rms, 0.11_wp))
    call check(abs(nf6 - nf4) <= 10.0_wp, say('fluid points against those at 4 s, t =', 6.0_wp, nf6, nf4))
  end subroutine test_dam_reaches_the_steady_free_surface

  !> The pore pressure of a drained face acts only where the water is (doc/theory.md 6.4,
  !> eq. 6.4a): the dam of test_dam_reaches_the_steady_free_surface with quadratic
  !> B-splines, whose nodes beyond the reservoir face the inflowing water leaves behind.
  !> Measured at 6 s (1 and 2 ranks alike): energy balance error 0.091, free surface 0.017
  !> mean and 0.115 largest (at the seepage face), pressure RMS 0.158. With the face load
  !> on those nodes the balance error was 1.0 (the books took 1e27 J of work on nodes of
  !> 1e-10 kg in the 0.05 m dam). Bounds: balance error 0.15; surface mean 0.035 and
  !> largest 0.17 (twice the mean; the largest +48 %), pressure 0.21 (+33 %).
  subroutine test_drained_face_loads_only_the_water_there()
    type(simulation_t) :: sim
    real(wp) :: w(0:nref, 0:nref), h(0:nref), err(ncol), rms, bal
    call begin_test('drained_face_loads_only_the_water_there')
    call baiocchi(w, h)
    call run_dam(6.0_wp, .false., sim)
    call surface_and_pressure(sim, w, h, err, rms)
    bal = sim%mon%balance
    call sim%free()
    call check(bal < 0.15_wp, say('energy balance error, t =', 6.0_wp, bal, 0.15_wp))
    call check(abs(sum(err)/ncol) < 0.035_wp, say('free surface - reference, mean (m), t =', &
                                                   6.0_wp, sum(err)/ncol, 0.035_wp))
    call check(maxval(abs(err)) < 0.17_wp, say('free surface - reference, largest (m), t =', &
                                                6.0_wp, maxval(abs(err)), 0.17_wp))
    call check(rms < 0.21_wp, say('pore pressure - reference, RMS / (rho_f g H), t =', 6.0_wp, rms, 0.21_wp))
  end subroutine test_drained_face_loads_only_the_water_there

  !> The dam run to t_end (sim left for the caller to read and free): with gauss the
  !> scene's grid functions (linear, fields at one Gauss point per cell), else quadratic
  !> B-splines.
  subroutine run_dam(t_end, gauss, sim)
    real(wp), intent(in) :: t_end
    logical, intent(in) :: gauss
    type(simulation_t), intent(inout) :: sim
    type(config_t) :: cfg
    cfg = grid_scene('dam', [ncol, 12], [1.0_wp, 1.2_wp], t_end, gravity=[0.0_wp, -9.81_wp])
    cfg%drag = 'implicit'
    if (gauss) then
      cfg%kernel = 'linear'
      cfg%quadrature = 'gauss'
      cfg%gauss_points = 1
      cfg%field_kernel = 'linear'
      cfg%field_radius = 0.75_wp
    else
      cfg%kernel = 'quadratic'
    end if
    cfg%flip = 0.9_wp
    cfg%cavitation_pressure = 0.0_wp
    cfg%pressure_smoothing = 'cell'
    allocate (cfg%materials(2), cfg%regions(1), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2650.0_wp, &
                                      youngs_modulus=1.0e8_wp, poisson_ratio=0.3_wp, conductivity=0.1_wp)
    cfg%materials(2) = material_cfg_t(id=2, model='fluid', density=1000.0_wp, bulk_modulus=3.0e7_wp)
    cfg%regions(1)%lo = 0.0_wp
    cfg%regions(1)%hi = [1.0_wp, 1.0_wp, 1.0_wp]
    cfg%regions(1)%material = 1
    cfg%regions(1)%phase = 'saturated'
    cfg%regions(1)%fluid_material = 2
    cfg%regions(1)%porosity = 0.3_wp
    cfg%regions(1)%geostatic = .true.
    call resolve_geostatic(cfg)
    cfg%bc(1:3) = [bc_roller, bc_roller, bc_fixed]
    cfg%fluid_bc(1:2) = fbc_drained
    cfg%pore_pressure(1) = rho_g
    cfg%pore_pressure_gradient(2, 1) = -rho_g
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
  end subroutine run_dam

  real(wp) function fluid_count(sim) result(nf)
    type(simulation_t), intent(in) :: sim
    nf = real(sim%phase(2)%pts%n, wp)
    call MPI_Allreduce(MPI_IN_PLACE, nf, 1, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD)
  end function fluid_count

  !> err(c): the highest water point of column c plus a quarter cell, minus the reference
  !> surface at the column's centre; rms: the pore pressure of the water points more
  !> than a cell below the reference surface minus the reference p = -rho_f g dw/dy
  !> (bilinear in the reference grid), RMS over those points in rho_f g H.
  subroutine surface_and_pressure(sim, w, h, err, rms)
    type(simulation_t), intent(in) :: sim
    real(wp), intent(in) :: w(0:nref, 0:nref), h(0:nref)
    real(wp), intent(out) :: err(ncol), rms
    real(wp) :: top(ncol), acc(2), dx, x, y, pref
    integer :: p, c
    dx = 1.0_wp/ncol
    top = 0.0_wp
    acc = 0.0_wp
    associate (f => sim%phase(2)%pts)
      do p = 1, f%n
        x = f%x(1, p)
        y = f%x(2, p)
        c = min(ncol, max(1, int(x/dx) + 1))
        top(c) = max(top(c), y)
        if (y >= surface_at(h, x) - dx) cycle
        pref = reference_pressure(w, x, y)
        acc(1) = acc(1) + ((f%pressure(p) - pref)/rho_g)**2
        acc(2) = acc(2) + 1.0_wp
      end do
    end associate
    call MPI_Allreduce(MPI_IN_PLACE, top, ncol, MPI_DOUBLE_PRECISION, MPI_MAX, MPI_COMM_WORLD)
    call MPI_Allreduce(MPI_IN_PLACE, acc, 2, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD)
    do c = 1, ncol
      err(c) = top(c) + 0.25_wp*dx - surface_at(h, (c - 0.5_wp)*dx)
    end do
    rms = sqrt(acc(1)/acc(2))
  end subroutine surface_and_pressure

  !> Baiocchi's w(x, y) = int_y^h (phi - t) dt of the dam (L = H = 1 m, no tailwater) on
  !> nref x nref intervals: w >= 0, -lap w + 1 >= 0, w (-lap w + 1) = 0, w = (1 - y)^2 / 2
  !> at x = 0, 0 at x = 1 and at the top, (1 - x) / 2 on the base; projected SOR (red-black,
  !> relaxation 1.9) to changes below 1e-12. h(i): the free surface at x_i, where sqrt(w)
  !> reaches 0 below the highest wet node (w ~ (h - y)^2 near the surface).
  !> Neither step rests on an exact zero that round-off can move: 1 - y and 1 - x are
  !> taken from the node's distance to the top and the outflow face in intervals, so the
  !> top row and the face start at 0 in any build (1 - j d contracted into a fused
  !> multiply-add is -5.6e-17 at j = nref, and w there 3e-33 > 0 made the top wet); and a
  !> node counts as wet where w exceeds wet_floor times the largest w, far above the
  !> round-off of w and the 1e-12 the iteration stops at, far below the w of the highest
  !> wet node of any column (doc/verification.md, "Seepage through a rectangular dam").
  subroutine baiocchi(w, h)
    real(wp), intent(out) :: w(0:nref, 0:nref), h(0:nref)
    real(wp), parameter :: wet_floor = 1.0e-9_wp
    real(wp) :: d, change, gs, new, s0, s1, wet
    integer :: i, j, it, colour, jt
    d = 1.0_wp/nref
    do j = 0, nref
      do i = 0, nref
        w(i, j) = 0.5_wp*((nref - j)*d)**2*((nref - i)*d)
      end do
    end do
    do it = 1, 200000
      change = 0.0_wp
      do colour = 0, 1
        do j = 1, nref - 1
          do i = 1, nref - 1
            if (mod(i + j, 2) /= colour) cycle
            gs = 0.25_wp*(w(i + 1, j) + w(i - 1, j) + w(i, j + 1) + w(i, j - 1) - d*d)
            new = max(0.0_wp, w(i, j) + 1.9_wp*(gs - w(i, j)))
            change = max(change, abs(new - w(i, j)))
            w(i, j) = new
          end do
        end do
      end do
      if (change < 1.0e-12_wp) exit
    end do
    wet = wet_floor*maxval(w)
    do i = 0, nref
      h(i) = 0.0_wp
      jt = -1
      do j = 0, nref
        if (w(i, j) > wet) jt = j
      end do
      if (jt < 0) cycle
      h(i) = jt*d
      if (jt >= 1) then
        if (w(i, jt - 1) > w(i, jt)) then
          s1 = sqrt(w(i, jt))
          s0 = sqrt(w(i, jt - 1))
          h(i) = jt*d + d*s1/(s0 - s1)
        end if
      end if
    end do
  end subroutine baiocchi

  !> The reference free surface at x, linear between the reference nodes.
  real(wp) function surface_at(h, x) result(y)
    real(wp), intent(in) :: h(0:nref), x
    real(wp) :: s
    integer :: i
    s = min(real(nref, wp), max(0.0_wp, x*nref))
    i = min(nref - 1, int(s))
    y = h(i) + (s - i)*(h(i + 1) - h(i))
  end function surface_at

  !> The reference pore pressure -rho_f g dw/dy at (x, y), bilinear from the nodal
  !> central differences (one-sided at the base and top).
  real(wp) function reference_pressure(w, x, y) result(p)
    real(wp), intent(in) :: w(0:nref, 0:nref), x, y
    real(wp) :: sx, sy, g(0:1, 0:1)
    integer :: i, j, a, b, jb
    sx = min(real(nref, wp), max(0.0_wp, x*nref))
    sy = min(real(nref, wp), max(0.0_wp, y*nref))
    i = min(nref - 1, int(sx))
    j = min(nref - 1, int(sy))
    do b = 0, 1
      do a = 0, 1
        jb = j + b
        if (jb == 0) then
          g(a, b) = (w(i + a, 1) - w(i + a, 0))*nref
        else if (jb == nref) then
          g(a, b) = (w(i + a, nref) - w(i + a, nref - 1))*nref
        else
          g(a, b) = (w(i + a, jb + 1) - w(i + a, jb - 1))*0.5_wp*nref
        end if
      end do
    end do
    sx = sx - i
    sy = sy - j
    p = -rho_g*((1.0_wp - sx)*(1.0_wp - sy)*g(0, 0) + sx*(1.0_wp - sy)*g(1, 0) + &
                (1.0_wp - sx)*sy*g(0, 1) + sx*sy*g(1, 1))
  end function reference_pressure

  !> The line of a check: name at a (time or place), got against the bound or value.
  function say(what, at, got, ref) result(s)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: at, got, ref
    character(len=200) :: s
    write (s, '(a, " ", f6.3, ": ", es11.4, " against ", es11.4)') what, at, got, ref
  end function say

end program test_dam_seepage
