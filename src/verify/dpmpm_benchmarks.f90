!> Benchmarks with analytical solutions: initial conditions and error measures.
!>
!> axial_bar: a 1D elastic bar on [x0, x0 + L], fixed at x0 (the grid's x- face)
!> and free at x0 + L, started in its first mode, v(x, 0) = A sin(beta (x - x0)),
!> beta = pi/(2L). Exact: v = A sin(beta X) cos(omega t), u = (A/omega) sin(beta X)
!> sin(omega t), omega = beta c, c = sqrt(M/rho) with the constrained modulus M
!> (1D is uniaxial strain).
!>
!> mms: the manufactured solution of doc/theory.md 9.4 on the unit square (M1):
!> u_x = B sin(pi X) sin(c pi t), u_y = B sin(pi Y) sin(c pi t + pi), c = sqrt(E/rho0),
!> compressible neo-Hookean, driven by the body force of doc/theory.md 9.4 at the
!> points' reference positions and the step's start time. Errors: e_u(t) of
!> doc/theory.md 9.4, the volume-weighted RMS velocity error, the mean velocity
!> error of the paper's eq. (15) (time-averaged from the history), and two crack
!> measures: the largest ratio of the distance between initially neighbouring
!> points to its exact value, and the number of grid cells without a point.
module dpmpm_benchmarks
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t
  use dpmpm_particles, only: particle_set_t
  use dpmpm_materials, only: material_t
  use dpmpm_gather, only: gather_columns
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM, &
                     MPI_Comm_rank, MPI_Bcast, MPI_INTEGER
  implicit none
  private
  public :: benchmark_setup, benchmark_errors, benchmark_error_names, nbench_err
  public :: benchmark_nerr, benchmark_body_force, mms_exact

  real(wp), parameter :: pi = acos(-1.0_wp)
  !> Most error measures of any benchmark; benchmark_nerr gives the count of each.
  integer, parameter :: nbench_err = 5
  character(len=24), parameter :: benchmark_error_names(nbench_err) = [character(len=24) :: &
    'error_velocity', 'error_displacement', 'error_velocity_mean', 'gap_ratio', 'empty_cells']
  !> Phase of u_y in the manufactured solution.
  real(wp), parameter :: mms_phase = pi

contains

  !> Number of error measures of a benchmark (the first ones of benchmark_error_names).
  pure integer function benchmark_nerr(name) result(n)
    character(len=*), intent(in) :: name
    select case (trim(name))
    case ('axial_bar')
      n = 2
    case ('mms')
      n = 5
    case default
      n = 0
    end select
  end function benchmark_nerr

  !> Manufactured displacement u and velocity v at reference position X (relative
  !> to the grid origin), time t, amplitude b and wave speed c; also F11, F22.
  pure subroutine mms_exact(xr, t, b, c, u, v, f11, f22)
    real(wp), intent(in) :: xr(2), t, b, c
    real(wp), intent(out) :: u(2), v(2), f11, f22
    u(1) = b*sin(pi*xr(1))*sin(c*pi*t)
    u(2) = b*sin(pi*xr(2))*sin(c*pi*t + mms_phase)
    v(1) = b*c*pi*sin(pi*xr(1))*cos(c*pi*t)
    v(2) = b*c*pi*sin(pi*xr(2))*cos(c*pi*t + mms_phase)
    f11 = 1.0_wp + pi*b*cos(pi*xr(1))*sin(c*pi*t)
    f22 = 1.0_wp + pi*b*cos(pi*xr(2))*sin(c*pi*t + mms_phase)
  end subroutine mms_exact

  !> Body acceleration of the manufactured solution at each point's reference
  !> position and time t (doc/theory.md 9.4):
  !> b_x = (pi^2 u_x/rho0) [(lambda (1 - ln J) + mu)/F11^2 + mu - rho0 c^2], b_y alike.
  subroutine benchmark_body_force(cfg, mats, ps, t, bacc)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(in) :: ps
    real(wp), intent(in) :: t
    real(wp), intent(out) :: bacc(:, :)
    real(wp) :: c, u(2), v(2), f11, f22, lnj, rho0, lam, mu
    integer :: p
    rho0 = mats(1)%density
    lam = mats(1)%lambda
    mu = mats(1)%mu
    c = mms_speed(mats)
    do p = 1, ps%n
      call mms_exact(ps%x0(1:2, p) - cfg%origin(1:2), t, cfg%amplitude, c, u, v, f11, f22)
      lnj = log(f11*f22)
      bacc(1, p) = pi*pi*u(1)/rho0*((lam*(1.0_wp - lnj) + mu)/f11**2 + mu - rho0*c*c)
      bacc(2, p) = pi*pi*u(2)/rho0*((lam*(1.0_wp - lnj) + mu)/f22**2 + mu - rho0*c*c)
    end do
  end subroutine benchmark_body_force

  !> c = sqrt(E/rho0) of the manufactured solution.
  pure real(wp) function mms_speed(mats) result(c)
    type(material_t), intent(in) :: mats(:)
    c = sqrt(mats(1)%mu*(3.0_wp*mats(1)%lambda + 2.0_wp*mats(1)%mu)/ &
             (mats(1)%lambda + mats(1)%mu)/mats(1)%density)
  end function mms_speed

  !> Set the benchmark's initial state on the points (nothing for 'none').
  subroutine benchmark_setup(cfg, mats, ps)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(inout) :: ps
    real(wp) :: beta, len
    integer :: p
    select case (trim(cfg%benchmark))
    case ('axial_bar')
      call bar_geometry(cfg, mats, len, beta)
      do p = 1, ps%n
        ps%v(1, p) = cfg%amplitude*sin(beta*(ps%x0(1, p) - cfg%origin(1)))
      end do
    case ('mms')
      call mms_setup(cfg, mats, ps)
    end select
  end subroutine benchmark_setup

  !> Mass-weighted RMS errors of velocity and displacement against the exact
  !> solution at time t, relative to their amplitudes (A and A/omega). Global over comm.
  function benchmark_errors(cfg, mats, ps, t, comm) result(err)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(in) :: ps
    real(wp), intent(in) :: t
    type(MPI_Comm), intent(in) :: comm
    real(wp) :: err(nbench_err)
    real(wp) :: beta, len, omega, s(3), xi, ve, ue
    integer :: p
    err = 0.0_wp
    select case (trim(cfg%benchmark))
    case ('axial_bar')
      call bar_geometry(cfg, mats, len, beta, omega)
      s = 0.0_wp
      do p = 1, ps%n
        xi = ps%x0(1, p) - cfg%origin(1)
        ve = cfg%amplitude*sin(beta*xi)*cos(omega*t)
        ue = cfg%amplitude/omega*sin(beta*xi)*sin(omega*t)
        s(1) = s(1) + ps%mass(p)*(ps%v(1, p) - ve)**2
        s(2) = s(2) + ps%mass(p)*(ps%x(1, p) - ps%x0(1, p) - ue)**2
        s(3) = s(3) + ps%mass(p)
      end do
      call MPI_Allreduce(MPI_IN_PLACE, s, 3, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
      err(1) = sqrt(s(1)/s(3))/cfg%amplitude
      err(2) = sqrt(s(2)/s(3))/(cfg%amplitude/omega)
    case ('mms')
      err = mms_errors(cfg, mats, ps, t, comm)
    end select
  end function benchmark_errors

  subroutine mms_setup(cfg, mats, ps)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(inout) :: ps
    real(wp) :: u(2), v(2), f11, f22
    integer :: p
    do p = 1, ps%n
      call mms_exact(ps%x0(1:2, p) - cfg%origin(1:2), 0.0_wp, cfg%amplitude, mms_speed(mats), &
                     u, v, f11, f22)
      ps%v(:, p) = v
    end do
  end subroutine mms_setup

  !> The error measures of the manufactured solution (module header), global over comm.
  function mms_errors(cfg, mats, ps, t, comm) result(err)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(in) :: ps
    real(wp), intent(in) :: t
    type(MPI_Comm), intent(in) :: comm
    real(wp) :: err(nbench_err)
    real(wp) :: s(4), u(2), v(2), f11, f22, c
    integer :: p
    c = mms_speed(mats)
    s = 0.0_wp
    do p = 1, ps%n
      call mms_exact(ps%x0(1:2, p) - cfg%origin(1:2), t, cfg%amplitude, c, u, v, f11, f22)
      s(1) = s(1) + ps%vol0(p)*sum((ps%x(1:2, p) - ps%x0(1:2, p) - u)**2)
      s(2) = s(2) + ps%vol0(p)*sum((ps%v(1:2, p) - v)**2)
      s(3) = s(3) + ps%vol0(p)
      s(4) = s(4) + norm2(ps%v(1:2, p) - v)
    end do
    err = 0.0_wp
    call MPI_Allreduce(MPI_IN_PLACE, s, 4, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
    err(1) = sqrt(s(2)/s(3))
    err(2) = sqrt(s(1))
    call crack_measures(cfg, mats, ps, t, comm, err(4), err(5))
    err(3) = s(4)/real(count_points(ps, comm), wp)
  end function mms_errors

  !> Total number of points over comm.
  integer function count_points(ps, comm) result(n)
    type(particle_set_t), intent(in) :: ps
    type(MPI_Comm), intent(in) :: comm
    call MPI_Allreduce(ps%n, n, 1, MPI_INTEGER, MPI_SUM, comm)
  end function count_points

  !> Crack measures on rank 0 from the gathered reference and current positions
  !> of a regular point lattice (region 1): the largest ratio of the distance
  !> between lattice neighbours to the exact one, and the empty grid cells.
  subroutine crack_measures(cfg, mats, ps, t, comm, gap, empty)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(particle_set_t), intent(in) :: ps
    real(wp), intent(in) :: t
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(out) :: gap, empty
    integer :: rank, ntot, k, p, q, ix, iy, nl(2), cell(2)
    integer, allocatable :: idx(:, :), occupied(:, :)
    real(wp), allocatable :: buf(:, :), all(:, :)
    real(wp) :: a(2), u(2), v(2), f11, f22, c, res(2), ep(2), eq(2)
    call MPI_Comm_rank(comm, rank)
    allocate (buf(4, ps%n))
    buf(1:2, :) = ps%x0(1:2, 1:ps%n) - spread(cfg%origin(1:2), 2, ps%n)
    buf(3:4, :) = ps%x(1:2, 1:ps%n) - spread(cfg%origin(1:2), 2, ps%n)
    call gather_columns(buf, ps%n, comm, all, ntot)
    res = 0.0_wp
    if (rank == 0) then
      c = mms_speed(mats)
      a = cfg%length(1:2)/real(cfg%ncells(1:2)*cfg%regions(1)%ppc, wp)
      nl = cfg%ncells(1:2)*cfg%regions(1)%ppc
      allocate (idx(0:nl(1) - 1, 0:nl(2) - 1), occupied(0:cfg%ncells(1) - 1, 0:cfg%ncells(2) - 1))
      idx = 0
      occupied = 0
      do p = 1, ntot
        ix = nint(all(1, p)/a(1) - 0.5_wp)
        iy = nint(all(2, p)/a(2) - 0.5_wp)
        if (ix >= 0 .and. ix < nl(1) .and. iy >= 0 .and. iy < nl(2)) idx(ix, iy) = p
        cell = floor(all(3:4, p)/(cfg%length(1:2)/real(cfg%ncells(1:2), wp)))
        cell = max(0, min(cfg%ncells(1:2) - 1, cell))
        occupied(cell(1), cell(2)) = 1
      end do
      res(2) = real(count(occupied == 0), wp)
      if (cfg%regions(1)%placement == 'regular') then
        do iy = 0, nl(2) - 1
          do ix = 0, nl(1) - 1
            p = idx(ix, iy)
            if (p == 0) cycle
            call mms_exact(all(1:2, p), t, cfg%amplitude, c, u, v, f11, f22)
            ep = all(1:2, p) + u
            do k = 1, 2
              if (k == 1 .and. ix + 1 < nl(1)) then
                q = idx(ix + 1, iy)
              else if (k == 2 .and. iy + 1 < nl(2)) then
                q = idx(ix, iy + 1)
              else
                cycle
              end if
              if (q == 0) cycle
              call mms_exact(all(1:2, q), t, cfg%amplitude, c, u, v, f11, f22)
              eq = all(1:2, q) + u
              res(1) = max(res(1), norm2(all(3:4, q) - all(3:4, p))/norm2(eq - ep))
            end do
          end do
        end do
      end if
    end if
    call MPI_Bcast(res, 2, MPI_DOUBLE_PRECISION, 0, comm)
    gap = res(1)
    empty = res(2)
  end subroutine crack_measures

  subroutine bar_geometry(cfg, mats, len, beta, omega)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    real(wp), intent(out) :: len, beta
    real(wp), intent(out), optional :: omega
    len = cfg%regions(1)%hi(1) - cfg%origin(1)
    beta = pi/(2.0_wp*len)
    if (present(omega)) omega = beta*sqrt(mats(1)%pwave/mats(1)%density)
  end subroutine bar_geometry

end module dpmpm_benchmarks
