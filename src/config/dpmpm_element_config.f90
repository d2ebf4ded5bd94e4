!> The parameters of an element test (app/dpmpm_element.f90): one material point of one
!> &material driven along a path given by &element. Types, names and defaults only;
!> dpmpm_element_input reads and checks them, dpmpm_element_path runs them.
module dpmpm_element_config
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: material_cfg_t, name_len
  implicit none
  private
  public :: element_cfg_t, element_paths, element_controls, element_senses
  public :: path_isotropic, path_oedometer, path_triaxial_drained, path_triaxial_undrained
  public :: path_simple_shear_drained, path_simple_shear_undrained, path_from_name
  public :: path_plane_strain_undrained
  public :: target_names, ntargets, target_of, initial_effective_stress

  !> The paths, in the order of their codes.
  integer, parameter :: path_isotropic = 1, path_oedometer = 2, path_triaxial_drained = 3, &
                        path_triaxial_undrained = 4, path_simple_shear_drained = 5, &
                        path_simple_shear_undrained = 6, path_plane_strain_undrained = 7
  character(len=22), parameter :: element_paths(7) = [character(len=22) :: 'isotropic', &
    'oedometer', 'triaxial_drained', 'triaxial_undrained', 'simple_shear_drained', &
    'simple_shear_undrained', 'plane_strain_undrained']
  character(len=6), parameter :: element_controls(2) = ['strain', 'stress']
  character(len=11), parameter :: element_senses(2) = ['compression', 'extension  ']

  !> The target variables of &element, one of which a monotonic path reads (target_of).
  integer, parameter :: ntargets = 7
  character(len=17), parameter :: target_names(ntargets) = [character(len=17) :: &
    'axial_strain', 'volumetric_strain', 'shear_strain', 'deviator', 'mean_stress', &
    'axial_stress', 'shear_stress']

  !> One element test: its material and its &element values (dpmpm_vars_element.inc).
  type :: element_cfg_t
    type(material_cfg_t) :: material
    include "dpmpm_vars_element_component.inc"
    character(len=:), allocatable :: input_file
    character(len=:), allocatable :: input_text   !< the file, echoed into the output
    character(len=:), allocatable :: echo         !< both groups as read, defaults included
  end type element_cfg_t

contains

  !> The initial effective stress (Voigt, tension positive): initial_stress when given,
  !> else sigma'_a = 3 p0 / (1 + 2 k0) axially and k0 sigma'_a radially.
  pure function initial_effective_stress(cfg) result(s)
    type(element_cfg_t), intent(in) :: cfg
    real(wp) :: s(6), sa
    s = 0.0_wp
    if (any(cfg%initial_stress /= 0.0_wp)) then
      s(1:3) = cfg%initial_stress
    else
      sa = 3.0_wp*cfg%p0/(1.0_wp + 2.0_wp*cfg%k0)
      s(1:3) = -[cfg%k0*sa, cfg%k0*sa, sa]
    end if
  end function initial_effective_stress

  !> Path code from its name, 0 if unknown.
  pure integer function path_from_name(name) result(code)
    character(len=*), intent(in) :: name
    code = findloc(element_paths, trim(adjustl(name)), dim=1)
  end function path_from_name

  !> Index in target_names of the target that a monotonic path of code path under control
  !> ('strain' or 'stress') reads: what it drives to its end value.
  pure integer function target_of(path, control) result(k)
    integer, intent(in) :: path
    character(len=*), intent(in) :: control
    logical :: strain
    strain = trim(control) == 'strain'
    select case (path)
    case (path_isotropic)
      k = merge(2, 5, strain)
    case (path_oedometer)
      k = merge(1, 6, strain)
    case (path_triaxial_drained, path_triaxial_undrained, path_plane_strain_undrained)
      k = merge(1, 4, strain)
    case default
      k = merge(3, 7, strain)
    end select
  end function target_of

end module dpmpm_element_config
