!> External loads: a face traction and gravity change the total momentum at
!> exactly the applied rate (internal forces sum to zero, FLIP transfers nodal
!> momentum changes exactly); a traction on part of a face has the exact resultant for
!> every grid function, and the time functions give their factors.
program test_loads
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, load_cfg_t, bc_roller, bc_fixed
  use dpmpm_grid, only: grid_t
  use dpmpm_face_loads, only: face_loads_t
  use dpmpm_kernels, only: kernel_from_name
  use dpmpm_simulation, only: simulation_t
  use dpmpm_assert, only: begin_test, check, check_close, am_root
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none
  call start_tests()
  call test_traction_changes_momentum_at_applied_rate()
  call test_gravity_changes_momentum_at_applied_rate()
  call test_strip_load_has_its_exact_resultant()
  call test_load_time_functions()
  call test_surface_load_matches_face_load()
  call end_tests()

contains

  function block(ndim, kernel) result(cfg)
    integer, intent(in) :: ndim
    character(len=*), intent(in) :: kernel
    type(config_t) :: cfg
    cfg%ndim = ndim
    cfg%ncells = [20, 20, 1]
    cfg%length = [2.0_wp, 2.0_wp, 1.0_wp]
    cfg%kernel = kernel
    cfg%t_end = 0.02_wp
    cfg%cfl = 0.3_wp
    cfg%flip = 1.0_wp
    allocate (cfg%materials(1), cfg%regions(1), cfg%loads(0))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=1000.0_wp, &
                                      youngs_modulus=1.0e6_wp, poisson_ratio=0.25_wp)
    cfg%regions(1)%lo = [0.0_wp, 0.4_wp, 0.0_wp]
    cfg%regions(1)%hi = [1.0_wp, 1.2_wp, 0.0_wp]
    cfg%regions(1)%ppc = 2
    cfg%regions(1)%placement = 'random'
  end function block

  !> Total momentum and mass of the points (all ranks).
  subroutine totals(sim, p, m)
    type(simulation_t), intent(in) :: sim
    real(wp), intent(out) :: p(3), m
    real(wp) :: s(4)
    integer :: k
    s = 0.0_wp
    do k = 1, sim%phase(1)%pts%n
      s(1:sim%nd) = s(1:sim%nd) + sim%phase(1)%pts%mass(k)*sim%phase(1)%pts%v(:, k)
      s(4) = s(4) + sim%phase(1)%pts%mass(k)
    end do
    call MPI_Allreduce(MPI_IN_PLACE, s, 4, MPI_DOUBLE_PRECISION, MPI_SUM, sim%dec%comm)
    p = s(1:3)
    m = s(4)
  end subroutine totals

  subroutine test_traction_changes_momentum_at_applied_rate()
    type(config_t) :: cfg
    type(simulation_t) :: sim
    real(wp) :: p(3), m
    integer :: nd
    character(len=16) :: kernel
    call begin_test('traction_changes_momentum_at_applied_rate')
    do nd = 1, 2
      kernel = merge('linear   ', 'quadratic', nd == 1)
      cfg = block(nd, trim(kernel))
      deallocate (cfg%loads)
      ! 5 Pa on the body's face at x = 0, pushing +x (face length 0.8 m in 2D: the
      ! face nodes from y = 0.4 to 1.2 carry mass; in 1D the area is 1).
      allocate (cfg%loads(1))
      cfg%loads(1) = load_cfg_t(face=1, traction=[5.0_wp, 0.0_wp, 0.0_wp], ramp_time=0.0_wp)
      call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
      call sim%run()
      call totals(sim, p, m)
      if (nd == 1) then
        call check_close(p(1), 5.0_wp*sim%time, 1.0e-10_wp, 0.0_wp, '1D: x momentum = traction * t')
      else
        call check(p(1) > 0.0_wp, '2D: x momentum grows in the traction direction')
        call check_close(p(2), 0.0_wp, 0.0_wp, 1.0e-12_wp*abs(p(1)), '2D: no y momentum from an x traction')
      end if
      call sim%free()
    end do
  end subroutine test_traction_changes_momentum_at_applied_rate

  subroutine test_gravity_changes_momentum_at_applied_rate()
    type(config_t) :: cfg
    type(simulation_t) :: sim
    real(wp) :: p(3), m
    call begin_test('gravity_changes_momentum_at_applied_rate')
    cfg = block(2, 'quadratic')
    cfg%gravity = [0.0_wp, -10.0_wp, 0.0_wp]
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    call totals(sim, p, m)
    call check_close(p(2), -10.0_wp*m*sim%time, 1.0e-10_wp, 0.0_wp, 'y momentum = M g t')
    call check_close(p(1), 0.0_wp, 0.0_wp, 1.0e-12_wp*abs(p(2)), 'no x momentum')
    ! Measured 6.5e-15 (round-off); a uniform acceleration is transferred exactly.
    call check(sim%energy_drift < 1.0e-12_wp, 'free fall: kinetic energy equals the work of gravity')
    call sim%free()
  end subroutine test_gravity_changes_momentum_at_applied_rate

  !> Sum over the nodes of a 2D grid (20 x 20 cells of 0.1 m, exterior layers included) of
  !> the nodal forces of the loads of cfg on face y- (free) at time t.
  function resultant(cfg, kernel, t) result(r)
    type(config_t), intent(in) :: cfg
    character(len=*), intent(in) :: kernel
    real(wp), intent(in) :: t
    real(wp) :: r(3)
    type(grid_t) :: grid
    type(face_loads_t) :: faces
    integer :: i, j
    call grid%init(cfg)
    call faces%init(cfg, grid, kernel_from_name(kernel), [1, 1, 1, 1, 1, 1])
    r = 0.0_wp
    do j = -2, 22
      do i = -2, 22
        r = r + faces%traction(t, [i, j, 0])
      end do
    end do
    call faces%free()
  end function resultant

  !> 2D grid of 2 m x 2 m with one &load on face y- (traction 0, 3 Pa).
  function strip_scene() result(cfg)
    type(config_t) :: cfg
    cfg%ndim = 2
    cfg%ncells = [20, 20, 1]
    cfg%length = [2.0_wp, 2.0_wp, 1.0_wp]
    allocate (cfg%loads(1))
    cfg%loads(1) = load_cfg_t(face=3, traction=[0.0_wp, 3.0_wp, 0.0_wp])
  end function strip_scene

  !> A strip x = 0.55 .. 1.37 m (not on nodes) of face y-: the nodal forces sum to the
  !> traction times 0.82 m for linear, quadratic and cubic grid functions (partition of
  !> unity, integrated exactly); the whole face gives 2 m.
  subroutine test_strip_load_has_its_exact_resultant()
    type(config_t) :: cfg
    real(wp) :: r(3)
    integer :: k
    character(len=9), parameter :: kernels(3) = ['linear   ', 'quadratic', 'cubic    ']
    call begin_test('strip_load_has_its_exact_resultant')
    do k = 1, 3
      cfg = strip_scene()
      r = resultant(cfg, trim(kernels(k)), 0.0_wp)
      call check_close(r(2), 6.0_wp, 1.0e-13_wp, 0.0_wp, trim(kernels(k))//': whole face, 3 Pa x 2 m')
      cfg%loads(1)%lo = [0.55_wp, 0.0_wp, 0.0_wp]
      cfg%loads(1)%hi = [1.37_wp, 0.0_wp, 0.0_wp]
      r = resultant(cfg, trim(kernels(k)), 0.0_wp)
      call check_close(r(2), 3.0_wp*0.82_wp, 1.0e-13_wp, 0.0_wp, trim(kernels(k))//': strip, 3 Pa x 0.82 m')
      call check(r(1) == 0.0_wp, trim(kernels(k))//': no force along the face')
    end do
  end subroutine test_strip_load_has_its_exact_resultant

  !> The factor of each time function, as the resultant of a whole-face load over 6 N:
  !> ramp over 0.2 s at 0.05 s (0.25); sine of 5 Hz at 0.03 s (sin(0.3 pi)) and after
  !> its duration 0.1 s (0); table (0, 0), (0.1, 1), (0.3, -1) at 0.2 s (0), 0.05 s (0.5)
  !> and 0.5 s (-1, the last factor).
  subroutine test_load_time_functions()
    type(config_t) :: cfg
    real(wp), parameter :: pi = 3.14159265358979323846264338327950_wp
    call begin_test('load_time_functions')
    cfg = strip_scene()
    cfg%loads(1)%ramp_time = 0.2_wp
    call check_close(fy(cfg, 0.05_wp), 0.25_wp, 1.0e-14_wp, 0.0_wp, 'ramp')
    cfg = strip_scene()
    cfg%loads(1)%time_function = 'sine'
    cfg%loads(1)%frequency = 5.0_wp
    cfg%loads(1)%duration = 0.1_wp
    call check_close(fy(cfg, 0.03_wp), sin(0.3_wp*pi), 1.0e-14_wp, 0.0_wp, 'sine')
    call check(fy(cfg, 0.1_wp) == 0.0_wp, 'sine: 0 after its duration')
    cfg = strip_scene()
    cfg%loads(1)%time_function = 'table'
    cfg%loads(1)%times(1:3) = [0.0_wp, 0.1_wp, 0.3_wp]
    cfg%loads(1)%factors(1:3) = [0.0_wp, 1.0_wp, -1.0_wp]
    call check_close(fy(cfg, 0.2_wp), 0.0_wp, 0.0_wp, 1.0e-14_wp, 'table between entries 2 and 3')
    call check_close(fy(cfg, 0.05_wp), 0.5_wp, 1.0e-14_wp, 0.0_wp, 'table between entries 1 and 2')
    call check_close(fy(cfg, 0.5_wp), -1.0_wp, 1.0e-14_wp, 0.0_wp, 'table after its last entry')
  end subroutine test_load_time_functions

  real(wp) function fy(cfg, t)
    type(config_t), intent(in) :: cfg
    real(wp), intent(in) :: t
    real(wp) :: r(3)
    r = resultant(cfg, 'linear', t)
    fy = r(2)/6.0_wp
  end function fy

  !> An elastic block 2 m x 1 m (20 x 10 cells, rollers at the sides, fixed base) under
  !> 10 kPa on 0.5 <= x <= 1.25 m of its top, ramped over 0.02 s, to 0.1 s: as a face load
  !> on the grid's top face (the block fills the grid) and as a surface load (&load
  !> surface) on the same block in a grid 1.5 m high. The surface load takes the nodes
  !> the face load takes: on one rank the displacements agree bit for bit (measured), on
  !> two (other decompositions of the two grids) to 2.6e-13 of the largest (measured
  !> with the scene files); tolerance 1e-11.
  subroutine test_surface_load_matches_face_load()
    real(wp), allocatable :: uf(:, :), us(:, :)
    call begin_test('surface_load_matches_face_load')
    uf = top_loaded(1.0_wp, .false.)
    us = top_loaded(1.5_wp, .true.)
    if (am_root) then
      call check(size(uf, 2) == size(us, 2) .and. size(uf, 2) > 0, 'the same points')
      if (size(uf, 2) == size(us, 2)) &
        call check(maxval(abs(uf - us)) <= 1.0e-11_wp*maxval(abs(uf)), 'displacements agree')
      call check(maxval(abs(uf)) > 1.0e-4_wp, 'the load moved the block')
    end if
  end subroutine test_surface_load_matches_face_load

  !> Displacements at 0.1 s (by id, on rank 0) of the block of
  !> test_surface_load_matches_face_load in a grid of the given height, loaded on its
  !> surface or on the grid face.
  function top_loaded(height, surface) result(u)
    real(wp), intent(in) :: height
    logical, intent(in) :: surface
    real(wp), allocatable :: u(:, :)
    type(config_t) :: cfg
    type(simulation_t) :: sim
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x0(:, :), x(:, :), v(:, :), st(:, :)
    cfg%ndim = 2
    cfg%ncells = [20, nint(10.0_wp*height), 1]
    cfg%length = [2.0_wp, height, 1.0_wp]
    cfg%t_end = 0.1_wp
    cfg%cfl = 0.5_wp
    cfg%bc(1:3) = [bc_roller, bc_roller, bc_fixed]
    allocate (cfg%materials(1), cfg%regions(1), cfg%loads(1))
    cfg%materials(1) = material_cfg_t(id=1, model='linear_elastic', density=2000.0_wp, &
                                      youngs_modulus=1.0e7_wp, poisson_ratio=0.3_wp)
    cfg%regions(1)%lo = 0.0_wp
    cfg%regions(1)%hi = [2.0_wp, 1.0_wp, 1.0_wp]
    cfg%loads(1) = load_cfg_t(face=4, traction=[0.0_wp, -1.0e4_wp, 0.0_wp], ramp_time=0.02_wp, &
                              lo=[0.5_wp, 0.0_wp, 0.0_wp], hi=[1.25_wp, 0.0_wp, 0.0_wp], surface=surface)
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%gather_points(ids, x0, v, st)
    call sim%run()
    call sim%gather_points(ids, x, v, st)
    call sim%free()
    u = x - x0
  end function top_loaded

end program test_loads
