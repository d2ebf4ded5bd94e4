! Modified Cam-Clay as a UMAT: the example of a pressure-dependent, hardening UMAT with state
! variables (doc/input.md, "A user's UMAT"). Standalone: it uses nothing of dpmpm, and
! follows the equations of doc/theory.md 5.7 in the UMAT's own terms (Abaqus order 11 22 33
! 12 13 23, engineering shears in DSTRAN, tension positive), so that it reproduces dpmpm's
! built-in 'cam_clay' (tests/test_umat_cam_clay.f90 compares them).
!
! In p = -tr(sigma)/3 (compression positive) and q = sqrt(3/2 s:s):
!   yield surface  f = q^2/M^2 + p (p - p_c);
!   swelling line  p + p_m = (p_n + p_m) exp((1 + e) deps_v^e / kappa), G constant or from K, nu;
!   flow           associated; hardening p_c = p_c,n exp((1 + e) deps_v^p / (lambda - kappa));
!   a trial stress in mean tension returns to zero stress (the apex).
! Backward Euler in (deps_v^p, dgamma) by Newton's method, the deviator returned radially; an
! increment whose iteration fails is split into 2, 4, ... 1024 parts, and if that fails too
! the UMAT asks for a shorter increment (PNEWDT = 0.5).
!
! PROPS: 1 lambda, 2 kappa, 3 M, 4 nu, 5 G (Pa; 0: from K and nu), 6 p_m (Pa), 7 e0,
!        8 p_c0 (Pa; 0: from OCR), 9 OCR.
! STATEV: 1 p_c (Pa), 2 e. Both 0 at the first call (dpmpm's call with a zero increment at
!        the start, KINC = 0): then e = e0 and p_c = p_c0, or OCR times the yield surface
!        through the stress given, p + q^2/(M^2 p) (p at least p_m), if that is larger.
! The void ratio follows the volume: 1 + e = (1 + e_n) det(DFGRD1)/det(DFGRD0).
! SSE = p^2/(2K) + q^2/(6G) at the new stress; SPD gains (sigma_n + sigma)/2 : deps^p.
subroutine umat(stress, statev, ddsdde, sse, spd, scd, rpl, ddsddt, drplde, drpldt, stran, &
                dstran, time, dtime, temp, dtemp, predef, dpred, cmname, ndi, nshr, ntens, &
                nstatv, props, nprops, coords, drot, pnewdt, celent, dfgrd0, dfgrd1, noel, &
                npt, layer, kspt, jstep, kinc)
  implicit none
  integer, parameter :: dp = kind(1.0d0)
  integer, intent(in) :: ndi, nshr, ntens, nstatv, nprops, noel, npt, layer, kspt
  integer, intent(in) :: jstep(4), kinc
  real(dp), intent(inout) :: stress(ntens), statev(nstatv), ddsdde(ntens, ntens)
  real(dp), intent(inout) :: sse, spd, scd, rpl, ddsddt(ntens), drplde(ntens), drpldt
  real(dp), intent(in) :: stran(ntens), dstran(ntens), time(2), dtime, temp, dtemp
  real(dp), intent(in) :: predef(1), dpred(1), props(nprops), coords(3), drot(3, 3)
  real(dp), intent(inout) :: pnewdt
  real(dp), intent(in) :: celent, dfgrd0(3, 3), dfgrd1(3, 3)
  character(len=80), intent(in) :: cmname
  integer, parameter :: max_halvings = 10
  real(dp) :: par(6), s0(6), pc0, e, pc, part(6), elastic(6), done(6), p, q, bulk, shear
  integer :: h, k, nsub, fail, i, j

  ! lambda, kappa, M, nu, G, p_m
  par = props(1:6)
  if (statev(2) <= 0.0_dp) then
    call invariants(stress, p, q)
    p = max(p, par(6), tiny(1.0_dp))
    statev(1) = max(props(8), props(9)*(p + q**2/(par(3)**2*p)))
    statev(2) = props(7)
  end if
  e = statev(2)
  s0 = stress
  pc0 = statev(1)

  ! the whole increment, or 2^h equal parts of it
  do h = 0, max_halvings
    nsub = 2**h
    stress = s0
    pc = pc0
    done = 0.0_dp
    do k = 1, nsub
      call mcc_return(par, dstran/real(nsub, dp), e, stress, pc, fail, part)
      if (fail /= 0) exit
      done = done + part
    end do
    if (fail == 0) exit
  end do
  if (fail /= 0) then
    stress = s0
    pnewdt = 0.5_dp
    return
  end if
  elastic = done

  statev(1) = pc
  spd = spd + 0.5_dp*dot_product(s0 + stress, dstran - elastic)
  statev(2) = (1.0_dp + e)*det(dfgrd1)/det(dfgrd0) - 1.0_dp

  ! the elastic tangent at the new state, and the stored energy
  call invariants(stress, p, q)
  call moduli(par, p, statev(2), bulk, shear)
  ddsdde = 0.0_dp
  do i = 1, ndi
    do j = 1, ndi
      ddsdde(i, j) = bulk - 2.0_dp*shear/3.0_dp
    end do
    ddsdde(i, i) = bulk + 4.0_dp*shear/3.0_dp
  end do
  do i = ndi + 1, ntens
    ddsdde(i, i) = shear
  end do
  sse = 0.0_dp
  if (bulk > 0.0_dp) sse = sse + p**2/(2.0_dp*bulk)
  if (shear > 0.0_dp) sse = sse + q**2/(6.0_dp*shear)

contains

  ! p (compression positive) and q of a stress in the order 11 22 33 12 13 23
  subroutine invariants(s, p, q)
    real(dp), intent(in) :: s(6)
    real(dp), intent(out) :: p, q
    real(dp) :: d(6)
    p = -(s(1) + s(2) + s(3))/3.0_dp
    d = s
    d(1:3) = d(1:3) + p
    q = sqrt(1.5_dp*(d(1)**2 + d(2)**2 + d(3)**2 + 2.0_dp*sum(d(4:6)**2)))
  end subroutine invariants

  ! the elastic bulk and shear moduli at p and void ratio e
  subroutine moduli(par, p, e, bulk, shear)
    real(dp), intent(in) :: par(6), p, e
    real(dp), intent(out) :: bulk, shear
    bulk = (1.0_dp + e)*max(p + par(6), 0.0_dp)/par(2)
    if (par(5) > 0.0_dp) then
      shear = par(5)
    else
      shear = 1.5_dp*bulk*(1.0_dp - 2.0_dp*par(4))/(1.0_dp + par(4))
    end if
  end subroutine moduli

  ! One backward-Euler return of the strain increment de (engineering shears) from stress s
  ! with preconsolidation pc at void ratio e; fail = 1 when Newton's method does not
  ! converge; de_el the elastic part of de.
  subroutine mcc_return(par, de, e, s, pc, fail, de_el)
    real(dp), intent(in) :: par(6), de(6), e
    real(dp), intent(inout) :: s(6), pc
    integer, intent(out) :: fail
    real(dp), intent(out) :: de_el(6)
    real(dp), parameter :: tol = 1.0e-12_dp
    integer, parameter :: max_iter = 60
    real(dp) :: p0, dev(6), ev, edev(6), a, b, bulk, shear, ptr, qtr, mm, pm, big, x, g
    real(dp) :: pp, pcx, div, q, r1, r2, j11, j12, j21, j22, jd, dx, dg
    integer :: it
    logical :: polish
    fail = 0
    mm = par(3)**2
    pm = par(6)
    call invariants(s, p0, q)
    dev = s
    dev(1:3) = dev(1:3) + p0
    ! volume strain, compression positive, and the deviatoric strain with tensor shears
    ev = -(de(1) + de(2) + de(3))
    edev(1:3) = de(1:3) + ev/3.0_dp
    edev(4:6) = 0.5_dp*de(4:6)
    a = (1.0_dp + e)/par(2)
    b = (1.0_dp + e)/(par(1) - par(2))
    call moduli(par, p0, e, bulk, shear)
    ! the elastic trial
    ptr = (p0 + pm)*exp(a*ev) - pm
    dev = dev + 2.0_dp*shear*edev
    qtr = sqrt(1.5_dp*(dev(1)**2 + dev(2)**2 + dev(3)**2 + 2.0_dp*sum(dev(4:6)**2)))
    ! a trial in mean tension lies beyond the apex of the surface: the soil has come apart
    ! and carries no effective stress (p_c stays)
    if (ptr <= 0.0_dp) then
      s = 0.0_dp
      de_el = de
      return
    end if
    big = max(pc, p0 + pm, ptr + pm)**2
    if (qtr**2/mm + ptr*(ptr - pc) <= tol*big) then
      s = dev
      s(1:3) = s(1:3) - ptr
      de_el = de
      return
    end if
    ! Newton's method in x (plastic volume strain) and g (the plastic multiplier):
    ! r1 = x - g (2p - p_c) = 0 (the flow rule's volume part), r2 = f(p, q, p_c) = 0
    x = 0.0_dp
    g = 0.0_dp
    polish = .false.
    do it = 1, max_iter
      pp = (ptr + pm)*exp(-a*x) - pm
      pcx = pc*exp(b*x)
      div = 1.0_dp + 6.0_dp*shear*g/mm
      q = qtr/div
      r1 = x - g*(2.0_dp*pp - pcx)
      r2 = q**2/mm + pp*(pp - pcx)
      ! r1 relative to its terms (at the critical state 2p - p_c vanishes and x with it);
      ! once both residuals pass, one more step takes them to round-off
      if (polish) exit
      polish = abs(r1) <= tol*max(abs(x), g*(2.0_dp*abs(pp) + pcx), tol) .and. &
               abs(r2) <= tol*big
      j11 = 1.0_dp + g*(2.0_dp*a*(pp + pm) + b*pcx)
      j12 = -(2.0_dp*pp - pcx)
      j21 = -(2.0_dp*pp - pcx)*a*(pp + pm) - pp*b*pcx
      j22 = -2.0_dp*q**2*(6.0_dp*shear/mm)/(mm*div)
      jd = j11*j22 - j12*j21
      if (jd == 0.0_dp) then
        fail = 1
        return
      end if
      dx = -(r1*j22 - j12*r2)/jd
      dg = -(j11*r2 - j21*r1)/jd
      x = x + dx
      g = max(g + dg, 0.0_dp)
    end do
    if (it > max_iter .or. .not. (abs(x) < huge(1.0_dp))) then
      fail = 1
      return
    end if
    pp = (ptr + pm)*exp(-a*x) - pm
    q = qtr/(1.0_dp + 6.0_dp*shear*g/mm)
    pc = pc*exp(b*x)
    if (qtr > 0.0_dp) dev = dev*(q/qtr)
    s = dev
    s(1:3) = s(1:3) - pp
    ! elastic part: de less the plastic strain g df/dsigma = g (3 s/M^2 - (2p - p_c)/3 I)
    de_el(1:3) = de(1:3) + x/3.0_dp - 3.0_dp*g/mm*dev(1:3)
    de_el(4:6) = de(4:6) - 6.0_dp*g/mm*dev(4:6)
  end subroutine mcc_return

  ! determinant of a 3x3 matrix
  real(dp) function det(f)
    real(dp), intent(in) :: f(3, 3)
    det = f(1, 1)*(f(2, 2)*f(3, 3) - f(2, 3)*f(3, 2)) - f(1, 2)*(f(2, 1)*f(3, 3) - f(2, 3)*f(3, 1)) &
          + f(1, 3)*(f(2, 1)*f(3, 2) - f(2, 2)*f(3, 1))
  end function det

end subroutine umat
