!> Scenes shared by the test programs.
module dpmpm_test_scenes
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, material_cfg_t, load_cfg_t, bc_fixed
  implicit none
  private
  public :: column_scene

contains

  !> The saturated column of doc/theory.md 9.1 (W1 unless changed): 1D along x,
  !> loaded and drained at x-, fixed and impermeable at x+.
  function column_scene(ncells, k, kf, t_end, drag) result(cfg)
    integer, intent(in) :: ncells
    real(wp), intent(in) :: k, kf, t_end
    character(len=*), intent(in) :: drag
    type(config_t) :: cfg
    cfg%name = 'column'
    cfg%ndim = 1
    cfg%ncells = [ncells, 1, 1]
    cfg%length = [10.0_wp, 1.0_wp, 1.0_wp]
    cfg%t_end = t_end
    cfg%cfl = 0.5_wp
    cfg%drag = drag
    cfg%benchmark = 'biot_column'
    allocate (cfg%materials(2), cfg%regions(1), cfg%loads(1))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2650.0_wp, &
                                      youngs_modulus=1.0e7_wp, poisson_ratio=0.0_wp, conductivity=k)
    cfg%materials(2) = material_cfg_t(id=2, model='fluid', density=1000.0_wp, bulk_modulus=kf)
    cfg%regions(1)%lo = [0.0_wp, 0.0_wp, 0.0_wp]
    cfg%regions(1)%hi = [10.0_wp, 1.0_wp, 1.0_wp]
    cfg%regions(1)%material = 1
    cfg%regions(1)%fluid_material = 2
    cfg%regions(1)%phase = 'saturated'
    cfg%regions(1)%porosity = 0.3_wp
    cfg%regions(1)%ppc = 2
    cfg%regions(1)%placement = 'random'
    cfg%regions(1)%seed = 5
    cfg%loads(1) = load_cfg_t(face=1, traction=[1.0_wp, 0.0_wp, 0.0_wp], ramp_time=0.0_wp)
    cfg%bc(2) = bc_fixed
  end function column_scene

end module dpmpm_test_scenes
