!> Scenes shared by the test programs.
module dpmpm_test_scenes
  use mpi_f08, only: MPI_COMM_WORLD
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, load_cfg_t, bc_fixed, bc_roller
  use dpmpm_simulation, only: simulation_t
  implicit none
  private
  public :: grid_scene, column_scene, released_column, run_both_phases

contains

  !> The part of a test scene that every test writes: its name, a grid of ncells cells
  !> over length (m) per axis (ndim = size(ncells); the axes beyond ndim one cell of 1
  !> m, as in an input file), the time to run, nmat materials, nreg regions and nload
  !> loads allocated at their defaults (each group where its count is given), and cfl, flip, gravity
  !> (its first components; the rest 0) and max_steps where given. Everything else is
  !> config_t's default, for the test to set.
  function grid_scene(name, ncells, length, t_end, nmat, nreg, nload, cfl, flip, gravity, &
                      max_steps) result(cfg)
    character(len=*), intent(in) :: name
    integer, intent(in) :: ncells(:)
    real(wp), intent(in) :: length(:)
    real(wp), intent(in), optional :: t_end, cfl, flip, gravity(:)
    integer, intent(in), optional :: nmat, nreg, nload, max_steps
    type(config_t) :: cfg
    integer :: nd
    nd = size(ncells)
    cfg%name = name
    cfg%ndim = nd
    cfg%ncells = 1
    cfg%ncells(1:nd) = ncells
    cfg%length = 1.0_wp
    cfg%length(1:nd) = length
    if (present(t_end)) cfg%t_end = t_end
    if (present(cfl)) cfg%cfl = cfl
    if (present(flip)) cfg%flip = flip
    if (present(gravity)) then
      cfg%gravity = 0.0_wp
      cfg%gravity(1:size(gravity)) = gravity
    end if
    if (present(max_steps)) cfg%max_steps = max_steps
    if (present(nmat)) allocate (cfg%materials(nmat))
    if (present(nreg)) allocate (cfg%regions(nreg))
    if (present(nload)) allocate (cfg%loads(nload))
  end function grid_scene

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

  !> Region 1 of cfg (material 1) the column of width 0.25 m and the given height (m) and
  !> depth along z (m) at the origin, against a smooth wall (x-) on a rough floor (y-),
  !> free on its right side, from sigma_yy = -rho g (H - y) and sigma_xx = sigma_zz =
  !> K0 sigma_yy (rho in kg/m^3, g in m/s^2).
  subroutine released_column(cfg, rho, g, height, depth, k0)
    type(config_t), intent(inout) :: cfg
    real(wp), intent(in) :: rho, g, height, depth, k0
    real(wp) :: syy
    cfg%regions(1)%lo = [0.0_wp, 0.0_wp, 0.0_wp]
    cfg%regions(1)%hi = [0.25_wp, height, depth]
    cfg%regions(1)%material = 1
    syy = -rho*g*height
    cfg%regions(1)%stress = [k0*syy, syy, k0*syy, 0.0_wp, 0.0_wp, 0.0_wp]
    cfg%regions(1)%stress_gradient(:, 2) = -[k0*syy, syy, k0*syy, 0.0_wp, 0.0_wp, 0.0_wp]/height
    cfg%bc(1) = bc_roller
    cfg%bc(3) = bc_fixed
  end subroutine released_column

  !> Run the two-phase scene cfg without output and gather both point sets on rank 0:
  !> positions, velocities and stresses of the solid (xs, vs, ss) and fluid (xf, vf, sf) points.
  subroutine run_both_phases(cfg, xs, vs, ss, xf, vf, sf)
    type(config_t), intent(in) :: cfg
    real(wp), allocatable, intent(out) :: xs(:, :), vs(:, :), ss(:, :), xf(:, :), vf(:, :), sf(:, :)
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    call sim%gather_points(ids, xs, vs, ss)
    call sim%gather_points(ids, xf, vf, sf, fluid=.true.)
    call sim%free()
  end subroutine run_both_phases

end module dpmpm_test_scenes
