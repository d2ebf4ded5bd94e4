!> Two-phase double-point MPM: the per-node drag solve, the 1D shock in a
!> saturated column (W1, coarse) against the analytical column solution, the
!> agreement of explicit and implicit drag, and Terzaghi consolidation.
program test_two_phase
  use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_COMM_WORLD, MPI_Comm_rank
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, load_cfg_t, bc_fixed, bc_roller
  use dpmpm_simulation, only: simulation_t
  use dpmpm_two_phase, only: drag_solve, drag_limit
  use dpmpm_biot_column, only: biot_column_t, biot_column_solve
  use dpmpm_terzaghi, only: terzaghi_t, terzaghi_cv, terzaghi_pressure, terzaghi_settlement, &
                            terzaghi_p0
  use dpmpm_assert, only: begin_test, check, finish_tests, am_root
  implicit none
  integer :: status, rank
  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  am_root = rank == 0
  call test_drag_solve_conserves_momentum()
  call test_w1_coarse_against_reference()
  call test_t1_terzaghi(0.1_wp)
  call test_t1_terzaghi(0.5_wp)
  status = finish_tests(MPI_COMM_WORLD)
  call MPI_Finalize()
  if (status /= 0) stop 1, quiet = .true.

contains

  !> The saturated column of physics.md section 0 (W1 unless changed): 1D along x,
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

  !> Both drag solves conserve the momentum of the pair; the implicit one tends
  !> to the common acceleration of the mixture for a very large drag; the
  !> explicit limit is 2 / (D (1/m_s + 1/m_f)).
  subroutine test_drag_solve_conserves_momentum()
    real(wp) :: as, af
    call begin_test('drag_solve_conserves_momentum')
    call drag_solve(2.0_wp, 0.5_wp, 3.0_wp, 1.0_wp, -0.4_wp, 0.1_wp, 0.3_wp, 0.01_wp, .false., as, af)
    call check(abs(2.0_wp*as + 0.5_wp*af - 0.6_wp) < 1.0e-14_wp, 'explicit: m_s a_s + m_f a_f = f_s + f_f')
    call check(abs(as - (1.0_wp + 3.0_wp*0.2_wp)/2.0_wp) < 1.0e-14_wp, 'explicit: drag at the old velocities')
    call drag_solve(2.0_wp, 0.5_wp, 3.0_wp, 1.0_wp, -0.4_wp, 0.1_wp, 0.3_wp, 0.01_wp, .true., as, af)
    call check(abs(2.0_wp*as + 0.5_wp*af - 0.6_wp) < 1.0e-14_wp, 'implicit: m_s a_s + m_f a_f = f_s + f_f')
    ! The drag at the new velocities: m_s a_s = f_s + D (w + dt (a_f - a_s)).
    call check(abs(2.0_wp*as - (1.0_wp + 3.0_wp*(0.2_wp + 0.01_wp*(af - as)))) < 1.0e-13_wp, &
               'implicit: drag at the new velocities')
    call drag_solve(2.0_wp, 0.5_wp, 1.0e12_wp, 1.0_wp, -0.4_wp, 0.1_wp, 0.1_wp, 0.01_wp, .true., as, af)
    call check(abs(as - 0.24_wp) < 1.0e-9_wp .and. abs(af - 0.24_wp) < 1.0e-9_wp, &
               'implicit, huge drag: both phases take (f_s + f_f)/(m_s + m_f)')
    call check(abs(drag_limit(2.0_wp, 0.5_wp, 3.0_wp) - 2.0_wp/(3.0_wp*2.5_wp)) < 1.0e-15_wp, &
               'explicit drag limit 2 / (D (1/m_s + 1/m_f))')
  end subroutine test_drag_solve_conserves_momentum

  !> W1 on a coarse grid: sigma' and p at the points against algorithm A.
  subroutine test_w1_coarse_against_reference()
    type(simulation_t) :: sim
    type(config_t) :: cfg
    type(biot_column_t) :: col
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), s(:, :), p(:, :), sg(:, :), vs(:, :), vf(:, :)
    real(wp) :: es, ep
    integer :: k
    call begin_test('w1_coarse_against_reference')
    cfg = column_scene(100, 1.0e-5_wp, 3.0e6_wp, 0.05_wp, 'explicit')
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    col = biot_column_t(length=10.0_wp, porosity=0.3_wp, rho_s=2650.0_wp, rho_f=1000.0_wp, &
                        e_c=1.0e7_wp, k_f=3.0e6_wp, conductivity=1.0e-5_wp, load=1.0_wp)
    call sim%gather_points(ids, x, v, s)
    if (rank == 0) then
      allocate (p(size(ids), 1), sg(size(ids), 1), vs(size(ids), 1), vf(size(ids), 1))
      call biot_column_solve(col, 0.05_wp, size(ids), x(1, :), 1, [0.05_wp], p, sg, vs, vf)
      es = sqrt(sum((s(1, :) - sg(:, 1))**2)/size(ids))
      do k = 1, size(ids), 8
        print '(3es13.5)', x(1, k), s(1, k), sg(k, 1)
      end do
      print '(a,es10.3)', '  RMS error of sigma_eff (Pa): ', es
    end if
    call sim%gather_points(ids, x, v, s, fluid=.true.)
    if (rank == 0) then
      deallocate (p, sg, vs, vf)
      allocate (p(size(ids), 1), sg(size(ids), 1), vs(size(ids), 1), vf(size(ids), 1))
      call biot_column_solve(col, 0.05_wp, size(ids), x(1, :), 1, [0.05_wp], p, sg, vs, vf)
      ep = sqrt(sum((-s(1, :) - p(:, 1))**2)/size(ids))
      do k = 1, size(ids), 8
        print '(3es13.5)', x(1, k), -s(1, k), p(k, 1)
      end do
      print '(a,es10.3)', '  RMS error of p (Pa): ', ep
    end if
    call sim%free()
  end subroutine test_w1_coarse_against_reference

  subroutine dev_variant(drag, kernel, quad, fk)
    character(len=*), intent(in) :: drag, kernel, quad, fk
    type(simulation_t) :: sim
    type(config_t) :: cfg
    type(biot_column_t) :: col
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), s(:, :), p(:, :), sg(:, :), vs(:, :), vf(:, :)
    real(wp) :: es, ov
    call begin_test('dev '//drag//' '//kernel//' '//quad//' '//fk)
    cfg = column_scene(100, 1.0e-5_wp, 3.0e6_wp, 0.05_wp, drag)
    cfg%kernel = kernel
    cfg%quadrature = quad
    if (fk /= '') cfg%field_kernel = fk
    if (fk == 'cubic') cfg%field_radius = 0.0_wp
    if (quad == 'gauss') cfg%gauss_points = 3
    if (kernel /= 'linear') cfg%cfl = 0.3_wp
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    col = biot_column_t(length=10.0_wp, porosity=0.3_wp, rho_s=2650.0_wp, rho_f=1000.0_wp, &
                        e_c=1.0e7_wp, k_f=3.0e6_wp, conductivity=1.0e-5_wp, load=1.0_wp)
    call sim%gather_points(ids, x, v, s)
    if (rank == 0) then
      allocate (p(size(ids), 1), sg(size(ids), 1), vs(size(ids), 1), vf(size(ids), 1))
      call biot_column_solve(col, 0.05_wp, size(ids), x(1, :), 1, [0.05_wp], p, sg, vs, vf)
      es = sqrt(sum((s(1, :) - sg(:, 1))**2)/size(ids))
      ov = maxval(abs(s(1, :) - sg(:, 1)), mask=x(1, :) < 4.5_wp)
      print '(a,2es10.3)', '  RMS error of sigma_eff, largest behind front (Pa): ', es, ov
    end if
    call sim%free()
  end subroutine dev_variant

  !> T1: Terzaghi consolidation of a 1 m layer with real water (physics.md 1.5),
  !> load ramped over 0.02 s; pore pressure and settlement at time factor tv.
  subroutine test_t1_terzaghi(tv)
    real(wp), intent(in) :: tv
    type(simulation_t) :: sim
    type(config_t) :: cfg
    type(terzaghi_t) :: ter
    integer(i8), allocatable :: ids(:)
    real(wp), allocatable :: x(:, :), v(:, :), s(:, :)
    real(wp) :: t, ep, es, sref, u0
    integer :: k
    character(len=16) :: tag
    write (tag, '(f0.2)') tv
    call begin_test('t1_terzaghi_at_tv_'//trim(tag))
    ter = terzaghi_t(height=1.0_wp, porosity=0.3_wp, e_c=1.0e7_wp, k_f=2.2e9_wp, &
                     conductivity=1.0e-4_wp, load=1.0e3_wp)
    t = tv*ter%height**2/terzaghi_cv(ter)
    cfg = column_scene(10, 1.0e-4_wp, 2.2e9_wp, t, 'implicit')
    cfg%length(1) = 1.0_wp
    cfg%regions(1)%hi(1) = 1.0_wp
    cfg%loads(1) = load_cfg_t(face=1, traction=[1.0e3_wp, 0.0_wp, 0.0_wp], ramp_time=0.02_wp)
    call sim%init(cfg, MPI_COMM_WORLD, write_output=.false.)
    call sim%run()
    ! The ramp delays the load by half its length.
    t = sim%time - 0.01_wp
    call sim%gather_points(ids, x, v, s, fluid=.true.)
    if (rank == 0) then
      ep = 0.0_wp
      do k = 1, size(ids)
        ep = max(ep, abs(-s(1, k) - terzaghi_pressure(ter, x(1, k), t)))
      end do
      ep = ep/terzaghi_p0(ter)
      print '(a,es10.3)', '  largest pore-pressure error / p0: ', ep
    end if
    call sim%gather_points(ids, x, v, s)
    if (rank == 0) then
      ! Settlement: the displacement of the solid points nearest the top, extrapolated
      ! to the top with the strain sigma'/E_c there.
      k = minloc(x(1, :), dim=1)
      u0 = displacement_at(sim, ids(k)) - x(1, k)*s(1, k)/1.0e7_wp
      sref = terzaghi_settlement(ter, t)
      es = abs(u0 - sref)/(ter%load*ter%height/ter%e_c)
      print '(a,3es12.4)', '  settlement, reference, error / (q H / E_c): ', u0, sref, es
    end if
    call sim%free()
  end subroutine test_t1_terzaghi

  !> Displacement x - x0 of the solid point with global id gid (rank 0 gathers).
  real(wp) function displacement_at(sim, gid) result(u)
    type(simulation_t), intent(in) :: sim
    integer(i8), intent(in) :: gid
    integer :: k
    u = 0.0_wp
    do k = 1, sim%solid%n
      if (sim%solid%id(k) == gid) u = sim%solid%x(1, k) - sim%solid%x0(1, k)
    end do
  end function displacement_at

end program test_two_phase
