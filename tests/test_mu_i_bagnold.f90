!> A mu(I) layer on a rough incline started on the Bagnold profile, its steady flow in closed
!> form (doc/theory.md 5.9): h = 0.04 m of glass beads (mu_s = 0.38, mu_2 = 0.64,
!> I_0 = 0.279, d = 5 mm, rho_s = 2500, bulk 1500 kg/m^3) at 25 degrees, 1 m long with free
!> ends, 5 cells across the depth, pure FLIP, each row of points moving with the closed-form
!> velocity at its height, in the stress of the infinite layer. After 0.2 s, before the
!> disturbance from the ends reaches the middle, the points that started within 0.1 m of the
!> middle still carry the closed-form flux and profile. Measured numbers and margins:
!> doc/verification.md, "The mu(I) rheology: steady flow against the Bagnold profile".
program test_mu_i_bagnold
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, bc_fixed
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, am_root
  implicit none
  real(wp), parameter :: mus = 0.38_wp, mu2 = 0.64_wp, i0 = 0.279_wp, dg = 5.0e-3_wp
  real(wp), parameter :: rhos = 2500.0_wp, rhob = 1500.0_wp, g = 9.81_wp, h = 0.04_wp
  real(wp), parameter :: pi = acos(-1.0_wp), theta = 25.0_wp*pi/180.0_wp
  real(wp), parameter :: x0 = 0.1_wp, length = 1.0_wp
  integer, parameter :: cells = 5, rows = 2*cells
  call start_tests()
  call test_layer_on_the_bagnold_profile_stays_on_it()
  call end_tests()

contains

  !> The closed form u(z) = (2/3) (I_theta/d) sqrt(phi g cos(theta)) (h^1.5 - (h - z)^1.5),
  !> I_theta = I_0 (tan(theta) - mu_s)/(mu_2 - tan(theta)), phi = rho_b/rho_s.
  elemental real(wp) function bagnold(z)
    real(wp), intent(in) :: z
    real(wp) :: ith
    ith = i0*(tan(theta) - mus)/(mu2 - tan(theta))
    bagnold = 2.0_wp/3.0_wp*ith/dg*sqrt(rhob/rhos*g*cos(theta))* &
              (h**1.5_wp - max(h - z, 0.0_wp)**1.5_wp)
  end function bagnold

  subroutine test_layer_on_the_bagnold_profile_stays_on_it()
    type(config_t) :: cfg
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids0(:), ids(:)
    real(wp), allocatable :: x0s(:, :), x(:, :), v(:, :), s(:, :), zc(:), vb(:)
    logical, allocatable :: mid(:)
    real(wp) :: c, sn, dx, dz, flux, us, rms
    integer :: k, n(rows)
    call begin_test('layer_on_the_bagnold_profile_stays_on_it')
    c = cos(theta)
    sn = sin(theta)
    dx = h/cells
    dz = 0.5_wp*dx
    cfg%name = 'mu_i_bagnold'
    cfg%ndim = 2
    cfg%ncells = [nint((x0 + length + 0.5_wp)/dx), 2*cells, 1]
    cfg%length = [cfg%ncells(1)*dx, 2.0_wp*h, 1.0_wp]
    cfg%t_end = 0.2_wp
    cfg%cfl = 0.5_wp
    cfg%flip = 1.0_wp
    cfg%gravity = [g*sn, -g*c, 0.0_wp]
    allocate (cfg%materials(1), cfg%regions(rows), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model='mu_i', density=rhob, grain_density=rhos, &
                                      youngs_modulus=2.0e5_wp, poisson_ratio=0.3_wp, &
                                      mu_s=mus, mu_2=mu2, i_0=i0, grain_diameter=dg, &
                                      max_dilation=2.0_wp)
    do k = 1, rows            ! one row of points (2 x 2 per cell) per region
      cfg%regions(k)%lo = [x0, (k - 1)*dz, 0.0_wp]
      cfg%regions(k)%hi = [x0 + length, k*dz, 1.0_wp]
      cfg%regions(k)%material = 1
      cfg%regions(k)%velocity = [bagnold((k - 0.5_wp)*dz), 0.0_wp, 0.0_wp]
      cfg%regions(k)%stress = rhob*g*h*[-c, -c, -c, 0.0_wp, 0.0_wp, sn]
      cfg%regions(k)%stress_gradient(:, 2) = -rhob*g*[-c, -c, -c, 0.0_wp, 0.0_wp, sn]
    end do
    cfg%bc(3) = bc_fixed
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%gather_points(ids0, x0s, v, s)
    call sim%run()
    call sim%gather_points(ids, x, v, s)
    call sim%free()
    if (.not. am_root) return
    call check(all(ids == ids0), 'the same points, by id')
    ! the points that started within 0.1 m of the middle, binned by height (one bin a row)
    mid = abs(x0s(1, :) - (x0 + 0.5_wp*length)) < 0.1_wp
    allocate (zc(rows), vb(rows))
    do k = 1, rows
      zc(k) = (k - 0.5_wp)*dz
      n(k) = count(mid .and. x(2, :) >= (k - 1)*dz .and. x(2, :) < k*dz)
      vb(k) = sum(v(1, :), mask=mid .and. x(2, :) >= (k - 1)*dz .and. x(2, :) < k*dz)/ &
              max(n(k), 1)
    end do
    us = bagnold(h)
    flux = sum(v(1, :), mask=mid)/count(mid)/(0.6_wp*us)
    rms = sqrt(sum((vb - bagnold(zc))**2)/rows)/us
    print '(a,f8.4,a,f8.4,a,i0,a)', '  after 0.2 s: mean over (3/5) u_s', flux, &
      ', RMS distance of the profile over u_s', rms, ' (', count(mid), ' points)'
    call check(all(n > 0), 'every row of the middle holds points')
    call check(abs(flux - 1.0_wp) < 0.03_wp, 'the flux within 3 % of the closed form')
    call check(rms < 0.03_wp, 'the profile within 3 % of u_s (RMS)')
  end subroutine test_layer_on_the_bagnold_profile_stays_on_it

end program test_mu_i_bagnold
