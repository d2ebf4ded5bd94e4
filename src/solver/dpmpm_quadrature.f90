!> Gauss quadrature of the internal forces (doc/theory.md 3.6): the driving code of
!> the MLS reconstruction of a stress-like field on the Gauss points of the
!> cells (sums, occupancy of the cells, solve, forces), and the point velocity
!> gradients (fluid points: divergences) by the transpose of the same operator. The
!> algebra is in dpmpm_gauss_fields; here are its passes with their halo exchanges.
module dpmpm_quadrature
  use dpmpm_kinds, only: wp
  use dpmpm_timer, only: t_halo
  use dpmpm_gauss_fields, only: occupancy_pass, gauss_accumulate, gauss_solve, gauss_forces, gauss_masses, &
                               gauss_velocity_gradient, gauss_strain
  use dpmpm_phase, only: phase_t
  use dpmpm_state, only: state_t
  implicit none
  private
  public :: gauss_force_integrals, gauss_point_gradients, gauss_point_divergences

contains

  !> Internal forces by Gauss quadrature of the stress-like field fields(6, :) of
  !> the points of phase tr (fields(1, :), an isotropic field, when tr%giso),
  !> reconstructed by MLS (solution in sol), added to node;
  !> keeps the positions and volumes for the transposed strain operator.
  subroutine gauss_force_integrals(self, tr, fields, sol, node, fields2, sol2, node2, gmass)
    class(state_t), intent(inout) :: self
    type(phase_t), intent(inout) :: tr
    real(wp), intent(in) :: fields(:, :)
    real(wp), intent(inout) :: sol(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(inout) :: node(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    !> A second field of the same points (fluid: the solid's share of p), with its own
    !> reconstruction and nodes; the pass over the points, the occupancy and the MLS
    !> solve (the counts and moments of the same points) are shared.
    real(wp), intent(in), optional :: fields2(:, :)
    real(wp), intent(inout), optional :: sol2(:, self%dec%alo(1):, self%dec%alo(2):, &
                                              self%dec%alo(3):)
    real(wp), intent(inout), optional :: node2(:, self%dec%alo(1):, self%dec%alo(2):, &
                                               self%dec%alo(3):)
    !> In place of node2: the second field is a density (in its first component),
    !> integrated against the grid functions into gmass(1, :) (gauss_masses).
    real(wp), intent(inout), optional :: gmass(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer :: n
    logical :: two
    two = present(fields2) .and. present(sol2) .and. (present(node2) .or. present(gmass))
    n = tr%pts%n
    tr%xold(:, 1:n) = tr%pts%x(:, 1:n)
    tr%volold(1:n) = tr%pts%vol(1:n)
    tr%gacc = 0.0_wp
    associate (pl => self%plan, clo => self%dec%clo, chi => self%dec%chi)
      if (two) then
        tr%gacc2 = 0.0_wp
        call gauss_accumulate(self%nd, n, tr%pts%x, tr%pts%vol, fields, self%grid%origin, self%grid%h, &
                              self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                              pl%field_radial, pl%field_basis, self%dec%alo, tr%gacc, fields2, &
                              tr%gacc2, cache=tr%reach, isotropic=tr%giso)
      else
        call gauss_accumulate(self%nd, n, tr%pts%x, tr%pts%vol, fields, self%grid%origin, self%grid%h, &
                              self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                              pl%field_radial, pl%field_basis, self%dec%alo, tr%gacc, cache=tr%reach, &
                              isotropic=tr%giso)
      end if
      call self%timers%tic(t_halo)
      call self%dec%halo_sum(tr%gacc)
      call gauss_occupancy(self, tr%gacc)
      if (two) call self%dec%halo_sum(tr%gacc2)
      call self%timers%toc(t_halo)
      if (two) then
        call gauss_solve(self%nd, pl%ngauss, pl%field_basis, self%dec%alo, clo, chi, tr%gacc, sol, &
                         self%mls_stats, tr%giso, tr%gacc2, sol2)
      else
        call gauss_solve(self%nd, pl%ngauss, pl%field_basis, self%dec%alo, clo, chi, tr%gacc, sol, &
                         self%mls_stats, tr%giso)
      end if
      call self%timers%tic(t_halo)
      call self%dec%halo_copy(sol)
      if (two) call self%dec%halo_copy(sol2)
      call self%timers%toc(t_halo)
      call gauss_forces(self%nd, pl%ngauss, pl%field_basis, self%kernel, self%grid%h, &
                        self%dec%alo, clo, chi, sol, node, tr%nvol(2:2, :, :, :), tr%giso)
      if (two .and. present(gmass)) then
        call gauss_masses(self%nd, pl%ngauss, pl%field_basis, self%kernel, self%grid%h, self%dec%alo, clo, chi, &
                          sol2, gmass, tr%giso)
      else if (two) then
        call gauss_forces(self%nd, pl%ngauss, pl%field_basis, self%kernel, self%grid%h, &
                          self%dec%alo, clo, chi, sol2, node2, isotropic=tr%giso)
      end if
    end associate
  end subroutine gauss_force_integrals

  !> Occupied Gauss cells: acc(1, c) holds the point count of each owned cell on
  !> entry and 1 (occupied) or 0 on exit. A cell is occupied when it holds a
  !> point or when the closing (dilation, then erosion, by a box of half-width
  !> self%fill cells) fills it: scattered points leave cells empty inside the
  !> body (on W1's uniform scatter 13 of 100 cells hold no solid point, runs of
  !> up to 3 hold no fluid point), and a cell left out of the quadrature cuts the
  !> body there. A gap of more than 2 fill cells stays open, and the closing does
  !> not grow a body past its outermost occupied cells.
  subroutine gauss_occupancy(self, acc)
    class(state_t), intent(inout) :: self
    real(wp), intent(inout) :: acc(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    associate (clo => self%dec%clo, chi => self%dec%chi)
      self%occ = 0.0_wp
      self%occ(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)) = &
        merge(1.0_wp, 0.0_wp, acc(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)) > 0.5_wp)
      call self%dec%halo_copy(self%occ)
      self%occ2 = 0.0_wp
      call occupancy_pass(self%nd, self%fill, .true., self%dec%alo, clo, chi, self%grid%ncells, &
                          self%occ, self%occ2)
      call self%dec%halo_copy(self%occ2)
      call occupancy_pass(self%nd, self%fill, .false., self%dec%alo, clo, chi, self%grid%ncells, &
                          self%occ2, self%occ)
      acc(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)) = &
        self%occ(1, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3))
    end associate
  end subroutine gauss_occupancy

  !> Point velocity gradients vgrad of the points of tr by the transpose of the
  !> quadrature force operator of their reconstruction sol, from the nodal
  !> velocities nvel (doc/theory.md 3.6).
  subroutine gauss_point_gradients(self, tr, sol, nvel, vgrad)
    class(state_t), intent(inout) :: self
    type(phase_t), intent(inout) :: tr
    real(wp), intent(in) :: sol(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: nvel(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(inout) :: vgrad(:, :)
    integer :: nkept
    call gauss_velocity_gradient(self%nd, self%plan%ngauss, self%kernel, self%grid%h, &
                                 self%dec%alo, self%dec%clo, self%dec%chi, sol, nvel, tr%glg)
    call self%dec%halo_copy(tr%glg)
    associate (pl => self%plan)
      call gauss_strain(self%nd, tr%pts%n, tr%xold, tr%volold, self%grid%origin, self%grid%h, &
                        self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                        pl%field_radial, pl%field_basis, self%dec%alo, sol, tr%glg, tr%vt, nkept, &
                        vgrad=vgrad, cache=tr%reach, isotropic=tr%giso)
    end associate
    self%nkept = self%nkept + nkept
  end subroutine gauss_point_gradients

  !> The divergences at the points of tr (fluid points) of two nodal velocities, div
  !> of nvel and div2 of nvel2 (the solid's), by the transpose of the quadrature force
  !> operator of the points' reconstruction sol in one pass over the points: the traces
  !> of the gradients gauss_point_gradients gives.
  subroutine gauss_point_divergences(self, tr, sol, nvel, nvel2, div, div2)
    class(state_t), intent(inout) :: self
    type(phase_t), intent(inout) :: tr
    real(wp), intent(in) :: sol(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: nvel(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: nvel2(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(inout) :: div(:), div2(:)
    integer :: nkept
    associate (pl => self%plan)
      call gauss_velocity_gradient(self%nd, pl%ngauss, self%kernel, self%grid%h, &
                                   self%dec%alo, self%dec%clo, self%dec%chi, sol, nvel, tr%glg)
      call self%dec%halo_copy(tr%glg)
      call gauss_velocity_gradient(self%nd, pl%ngauss, self%kernel, self%grid%h, &
                                   self%dec%alo, self%dec%clo, self%dec%chi, sol, nvel2, tr%glg2)
      call self%dec%halo_copy(tr%glg2)
      call gauss_strain(self%nd, tr%pts%n, tr%xold, tr%volold, self%grid%origin, self%grid%h, &
                        self%grid%ncells, pl%ngauss, pl%field_kernel, pl%field_radius, &
                        pl%field_radial, pl%field_basis, self%dec%alo, sol, tr%glg, tr%vt, nkept, &
                        div=div, lg2=tr%glg2, div2=div2, cache=tr%reach, isotropic=tr%giso)
    end associate
    ! Both divergences keep their point-wise value at the same points.
    self%nkept = self%nkept + 2*nkept
  end subroutine gauss_point_divergences

end module dpmpm_quadrature
