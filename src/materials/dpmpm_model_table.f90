!> The table of constitutive models: one line per model with its input name, its number
!> of state values per point and their names, and what it needs of the scene. The input
!> reader and checks, the echo, the point sets, the output and doc/input.md take the
!> names from here (tests/test_materials.f90, model_table_names_every_model, checks that
!> each name is documented). Adding a model: its module behind the interface of
!> dpmpm_materials (stress_update), its line here, its input variables and checks.
module dpmpm_model_table
  implicit none
  private
  public :: model_info_t, model_table, max_state, model_from_name, model_names, model_nstate
  public :: model_needs_defgrad, is_plastic, scene_state_names, material_nstate
  public :: model_linear_elastic, model_neo_hookean, model_fluid, model_mohr_coulomb
  public :: model_drucker_prager, model_rigid, model_cam_clay, is_pressure_dependent, model_umat
  public :: model_sanisand
  public :: model_mu_i

  !> The most state values a model may keep per point.
  integer, parameter :: max_state = 24

  !> One model: its input name, how many state values a point of it keeps (nstate) and
  !> their names (frame datasets of the point set), and what it needs: the deformation
  !> gradient (finite strain), a stiffness that follows the pressure, the strain rate,
  !> the pore fluid (effective stress of a saturated skeleton), and whether it dissipates
  !> (plastic work counted in the energy balance).
  type :: model_info_t
    character(len=16) :: name = ''
    integer :: nstate = 0
    character(len=24) :: state_names(max_state) = ''
    logical :: needs_defgrad = .false.
    logical :: pressure_dependent = .false.
    logical :: rate_dependent = .false.
    logical :: skeleton = .false.      !< may be the skeleton of a saturated soil
    logical :: plastic = .false.       !< dissipates: plastic work in the energy balance
    logical :: stressed = .true.       !< has a stress (a rigid body has none)
  end type model_info_t

  !> Model codes: the lines of model_table.
  integer, parameter :: model_linear_elastic = 1, model_neo_hookean = 2, model_fluid = 3
  integer, parameter :: model_mohr_coulomb = 4, model_drucker_prager = 5, model_rigid = 6
  integer, parameter :: model_cam_clay = 7, model_umat = 8, model_sanisand = 9
  integer, parameter :: model_mu_i = 10

  !> The one state value of the Mohr-Coulomb and Drucker-Prager soils: the accumulated
  !> plastic strain that softens the cohesion (dpmpm_plasticity).
  character(len=24), parameter :: plastic_strain(max_state) = &
    reshape([character(len=24) :: 'plastic_strain'], [max_state], pad=[character(len=24) :: ''])

  !> The state values of Modified Cam-Clay: the preconsolidation pressure p_c (Pa) and the
  !> void ratio e.
  character(len=24), parameter :: cam_clay_state(max_state) = &
    reshape([character(len=24) :: 'preconsolidation', 'void_ratio'], [max_state], &
            pad=[character(len=24) :: ''])

  !> The state values the umat wrapper keeps itself (dpmpm_model_umat), before the UMAT's
  !> own STATEV (named statev_1, statev_2, ...): the total strain STRAN (dpmpm's Voigt order,
  !> engineering shears) and the specific energies SSE, SPD and SCD (J/m^3).
  character(len=24), parameter :: umat_state(max_state) = &
    reshape([character(len=24) :: 'strain_xx', 'strain_yy', 'strain_zz', 'strain_yz', &
             'strain_xz', 'strain_xy', 'sse', 'spd', 'scd'], [max_state], &
            pad=[character(len=24) :: ''])

  !> The state values of SANISAND (dpmpm_model_sanisand): the back-stress ratio alpha, the
  !> fabric-dilatancy tensor z and the alpha of the last load reversal alpha_in (Voigt order,
  !> tensor shears, compression positive), and the void ratio e.
  character(len=24), parameter :: sanisand_state(max_state) = &
    reshape([character(len=24) :: 'alpha_xx', 'alpha_yy', 'alpha_zz', 'alpha_yz', 'alpha_xz', &
             'alpha_xy', 'fabric_xx', 'fabric_yy', 'fabric_zz', 'fabric_yz', 'fabric_xz', &
             'fabric_xy', 'alpha_in_xx', 'alpha_in_yy', 'alpha_in_zz', 'alpha_in_yz', &
             'alpha_in_xz', 'alpha_in_xy', 'void_ratio'], [max_state], &
            pad=[character(len=24) :: ''])

  !> The state values of the mu(I) rheology: the accumulated plastic shear strain and the
  !> inertial number I of the last step (dpmpm_model_mu_i).
  character(len=24), parameter :: mu_i_state(max_state) = &
    reshape([character(len=24) :: 'plastic_shear_strain', 'inertial_number'], [max_state], &
            pad=[character(len=24) :: ''])

  type(model_info_t), parameter :: model_table(10) = [ &
    model_info_t(name='linear_elastic', skeleton=.true.), &
    model_info_t(name='neo_hookean', needs_defgrad=.true., skeleton=.true.), &
    model_info_t(name='fluid'), &
    model_info_t(name='mohr_coulomb', nstate=1, state_names=plastic_strain, skeleton=.true., &
                 plastic=.true.), &
    model_info_t(name='drucker_prager', nstate=1, state_names=plastic_strain, skeleton=.true., &
                 plastic=.true.), &
    model_info_t(name='rigid', stressed=.false.), &
    model_info_t(name='cam_clay', nstate=2, state_names=cam_clay_state, &
                 pressure_dependent=.true., skeleton=.true., plastic=.true.), &
    model_info_t(name='umat', nstate=9, state_names=umat_state, needs_defgrad=.true., &
                 skeleton=.true., plastic=.true.), &
    model_info_t(name='sanisand', nstate=19, state_names=sanisand_state, &
                 pressure_dependent=.true., skeleton=.true., plastic=.true.), &
    model_info_t(name='mu_i', nstate=2, state_names=mu_i_state, rate_dependent=.true., &
                 skeleton=.true., plastic=.true.)]

contains

  !> Model code from its input name (blanks around it ignored), 0 if unknown.
  pure integer function model_from_name(name) result(m)
    character(len=*), intent(in) :: name
    do m = 1, size(model_table)
      if (trim(adjustl(name)) == trim(model_table(m)%name)) return
    end do
    m = 0
  end function model_from_name

  !> The input names of every model, comma separated (for messages and the echo).
  function model_names() result(s)
    character(len=:), allocatable :: s
    integer :: m
    s = trim(model_table(1)%name)
    do m = 2, size(model_table)
      s = s//', '//trim(model_table(m)%name)
    end do
  end function model_names

  !> State values per point of model code m (0 for an unknown code).
  elemental integer function model_nstate(m) result(k)
    integer, intent(in) :: m
    k = 0
    if (m >= 1 .and. m <= size(model_table)) k = model_table(m)%nstate
  end function model_nstate

  !> True for the models that keep a deformation gradient.
  elemental logical function model_needs_defgrad(m) result(yes)
    integer, intent(in) :: m
    yes = .false.
    if (m >= 1 .and. m <= size(model_table)) yes = model_table(m)%needs_defgrad
  end function model_needs_defgrad

  !> True for the elasto-plastic models (plastic work, the bound of dilation).
  elemental logical function is_plastic(m)
    integer, intent(in) :: m
    is_plastic = .false.
    if (m >= 1 .and. m <= size(model_table)) is_plastic = model_table(m)%plastic
  end function is_plastic

  !> True for the models whose stiffness follows the pressure (the wave speed of each point
  !> then comes from its own stress and state, dpmpm_materials' point_moduli).
  elemental logical function is_pressure_dependent(m) result(yes)
    integer, intent(in) :: m
    yes = .false.
    if (m >= 1 .and. m <= size(model_table)) yes = model_table(m)%pressure_dependent
  end function is_pressure_dependent

  !> State values per point of a material of model code m: the model's, and for a umat
  !> the UMAT's own nstatev (umat_nstatev) after the wrapper's.
  elemental integer function material_nstate(m, nstatev) result(k)
    integer, intent(in) :: m, nstatev
    k = model_nstate(m)
    if (m == model_umat) k = k + max(nstatev, 0)
  end function material_nstate

  !> The name of state value k of a material of model code m (statev_<j> for the j-th
  !> STATEV of a umat).
  function state_name(m, k) result(name)
    integer, intent(in) :: m, k
    character(len=24) :: name
    if (k <= model_nstate(m)) then
      name = model_table(m)%state_names(k)
    else
      write (name, '(a,i0)') 'statev_', k - model_nstate(m)
    end if
  end function state_name

  !> The names of the state values of a point set whose points carry the models of codes
  !> models(:) (with the umat_nstatev of each material in nstatev, where a umat may be
  !> among them): slot k is named by the models that have a k-th value, 'state_<k>' where
  !> two of them name it differently. Its size is the largest nstate among them.
  function scene_state_names(models, nstatev) result(names)
    integer, intent(in) :: models(:)
    integer, intent(in), optional :: nstatev(:)
    character(len=24), allocatable :: names(:)
    integer :: k, j, ns, counts(size(models))
    counts = model_nstate(models)
    if (present(nstatev)) counts = material_nstate(models, nstatev)
    ns = maxval([0, counts])
    allocate (names(ns))
    names = ''
    do k = 1, ns
      do j = 1, size(models)
        if (counts(j) < k) cycle
        if (names(k) == '') then
          names(k) = state_name(models(j), k)
        else if (names(k) /= state_name(models(j), k)) then
          write (names(k), '(a,i0)') 'state_', k
          exit
        end if
      end do
    end do
  end function scene_state_names

end module dpmpm_model_table
