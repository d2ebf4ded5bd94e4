!> Elastic stress updates (dpmpm_materials): the plane-strain forms that 2D scenes
!> use give what the general 3x3 update gives for a velocity gradient and a
!> deformation gradient without a third row and column. The model table
!> (dpmpm_model_table): its lines, the state names of a scene, every model module behind
!> the one interface, and every model documented in doc/input.md (the first argument).
program test_materials
  use dpmpm_kinds, only: wp
  use dpmpm_materials, only: material_t, stress_update, model_neo_hookean, model_linear_elastic, &
                             model_update, materials_from_config
  use dpmpm_model_table, only: model_table, max_state, model_from_name, model_names, &
                               scene_state_names, model_mohr_coulomb, model_drucker_prager, &
                               model_umat, model_cam_clay
  use dpmpm_model_elastic, only: elastic_update
  use dpmpm_model_neo_hookean, only: neo_hookean_update
  use dpmpm_model_plastic, only: plastic_update
  use dpmpm_config, only: material_cfg_t
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  integer, parameter :: npt = 25
  !> Measured largest relative difference 6.3e-15 (release, neo-Hookean stress after 20
  !> steps; 3.3e-16 in the debug build); 5x margin.
  real(wp), parameter :: tol_rel = 3.0e-14_wp
  call start_tests()
  call test_plane_neo_hookean_matches_general()
  call test_plane_linear_elastic_matches_general()
  call test_model_table_lines_are_consistent()
  call test_scene_state_names_follow_the_models()
  call test_stress_update_dispatches_to_each_model_module()
  call test_model_table_names_every_model_in_the_input_doc()
  call end_tests()

contains

  !> A material of E = 1e7 Pa, nu = 0.3 and the given model.
  function elastic(model) result(mat)
    integer, intent(in) :: model
    type(material_t) :: mat
    mat%model = model
    mat%youngs = 1.0e7_wp
    mat%poisson = 0.3_wp
    mat%mu = mat%youngs/(2.0_wp*(1.0_wp + mat%poisson))
    mat%lambda = mat%youngs*mat%poisson/((1.0_wp + mat%poisson)*(1.0_wp - 2.0_wp*mat%poisson))
    mat%pwave = mat%lambda + 2.0_wp*mat%mu
  end function elastic

  !> In-plane velocity gradients of different size and sense at every point (3x3
  !> column-major, third row and column zero).
  subroutine plane_gradients(vgrad)
    real(wp), intent(out) :: vgrad(9, npt)
    integer :: p
    vgrad = 0.0_wp
    do p = 1, npt
      vgrad(1, p) = 0.8_wp*sin(0.7_wp*p)
      vgrad(2, p) = 0.5_wp*cos(1.1_wp*p)
      vgrad(4, p) = -0.6_wp*sin(0.3_wp*p + 1.0_wp)
      vgrad(5, p) = 0.4_wp*cos(0.9_wp*p + 0.5_wp)
    end do
  end subroutine plane_gradients

  !> Twenty steps of a large in-plane motion: F, stress and volume of the plane form
  !> against the general one.
  subroutine test_plane_neo_hookean_matches_general()
    type(material_t) :: mat
    real(wp) :: vgrad(9, npt), s1(6, npt), s2(6, npt), f1(9, npt), f2(9, npt)
    real(wp) :: vol1(npt), vol2(npt), vol0(npt)
    integer :: pmat(npt), step, p
    real(wp), parameter :: dt = 0.01_wp
    call begin_test('plane_neo_hookean_matches_general')
    mat = elastic(model_neo_hookean)
    call plane_gradients(vgrad)
    pmat = 1
    vol0 = 1.0e-3_wp
    vol1 = vol0; vol2 = vol0
    s1 = 0.0_wp; s2 = 0.0_wp
    f1 = 0.0_wp
    do p = 1, npt
      f1([1, 5, 9], p) = 1.0_wp
    end do
    f2 = f1
    do step = 1, 20
      call stress_update(mat, 1, dt, npt, pmat, vgrad, s1, vol1, vol0, defgrad=f1)
      call stress_update(mat, 1, dt, npt, pmat, vgrad, s2, vol2, vol0, defgrad=f2, plane=.true.)
    end do
    call check_close(maxval(abs(f2 - f1))/maxval(abs(f1)), 0.0_wp, 0.0_wp, tol_rel, 'F (relative)')
    call check_close(maxval(abs(s2 - s1))/maxval(abs(s1)), 0.0_wp, 0.0_wp, tol_rel, 'stress (relative)')
    call check_close(maxval(abs(vol2 - vol1))/maxval(vol1), 0.0_wp, 0.0_wp, tol_rel, 'volume (relative)')
  end subroutine test_plane_neo_hookean_matches_general

  !> Twenty steps of the hypoelastic (Jaumann) update from a plane-strain stress.
  subroutine test_plane_linear_elastic_matches_general()
    type(material_t) :: mat
    real(wp) :: vgrad(9, npt), s1(6, npt), s2(6, npt), vol1(npt), vol2(npt), vol0(npt)
    integer :: pmat(npt), step, p
    real(wp), parameter :: dt = 1.0e-3_wp
    call begin_test('plane_linear_elastic_matches_general')
    mat = elastic(model_linear_elastic)
    call plane_gradients(vgrad)
    pmat = 1
    vol0 = 1.0e-3_wp
    vol1 = vol0; vol2 = vol0
    do p = 1, npt
      s1(:, p) = [-1.0e4_wp, -2.5e4_wp, -1.2e4_wp, 0.0_wp, 0.0_wp, 3.0e3_wp]*real(1 + mod(p, 3), wp)
    end do
    s2 = s1
    do step = 1, 20
      call stress_update(mat, 1, dt, npt, pmat, vgrad, s1, vol1, vol0)
      call stress_update(mat, 1, dt, npt, pmat, vgrad, s2, vol2, vol0, plane=.true.)
    end do
    call check_close(maxval(abs(s2 - s1))/maxval(abs(s1)), 0.0_wp, 0.0_wp, tol_rel, 'stress (relative)')
    call check_close(maxval(abs(vol2 - vol1))/maxval(vol1), 0.0_wp, 0.0_wp, tol_rel, 'volume (relative)')
  end subroutine test_plane_linear_elastic_matches_general

  !> Each line of the table: found by its name, state names for exactly its nstate
  !> values, names unique; an unknown name gives 0 and model_names lists every model.
  subroutine test_model_table_lines_are_consistent()
    integer :: m, j
    call begin_test('model_table_lines_are_consistent')
    do m = 1, size(model_table)
      associate (t => model_table(m))
        call check_equal_int(model_from_name(t%name), m, 'model '//trim(t%name)//' by its name')
        call check(t%nstate >= 0 .and. t%nstate <= max_state, trim(t%name)//': nstate in range')
        call check(all(t%state_names(1:t%nstate) /= '') .and. &
                   all(t%state_names(t%nstate + 1:) == ''), &
                   trim(t%name)//': a name for each state value and none more')
        call check(index(model_names(), trim(t%name)) > 0, trim(t%name)//' in model_names')
        do j = 1, m - 1
          call check(model_table(j)%name /= t%name, trim(t%name)//' named once')
        end do
      end associate
    end do
    call check_equal_int(model_from_name('cam_clay_typo'), 0, 'an unknown model is 0')
    call check_equal_int(model_from_name('  mohr_coulomb '), model_mohr_coulomb, &
                         'blanks around a name are ignored')
  end subroutine test_model_table_lines_are_consistent

  !> The state values of a scene: as many as its model with the most, named by the models.
  subroutine test_scene_state_names_follow_the_models()
    character(len=24), allocatable :: names(:)
    call begin_test('scene_state_names_follow_the_models')
    names = scene_state_names([model_linear_elastic, model_neo_hookean])
    call check_equal_int(size(names), 0, 'elastic scenes keep no state')
    names = scene_state_names([model_linear_elastic, model_mohr_coulomb, model_drucker_prager])
    call check_equal_int(size(names), 1, 'the plastic soils keep one value')
    if (size(names) == 1) call check(names(1) == 'plastic_strain', 'named plastic_strain')
    ! a umat: the wrapper's 9 values, then its material's umat_nstatev STATEV
    names = scene_state_names([model_linear_elastic, model_umat], [5, 3])
    call check_equal_int(size(names), 12, 'a umat keeps 9 values and its 3 STATEV')
    if (size(names) == 12) call check(names(1) == 'strain_xx' .and. names(9) == 'scd' .and. &
                                      names(10) == 'statev_1' .and. names(12) == 'statev_3', &
                                      'named strain_xx .. scd, statev_1 .. statev_3')
    names = scene_state_names([model_cam_clay, model_umat], [0, 0])
    call check_equal_int(size(names), 9, 'a umat without STATEV keeps 9 values')
    if (size(names) == 9) call check(names(1) == 'state_1' .and. names(3) == 'strain_zz', &
                                     'shared slots named state_<k>, the others by the umat')
  end subroutine test_scene_state_names_follow_the_models

  !> stress_update gives what each model's module gives called directly (bit for bit), on
  !> points of two materials, and each module has the interface model_update (checked by
  !> the compiler in the pointer assignments).
  subroutine test_stress_update_dispatches_to_each_model_module()
    procedure(model_update), pointer :: direct
    type(material_t), allocatable :: mats(:)
    real(wp) :: vgrad(9, npt), s1(6, npt), s2(6, npt), f1(9, npt), f2(9, npt), e1(1, npt)
    real(wp) :: e2(1, npt), vol1(npt), vol2(npt), vol0(npt), w1, w2
    integer :: pmat(npt), m, p
    call begin_test('stress_update_dispatches_to_each_model_module')
    call materials_from_config([material_cfg_t(id=1, model='linear_elastic'), &
                                material_cfg_t(id=2, model='neo_hookean'), &
                                material_cfg_t(id=3, model='mohr_coulomb', cohesion=1.0e3_wp), &
                                material_cfg_t(id=4, model='drucker_prager', &
                                               cohesion=1.0e3_wp)], mats)
    call plane_gradients(vgrad)
    vgrad = 1.0e-2_wp*vgrad
    do m = 1, size(mats)
      select case (m)
      case (1)
        direct => elastic_update
      case (2)
        direct => neo_hookean_update
      case default
        direct => plastic_update
      end select
      pmat = [(merge(m, 5 - m, mod(p, 2) == 0), p=1, npt)]
      s1 = 0.0_wp; s2 = 0.0_wp; vol1 = 1.0_wp; vol2 = 1.0_wp; vol0 = 1.0_wp
      e1 = 0.0_wp; e2 = 0.0_wp; w1 = 0.0_wp; w2 = 0.0_wp
      f1 = spread([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], 2, npt)
      f2 = f1
      call stress_update(mats(m), m, 1.0_wp, npt, pmat, vgrad, s1, vol1, vol0, f1, e1, w1, &
                         plane=.true.)
      call direct(mats(m), m, 1.0_wp, npt, pmat, vgrad, s2, vol2, vol0, f2, e2, w2, plane=.true.)
      call check(all(s1 == s2) .and. all(vol1 == vol2) .and. all(f1 == f2) .and. &
                 all(e1 == e2) .and. w1 == w2, trim(model_table(mats(m)%model)%name)// &
                 ': stress_update is its module''s update')
      call check(any(s1 /= 0.0_wp), trim(model_table(mats(m)%model)%name)//': stress changed')
    end do
  end subroutine test_stress_update_dispatches_to_each_model_module

  !> doc/input.md (the program's first argument) names every model of the table.
  subroutine test_model_table_names_every_model_in_the_input_doc()
    character(len=4096) :: path
    character(len=1024) :: line
    logical :: seen(size(model_table))
    integer :: u, ios, m
    call begin_test('model_table_names_every_model_in_the_input_doc')
    call get_command_argument(1, path)
    open (newunit=u, file=trim(path), status='old', action='read', iostat=ios)
    call check(ios == 0, 'doc/input.md opened: '//trim(path))
    if (ios /= 0) return
    seen = .false.
    do
      read (u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      do m = 1, size(model_table)
        if (index(line, '`'//trim(model_table(m)%name)//'`') > 0) seen(m) = .true.
      end do
    end do
    close (u)
    do m = 1, size(model_table)
      call check(seen(m), 'doc/input.md names `'//trim(model_table(m)%name)//'`')
    end do
  end subroutine test_model_table_names_every_model_in_the_input_doc

end program test_materials
