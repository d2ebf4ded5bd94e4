!> A user's material: an Abaqus/Standard UMAT compiled in (the CMake cache variable
!> DPMPM_UMAT names its file; src/materials/umat/umat_linear_elastic.f by default). The conversions
!> between dpmpm and the UMAT's argument list are written here once:
!> - order: dpmpm's Voigt order is xx yy zz yz xz xy, the UMAT's 11 22 33 12 13 23 (NDI = 3,
!>   NSHR = 3, NTENS = 6 always; in plane strain the out-of-plane increments are zero);
!> - strain: engineering shears (gamma = 2 eps) in STRAN and DSTRAN, as in dpmpm's deps;
!> - sign: both take the Cauchy stress positive in tension, so nothing changes sign;
!> - the increment: DSTRAN = dt D from the point's velocity gradient L (D its symmetric
!>   part), and the stress and STRAN passed in are rotated with the spin first,
!>   sigma + dt (W sigma - sigma W), as Abaqus/Standard passes a rotated stress; DROT is
!>   the rotation of the increment, (I - dt W/2)^-1 (I + dt W/2) (Hughes & Winget 1980), for
!>   the UMAT's own tensors; DFGRD0 and DFGRD1 are F at the start and end of the step,
!>   F <- (I + dt L) F;
!> - state: a point keeps STRAN (6 values, dpmpm's order), SSE, SPD and SCD (J/m^3) and
!>   then the UMAT's NSTATV values (dpmpm_model_table, umat_state); SSE V is the point's
!>   stored energy and the rise of (SPD + SCD) V its dissipation, in the energy balance;
!>   at the start one call with a zero increment (KINC = 0) lets the UMAT set STATEV and
!>   SSE from the initial stress (umat_init_state);
!> - PNEWDT < 1 (the UMAT asks for a shorter increment): the stress, state and F of the
!>   point are restored and the step is taken in ceiling(1/PNEWDT) times as many substeps
!>   (each with dt/nsub, the same L, its own rotation), up to max_substeps; a point that
!>   still asks for less stops the run with its id;
!> - the volume follows det(I + dt L), as in the other models; DDSDDE is not used (the
!>   scheme is explicit: the time step takes youngs_modulus and poisson_ratio, the
!>   stiffest the UMAT gets); TEMP, DTEMP, PREDEF, DPRED, RPL, DDSDDT, DRPLDE, DRPLDT are 0.
!> doc/input.md ("A user's UMAT") lists every argument as dpmpm fills it.
module dpmpm_model_umat
  use dpmpm_kinds, only: wp, i8
  use dpmpm_material_params, only: material_t
  use dpmpm_model_plastic, only: jaumann_strain
  use dpmpm_error, only: fatal
  implicit none
  private
  public :: umat_update, umat_init_state, umat_own, max_substeps, abaqus_order

  !> The state values the wrapper keeps before the UMAT's STATEV: STRAN (6), SSE, SPD, SCD.
  integer, parameter :: umat_own = 9
  !> The most substeps one step of a point is taken in when the UMAT asks for less (2^10).
  integer, parameter :: max_substeps = 1024
  !> Abaqus' component k (11 22 33 12 13 23) is dpmpm's component abaqus_order(k).
  integer, parameter :: abaqus_order(6) = [1, 2, 3, 6, 5, 4]
  !> The UMAT's real kind: double precision, as ABA_PARAM.INC declares.
  integer, parameter :: dp = kind(1.0d0)
  !> PNEWDT before each call: a large value, no wish for a shorter increment.
  real(dp), parameter :: pnewdt_none = 1.0e36_dp

  !> The Abaqus/Standard UMAT argument list (the user's file defines the routine umat).
  interface
    subroutine umat(stress, statev, ddsdde, sse, spd, scd, rpl, ddsddt, drplde, drpldt, stran, &
                    dstran, time, dtime, temp, dtemp, predef, dpred, cmname, ndi, nshr, ntens, &
                    nstatv, props, nprops, coords, drot, pnewdt, celent, dfgrd0, dfgrd1, noel, &
                    npt, layer, kspt, jstep, kinc)
      import :: dp
      integer, intent(in) :: ndi, nshr, ntens, nstatv, nprops, noel, npt, layer, kspt
      integer, intent(in) :: jstep(4), kinc
      real(dp), intent(inout) :: stress(ntens), statev(nstatv), ddsdde(ntens, ntens)
      real(dp), intent(inout) :: sse, spd, scd, rpl, ddsddt(ntens), drplde(ntens), drpldt
      real(dp), intent(in) :: stran(ntens), dstran(ntens), time(2), dtime, temp, dtemp
      real(dp), intent(in) :: predef(1), dpred(1), props(nprops), coords(3), drot(3, 3)
      real(dp), intent(inout) :: pnewdt
      real(dp), intent(in) :: celent, dfgrd0(3, 3), dfgrd1(3, 3)
      character(len=80), intent(in) :: cmname
    end subroutine umat
  end interface

contains

  !> The update of stress_update (dpmpm_materials) for the points of material index m, with
  !> what only a UMAT reads: the time at the start of the step, the steps done (KINC is one
  !> more), the points' positions x and ids, the cell size celent (each zero where absent).
  !> state(1:9, :) are the wrapper's values, state(10:, :) the UMAT's STATEV.
  subroutine umat_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                         dissipation, plane, time, step, x, ids, celent)
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
    real(wp), intent(in), optional :: time, celent
    integer(i8), intent(in), optional :: step, ids(:)
    real(wp), intent(in), optional :: x(:, :)
    real(wp) :: sr(6), de(6), jac, lv(9), f0(3, 3), f1(3, 3), st(umat_own + mat%umat_nstatev)
    real(wp) :: s(6), t0, h, xp(3), wsum, spent
    integer :: p, ns, nsub, k, noel, kinc
    logical :: flat, done
    character(len=256) :: msg
    flat = .false.
    if (present(plane)) flat = plane
    t0 = 0.0_wp
    if (present(time)) t0 = time
    h = 0.0_wp
    if (present(celent)) h = celent
    kinc = 1
    if (present(step)) kinc = int(min(step + 1, int(huge(kinc), i8)))
    ns = umat_own + mat%umat_nstatev
    wsum = 0.0_wp
    if (present(dissipation)) wsum = dissipation
    do p = 1, n
      if (pmat(p) /= m) cycle
      lv = vgrad(:, p)
      if (flat) lv(3:9:3) = 0.0_wp
      if (flat) lv(7:8) = 0.0_wp
      ! the volume and F of the whole step
      call jaumann_strain(dt, lv, stress(:, p), flat, sr, de, jac)
      f0 = identity()
      if (present(defgrad)) f0 = reshape(defgrad(:, p), [3, 3])
      f1 = matmul(identity() + dt*reshape(lv, [3, 3]), f0)
      xp = 0.0_wp
      if (present(x)) xp(1:size(x, 1)) = x(:, p)
      noel = 0
      if (present(ids)) noel = int(min(ids(p), int(huge(noel), i8)))
      st = 0.0_wp
      if (present(state)) st = state(1:ns, p)
      spent = st(8) + st(9)
      nsub = 1
      do
        s = stress(:, p)
        st = 0.0_wp
        if (present(state)) st = state(1:ns, p)
        call substeps(mat, dt, lv, flat, nsub, f0, f1, t0, xp, h, noel, kinc, s, st, done, k)
        if (done) exit
        if (nsub >= max_substeps) then
          write (msg, '(a,i0,a,es12.5,a,i0,a)') 'the UMAT at the point of id ', noel, ' (time ', &
            t0, ') asks for a shorter increment (PNEWDT < 1) even in ', nsub, ' substeps'
          call fatal(trim(msg), 'umat_update')
        end if
        nsub = min(max_substeps, nsub*k)
      end do
      stress(:, p) = s
      if (present(state)) state(1:ns, p) = st
      if (present(defgrad)) defgrad(:, p) = reshape(f1, [9])
      wsum = wsum + vol(p)*(st(8) + st(9) - spent)
      vol(p) = vol(p)*jac
    end do
    if (present(dissipation)) dissipation = wsum
  end subroutine umat_update

  !> The state of the points of material index m at the start (not on a restart): one call
  !> of the UMAT per point with a zero increment (DSTRAN = 0, DTIME = 0, KINC = 0, F = I,
  !> COORDS the position x where given, NOEL the id), whose STATEV, SSE, SPD and SCD are kept
  !> and whose stress is not: the UMAT's chance to set its state from the initial stress (as
  !> Abaqus' SDVINI would) and its stored energy, so that the energy does not jump at the
  !> first step. STRAN starts at 0.
  subroutine umat_init_state(mat, m, n, pmat, stress, state, x, ids)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: stress(:, :)
    real(wp), intent(inout) :: state(:, :)
    real(wp), intent(in), optional :: x(:, :)
    integer(i8), intent(in), optional :: ids(:)
    real(dp) :: a_s(6), zero6(6), ddsdde(6, 6), sse, spd, scd, rpl, ddsddt(6), drplde(6)
    real(dp) :: drpldt, predef(1), dpred(1), coords(3), eye(3, 3), pnewdt
    real(dp) :: props(max(mat%umat_nprops, 1)), statev(max(mat%umat_nstatev, 1))
    integer :: p, nsv, noel
    nsv = mat%umat_nstatev
    props = 0.0_dp
    props(1:mat%umat_nprops) = real(mat%umat_props(1:mat%umat_nprops), dp)
    eye = real(identity(), dp)
    zero6 = 0.0_dp
    do p = 1, n
      if (pmat(p) /= m) cycle
      a_s = real(stress(abaqus_order, p), dp)
      statev = 0.0_dp
      sse = 0.0_dp; spd = 0.0_dp; scd = 0.0_dp
      ddsdde = 0.0_dp; rpl = 0.0_dp; ddsddt = 0.0_dp; drplde = 0.0_dp; drpldt = 0.0_dp
      predef = 0.0_dp; dpred = 0.0_dp
      coords = 0.0_dp
      if (present(x)) coords(1:size(x, 1)) = real(x(:, p), dp)
      noel = 0
      if (present(ids)) noel = int(min(ids(p), int(huge(noel), i8)))
      pnewdt = pnewdt_none
      call umat(a_s, statev, ddsdde, sse, spd, scd, rpl, ddsddt, drplde, drpldt, zero6, zero6, &
                [0.0_dp, 0.0_dp], 0.0_dp, 0.0_dp, 0.0_dp, predef, dpred, mat%umat_name, 3, 3, 6, &
                nsv, props, mat%umat_nprops, coords, eye, pnewdt, 0.0_dp, eye, eye, noel, 1, 1, 1, &
                [1, 1, 1, 0], 0)
      state(:, p) = 0.0_wp
      state(7, p) = real(sse, wp)
      state(8, p) = real(spd, wp)
      state(9, p) = real(scd, wp)
      state(umat_own + 1:umat_own + nsv, p) = real(statev(1:nsv), wp)
    end do
  end subroutine umat_init_state

  !> One step of one point in nsub substeps of dt/nsub: the stress s and the state st
  !> (the wrapper's values and STATEV) from the start of the step to its end; done is false
  !> when a call returned PNEWDT < 1, and then factor is ceiling(1/PNEWDT) (at least 2).
  subroutine substeps(mat, dt, lv, plane, nsub, f0, f1, t0, xp, h, noel, kinc, s, st, done, &
                      factor)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt, lv(9), f0(3, 3), f1(3, 3), t0, xp(3), h
    logical, intent(in) :: plane
    integer, intent(in) :: nsub, noel, kinc
    real(wp), intent(inout) :: s(6), st(:)
    logical, intent(out) :: done
    integer, intent(out) :: factor
    real(wp) :: sr(6), de(6), jac, e(6), er(6), dsub
    real(dp) :: a_s(6), a_e(6), a_de(6), ddsdde(6, 6), sse, spd, scd, rpl, ddsddt(6), drplde(6)
    real(dp) :: drpldt, tm(2), predef(1), dpred(1), coords(3), drot(3, 3), pnewdt, g0(3, 3)
    real(dp) :: g1(3, 3), props(max(mat%umat_nprops, 1)), statev(max(mat%umat_nstatev, 1))
    integer :: k, nsv
    nsv = mat%umat_nstatev
    dsub = dt/real(nsub, wp)
    props = 0.0_dp
    props(1:mat%umat_nprops) = real(mat%umat_props(1:mat%umat_nprops), dp)
    coords = real(xp, dp)
    drot = real(increment_rotation(dsub, lv), dp)
    done = .true.
    factor = 1
    do k = 1, nsub
      ! the stress and STRAN rotated with the spin (the strain's shears as tensor shears),
      ! and the strain increment of the substep
      call jaumann_strain(dsub, lv, s, plane, sr, de, jac)
      e = st(1:6)
      e(4:6) = 0.5_wp*e(4:6)
      call jaumann_strain(dsub, lv, e, plane, er, de, jac)
      er(4:6) = 2.0_wp*er(4:6)
      a_s = real(sr(abaqus_order), dp)
      a_e = real(er(abaqus_order), dp)
      a_de = real(de(abaqus_order), dp)
      sse = real(st(7), dp); spd = real(st(8), dp); scd = real(st(9), dp)
      statev = 0.0_dp
      statev(1:nsv) = real(st(umat_own + 1:umat_own + nsv), dp)
      ddsdde = 0.0_dp; rpl = 0.0_dp; ddsddt = 0.0_dp; drplde = 0.0_dp; drpldt = 0.0_dp
      predef = 0.0_dp; dpred = 0.0_dp
      tm = real(t0 + (k - 1)*dsub, dp)
      g0 = real(f0 + real(k - 1, wp)/real(nsub, wp)*(f1 - f0), dp)
      g1 = real(f0 + real(k, wp)/real(nsub, wp)*(f1 - f0), dp)
      if (k == nsub) g1 = real(f1, dp)
      pnewdt = pnewdt_none
      call umat(a_s, statev, ddsdde, sse, spd, scd, rpl, ddsddt, drplde, drpldt, a_e, a_de, tm, &
                real(dsub, dp), 0.0_dp, 0.0_dp, predef, dpred, mat%umat_name, 3, 3, 6, nsv, props, &
                mat%umat_nprops, coords, drot, pnewdt, real(h, dp), g0, g1, noel, 1, 1, 1, &
                [1, 1, 1, 0], kinc)
      if (pnewdt < 1.0_dp) then
        done = .false.
        factor = 2
        if (pnewdt > 0.0_dp) factor = max(2, ceiling(1.0_dp/max(pnewdt, 1.0_dp/max_substeps)))
        return
      end if
      s(abaqus_order) = real(a_s, wp)
      st(1:6) = er + de
      st(7) = real(sse, wp); st(8) = real(spd, wp); st(9) = real(scd, wp)
      st(umat_own + 1:umat_own + nsv) = real(statev(1:nsv), wp)
    end do
  end subroutine substeps

  !> The rotation of an increment of spin W dt (L the velocity gradient, column-major):
  !> (I - dt W/2)^-1 (I + dt W/2), orthogonal for any dt (Hughes & Winget 1980).
  pure function increment_rotation(dt, lv) result(r)
    real(wp), intent(in) :: dt, lv(9)
    real(wp) :: r(3, 3)
    real(wp) :: w(3, 3), a(3, 3), b(3, 3), l(3, 3)
    l = reshape(lv, [3, 3])
    w = 0.25_wp*dt*(l - transpose(l))
    a = identity() - w
    b = identity() + w
    r = matmul(inverse3(a), b)
  end function increment_rotation

  !> The 3x3 identity.
  pure function identity() result(a)
    real(wp) :: a(3, 3)
    integer :: k
    a = 0.0_wp
    do k = 1, 3
      a(k, k) = 1.0_wp
    end do
  end function identity

  !> The inverse of a 3x3 matrix by its cofactors (a of I - W, never singular).
  pure function inverse3(a) result(b)
    real(wp), intent(in) :: a(3, 3)
    real(wp) :: b(3, 3)
    real(wp) :: det
    b(1, 1) = a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)
    b(1, 2) = a(1, 3)*a(3, 2) - a(1, 2)*a(3, 3)
    b(1, 3) = a(1, 2)*a(2, 3) - a(1, 3)*a(2, 2)
    b(2, 1) = a(2, 3)*a(3, 1) - a(2, 1)*a(3, 3)
    b(2, 2) = a(1, 1)*a(3, 3) - a(1, 3)*a(3, 1)
    b(2, 3) = a(1, 3)*a(2, 1) - a(1, 1)*a(2, 3)
    b(3, 1) = a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1)
    b(3, 2) = a(1, 2)*a(3, 1) - a(1, 1)*a(3, 2)
    b(3, 3) = a(1, 1)*a(2, 2) - a(1, 2)*a(2, 1)
    det = a(1, 1)*b(1, 1) + a(1, 2)*b(2, 1) + a(1, 3)*b(3, 1)
    b = b/det
  end function inverse3

end module dpmpm_model_umat
