!> The saturated 1D column shaken along its axis at its base (doc/theory.md 9.2, "Base motion";
!> doc/verification.md, "Saturated column shaken vertically"): the Laplace-domain reference
!> biot_column_base_solve checked apart from the code (the undrained limit against
!> d'Alembert's sum, a coupled column against a fine finite-difference integration of the
!> same 1D equations written here), then the code's column against it; and the energy balance
!> of the 2D saturated column shaken at its base (doc/verification.md, "Energy of the shaken
!> saturated column"). Every bound is a measured error (debug build) times a stated margin.
program test_biot_base
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, motion_series_t, bc_fixed, bc_free, bc_roller, &
                          fbc_impermeable, fbc_drained
  use dpmpm_input, only: read_input
  use dpmpm_motion, only: motion_from_samples
  use dpmpm_simulation, only: simulation_t
  use dpmpm_biot_column, only: biot_column_t, biot_column_base_solve, biot_wave_speeds, biot_drag
  use dpmpm_assert, only: begin_test, check, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  real(wp), parameter :: pi = acos(-1.0_wp)
  !> The base record: a Ricker pulse of velocity, peak frequency f0, centred at t0, sampled
  !> every dtb to t_rec (at rest before and after: its first and last samples set to 0, where
  !> the pulse is 1e-8 of its peak).
  real(wp), parameter :: f0 = 20.0_wp, t0 = 0.075_wp, amp = 0.01_wp, dtb = 1.0e-4_wp, t_rec = 0.15_wp
  !> Times compared: every 5 ms to t_end.
  real(wp), parameter :: t_end = 0.25_wp, t_out = 5.0e-3_wp
  integer, parameter :: nout = 50
  !> inputs/tied_saturated_2d.nml (the argument)
  character(len=512) :: scene
  !> Frequencies of the inversion, without the Lanczos factors (the record has no jumps, and
  !> the factors would damp its 60 Hz by 3.5e-4 with 2^12): 2^12, up to 4 kHz; what is left is
  !> the inversion's error at the kinks of the piecewise linear record, 1e-5 of the peak
  !> (test a; 3.9e-6 with 2^14).
  integer, parameter :: NFREQ = 2**12
  real(wp), parameter :: SLOW_PART = 0.3_wp
  !> Bounds of the shaken column's energy balance (test d)
  real(wp), parameter :: BAL_TIED = 2.4e-3_wp, DRIFT_TIED = 2.4e-3_wp, BAL_ROLLER = 4.0e-4_wp, DRIFT_ROLLER = 2.3e-4_wp
  call start_tests()
  call get_command_argument(1, scene)
  call test_base_undrained_limit_is_dalembert()
  call test_base_against_finite_differences()
  call test_column_shaken_vertically()
  call test_shaken_column_energy_balance()
  call end_tests()

contains

  !> The column of the tests: W4 of doc/theory.md 9.1 with conductivity k (soft water, so that
  !> the fast wave, 220 m/s, is resolved by a grid of 0.1-0.2 m at the pulse's frequencies).
  !> With k = 1e-2 m/s the drag coefficient is 1.6e5 kg/(m^3 s) against n rho_f omega = 5e4 at
  !> 20 Hz: the phases move together to a few per cent, and the slow wave diffuses in from the
  !> drained top (c_v = 16 m^2/s: 2 m in 0.25 s).
  function w4_column(k) result(col)
    real(wp), intent(in) :: k
    type(biot_column_t) :: col
    col = biot_column_t(length=10.0_wp, porosity=0.4_wp, rho_s=2600.0_wp, rho_f=1000.0_wp, &
                        e_c=20.0e6_wp, k_f=30.0e6_wp, conductivity=k)
  end function w4_column

  !> The record's samples (positive downwards, into the column).
  subroutine base_record(vb)
    real(wp), allocatable, intent(out) :: vb(:)
    integer :: i, nb
    real(wp) :: tau
    nb = nint(t_rec/dtb) + 1
    allocate (vb(nb))
    do i = 1, nb
      tau = real(i - 1, wp)*dtb - t0
      vb(i) = amp*(1.0_wp - 2.0_wp*(pi*f0*tau)**2)*exp(-(pi*f0*tau)**2)
    end do
    vb(1) = 0.0_wp
    vb(nb) = 0.0_wp
  end subroutine base_record

  !> The record at time t as the code takes it: linear between samples, 0 before, the last
  !> sample after.
  pure real(wp) function base_at(vb, t) result(v)
    real(wp), intent(in) :: vb(:), t
    integer :: i
    real(wp) :: u
    v = 0.0_wp
    if (t <= 0.0_wp) return
    u = t/dtb
    i = int(u)
    if (i + 2 > size(vb)) then
      v = vb(size(vb))
      return
    end if
    u = u - real(i, wp)
    v = (1.0_wp - u)*vb(i + 1) + u*vb(i + 2)
  end function base_at

  !> The reference at the output times j t_out (j = 1 .. nout) and depths z.
  subroutine reference(col, z, p, sig, vs, vf)
    type(biot_column_t), intent(in) :: col
    real(wp), intent(in) :: z(:)
    real(wp), allocatable, intent(out) :: p(:, :), sig(:, :), vs(:, :), vf(:, :)
    real(wp), allocatable :: vb(:)
    real(wp) :: times(nout)
    integer :: j
    call base_record(vb)
    times = [(real(j, wp)*t_out, j=1, nout)]
    allocate (p(size(z), nout), sig(size(z), nout), vs(size(z), nout), vf(size(z), nout))
    call biot_column_base_solve(col, size(vb), dtb, vb, t_end, size(z), z, nout, times, p, sig, vs, vf, &
                                window=.false., nfreq=NFREQ)
  end subroutine reference

  !> (a) The undrained limit (k = 1e-12 m/s: the drag couples the phases at every frequency of
  !> the pulse, and the drained top's boundary layer is sqrt(c_v t) = 2e-5 m thin): one elastic
  !> column of modulus E_c + M and density rho_sat on a moving base under a free top, whose
  !> velocity is d'Alembert's sum v(z,t) = sum_k (-1)^k [V_b(t - ((2k+1)L - z)/c_u) +
  !> V_b(t - ((2k+1)L + z)/c_u)]; and p = -(M/E_c) sigma' (both from the same volume change).
  !> At the base itself the reference's velocity must be V_b (exact in the Laplace domain):
  !> what is left there is the inversion's error at the kinks of the piecewise linear record.
  !> Measured (largest over 50 times at z = 0, 2.5, 5, 8, 10 m, relative to the peaks; 2^12
  !> frequencies): v_s 9.9e-6 (the same as at the base: with 2^14, 3.9e-6 at both),
  !> v_f - v_s 1.7e-11, p + (M/E_c) sigma' 1.7e-6 (at the base; 8e-12 elsewhere). Bounds:
  !> 1.5e-5, 1e-10, 3e-6.
  subroutine test_base_undrained_limit_is_dalembert()
    type(biot_column_t) :: col
    real(wp), allocatable :: p(:, :), sig(:, :), vs(:, :), vf(:, :), vb(:)
    real(wp) :: z(5), c_u, c_s, t, ref, err_v, err_w, err_p, err_b, vpk, ppk, m
    integer :: i, j, k
    call begin_test('base_undrained_limit_is_dalembert')
    col = w4_column(1.0e-12_wp)
    call biot_wave_speeds(col, c_u, c_s)
    m = col%k_f/col%porosity
    z = [0.0_wp, 2.5_wp, 5.0_wp, 8.0_wp, 10.0_wp]
    call reference(col, z, p, sig, vs, vf)
    call base_record(vb)
    vpk = maxval(abs(vs))
    ppk = maxval(abs(p))
    err_v = 0.0_wp; err_w = 0.0_wp; err_p = 0.0_wp; err_b = 0.0_wp
    do j = 1, nout
      t = real(j, wp)*t_out
      do i = 1, size(z)
        ref = 0.0_wp
        do k = 0, 20
          ref = ref + (-1.0_wp)**k*(base_at(vb, t - ((2*k + 1)*col%length - z(i))/c_u) + &
                                    base_at(vb, t - ((2*k + 1)*col%length + z(i))/c_u))
        end do
        err_v = max(err_v, abs(vs(i, j) - ref)/vpk)
        if (i == size(z)) err_b = max(err_b, abs(vs(i, j) - base_at(vb, t))/vpk)
        err_w = max(err_w, abs(vf(i, j) - vs(i, j))/vpk)
        err_p = max(err_p, abs(p(i, j) + m/col%e_c*sig(i, j))/ppk)
      end do
    end do
    print '(a,4es10.2,a,2es10.2)', '  undrained: v_s, v_f - v_s, p + M/E_c sigma'', v_s(L) - V_b: ', &
      err_v, err_w, err_p, err_b, '; peaks v, p: ', vpk, ppk
    call check(vpk > 0.5_wp*amp, 'the pulse reaches the column')
    call check(err_v < 1.5e-5_wp, 'v_s = d''Alembert''s sum')
    call check(err_b < 1.5e-5_wp, 'v_s = V_b at the base')
    call check(err_w < 1.0e-10_wp, 'v_f = v_s')
    call check(err_p < 3.0e-6_wp, 'p = -(M/E_c) sigma''')
  end subroutine test_base_undrained_limit_is_dalembert

  !> (b) A coupled column (k = 1e-2 m/s) against a finite-difference integration of the 1D
  !> equations (2.7) on 500 and 1000 cells (fd_column): the differences fall by 4 with the
  !> cell (second order), so they are the integration's error, and the finer one bounds the
  !> reference's. Measured (largest over 50 times at z = 0, 2.5, 5, 8 m, relative to each
  !> field's peak): 500 cells v_s 1.02e-4, v_f 9.65e-5, p 9.70e-5; 1000 cells 2.54e-5,
  !> 2.40e-5, 2.42e-5 (ratios 4.0). Bounds on 1000 cells: 3.7e-5 (1.45x); ratios above 3.5.
  subroutine test_base_against_finite_differences()
    type(biot_column_t) :: col
    real(wp), allocatable :: p(:, :), sig(:, :), vs(:, :), vf(:, :)
    real(wp) :: z(4), e1(3), e2(3)
    integer :: i
    call begin_test('base_against_finite_differences')
    col = w4_column(1.0e-2_wp)
    z = [0.0_wp, 2.5_wp, 5.0_wp, 8.0_wp]
    call reference(col, z, p, sig, vs, vf)
    call fd_errors(col, 500, z, p, vs, vf, e1)
    call fd_errors(col, 1000, z, p, vs, vf, e2)
    print '(a,3es10.2,a,3es10.2)', '  finite differences, v_s v_f p: 500 cells', e1, '; 1000 cells', e2
    do i = 1, 3
      call check(e2(i) < 3.7e-5_wp, 'the reference against 1000 cells of finite differences')
      call check(e1(i) > 3.5_wp*e2(i), 'second order: the difference is the integration''s')
    end do
  end subroutine test_base_against_finite_differences

  !> Largest differences of fd_column on nc cells from the reference p, vs, vf (depths z,
  !> the output times), relative to each field's peak: e = (v_s, v_f, p).
  subroutine fd_errors(col, nc, z, p, vs, vf, e)
    type(biot_column_t), intent(in) :: col
    integer, intent(in) :: nc
    real(wp), intent(in) :: z(:), p(:, :), vs(:, :), vf(:, :)
    real(wp), intent(out) :: e(3)
    real(wp), allocatable :: ps(:, :), vss(:, :), vfs(:, :)
    call fd_column(col, nc, z, ps, vss, vfs)
    e(1) = maxval(abs(vss - vs))/maxval(abs(vs))
    e(2) = maxval(abs(vfs - vf))/maxval(abs(vf))
    e(3) = maxval(abs(ps - p))/maxval(abs(p))
  end subroutine fd_errors

  !> Finite differences of (2.7) on nc cells, z down from the top: velocities at the nodes
  !> z_i = i h (i = nc the base, given), sigma' and p at the cell centres, staggered in time
  !> (the velocities half a step behind the stresses: leapfrog), the drag by the trapezoid
  !> rule (a 2 x 2 solve per node), the top node a half cell with sigma' = p = 0 beyond it.
  !> Fields at depths z (linear between nodes or centres) at the output times (velocities
  !> as the mean of the two half steps around them).
  subroutine fd_column(col, nc, z, pz, vsz, vfz)
    type(biot_column_t), intent(in) :: col
    integer, intent(in) :: nc
    real(wp), intent(in) :: z(:)
    real(wp), allocatable, intent(out) :: pz(:, :), vsz(:, :), vfz(:, :)
    real(wp), allocatable :: vs(:), vf(:), sig(:), p(:), vs_old(:), vf_old(:), vb(:)
    real(wp) :: h, dt, c_u, c_s, nf, ns, m, ms, mf, q, w, e, a11, a12, a22, det, r1, r2, fs, ff
    real(wp) :: dvs, dvf, sl, pl, wt
    integer :: nsub, k, kout, i, c, iz
    logical :: pending
    call base_record(vb)
    nf = col%porosity
    ns = 1.0_wp - nf
    m = col%k_f/nf
    ms = ns*col%rho_s
    mf = nf*col%rho_f
    q = biot_drag(col)
    h = col%length/real(nc, wp)
    call biot_wave_speeds(col, c_u, c_s)
    nsub = ceiling(t_out/(0.5_wp*h/c_u))
    dt = t_out/real(nsub, wp)
    allocate (vs(0:nc), vf(0:nc), sig(nc), p(nc), vs_old(0:nc), vf_old(0:nc))
    allocate (pz(size(z), nout), vsz(size(z), nout), vfz(size(z), nout))
    vs = 0.0_wp; vf = 0.0_wp; sig = 0.0_wp; p = 0.0_wp
    kout = 0
    pending = .false.
    ! (one step beyond the last output time: its velocities are the mean of the half steps
    ! around it)
    do k = 1, nsub*nout + 1
      ! velocities from (k - 3/2) dt to (k - 1/2) dt
      do i = 0, nc - 1
        wt = merge(0.5_wp, 1.0_wp, i == 0)
        sl = 0.0_wp; pl = 0.0_wp
        if (i > 0) then
          sl = sig(i); pl = p(i)
        end if
        fs = ((sig(i + 1) - sl) - ns*(p(i + 1) - pl))/(wt*h)
        ff = -nf*(p(i + 1) - pl)/(wt*h)
        w = vf(i) - vs(i)
        e = 0.5_wp*dt*q
        a11 = ms + e; a12 = -e; a22 = mf + e
        r1 = dt*(fs + q*w)
        r2 = dt*(ff - q*w)
        det = a11*a22 - a12*a12
        dvs = (a22*r1 - a12*r2)/det
        dvf = (a11*r2 - a12*r1)/det
        vs(i) = vs(i) + dvs
        vf(i) = vf(i) + dvf
      end do
      vs(nc) = base_at(vb, (real(k, wp) - 0.5_wp)*dt)
      vf(nc) = vs(nc)
      if (pending) then
        do iz = 1, size(z)
          vsz(iz, kout) = at_node(0.5_wp*(vs + vs_old), h, z(iz))
          vfz(iz, kout) = at_node(0.5_wp*(vf + vf_old), h, z(iz))
        end do
        pending = .false.
      end if
      if (k > nsub*nout) exit
      ! stresses from (k - 1) dt to k dt
      do c = 1, nc
        sig(c) = sig(c) + dt*col%e_c*(vs(c) - vs(c - 1))/h
        p(c) = p(c) - dt*m*(ns*(vs(c) - vs(c - 1)) + nf*(vf(c) - vf(c - 1)))/h
      end do
      if (mod(k, nsub) == 0) then
        kout = kout + 1
        do iz = 1, size(z)
          pz(iz, kout) = at_centre(p, h, z(iz))
        end do
        vs_old = vs
        vf_old = vf
        pending = .true.
      end if
    end do
  end subroutine fd_column

  !> f at depth zz from its values at the nodes i h (i = 0 ..), linear between them.
  pure real(wp) function at_node(f, h, zz)
    real(wp), intent(in) :: f(0:), h, zz
    integer :: j
    real(wp) :: u
    j = min(int(zz/h), size(f) - 2)
    u = zz/h - real(j, wp)
    at_node = (1.0_wp - u)*f(j) + u*f(j + 1)
  end function at_node

  !> f at depth zz from its values at the cell centres (c - 1/2) h (c = 1 ..), linear between
  !> them, and between 0 at the top (the drained top's p) and the first centre.
  pure real(wp) function at_centre(f, h, zz)
    real(wp), intent(in) :: f(:), h, zz
    integer :: j
    real(wp) :: u
    if (zz <= 0.5_wp*h) then
      at_centre = f(1)*zz/(0.5_wp*h)
      return
    end if
    j = min(int(zz/h - 0.5_wp) + 1, size(f) - 1)
    u = zz/h - 0.5_wp - real(j - 1, wp)
    at_centre = (1.0_wp - u)*f(j) + u*f(j + 1)
  end function at_centre

  !> (c) The code's column shaken along its axis: 1D, base x- fixed and impermeable, moving
  !> with the record (x up: the code's base velocity is -V_b), top x+ free and drained, no
  !> gravity, implicit drag, 2 points per cell and phase placed regularly, 50 and 100 cells,
  !> k = 1e-2 m/s.
  !> At every output time each point's velocity and pore pressure against the reference at
  !> its depth: RMS over points and times relative to the field's peak; the surface (the
  !> mean of each phase's points in the top cell); the pore pressure of the top metre, where
  !> the drained top lets the slow wave diffuse in. Measured (debug; doc/verification.md,
  !> "Saturated column shaken vertically"), 50 / 100 cells: v_s 7.09e-3 / 1.50e-3, v_f
  !> 8.24e-3 / 2.04e-3, p 9.50e-3 / 4.73e-3, surface v_s 1.02e-2 / 2.14e-3, v_f 1.18e-2 /
  !> 2.92e-3, p of the top metre 1.05e-2 / 5.20e-3, where the slow wave's part of p (the
  !> drained top's reference against the undrained column's) is 2.64e-2: the code's error
  !> is 0.20 of it. Bounds on 100 cells: 1.3 times the measured, 0.3 of the slow part; the
  !> error falls by at least 1.6 from 50 to 100 cells (measured: by 4.0-4.8 for the
  !> velocities, 2.0 for p).
  subroutine test_column_shaken_vertically()
    real(wp) :: e50(7), e100(7)
    integer :: i
    call begin_test('column_shaken_vertically')
    call column_errors(50, e50)
    call column_errors(100, e100)
    print '(a,6es10.2)', '  code, 50 cells:  RMS v_s v_f p, surface v_s v_f, p top metre', e50(1:6)
    print '(a,6es10.2)', '  code, 100 cells: RMS v_s v_f p, surface v_s v_f, p top metre', e100(1:6)
    print '(a,es10.2)', '  the slow wave''s part of p in the top metre (undrained against drained top)', e100(7)
    call check(e100(1) < 2.0e-3_wp .and. e100(2) < 2.7e-3_wp, 'velocities of both phases (RMS)')
    call check(e100(3) < 6.2e-3_wp, 'pore pressure (RMS)')
    call check(e100(4) < 2.8e-3_wp .and. e100(5) < 3.8e-3_wp, 'surface velocities of both phases')
    call check(e100(6) < 6.8e-3_wp, 'pore pressure of the top metre')
    call check(e100(6) < SLOW_PART*e100(7), 'the code resolves the slow wave''s part of p')
    do i = 1, 6
      call check(1.6_wp*e100(i) < e50(i), 'the error falls with the cell')
    end do
  end subroutine test_column_shaken_vertically

  !> The code's column on nc cells against the reference: e = RMS over points and output times
  !> of v_s, v_f, p (relative to the peaks of the reference), RMS over the times of the
  !> mean velocity of each phase's points in the top cell, and of p over the points of the
  !> top metre (relative to the peak of p); e(7) the same of the reference of the undrained
  !> column (k = 1e-12 m/s) against the reference: the size of the slow wave's part there.
  subroutine column_errors(nc, e)
    integer, intent(in) :: nc
    real(wp), intent(out) :: e(7)
    type(biot_column_t) :: col
    type(config_t) :: cfg
    type(simulation_t) :: sim
    real(wp), allocatable :: vb(:), tb(:), z(:), p(:, :), sig(:, :), vs(:, :), vf(:, :)
    real(wp), allocatable :: sx(:, :), sv(:, :), ss(:, :), fx(:, :), fv(:, :), fs(:, :)
    integer(i8), allocatable :: ids(:), fids(:)
    real(wp) :: acc(7), pk(3), zs, top_ref(2), top(2)
    real(wp), allocatable :: pu(:, :), sigu(:, :), vsu(:, :), vfu(:, :)
    real(wp), allocatable :: pr(:)
    integer :: i, j, n, ntop(2), nmetre
    col = w4_column(1.0e-2_wp)
    cfg%name = 'base_column'
    cfg%ndim = 1
    cfg%ncells = [nc, 1, 1]
    cfg%length = [col%length, 1.0_wp, 1.0_wp]
    cfg%cfl = 0.5_wp
    cfg%drag = 'implicit'
    allocate (cfg%materials(2), cfg%regions(1))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=col%rho_s, &
                                      youngs_modulus=col%e_c, poisson_ratio=0.0_wp, &
                                      conductivity=col%conductivity)
    cfg%materials(2) = material_cfg_t(id=2, model='fluid', density=col%rho_f, bulk_modulus=col%k_f)
    cfg%regions(1)%lo = [0.0_wp, 0.0_wp, 0.0_wp]
    cfg%regions(1)%hi = [col%length, 1.0_wp, 1.0_wp]
    cfg%regions(1)%material = 1
    cfg%regions(1)%fluid_material = 2
    cfg%regions(1)%phase = 'saturated'
    cfg%regions(1)%porosity = col%porosity
    cfg%regions(1)%ppc = 2
    cfg%regions(1)%placement = 'regular'
    cfg%bc(1) = bc_fixed
    cfg%fluid_bc(1) = fbc_impermeable
    cfg%bc(2) = bc_free
    cfg%fluid_bc(2) = fbc_drained
    cfg%motion_base = 'x-'
    call base_record(vb)
    tb = [(real(i - 1, wp)*dtb, i=1, size(vb))]
    call motion_from_samples('velocity', tb, -vb, 'none', cfg%motion(1))
    cfg%t_end = t_out
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    ! the points' depths (they move by 1e-4 m at most: the reference at the start's)
    call sim%gather_points(ids, sx, sv, ss)
    call sim%gather_points(fids, fx, fv, fs, fluid=.true.)
    n = size(sx, 2)
    z = [col%length - sx(1, :), col%length - fx(1, :)]
    call reference(col, z, p, sig, vs, vf)
    ! the undrained column's (k = 1e-12 m/s): what the slow wave adds is p - p_u
    call reference(w4_column(1.0e-12_wp), z, pu, sigu, vsu, vfu)
    pk = [maxval(abs(vs(1:n, :))), maxval(abs(vf(n + 1:, :))), maxval(abs(p(n + 1:, :)))]
    acc = 0.0_wp
    zs = col%length/real(nc, wp)
    do j = 1, nout
      sim%cfg%t_end = real(j, wp)*t_out
      call sim%run()
      call sim%gather_points(ids, sx, sv, ss)
      call sim%gather_points(fids, fx, fv, fs, fluid=.true.)
      ! the code's x is up: its velocities are -v
      acc(1) = acc(1) + sum((-sv(1, :) - vs(1:n, j))**2)/real(n, wp)
      acc(2) = acc(2) + sum((-fv(1, :) - vf(n + 1:, j))**2)/real(size(fx, 2), wp)
      pr = pressure_in_order(sim, fids)
      acc(3) = acc(3) + sum((pr - p(n + 1:, j))**2)/real(size(fx, 2), wp)
      nmetre = count(z(n + 1:) < 1.0_wp)
      acc(6) = acc(6) + sum((pr - p(n + 1:, j))**2, mask=z(n + 1:) < 1.0_wp)/real(nmetre, wp)
      acc(7) = acc(7) + sum((pu(n + 1:, j) - p(n + 1:, j))**2, mask=z(n + 1:) < 1.0_wp)/real(nmetre, wp)
      top = 0.0_wp; top_ref = 0.0_wp; ntop = 0
      do i = 1, n
        if (z(i) > zs) cycle
        top(1) = top(1) - sv(1, i); top_ref(1) = top_ref(1) + vs(i, j); ntop(1) = ntop(1) + 1
      end do
      do i = 1, size(fx, 2)
        if (z(n + i) > zs) cycle
        top(2) = top(2) - fv(1, i); top_ref(2) = top_ref(2) + vf(n + i, j); ntop(2) = ntop(2) + 1
      end do
      acc(4:5) = acc(4:5) + ((top - top_ref)/real(ntop, wp))**2
    end do
    call sim%free()
    e(1:3) = sqrt(acc(1:3)/real(nout, wp))/pk
    e(4:5) = sqrt(acc(4:5)/real(nout, wp))/pk(1:2)
    e(6:7) = sqrt(acc(6:7)/real(nout, wp))/pk(3)
  end subroutine column_errors

  !> The pore pressure of the fluid points of ids (one rank), in that order.
  function pressure_in_order(sim, ids) result(pr)
    type(simulation_t), intent(in) :: sim
    integer(i8), intent(in) :: ids(:)
    real(wp) :: pr(size(ids))
    integer :: i, k
    pr = huge(1.0_wp)
    do k = 1, sim%phase(2)%pts%n
      do i = 1, size(ids)
        if (ids(i) == sim%phase(2)%pts%id(k)) pr(i) = sim%phase(2)%pts%pressure(k)
      end do
    end do
  end function pressure_in_order

  !> (d) The energy balance of the saturated column of inputs/tied_saturated_2d.nml (geostatic,
  !> gravity) shaken by its 2 Hz record for 0.25 s: as shipped (tied sides, shaken across),
  !> and between roller sides shaken along the column. The monitor's balance error (doc/theory.md
  !> 8: |KE + stored + D - W - E_0| over the work done + initial energy + D) and the drift
  !> (largest change of KE + stored - W over the largest KE + stored). Before the base's
  !> bookkeeping was mended (doc/verification.md, "Energy of the shaken saturated column")
  !> they were 0.84 and 5.2 (tied, to 5 s) and 0.36 and 0.45 (rollers): the drag of pore water
  !> sliding along a held skeleton at the base's nodes was booked as dissipated, and gravity's
  !> work on the base's nodes moving up and down was not booked; at 0.25 s they were 0.67
  !> and 2.1 (tied) and 0.36 and 0.45 (rollers). Measured now (debug): 1.60e-3 and 1.61e-3
  !> (tied), 2.66e-4 and 1.54e-4 (rollers). Bounds: 1.5 times the measured.
  subroutine test_shaken_column_energy_balance()
    real(wp) :: bal(2), drift(2)
    call begin_test('shaken_column_energy_balance')
    call shaken_run(.false., bal(1), drift(1))
    call shaken_run(.true., bal(2), drift(2))
    print '(a,2es10.2,a,2es10.2)', '  shaken column: balance error, drift: tied, across', bal(1), drift(1), &
      '; rollers, along', bal(2), drift(2)
    call check(bal(1) < BAL_TIED .and. drift(1) < DRIFT_TIED, 'tied sides, shaken across')
    call check(bal(2) < BAL_ROLLER .and. drift(2) < DRIFT_ROLLER, 'roller sides, shaken along')
  end subroutine test_shaken_column_energy_balance

  !> The scene for 0.25 s, with roller sides and its record along the column (rollers), or as
  !> shipped: the monitor's balance error and the drift at the end.
  subroutine shaken_run(rollers, bal, drift)
    logical, intent(in) :: rollers
    real(wp), intent(out) :: bal, drift
    type(config_t) :: cfg
    type(simulation_t) :: sim
    integer :: st
    call read_input(trim(scene), MPI_COMM_WORLD, cfg, st)
    call check_equal_int(st, 0, 'the scene reads')
    cfg%t_end = 0.25_wp
    cfg%frame_interval = 0.0_wp
    if (rollers) then
      cfg%tied(1:2) = .false.
      cfg%bc(1:2) = bc_roller
      cfg%motion(2) = cfg%motion(1)
      cfg%motion(1) = motion_series_t()
    end if
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    bal = sim%mon%balance
    drift = sim%energy_drift
    call sim%free()
  end subroutine shaken_run

end program test_biot_base
