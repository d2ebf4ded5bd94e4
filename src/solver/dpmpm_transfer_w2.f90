!> The grid transfers of fixed dimension for stencils of 2 nodes per axis (linear
!> B-splines): dpmpm_transfer_kernels.inc with the stencil width as a constant.
module dpmpm_transfer_w2
  use dpmpm_kinds, only: wp
  use dpmpm_drag, only: gravity_drag
  use dpmpm_transfer_set, only: transfer_set_t
  implicit none
  private
  !> Nodes per axis of the stencils (the 2D kernels read the first two).
  integer, parameter :: nw(3) = 2
#include "dpmpm_transfer_kernels.inc"
end module dpmpm_transfer_w2
