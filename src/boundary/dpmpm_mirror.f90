!> Mirror walls: the exterior nodes beyond fixed and roller faces folded onto
!> their mirror images inside the grid (node -k onto +k, ncells+k onto ncells-k),
!> as if the points had mirror images behind the wall, and set again from them.
!> A fixed wall mirrors every vector component oddly (zero velocity on the wall),
!> a roller only the normal one (a plane of symmetry); scalars fold evenly.
module dpmpm_mirror
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: bc_free, bc_fixed, bc_roller, fbc_impermeable
  implicit none
  private
  public :: mirror_t, mirror_sign, fluid_mirror_bc

  !> The node block of this rank and the grid it sits in.
  type :: mirror_t
    integer :: nd = 1
    integer :: ncells(3) = 1
    integer :: gw(3) = 0                  !< ghost layers per axis
    integer :: alo(3) = 0, ahi(3) = 0     !< stored nodes (owned + ghosts)
  contains
    procedure :: init => mirror_init
    procedure :: fold => fold_exterior
    procedure :: unfold => unfold_exterior
    procedure :: fold_planes
  end type mirror_t

contains

  !> The walls of a grid of ncells cells seen from the node block alo..ahi with gw ghost layers.
  subroutine mirror_init(self, nd, ncells, gw, alo, ahi)
    class(mirror_t), intent(inout) :: self
    integer, intent(in) :: nd, ncells(3), gw(3), alo(3), ahi(3)
    self%nd = nd
    self%ncells = ncells
    self%gw = gw
    self%alo = alo
    self%ahi = ahi
  end subroutine mirror_init

  !> Conditions under which the fluid nodes beyond a face are folded: an
  !> impermeable face (fbc) at a fixed or roller solid face (bc) is a plane of
  !> symmetry of the fluid (roller); elsewhere the fluid is free.
  pure function fluid_mirror_bc(nd, fbc, bc_solid) result(bc)
    integer, intent(in) :: nd, fbc(6), bc_solid(6)
    integer :: bc(6)
    integer :: f
    bc = bc_free
    do f = 1, 2*nd
      if (fbc(f) == fbc_impermeable .and. bc_solid(f) /= bc_free) bc(f) = bc_roller
    end do
  end function fluid_mirror_bc

  !> Sign of vector component c under reflection in the face of axis d with
  !> condition bc: a fixed wall mirrors every component oddly (zero velocity on
  !> the wall), a roller only the normal one (a plane of symmetry).
  pure real(wp) function mirror_sign(bc, d, c) result(sg)
    integer, intent(in) :: bc, d, c
    sg = 1.0_wp
    if (bc == bc_fixed .or. c == d) sg = -1.0_wp
  end function mirror_sign

  !> Per-face signs of the components of a field with nscalar scalars followed
  !> by vectors of nd components, under reflection in each face (mirror_sign).
  function scalar_vector_signs(self, ncomp, nscalar, bc) result(sg)
    class(mirror_t), intent(in) :: self
    integer, intent(in) :: ncomp, nscalar, bc(6)
    real(wp) :: sg(ncomp, 6)
    integer :: f, c
    sg = 1.0_wp
    do f = 1, 2*self%nd
      do c = nscalar + 1, ncomp
        sg(c, f) = mirror_sign(bc(f), (f + 1)/2, mod(c - nscalar - 1, self%nd) + 1)
      end do
    end do
  end function scalar_vector_signs

  !> Fold the exterior nodes beyond fixed and roller faces onto their mirror
  !> images inside the grid (node -k onto +k, ncells+k onto ncells-k), as if the
  !> points had mirror images behind the wall. Scalars (the first nscalar
  !> components) fold evenly, vector components with mirror_sign. Linear in f,
  !> so it is applied before halo_sum on every rank that stores exterior nodes.
  !> bc: the face conditions of the phase (the grid's, or the fluid's, fluid_mirror_bc).
  subroutine fold_exterior(self, f, nscalar, bc)
    class(mirror_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    integer, intent(in) :: nscalar
    integer, intent(in) :: bc(6)
    call self%fold_planes(f, scalar_vector_signs(self, size(f, 1), nscalar, bc), .true., bc)
  end subroutine fold_exterior

  !> Set the exterior nodes from their mirror images (the inverse of fold_exterior
  !> for velocities), after halo_copy so that the images are present.
  subroutine unfold_exterior(self, f, nscalar, bc)
    class(mirror_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    integer, intent(in) :: nscalar
    integer, intent(in) :: bc(6)
    call self%fold_planes(f, scalar_vector_signs(self, size(f, 1), nscalar, bc), .false., bc)
  end subroutine unfold_exterior

  !> The plane loop of fold_exterior (fold: exterior added onto its image and
  !> cleared) and unfold_exterior (exterior set from its image), with the
  !> component signs sg(:, face) of each fixed or roller face.
  subroutine fold_planes(self, f, sg, fold, bc)
    class(mirror_t), intent(in) :: self
    real(wp), intent(inout) :: f(:, self%alo(1):, self%alo(2):, self%alo(3):)
    real(wp), intent(in) :: sg(:, :)
    logical, intent(in) :: fold
    integer, intent(in) :: bc(6)
    integer :: d, side, k, ext, img, face
    do d = 1, self%nd
      do side = 1, 2
        face = 2*(d - 1) + side
        if (bc(face) == bc_free) cycle
        do k = 1, self%gw(d)
          if (side == 1) then
            ext = -k; img = k
          else
            ext = self%ncells(d) + k; img = self%ncells(d) - k
          end if
          if (ext < self%alo(d) .or. ext > self%ahi(d)) cycle
          if (img < self%alo(d) .or. img > self%ahi(d)) cycle
          if (fold) then
            call plane_op(f, d, ext - self%alo(d) + 1, img - self%alo(d) + 1, sg(:, face), .true.)
          else
            call plane_op(f, d, img - self%alo(d) + 1, ext - self%alo(d) + 1, sg(:, face), .false.)
          end if
        end do
      end do
    end do
  end subroutine fold_planes

  !> On planes normal to axis d (1-based indices ia, ib of the array): with
  !> accumulate, f(ib) += sg f(ia) and f(ia) = 0; otherwise f(ib) = sg f(ia).
  subroutine plane_op(f, d, a, b, sg, accumulate)
    real(wp), intent(inout) :: f(:, :, :, :)
    integer, intent(in) :: d, a, b
    real(wp), intent(in) :: sg(:)
    logical, intent(in) :: accumulate
    integer :: la(3), ha(3), lb(3), hb(3), c
    la = 1
    ha = [size(f, 2), size(f, 3), size(f, 4)]
    lb = la
    hb = ha
    la(d) = a; ha(d) = a
    lb(d) = b; hb(d) = b
    do c = 1, size(f, 1)
      associate (fa => f(c, la(1):ha(1), la(2):ha(2), la(3):ha(3)), &
                 fb => f(c, lb(1):hb(1), lb(2):hb(2), lb(3):hb(3)))
        if (accumulate) then
          fb = fb + sg(c)*fa
          fa = 0.0_wp
        else
          fb = sg(c)*fa
        end if
      end associate
    end do
  end subroutine plane_op

end module dpmpm_mirror
