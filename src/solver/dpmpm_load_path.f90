!> Is a body loaded on a grid face cut? With point quadrature two neighbouring nodes
!> feel each other only through the points whose grid functions reach both. Where no
!> point of any set couples the nodes on either side of a plane across the whole
!> grid, the part between the load and that plane is held by nothing and moves
!> freely under the load (Standard MPM on scattered points: doc/theory.md, section
!> 3.6). Checked at every diagnostics record for each face with a traction; a cut is
!> reported once per face with the time and where it is (doc/verification.md,
!> "Long runs of the two-phase step").
module dpmpm_load_path
  use dpmpm_kinds, only: wp, i8
  use dpmpm_kernels, only: kernel_width, kernel_linear, kernel_quadratic, kernel_cubic, refuse_kernel
  use dpmpm_state, only: state_t
  use dpmpm_config, only: face_names
  use dpmpm_strings, only: rtoa
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER8, MPI_SUM
  implicit none
  private
  public :: check_load_path, uncovered_run, first_node

contains

  !> First node (global index along the axis, node 0 at the origin) of the grid
  !> functions of a point at xi cell widths from the origin.
  integer function first_node(kernel, xi) result(i)
    integer, intent(in) :: kernel
    real(wp), intent(in) :: xi
    select case (kernel)
    case (kernel_linear)
      i = floor(xi)
    case (kernel_quadratic)
      i = floor(xi - 0.5_wp)
    case (kernel_cubic)
      i = floor(xi) - 1
    case default
      i = 0
      call refuse_kernel(kernel, 'first_node')
    end select
  end function first_node

  !> cover(e): points whose grid functions reach both nodes e and e + 1 (the edge e;
  !> lbound(cover) is the first edge). Walking from the low end (from_high false) or the
  !> high end, the first run of edges nobody covers that has covered edges on both
  !> sides: its first and last edge, [0, -1] when there is none.
  pure function uncovered_run(cover, from_high) result(run)
    integer(i8), intent(in) :: cover(:)
    logical, intent(in) :: from_high
    integer :: run(2)
    integer :: n, k, e, first, last, step
    run = [0, -1]
    n = size(cover)
    if (from_high) then
      first = n; last = 1; step = -1
    else
      first = 1; last = n; step = 1
    end if
    ! the covered edge nearest the loaded end
    do k = first, last, step
      if (cover(k) > 0) exit
    end do
    if (cover(min(max(k, 1), n)) == 0) return
    do e = k, last, step
      if (cover(e) > 0) cycle
      ! an uncovered run starts at e; it is a cut when a covered edge follows
      do k = e, last, step
        if (cover(k) > 0) exit
      end do
      if (k < 1 .or. k > n) return
      run = [min(e, k - step), max(e, k - step)]
      return
    end do
  end function uncovered_run

  !> Collective. For each face with a traction not yet reported: the edges along the
  !> face's normal that the points of every set cover, summed over the ranks; a run of
  !> uncovered edges between covered ones is a cut, reported once with the time.
  !> Gauss quadrature (the MLS pair) integrates over the cells of the body, not at its
  !> points, and is not checked.
  subroutine check_load_path(self)
    class(state_t), intent(inout) :: self
    integer(i8), allocatable :: cover(:)
    integer :: k, f, d, ip, p, i0, nw, run(2), nc, lo
    real(wp) :: x0, h
    character(len=512) :: line
    if (.not. allocated(self%cfg%loads) .or. self%plan%gauss) return
    nw = kernel_width(self%kernel)
    do k = 1, size(self%cfg%loads)
      f = self%cfg%loads(k)%face
      if (f < 1 .or. f > 2*self%nd) cycle
      if (all(self%cfg%loads(k)%traction == 0.0_wp) .or. self%cut_time(f) >= 0.0_wp) cycle
      ! A load on the body's surface follows the surface: points that left it (above the
      ! load) are no part of its path.
      if (self%cfg%loads(k)%surface) cycle
      d = (f + 1)/2
      nc = self%grid%ncells(d)
      x0 = self%grid%origin(d)
      h = self%grid%h(d)
      ! edges -2 .. nc + 1: every node a grid function of a point inside the grid reaches
      lo = -2
      allocate (cover(lo:nc + 1))
      cover = 0
      do ip = 1, self%nph
        associate (pts => self%phase(ip)%pts)
          do p = 1, pts%n
            i0 = first_node(self%kernel, (pts%x(d, p) - x0)/h)
            i0 = max(i0, lo)
            cover(i0:min(i0 + nw - 2, nc + 1)) = cover(i0:min(i0 + nw - 2, nc + 1)) + 1
          end do
        end associate
      end do
      call MPI_Allreduce(MPI_IN_PLACE, cover, size(cover), MPI_INTEGER8, MPI_SUM, self%dec%comm)
      run = uncovered_run(cover, from_high=mod(f, 2) == 0)
      deallocate (cover)
      if (run(1) > run(2)) cycle
      self%cut_time(f) = self%time
      ! edge e (array position e - lo + 1) joins nodes e and e + 1
      run = run + lo - 1
      write (line, '(a)') 'the body loaded on face '//face_names(f)//' is cut at t = '// &
        trim(rtoa(self%time))//' s: no point couples the nodes at '//face_names(f) (1:1)//' = '// &
        trim(rtoa(x0 + run(1)*h))//' m and '//trim(rtoa(x0 + (run(2) + 1)*h))// &
        ' m; the part between the load and this plane is '// &
        'held by nothing and moves freely under the load (more points per cell, wider grid '// &
        'functions or Gauss quadrature bridge it: doc/theory.md, section 3.6)'
      call self%log%warning(line)
    end do
  end subroutine check_load_path

end module dpmpm_load_path
