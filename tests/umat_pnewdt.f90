!> A UMAT for tests/test_umat_pnewdt.f90: linear elastic (PROPS(1) = E, PROPS(2) = nu) that
!> refuses increments with a strain component above PROPS(3), asking for
!> PNEWDT = min(0.5, 0.9 PROPS(3)/max |DSTRAN|), and every increment when PROPS(3) <= 0.
!> It counts its calls in STATEV(1) and sums DTIME in STATEV(2) and DSTRAN(1) in STATEV(3),
!> so that the test sees which calls the wrapper kept.
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
  real(dp) :: lam, g, tr, big
  statev(1) = statev(1) + 1.0_dp
  statev(2) = statev(2) + dtime
  statev(3) = statev(3) + dstran(1)
  big = maxval(abs(dstran))
  if (props(3) <= 0.0_dp) then
    pnewdt = 0.5_dp
    return
  else if (big > props(3)) then
    pnewdt = min(0.5_dp, 0.9_dp*props(3)/big)
    return
  end if
  lam = props(1)*props(2)/((1.0_dp + props(2))*(1.0_dp - 2.0_dp*props(2)))
  g = props(1)/(2.0_dp*(1.0_dp + props(2)))
  tr = dstran(1) + dstran(2) + dstran(3)
  stress(1:3) = stress(1:3) + (lam*tr + 2.0_dp*g*dstran(1:3))
  stress(4:6) = stress(4:6) + g*dstran(4:6)
end subroutine umat
