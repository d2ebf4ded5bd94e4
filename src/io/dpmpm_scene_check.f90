!> Checks of a scene that need its points: every &region makes points, no two regions
!> overlap (the points of both would fill the overlap twice, with twice its mass), and
!> every &load and absorbing face acts on a face that the body touches. Run once the points are generated; a failure is
!> reported like an input error, once by rank 0, and every rank returns status 2 (the
!> caller stops, with exit code 2).
module dpmpm_scene_check
  use, intrinsic :: iso_fortran_env, only: error_unit
  use dpmpm_kinds, only: wp, i8
  use dpmpm_config, only: config_t, face_names
  use dpmpm_grid, only: grid_t, cell_of
  use dpmpm_particles, only: particle_set_t
  use dpmpm_generate, only: in_region
  use dpmpm_strings, only: itoa, i8toa
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER8, MPI_SUM
  implicit none
  private
  public :: check_scene_points

contains

  !> counts(r): points region r made on this rank (both sets). A region without any point
  !> on any rank, or a load on a face with no point in the layer of cells next to it (its
  !> traction would act on empty nodes), is refused: status 2 on every rank, else 0.
  !> Collective over comm.
  subroutine check_scene_points(cfg, grid, comm, counts, solid, status, fluid)
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: grid
    type(MPI_Comm), intent(in) :: comm
    integer(i8), intent(in) :: counts(:)
    type(particle_set_t), intent(in) :: solid
    integer, intent(out) :: status
    type(particle_set_t), intent(in), optional :: fluid
    integer(i8), allocatable :: nreg(:), nload(:), both(:, :)
    integer(i8) :: nabs(6)
    integer :: r, l, f, rank, nbad, j
    character(len=32) :: spacing
    call MPI_Comm_rank(comm, rank)
    nreg = counts
    call MPI_Allreduce(MPI_IN_PLACE, nreg, size(nreg), MPI_INTEGER8, MPI_SUM, comm)
    allocate (both(size(nreg), size(nreg)))
    both = 0
    call count_overlaps(cfg, grid%ndim, solid, both)
    if (present(fluid)) call count_overlaps(cfg, grid%ndim, fluid, both)
    call MPI_Allreduce(MPI_IN_PLACE, both, size(both), MPI_INTEGER8, MPI_SUM, comm)
    ! (a config_t built by hand may have no load list at all)
    if (allocated(cfg%loads)) then
      allocate (nload(size(cfg%loads)))
    else
      allocate (nload(0))
    end if
    do l = 1, size(nload)
      if (cfg%loads(l)%surface) then
        ! on the body's surface: any solid point under lo..hi
        nload(l) = points_next_to_face(grid, cfg%loads(l)%face, solid, cfg%loads(l)%lo, cfg%loads(l)%hi, &
                                       anywhere=.true.)
        cycle
      end if
      nload(l) = points_next_to_face(grid, cfg%loads(l)%face, solid, cfg%loads(l)%lo, cfg%loads(l)%hi)
      if (present(fluid)) nload(l) = nload(l) + points_next_to_face(grid, cfg%loads(l)%face, fluid, &
                                                                    cfg%loads(l)%lo, cfg%loads(l)%hi)
    end do
    call MPI_Allreduce(MPI_IN_PLACE, nload, size(nload), MPI_INTEGER8, MPI_SUM, comm)
    nabs = 1
    do f = 1, 2*cfg%ndim
      if (cfg%absorbing(f) == 0) cycle
      nabs(f) = points_next_to_face(grid, f, solid)
      if (present(fluid)) nabs(f) = nabs(f) + points_next_to_face(grid, f, fluid)
    end do
    call MPI_Allreduce(MPI_IN_PLACE, nabs, 6, MPI_INTEGER8, MPI_SUM, comm)
    nbad = count(nreg == 0) + count(nload == 0) + count(nabs == 0) + count(both > 0)
    status = 0
    if (nbad == 0) return
    if (rank == 0) then
      do r = 1, size(nreg)
        do j = 1, r - 1
          if (both(j, r) == 0) cycle
          call report(cfg, '&region'//region_place(cfg, r)//': its '//outline(cfg, r)// &
                      ' overlap the '//outline(cfg, j)//' of &region'//region_place(cfg, j)// &
                      ': '//i8toa(both(j, r))//' points lie in both, so that the overlap is '// &
                      'filled twice (its points and mass count twice); regions must not '// &
                      'overlap: let them meet at a common face')
        end do
      end do
      do r = 1, size(nreg)
        if (nreg(r) > 0) cycle
        write (spacing, '(es10.3)') minval(grid%h(1:grid%ndim))/real(cfg%regions(r)%ppc, wp)
        call report(cfg, '&region'//which(r, size(nreg))//': makes no points: no point '// &
                    'position of its placement falls inside it (the points are '// &
                    trim(adjustl(spacing))//' m apart with ppc = '//itoa(cfg%regions(r)%ppc)// &
                    '); make it larger or raise ppc')
      end do
      do l = 1, size(nload)
        if (nload(l) > 0) cycle
        f = cfg%loads(l)%face
        if (cfg%loads(l)%surface) then
          call report(cfg, '&load'//which(l, size(nload))//' face = '''//face_names(f)// &
                      ''', surface = .true.: no point of the body lies within lo..hi along the '// &
                      'face, so the traction would act on nothing; move lo..hi over the body')
          cycle
        end if
        call report(cfg, '&load'//which(l, size(nload))//' face = '''//face_names(f)// &
                    ''': the body does not touch face '//face_names(f)//' (no point in the '// &
                    'layer of cells next to it, or next to lo..hi on it), so the traction '// &
                    'would act on nothing; '// &
                    'move the load to a face the body reaches, or extend the body to it')
      end do
      do f = 1, 6
        if (nabs(f) > 0) cycle
        call report(cfg, '&boundary face = '''//face_names(f)//''', condition = '// &
                    '''absorbing'': the body does not touch face '//face_names(f)//' (no '// &
                    'point in the layer of cells next to it), so its dashpots would act on '// &
                    'nothing; extend the body to the face')
      end do
      flush (error_unit)
    end if
    status = 2
  end subroutine check_scene_points

  !> " (group k of n, line L)" of &region k (" (line L)" when it is the only one).
  function region_place(cfg, k) result(s)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    s = 'line '//itoa(cfg%regions(k)%line)
    if (size(cfg%regions) > 1) s = 'group '//itoa(k)//' of '//itoa(size(cfg%regions))//', '//s
    s = ' ('//s//')'
  end function region_place

  !> The variables that give the outline of &region k: lo, hi or poly_x, poly_y.
  function outline(cfg, k) result(s)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    s = 'lo, hi'
    if (trim(cfg%regions(k)%shape) == 'polygon') s = 'poly_x, poly_y'
  end function outline

  !> both(j, k), j < k: points of ps that lie in both region j and region k (by the test
  !> that keeps a generated point), added to what both holds.
  subroutine count_overlaps(cfg, nd, ps, both)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: nd
    type(particle_set_t), intent(in) :: ps
    integer(i8), intent(inout) :: both(:, :)
    logical :: inside(size(cfg%regions))
    real(wp) :: x(3)
    integer :: p, r, j
    if (size(cfg%regions) < 2) return
    x = 0.0_wp
    do p = 1, ps%n
      x(1:nd) = ps%x(1:nd, p)
      do r = 1, size(cfg%regions)
        inside(r) = in_region(cfg%regions(r), x, nd)
      end do
      if (count(inside) < 2) cycle
      do r = 1, size(cfg%regions)
        if (.not. inside(r)) cycle
        do j = 1, r - 1
          if (inside(j)) both(j, r) = both(j, r) + 1
        end do
      end do
    end do
  end subroutine count_overlaps

  !> " (group k of n)" when the group is repeated, "" when it is given once.
  function which(k, n) result(s)
    integer, intent(in) :: k, n
    character(len=:), allocatable :: s
    s = ''
    if (n > 1) s = ' (group '//itoa(k)//' of '//itoa(n)//')'
  end function which

  !> One line in the format of the input errors.
  subroutine report(cfg, text)
    type(config_t), intent(in) :: cfg
    character(len=*), intent(in) :: text
    write (error_unit, '(a)') 'dpmpm: input error: '//trim(cfg%input_file)//': '// &
      trim(text)
  end subroutine report

  !> Points of ps in the layer of cells next to grid face f (on this rank), or at any
  !> distance from it with anywhere; with lo, hi, only those within a cell of lo..hi along
  !> each axis of the face where hi > lo (the part of the face a &load acts on).
  integer(i8) function points_next_to_face(grid, f, ps, lo, hi, anywhere) result(n)
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: f
    type(particle_set_t), intent(in) :: ps
    real(wp), intent(in), optional :: lo(3), hi(3)
    logical, intent(in), optional :: anywhere
    integer :: p, d, t, c(3), layer
    logical :: near, everywhere
    everywhere = .false.
    if (present(anywhere)) everywhere = anywhere
    d = (f + 1)/2
    layer = merge(0, grid%ncells(d) - 1, mod(f, 2) == 1)
    n = 0
    do p = 1, ps%n
      c = cell_of(grid%origin, grid%h, ps%x(:, p), grid%ndim)
      if (c(d) /= layer .and. .not. everywhere) cycle
      near = .true.
      if (present(lo)) then
        do t = 1, grid%ndim
          if (t == d .or. hi(t) <= lo(t)) cycle
          if (ps%x(t, p) < lo(t) - grid%h(t) .or. ps%x(t, p) > hi(t) + grid%h(t)) near = .false.
        end do
      end if
      if (near) n = n + 1
    end do
  end function points_next_to_face

end module dpmpm_scene_check
