!> Rank-count invariance: one 2D scene run on 1, 2 and 4 ranks (sub-communicators
!> of a 4-rank job) gives the same point fields, matched by id, to 1e-10 relative.
!> Points are scattered randomly, move across rank boundaries, and the body deforms.
program test_rank_invariance
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Comm, MPI_Comm_split, MPI_Comm_size, MPI_Comm_free, &
                     MPI_UNDEFINED, MPI_COMM_NULL, operator(/=)
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, region_cfg_t, material_cfg_t, bc_fixed, bc_roller
  use dpmpm_test_scenes, only: grid_scene, column_scene
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check
  use dpmpm_test_main, only: start_tests, end_tests
  use dpmpm_test_compare, only: reldiff
  implicit none
  integer :: rank, nworld
  call start_tests(rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nworld)
  call test_same_fields_on_1_2_4_ranks('linear', 'musl')
  call test_same_fields_on_1_2_4_ranks('quadratic', 'musl')
  call test_same_fields_on_1_2_4_ranks('quadratic', 'usl')
  ! MLS: the transposed Gauss-point pair, MLS velocities with a linear basis, and
  ! radial Wendland velocities (moment sums and Gauss sums cross rank boundaries).
  call test_same_fields_on_1_2_4_ranks('cubic', 'musl', 'pair')
  call test_same_fields_on_1_2_4_ranks('cubic', 'musl', 'cubic_linear')
  call test_same_fields_on_1_2_4_ranks('quadratic', 'musl', 'wendland')
  ! Two-phase: the 1D shock column W1 as a 2D column, and a 2D saturated block
  ! settling under gravity (solid and fluid points cross rank boundaries).
  call test_same_fields_on_1_2_4_ranks('linear', 'musl', 'column_2d')
  call test_same_fields_on_1_2_4_ranks('cubic', 'musl', 'saturated_block')
  call test_same_fields_on_1_2_4_ranks('cubic', 'musl', 'saturated_block_pair')
  ! Two layers of different porosity with the porosity-gradient term.
  call test_same_fields_on_1_2_4_ranks('quadratic', 'musl', 'layered_block')
  ! The same layers of Mohr-Coulomb soil with the cell smoothing of the skeleton's
  ! volumetric strain rate and of the pore pressure (cell sums stay on the cell's rank).
  call test_same_fields_on_1_2_4_ranks('linear', 'musl', 'smoothed_block')
  call end_tests()

contains

  !> A 2D neo-Hookean block thrown sideways on a fixed floor under gravity.
  function scene(kernel, scheme, mls) result(cfg)
    character(len=*), intent(in) :: kernel, scheme
    character(len=*), intent(in), optional :: mls
    type(config_t) :: cfg
    cfg = grid_scene('rank_invariance', [16, 12], [1.6_wp, 1.2_wp], 0.3_wp, nmat=1, nreg=1, &
                     nload=0, cfl=0.4_wp, flip=0.95_wp, gravity=[0.0_wp, -10.0_wp])
    cfg%kernel = kernel
    cfg%scheme = scheme
    cfg%materials(1) = material_cfg_t(id=3, model='neo_hookean', density=1000.0_wp, &
                                      youngs_modulus=1.0e5_wp, poisson_ratio=0.3_wp)
    cfg%regions(1) = region_cfg_t(lo=[0.25_wp, 0.0_wp, 0.0_wp], hi=[1.05_wp, 0.7_wp, 0.0_wp], &
                                  material=3, ppc=2, placement='random', seed=11, &
                                  velocity=[1.0_wp, 0.5_wp, 0.0_wp])
    cfg%bc(3) = bc_fixed
    cfg%bc(1) = bc_roller
    cfg%bc(2) = bc_roller
    if (.not. present(mls)) return
    select case (mls)
    case ('column_2d')
      cfg = column_2d(kernel, scheme)
    case ('saturated_block', 'saturated_block_pair', 'layered_block', 'smoothed_block')
      cfg%materials(1)%model = 'linear_elastic'
      cfg%materials(1)%conductivity = 1.0e-3_wp
      cfg%materials = [cfg%materials(1), material_cfg_t(id=4, model='fluid', density=1000.0_wp, &
                                                        bulk_modulus=2.0e6_wp)]
      cfg%regions(1)%phase = 'saturated'
      cfg%regions(1)%fluid_material = 4
      cfg%regions(1)%porosity = 0.35_wp
      cfg%regions(1)%velocity = [0.3_wp, 0.1_wp, 0.0_wp]
      cfg%t_end = 0.15_wp
      cfg%drag = 'implicit'
      if (mls == 'saturated_block_pair') then
        cfg%quadrature = 'gauss'
        cfg%field_kernel = 'wendland_c2'
        cfg%field_radius = 2.0_wp
        cfg%t_end = 0.08_wp
      end if
      if (mls == 'smoothed_block') then
        cfg%materials(1)%model = 'mohr_coulomb'
        cfg%materials(1)%friction_angle = 30.0_wp
        cfg%materials(1)%cohesion = 50.0_wp
        cfg%volumetric_smoothing = 'cell'
        cfg%pressure_smoothing = 'cell'
      end if
      if (mls == 'layered_block' .or. mls == 'smoothed_block') then
        cfg%porosity_gradient = .true.
        cfg%regions = [cfg%regions(1), cfg%regions(1)]
        cfg%regions(1)%hi(2) = 0.35_wp
        cfg%regions(2)%lo(2) = 0.35_wp
        cfg%regions(2)%porosity = 0.5_wp
        cfg%regions(2)%seed = 12
      end if
    case ('pair')
      cfg%quadrature = 'gauss'
      cfg%field_kernel = 'wendland_c2'
      cfg%field_radius = 2.0_wp
    case ('cubic_linear')
      cfg%velocity_kernel = 'cubic'
      cfg%velocity_basis = 'linear'
      cfg%quadrature = 'gauss'
      cfg%field_kernel = 'cubic'
      cfg%field_radius = 0.0_wp
    case ('wendland')
      cfg%velocity_kernel = 'wendland_c2'
      cfg%velocity_radius = 2.0_wp
      cfg%quadrature = 'gauss'
      cfg%field_kernel = 'quadratic'
      cfg%field_radius = 0.0_wp
    end select
  end function scene

  !> W1 (doc/theory.md 9.1) as a 2D column of 100 x 2 cells along x with roller
  !> sides, explicit drag, to 5 ms.
  function column_2d(kernel, scheme) result(cfg)
    character(len=*), intent(in) :: kernel, scheme
    type(config_t) :: cfg
    cfg = column_scene(100, 1.0e-5_wp, 3.0e6_wp, 5.0e-3_wp, 'explicit')
    cfg%name = 'column_2d'
    cfg%benchmark = 'none'
    cfg%ndim = 2
    cfg%ncells(2) = 2
    cfg%length(2) = 0.2_wp
    cfg%kernel = kernel
    cfg%scheme = scheme
    cfg%regions(1)%hi = [10.0_wp, 0.2_wp, 0.0_wp]
    cfg%regions(1)%seed = 3
    cfg%bc(3) = bc_roller
    cfg%bc(4) = bc_roller
  end function column_2d

  subroutine run_on(n, cfg, ids, x, v, s, steps, fids, fx, fv, fs)
    integer, intent(in) :: n
    type(config_t), intent(in) :: cfg
    integer(i8), allocatable, intent(out) :: ids(:)
    real(wp), allocatable, intent(out) :: x(:, :), v(:, :), s(:, :)
    integer(i8), intent(out) :: steps
    integer(i8), allocatable, intent(out) :: fids(:)
    real(wp), allocatable, intent(out) :: fx(:, :), fv(:, :), fs(:, :)
    type(MPI_Comm) :: sub
    type(simulation_t) :: sim
    integer :: color
    color = MPI_UNDEFINED
    if (rank < n) color = 0
    call MPI_Comm_split(MPI_COMM_WORLD, color, rank, sub)
    steps = 0
    if (sub /= MPI_COMM_NULL) then
      call sim%init(cfg, sub, write_output=.false.)
      call sim%run()
      call sim%gather_points(ids, x, v, s)
      call sim%gather_points(fids, fx, fv, fs, fluid=.true.)
      steps = sim%step
      call sim%free()
      call MPI_Comm_free(sub)
    end if
  end subroutine run_on

  subroutine test_same_fields_on_1_2_4_ranks(kernel, scheme, mls)
    character(len=*), intent(in) :: kernel, scheme
    character(len=*), intent(in), optional :: mls
    integer(i8), allocatable :: id1(:), idn(:), fid1(:), fidn(:)
    real(wp), allocatable :: x1(:, :), v1(:, :), s1(:, :), xn(:, :), vn(:, :), sn(:, :)
    real(wp), allocatable :: fx1(:, :), fv1(:, :), fs1(:, :), fxn(:, :), fvn(:, :), fsn(:, :)
    real(wp) :: dev
    integer(i8) :: steps1, stepsn
    integer :: n
    character(len=64) :: tag
    character(len=:), allocatable :: variant
    variant = ''
    if (present(mls)) variant = '_'//mls
    call begin_test('same_fields_on_1_2_4_ranks_'//kernel//'_'//scheme//variant)
    call run_on(1, scene(kernel, scheme, mls), id1, x1, v1, s1, steps1, fid1, fx1, fv1, fs1)
    do n = 2, 4, 2
      if (n > nworld) cycle
      call run_on(n, scene(kernel, scheme, mls), idn, xn, vn, sn, stepsn, fidn, fxn, fvn, fsn)
      if (rank /= 0) cycle
      write (tag, '(a,i0,a)') ' (', n, ' ranks vs 1)'
      call check(size(idn) == size(id1), 'same number of points'//trim(tag))
      if (size(idn) /= size(id1)) cycle
      call check(all(idn == id1), 'same ids'//trim(tag))
      call check(stepsn == steps1, 'same number of steps'//trim(tag))
      dev = max(reldiff(xn - spread(x1(:, 1), 2, size(x1, 2)), x1 - spread(x1(:, 1), 2, size(x1, 2))), &
                reldiff(vn, v1), reldiff(sn, s1))
      if (size(fid1) > 0) then
        call check(size(fidn) == size(fid1), 'same number of fluid points'//trim(tag))
        if (size(fidn) /= size(fid1)) cycle
        call check(all(fidn == fid1), 'same fluid ids'//trim(tag))
        dev = max(dev, reldiff(fxn - spread(fx1(:, 1), 2, size(fx1, 2)), &
                               fx1 - spread(fx1(:, 1), 2, size(fx1, 2))), &
                  reldiff(fvn, fv1), reldiff(fsn, fs1))
      end if
      print '(a,i0,a,es10.3)', '  largest relative deviation on ', n, ' ranks: ', dev
      call check(dev <= 1.0e-10_wp, 'positions, velocities and stresses agree to 1e-10'//trim(tag))
    end do
    if (rank == 0) print '(a,i0,a,i0,a,i0,a)', '  ', size(id1), ' solid points, ', size(fid1), &
      ' fluid points, ', steps1, ' steps'
  end subroutine test_same_fields_on_1_2_4_ranks

end program test_rank_invariance
