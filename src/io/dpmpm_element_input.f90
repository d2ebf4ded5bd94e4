!> The input of an element test (app/dpmpm_element.f90): one namelist file with one
!> &material group, the same variables as in a scene (dpmpm_vars_material.inc), so that a
!> material block can be copied from a scene, and one &element group
!> (dpmpm_vars_element.inc). Every problem is collected and reported at once, in the
!> words of the scene reader: group, variable, value and what is allowed.
!> The &material values are checked by the scene's own checks (check_config on a scene of
!> defaults that holds this one material), so that a check written for a new model
!> applies here as it stands.
module dpmpm_element_input
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, material_cfg_t, name_len, max_props, max_table
  use dpmpm_element_config, only: element_cfg_t, element_paths, element_controls, &
                                  element_senses, path_from_name, target_names, ntargets, &
                                  target_of, initial_effective_stress, path_isotropic, &
                                  path_oedometer, path_triaxial_drained, path_triaxial_undrained, &
                                  path_simple_shear_drained, path_simple_shear_undrained, &
                                  path_plane_strain_undrained
  use dpmpm_model_table, only: model_from_name, model_table
  use dpmpm_input_problems, only: input_problems_t, g_material, add_raw, add_file_problem, real_ok, &
                                  prop_unset, count_given
  use dpmpm_input_read, only: load_text, split_records, next_eol
  use dpmpm_input_check, only: check_config
  use dpmpm_nml_text, only: nml_records, nml_echo, nml_names
  use dpmpm_strings, only: itoa, rtoa, rtoa_list, quote, lower
  implicit none
  private
  public :: read_element_input

  !> Buffer length of the strings read (a longer value is seen and refused, not cut).
  integer, parameter :: long_len = 4096

contains

  !> Read and check the element test of filename into cfg; every problem goes to pb (its
  !> file name set by the caller's pb%init), none when the input is good.
  subroutine read_element_input(filename, cfg, pb)
    character(len=*), intent(in) :: filename
    type(element_cfg_t), intent(out) :: cfg
    type(input_problems_t), intent(inout) :: pb
    character(len=:), allocatable :: text, records(:)
    integer :: line_material, line_element, n_material, n_element
    logical :: ok_material, ok_element

    call load_text(filename, text, pb)
    if (pb%nprob > 0) return
    cfg%input_file = filename
    cfg%input_text = text
    cfg%echo = ''
    call scan_groups(pb, text, n_material, line_material, n_element, line_element)
    call split_records(text, records)
    ok_material = .false.
    ok_element = .false.
    if (n_material == 0) call add_file_problem(pb, 'no &material group: an element test '// &
                                               'needs one (the variables of a scene''s &material)')
    if (n_material > 1) call add_file_problem(pb, '&material is given '//itoa(n_material)// &
                                              ' times: an element test takes one material')
    if (n_element == 0) call add_file_problem(pb, 'no &element group: it is required (path, '// &
                                              'control, p0 and the target of the path)')
    if (n_element > 1) call add_file_problem(pb, '&element is given '//itoa(n_element)// &
                                             ' times: give it once')
    if (n_material == 1) then
      call pb%opened(g_material, line_material)
      call read_material(pb, records, cfg, ok_material)
    end if
    if (n_element == 1) call read_element(pb, records, cfg, line_element, ok_element)
    if (ok_material) call check_material(pb, cfg%material)
    if (ok_element) call check_element(pb, cfg, line_element)
  end subroutine read_element_input

  !> Find the group openings ("&name" first on a line): how many &material and &element
  !> groups there are and the line of the first of each; any other group is a problem.
  subroutine scan_groups(pb, text, n_material, line_material, n_element, line_element)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: text
    integer, intent(out) :: n_material, line_material, n_element, line_element
    integer :: pos, eol, line, i, j
    character(len=:), allocatable :: word
    n_material = 0
    n_element = 0
    line_material = 0
    line_element = 0
    pos = 1
    line = 0
    do while (pos <= len(text))
      line = line + 1
      eol = next_eol(text, pos)
      i = pos
      do while (i < eol)
        if (text(i:i) /= ' ' .and. text(i:i) /= char(9)) exit
        i = i + 1
      end do
      if (i < eol) then
        if (text(i:i) == '&') then
          j = i + 1
          do while (j < eol)
            if (scan(lower(text(j:j)), 'abcdefghijklmnopqrstuvwxyz0123456789_') == 0) exit
            j = j + 1
          end do
          word = lower(text(i + 1:j - 1))
          select case (word)
          case ('end')
          case ('material')
            n_material = n_material + 1
            if (n_material == 1) line_material = line
          case ('element')
            n_element = n_element + 1
            if (n_element == 1) line_element = line
          case default
            call add_file_problem(pb, '&'//word//' (line '//itoa(line)//'): unknown group; '// &
                                  'an element test has the groups &material and &element')
          end select
        end if
      end if
      pos = eol + 1
    end do
  end subroutine scan_groups

  !> Read the &material group (its variables: dpmpm_vars_material.inc) into cfg%material.
  subroutine read_material(pb, records, cfg, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(element_cfg_t), intent(inout) :: cfg
    logical, intent(out) :: ok
    include "dpmpm_vars_material_local.inc"
    include "dpmpm_vars_material_namelist.inc"
    integer :: ios, nprops
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    include "dpmpm_vars_material_default.inc"
    ! props not given stay at a mark, so that NPROPS is the count of those given
    umat_props = prop_unset
    read (records, nml=material, iostat=ios, iomsg=msg)
    nprops = count_given(umat_props)
    call nml_records(echo)
    write (echo, nml=material)
    call took_group(pb, 'material', ios, msg, echo, cfg%echo, ok)
    if (.not. ok) return
    associate (dest => cfg%material)
      include "dpmpm_vars_material_kept.inc"
      dest%umat_nprops = nprops
    end associate
  end subroutine read_material

  !> Read the &element group (its variables: dpmpm_vars_element.inc) into cfg.
  subroutine read_element(pb, records, cfg, line, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: records(:)
    type(element_cfg_t), intent(inout) :: cfg
    integer, intent(in) :: line
    logical, intent(out) :: ok
    include "dpmpm_vars_element_local.inc"
    include "dpmpm_vars_element_namelist.inc"
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: echo(:)
    include "dpmpm_vars_element_default.inc"
    read (records(max(1, line):), nml=element, iostat=ios, iomsg=msg)
    call nml_records(echo)
    write (echo, nml=element)
    call took_group(pb, 'element', ios, msg, echo, cfg%echo, ok)
    if (.not. ok) return
    associate (dest => cfg)
      include "dpmpm_vars_element_kept.inc"
    end associate
  end subroutine read_element

  !> After the read of group (status ios, message msg) and the write of its namelist into
  !> echo: ok tells whether it was read; if so its echo joins cfg_echo, else the error is
  !> a problem that names the group's variables.
  subroutine took_group(pb, group, ios, msg, echo, cfg_echo, ok)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: group, msg, echo(:)
    integer, intent(in) :: ios
    character(len=:), allocatable, intent(inout) :: cfg_echo
    logical, intent(out) :: ok
    character(len=:), allocatable :: what
    ok = ios == 0
    if (ok) then
      cfg_echo = cfg_echo//nml_echo(echo)
      return
    end if
    what = trim(msg)
    if (ios < 0) what = 'the namelist reader did not find this group (is it terminated by "/"?)'
    call add_raw(pb, '&'//group//': cannot read the group: '//what//'; the variables of &'// &
                 group//' are '//nml_names(echo))
  end subroutine took_group

  !> A TEXT value longer than its variable (the list's macros call this).
  subroutine check_length(pb, group, var, value, limit)
    type(input_problems_t), intent(inout) :: pb
    character(len=*), intent(in) :: group, var, value
    integer, intent(in) :: limit
    if (len_trim(value) > limit) call add_raw(pb, '&'//group//' '//var//' is '// &
                                              itoa(len_trim(value))//' characters long: at most '// &
                                              itoa(limit)//' are allowed')
  end subroutine check_length

  !> The checks of a scene's &material, and a model that has a stress of its own.
  subroutine check_material(pb, m)
    type(input_problems_t), intent(inout) :: pb
    type(material_cfg_t), intent(in) :: m
    type(config_t) :: scene
    integer :: code
    allocate (scene%materials(1), scene%regions(0), scene%loads(0))
    scene%materials(1) = m
    call check_config(pb, scene, 1)
    code = model_from_name(m%model)
    if (code > 0) then
      if (.not. model_table(code)%skeleton .or. .not. model_table(code)%stressed) &
        call add_raw(pb, '&material model = '//quote(m%model)//': an element test needs '// &
                     'the model of a soil skeleton: '//skeleton_models())
    end if
  end subroutine check_material

  !> The models that may be the skeleton of a soil, comma separated.
  function skeleton_models() result(s)
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(model_table)
      if (.not. model_table(k)%skeleton) cycle
      if (len(s) > 0) s = s//', '
      s = s//trim(model_table(k)%name)
    end do
  end function skeleton_models

  !> Every value of &element (opening at line), alone and against the others.
  subroutine check_element(pb, cfg, line)
    type(input_problems_t), intent(inout) :: pb
    type(element_cfg_t), intent(in) :: cfg
    integer, intent(in) :: line
    integer :: path, k, need
    logical :: strain, cyclic, shear, stress_ok
    real(wp) :: s0(6), y0, targets(ntargets)
    character(len=:), allocatable :: where

    where = ' [line '//itoa(line)//']'
    path = path_from_name(cfg%path)
    if (path == 0) call bad('path', quote(cfg%path), 'the paths are '//listed(element_paths))
    if (.not. any(cfg%control == element_controls)) &
      call bad('control', quote(cfg%control), 'the controls are '//listed(element_controls))
    if (.not. any(cfg%sense == element_senses)) &
      call bad('sense', quote(cfg%sense), 'the senses are '//listed(element_senses))
    strain = cfg%control == 'strain'
    cyclic = cfg%cycles > 0
    shear = path == path_simple_shear_drained .or. path == path_simple_shear_undrained

    ! the initial effective stress
    stress_ok = .true.
    if (any(cfg%initial_stress /= 0.0_wp)) then
      if (cfg%p0 /= 0.0_wp) call bad('p0', rtoa(cfg%p0), 'give the initial stress once: '// &
                                     'p0 (with k0) or initial_stress, not both')
      if (cfg%k0 /= 1.0_wp) call bad('k0', rtoa(cfg%k0), 'initial_stress gives every normal '// &
                                     'stress: leave k0 out')
      if (.not. (all(abs(cfg%initial_stress) < huge(1.0_wp)) .and. &
                 -sum(cfg%initial_stress) > 0.0_wp)) then
        call bad('initial_stress', rtoa_list(cfg%initial_stress), 'must be finite with a '// &
                 'mean effective stress p'' = -(sxx + syy + szz)/3 > 0 (Pa, tension positive)')
        stress_ok = .false.
      end if
    else
      if (.not. real_ok(cfg%p0, gt=0.0_wp)) then
        call bad('p0', rtoa(cfg%p0), 'must be > 0 (Pa, the initial mean effective stress, '// &
                 'compression positive), or give initial_stress')
        stress_ok = .false.
      end if
      if (.not. real_ok(cfg%k0, gt=0.0_wp)) then
        call bad('k0', rtoa(cfg%k0), 'must be > 0 (sigma''_r / sigma''_a of the initial state)')
        stress_ok = .false.
      end if
    end if

    ! the course of the path
    if (cfg%steps < 1) call bad('steps', itoa(cfg%steps), 'must be >= 1')
    if (.not. real_ok(cfg%dt, gt=0.0_wp)) call bad('dt', rtoa(cfg%dt), 'must be > 0 (s)')
    if (.not. real_ok(cfg%void_ratio, ge=0.0_wp)) call bad('void_ratio', rtoa(cfg%void_ratio), &
                                                            'must be >= 0 (0 = no void ratio '// &
                                                            'in the output)')
    if (.not. real_ok(cfg%tolerance, gt=0.0_wp, lt=1.0e-2_wp)) &
      call bad('tolerance', rtoa(cfg%tolerance), 'must be in (0, 0.01): the largest stress '// &
               'condition of a step over the stress scale')
    if (cfg%max_iterations < 1) call bad('max_iterations', itoa(cfg%max_iterations), &
                                         'must be >= 1')
    if (len_trim(cfg%output) == 0) call bad('output', "''", 'must name the HDF5 file to write')
    if (cfg%cycles < 0) call bad('cycles', itoa(cfg%cycles), 'must be >= 0 (0 = monotonic)')
    if (shear .and. cfg%sense /= 'compression') &
      call bad('sense', quote(cfg%sense), 'simple shear has no compression or extension: '// &
               'the sign of shear_strain or shear_stress gives its direction (leave sense out)')
    if (path == 0) return

    targets = [cfg%axial_strain, cfg%volumetric_strain, cfg%shear_strain, cfg%deviator, &
               cfg%mean_stress, cfg%axial_stress, cfg%shear_stress]
    if (cyclic) then
      if (path == path_isotropic .or. path == path_oedometer) &
        call bad('cycles', itoa(cfg%cycles), 'a cyclic path is triaxial or simple shear; '// &
                 trim(cfg%path)//' is monotonic (cycles = 0)')
      if (.not. real_ok(cfg%amplitude, gt=0.0_wp)) call bad('amplitude', rtoa(cfg%amplitude), &
        'must be > 0 on a cyclic path: of '//merge('eps_a or gamma', 'q or tau      ', strain)// &
        ' about the initial value')
      if (modulo(cfg%steps, 4) /= 0) call bad('steps', itoa(cfg%steps), 'must be a multiple '// &
                                              'of 4 on a cyclic path (the steps of one cycle, '// &
                                              'whose peaks fall on its quarters)')
      do k = 1, ntargets
        if (targets(k) /= 0.0_wp) call bad(trim(target_names(k)), rtoa(targets(k)), &
                                           'a cyclic path reads amplitude and cycles: leave it 0')
      end do
      return
    end if

    if (cfg%amplitude /= 0.0_wp) call bad('amplitude', rtoa(cfg%amplitude), &
                                          'only a cyclic path (cycles > 0) reads it: leave it 0')
    need = target_of(path, cfg%control)
    do k = 1, ntargets
      if (k == need .or. targets(k) == 0.0_wp) cycle
      call bad(trim(target_names(k)), rtoa(targets(k)), 'not read by path = '// &
               quote(cfg%path)//' under control = '//quote(cfg%control)//' (its target is '// &
               trim(target_names(need))//'): leave it 0')
    end do
    if (strain) then
      if (shear) then
        if (.not. (real_ok(cfg%shear_strain) .and. cfg%shear_strain /= 0.0_wp)) &
          call bad('shear_strain', rtoa(cfg%shear_strain), 'must be a finite gamma_xz /= 0 '// &
                   '(its sign the direction of the shear)')
      else if (.not. real_ok(targets(need), gt=0.0_wp)) then
        call bad(trim(target_names(need)), rtoa(targets(need)), 'must be > 0 (the size of the '// &
                 'strain at the end of the path; sense gives its direction)')
      end if
      return
    end if
    ! stress control: an end value on the side of the initial one that sense names
    if (.not. stress_ok) return
    s0 = initial_effective_stress(cfg)
    select case (path)
    case (path_isotropic)
      y0 = -sum(s0(1:3))/3.0_wp
      call check_end('mean_stress', cfg%mean_stress, y0, 'p''', .true.)
    case (path_oedometer)
      y0 = -s0(3)
      call check_end('axial_stress', cfg%axial_stress, y0, 'sigma''_a', .true.)
    case (path_triaxial_drained, path_triaxial_undrained)
      y0 = 0.5_wp*(s0(1) + s0(2)) - s0(3)
      call check_end('deviator', cfg%deviator, y0, 'q', .false.)
    case (path_plane_strain_undrained)
      y0 = s0(1) - s0(3)
      call check_end('deviator', cfg%deviator, y0, 'sigma''_a - sigma''_x', .false.)
    case default
      if (.not. (real_ok(cfg%shear_stress) .and. cfg%shear_stress /= 0.0_wp)) &
        call bad('shear_stress', rtoa(cfg%shear_stress), 'must be a finite tau /= 0 (Pa; its '// &
                 'sign the direction of the shear)')
    end select

  contains

    !> A problem with variable var of &element.
    subroutine bad(var, value, allowed)
      character(len=*), intent(in) :: var, value, allowed
      call add_raw(pb, '&element '//var//' = '//value//': '//allowed//where)
    end subroutine bad

    !> The end value y of the stress measure named what (initial value y0) of a monotonic
    !> stress-controlled path: above y0 in compression, below in extension, and > 0 when
    !> positive is true.
    subroutine check_end(var, y, y0, what, positive)
      character(len=*), intent(in) :: var, what
      real(wp), intent(in) :: y, y0
      logical, intent(in) :: positive
      if (.not. real_ok(y) .or. (positive .and. .not. y > 0.0_wp)) then
        call bad(var, rtoa(y), 'must be a finite'//merge(' positive', '         ', positive)// &
                 ' end value of '//what//' (Pa)')
      else if (cfg%sense == 'compression' .and. .not. y > y0) then
        call bad(var, rtoa(y), 'must be above the initial '//what//' = '//rtoa(y0)// &
                 ' (Pa) in compression (sense = ''extension'' goes below it)')
      else if (cfg%sense == 'extension' .and. .not. y < y0) then
        call bad(var, rtoa(y), 'must be below the initial '//what//' = '//rtoa(y0)// &
                 ' (Pa) in extension')
      end if
    end subroutine check_end

  end subroutine check_element

  !> The names of a list, comma separated.
  function listed(names) result(s)
    character(len=*), intent(in) :: names(:)
    character(len=:), allocatable :: s
    integer :: k
    s = trim(names(1))
    do k = 2, size(names)
      s = s//', '//trim(names(k))
    end do
  end function listed

end module dpmpm_element_input
