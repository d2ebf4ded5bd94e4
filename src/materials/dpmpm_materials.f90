!> Constitutive models behind one interface. The model is chosen per material
!> group of points, not per point: each update routine loops over the points of
!> one material. Stress is Cauchy, tension positive, Voigt order xx yy zz yz xz xy.
module dpmpm_materials
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: material_cfg_t
  use dpmpm_plasticity, only: plastic_params_t, plastic_setup, plastic_returns, dp_match_names, &
                              dp_plane_strain, surface_mohr_coulomb, surface_drucker_prager
  implicit none
  private
  public :: material_t, model_linear_elastic, model_neo_hookean, model_fluid, model_from_name
  public :: model_mohr_coulomb, model_drucker_prager, model_rigid, is_plastic
  public :: materials_from_config, stress_update, strain_energy, wave_speed, wave_speeds
  public :: voigt_to_tensor, tensor_to_voigt

  integer, parameter :: model_linear_elastic = 1, model_neo_hookean = 2, model_fluid = 3
  !> Elasto-plastic soils (dpmpm_plasticity): linear elastic with the Jaumann rate, then a
  !> return to the Mohr-Coulomb or Drucker-Prager surface.
  integer, parameter :: model_mohr_coulomb = 4, model_drucker_prager = 5
  !> A rigid body moving at a prescribed velocity (dpmpm_rigid): no stress, no wave.
  integer, parameter :: model_rigid = 6

  !> Parameters of one material, with the derived elastic constants.
  type :: material_t
    integer :: id = 1
    integer :: model = model_linear_elastic
    real(wp) :: density = 1.0_wp
    real(wp) :: youngs = 1.0_wp, poisson = 0.0_wp
    real(wp) :: lambda = 0.0_wp, mu = 0.0_wp, bulk = 0.0_wp
    real(wp) :: pwave = 0.0_wp          !< constrained modulus lambda + 2 mu
    real(wp) :: bulk_fluid = 0.0_wp     !< K_f of a fluid
    real(wp) :: conductivity = 0.0_wp   !< hydraulic conductivity of a soil (m/s), 0 = none
    logical :: kozeny_carman = .false.  !< k follows the porosity (Kozeny-Carman)
    type(plastic_params_t) :: plastic   !< strength of mohr_coulomb and drucker_prager
    real(wp) :: max_dilation = 0.0_wp   !< mohr_coulomb, drucker_prager: bound of V/V0, 0 = none
    real(wp) :: velocity(3) = 0.0_wp    !< rigid: the prescribed velocity of the body (m/s)
  end type material_t

contains

  !> Model code from its input name, 0 if unknown.
  pure integer function model_from_name(name) result(m)
    character(len=*), intent(in) :: name
    select case (trim(adjustl(name)))
    case ('linear_elastic')
      m = model_linear_elastic
    case ('neo_hookean')
      m = model_neo_hookean
    case ('fluid')
      m = model_fluid
    case ('mohr_coulomb')
      m = model_mohr_coulomb
    case ('drucker_prager')
      m = model_drucker_prager
    case ('rigid')
      m = model_rigid
    case default
      m = 0
    end select
  end function model_from_name

  !> Materials with Lame constants from E and nu.
  subroutine materials_from_config(cfgs, mats)
    type(material_cfg_t), intent(in) :: cfgs(:)
    type(material_t), allocatable, intent(out) :: mats(:)
    integer :: k, match
    real(wp) :: e, nu
    allocate (mats(size(cfgs)))
    do k = 1, size(cfgs)
      e = cfgs(k)%youngs_modulus
      nu = cfgs(k)%poisson_ratio
      mats(k)%id = cfgs(k)%id
      mats(k)%model = model_from_name(cfgs(k)%model)
      mats(k)%density = cfgs(k)%density
      mats(k)%youngs = e
      mats(k)%poisson = nu
      mats(k)%lambda = e*nu/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
      mats(k)%mu = e/(2.0_wp*(1.0_wp + nu))
      mats(k)%bulk = e/(3.0_wp*(1.0_wp - 2.0_wp*nu))
      mats(k)%pwave = mats(k)%lambda + 2.0_wp*mats(k)%mu
      mats(k)%bulk_fluid = cfgs(k)%bulk_modulus
      mats(k)%conductivity = cfgs(k)%conductivity
      mats(k)%kozeny_carman = cfgs(k)%conductivity_law == 'kozeny_carman'
      if (is_plastic(mats(k)%model)) then
        match = findloc(dp_match_names, trim(cfgs(k)%dp_match), dim=1)
        if (match == 0) match = dp_plane_strain
        mats(k)%plastic = plastic_setup(merge(surface_mohr_coulomb, surface_drucker_prager, &
                                              mats(k)%model == model_mohr_coulomb), &
                                        mats(k)%bulk, mats(k)%mu, cfgs(k)%friction_angle, &
                                        cfgs(k)%dilatancy_angle, cfgs(k)%cohesion, &
                                        cfgs(k)%tensile_strength, cfgs(k)%cohesion_softening, &
                                        cfgs(k)%residual_cohesion, match)
        mats(k)%max_dilation = cfgs(k)%max_dilation
      end if
      if (mats(k)%model == model_fluid) then
        mats(k)%lambda = 0.0_wp; mats(k)%mu = 0.0_wp; mats(k)%pwave = 0.0_wp
        mats(k)%bulk = cfgs(k)%bulk_modulus
      end if
      if (mats(k)%model == model_rigid) then
        ! no stress (stress_update and strain_energy leave it out) and no wave to resolve
        mats(k)%lambda = 0.0_wp; mats(k)%mu = 0.0_wp; mats(k)%pwave = 0.0_wp
        mats(k)%velocity = cfgs(k)%velocity
      end if
    end do
  end subroutine materials_from_config

  !> True for the elasto-plastic models, whose points carry an accumulated plastic strain.
  elemental logical function is_plastic(model)
    integer, intent(in) :: model
    is_plastic = model == model_mohr_coulomb .or. model == model_drucker_prager
  end function is_plastic

  !> Speed of the fastest (dilatational) wave at current density rho.
  pure real(wp) function wave_speed(mat, rho) result(c)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: rho
    c = sqrt(mat%pwave/rho)
  end function wave_speed

  !> wave_speed of n points of materials mats(pmat(:)) at density mass / vol, in c
  !> (the same formula; the time step's scan takes them in chunks).
  pure subroutine wave_speeds(mats, n, pmat, mass, vol, c)
    type(material_t), intent(in) :: mats(:)
    integer, intent(in) :: n, pmat(:)
    real(wp), intent(in) :: mass(:), vol(:)
    real(wp), intent(out) :: c(:)
    integer :: p
    ! (the moduli gathered first, so that the loop of roots vectorises)
    do p = 1, n
      c(p) = mats(pmat(p))%pwave
    end do
    do p = 1, n
      c(p) = sqrt(c(p)/(mass(p)/vol(p)))
    end do
  end subroutine wave_speeds

  !> 3x3 symmetric tensor from Voigt components.
  pure function voigt_to_tensor(s) result(t)
    real(wp), intent(in) :: s(6)
    real(wp) :: t(3, 3)
    t(1, 1) = s(1); t(2, 2) = s(2); t(3, 3) = s(3)
    t(2, 3) = s(4); t(3, 2) = s(4)
    t(1, 3) = s(5); t(3, 1) = s(5)
    t(1, 2) = s(6); t(2, 1) = s(6)
  end function voigt_to_tensor

  !> Voigt components of the symmetric part of a 3x3 tensor.
  pure function tensor_to_voigt(t) result(s)
    real(wp), intent(in) :: t(3, 3)
    real(wp) :: s(6)
    s = [t(1, 1), t(2, 2), t(3, 3), 0.5_wp*(t(2, 3) + t(3, 2)), 0.5_wp*(t(1, 3) + t(3, 1)), &
         0.5_wp*(t(1, 2) + t(2, 1))]
  end function tensor_to_voigt

  !> Update stress, volume (and F) of the points of material index m over one
  !> step dt, given each point's velocity gradient vgrad(9, n) (3x3, column-major).
  !> Linear elastic: hypoelastic with the Jaumann rate (objective under rotation).
  !> Neo-Hookean: F <- (I + dt L) F, sigma = (mu (F F^T - I) + lambda ln J I)/J.
  !> Mohr-Coulomb, Drucker-Prager: the stress is first rotated with the spin (Jaumann,
  !> sigma + dt (W sigma - sigma W)), then plastic_return takes the strain increment dt D
  !> (elastic predictor and return); epsp is the accumulated plastic strain of each point.
  !> In a saturated soil this is the effective stress; the pore pressure stays apart.
  !> dissipation (when present) gains the plastic work of the step,
  !> V (sigma_n + sigma_n+1)/2 : d eps^p with d eps^p = dt D - C^-1 (sigma_n+1 - sigma_n)
  !> (sigma_n after the rotation), so that the energy balance can count it.
  !> plane (2D, plane strain): the velocity gradients and F have no third row and
  !> column, and the elastic models take the short 2D forms of the same formulas.
  subroutine stress_update(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, epsp, &
                           dissipation, plane)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    real(wp), intent(in) :: dt
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: vgrad(:, :)
    real(wp), intent(inout) :: stress(:, :), vol(:)
    real(wp), intent(in) :: vol0(:)
    real(wp), intent(inout), optional :: defgrad(:, :)
    real(wp), intent(inout), optional :: epsp(:)
    real(wp), intent(inout), optional :: dissipation
    logical, intent(in), optional :: plane
    real(wp) :: lg(3, 3), dmat(3, 3), wmat(3, 3), s(3, 3), f(3, 3), b(3, 3), ident(3, 3), tr
    integer, parameter :: nb = 64
    real(wp) :: dsig(6), dep(6), sr(6, nb), sn(6, nb), de(6, nb), jb(nb), ep(nb), lnj(nb), wsum
    real(wp) :: rcp_youngs, rcp_mu
    integer :: p, p0, k, q, nk, idx(nb)
    logical :: flat
    if (present(plane)) then
      if (plane .and. mat%model == model_neo_hookean) then
        call neo_hookean_plane(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad)
        return
      else if (plane .and. mat%model == model_linear_elastic) then
        call linear_elastic_plane(mat, m, dt, n, pmat, vgrad, stress, vol)
        return
      end if
    end if
    ident = 0.0_wp
    do k = 1, 3
      ident(k, k) = 1.0_wp
    end do
    select case (mat%model)
    case (model_linear_elastic)
      do p = 1, n
        if (pmat(p) /= m) cycle
        lg = as_3x3(vgrad(:, p))
        dmat = 0.5_wp*(lg + transpose(lg))
        wmat = 0.5_wp*(lg - transpose(lg))
        s = voigt_to_tensor(stress(:, p))
        tr = dmat(1, 1) + dmat(2, 2) + dmat(3, 3)
        s = s + dt*(mat%lambda*tr*ident + 2.0_wp*mat%mu*dmat + matmul(wmat, s) - matmul(s, wmat))
        stress(:, p) = tensor_to_voigt(s)
        vol(p) = vol(p)*det3(ident + dt*lg)
      end do
    case (model_neo_hookean)
      ! (chunks of points as in neo_hookean_plane: F and J, ln J in a loop of its own, the
      ! stresses)
      do p0 = 1, n, nb
        nk = min(nb, n - p0 + 1)
        do k = 1, nk
          p = p0 + k - 1
          jb(k) = 1.0_wp
          if (pmat(p) /= m) cycle
          lg = as_3x3(vgrad(:, p))
          f = matmul(ident + dt*lg, as_3x3(defgrad(:, p)))
          defgrad(1:3, p) = f(:, 1); defgrad(4:6, p) = f(:, 2); defgrad(7:9, p) = f(:, 3)
          jb(k) = det3(f)
        end do
        do k = 1, nk
          lnj(k) = log(jb(k))
        end do
        do k = 1, nk
          p = p0 + k - 1
          if (pmat(p) /= m) cycle
          f = as_3x3(defgrad(:, p))
          b = matmul(f, transpose(f))
          s = (mat%mu*(b - ident) + mat%lambda*lnj(k)*ident)/jb(k)
          stress(:, p) = tensor_to_voigt(s)
          vol(p) = vol0(p)*jb(k)
        end do
      end do
    case (model_mohr_coulomb, model_drucker_prager)
      flat = .false.
      if (present(plane)) flat = plane
      rcp_youngs = 1.0_wp/mat%youngs
      rcp_mu = 1.0_wp/mat%mu
      wsum = 0.0_wp
      if (present(dissipation)) wsum = dissipation
      ! In blocks of up to nb points of the material: rotation and strain increment, the
      ! returns in one call, then the plastic work and the volume.
      p = 0
      do while (p < n)
        nk = 0
        do while (p < n .and. nk < nb)
          p = p + 1
          if (pmat(p) /= m) cycle
          nk = nk + 1
          idx(nk) = p
          call jaumann_strain(dt, vgrad(:, p), stress(:, p), flat, sr(:, nk), de(:, nk), jb(nk))
          ep(nk) = epsp(p)
        end do
        sn(:, 1:nk) = sr(:, 1:nk)
        call plastic_returns(mat%plastic, nk, de, sn, ep)
        do k = 1, nk
          q = idx(k)
          stress(:, q) = sn(:, k)
          epsp(q) = ep(k)
          if (present(dissipation)) then
            dsig = sn(:, k) - sr(:, k)
            dep(1:3) = de(1:3, k) - ((1.0_wp + mat%poisson)*dsig(1:3) - mat%poisson*sum(dsig(1:3))) &
                       *rcp_youngs
            dep(4:6) = de(4:6, k) - dsig(4:6)*rcp_mu
            wsum = wsum + 0.5_wp*vol(q)*dot_product(sr(:, k) + sn(:, k), dep)
          end if
          vol(q) = vol(q)*jb(k)
          ! Grains that have moved apart: the volume stays at the bound (doc/theory.md 5.4).
          if (mat%max_dilation > 0.0_wp) vol(q) = min(vol(q), mat%max_dilation*vol0(q))
        end do
      end do
      if (present(dissipation)) dissipation = wsum
    end select
  end subroutine stress_update

  !> The elastic predictor's kinematics of the plastic soils for one point with velocity
  !> gradient lv (3x3 column-major): the stress s rotated with the spin W = (L - L^T)/2,
  !> sr = s + dt (W s - s W), the strain increment deps = dt D (engineering shears) and
  !> jac = det(I + dt L). W s - s W = Z + Z^T with Z = W s is written out for its few
  !> terms; plane (2D) leaves out the third row and column of L, which are zero there.
  pure subroutine jaumann_strain(dt, lv, s, plane, sr, deps, jac)
    real(wp), intent(in) :: dt, lv(9), s(6)
    logical, intent(in) :: plane
    real(wp), intent(out) :: sr(6), deps(6), jac
    real(wp) :: w12, w13, w23, a11, a22, a33
    w12 = 0.5_wp*dt*(lv(4) - lv(2))
    a11 = 1.0_wp + dt*lv(1)
    a22 = 1.0_wp + dt*lv(5)
    if (plane) then
      ! only w12: the in-plane block turns, s13 and s23 turn into each other
      sr(1) = s(1) + 2.0_wp*w12*s(6)
      sr(2) = s(2) - 2.0_wp*w12*s(6)
      sr(3) = s(3)
      sr(4) = s(4) - w12*s(5)
      sr(5) = s(5) + w12*s(4)
      sr(6) = s(6) + w12*(s(2) - s(1))
      deps = 0.0_wp
      deps(1) = dt*lv(1)
      deps(2) = dt*lv(5)
      deps(6) = dt*(lv(4) + lv(2))
      jac = a11*a22 - dt*dt*lv(4)*lv(2)
    else
      w13 = 0.5_wp*dt*(lv(7) - lv(3))
      w23 = 0.5_wp*dt*(lv(8) - lv(6))
      sr(1) = s(1) + 2.0_wp*(w12*s(6) + w13*s(5))
      sr(2) = s(2) + 2.0_wp*(w23*s(4) - w12*s(6))
      sr(3) = s(3) - 2.0_wp*(w13*s(5) + w23*s(4))
      sr(4) = s(4) - w12*s(5) - w13*s(6) + w23*(s(3) - s(2))
      sr(5) = s(5) + w12*s(4) + w13*(s(3) - s(1)) - w23*s(6)
      sr(6) = s(6) + w12*(s(2) - s(1)) + w13*s(4) + w23*s(5)
      deps(1) = dt*lv(1)
      deps(2) = dt*lv(5)
      deps(3) = dt*lv(9)
      deps(4) = dt*(lv(8) + lv(6))
      deps(5) = dt*(lv(7) + lv(3))
      deps(6) = dt*(lv(4) + lv(2))
      a33 = 1.0_wp + dt*lv(9)
      jac = a11*(a22*a33 - dt*dt*lv(8)*lv(6)) - dt*lv(4)*(dt*lv(2)*a33 - dt*dt*lv(8)*lv(3)) &
            + dt*lv(7)*(dt*dt*lv(2)*lv(6) - a22*dt*lv(3))
    end if
  end subroutine jaumann_strain

  !> The neo-Hookean update of stress_update in plane strain: F33 = 1 and the
  !> in-plane 2x2 block of F carries the motion. Chunks of points: F and J in one loop,
  !> ln J in the next (J = 1 stands in at points of other materials), the stresses in a
  !> third, so that the first and the last vectorise.
  subroutine neo_hookean_plane(mat, m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    real(wp), intent(in) :: dt
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: vgrad(:, :)
    real(wp), intent(inout) :: stress(:, :), vol(:)
    real(wp), intent(in) :: vol0(:)
    real(wp), intent(inout) :: defgrad(:, :)
    integer, parameter :: nb = 64
    real(wp) :: a11, a21, a12, a22, f11, f21, f12, f22, jac(nb), lnj(nb), rj
    integer :: p, p0, k, nk
    do p0 = 1, n, nb
      nk = min(nb, n - p0 + 1)
      do k = 1, nk
        p = p0 + k - 1
        jac(k) = 1.0_wp
        if (pmat(p) /= m) cycle
        ! A = I + dt L; F <- A F (column-major: 1 = 11, 2 = 21, 4 = 12, 5 = 22).
        a11 = 1.0_wp + dt*vgrad(1, p); a21 = dt*vgrad(2, p)
        a12 = dt*vgrad(4, p); a22 = 1.0_wp + dt*vgrad(5, p)
        f11 = a11*defgrad(1, p) + a12*defgrad(2, p)
        f21 = a21*defgrad(1, p) + a22*defgrad(2, p)
        f12 = a11*defgrad(4, p) + a12*defgrad(5, p)
        f22 = a21*defgrad(4, p) + a22*defgrad(5, p)
        defgrad(1, p) = f11; defgrad(2, p) = f21; defgrad(4, p) = f12; defgrad(5, p) = f22
        jac(k) = f11*f22 - f12*f21
      end do
      do k = 1, nk
        lnj(k) = log(jac(k))
      end do
      do k = 1, nk
        p = p0 + k - 1
        if (pmat(p) /= m) cycle
        f11 = defgrad(1, p); f21 = defgrad(2, p); f12 = defgrad(4, p); f22 = defgrad(5, p)
        rj = 1.0_wp/jac(k)
        ! sigma = (mu (F F^T - I) + lambda ln J I)/J; the third normal stress has F33 = 1.
        stress(1, p) = (mat%mu*(f11*f11 + f12*f12 - 1.0_wp) + mat%lambda*lnj(k))*rj
        stress(2, p) = (mat%mu*(f21*f21 + f22*f22 - 1.0_wp) + mat%lambda*lnj(k))*rj
        stress(3, p) = mat%lambda*lnj(k)*rj
        stress(4, p) = 0.0_wp
        stress(5, p) = 0.0_wp
        stress(6, p) = mat%mu*(f11*f21 + f12*f22)*rj
        vol(p) = vol0(p)*jac(k)
      end do
    end do
  end subroutine neo_hookean_plane

  !> The hypoelastic (Jaumann) update of stress_update in plane strain: D33 = 0,
  !> one spin component w = (L12 - L21)/2, and no out-of-plane shear stress.
  subroutine linear_elastic_plane(mat, m, dt, n, pmat, vgrad, stress, vol)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    real(wp), intent(in) :: dt
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: vgrad(:, :)
    real(wp), intent(inout) :: stress(:, :), vol(:)
    real(wp) :: l11, l21, l12, l22, d12, w12, tr, s11, s22, s12
    integer :: p
    do p = 1, n
      if (pmat(p) /= m) cycle
      l11 = vgrad(1, p); l21 = vgrad(2, p); l12 = vgrad(4, p); l22 = vgrad(5, p)
      d12 = 0.5_wp*(l12 + l21)
      w12 = 0.5_wp*(l12 - l21)
      tr = l11 + l22
      s11 = stress(1, p); s22 = stress(2, p); s12 = stress(6, p)
      ! (W s - s W) in the plane: 2 w s12, -2 w s12 and w (s22 - s11).
      stress(1, p) = s11 + dt*(mat%lambda*tr + 2.0_wp*mat%mu*l11 + 2.0_wp*w12*s12)
      stress(2, p) = s22 + dt*(mat%lambda*tr + 2.0_wp*mat%mu*l22 - 2.0_wp*w12*s12)
      stress(3, p) = stress(3, p) + dt*mat%lambda*tr
      stress(6, p) = s12 + dt*(2.0_wp*mat%mu*d12 + w12*(s22 - s11))
      vol(p) = vol(p)*((1.0_wp + dt*l11)*(1.0_wp + dt*l22) - dt*dt*l12*l21)
    end do
  end subroutine linear_elastic_plane

  !> Stored elastic energy of the points of material index m (J, per unit
  !> length/area in 2D/1D). Linear elastic (and the elastic part of the plastic soils):
  !> sigma : C^-1 : sigma / 2 times volume;
  !> neo-Hookean: (mu/2)(tr C - 3) - mu ln J + (lambda/2) (ln J)^2 per reference volume.
  pure real(wp) function strain_energy(mat, m, n, pmat, stress, vol, vol0, defgrad) result(e)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m, n
    integer, intent(in) :: pmat(:)
    real(wp), intent(in) :: stress(:, :), vol(:), vol0(:)
    real(wp), intent(in), optional :: defgrad(:, :)
    real(wp) :: s(6), tr, w, f(3, 3), lnj
    integer :: p
    e = 0.0_wp
    do p = 1, n
      if (pmat(p) /= m) cycle
      select case (mat%model)
      case (model_linear_elastic, model_mohr_coulomb, model_drucker_prager)
        s = stress(:, p)
        tr = s(1) + s(2) + s(3)
        ! sigma : eps with eps = ((1+nu) sigma - nu tr(sigma) I)/E; shear terms count twice.
        w = ((1.0_wp + mat%poisson)*(sum(s(1:3)**2) + 2.0_wp*sum(s(4:6)**2)) - mat%poisson*tr**2) &
            /mat%youngs
        e = e + 0.5_wp*w*vol(p)
      case (model_neo_hookean)
        f = as_3x3(defgrad(:, p))
        lnj = log(det3(f))
        w = 0.5_wp*mat%mu*(sum(f**2) - 3.0_wp) - mat%mu*lnj + 0.5_wp*mat%lambda*lnj**2
        e = e + w*vol0(p)
      end select
    end do
  end function strain_energy

  !> A 3x3 tensor from its 9 values stored column-major (as reshape would, without
  !> the library call for a section of run-time shape).
  pure function as_3x3(a) result(t)
    real(wp), intent(in) :: a(9)
    real(wp) :: t(3, 3)
    t(:, 1) = a(1:3)
    t(:, 2) = a(4:6)
    t(:, 3) = a(7:9)
  end function as_3x3

  pure real(wp) function det3(a)
    real(wp), intent(in) :: a(3, 3)
    det3 = a(1, 1)*(a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)) - a(1, 2)*(a(2, 1)*a(3, 3) - a(2, 3)*a(3, 1)) &
           + a(1, 3)*(a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1))
  end function det3

end module dpmpm_materials
