!> The input of a run, collectively: rank 0 reads the file as text and broadcasts it
!> (length, then characters); every rank parses the same text into its own config_t
!> (dpmpm_input_read). Rank 0 resolves restart = 'latest' against its file system and
!> checks the values (dpmpm_input_check), then tells every rank the verdict. On any
!> problem rank 0 prints all of them, one per line, and every rank returns status 2; the
!> caller stops. Values that are valid but do nothing in the scene are printed by rank 0 as
!> warnings, and the run goes on. A new input variable is declared in config_t, read in its group's
!> namelist (which also gives its echo and its place in messages), checked and used:
!> nothing here changes.
module dpmpm_input
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use dpmpm_config, only: config_t, resolve_geostatic
  use dpmpm_input_problems, only: input_problems_t, add_value, g_run, g_motion
  use dpmpm_kinds, only: wp, i8
  use dpmpm_strings, only: i8toa, rtoa
  use dpmpm_h5_salvage, only: last_record
  use dpmpm_input_read, only: load_text, parse_input
  use dpmpm_input_check, only: check_config
  use dpmpm_motion, only: load_motions, bcast_motions, motion_values_ok
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Comm_size, MPI_Bcast, MPI_INTEGER, &
                     MPI_CHARACTER
  implicit none
  private
  public :: read_input, print_config, input_ok, input_refused

  !> Status of read_input: the input is good, or it was refused (the problems are printed).
  integer, parameter :: input_ok = 0, input_refused = 2

contains

  !> Read, parse and check the input file (collective over comm). status = input_ok, or
  !> input_refused after rank 0 printed every problem to stderr (the exit code of a refused
  !> input is 2). With restart_latest (the command line's --restart) the input's &run
  !> restart is taken as 'latest': continue from <dir>/<name>.ckpt.h5 when it exists, else
  !> start afresh, unless the output holds a finished run: that is refused unless start_over
  !> (the command line's --start-over) asks to run it again.
  subroutine read_input(filename, comm, cfg, status, restart_latest, start_over)
    character(len=*), intent(in) :: filename
    type(MPI_Comm), intent(in) :: comm
    type(config_t), intent(out) :: cfg
    integer, intent(out) :: status
    logical, intent(in), optional :: restart_latest, start_over
    type(input_problems_t) :: pb
    character(len=:), allocatable :: text
    integer :: rank, nranks, nprob

    call MPI_Comm_rank(comm, rank)
    call MPI_Comm_size(comm, nranks)
    call pb%init(filename)
    if (rank == 0) call load_text(filename, text, pb)
    call bcast_text(text, pb%nprob == 0, comm)
    if (.not. allocated(text)) then
      call refuse(pb, rank, status)
      return
    end if

    call parse_input(text, cfg, pb)
    nprob = 0
    if (rank == 0) then
      if (present(restart_latest)) then
        if (restart_latest) cfg%restart = 'latest'
      end if
      call resolve_latest(cfg, pb, present_and_true(start_over))
      call check_config(pb, cfg, nranks)
      ! The &motion files, when the choices that read them are good (their problems are
      ! reported with the others).
      if (pb%read_ok(g_motion) .and. motion_values_ok(cfg)) call load_motions(cfg, pb, filename)
      nprob = pb%nprob
    end if
    call MPI_Bcast(nprob, 1, MPI_INTEGER, 0, comm)
    if (nprob > 0) then
      call refuse(pb, rank, status)
      return
    end if
    if (rank == 0) call pb%write_warnings(error_unit)
    ! The initial state of level ground, where asked for (checked above).
    call resolve_geostatic(cfg)
    call bcast_motions(cfg, comm)
    ! The checkpoint to continue from, as rank 0 found it.
    call MPI_Bcast(cfg%restart, len(cfg%restart), MPI_CHARACTER, 0, comm)
    cfg%input_file = filename
    call pb%free()
    status = input_ok
  end subroutine read_input

  !> Rank 0's text on every rank: its length (-1 when rank 0 has none to give, ok false),
  !> then its characters. text stays unallocated on every rank when there is none.
  subroutine bcast_text(text, ok, comm)
    character(len=:), allocatable, intent(inout) :: text
    logical, intent(in) :: ok
    type(MPI_Comm), intent(in) :: comm
    integer :: rank, n
    call MPI_Comm_rank(comm, rank)
    n = -1
    if (rank == 0 .and. ok) n = len(text)
    call MPI_Bcast(n, 1, MPI_INTEGER, 0, comm)
    if (n < 0) then
      if (allocated(text)) deallocate (text)
      return
    end if
    if (rank /= 0) then
      if (allocated(text)) deallocate (text)
      allocate (character(len=n) :: text)
    end if
    if (n > 0) call MPI_Bcast(text, n, MPI_CHARACTER, 0, comm)
  end subroutine bcast_text

  !> Rank 0 prints the problems, then the warnings; every rank returns input_refused.
  subroutine refuse(pb, rank, status)
    type(input_problems_t), intent(inout) :: pb
    integer, intent(in) :: rank
    integer, intent(out) :: status
    if (rank == 0) call pb%write(error_unit)
    if (rank == 0) call pb%write_warnings(error_unit)
    call pb%free()
    status = input_refused
  end subroutine refuse

  !> Print every parameter of the input, defaults included, as namelist groups that read
  !> back as the same input (the groups' echo made by their readers).
  subroutine print_config(cfg, unit)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: unit
    write (unit, '(a)') '! dpmpm: parameters of '//trim(cfg%input_file)//', defaults included'
    if (allocated(cfg%echo)) write (unit, '(a)', advance='no') cfg%echo
  end subroutine print_config

  !> restart = 'latest': the run's own checkpoint <dir>/<name>.ckpt.h5 when it exists (the
  !> run continues), else none (the run starts at t = 0); said on standard output. This
  !> lets a chain of batch jobs run the same input again and again. Without a checkpoint,
  !> an output <dir>/<name>.h5 whose last record reached this input's t_end or max_steps is
  !> a finished run: starting again would replace it, so that is a problem in pb unless
  !> start_over.
  subroutine resolve_latest(cfg, pb, start_over)
    type(config_t), intent(inout) :: cfg
    type(input_problems_t), intent(inout) :: pb
    logical, intent(in) :: start_over
    character(len=:), allocatable :: path, out
    logical :: exists, found
    integer(i8) :: step
    real(wp) :: time
    if (trim(cfg%restart) /= 'latest') return
    path = trim(cfg%output_dir)//'/'//trim(cfg%name)//'.ckpt.h5'
    inquire (file=path, exist=exists)
    if (exists) then
      cfg%restart = path
      write (output_unit, '(a)') 'dpmpm: restart = ''latest'': continuing from '//path
    else
      cfg%restart = ''
      out = trim(cfg%output_dir)//'/'//trim(cfg%name)//'.h5'
      inquire (file=out, exist=exists)
      found = .false.
      if (exists) call last_record(out, step, time, found)
      if (found) found = time >= cfg%t_end*(1.0_wp - 1.0e-12_wp) .or. step >= cfg%max_steps
      if (found .and. .not. start_over) then
        call add_value(pb, g_run, 1, 'restart', '''latest''', 'there is no checkpoint '// &
                       path//' to continue, and '//out//' holds a finished run (step '// &
                       i8toa(step)//', t = '//rtoa(time)//'); dpmpm --restart --start-over '// &
                       'runs it again from t = 0, replacing that output')
      else if (found) then
        write (output_unit, '(a)') 'dpmpm: restart = ''latest'' with --start-over: no '// &
          'checkpoint '//path//'; running the finished run of '//out//' again from t = 0'
      else
        write (output_unit, '(a)') 'dpmpm: restart = ''latest'': no checkpoint '//path// &
          ' yet, starting at t = 0'
      end if
    end if
    flush (output_unit)
  end subroutine resolve_latest

  !> An optional flag given and true.
  pure logical function present_and_true(flag)
    logical, intent(in), optional :: flag
    present_and_true = .false.
    if (present(flag)) present_and_true = flag
  end function present_and_true

end module dpmpm_input
