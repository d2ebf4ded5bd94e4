!> The dpmpm program: command line, input, scene, run.
module dpmpm_app
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Comm_size
  use dpmpm_config, only: config_t
  use dpmpm_input, only: read_input, print_config
  use dpmpm_simulation, only: run_scene
  use dpmpm_posix, only: catch_stop_signals
  use dpmpm_build_info, only: dpmpm_version, git_commit
  implicit none
  private
  public :: run_app

  character(len=*), parameter :: usage = 'usage: dpmpm [--check] [--restart [--start-over]] '// &
                                         'scene.nml | --help | --version'

contains

  !> Run dpmpm on the ranks of comm: `dpmpm [--check] [--restart] scene.nml`, `dpmpm --help`,
  !> `dpmpm --version`. With --check, read and check the input and print the resolved parameters.
  !> The exit status for the program (the same on every rank): 0 done, 2 bad command line,
  !> restart or time step, 3 stopped early with a checkpoint, 4 stopped by the run monitor.
  integer function run_app(comm) result(status)
    type(MPI_Comm), intent(in) :: comm
    type(config_t) :: cfg
    character(len=:), allocatable :: arg, file
    logical :: check_only, restart_latest, start_over
    integer :: rank, nranks, k, n

    status = 0
    call MPI_Comm_rank(comm, rank)
    call MPI_Comm_size(comm, nranks)
    check_only = .false.
    restart_latest = .false.
    start_over = .false.
    file = ''
    do k = 1, command_argument_count()
      call get_command_argument(k, length=n)
      allocate (character(len=n) :: arg)
      call get_command_argument(k, arg)
      if (arg == '--help' .or. arg == '-h') then
        if (rank == 0) call print_help()
        return
      else if (arg == '--version') then
        if (rank == 0) write (output_unit, '(a)') version_text()
        return
      else if (arg == '--check') then
        check_only = .true.
      else if (arg == '--restart') then
        restart_latest = .true.
      else if (arg == '--start-over') then
        start_over = .true.
      else if (arg(1:min(1, n)) == '-' .or. len(file) > 0) then
        status = usage_error(rank, 'unexpected argument '''//arg//'''')
        return
      else
        file = arg
      end if
      deallocate (arg)
    end do
    if (len(file) == 0) then
      status = usage_error(rank, 'no input file given')
      return
    end if

    call read_input(file, comm, cfg, status, restart_latest, start_over)
    if (status /= 0) return
    if (check_only) then
      if (rank == 0) call print_config(cfg, output_unit)
      return
    end if
    if (rank == 0) then
      write (output_unit, '(a,i0,a)') version_text()//': '//file//' on ', nranks, &
        trim(merge(' rank ', ' ranks', nranks == 1))
      flush (output_unit)
    end if
    ! SIGTERM and SIGUSR1 (sent by batch schedulers before the kill) now only set a flag:
    ! the run writes a checkpoint and stops at the next look (every few steps).
    if (.not. catch_stop_signals() .and. rank == 0) &
      write (error_unit, '(a)') 'dpmpm: warning: cannot catch SIGTERM and SIGUSR1; a '// &
      'scheduler''s stop signal will end the run without a checkpoint'
    status = run_scene(cfg, comm)
  end function run_app

  !> "dpmpm 0.1.0 (commit 0123456789ab)"
  function version_text() result(s)
    character(len=:), allocatable :: s
    s = 'dpmpm '//dpmpm_version//' (commit '//git_commit//')'
  end function version_text

  !> What dpmpm does, its command line, its exit codes and where to read more.
  subroutine print_help()
    write (output_unit, '(a)') version_text()//': double-point material point method '// &
      '(2P-MPM) with MLS shape functions', &
      '', &
      usage, &
      '', &
      '  mpirun -n N dpmpm scene.nml           run the scene on N ranks', &
      '  mpirun -n N dpmpm --check scene.nml   check the input and print every resolved', &
      '                                        parameter (itself a valid input file)', &
      '  mpirun -n N dpmpm --restart scene.nml continue from <dir>/<name>.ckpt.h5 when it', &
      '                                        exists, else start at t = 0 (&run restart =', &
      '                                        ''latest''): the same line for every job of a', &
      '                                        chain; where there is no checkpoint and', &
      '                                        <dir>/<name>.h5 holds a finished run, it', &
      '                                        stops (exit code 2) instead of replacing it', &
      '  mpirun -n N dpmpm --restart --start-over scene.nml', &
      '                                        the same, but a finished run without a', &
      '                                        checkpoint is run again from t = 0', &
      '  dpmpm --help                          this text', &
      '  dpmpm --version                       version and git commit of the build', &
      '', &
      'The scene is one Fortran namelist file (&run, &grid, &shape, &material, &region,', &
      '&boundary, &load, &output, &benchmark); the output is <dir>/<name>.h5 with an XDMF', &
      'sidecar <name>.xmf. On SIGTERM, SIGUSR1 or &run max_wall_time the run writes', &
      '<dir>/<name>.ckpt.h5 and stops; &run restart continues from it.', &
      '', &
      'Exit codes: 0 finished, 2 bad input or command line, 3 stopped early with a', &
      'checkpoint (continue it), 4 stopped by the run monitor (the run grew or a value', &
      'became non-finite), 1 error during the run.', &
      '', &
      'Documentation: doc/input.md (every input variable), doc/output.md (the HDF5 layout).'
    flush (output_unit)
  end subroutine print_help

  !> Print the usage on rank 0; the exit status 2 of a bad command line.
  integer function usage_error(rank, why) result(status)
    integer, intent(in) :: rank
    character(len=*), intent(in) :: why
    if (rank == 0) then
      write (error_unit, '(a)') 'dpmpm: '//why
      write (error_unit, '(a)') usage
      write (error_unit, '(a)') 'dpmpm --help says more'
      flush (error_unit)
    end if
    status = 2
  end function usage_error

end module dpmpm_app
