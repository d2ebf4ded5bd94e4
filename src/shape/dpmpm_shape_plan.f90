!> The shape-function choices of a run, resolved from &shape: the grid functions
!> of the transfer (P2G, G2P, nodal masses), how nodal velocities are
!> reconstructed (mass-weighted projection or MLS), and how the force integrals
!> are evaluated (point quadrature, or Gauss points of the grid cells with
!> stresses reconstructed by MLS; doc/theory.md 3.3 and 3.6).
!>
!> Standard MPM is the linear grid kernel with projection velocities and point
!> quadrature; the projection is the constant-basis MLS with the grid kernel
!> and mass weights, so the MLS path run with those settings gives the same
!> numbers (tests/test_mls_solver.f90).
module dpmpm_shape_plan
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t
  use dpmpm_kernels, only: kernel_from_name, kernel_reach, grid_kernel_t, grid_kernel_table, &
                           bind_grid_kernel
  use dpmpm_mls, only: basis_from_name
  implicit none
  private
  public :: shape_plan_t, max_gauss

  !> Most Gauss points per cell and axis.
  integer, parameter :: max_gauss = 4

  !> Resolved &shape settings.
  type :: shape_plan_t
    integer :: grid_kernel = 1
    !> the grid kernel bound once per run (its width, ghost layer and reach)
    type(grid_kernel_t) :: grid = grid_kernel_table(1)
    logical :: velocity_mls = .false.     !< nodal velocities by MLS instead of projection
    integer :: velocity_kernel = 1
    integer :: velocity_basis = 0
    real(wp) :: velocity_radius = 0.0_wp
    logical :: velocity_radial = .false.
    logical :: gauss = .false.            !< force integrals at Gauss points
    integer :: ngauss = 2
    integer :: field_kernel = 4
    integer :: field_basis = 0
    real(wp) :: field_radius = 2.0_wp
    logical :: field_radial = .true.      !< radial weight; else a tensor product (box)
  contains
    procedure :: init => plan_init
    procedure :: ghost_width => plan_ghost_width
  end type shape_plan_t

contains

  !> Resolve the plan from a checked config (names already validated).
  subroutine plan_init(self, cfg)
    class(shape_plan_t), intent(out) :: self
    type(config_t), intent(in) :: cfg
    self%grid_kernel = kernel_from_name(cfg%kernel)
    self%grid = bind_grid_kernel(self%grid_kernel, 'shape plan (&shape kernel)')
    self%velocity_mls = len_trim(cfg%velocity_kernel) > 0
    if (self%velocity_mls) then
      self%velocity_kernel = kernel_from_name(cfg%velocity_kernel)
      self%velocity_basis = basis_from_name(cfg%velocity_basis)
      self%velocity_radius = cfg%velocity_radius
      self%velocity_radial = cfg%velocity_radius > 0.0_wp
    end if
    self%gauss = cfg%quadrature == 'gauss'
    if (self%gauss) then
      self%ngauss = cfg%gauss_points
      self%field_kernel = kernel_from_name(cfg%field_kernel)
      self%field_basis = basis_from_name(cfg%field_basis)
      self%field_radius = cfg%field_radius
      ! a box of half-width field_radius is the tensor product of the kernel's profile
      self%field_radial = cfg%field_radius > 0.0_wp .and. cfg%field_support /= 'box'
    end if
  end subroutine plan_init

  !> Ghost layer (nodes and cells) wide enough for every stencil in use: the
  !> grid kernel, and the reach of the MLS weights around a point.
  integer function plan_ghost_width(self) result(gw)
    class(shape_plan_t), intent(in) :: self
    gw = self%grid%ghost
    if (self%velocity_mls) gw = max(gw, ceiling(kernel_reach(self%velocity_kernel, &
                                    self%velocity_radius, self%velocity_radial)))
    if (self%gauss) gw = max(gw, ceiling(kernel_reach(self%field_kernel, self%field_radius, &
                                 self%field_radial)))
  end function plan_ghost_width

end module dpmpm_shape_plan
