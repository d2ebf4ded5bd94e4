!> The element-test program (app/dpmpm_element.f90): `dpmpm_element [--check] test.nml`
!> reads and checks the test (dpmpm_element_input), runs it (dpmpm_element_path) and
!> writes its HDF5 file (dpmpm_element_output). One material point: it runs on one rank.
!> Exit status: 0 done, 1 a step did not converge (the file holds the steps before it),
!> 2 a refused input or command line.
module dpmpm_element_app
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use mpi_f08, only: MPI_Comm, MPI_Comm_size
  use dpmpm_kinds, only: wp
  use dpmpm_build_info, only: dpmpm_version, git_commit
  use dpmpm_element_config, only: element_cfg_t, path_from_name
  use dpmpm_element_input, only: read_element_input
  use dpmpm_element_output, only: write_element_file
  use dpmpm_element_path, only: element_history_t, run_element, is_undrained, element_ok, &
                                element_inadmissible
  use dpmpm_input_problems, only: input_problems_t, add_raw
  use dpmpm_materials, only: material_t, materials_from_config
  use dpmpm_model_table, only: model_table, scene_state_names
  implicit none
  private
  public :: run_element_app

contains

  !> Run the program on comm (one rank) with the command line's arguments; the exit status.
  integer function run_element_app(comm) result(status)
    type(MPI_Comm), intent(in) :: comm
    character(len=4096) :: arg, file
    integer :: nargs, k, nranks
    logical :: check_only
    call MPI_Comm_size(comm, nranks)
    nargs = command_argument_count()
    check_only = .false.
    file = ''
    do k = 1, nargs
      call get_command_argument(k, arg)
      select case (trim(arg))
      case ('--help', '-h')
        call print_help()
        status = 0
        return
      case ('--version')
        write (output_unit, '(a)') 'dpmpm_element '//dpmpm_version//' (commit '//git_commit//')'
        status = 0
        return
      case ('--check')
        check_only = .true.
      case default
        if (len_trim(file) > 0 .or. arg(1:1) == '-') then
          write (error_unit, '(a)') 'dpmpm_element: unexpected argument '''//trim(arg)// &
            '''; dpmpm_element --help says more'
          status = 2
          return
        end if
        file = arg
      end select
    end do
    if (len_trim(file) == 0) then
      write (error_unit, '(a)') 'dpmpm_element: no input file; dpmpm_element --help says more'
      status = 2
      return
    end if
    if (nranks /= 1) then
      write (error_unit, '(a,i0,a)') 'dpmpm_element: an element test is one material point: '// &
        'run it on one rank, not ', nranks
      status = 2
      return
    end if
    status = element_test(trim(file), check_only)
  end function run_element_app

  !> Read, check, run and write the element test of file; the exit status.
  integer function element_test(file, check_only) result(status)
    character(len=*), intent(in) :: file
    logical, intent(in) :: check_only
    type(input_problems_t) :: pb
    type(element_cfg_t) :: cfg
    type(material_t), allocatable :: mats(:)
    type(element_history_t) :: hist
    character(len=24), allocatable :: names(:)
    real(wp), allocatable :: cols(:, :)
    integer :: path, nc

    call pb%init(file)
    call read_element_input(file, cfg, pb)
    if (pb%nprob > 0) then
      call pb%write(error_unit)
      status = 2
      return
    end if
    if (check_only) then
      write (output_unit, '(a)') '! dpmpm_element: parameters of '//file//', defaults included'
      write (output_unit, '(a)', advance='no') cfg%echo
      status = 0
      return
    end if
    call materials_from_config([cfg%material], mats)
    call run_element(cfg, mats(1), hist)
    if (hist%status == element_inadmissible) then
      call add_raw(pb, '&element: '//hist%message)
      call pb%write(error_unit)
      status = 2
      return
    end if

    ! the series of the file: every path has these, undrained ones the excess pore
    ! pressure, and a test with an initial void ratio the void ratio
    path = path_from_name(cfg%path)
    names = [character(len=24) :: 'time', 'cycle', 'p', 'q', 'axial_strain', &
             'volumetric_strain', 'shear_strain', 'shear_stress', 'volume_ratio', 'residual']
    nc = hist%nrec
    cols = reshape([hist%time(1:nc), hist%cycle(1:nc), hist%p(1:nc), hist%q(1:nc), &
                    hist%axial_strain(1:nc), hist%volumetric_strain(1:nc), &
                    hist%shear_strain(1:nc), hist%shear_stress(1:nc), hist%volume_ratio(1:nc), &
                    hist%residual(1:nc)], [nc, size(names)])
    if (is_undrained(path)) call add_column('excess_pore_pressure', hist%excess_pore_pressure)
    if (cfg%void_ratio > 0.0_wp) call add_column('void_ratio', hist%void_ratio)
    associate (model => model_table(mats(1)%model))
      call write_element_file(cfg, model%name, merge('complete', 'stopped ', &
                              hist%status == element_ok), message_of(hist), hist%nplanned, &
                              hist%strain(:, 1:hist%nrec), hist%stress(:, 1:hist%nrec), &
                              hist%state(:, 1:hist%nrec), &
                              scene_state_names([mats(1)%model], [mats(1)%umat_nstatev]), &
                              hist%iterations(1:hist%nrec), names, cols)
    end associate
    write (output_unit, '(a,i0,a,i0,a)') 'dpmpm_element: '//trim(cfg%path)//' ('// &
      trim(cfg%control)//' control), ', nc - 1, ' of ', hist%nplanned, ' steps: '// &
      'p'' = '//num(hist%p(nc))//' Pa, q = '//num(hist%q(nc))//' Pa, eps_a = '// &
      num(hist%axial_strain(nc))//', eps_v = '//num(hist%volumetric_strain(nc))
    write (output_unit, '(a)') 'written '//trim(cfg%output)
    status = 0
    if (hist%status /= element_ok) then
      write (error_unit, '(a)') 'dpmpm_element: '//file//': the path stopped: '//hist%message
      status = 1
    end if

  contains

    !> One more series of the file.
    subroutine add_column(name, v)
      character(len=*), intent(in) :: name
      real(wp), intent(in) :: v(:)
      real(wp), allocatable :: c(:, :)
      names = [character(len=24) :: names, name]
      allocate (c(hist%nrec, size(cols, 2) + 1))
      c(:, 1:size(cols, 2)) = cols
      c(:, size(c, 2)) = v(1:hist%nrec)
      call move_alloc(c, cols)
    end subroutine add_column

  end function element_test

  !> The message of a history ('' when the path was complete).
  function message_of(hist) result(s)
    type(element_history_t), intent(in) :: hist
    character(len=:), allocatable :: s
    s = ''
    if (allocated(hist%message)) s = hist%message
  end function message_of

  !> A real as short text.
  function num(x) result(t)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: t
    character(len=24) :: buf
    write (buf, '(es12.5)') x
    t = trim(adjustl(buf))
  end function num

  !> The usage, the input and the exit codes.
  subroutine print_help()
    write (output_unit, '(a)') 'dpmpm_element '//dpmpm_version//' (commit '//git_commit// &
      '): one material point of a dpmpm model along a laboratory path', &
      '', &
      'usage:', &
      '  dpmpm_element test.nml           run the test, write the HDF5 file of &element output', &
      '  dpmpm_element --check test.nml   check the input, print its parameters', &
      '  dpmpm_element --help | --version', &
      '', &
      'The input holds one &material (as in a scene) and one &element group (doc/input.md,', &
      '"Element tests"); python3 -m dpmpm element FILE.h5 plots the result.', &
      '', &
      'exit status: 0 done; 1 a step did not converge (the file holds the steps before it);', &
      '  2 a refused input or command line'
  end subroutine print_help

end module dpmpm_element_app
