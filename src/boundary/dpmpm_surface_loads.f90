!> Loads on a body's surface inside the grid (&load surface = .true., doc/theory.md 6.3):
!> a traction on the upper surface of soil that does not reach the grid's top face, on
!> part of it (lo..hi) and with the time functions of face loads. Along every grid line
!> normal to the load's face, the outermost node seen from that face where the body has
!> mass (over all ranks) takes the traction times its share of the face area: the nodes
!> a face load would load if the body filled the grid up to that face. In axisymmetry the
!> share is the ring's per radian (load_area): on a line of constant z (faces x-, x+) the
!> node's r times its plane share, on a line of constant r its integral of N_I r dr.
module dpmpm_surface_loads
  use dpmpm_kinds, only: wp
  use dpmpm_face_loads, only: face_loads_t, load_factor, load_area
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER, MPI_MAX
  implicit none
  private
  public :: surface_forces

contains

  !> The nodal forces of the surface loads of faces at time, on the owned nodes olo..ohi
  !> of the node block from lo, into sforce(1:nd, :, :, :) (cleared first); node(1) is the
  !> nodal mass of the loaded body (summed over the ranks). Collective over comm.
  subroutine surface_forces(faces, time, nd, lo, olo, ohi, node, comm, sforce)
    type(face_loads_t), intent(in) :: faces
    real(wp), intent(in) :: time
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3)
    real(wp), intent(in) :: node(:, lo(1):, lo(2):, lo(3):)
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(inout) :: sforce(:, lo(1):, lo(2):, lo(3):)
    integer, allocatable :: outer(:, :)
    integer :: l, d, s, t(2), n(2), i, j, k, idx(3), c(2)
    real(wp) :: f
    sforce = 0.0_wp
    do l = 1, size(faces%loads)
      associate (ld => faces%loads(l))
        if (.not. ld%surface) cycle
        d = (ld%face + 1)/2
        s = merge(-1, 1, mod(ld%face, 2) == 1)      ! -1: face d-, the outermost is the lowest index
        ! the two axes along the face (an unused axis has the one node 0)
        t = pack([1, 2, 3], [1, 2, 3] /= d)
        n = 0
        where (t <= nd) n = faces%grid%ncells(t)
        allocate (outer(0:n(1), 0:n(2)))
        outer = -huge(1)
        do k = olo(3), ohi(3)
          do j = olo(2), ohi(2)
            do i = olo(1), ohi(1)
              if (node(1, i, j, k) <= 0.0_wp) cycle
              idx = [i, j, k]
              c = idx(t)
              outer(c(1), c(2)) = max(outer(c(1), c(2)), s*idx(d))
            end do
          end do
        end do
        call MPI_Allreduce(MPI_IN_PLACE, outer, size(outer), MPI_INTEGER, MPI_MAX, comm)
        f = load_factor(ld, time)
        ! each line's outermost node, loaded by the rank that owns it (the one that found it)
        do j = 0, n(2)
          do i = 0, n(1)
            if (outer(i, j) == -huge(1)) cycle
            idx(t) = [i, j]
            idx(d) = s*outer(i, j)
            if (any(idx < olo .or. idx > ohi)) cycle
            sforce(1:nd, idx(1), idx(2), idx(3)) = sforce(1:nd, idx(1), idx(2), idx(3)) + &
                                                   f*load_area(faces, idx, ld)*ld%traction(1:nd)
          end do
        end do
        deallocate (outer)
      end associate
    end do
  end subroutine surface_forces

end module dpmpm_surface_loads
