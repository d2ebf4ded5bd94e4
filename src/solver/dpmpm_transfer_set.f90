!> The grid transfers of one dimension and one stencil width, as a table of procedures:
!> transfer_set_t holds a pointer to each form of fixed width (dpmpm_transfer_kernels.fypp)
!> that dpmpm_transfer calls. Each module dpmpm_transfer_wN fills the 2D and the 3D set of
!> its width once (fixed_width_sets), and dpmpm_transfer looks the set up by the width
!> instead of naming every width in every kernel. A pointer left null is a form that the
!> dimension does not have (reaches_thin_node in 3D).
module dpmpm_transfer_set
  use dpmpm_kinds, only: wp
  implicit none
  private
  public :: transfer_set_t

  abstract interface
    !> p2g_2d, p2g_3d
    subroutine p2g_form(n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
      real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), stress(:, :)
      logical, intent(in) :: point_forces
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    end subroutine p2g_form

    !> p2g_body_2d, p2g_body_3d
    subroutine p2g_body_form(n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, bacc)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
      real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), stress(:, :)
      logical, intent(in) :: point_forces
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
      real(wp), contiguous, intent(in) :: bacc(:, :)
    end subroutine p2g_body_form

    !> porous_p2g_2d, porous_p2g_3d
    subroutine porous_p2g_form(n, i0, sw, sdw, mass, v, vol, stress, point_forces, lo, node, poro, kinv, sporo)
      import :: wp
      integer, intent(in) :: n
      logical, intent(in) :: point_forces
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
      real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), stress(:, :), poro(:), kinv(:)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):), sporo(:, lo(1):, lo(2):, lo(3):)
    end subroutine porous_p2g_form

    !> g2p_2d, g2p_3d
    subroutine g2p_form(n, i0, sw, sdw, lo, nvel, flip, dt, v, x, vgrad, gradient, gf, gv, gather)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), gf(:, lo(1):, lo(2):, lo(3):)
      real(wp), intent(in) :: flip, dt
      real(wp), contiguous, intent(inout) :: v(:, :), x(:, :), vgrad(:, :), gv(:, :)
      logical, intent(in) :: gradient, gather
    end subroutine g2p_form

    !> g2p_remap_2d, g2p_remap_3d
    subroutine g2p_remap_form(n, i0, sw, lo, nvel, flip, dt, mass, v, x, node)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
      real(wp), intent(in) :: flip, dt
      real(wp), contiguous, intent(inout) :: v(:, :), x(:, :), node(:, lo(1):, lo(2):, lo(3):)
    end subroutine g2p_remap_form

    !> g2p_remap_project_2d, g2p_remap_project_3d
    subroutine g2p_remap_project_form(n, i0, sw, lo, nvel, flip, dt, mass, v, x, node, gf, gv)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), gf(:, lo(1):, lo(2):, lo(3):)
      real(wp), intent(in) :: flip, dt
      real(wp), contiguous, intent(inout) :: v(:, :), x(:, :), node(:, lo(1):, lo(2):, lo(3):), gv(:, :)
    end subroutine g2p_remap_project_form

    !> point_gradient_2d, point_gradient_3d
    subroutine point_gradient_form(n, i0, sw, sdw, lo, nvel, vgrad)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):)
      real(wp), contiguous, intent(inout) :: vgrad(:, :)
    end subroutine point_gradient_form

    !> point_divergences_2d, point_divergences_3d
    subroutine point_divergences_form(n, i0, sw, sdw, lo, nvel, nvel2, div, div2)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(in) :: nvel(:, lo(1):, lo(2):, lo(3):), nvel2(:, lo(1):, lo(2):, lo(3):)
      real(wp), contiguous, intent(inout) :: div(:), div2(:)
    end subroutine point_divergences_form

    !> momentum_project_p2g_2d, momentum_project_p2g_3d
    subroutine momentum_project_p2g_form(n, i0, sw, mass, v, lo, fp, node)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), v(:, :), fp(:, :)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    end subroutine momentum_project_p2g_form

    !> momentum_p2g_2d, momentum_p2g_3d
    subroutine momentum_p2g_form(n, i0, sw, mass, v, lo, node)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), v(:, :)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(inout) :: node(:, lo(1):, lo(2):, lo(3):)
    end subroutine momentum_p2g_form

    !> volume_p2g_2d, volume_p2g_3d
    subroutine volume_p2g_form(n, i0, sw, vol, lo, nvol)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), vol(:)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(inout) :: nvol(:, lo(1):, lo(2):, lo(3):)
    end subroutine volume_p2g_form

    !> interp_two_values_2d, interp_two_values_3d
    subroutine interp_two_values_form(n, i0, sw, lo, f, comp, val, val2)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
      integer, intent(in) :: comp
      real(wp), contiguous, intent(out) :: val(:), val2(:)
    end subroutine interp_two_values_form

    !> fluid_p2g_2d, fluid_p2g_3d
    subroutine fluid_p2g_form(n, i0, sw, sdw, mass, v, vol, poro, pres, kinv, momentum, point_forces, lo, &
                              node_s, node_f, drag, fvol)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), sdw(:, :, :)
      real(wp), contiguous, intent(in) :: mass(:), v(:, :), vol(:), poro(:), pres(:), kinv(:)
      logical, intent(in) :: momentum, point_forces
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(inout) :: node_s(:, lo(1):, lo(2):, lo(3):), node_f(:, lo(1):, lo(2):, lo(3):)
      real(wp), contiguous, intent(inout) :: drag(:, lo(1):, lo(2):, lo(3):)
      real(wp), contiguous, intent(inout), optional :: fvol(:, lo(1):, lo(2):, lo(3):)
    end subroutine fluid_p2g_form

    !> solid_porosity_p2g_2d, solid_porosity_p2g_3d
    subroutine solid_porosity_p2g_form(n, i0, sw, mass, poro, kinv, lo, sporo)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :), mass(:), poro(:), kinv(:)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(inout) :: sporo(:, lo(1):, lo(2):, lo(3):)
    end subroutine solid_porosity_p2g_form

    !> reaches_thin_node_2d (2D only)
    subroutine reaches_thin_node_form(n, i0, sw, lo, f, hi, vmin, flag)
      import :: wp
      integer, intent(in) :: n
      integer, contiguous, intent(in) :: i0(:, :)
      real(wp), contiguous, intent(in) :: sw(:, :, :)
      integer, intent(in) :: lo(3)
      real(wp), contiguous, intent(in) :: f(:, lo(1):, lo(2):, lo(3):)
      integer, intent(in) :: hi(3)
      real(wp), intent(in) :: vmin
      logical, intent(out) :: flag(:)
    end subroutine reaches_thin_node_form
  end interface

  !> The forms of fixed width of one dimension: width = 0 while no module has filled it.
  type :: transfer_set_t
    integer :: nd = 0                 !< dimension (2 or 3)
    integer :: width = 0              !< nodes per axis of the stencils
    procedure(p2g_form), pointer, nopass :: p2g => null()
    procedure(p2g_body_form), pointer, nopass :: p2g_body => null()
    procedure(porous_p2g_form), pointer, nopass :: porous_p2g => null()
    procedure(g2p_form), pointer, nopass :: g2p => null()
    procedure(g2p_remap_form), pointer, nopass :: g2p_remap => null()
    procedure(g2p_remap_project_form), pointer, nopass :: g2p_remap_project => null()
    procedure(point_gradient_form), pointer, nopass :: point_gradient => null()
    procedure(point_divergences_form), pointer, nopass :: point_divergences => null()
    procedure(momentum_project_p2g_form), pointer, nopass :: momentum_project_p2g => null()
    procedure(momentum_p2g_form), pointer, nopass :: momentum_p2g => null()
    procedure(volume_p2g_form), pointer, nopass :: volume_p2g => null()
    procedure(interp_two_values_form), pointer, nopass :: interp_two_values => null()
    procedure(fluid_p2g_form), pointer, nopass :: fluid_p2g => null()
    procedure(solid_porosity_p2g_form), pointer, nopass :: solid_porosity_p2g => null()
    procedure(reaches_thin_node_form), pointer, nopass :: reaches_thin_node => null()
  end type transfer_set_t

end module dpmpm_transfer_set
