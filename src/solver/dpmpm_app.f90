!> The dpmpm program: command line, input, scene, run.
module dpmpm_app
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank
  use dpmpm_config, only: config_t
  use dpmpm_input, only: read_input, print_config
  use dpmpm_error, only: clean_stop
  use dpmpm_simulation, only: run_scene
  use dpmpm_posix, only: catch_stop_signals
  implicit none
  private
  public :: run_app

  character(len=*), parameter :: usage = 'usage: dpmpm [--check] scene.nml'

contains

  !> Run dpmpm on the ranks of comm: `dpmpm [--check] scene.nml`. With --check, read and check
  !> the input and print the resolved parameters; a bad command line stops with exit code 2.
  subroutine run_app(comm)
    type(MPI_Comm), intent(in) :: comm
    type(config_t) :: cfg
    character(len=:), allocatable :: arg, file
    logical :: check_only
    integer :: rank, k, n

    call MPI_Comm_rank(comm, rank)
    check_only = .false.
    file = ''
    do k = 1, command_argument_count()
      call get_command_argument(k, length=n)
      allocate (character(len=n) :: arg)
      call get_command_argument(k, arg)
      if (arg == '--check') then
        check_only = .true.
      else if (arg(1:min(1, n)) == '-' .or. len(file) > 0) then
        call usage_stop(rank, 'unexpected argument '''//arg//'''')
      else
        file = arg
      end if
      deallocate (arg)
    end do
    if (len(file) == 0) call usage_stop(rank, 'no input file given')

    call read_input(file, comm, cfg)
    if (check_only) then
      if (rank == 0) call print_config(cfg, output_unit)
      return
    end if
    ! SIGTERM and SIGUSR1 (sent by batch schedulers before the kill) now only set a flag:
    ! the run writes a checkpoint and stops at the next look (every few steps).
    if (.not. catch_stop_signals() .and. rank == 0) &
      write (error_unit, '(a)') 'dpmpm: warning: cannot catch SIGTERM and SIGUSR1; a '// &
      'scheduler''s stop signal will end the run without a checkpoint'
    call run_scene(cfg, comm)
  end subroutine run_app

  !> Print the usage on rank 0 and stop every rank with exit code 2.
  subroutine usage_stop(rank, why)
    integer, intent(in) :: rank
    character(len=*), intent(in) :: why
    if (rank == 0) then
      write (error_unit, '(a)') 'dpmpm: '//why
      write (error_unit, '(a)') usage
      flush (error_unit)
    end if
    call clean_stop(2)
  end subroutine usage_stop

end module dpmpm_app
