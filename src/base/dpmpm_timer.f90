!> Wall-clock timers for the stages of a step, reported at the end of a run.
module dpmpm_timer
  use dpmpm_kinds, only: wp
  use mpi_f08, only: MPI_Wtime
  implicit none
  private
  public :: timer_set_t, ntimers, timer_names
  public :: t_total, t_stencil, t_p2g, t_halo, t_nodal, t_g2p, t_stress, t_migrate, t_output, &
            t_checkpoint

  integer, parameter :: t_total = 1, t_stencil = 2, t_p2g = 3, t_halo = 4, t_nodal = 5, &
                        t_g2p = 6, t_stress = 7, t_migrate = 8, t_output = 9, t_checkpoint = 10
  integer, parameter :: ntimers = 10
  character(len=12), parameter :: timer_names(ntimers) = [character(len=12) :: &
    'total', 'stencil', 'p2g', 'halo', 'nodal', 'g2p', 'stress', 'migrate', 'output', 'checkpoint']

  !> Accumulated seconds per stage, and how many times each stage ran.
  type :: timer_set_t
    real(wp) :: acc(ntimers) = 0.0_wp
    real(wp) :: started(ntimers) = 0.0_wp
    integer :: calls(ntimers) = 0
  contains
    procedure :: tic => timer_tic
    procedure :: toc => timer_toc
  end type timer_set_t

contains

  !> Start stage k.
  subroutine timer_tic(self, k)
    class(timer_set_t), intent(inout) :: self
    integer, intent(in) :: k
    self%started(k) = MPI_Wtime()
  end subroutine timer_tic

  !> Stop stage k and add the elapsed time.
  subroutine timer_toc(self, k)
    class(timer_set_t), intent(inout) :: self
    integer, intent(in) :: k
    self%acc(k) = self%acc(k) + (MPI_Wtime() - self%started(k))
    self%calls(k) = self%calls(k) + 1
  end subroutine timer_toc

end module dpmpm_timer
