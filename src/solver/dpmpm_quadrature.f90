!> Gauss quadrature of the internal forces (doc/theory.md 3.6): the driving code of
!> the MLS reconstruction of a stress-like field on the Gauss points of the
!> cells (sums, occupancy of the cells, solve, forces), and the point velocity
!> gradients (fluid points: divergences) by the transpose of the same operator, and
!> at the nodes the shares of the pore pressure's force (porosity-gradient terms) and
!> gravity by the same quadrature (doc/theory.md 3.6, items 7 and 8). The algebra is in
!> dpmpm_gauss_fields; here are its passes with their halo exchanges.
module dpmpm_quadrature
  use dpmpm_kinds, only: wp
  use dpmpm_grid, only: node_slots_t, node_slots
  use dpmpm_timer, only: t_halo
  use mpi_f08, only: MPI_Allreduce, MPI_IN_PLACE, MPI_INTEGER, MPI_MAX
  use dpmpm_gauss_fields, only: occupancy_pass, gauss_accumulate, gauss_solve, gauss_forces, gauss_masses, &
                               gauss_velocity_gradient, gauss_strain, thin_fraction, widened_radii, &
                               widened_cell_offset, gauss_radius_slot, gauss_cell_components
  use dpmpm_phase, only: phase_t, solid_phase, fluid_phase
  use dpmpm_state, only: state_t
  use dpmpm_transfer, only: volume_p2g
  implicit none
  private
  public :: gauss_force_integrals, gauss_point_gradients, gauss_point_divergences
  public :: gauss_p2g, gauss_pressure_forces, gauss_mixture_divergence, gauss_gravity, gauss_gravity_work

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
    integer :: n, iw, g
    real(wp), allocatable :: wide(:, :, :, :)
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
        call widen_empty_gauss_points(self, tr, fields, wide, fields2)
        call gauss_solve(self%nd, pl%ngauss, pl%field_basis, self%dec%alo, clo, chi, tr%gacc, sol, &
                         self%mls_stats, tr%giso, tr%gacc2, sol2)
      else
        call widen_empty_gauss_points(self, tr, fields, wide)
        call gauss_solve(self%nd, pl%ngauss, pl%field_basis, self%dec%alo, clo, chi, tr%gacc, sol, &
                         self%mls_stats, tr%giso)
      end if
      ! The radius each widened Gauss point took, for the transpose (gauss_strain).
      if (allocated(wide)) then
        iw = gauss_radius_slot(self%nd, pl%ngauss, pl%field_basis, tr%giso)
        do g = 1, pl%ngauss**self%nd
          sol(iw + g, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)) = &
            max(wide(g, clo(1):chi(1), clo(2):chi(2), clo(3):chi(3)), 0.0_wp)
        end do
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

  !> Gauss points of occupied owned cells that found no point of tr within the field's
  !> radius widen their reach (widened_radii: 0.75 -> 1.0, then 1.25 cells) instead of
  !> entering the forces with a zero field: the points within the wider reach are added
  !> to their sums in tr%gacc (and tr%gacc2) alone, and wide(g, c) keeps the radius each
  !> took (0 for the others and for those that found no point even so). Unallocated
  !> without &shape field_widen, or where no Gauss point on any rank is empty: then
  !> nothing changes. A radius whose
  !> reach would pass the ghost cells (or 3 cells) is not tried. Counts the widened
  !> Gauss points in self%mls_stats%nwidened.
  subroutine widen_empty_gauss_points(self, tr, fields, wide, fields2)
    class(state_t), intent(inout) :: self
    type(phase_t), intent(inout) :: tr
    real(wp), intent(in) :: fields(:, :)
    real(wp), allocatable, intent(out) :: wide(:, :, :, :)
    real(wp), intent(in), optional :: fields2(:, :)
    real(wp), parameter :: unfound = -1.0_wp
    integer :: i, j, k, g, ngp, ncg, lv, nempty(1)
    real(wp) :: rw(2)
    if (.not. self%cfg%field_widen) return
    associate (pl => self%plan, clo => self%dec%clo, chi => self%dec%chi, acc => tr%gacc)
      ngp = pl%ngauss**self%nd
      ncg = (gauss_cell_components(self%nd, pl%ngauss, pl%field_basis, tr%giso) - 1)/ngp
      nempty = 0
      do k = clo(3), chi(3)
        do j = clo(2), chi(2)
          do i = clo(1), chi(1)
            if (acc(1, i, j, k) < 0.5_wp) cycle
            do g = 1, ngp
              if (acc(2 + (g - 1)*ncg, i, j, k) < 0.5_wp) nempty(1) = nempty(1) + 1
            end do
          end do
        end do
      end do
      call MPI_Allreduce(MPI_IN_PLACE, nempty, 1, MPI_INTEGER, MPI_MAX, self%dec%comm)
      if (nempty(1) == 0) return
      allocate (wide(ngp, lbound(acc, 2):ubound(acc, 2), lbound(acc, 3):ubound(acc, 3), &
                     lbound(acc, 4):ubound(acc, 4)))
      wide = 0.0_wp
      do k = clo(3), chi(3)
        do j = clo(2), chi(2)
          do i = clo(1), chi(1)
            if (acc(1, i, j, k) < 0.5_wp) cycle
            do g = 1, ngp
              if (acc(2 + (g - 1)*ncg, i, j, k) < 0.5_wp) wide(g, i, j, k) = unfound
            end do
          end do
        end do
      end do
      rw = widened_radii(pl%field_radius)
      do lv = 1, 2
        if (widened_cell_offset(pl%ngauss, pl%field_kernel, rw(lv), pl%field_radial) > &
            minval(self%dec%gw(1:self%nd)) .or. rw(lv) > 3.0_wp) exit
        where (wide == unfound) wide = rw(lv)
        call self%dec%halo_copy(wide)
        if (present(fields2)) then
          call gauss_accumulate(self%nd, tr%pts%n, tr%pts%x, tr%pts%vol, fields, self%grid%origin, &
                                self%grid%h, self%grid%ncells, pl%ngauss, pl%field_kernel, rw(lv), &
                                pl%field_radial, pl%field_basis, self%dec%alo, acc, fields2, &
                                tr%gacc2, isotropic=tr%giso, only=wide, level=rw(lv))
        else
          call gauss_accumulate(self%nd, tr%pts%n, tr%pts%x, tr%pts%vol, fields, self%grid%origin, &
                                self%grid%h, self%grid%ncells, pl%ngauss, pl%field_kernel, rw(lv), &
                                pl%field_radial, pl%field_basis, self%dec%alo, acc, &
                                isotropic=tr%giso, only=wide, level=rw(lv))
        end if
        ! (the ghosts of acc are zero after the first halo_sum: only the new sums move)
        call self%dec%halo_sum(acc)
        if (present(fields2)) call self%dec%halo_sum(tr%gacc2)
        do k = clo(3), chi(3)
          do j = clo(2), chi(2)
            do i = clo(1), chi(1)
              do g = 1, ngp
                if (wide(g, i, j, k) /= rw(lv)) cycle
                if (acc(2 + (g - 1)*ncg, i, j, k) < 0.5_wp) then
                  wide(g, i, j, k) = unfound
                else
                  self%mls_stats%nwidened = self%mls_stats%nwidened + 1
                end if
              end do
            end do
          end do
        end do
      end do
      where (wide < 0.0_wp) wide = 0.0_wp
    end associate
  end subroutine widen_empty_gauss_points

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

  !> p2g by Gauss quadrature (doc/theory.md 3.6): the point volume of the nodes beside
  !> their quadrature volume (thin nodes), the internal forces of the skeleton and of the
  !> pore pressure. With ggrav (gravity) the Gauss points carry the density as well, and
  !> gms (the solid's) and, with the porosity-gradient terms, gmf (the fluid's own density
  !> m / (n V)) come back with the Gauss masses in their first component (gauss_gravity).
  !> With the porosity-gradient terms the Gauss points carry p alone, and its force F_I
  !> comes back in gpf (nd components), to be shared at the nodes once the nodal porosity
  !> is known (gauss_pressure_forces; item 7); without them the fluid takes -n_f p and the
  !> solid -(1 - n_f) p in one pass. Unallocated on return where not asked for.
  subroutine gauss_p2g(self, ggrav, gpf, gms, gmf)
    class(state_t), intent(inout) :: self
    logical, intent(in) :: ggrav
    real(wp), allocatable, intent(out) :: gpf(:, :, :, :), gms(:, :, :, :), gmf(:, :, :, :)
    real(wp), allocatable :: pseudo(:, :), pseudo2(:, :), fnode(:, :, :, :)
    integer :: ip, nd, ns, nf
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    do ip = 1, self%nph
      associate (ph => self%phase(ip))
        ph%nvol = 0.0_wp
        call volume_p2g(ph%st%nw, ph%pts%n, ph%st%i0, ph%st%sw, ph%pts%vol, self%dec%alo, ph%nvol)
      end associate
    end do
    associate (s => self%phase(solid_phase), lo => self%dec%alo, hi => self%dec%ahi)
      ns = s%pts%n
      if (ggrav) then
        allocate (pseudo(size(s%pts%stress, 1), ns))
        pseudo = 0.0_wp
        pseudo(1, :) = s%pts%mass(1:ns)/s%pts%vol(1:ns)
        allocate (gms(1 + nd, lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)))
        gms = 0.0_wp
        call gauss_force_integrals(self, s, s%pts%stress, s%gsol, s%node, pseudo, s%gsol2, gmass=gms)
        deallocate (pseudo)
      else
        call gauss_force_integrals(self, s, s%pts%stress, s%gsol, s%node)
      end if
    end associate
    if (self%nph < 2) return
    associate (f => self%phase(fluid_phase))
      nf = f%pts%n
      allocate (pseudo(1, nf), pseudo2(1, nf))
      if (self%cfg%porosity_gradient) then
        pseudo(1, :) = -f%pts%pressure(1:nf)
        allocate (fnode, mold=f%node)
        fnode = 0.0_wp
        if (ggrav) then
          pseudo2(1, :) = f%pts%mass(1:nf)/(f%pts%porosity(1:nf)*f%pts%vol(1:nf))
          allocate (gmf, mold=gms)
          gmf = 0.0_wp
          call gauss_force_integrals(self, f, pseudo, f%gsol, fnode, pseudo2, f%gsol2, gmass=gmf)
        else
          call gauss_force_integrals(self, f, pseudo, f%gsol, fnode)
        end if
        allocate (gpf(nd, self%dec%alo(1):self%dec%ahi(1), self%dec%alo(2):self%dec%ahi(2), &
                      self%dec%alo(3):self%dec%ahi(3)))
        gpf = fnode(sl%force_lo:sl%force_hi, :, :, :)
      else
        ! (isotropic fields: one value per point, f%giso)
        pseudo(1, :) = -f%pts%porosity(1:nf)*f%pts%pressure(1:nf)
        pseudo2(1, :) = -(1.0_wp - f%pts%porosity(1:nf))*f%pts%pressure(1:nf)
        call gauss_force_integrals(self, f, pseudo, f%gsol, f%node, pseudo2, f%gsol2, &
                                   self%phase(solid_phase)%node)
      end if
    end associate
  end subroutine gauss_p2g

  !> With Gauss quadrature and the porosity-gradient terms: the forces of the pore
  !> pressure at the Gauss points, F_I = sum_g w_g p_g grad N_I(x_g) (gpf from gauss_p2g,
  !> folded with the fluid's conditions, and gps, the same folded with the solid's; both
  !> summed over the ranks), shared at the owned nodes: n_I F_I
  !> to the fluid and (1 - n_I) F_I to the solid ((3.3a) with the Gauss points in the
  !> place of the fluid points; the owned nodal porosity is known).
  subroutine gauss_pressure_forces(self, gpf, gps)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: gpf(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: gps(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer :: i, j, k, nd
    real(wp) :: nI
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    associate (olo => self%dec%olo, ohi => self%dec%ohi, fn => self%phase(fluid_phase)%node, &
               sn => self%phase(solid_phase)%node)
      do k = olo(3), ohi(3)
        do j = olo(2), ohi(2)
          do i = olo(1), ohi(1)
            nI = self%cpl%nporo(1, i, j, k)
            fn(sl%force_lo:sl%force_hi, i, j, k) = fn(sl%force_lo:sl%force_hi, i, j, k) + nI*gpf(1:nd, i, j, k)
            sn(sl%force_lo:sl%force_hi, i, j, k) = sn(sl%force_lo:sl%force_hi, i, j, k) + (1.0_wp - nI)*gps(1:nd, i, j, k)
          end do
        end do
      end do
    end associate
  end subroutine gauss_pressure_forces

  !> Gravity by the Gauss quadrature of the forces: the nodal update gives each node
  !> m_I g of its points' masses; the difference (M_I - m_I) g to the Gauss masses
  !> M_I = sum_g w_g rho_g N_I(x_g) (gm(1, :), summed over the ranks; gauss_masses) joins
  !> the forces of the owned nodes that take internal forces (not the thin ones, whose
  !> points barely reach them) and is kept in gm(2:1+nd, :) for its work
  !> (gauss_gravity_work). On points scattered in the cells m_I scatters from node to
  !> node while the Gauss-point forces of a stress at rest do not, and the difference
  !> drove free water at rest (doc/theory.md 3.6, item 8). With nporo (the pore fluid
  !> with the porosity-gradient terms, rho_g its own density) the fluid takes n_I M_I g,
  !> shared like the pressure's force n_I F_I that balances it at rest; the solid then
  !> takes the rest of the fluid's weight (transfer: the fluid's difference, taken from
  !> it where the solid has a node), so that the nodes carry the weight of the points.
  subroutine gauss_gravity(self, ph, g, gm, nporo, transfer)
    class(state_t), intent(inout) :: self
    type(phase_t), intent(inout) :: ph
    !> the gravity of the step
    real(wp), intent(in) :: g(3)
    real(wp), intent(inout) :: gm(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in), optional :: nporo(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in), optional :: transfer(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    integer :: i, j, k, nd
    real(wp) :: mg
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    associate (olo => self%dec%olo, ohi => self%dec%ohi, node => ph%node)
      do k = olo(3), ohi(3)
        do j = olo(2), ohi(2)
          do i = olo(1), ohi(1)
            gm(2:1 + nd, i, j, k) = 0.0_wp
            if (node(1, i, j, k) <= 0.0_wp) cycle
            if (ph%nvol(1, i, j, k) < thin_fraction*ph%nvol(2, i, j, k)) cycle
            mg = gm(1, i, j, k)
            if (present(nporo)) mg = nporo(1, i, j, k)*mg
            gm(2:1 + nd, i, j, k) = (mg - node(1, i, j, k))*g(1:nd)
            if (present(transfer)) gm(2:1 + nd, i, j, k) = gm(2:1 + nd, i, j, k) - transfer(2:1 + nd, i, j, k)
            node(sl%force_lo:sl%force_hi, i, j, k) = node(sl%force_lo:sl%force_hi, i, j, k) + gm(2:1 + nd, i, j, k)
          end do
        end do
      end do
    end associate
  end subroutine gauss_gravity

  !> The work over the step of the gravity beyond the points' own (gauss_gravity; the
  !> force in gm(2:1+nd, :) of the owned nodes) at the nodes' mean velocity.
  subroutine gauss_gravity_work(self, nvel, gm, dt)
    class(state_t), intent(inout) :: self
    real(wp), intent(in) :: nvel(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: gm(:, self%dec%alo(1):, self%dec%alo(2):, self%dec%alo(3):)
    real(wp), intent(in) :: dt
    integer :: i, j, k, nd
    type(node_slots_t) :: sl
    nd = self%nd
    sl = node_slots(nd)
    associate (olo => self%dec%olo, ohi => self%dec%ohi)
      do k = olo(3), ohi(3)
        do j = olo(2), ohi(2)
          do i = olo(1), ohi(1)
            self%ext_work = self%ext_work + 0.5_wp*dt*dot_product(gm(2:1 + nd, i, j, k), &
                                                                  nvel(sl%old_lo:sl%old_hi, i, j, k) + &
                                                                  nvel(sl%new_lo:sl%new_hi, i, j, k))
          end do
        end do
      end do
    end associate
  end subroutine gauss_gravity_work

  !> With Gauss quadrature and the porosity-gradient terms: the divergence of the
  !> mixture flux n_I v_f,I + (1 - n_I) v_s,I at the fluid points by the transpose of
  !> the Gauss pressure forces (gauss_pressure_forces), into mix; the fluid points'
  !> divf and divs are then 0, so that the pressure update takes mix alone. A point out
  !> of the Gauss points' reach keeps its point-wise value, divf and divs of the
  !> nodal velocities weighted by its porosity plus mix from mixture_flux on entry.
  subroutine gauss_mixture_divergence(self, mix)
    class(state_t), intent(inout) :: self
    real(wp), intent(inout) :: mix(:)
    real(wp), allocatable :: uf(:, :, :, :), us(:, :, :, :)
    integer :: nd, nf, c
    nd = self%nd
    associate (f => self%phase(fluid_phase), s => self%phase(solid_phase))
      nf = f%pts%n
      uf = f%nvel
      us = s%nvel
      do c = nd + 1, 2*nd
        uf(c, :, :, :) = self%cpl%nporo(1, :, :, :)*uf(c, :, :, :)
        us(c, :, :, :) = (1.0_wp - self%cpl%nporo(1, :, :, :))*us(c, :, :, :)
      end do
      f%divf(1:nf) = f%pts%porosity(1:nf)*f%divf(1:nf) + mix(1:nf)
      f%divs(1:nf) = (1.0_wp - f%pts%porosity(1:nf))*f%divs(1:nf)
      call gauss_point_divergences(self, f, f%gsol, uf, us, f%divf, f%divs)
      mix(1:nf) = f%divf(1:nf) + f%divs(1:nf)
      f%divf(1:nf) = 0.0_wp
      f%divs(1:nf) = 0.0_wp
    end associate
  end subroutine gauss_mixture_divergence

end module dpmpm_quadrature
