!> Reproducible pseudo-random numbers without state: a number is a function of its
!> inputs only (seed, a global cell or point number, a slot, an axis), so that every rank
!> draws the same value for the same point whatever the number of ranks.
module dpmpm_hash
  use dpmpm_kinds, only: wp, i8
  implicit none
  private
  public :: hash_uniform

contains

  !> A uniform number in [0, 1) that depends only on (seed, cell, slot, axis):
  !> a 32-bit integer hash (xor-shift and multiply rounds) applied to each input in turn.
  pure real(wp) function hash_uniform(seed, cell, slot, axis) result(u)
    integer, intent(in) :: seed, slot, axis
    integer(i8), intent(in) :: cell
    integer(i8), parameter :: mask32 = 4294967295_i8
    integer(i8) :: h
    h = hash32(iand(int(seed, i8), mask32))
    h = hash32(ieor(h, iand(cell, mask32)))
    h = hash32(ieor(h, iand(ishft(cell, -32), mask32)))
    h = hash32(ieor(h, int(slot, i8)))
    h = hash32(ieor(h, int(axis, i8) + 1779033703_i8))
    u = real(h, wp)/4294967296.0_wp
  contains
    !> One avalanche round on a 32-bit value held in 64 bits.
    pure integer(i8) function hash32(x0) result(x)
      integer(i8), intent(in) :: x0
      x = x0
      x = ieor(x, ishft(x, -16))
      x = mul32(x, 2146121005_i8)
      x = ieor(x, ishft(x, -15))
      x = mul32(x, 2221713035_i8)
      x = ieor(x, ishft(x, -16))
    end function hash32
    !> (x*c) mod 2^32 without 64-bit overflow: multiply by the 16-bit halves of c.
    pure integer(i8) function mul32(x, c)
      integer(i8), intent(in) :: x, c
      mul32 = iand(x*iand(c, 65535_i8) + ishft(iand(x*ishft(c, -16), 65535_i8), 16), mask32)
    end function mul32
  end function hash_uniform

end module dpmpm_hash
