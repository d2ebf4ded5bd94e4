!> The frequency-domain reference of 1D site response: a uniform layer of height H on a
!> rigid base (Kramer 1996, ch. 7): the surface motion over the base motion is
!> 1/cos(omega H/c*), with c* = c sqrt(1 + i omega b) for a Kelvin-Voigt (viscous) damping
!> G* = G (1 + i omega b) and c* = c without damping. The base velocity, sampled evenly,
!> is transformed with FFTW, multiplied by the transfer function and transformed back.
!> Undamped, the transfer function has poles at the layer's modes and the response never
!> decays: the transform is taken on the complex frequency s = alpha + i omega (the
!> samples weighted by exp(-alpha t) before and exp(alpha t) after, the numerical Laplace
!> transform), which moves the poles off the axis and makes what the periodic transform
!> folds back from beyond its length exp(-alpha T_fft) = 1e-8 of the response.
!> With Rayleigh damping (mass-proportional a on the velocity relative to the base,
!> stiffness-proportional b): rho u_tt = d/dz (G (u_z + b u_zt)) - a rho (u_t - u_b,t), whose
!> transfer function is 1 - s/(s + a) (1 - 1/cosh(k H)), k^2 = s (s + a)/(c^2 (1 + s b))
!> (doc/theory.md 4.7); a = 0 gives 1/cosh(s H/c*) again.
module dpmpm_site_response
  use, intrinsic :: iso_c_binding
  use dpmpm_kinds, only: wp
  implicit none
  private
  include 'fftw3.f03'

  public :: layer_surface_velocity

contains

  !> Surface velocity vs(:) of the layer (height [m], wave speed [m/s], optional viscous
  !> damping b [s]: G* = G (1 + s b), and mass-proportional damping a [1/s] of the motion
  !> relative to the base) at the samples of the base velocity vb(:), taken every dt from
  !> t = 0 (at rest before).
  subroutine layer_surface_velocity(vb, dt, height, speed, vs, damping, mass_damping)
    real(wp), intent(in) :: vb(:), dt, height, speed
    real(wp), intent(out) :: vs(:)
    real(wp), intent(in), optional :: damping, mass_damping
    real(wp), parameter :: pi = acos(-1.0_wp)
    real(c_double), allocatable :: x(:)
    complex(c_double_complex), allocatable :: spec(:)
    type(c_ptr) :: fwd, bwd
    integer :: n, nfft, k
    real(wp) :: alpha, tfft, b, a
    complex(wp) :: s, cstar, kh
    n = size(vb)
    b = 0.0_wp
    if (present(damping)) b = damping
    a = 0.0_wp
    if (present(mass_damping)) a = mass_damping
    nfft = 1
    do while (nfft < 4*n)
      nfft = 2*nfft
    end do
    tfft = nfft*dt
    alpha = log(1.0e8_wp)/tfft
    allocate (x(0:nfft - 1), spec(0:nfft/2))
    fwd = fftw_plan_dft_r2c_1d(int(nfft, c_int), x, spec, FFTW_ESTIMATE)
    bwd = fftw_plan_dft_c2r_1d(int(nfft, c_int), spec, x, FFTW_ESTIMATE)
    x = 0.0_wp
    do k = 0, n - 1
      x(k) = vb(k + 1)*exp(-alpha*dt*k)
    end do
    call fftw_execute_dft_r2c(fwd, x, spec)
    ! FFTW's forward transform has exp(-i omega t): the spectrum at s = alpha + i omega.
    do k = 0, nfft/2
      s = cmplx(alpha, 2.0_wp*pi*real(k, wp)/tfft, wp)
      if (a > 0.0_wp) then
        kh = height/speed*sqrt(s*(s + a)/(1.0_wp + s*b))
        spec(k) = spec(k)*(1.0_wp - s/(s + a)*(1.0_wp - sech(kh)))
      else
        cstar = speed*sqrt(1.0_wp + s*b)
        spec(k) = spec(k)/cosh(s*height/cstar)
      end if
    end do
    call fftw_execute_dft_c2r(bwd, spec, x)
    do k = 0, n - 1
      vs(k + 1) = x(k)*exp(alpha*dt*k)/real(nfft, wp)
    end do
    call fftw_destroy_plan(fwd)
    call fftw_destroy_plan(bwd)
  end subroutine layer_surface_velocity

  !> 1/cosh(z) without overflow: 2 exp(-z)/(1 + exp(-2 z)) on the side Re z >= 0 (cosh is even).
  pure complex(wp) function sech(z)
    complex(wp), intent(in) :: z
    complex(wp) :: w
    w = z
    if (real(w) < 0.0_wp) w = -w
    sech = 2.0_wp*exp(-w)/(1.0_wp + exp(-2.0_wp*w))
  end function sech

end module dpmpm_site_response
