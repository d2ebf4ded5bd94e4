!> Benchmarks with analytical solutions: initial conditions and error measures.
!>
!> axial_bar: a 1D elastic bar on [x0, x0 + L], fixed at x0 (the grid's x- face)
!> and free at x0 + L, started in its first mode, v(x, 0) = A sin(beta (x - x0)),
!> beta = pi/(2L). Exact: v = A sin(beta X) cos(omega t), u = (A/omega) sin(beta X)
!> sin(omega t), omega = beta c, c = sqrt(M/rho) with the constrained modulus M
!> (1D is uniaxial strain).
module dpmpm_benchmarks
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t
  use dpmpm_particles, only: particle_set_t
  use dpmpm_materials, only: material_t
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM
  implicit none
  private
  public :: benchmark_setup, benchmark_errors, benchmark_error_names, nbench_err

  real(wp), parameter :: pi = acos(-1.0_wp)
  integer, parameter :: nbench_err = 2
  character(len=24), parameter :: benchmark_error_names(nbench_err) = [character(len=24) :: &
    'error_velocity', 'error_displacement']

contains

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
    end select
  end function benchmark_errors

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
