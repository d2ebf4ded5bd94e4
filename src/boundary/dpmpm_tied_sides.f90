!> Tied faces (&boundary condition = 'tied'): the nodes of the two faces of an axis that
!> lie at the same place along the faces move together, in every component, as one node
!> with both masses and both momenta. A 2D or 3D column between tied sides then moves as
!> the free field, the 1D column: a shear wave from a shaken base rises through it as
!> through a layer of infinite extent (doc/verification.md, "Site response on a rigid
!> base"). To the grid the faces are free (no constraint, no mirror: linear grid functions
!> only, which the input checks). The pairs may lie on different ranks: their mass and
!> momenta are summed over the ranks, one reduction per call.
module dpmpm_tied_sides
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: node_slots_t, node_slots
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_SUM, MPI_DOUBLE_PRECISION
  implicit none
  private
  public :: tie_sides, tie_sums, join_pairs, unjoin_pairs, copy_pairs

contains

  !> For every axis whose faces are tied (tied(2a - 1), tied(2a)): the owned nodes olo..ohi
  !> of the two faces (grid of ncells cells) that hold mass (node(1)) take the mass-weighted
  !> mean of the pair's new velocities (nvel(nd+1:2nd)), and with both also of the old ones
  !> (nvel(1:nd)); the new velocities of a node are what the nodal update gave it, so that the
  !> mean is the velocity of the joined node, (p0 + p1 + dt (f0 + f1))/(m0 + m1).
  subroutine tie_sides(nd, lo, olo, ohi, ncells, tied, node, nvel, both, comm)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3), ncells(3)
    logical, intent(in) :: tied(6)
    real(wp), intent(in) :: node(:, lo(1):, lo(2):, lo(3):)
    real(wp), intent(inout) :: nvel(:, lo(1):, lo(2):, lo(3):)
    logical, intent(in) :: both
    type(MPI_Comm), intent(in) :: comm
    real(wp), allocatable :: sums(:, :, :)
    integer, allocatable :: fn(:, :)
    integer :: a, b, c, side, nb, nc, ncomp, q
    real(wp) :: m
    type(node_slots_t) :: sl
    sl = node_slots(nd)
    ncomp = 1 + 2*nd
    do a = 1, nd
      if (.not. (tied(2*a - 1) .and. tied(2*a))) cycle
      ! the two other axes (b, c) index a node of the face; an unused axis has one node
      b = merge(2, 1, a == 1)
      c = 6 - a - b
      nb = merge(ncells(b), 0, b <= nd)
      nc = merge(ncells(c), 0, c <= nd)
      allocate (sums(ncomp, 0:nb, 0:nc))
      sums = 0.0_wp
      do side = 0, 1
        call face_nodes(a, side, olo, ohi, ncells, fn)
        do q = 1, size(fn, 2)
          associate (i => fn(1:3, q), jb => fn(4, q), jc => fn(5, q))
            m = node(1, i(1), i(2), i(3))
            if (m <= 0.0_wp) cycle
            sums(1, jb, jc) = sums(1, jb, jc) + m
            sums(2:ncomp, jb, jc) = sums(2:ncomp, jb, jc) + m*nvel(1:2*nd, i(1), i(2), i(3))
          end associate
        end do
      end do
      call MPI_Allreduce(MPI_IN_PLACE, sums, size(sums), MPI_DOUBLE_PRECISION, MPI_SUM, comm)
      do side = 0, 1
        call face_nodes(a, side, olo, ohi, ncells, fn)
        do q = 1, size(fn, 2)
          associate (i => fn(1:3, q), jb => fn(4, q), jc => fn(5, q))
            if (node(1, i(1), i(2), i(3)) <= 0.0_wp .or. sums(1, jb, jc) <= 0.0_wp) cycle
            nvel(sl%new_lo:sl%new_hi, i(1), i(2), i(3)) = sums(2 + nd:ncomp, jb, jc)/sums(1, jb, jc)
            if (both) nvel(sl%old_lo:sl%old_hi, i(1), i(2), i(3)) = sums(2:1 + nd, jb, jc)/sums(1, jb, jc)
          end associate
        end do
      end do
      deallocate (sums)
    end do
  end subroutine tie_sides

  !> For every tied axis: the node sums field(:, ...) of the owned nodes of the two faces
  !> replaced, at both nodes of each pair, by the pair's total, as at one node.
  subroutine tie_sums(nd, lo, olo, ohi, ncells, tied, field, comm)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3), ncells(3)
    logical, intent(in) :: tied(6)
    real(wp), intent(inout) :: field(:, lo(1):, lo(2):, lo(3):)
    type(MPI_Comm), intent(in) :: comm
    real(wp), allocatable :: sums(:, :, :)
    integer, allocatable :: fn(:, :)
    integer :: a, side, q
    do a = 1, nd
      if (.not. (tied(2*a - 1) .and. tied(2*a))) cycle
      call face_sums(a, lo, olo, ohi, ncells, field, 1, comm, sums)
      do side = 0, 1
        call face_nodes(a, side, olo, ohi, ncells, fn)
        do q = 1, size(fn, 2)
          field(:, fn(1, q), fn(2, q), fn(3, q)) = sums(:, fn(4, q), fn(5, q))
        end do
      end do
      deallocate (sums)
    end do
  end subroutine tie_sums

  !> For every tied axis: the node sums field(:, ...) of the pairs put together at the node
  !> of the lower face (the pair's total there, zero at the upper face's node), so that a
  !> nodal update sees each pair as one node, once. Axes in turn, so that the corner nodes
  !> of two tied axes end as one node at the lowest corner. kept: the values of the faces'
  !> nodes before, for unjoin_pairs.
  subroutine join_pairs(nd, lo, olo, ohi, ncells, tied, field, kept, comm)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3), ncells(3)
    logical, intent(in) :: tied(6)
    real(wp), intent(inout) :: field(:, lo(1):, lo(2):, lo(3):)
    real(wp), allocatable, intent(out) :: kept(:)
    type(MPI_Comm), intent(in) :: comm
    integer :: a
    call face_values(nd, lo, olo, ohi, ncells, tied, field, kept, .false.)
    do a = 1, nd
      if (tied(2*a - 1) .and. tied(2*a)) call pair_exchange(a, lo, olo, ohi, ncells, field, .true., comm)
    end do
  end subroutine join_pairs

  !> The values of the tied faces' nodes that join_pairs kept, back in field.
  subroutine unjoin_pairs(nd, lo, olo, ohi, ncells, tied, field, kept)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3), ncells(3)
    logical, intent(in) :: tied(6)
    real(wp), intent(inout) :: field(:, lo(1):, lo(2):, lo(3):)
    real(wp), allocatable, intent(inout) :: kept(:)
    call face_values(nd, lo, olo, ohi, ncells, tied, field, kept, .true.)
  end subroutine unjoin_pairs

  !> The owned nodes of the tied faces, axis by axis, lower face first, in field and in buf
  !> (one node's components after another): back (.true.) puts buf's values into field,
  !> else buf is made from field's. A corner node of two tied axes appears in both.
  subroutine face_values(nd, lo, olo, ohi, ncells, tied, field, buf, back)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3), ncells(3)
    logical, intent(in) :: tied(6)
    real(wp), intent(inout) :: field(:, lo(1):, lo(2):, lo(3):)
    real(wp), allocatable, intent(inout) :: buf(:)
    logical, intent(in) :: back
    integer, allocatable :: fn(:, :)
    integer :: a, side, n, nc, pass, q
    nc = size(field, 1)
    do pass = merge(2, 1, back), 2
      n = 0
      do a = 1, nd
        if (.not. (tied(2*a - 1) .and. tied(2*a))) cycle
        do side = 0, 1
          call face_nodes(a, side, olo, ohi, ncells, fn)
          do q = 1, size(fn, 2)
            if (pass == 2 .and. back) then
              field(:, fn(1, q), fn(2, q), fn(3, q)) = buf(n + 1:n + nc)
            else if (pass == 2) then
              buf(n + 1:n + nc) = field(:, fn(1, q), fn(2, q), fn(3, q))
            end if
            n = n + nc
          end do
        end do
      end do
      ! (the first pass counts the values)
      if (pass == 1) allocate (buf(n))
    end do
  end subroutine face_values

  !> For every tied axis, in the reverse order of join_pairs: the values field(:, ...) of
  !> the lower face's node given to the upper face's node of its pair (the velocities of
  !> the joined node to both).
  subroutine copy_pairs(nd, lo, olo, ohi, ncells, tied, field, comm)
    integer, intent(in) :: nd, lo(3), olo(3), ohi(3), ncells(3)
    logical, intent(in) :: tied(6)
    real(wp), intent(inout) :: field(:, lo(1):, lo(2):, lo(3):)
    type(MPI_Comm), intent(in) :: comm
    integer :: a
    do a = nd, 1, -1
      if (tied(2*a - 1) .and. tied(2*a)) call pair_exchange(a, lo, olo, ohi, ncells, field, .false., comm)
    end do
  end subroutine copy_pairs

  !> The pairs of tied axis a, over the ranks (one reduction): join (.true.) puts the sum of
  !> both nodes' values at the lower node and zero at the upper one; otherwise the upper
  !> node takes the lower node's values.
  subroutine pair_exchange(a, lo, olo, ohi, ncells, field, join, comm)
    integer, intent(in) :: a, lo(3), olo(3), ohi(3), ncells(3)
    real(wp), intent(inout) :: field(:, lo(1):, lo(2):, lo(3):)
    logical, intent(in) :: join
    type(MPI_Comm), intent(in) :: comm
    real(wp), allocatable :: sums(:, :, :)
    integer, allocatable :: fn(:, :)
    integer :: side, q
    call face_sums(a, lo, olo, ohi, ncells, field, merge(1, 0, join), comm, sums)
    do side = 0, 1
      call face_nodes(a, side, olo, ohi, ncells, fn)
      do q = 1, size(fn, 2)
        associate (i => fn(1:3, q), jb => fn(4, q), jc => fn(5, q))
          if (side == 0 .and. join) then
            field(:, i(1), i(2), i(3)) = sums(:, jb, jc)
          else if (side == 1 .and. join) then
            field(:, i(1), i(2), i(3)) = 0.0_wp
          else if (side == 1) then
            field(:, i(1), i(2), i(3)) = sums(:, jb, jc)
          end if
        end associate
      end do
    end do
  end subroutine pair_exchange

  !> The values of field at the owned nodes of faces 0..last_side of axis a, summed per
  !> pair (indexed by the node's place along the other two axes) over the faces and the
  !> ranks (one reduction). An unused axis has the one node 0: its extent here is merely
  !> larger.
  subroutine face_sums(a, lo, olo, ohi, ncells, field, last_side, comm, sums)
    integer, intent(in) :: a, lo(3), olo(3), ohi(3), ncells(3), last_side
    real(wp), intent(in) :: field(:, lo(1):, lo(2):, lo(3):)
    type(MPI_Comm), intent(in) :: comm
    real(wp), allocatable, intent(out) :: sums(:, :, :)
    integer, allocatable :: fn(:, :)
    integer :: b, c, side, q
    b = merge(2, 1, a == 1)
    c = 6 - a - b
    allocate (sums(size(field, 1), 0:ncells(b), 0:ncells(c)))
    sums = 0.0_wp
    do side = 0, last_side
      call face_nodes(a, side, olo, ohi, ncells, fn)
      do q = 1, size(fn, 2)
        sums(:, fn(4, q), fn(5, q)) = sums(:, fn(4, q), fn(5, q)) + field(:, fn(1, q), fn(2, q), fn(3, q))
      end do
    end do
    call MPI_Allreduce(MPI_IN_PLACE, sums, size(sums), MPI_DOUBLE_PRECISION, MPI_SUM, comm)
  end subroutine face_sums

  !> The owned nodes of face side (0: the lower, 1: the upper) of axis a, along the other
  !> two axes b, c (b the lower) with c the outer: node(1:3, q) the node's index, node(4:5,
  !> q) its place (jb, jc) along b and c, which it shares with its pair on the other face.
  !> None where this rank owns no node of the face.
  pure subroutine face_nodes(a, side, olo, ohi, ncells, node)
    integer, intent(in) :: a, side, olo(3), ohi(3), ncells(3)
    integer, allocatable, intent(out) :: node(:, :)
    integer :: b, c, flo(3), fhi(3), jb, jc, q
    b = merge(2, 1, a == 1)
    c = 6 - a - b
    call face_box(a, side, olo, ohi, ncells, flo, fhi)
    allocate (node(5, max(0, fhi(b) - flo(b) + 1)*max(0, fhi(c) - flo(c) + 1)))
    q = 0
    do jc = flo(c), fhi(c)
      do jb = flo(b), fhi(b)
        q = q + 1
        node(a, q) = flo(a)
        node(b, q) = jb
        node(c, q) = jc
        node(4:5, q) = [jb, jc]
      end do
    end do
  end subroutine face_nodes

  !> The owned nodes of face side (0: the lower, 1: the upper) of axis a: flo..fhi, empty
  !> (flo > fhi along every axis) where this rank owns none of them; along an unused axis
  !> the one node 0.
  pure subroutine face_box(a, side, olo, ohi, ncells, flo, fhi)
    integer, intent(in) :: a, side, olo(3), ohi(3), ncells(3)
    integer, intent(out) :: flo(3), fhi(3)
    integer :: at
    flo = max(olo, 0)
    fhi = min(ohi, ncells)
    at = side*ncells(a)
    if (olo(a) <= at .and. at <= ohi(a)) then
      flo(a) = at
      fhi(a) = at
    else
      ! empty along every axis: the loops over the face run over the other two
      flo = 1
      fhi = 0
    end if
  end subroutine face_box

end module dpmpm_tied_sides
