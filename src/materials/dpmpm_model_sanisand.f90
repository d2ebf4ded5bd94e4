!> SANISAND, the bounding-surface sand model of Dafalias & Manzari (2004), "Simple
!> plasticity sand model accounting for fabric change effects", J. Eng. Mech. 130(6),
!> 622-634: one set of constants for loose and dense sand at any pressure (the state
!> parameter psi), with a dilatancy that grows after dilation (the fabric tensor z), so
!> that loose sand contracts and liquefies under cyclic undrained shear. Compression is
!> positive inside this module: sigma = -stress, p = tr(sigma)/3, s = sigma - p I, the
!> stress ratio r = s/p, the strain increment deps = -dt D (tensor shears).
!>   yield surface   f = ||s - p alpha|| - sqrt(2/3) m p (a thin cone around the back-stress
!>                   ratio alpha), n = (r - alpha)/||r - alpha||, cos 3theta = sqrt(6) tr n^3;
!>   surfaces        alpha^c,b,d = sqrt(2/3) (g(theta, c) M {1, exp(-n_b psi), exp(n_d psi)}
!>                   - m) n with g = 2c/((1 + c) - (1 - c) cos 3theta), psi = e - e_c,
!>                   e_c = e_c0 - lambda_c (p/p_at)^xi;
!>   elasticity      G = G0 p_at (2.97 - e)^2/(1 + e) sqrt(p/p_at), K = 2(1 + nu)G/(3(1 - 2nu));
!>   hardening       dalpha = <L> (2/3) h (alpha^b - alpha), h = b0/((alpha - alpha_in):n),
!>                   b0 = G0 h0 (1 - c_h e)(p/p_at)^(-1/2), K_p = (2/3) p h (alpha^b - alpha):n;
!>   flow            deps^p = <L> R, R = B n - C (n^2 - I/3) + D I/3,
!>                   B = 1 + (3/2)(1 - c)/c g cos 3theta, C = 3 sqrt(3/2)(1 - c)/c g,
!>                   D = A_d (alpha^d - alpha):n, A_d = A0 (1 + <z:n>);
!>   fabric          dz = -c_z <-deps_v^p> (z_max n + z);
!>   loading index   L = (2G n:de - K N deps_v)/(K_p + 2G(B - C tr n^3) - K N D),
!>                   N = alpha:n + sqrt(2/3) m (the gradient of f is n - N I/3).
!> alpha_in, the back-stress ratio at the last load reversal, becomes alpha where a new
!> plastic loading starts with (alpha - alpha_in):n < 0; (alpha - alpha_in):n is taken at
!> least tiny_projection, so that h, infinite right at a reversal, stays finite.
!>
!> Integration (Sloan 1987; Sloan, Abbo & Sheng 2001): explicit, the elastic part and the
!> plastic part each by modified Euler with substeps whose size follows the estimated
!> relative error (tolerance integration_tolerance); a point on its yield surface that loads
!> goes straight to the plastic part, one inside (or unloading) takes the elastic trial and
!> the crossing of the yield surface by the Pegasus method on the elastic path; after each
!> plastic substep the point is put
!> back on the yield surface by moving alpha along n by f/p (the stress is kept; this
!> closes the drift exactly). An integration that needs more than max_substeps substeps,
!> or whose substep shrinks below min_fraction, fails: the caller stops the run naming the
!> point. The model is undefined at p <= 0: the moduli and the stress ratio are taken at
!> p >= pressure_floor, and a point whose p falls below pressure_floor in a substep is put
!> at p = pressure_floor with its stress ratio on the yield surface, r = alpha + sqrt(2/3)
!> m n (n of the substep's start): the sand has liquefied and carries no more than that
!> mean stress, and goes on shearing plastically from there.
!> State (dpmpm_model_table, 19 values): alpha (6), z (6), alpha_in (6), all deviatoric in
!> Voigt order xx yy zz yz xz xy with tensor shears, and the void ratio e, which follows
!> the volume: (1 + e) = (1 + e_n) J over a step.
module dpmpm_model_sanisand
  use dpmpm_kinds, only: wp
  use dpmpm_error, only: fatal
  use dpmpm_material_params, only: material_t
  use dpmpm_model_plastic, only: jaumann_strain
  implicit none
  private
  public :: sanisand_update, sanisand_integrate, sanisand_init_state, sanisand_moduli
  public :: sanisand_energy, sanisand_yield, sanisand_nstate, max_substeps

  !> State values per point: alpha, z, alpha_in (6 each) and e.
  integer, parameter :: sanisand_nstate = 19
  !> The most substeps of one strain increment before the integration is declared failed.
  integer, parameter :: max_substeps = 200000
  !> The smallest substep, as a fraction of the increment.
  real(wp), parameter :: min_fraction = 1.0e-12_wp
  !> |f| <= yield_tol p counts as on the yield surface.
  real(wp), parameter :: yield_tol = 1.0e-9_wp
  !> The least (alpha - alpha_in):n in h = b0/((alpha - alpha_in):n).
  real(wp), parameter :: tiny_projection = 1.0e-10_wp
  real(wp), parameter :: sqrt23 = 0.816496580927726_wp, sqrt6 = 2.449489742783178_wp
  real(wp), parameter :: sqrt32 = 1.224744871391589_wp
  !> How many passes (elastic part, crossing, plastic part) one increment may take.
  integer, parameter :: max_passes = 200
  !> What went wrong, by the code of sanisand_integrate.
  character(len=40), parameter :: failures(3) = [character(len=40) :: &
    'more substeps than max_substeps', 'a substep below 1e-12 of the increment', &
    'more passes than max_passes']

contains

  !> The update of stress_update (dpmpm_materials) for the points of material index m: the
  !> stress and the tensors alpha, z, alpha_in rotated with the spin (Jaumann), then
  !> sanisand_integrate of the strain increment dt D; the void ratio follows the volume.
  !> dissipation gains V times the plastic work sigma:deps^p of the step. A point whose
  !> integration fails stops the run through fatal (MPI_Abort) with its index and state.
  subroutine sanisand_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                             dissipation, plane)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    real(wp), intent(in) :: dt
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: vgrad(:, :)
    real(wp), intent(inout) :: stress(:, :), vol(:)
    real(wp), intent(in) :: vol0(:)
    real(wp), intent(inout), optional :: defgrad(:, :), state(:, :)
    real(wp), intent(inout), optional :: dissipation
    logical, intent(in), optional :: plane
    real(wp) :: sr(6), de(6), jac, st(sanisand_nstate), work, wsum, d6(6), j6
    character(len=2048) :: msg
    integer :: p, code, nsub, k
    logical :: flat
    flat = .false.
    if (present(plane)) flat = plane
    wsum = 0.0_wp
    if (present(dissipation)) wsum = dissipation
    do p = 1, n
      if (pmat(p) /= m) cycle
      call jaumann_strain(dt, vgrad(:, p), stress(:, p), flat, sr, de, jac)
      st = state(1:sanisand_nstate, p)
      ! the tensors of the state turn with the material, as the stress does
      do k = 0, 2
        call jaumann_strain(dt, vgrad(:, p), state(6*k + 1:6*k + 6, p), flat, &
                            st(6*k + 1:6*k + 6), d6, j6)
      end do
      call sanisand_integrate(mat, de, sr, st, code, work, nsub)
      if (code /= 0) then
        write (msg, '(a,i0,a,a,a,i0,a,6es24.16,a,19es24.16,a,6es24.16)') &
          'the SANISAND integration of point ', p, ' failed (', trim(failures(code)), ', ', &
          nsub, ' substeps); stress ', stress(:, p), ', state (alpha, z, alpha_in, e) ', &
          state(1:sanisand_nstate, p), ', strain increment ', de
        call fatal(trim(msg), 'sanisand_update')
      end if
      wsum = wsum + vol(p)*work
      stress(:, p) = sr
      st(19) = (1.0_wp + state(19, p))*jac - 1.0_wp
      state(1:sanisand_nstate, p) = st
      vol(p) = vol(p)*jac
    end do
    if (present(dissipation)) dissipation = wsum
  end subroutine sanisand_update

  !> The integration of one point over the strain increment deps (engineering shears,
  !> tension positive): stress (Voigt, tension positive) and st (alpha, z, alpha_in, e) at
  !> the start in, at the end out, except e, which the caller sets from the volume (e is
  !> taken along the increment as (1 + e_n) exp(-T deps_v) - 1 at fraction T). work: the
  !> plastic work sigma:deps^p per unit volume; nsub the substeps taken; code 0 on success,
  !> else why the integration failed (failures(code); stress and st are then those at the
  !> start).
  pure subroutine sanisand_integrate(mat, deps, stress, st, code, work, nsub)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: deps(6)
    real(wp), intent(inout) :: stress(6), st(:)
    integer, intent(out) :: code, nsub
    real(wp), intent(out) :: work
    real(wp) :: y(18), ytr(18), ain(6), dec(6), t, ta, tb, fa, fb, fy, e0, ymid(18), fm, tx
    real(wp) :: wdum
    integer :: pass, k
    logical :: left, onload
    code = 0
    nsub = 0
    work = 0.0_wp
    wdum = 0.0_wp
    tb = 1.0_wp
    fb = 0.0_wp
    fa = 0.0_wp
    e0 = st(19)
    y(1:6) = -stress
    y(7:18) = st(1:12)
    ain = st(13:18)
    ! compression positive, tensor shears
    dec(1:3) = -deps(1:3)
    dec(4:6) = -0.5_wp*deps(4:6)
    ! a point outside its yield surface at the start (the turn of stress and alpha with the
    ! spin is exact to first order only) is put back on it as after a plastic substep
    fy = sanisand_yield(mat, y)
    if (fy > yield_tol*pmean(y) .and. pmean(y) >= mat%sd_pmin) &
      y(7:12) = y(7:12) + (fy/pmean(y))*normal(mat, y)
    t = 0.0_wp
    do pass = 1, max_passes
      ! on the surface and loading: plastic from here (no elastic trial needed)
      fy = sanisand_yield(mat, y)
      onload = abs(fy) <= yield_tol*pmean(y)
      if (onload) onload = loads(mat, y, e_at(e0, dec, t), ain, dec)
      if (.not. onload) then
        ! the elastic trial of what is left of the increment
        ytr = y
        call march(mat, ytr, ain, e0, dec, t, 1.0_wp, .false., code, nsub, wdum, left, tx)
        if (code /= 0) exit
        if (sanisand_yield(mat, ytr) <= yield_tol*pmean(ytr)) then
          y = ytr
          t = 1.0_wp
          exit
        end if
        fy = sanisand_yield(mat, y)
        if (fy < -yield_tol*pmean(y)) then
          ! inside: the elastic path crosses the surface at ta in (t, 1)
          ta = t
          fa = fy
          tb = 1.0_wp
          fb = sanisand_yield(mat, ytr)
        else
          ! on the surface and unloading: the elastic path may cross the surface again
          ! later (the last of 32 samples inside before the first outside bracket it)
          ta = -1.0_wp
          if (.not. loads(mat, y, e_at(e0, dec, t), ain, dec)) then
            do k = 1, 32
              ymid = y
              call march(mat, ymid, ain, e0, dec, t, t + (1.0_wp - t)*k/32.0_wp, .false., code, &
                         nsub, wdum, left, tx)
              if (code /= 0) exit
              fm = sanisand_yield(mat, ymid)
              if (fm < -yield_tol*pmean(ymid)) then
                ta = t + (1.0_wp - t)*k/32.0_wp
                fa = fm
              else if (ta >= 0.0_wp) then
                tb = t + (1.0_wp - t)*k/32.0_wp
                fb = fm
                exit
              end if
            end do
            if (code /= 0) exit
            if (ta >= 0.0_wp .and. k > 32) then
              tb = 1.0_wp
              fb = sanisand_yield(mat, ytr)
            end if
            if (ta >= 0.0_wp) then
              ! restart the crossing from the last point inside
              call march(mat, y, ain, e0, dec, t, ta, .false., code, nsub, wdum, left, tx)
              if (code /= 0) exit
              t = ta
              fa = sanisand_yield(mat, y)
            end if
          end if
        end if
        if (ta >= 0.0_wp) then
          call crossing(mat, y, ain, e0, dec, t, tb, fa, fb, ta, code, nsub)
          if (code /= 0) exit
          t = ta
        end if
      end if
      ! a new plastic loading: alpha_in is the alpha of the last load reversal
      if (dot(y(7:12) - ain, normal(mat, y)) < 0.0_wp) ain = y(7:12)
      call march(mat, y, ain, e0, dec, t, 1.0_wp, .true., code, nsub, work, left, tx)
      t = tx
      if (code /= 0) exit
      if (.not. left) exit
    end do
    if (t < 1.0_wp .and. code == 0) code = 3
    if (code /= 0) return
    stress = -y(1:6)
    st(1:12) = y(7:18)
    st(13:18) = ain
  end subroutine sanisand_integrate

  !> The crossing of the yield surface on the elastic path from fraction t (state y, f = fa
  !> < 0 there) towards tb (f = fb > 0), by the Pegasus method; y and t come back at the
  !> crossing (|f| <= yield_tol p).
  pure subroutine crossing(mat, y, ain, e0, dec, t, tb, fa, fb, tx, code, nsub)
    type(material_t), intent(in) :: mat
    real(wp), intent(inout) :: y(18)
    real(wp), intent(in) :: ain(6), e0, dec(6), t
    real(wp), intent(in) :: tb, fa, fb
    real(wp), intent(out) :: tx
    integer, intent(inout) :: code, nsub
    real(wp) :: a0, a1, f0, f1, a, fx, yx(18), wdum, tend
    integer :: it
    logical :: left
    a0 = t
    a1 = tb
    f0 = fa
    f1 = fb
    a = a1
    yx = y
    wdum = 0.0_wp
    do it = 1, 100
      a = a1 - f1*(a1 - a0)/(f1 - f0)
      yx = y
      call march(mat, yx, ain, e0, dec, t, a, .false., code, nsub, wdum, left, tend)
      if (code /= 0) return
      fx = sanisand_yield(mat, yx)
      if (abs(fx) <= yield_tol*pmean(yx)) exit
      if (fx*f1 < 0.0_wp) then
        a0 = a1
        f0 = f1
      else
        f0 = f0*f1/(f1 + fx)
      end if
      a1 = a
      f1 = fx
    end do
    y = yx
    tx = a
  end subroutine crossing

  !> Integrate y = [sigma, alpha, z] from fraction ta to tb of the strain increment dec by
  !> modified Euler with error control: elastic (plastic false) or elasto-plastic from a
  !> point on the yield surface; tend the fraction reached. A plastic march stops early
  !> (left true) where an unloading substep has taken the point inside the surface.
  pure subroutine march(mat, y, ain, e0, dec, ta, tb, plastic, code, nsub, work, left, tend)
    type(material_t), intent(in) :: mat
    real(wp), intent(inout) :: y(18)
    real(wp), intent(in) :: ain(6), e0, dec(6)
    real(wp), intent(in) :: ta, tb
    real(wp), intent(out) :: tend
    logical, intent(in) :: plastic
    integer, intent(inout) :: code, nsub
    real(wp), intent(inout) :: work
    logical, intent(out) :: left
    real(wp) :: t, dtt, k1(18), k2(18), y1(18), yn(18), w1, w2, err, q, f, pn, nst(6)
    logical :: l1, l2, failed_before
    left = .false.
    t = ta
    tend = ta
    dtt = tb - ta
    failed_before = .false.
    do while (tb - t > min_fraction)
      if (nsub >= max_substeps .or. dtt < min_fraction) then
        code = merge(1, 2, nsub >= max_substeps)
        return
      end if
      dtt = min(dtt, tb - t)
      if (plastic) then
        f = sanisand_yield(mat, y)
        if (f < -yield_tol*pmean(y)) then
          left = .true.
          tend = t
          return
        end if
      end if
      nsub = nsub + 1
      call rates(mat, y, e_at(e0, dec, t), ain, dec*dtt, plastic, k1, l1, w1)
      y1 = y + k1
      call rates(mat, y1, e_at(e0, dec, t + dtt), ain, dec*dtt, plastic, k2, l2, w2)
      yn = y + 0.5_wp*(k1 + k2)
      err = max(norm(k2(1:6) - k1(1:6))/(2.0_wp*max(norm(yn(1:6)), mat%sd_pmin)), &
                norm(k2(7:12) - k1(7:12))/(2.0_wp*mat%sd_mc), &
                norm(k2(13:18) - k1(13:18))/(2.0_wp*max(mat%sd_zmax, 1.0_wp)))
      if (.not. (err <= mat%sd_tol)) then
        ! rejected: a smaller substep
        q = 0.1_wp
        if (err < huge(1.0_wp)) q = max(0.9_wp*sqrt(mat%sd_tol/err), 0.1_wp)
        dtt = q*dtt
        failed_before = .true.
        cycle
      end if
      nst = normal(mat, y)
      y = yn
      work = work + 0.5_wp*(w1 + w2)
      t = t + dtt
      pn = pmean(y)
      if (pn < mat%sd_pmin) then
        ! below the floor: p = pressure_floor at the stress ratio on the yield surface,
        ! r = alpha + sqrt(2/3) m n (n of the substep's start)
        y(1:6) = mat%sd_pmin*(y(7:12) + sqrt23*mat%sd_m*nst)
        y(1:3) = y(1:3) + mat%sd_pmin
      else if (plastic .and. (l1 .or. l2)) then
        ! back on the yield surface: alpha moves along n by f/p
        f = sanisand_yield(mat, y)
        if (abs(f) > yield_tol*pn) y(7:12) = y(7:12) + (f/pn)*normal(mat, y)
      end if
      q = 1.1_wp
      if (err > 0.0_wp) q = min(0.9_wp*sqrt(mat%sd_tol/err), 1.1_wp)
      if (failed_before) q = min(q, 1.0_wp)
      failed_before = .false.
      dtt = max(q, 0.1_wp)*dtt
    end do
    tend = tb
  end subroutine march

  !> The increments dy of y = [sigma, alpha, z] (compression positive) for the strain
  !> increment de (tensor, compression positive) at void ratio e: elastic, or, where plastic
  !> and the point loads (L > 0), elasto-plastic; loading tells which; w = sigma:deps^p.
  pure subroutine rates(mat, y, e, ain, de, plastic, dy, loading, w)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: y(18), e, ain(6), de(6)
    logical, intent(in) :: plastic
    real(wp), intent(out) :: dy(18), w
    logical, intent(out) :: loading
    real(wp) :: p, pact, s(6), al(6), z(6), n(6), n2(6), dev(6), dv, k, g, trn3, cos3, gth
    real(wp) :: psi, ab(6), ad(6), b0, h, kp, ad_amp, d, bb, cc, rdev(6), nn, num, den, lam
    dy = 0.0_wp
    w = 0.0_wp
    loading = .false.
    pact = pmean(y)
    p = max(pact, mat%sd_pmin)
    dv = de(1) + de(2) + de(3)
    dev = de
    dev(1:3) = dev(1:3) - dv/3.0_wp
    call sanisand_moduli(mat, p, e, k, g)
    dy(1:6) = 2.0_wp*g*dev
    dy(1:3) = dy(1:3) + k*dv
    if (.not. plastic) return
    s = y(1:6)
    s(1:3) = s(1:3) - pact
    al = y(7:12)
    z = y(13:18)
    n = s/p - al
    if (norm(n) <= tiny(1.0_wp)) return
    n = n/norm(n)
    n2 = square(n)
    trn3 = dot(n2, n)
    cos3 = max(-1.0_wp, min(1.0_wp, sqrt6*trn3))
    gth = 2.0_wp*mat%sd_c/((1.0_wp + mat%sd_c) - (1.0_wp - mat%sd_c)*cos3)
    psi = e - (mat%sd_ec0 - mat%sd_lc*(p/mat%sd_pat)**mat%sd_xi)
    ab = sqrt23*(gth*mat%sd_mc*exp(-mat%sd_nb*psi) - mat%sd_m)*n
    ad = sqrt23*(gth*mat%sd_mc*exp(mat%sd_nd*psi) - mat%sd_m)*n
    b0 = mat%sd_g0*mat%sd_h0*(1.0_wp - mat%sd_ch*e)/sqrt(p/mat%sd_pat)
    h = b0/max(dot(al - ain, n), tiny_projection)
    kp = 2.0_wp/3.0_wp*p*h*dot(ab - al, n)
    ad_amp = mat%sd_a0*(1.0_wp + max(dot(z, n), 0.0_wp))
    d = ad_amp*dot(ad - al, n)
    bb = 1.0_wp + 1.5_wp*(1.0_wp - mat%sd_c)/mat%sd_c*gth*cos3
    cc = 3.0_wp*sqrt32*(1.0_wp - mat%sd_c)/mat%sd_c*gth
    rdev = bb*n - cc*n2
    rdev(1:3) = rdev(1:3) + cc/3.0_wp
    nn = dot(al, n) + sqrt23*mat%sd_m
    num = 2.0_wp*g*dot(n, dev) - k*nn*dv
    den = kp + 2.0_wp*g*(bb - cc*trn3) - k*nn*d
    if (num <= 0.0_wp .or. den <= 0.0_wp) return
    lam = num/den
    loading = .true.
    dy(1:6) = dy(1:6) - lam*2.0_wp*g*rdev
    dy(1:3) = dy(1:3) - lam*k*d
    dy(7:12) = lam*2.0_wp/3.0_wp*h*(ab - al)
    dy(13:18) = -mat%sd_cz*max(-lam*d, 0.0_wp)*(mat%sd_zmax*n + z)
    w = lam*(dot(s, rdev) + pact*d)
  end subroutine rates

  !> Whether a point on the yield surface loads (L > 0) under the strain increment de.
  pure logical function loads(mat, y, e, ain, de)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: y(18), e, ain(6), de(6)
    real(wp) :: dy(18), w
    call rates(mat, y, e, ain, de, .true., dy, loads, w)
  end function loads

  !> The yield function f = ||s - p alpha|| - sqrt(2/3) m p of y = [sigma, alpha, ...]
  !> (compression positive; p at least pressure_floor).
  pure real(wp) function sanisand_yield(mat, y) result(f)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: y(:)
    real(wp) :: s(6), p
    p = pmean(y)
    s = y(1:6)
    s(1:3) = s(1:3) - p
    p = max(p, mat%sd_pmin)
    f = norm(s - p*y(7:12)) - sqrt23*mat%sd_m*p
  end function sanisand_yield

  !> n = (r - alpha)/||r - alpha|| of y = [sigma, alpha, ...] (zero if r = alpha; r at p at
  !> least pressure_floor).
  pure function normal(mat, y) result(n)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: y(:)
    real(wp) :: n(6), p, a
    p = pmean(y)
    n = y(1:6)
    n(1:3) = n(1:3) - p
    n = n/max(p, mat%sd_pmin) - y(7:12)
    a = norm(n)
    if (a > 0.0_wp) then
      n = n/a
    else
      n = 0.0_wp
    end if
  end function normal

  !> The void ratio at fraction t of the strain increment dec (compression positive).
  pure real(wp) function e_at(e0, dec, t)
    real(wp), intent(in) :: e0, dec(6), t
    e_at = (1.0_wp + e0)*exp(-t*(dec(1) + dec(2) + dec(3))) - 1.0_wp
  end function e_at

  !> p = tr(sigma)/3 of compression-positive Voigt components.
  pure real(wp) function pmean(y)
    real(wp), intent(in) :: y(:)
    pmean = (y(1) + y(2) + y(3))/3.0_wp
  end function pmean

  !> a:b of symmetric tensors in Voigt order with tensor shears.
  pure real(wp) function dot(a, b)
    real(wp), intent(in) :: a(6), b(6)
    dot = a(1)*b(1) + a(2)*b(2) + a(3)*b(3) + 2.0_wp*(a(4)*b(4) + a(5)*b(5) + a(6)*b(6))
  end function dot

  !> ||a|| = sqrt(a:a).
  pure real(wp) function norm(a)
    real(wp), intent(in) :: a(6)
    norm = sqrt(dot(a, a))
  end function norm

  !> The matrix product a a of a symmetric tensor (Voigt xx yy zz yz xz xy, tensor shears).
  pure function square(a) result(b)
    real(wp), intent(in) :: a(6)
    real(wp) :: b(6)
    b(1) = a(1)**2 + a(6)**2 + a(5)**2
    b(2) = a(6)**2 + a(2)**2 + a(4)**2
    b(3) = a(5)**2 + a(4)**2 + a(3)**2
    b(4) = a(6)*a(5) + a(2)*a(4) + a(4)*a(3)
    b(5) = a(1)*a(5) + a(6)*a(4) + a(5)*a(3)
    b(6) = a(1)*a(6) + a(6)*a(2) + a(5)*a(4)
  end function square

  !> The elastic moduli at mean effective stress p (compression positive; at least
  !> pressure_floor) and void ratio e: G = G0 p_at (2.97 - e)^2/(1 + e) sqrt(p/p_at),
  !> K = 2(1 + nu) G/(3(1 - 2 nu)).
  elemental subroutine sanisand_moduli(mat, p, e, k, g)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: p, e
    real(wp), intent(out), optional :: k, g
    real(wp) :: gg
    gg = mat%sd_g0*mat%sd_pat*(2.97_wp - e)**2/(1.0_wp + e)*sqrt(max(p, mat%sd_pmin)/mat%sd_pat)
    if (present(g)) g = gg
    if (present(k)) k = 2.0_wp*(1.0_wp + mat%poisson)/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))*gg
  end subroutine sanisand_moduli

  !> The initial state of the points of material index m from their initial (effective)
  !> stress: alpha = alpha_in = r = s/p (the yield surface centred on the stress; 0 at
  !> p <= pressure_floor), z = 0, e = void_ratio.
  subroutine sanisand_init_state(mat, m, n, pmat, stress, state)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: stress(:, :)
    real(wp), intent(inout) :: state(:, :)
    real(wp) :: p, s(6)
    integer :: k
    do k = 1, n
      if (pmat(k) /= m) cycle
      s = -stress(:, k)
      p = (s(1) + s(2) + s(3))/3.0_wp
      s(1:3) = s(1:3) - p
      state(1:sanisand_nstate, k) = 0.0_wp
      if (p > mat%sd_pmin) state(1:6, k) = s/p
      state(13:18, k) = state(1:6, k)
      state(19, k) = mat%sd_e0
    end do
  end subroutine sanisand_init_state

  !> Stored elastic energy of one point, approximated with the moduli at its stress:
  !> V (p^2/(2K) + q^2/(6G)).
  pure real(wp) function sanisand_energy(mat, s, e, vol) result(w)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: s(6), e, vol
    real(wp) :: p, q, d(6), k, g
    p = -(s(1) + s(2) + s(3))/3.0_wp
    d = s
    d(1:3) = d(1:3) + p
    q = sqrt(1.5_wp*dot(d, d))
    call sanisand_moduli(mat, p, e, k, g)
    w = vol*(p**2/(2.0_wp*k) + q**2/(6.0_wp*g))
  end function sanisand_energy

end module dpmpm_model_sanisand
