!> Point generation tests on 1, 2 or 4 ranks: the solid and fluid sets of a scene with
!> solid, fluid and saturated regions and every placement. Masses, volumes, porosities and
!> inverse conductivities follow the phase rules; uniform placement puts N equal points in a
!> box; and on every rank layout each set is exactly the set one rank alone generates
!> (same ids, positions and values, every point once, on the rank owning its cell). The
!> generation itself needs only a range of cells: blocks of cells that tile the grid give
!> the whole set between them. A set holds only the fields its scene needs: its bytes
!> per point are those of the fields asked for.
program test_generate
  use mpi_f08, only: MPI_COMM_WORLD, MPI_COMM_SELF, MPI_Comm_size, MPI_Allreduce, MPI_IN_PLACE, &
                     MPI_SUM, MPI_INTEGER, MPI_DOUBLE_PRECISION
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, material_cfg_t, region_cfg_t
  use dpmpm_grid, only: grid_t, cell_of
  use dpmpm_decomp, only: decomp_t
  use dpmpm_particles, only: particle_set_t
  use dpmpm_materials, only: material_t, materials_from_config
  use dpmpm_migrate, only: check_owned
  use dpmpm_generate, only: generate_points, point_in_polygon
  use dpmpm_test_layouts, only: layouts_for
  use dpmpm_assert, only: begin_test, check, check_close, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests
  implicit none

  real(wp), parameter :: rho_soil = 2650.0_wp, rho_water = 1000.0_wp, rho_steel = 7850.0_wp
  real(wp), parameter :: k_soil = 1.0e-4_wp, n_sat = 0.4_wp
  integer :: nranks, rank
  !> Largest relative departure of a quarter's count from a quarter of the points
  real(wp), parameter :: stirred_quarter_bound = 0.15_wp

  call start_tests(rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  call test_phase_masses_and_volumes()
  call test_uniform_box_and_polygon()
  call test_default_phase_is_solid()
  call test_sets_do_not_depend_on_ranks()
  call test_cell_blocks_tile_the_set()
  call test_point_memory_follows_the_fields()
  call test_stirred_points_are_the_lattice_moved()
  call end_tests()

contains

  ! ------------------------------------------------------------------ scene

  !> A 2D grid of 12 x 10 cells of 0.1 m with materials 1 soil (k > 0), 2 water, 3 steel.
  subroutine make_config(cfg)
    type(config_t), intent(out) :: cfg
    cfg%ndim = 2
    cfg%ncells = [12, 10, 1]
    cfg%origin = [-0.5_wp, 0.2_wp, 0.0_wp]
    cfg%length = [1.2_wp, 1.0_wp, 1.0_wp]
    allocate (cfg%materials(3))
    cfg%materials(1) = material_cfg_t(id=1, density=rho_soil, youngs_modulus=1.0e7_wp, &
                                      conductivity=k_soil)
    cfg%materials(2) = material_cfg_t(id=2, model='fluid', density=rho_water, &
                                      bulk_modulus=2.2e9_wp)
    cfg%materials(3) = material_cfg_t(id=3, density=rho_steel)
  end subroutine make_config

  !> A box region of one phase aligned with the cells.
  function box(lo, hi, phase, material, placement) result(r)
    real(wp), intent(in) :: lo(2), hi(2)
    character(len=*), intent(in) :: phase, placement
    integer, intent(in) :: material
    type(region_cfg_t) :: r
    r%lo(1:2) = lo
    r%hi(1:2) = hi
    r%phase = phase
    r%material = material
    r%placement = placement
    if (phase == 'saturated') then
      r%fluid_material = 2
      r%porosity = n_sat
    end if
  end function box

  !> The scene: a steel block (regular), a saturated layer (random), water above it up to the
  !> upper grid face (uniform), a saturated wedge (polygon, uniform), a steel strip
  !> (uniform, ppc 3) and a pond of water (polygon, stirred) over the block and the layer.
  subroutine make_scene(cfg)
    type(config_t), intent(out) :: cfg
    call make_config(cfg)
    allocate (cfg%regions(6))
    cfg%regions(1) = box([-0.5_wp, 0.2_wp], [-0.2_wp, 0.5_wp], 'solid', 3, 'regular')
    cfg%regions(2) = box([-0.2_wp, 0.2_wp], [0.7_wp, 0.6_wp], 'saturated', 1, 'random')
    cfg%regions(2)%seed = 5
    cfg%regions(3) = box([-0.2_wp, 0.6_wp], [0.7_wp, 1.2_wp], 'fluid', 2, 'uniform')
    cfg%regions(3)%seed = 9
    cfg%regions(4)%shape = 'polygon'
    cfg%regions(4)%npoly = 3
    cfg%regions(4)%poly(:, 1:3) = reshape([-0.5_wp, 0.6_wp, -0.25_wp, 0.6_wp, -0.5_wp, &
                                           1.0_wp], [2, 3])
    cfg%regions(4)%phase = 'saturated'
    cfg%regions(4)%material = 1
    cfg%regions(4)%fluid_material = 2
    cfg%regions(4)%porosity = 0.3_wp
    cfg%regions(4)%placement = 'uniform'
    cfg%regions(4)%fluid_seed = 17
    cfg%regions(5) = box([-0.45_wp, 1.0_wp], [-0.3_wp, 1.15_wp], 'solid', 3, 'uniform')
    cfg%regions(5)%ppc = 3
    cfg%regions(6)%shape = 'polygon'
    cfg%regions(6)%npoly = 4
    cfg%regions(6)%poly(:, 1:4) = reshape([-0.45_wp, 0.25_wp, 0.3_wp, 0.3_wp, 0.6_wp, &
                                           0.55_wp, -0.4_wp, 0.5_wp], [2, 4])
    cfg%regions(6)%phase = 'fluid'
    cfg%regions(6)%material = 2
    cfg%regions(6)%placement = 'stirred'
    cfg%regions(6)%seed = 3
  end subroutine make_scene

  !> Grid, decomposition over comm with layout dims, materials and one set of a phase.
  subroutine generate(cfg, comm_world, dims, phase, ps, grid, dec)
    type(config_t), intent(in) :: cfg
    logical, intent(in) :: comm_world
    integer, intent(in) :: dims(3)
    character(len=*), intent(in) :: phase
    type(particle_set_t), intent(out) :: ps
    type(grid_t), intent(out) :: grid
    type(decomp_t), intent(inout) :: dec
    type(material_t), allocatable :: mats(:)
    call grid%init(cfg)
    if (comm_world) then
      call dec%init(MPI_COMM_WORLD, cfg%ndim, cfg%ncells, 1, dims)
    else
      call dec%init(MPI_COMM_SELF, cfg%ndim, cfg%ncells, 1, [0, 0, 0])
    end if
    call materials_from_config(cfg%materials, mats)
    call ps%init(phase, cfg%ndim, .false., has_porosity=.true., has_pressure=phase == 'fluid')
    call generate_points(cfg, grid, dec%clo, dec%chi, mats, ps, phase)
  end subroutine generate

  real(wp) function gsum(x)
    real(wp), intent(in) :: x
    gsum = x
    call MPI_Allreduce(MPI_IN_PLACE, gsum, 1, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD)
  end function gsum

  integer function isum(x)
    integer, intent(in) :: x
    isum = x
    call MPI_Allreduce(MPI_IN_PLACE, isum, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
  end function isum

  ! ------------------------------------------------------------------ tests

  !> A steel block, a saturated layer and water: each set fills its regions (volumes add up
  !> to the region volumes), masses are (1 - n) rho_s V and n rho_f V in the saturated layer,
  !> porosity and 1/k are stored as the phase rules say, and the pore fluid points are not
  !> placed on the skeleton points.
  subroutine test_phase_masses_and_volumes()
    type(config_t) :: cfg
    type(particle_set_t) :: solid, fluid
    type(grid_t) :: grid
    type(decomp_t) :: dec
    real(wp), parameter :: v_steel = 0.3_wp*0.3_wp, v_sat = 0.9_wp*0.4_wp, v_water = 0.9_wp*0.6_wp
    integer :: k, j, nsame
    logical :: ok
    call begin_test('phase_masses_and_volumes')
    call make_scene(cfg)
    cfg%regions = cfg%regions(1:3)
    call generate(cfg, .true., [0, 0, 0], 'solid', solid, grid, dec)
    call check_close(gsum(sum(solid%vol(1:solid%n))), v_steel + v_sat, 1.0e-12_wp, 0.0_wp, &
                     'solid set volume = steel + saturated layer')
    call check_close(gsum(sum(solid%mass(1:solid%n))), rho_steel*v_steel + &
                     (1.0_wp - n_sat)*rho_soil*v_sat, 1.0e-12_wp, 0.0_wp, 'solid set mass')
    ok = .true.
    do k = 1, solid%n
      if (solid%mat(k) == 1) then
        ok = ok .and. solid%porosity(k) == n_sat .and. &
             abs(solid%mass(k) - (1.0_wp - n_sat)*rho_soil*solid%vol(k)) <= 1.0e-12_wp*solid%mass(k)
      else
        ok = ok .and. solid%mat(k) == 3 .and. solid%porosity(k) == 0.0_wp
      end if
    end do
    call check(ok, 'solid points: porosity n in the saturated layer, 0 in the steel')
    call check(all(solid%stress(:, 1:solid%n) == 0.0_wp), 'solid points start unstressed')

    call generate(cfg, .true., [0, 0, 0], 'fluid', fluid, grid, dec)
    call check_close(gsum(sum(fluid%vol(1:fluid%n))), v_sat + v_water, 1.0e-12_wp, 0.0_wp, &
                     'fluid set volume = saturated layer + water')
    call check_close(gsum(sum(fluid%mass(1:fluid%n))), n_sat*rho_water*v_sat + &
                     rho_water*v_water, 1.0e-12_wp, 0.0_wp, 'fluid set mass')
    call check(all(fluid%mat(1:fluid%n) == 2), 'fluid points carry the fluid material')
    call check(all(fluid%pressure(1:fluid%n) == 0.0_wp), 'fluid points start at zero pressure')
    ok = .true.
    do k = 1, fluid%n
      if (fluid%porosity(k) == 1.0_wp) then
        ok = ok .and. fluid%kinv(k) == 0.0_wp .and. fluid%mass(k) == rho_water*fluid%vol(k)
      else
        ok = ok .and. fluid%porosity(k) == n_sat .and. fluid%kinv(k) == 1.0_wp/k_soil .and. &
             abs(fluid%mass(k) - n_sat*rho_water*fluid%vol(k)) <= 1.0e-12_wp*fluid%mass(k)
      end if
    end do
    call check(ok, 'fluid points: porosity, 1/k and mass of free water and pore fluid')
    ! Pore fluid and skeleton share ids and slots but not positions (seed + 1).
    nsame = 0
    do k = 1, fluid%n
      if (fluid%porosity(k) == 1.0_wp) cycle
      j = findloc(solid%id(1:solid%n), fluid%id(k), dim=1)
      if (j > 0) then
        if (all(solid%x(:, j) == fluid%x(:, k))) nsame = nsame + 1
      end if
    end do
    call check_equal_int(isum(nsame), 0, 'pore fluid points placed apart from the skeleton')
  end subroutine test_phase_masses_and_volumes

  !> Uniform placement: N = nint(V / cell volume * ppc**2) points of volume V / N in a box,
  !> ids base + 1 .. base + N, all inside; polygon candidates kept inside the polygon with
  !> the volume of a cell share.
  subroutine test_uniform_box_and_polygon()
    type(config_t) :: cfg
    type(particle_set_t) :: solid, fluid
    type(grid_t) :: grid
    type(decomp_t) :: dec
    integer :: k, n
    integer(i8) :: base
    logical :: ok
    call begin_test('uniform_box_and_polygon')
    call make_scene(cfg)
    call generate(cfg, .true., [0, 0, 0], 'fluid', fluid, grid, dec)
    ! Region 3 (water, 0.9 x 0.6 m, ppc 2): N = 54 cells * 4 = 216; ids after regions 1, 2.
    base = 2_i8*120_i8*4_i8
    n = count(fluid%id(1:fluid%n) > base .and. fluid%id(1:fluid%n) <= base + 216)
    call check_equal_int(isum(n), 216, 'water: N points')
    ok = .true.
    do k = 1, fluid%n
      if (fluid%id(k) <= base .or. fluid%id(k) > base + 216) cycle
      ok = ok .and. abs(fluid%vol(k) - 0.9_wp*0.6_wp/216.0_wp) <= 1.0e-15_wp .and. &
           fluid%porosity(k) == 1.0_wp
      ok = ok .and. fluid%x(1, k) >= -0.2_wp .and. fluid%x(1, k) < 0.7_wp .and. &
           fluid%x(2, k) >= 0.6_wp .and. fluid%x(2, k) < 1.2_wp
    end do
    call check(ok, 'water: equal volumes V / N, inside the box')
    ! Region 4 (wedge): candidates over its 0.25 x 0.4 m bounding box, kept inside.
    base = 3_i8*120_i8*4_i8
    ok = .true.
    n = 0
    do k = 1, fluid%n
      if (fluid%id(k) <= base .or. fluid%id(k) > base + 120_i8*4_i8) cycle
      n = n + 1
      ok = ok .and. point_in_polygon(fluid%x(:, k), cfg%regions(4)%poly(:, 1:3)) .and. &
           abs(fluid%vol(k) - 0.01_wp/4.0_wp) <= 1.0e-15_wp .and. fluid%porosity(k) == 0.3_wp
      ok = ok .and. fluid%id(k) <= base + 40   ! nint(0.1 / 0.01 * 4) candidates
    end do
    call check(ok, 'wedge: points inside the polygon, cell share volume, ids of candidates')
    n = isum(n)
    call check(n > 10 .and. n < 30, 'wedge: about half of the 40 candidates kept')
    ! Region 5 (steel strip 0.15 x 0.15 m, ppc 3): N = nint(2.25 * 9) = 20.
    call generate(cfg, .true., [0, 0, 0], 'solid', solid, grid, dec)
    base = 4_i8*120_i8*4_i8
    n = count(solid%id(1:solid%n) > base)
    call check_equal_int(isum(n), 20, 'steel strip: N points')
    call check_close(gsum(sum(solid%vol(1:solid%n), mask=solid%id(1:solid%n) > base)), &
                     0.15_wp*0.15_wp, 1.0e-13_wp, 0.0_wp, 'steel strip: volumes fill the box')
  end subroutine test_uniform_box_and_polygon

  !> Without phase, generate_points fills the solid set; regular points keep the ids
  !> (global cell)*ppc**ndim + slot + 1 of the first region.
  subroutine test_default_phase_is_solid()
    type(config_t) :: cfg
    type(particle_set_t) :: a, b
    type(grid_t) :: grid
    type(decomp_t) :: dec
    type(material_t), allocatable :: mats(:)
    integer :: k, cell, slot
    real(wp) :: s(2)
    logical :: ok
    call begin_test('default_phase_is_solid')
    call make_scene(cfg)
    call generate(cfg, .true., [0, 0, 0], 'solid', a, grid, dec)
    call materials_from_config(cfg%materials, mats)
    call b%init('solid', cfg%ndim, .false.)
    call generate_points(cfg, grid, dec%clo, dec%chi, mats, b)
    call check_equal_int(b%n, a%n, 'same number of points')
    if (b%n == a%n) call check(all(a%id(1:a%n) == b%id(1:b%n)) .and. &
                               all(a%x(:, 1:a%n) == b%x(:, 1:b%n)) .and. &
                               all(a%mass(1:a%n) == b%mass(1:b%n)), 'same points')
    ok = .true.
    do k = 1, b%n
      if (b%id(k) > 480) cycle
      ! Cell (i, j) of 0.1 m from (-0.5, 0.2); slot (a, b) from the quarter of the cell.
      s = [(b%x(1, k) + 0.5_wp)/0.1_wp, (b%x(2, k) - 0.2_wp)/0.1_wp]
      cell = floor(s(1)) + 12*floor(s(2))
      slot = merge(1, 0, s(1) - floor(s(1)) > 0.5_wp) + 2*merge(1, 0, s(2) - floor(s(2)) > 0.5_wp)
      ok = ok .and. b%id(k) == 4*cell + slot + 1
    end do
    call check(ok, 'regular ids from the global cell and slot')
  end subroutine test_default_phase_is_solid

  !> On every rank layout, each set holds exactly the points one rank alone generates:
  !> every id once over the ranks, the same position, mass, volume, porosity, 1/k and
  !> material, and every point on the rank owning its cell.
  subroutine test_sets_do_not_depend_on_ranks()
    type(config_t) :: cfg
    type(particle_set_t) :: ps, ref
    type(grid_t) :: grid
    type(decomp_t) :: dec, dec1
    integer, allocatable :: layouts(:, :), seen(:)
    integer :: l, p, k, j, nbad, ndup
    character(len=5), parameter :: phases(2) = ['solid', 'fluid']
    character(len=64) :: what
    logical :: same
    call begin_test('sets_do_not_depend_on_ranks')
    call make_scene(cfg)
    call layouts_for(2, nranks, layouts)
    do p = 1, 2
      call generate(cfg, .false., [0, 0, 0], phases(p), ref, grid, dec1)
      ndup = 0
      do k = 1, ref%n
        if (count(ref%id(1:ref%n) == ref%id(k)) /= 1) ndup = ndup + 1
      end do
      call check_equal_int(ndup, 0, trim(phases(p))//': ids unique')
      do l = 1, size(layouts, 2)
        write (what, '(a,a,3i2)') trim(phases(p)), ' layout', layouts(:, l)
        call generate(cfg, .true., layouts(:, l), phases(p), ps, grid, dec)
        allocate (seen(ref%n))
        seen = 0
        same = .true.
        do k = 1, ps%n
          j = findloc(ref%id(1:ref%n), ps%id(k), dim=1)
          if (j == 0) then
            same = .false.
            cycle
          end if
          seen(j) = seen(j) + 1
          same = same .and. all(ps%x(:, k) == ref%x(:, j)) .and. ps%mass(k) == ref%mass(j) .and. &
                 ps%vol(k) == ref%vol(j) .and. ps%porosity(k) == ref%porosity(j) .and. &
                 ps%mat(k) == ref%mat(j)
          if (p == 2) same = same .and. ps%kinv(k) == ref%kinv(j)
        end do
        call check(same, trim(what)//': every point as generated on one rank')
        call MPI_Allreduce(MPI_IN_PLACE, seen, ref%n, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
        call check(all(seen == 1), trim(what)//': every point on exactly one rank')
        call check_owned(dec, grid%origin, grid%h, ps, nbad)
        call check_equal_int(nbad, 0, trim(what)//': points on the rank owning their cell')
        deallocate (seen)
        call dec%free()
      end do
      call dec1%free()
    end do
  end subroutine test_sets_do_not_depend_on_ranks

  !> generate_points on four blocks of cells that tile the grid, without any decomposition:
  !> each block gets exactly the points of the whole grid whose cells lie in it.
  subroutine test_cell_blocks_tile_the_set()
    type(config_t) :: cfg
    type(grid_t) :: grid
    type(material_t), allocatable :: mats(:)
    type(particle_set_t) :: whole, part
    character(len=5), parameter :: phases(2) = ['solid', 'fluid']
    integer :: ip, b, k, n, c(3), lo(3, 4), hi(3, 4)
    logical :: ok
    call begin_test('cell_blocks_tile_the_set')
    call make_scene(cfg)
    call grid%init(cfg)
    call materials_from_config(cfg%materials, mats)
    ! x cells 0..4 | 5..11, y cells 0..3 | 4..9
    lo = reshape([0, 0, 0, 5, 0, 0, 0, 4, 0, 5, 4, 0], [3, 4])
    hi = reshape([4, 3, 0, 11, 3, 0, 4, 9, 0, 11, 9, 0], [3, 4])
    do ip = 1, 2
      call whole%init(phases(ip), cfg%ndim, .false., has_porosity=.true., &
                      has_pressure=ip == 2)
      call generate_points(cfg, grid, [0, 0, 0], grid%ncells - 1, mats, whole, phases(ip))
      n = 0
      ok = .true.
      do b = 1, 4
        call part%init(phases(ip), cfg%ndim, .false., has_porosity=.true., &
                       has_pressure=ip == 2)
        call generate_points(cfg, grid, lo(:, b), hi(:, b), mats, part, phases(ip))
        n = n + part%n
        do k = 1, part%n
          c = cell_of(grid%origin, grid%h, part%x(:, k), grid%ndim)
          if (any(c < lo(:, b) .or. c > hi(:, b))) ok = .false.
          if (count(whole%id(1:whole%n) == part%id(k)) /= 1) ok = .false.
        end do
      end do
      call check(whole%n > 0, phases(ip)//': the scene makes points')
      call check_equal_int(n, whole%n, phases(ip)//': the blocks hold every point once')
      call check(ok, phases(ip)//': each point in its block, with an id of the whole set')
    end do
  end subroutine test_cell_blocks_tile_the_set

  !> Bytes per point of a 2D set: id (8), material index (4), x, x0, v (3 x 2 x 8), mass,
  !> vol, vol0 (3 x 8) and stress (6 x 8) always, 132 in all; F adds 72 (neo-Hookean),
  !> porosity 8 (two-phase scenes), pore pressure and 1/k 16 (fluid points), the plastic
  !> strain 8 (plastic soils).
  subroutine test_point_memory_follows_the_fields()
    type(particle_set_t) :: ps
    call begin_test('point_memory_follows_the_fields')
    call ps%init('solid', 2, .false.)
    call check_equal_int(ps%bytes_per_point(), 132, 'elastic, one phase')
    call ps%init('solid', 2, .true.)
    call check_equal_int(ps%bytes_per_point(), 132 + 72, 'neo-Hookean')
    call ps%init('solid', 2, .false., has_porosity=.true., nstate=1)
    call check_equal_int(ps%bytes_per_point(), 132 + 8 + 8, 'plastic soil skeleton')
    call ps%init('fluid', 2, .false., has_porosity=.true., has_pressure=.true.)
    call check_equal_int(ps%bytes_per_point(), 132 + 8 + 16, 'pore fluid')
    call ps%free()
  end subroutine test_point_memory_follows_the_fields

  !> Stirred placement of a saturated box of 8 x 6 cells (ppc 2): each set holds the points
  !> of the regular placement (the same ids, volumes and masses), moved inside the box, no
  !> two on one spot, most of them by more than a tenth of a cell; the shears keep the
  !> density: each quarter of the box holds a quarter of the points within the bound
  !> below (measured: doc/verification.md, "Saturated soil at rest on scattered points").
  subroutine test_stirred_points_are_the_lattice_moved()
    type(config_t) :: cfg
    type(particle_set_t) :: st, reg
    type(grid_t) :: grid
    type(decomp_t) :: dec
    character(len=5), parameter :: phases(2) = ['solid', 'fluid']
    real(wp), parameter :: lo(2) = [-0.3_wp, 0.3_wp], hi(2) = [0.5_wp, 0.9_wp]
    integer :: ip, k, j, nmoved, nq(4), q
    real(wp) :: dmin
    logical :: same
    call begin_test('stirred_points_are_the_lattice_moved')
    do ip = 1, 2
      call make_config(cfg)
      allocate (cfg%regions(1))
      cfg%regions(1) = box(lo, hi, 'saturated', 1, 'regular')
      call generate(cfg, .false., [0, 0, 0], phases(ip), reg, grid, dec)
      call dec%free()
      cfg%regions(1)%placement = 'stirred'
      call generate(cfg, .false., [0, 0, 0], phases(ip), st, grid, dec)
      call dec%free()
      call check_equal_int(st%n, reg%n, phases(ip)//': as many points as the regular placement')
      same = st%n == reg%n
      nmoved = 0
      nq = 0
      dmin = huge(1.0_wp)
      do k = 1, st%n
        j = findloc(reg%id(1:reg%n), st%id(k), dim=1)
        if (j == 0) then
          same = .false.
          cycle
        end if
        same = same .and. st%vol(k) == reg%vol(j) .and. st%mass(k) == reg%mass(j)
        same = same .and. all(st%x(1:2, k) >= lo) .and. all(st%x(1:2, k) < hi)
        if (norm2(st%x(1:2, k) - reg%x(1:2, j)) > 0.01_wp) nmoved = nmoved + 1
        q = 1 + merge(1, 0, st%x(1, k) >= 0.5_wp*(lo(1) + hi(1))) + &
            2*merge(1, 0, st%x(2, k) >= 0.5_wp*(lo(2) + hi(2)))
        nq(q) = nq(q) + 1
        do j = k + 1, st%n
          dmin = min(dmin, norm2(st%x(1:2, k) - st%x(1:2, j)))
        end do
      end do
      call check(same, phases(ip)//': the regular ids, volumes and masses, inside the box')
      call check(dmin > 0.0_wp, phases(ip)//': no two points on one spot')
      call check(nmoved > 3*st%n/4, phases(ip)//': most points moved')
      write (*, '(2a, 4i5, a, i5, a, es10.3)') phases(ip), ' quarters', nq, ' of', st%n, &
        ' nearest pair', dmin
      call check(all(abs(real(nq, wp) - 0.25_wp*st%n) <= stirred_quarter_bound*0.25_wp*st%n), &
                 phases(ip)//': each quarter holds about a quarter of the points')
    end do
  end subroutine test_stirred_points_are_the_lattice_moved

end program test_generate
