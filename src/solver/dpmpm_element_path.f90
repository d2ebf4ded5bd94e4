!> The element test: one material point driven along a laboratory path (isotropic,
!> oedometer, drained and undrained triaxial, drained and undrained simple shear),
!> monotonic or cyclic, under strain or stress control, by the stress update of the
!> simulation itself (dpmpm_materials' stress_update, the same call as in a time step).
!>
!> Axes: z is the axial (vertical) direction, x and y the radial ones; simple shear is
!> gamma_xz. Stress and strain are tension positive in Voigt order xx yy zz yz xz xy
!> (engineering shears), as everywhere in dpmpm; the soil-mechanics quantities written
!> beside them are compression positive: p' = -tr(sigma)/3, q = sigma'_a - sigma'_r =
!> (sigma_xx + sigma_yy)/2 - sigma_zz, eps_a = -eps_zz, eps_v = -tr(eps).
!>
!> Each step prescribes a strain increment of the form deps = dir dx + B u: dx is the
!> step of the driven strain (strain control; 0 under stress control) and u the nu <= 2
!> unknown strains (the triaxial and isotropic paths are axisymmetric: x and y strain
!> alike, which keeps the one solution of a perfectly plastic Mohr-Coulomb edge, where the
!> split of the radial strain between x and y would be free), found by Newton's method
!> (Jacobian by forward differences of the model's response, a halving line search) so
!> that nu stress conditions hold: the constant cell pressure of a drained triaxial test,
!> the constant vertical stress of drained simple shear, the constant deviator of an
!> isotropic test, the target q, p', sigma'_a or tau of stress control. Undrained means
!> constant volume of the skeleton (the pore water incompressible against it):
!> tr(deps) = 0, eps_r = -eps_a/2 in triaxial, no normal strain in simple shear. Plane
!> strain undrained: no strain along y, eps_x = -eps_a; its deviator (the q of stress
!> control and of the deviator target) is sigma'_a - sigma'_x, and the pore pressure the
!> change of sigma'_x at a constant total sigma_x.
!> A step that does not converge stops the path and is reported (element_history_t).
module dpmpm_element_path
  use dpmpm_kinds, only: wp
  use dpmpm_element_config, only: element_cfg_t, path_isotropic, path_oedometer, &
                                  path_triaxial_drained, path_triaxial_undrained, &
                                  path_simple_shear_drained, path_simple_shear_undrained, &
                                  path_plane_strain_undrained, path_from_name, target_of, &
                                  initial_effective_stress
  use dpmpm_materials, only: material_t, stress_update, init_state, point_moduli
  use dpmpm_model_table, only: model_table
  use dpmpm_strings, only: itoa
  implicit none
  private
  public :: element_history_t, run_element, set_initial_state
  public :: is_undrained, element_ok, element_inadmissible, element_not_converged

  !> Outcome of run_element: the whole path done, the initial stress not admissible for
  !> the model (an input problem), or a step that did not converge (the path stopped there).
  integer, parameter :: element_ok = 0, element_inadmissible = 1, element_not_converged = 2

  !> Largest number of unknown strains of a step.
  integer, parameter :: max_unknowns = 2

  !> The records of an element test: record 0 is the initial state, record k the state
  !> after step k; nrec = steps done + 1. Compression-positive quantities as described
  !> in the module's header; excess_pore_pressure only for undrained paths (0 otherwise),
  !> void_ratio only with an initial void ratio (0 otherwise).
  type :: element_history_t
    integer :: status = element_ok
    integer :: nrec = 0
    integer :: nplanned = 0               !< steps of the whole path
    character(len=:), allocatable :: message  !< what went wrong (status /= element_ok)
    real(wp), allocatable :: time(:)      !< s
    real(wp), allocatable :: cycle(:)     !< cycles done (fraction), 0 for a monotonic path
    real(wp), allocatable :: strain(:, :) !< (6, nrec) sum of the strain increments
    real(wp), allocatable :: stress(:, :) !< (6, nrec) effective stress (Pa)
    real(wp), allocatable :: state(:, :)  !< (nstate, nrec) the model's state values
    real(wp), allocatable :: volume_ratio(:) !< V / V0 as the model integrates it
    real(wp), allocatable :: p(:), q(:), axial_strain(:), volumetric_strain(:)
    real(wp), allocatable :: shear_strain(:), shear_stress(:) !< gamma_xz, tau = sigma_xz
    real(wp), allocatable :: excess_pore_pressure(:), void_ratio(:)
    integer, allocatable :: iterations(:) !< Newton iterations of each step (0 at record 0)
    real(wp), allocatable :: residual(:)  !< |stress conditions| / stress scale at the end
  end type element_history_t

contains

  !> True for the paths at constant volume (undrained), which have an excess pore pressure.
  pure logical function is_undrained(path)
    integer, intent(in) :: path
    is_undrained = path == path_triaxial_undrained .or. path == path_simple_shear_undrained .or. &
                   path == path_plane_strain_undrained
  end function is_undrained

  !> The initial state values of a point of material mat at the initial effective stress
  !> stress: THE place where a model whose state depends on the initial stress (a
  !> preconsolidation pressure, a void ratio) gets it. The models of dpmpm_model_table
  !> so far start from zero state (the plastic strain of mohr_coulomb and drucker_prager).
  subroutine set_initial_state(mat, stress, state)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: stress(6)
    real(wp), intent(out) :: state(:)
    real(wp) :: s(6, 1), st(size(state), 1)
    s(:, 1) = stress
    st = 0.0_wp
    if (size(state) > 0) call init_state(mat, 1, 1, [1], s, st)
    state = st(:, 1)
  end subroutine set_initial_state

  !> Run the element test cfg of material mat (material index 1 of stress_update) into
  !> hist. hist%status tells the outcome; the records up to the last converged step are
  !> kept in every case.
  subroutine run_element(cfg, mat, hist)
    type(element_cfg_t), intent(in) :: cfg
    type(material_t), intent(in) :: mat
    type(element_history_t), intent(out) :: hist
    integer :: path, ns, nu, nsteps, k, it, steps
    real(wp) :: sig0(6), sig(6), eps(6), vol, defgrad(9), scale, dir(6), bmat(6, max_unknowns)
    real(wp) :: x, xprev, y, y0, u(max_unknowns), uprev(max_unknowns), deps(6), res, s1(6)
    real(wp), allocatable :: st(:), st1(:)
    logical :: strain_control, cyclic, ok
    real(wp) :: vol1, f1(9)

    path = path_from_name(cfg%path)
    strain_control = trim(cfg%control) == 'strain'
    cyclic = cfg%cycles > 0
    steps = cfg%steps
    nsteps = steps
    if (cyclic) nsteps = steps*cfg%cycles
    ns = mat%nstate
    allocate (st(ns), st1(ns))
    sig0 = initial_effective_stress(cfg)
    sig = sig0
    eps = 0.0_wp
    vol = 1.0_wp
    defgrad = [1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp]
    ! the model's state values at the initial stress: set_initial_state, the one place
    call set_initial_state(mat, sig0, st)
    call plan(path, strain_control, dir, bmat, nu)
    y0 = stress_measure(path, sig0)
    scale = max(maxval(abs(sig0)), abs(cfg%amplitude), 1.0_wp)
    if (.not. strain_control .and. .not. cyclic) &
      scale = max(scale, abs(target_value(cfg, path)))
    call allocate_history(hist, nsteps, ns, cfg%void_ratio > 0.0_wp)
    hist%nplanned = nsteps
    call record(hist, cfg, path, 0, 0.0_wp, 0.0_wp, eps, sig, sig0, st, vol, 0, 0.0_wp)

    ! The initial stress must be a state of the model: a step without strain keeps it.
    s1 = sig
    st1 = st
    vol1 = vol
    f1 = defgrad
    call update(mat, cfg%dt, [(0.0_wp, k=1, 6)], s1, vol1, f1, st1)
    if (maxval(abs(s1 - sig)) > 1.0e-9_wp*scale) then
      hist%status = element_inadmissible
      hist%message = 'the initial stress is not a state of model '''// &
                     trim(model_table(mat%model)%name)//''': a step without strain moves it by '// &
                     num(maxval(abs(s1 - sig)))// &
                     ' Pa (outside the yield surface, or a model that computes its stress '// &
                     'from the deformation alone)'
      return
    end if

    xprev = 0.0_wp
    uprev = 0.0_wp
    do k = 1, nsteps
      ! the driven strain (strain control) or the target stress (stress control)
      x = 0.0_wp
      y = y0
      if (strain_control) then
        x = driven(cfg, path, k)
      else
        y = stress_target(cfg, path, k, y0)
      end if
      ! first guess: the unknowns of the step before
      u = uprev
      call solve_step(mat, cfg, path, dir*(x - xprev), bmat, nu, sig, sig0, st, vol, defgrad, &
                      y, scale, u, deps, it, res, ok)
      if (.not. ok) then
        hist%status = element_not_converged
        hist%message = 'step '//itoa(k)//' of '//itoa(nsteps)//' did not converge in '// &
                       itoa(cfg%max_iterations)//' iterations: the stress conditions are off by '// &
                       num(res)//' of the stress scale '//num(scale)//' Pa (tolerance '// &
                       num(cfg%tolerance)//')'
        if (.not. strain_control) hist%message = hist%message//'; a stress target beyond '// &
                                                 'the strength of the material has no strain '// &
                                                 'that reaches it'
        return
      end if
      call update(mat, cfg%dt, deps, sig, vol, defgrad, st)
      eps = eps + deps
      uprev = u
      xprev = x
      call record(hist, cfg, path, k, k*cfg%dt, merge(real(k, wp)/steps, 0.0_wp, cyclic), &
                  eps, sig, sig0, st, vol, it, res)
    end do
  end subroutine run_element

  !> The strain directions of a step: deps = dir dx + bmat(:, 1:nu) u, with dx the step of
  !> the driven strain (eps_a or eps_v compression positive, gamma_xz) under strain control,
  !> and the nu unknowns of the stress conditions (stress_conditions).
  pure subroutine plan(path, strain_control, dir, bmat, nu)
    integer, intent(in) :: path
    logical, intent(in) :: strain_control
    real(wp), intent(out) :: dir(6), bmat(6, max_unknowns)
    integer, intent(out) :: nu
    real(wp), parameter :: e(6, 6) = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
                                              0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
                                              0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
                                              0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, &
                                              0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, &
                                              0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [6, 6])
    ! an equal strain of x and y (the radial strain of an axisymmetric test), and the
    ! volume-free split of radial against axial strain
    real(wp), parameter :: radial(6) = [1.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    real(wp), parameter :: split_ra(6) = [0.5_wp, 0.5_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    ! the volume-free split of x against z strain with none along y (plane strain)
    real(wp), parameter :: split_xz(6) = [1.0_wp, 0.0_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    dir = 0.0_wp
    bmat = 0.0_wp
    nu = 0
    select case (path)
    case (path_isotropic)
      if (strain_control) then
        ! eps_v driven, q held by the volume-free split of radial and axial strain
        dir(1:3) = -1.0_wp/3.0_wp
        nu = 1
        bmat(:, 1) = split_ra
      else
        nu = 2
        bmat(:, 1) = radial
        bmat(:, 2) = e(:, 3)
      end if
    case (path_oedometer)
      if (strain_control) then
        dir(3) = -1.0_wp
      else
        nu = 1
        bmat(:, 1) = e(:, 3)
      end if
    case (path_triaxial_drained)
      nu = 1
      bmat(:, 1) = radial
      if (strain_control) then
        dir(3) = -1.0_wp
      else
        nu = 2
        bmat(:, 2) = e(:, 3)
      end if
    case (path_triaxial_undrained)
      if (strain_control) then
        ! eps_r = -eps_a / 2
        dir = split_ra
      else
        nu = 1
        bmat(:, 1) = -split_ra
      end if
    case (path_plane_strain_undrained)
      if (strain_control) then
        ! eps_x = -eps_a, eps_y = 0
        dir = split_xz
      else
        nu = 1
        bmat(:, 1) = -split_xz
      end if
    case (path_simple_shear_drained)
      nu = 1
      bmat(:, 1) = e(:, 3)
      if (strain_control) then
        dir(5) = 1.0_wp
      else
        nu = 2
        bmat(:, 2) = e(:, 5)
      end if
    case (path_simple_shear_undrained)
      if (strain_control) then
        dir(5) = 1.0_wp
      else
        nu = 1
        bmat(:, 1) = e(:, 5)
      end if
    end select
  end subroutine plan

  !> The nu stress conditions of a step at stress s (initial stress s0, stress target y),
  !> zero when they hold: the initial values of the stresses the path holds, and y for
  !> the measure of stress control (stress_measure).
  pure function stress_conditions(path, strain_control, s, s0, y, nu) result(r)
    integer, intent(in) :: path, nu
    logical, intent(in) :: strain_control
    real(wp), intent(in) :: s(6), s0(6), y
    real(wp) :: r(nu), pdiff
    select case (path)
    case (path_isotropic)
      if (strain_control) then
        r(1) = qdev(s) - qdev(s0)
      else
        ! every normal stress changed by the change of p'
        pdiff = y - pmean(s0)
        r(1) = prad(s) - (prad(s0) + pdiff)
        r(2) = -s(3) - (-s0(3) + pdiff)
      end if
    case (path_oedometer)
      if (.not. strain_control) r(1) = -s(3) - y
    case (path_triaxial_drained)
      r(1) = prad(s) - prad(s0)
      if (.not. strain_control) r(2) = qdev(s) - y
    case (path_triaxial_undrained)
      if (.not. strain_control) r(1) = qdev(s) - y
    case (path_plane_strain_undrained)
      if (.not. strain_control) r(1) = qplane(s) - y
    case (path_simple_shear_drained)
      r(1) = s(3) - s0(3)
      if (.not. strain_control) r(2) = s(5) - y
    case (path_simple_shear_undrained)
      if (.not. strain_control) r(1) = s(5) - y
    end select
  end function stress_conditions

  !> The measure of stress that stress control drives: p' (isotropic), sigma'_a
  !> (oedometer), q (triaxial), tau = sigma_xz (simple shear).
  pure real(wp) function stress_measure(path, s) result(y)
    integer, intent(in) :: path
    real(wp), intent(in) :: s(6)
    select case (path)
    case (path_isotropic)
      y = pmean(s)
    case (path_oedometer)
      y = -s(3)
    case (path_triaxial_drained, path_triaxial_undrained)
      y = qdev(s)
    case (path_plane_strain_undrained)
      y = qplane(s)
    case default
      y = s(5)
    end select
  end function stress_measure

  !> The target of a monotonic path (the &element variable target_of names).
  pure real(wp) function target_value(cfg, path) result(t)
    type(element_cfg_t), intent(in) :: cfg
    integer, intent(in) :: path
    select case (target_of(path, cfg%control))
    case (1)
      t = cfg%axial_strain
    case (2)
      t = cfg%volumetric_strain
    case (3)
      t = cfg%shear_strain
    case (4)
      t = cfg%deviator
    case (5)
      t = cfg%mean_stress
    case (6)
      t = cfg%axial_stress
    case default
      t = cfg%shear_stress
    end select
  end function target_value

  !> The driven strain after step k under strain control: eps_a or eps_v (compression
  !> positive; extension negative) or gamma_xz, along a straight line to the target, or
  !> around zero with the amplitude along a cyclic path.
  pure real(wp) function driven(cfg, path, k) result(x)
    type(element_cfg_t), intent(in) :: cfg
    integer, intent(in) :: path, k
    real(wp) :: sgn
    sgn = merge(-1.0_wp, 1.0_wp, trim(cfg%sense) == 'extension')
    if (cfg%cycles > 0) then
      x = sgn*cfg%amplitude*wave(real(k, wp)/cfg%steps)
    else
      x = sgn*target_value(cfg, path)*real(k, wp)/cfg%steps
    end if
  end function driven

  !> The target stress measure after step k under stress control: from its initial value
  !> y0 along a straight line to the target value, or around y0 with the amplitude along
  !> a cyclic path (compression, or a positive tau, first).
  pure real(wp) function stress_target(cfg, path, k, y0) result(y)
    type(element_cfg_t), intent(in) :: cfg
    integer, intent(in) :: path, k
    real(wp), intent(in) :: y0
    real(wp) :: sgn
    sgn = merge(-1.0_wp, 1.0_wp, trim(cfg%sense) == 'extension')
    if (cfg%cycles > 0) then
      y = y0 + sgn*cfg%amplitude*wave(real(k, wp)/cfg%steps)
    else
      y = y0 + (target_value(cfg, path) - y0)*real(k, wp)/cfg%steps
    end if
  end function stress_target

  !> One cycle of a triangular wave at t cycles: 0 -> 1 -> 0 -> -1 -> 0 over each cycle
  !> (its peaks at quarters, which the steps of a cycle, a multiple of 4, fall on).
  pure real(wp) function wave(t) result(w)
    real(wp), intent(in) :: t
    real(wp) :: f
    f = t - aint(t)
    if (f <= 0.25_wp) then
      w = 4.0_wp*f
    else if (f <= 0.75_wp) then
      w = 2.0_wp - 4.0_wp*f
    else
      w = 4.0_wp*f - 4.0_wp
    end if
  end function wave

  !> Newton's method on the nu unknowns u of one step (deps = dknown + bmat u) from the
  !> state (s, state, vol, defgrad), until every stress condition is within
  !> cfg%tolerance * scale. On return deps is the step's strain increment, it the
  !> iterations taken, res the largest condition over scale, ok whether it converged.
  subroutine solve_step(mat, cfg, path, dknown, bmat, nu, s, s0, state, vol, defgrad, y, &
                        scale, u, deps, it, res, ok)
    type(material_t), intent(in) :: mat
    type(element_cfg_t), intent(in) :: cfg
    integer, intent(in) :: path, nu
    real(wp), intent(in) :: dknown(6), bmat(6, max_unknowns), s(6), s0(6), state(:), vol
    real(wp), intent(in) :: defgrad(9), y, scale
    real(wp), intent(inout) :: u(max_unknowns)
    real(wp), intent(out) :: deps(6), res
    integer, intent(out) :: it
    logical, intent(out) :: ok
    real(wp) :: r(max_unknowns), rt(max_unknowns), jac(max_unknowns, max_unknowns)
    real(wp) :: du(max_unknowns), ut(max_unknowns), h, lam, href, rnorm, tnorm, pw(1)
    integer :: j
    logical :: strain_control
    strain_control = trim(cfg%control) == 'strain'
    it = 0
    ok = .true.
    res = 0.0_wp
    deps = dknown
    if (nu == 0) return
    ! forward-difference steps: small against the strains that change the stress by scale
    ! (the constrained modulus of the point: a model whose stiffness follows the pressure
    ! has its own at this stress)
    call point_moduli([mat], 1, [1], reshape(s, [6, 1]), reshape(state, [size(state), 1]), pw)
    href = 1.0e-8_wp*scale/max(pw(1), 1.0_wp)
    r(1:nu) = conditions_at(u)
    rnorm = maxval(abs(r(1:nu)))
    do
      res = rnorm/scale
      if (rnorm <= cfg%tolerance*scale) exit
      if (it >= cfg%max_iterations) then
        ok = .false.
        exit
      end if
      it = it + 1
      do j = 1, nu
        h = max(href, 1.0e-7_wp*abs(u(j)))
        ut(1:nu) = u(1:nu)
        ut(j) = ut(j) + h
        rt(1:nu) = conditions_at(ut)
        jac(1:nu, j) = (rt(1:nu) - r(1:nu))/h
      end do
      call solve_small(jac(1:nu, 1:nu), -r(1:nu), du(1:nu), ok)
      if (.not. ok) exit
      ! a halving line search: take the first step that lowers the largest condition
      lam = 1.0_wp
      do
        ut(1:nu) = u(1:nu) + lam*du(1:nu)
        rt(1:nu) = conditions_at(ut)
        tnorm = maxval(abs(rt(1:nu)))
        if (tnorm < rnorm .or. lam < 1.0e-3_wp) exit
        lam = 0.5_wp*lam
      end do
      u(1:nu) = ut(1:nu)
      r(1:nu) = rt(1:nu)
      rnorm = tnorm
    end do
    deps = dknown + matmul(bmat(:, 1:nu), u(1:nu))

  contains

    !> The stress conditions after the step with unknowns uu (on copies of the state).
    function conditions_at(uu) result(rr)
      real(wp), intent(in) :: uu(max_unknowns)
      real(wp) :: rr(nu), st(6), stt(size(state)), vt, ft(9)
      st = s
      stt = state
      vt = vol
      ft = defgrad
      call update(mat, cfg%dt, dknown + matmul(bmat(:, 1:nu), uu(1:nu)), st, vt, ft, stt)
      rr = stress_conditions(path, strain_control, st, s0, y, nu)
    end function conditions_at

  end subroutine solve_step

  !> Solve the small system a x = b (n <= max_unknowns) by Gaussian elimination with partial
  !> pivoting; ok false for a singular matrix.
  pure subroutine solve_small(a, b, x, ok)
    real(wp), intent(in) :: a(:, :), b(:)
    real(wp), intent(out) :: x(:)
    logical, intent(out) :: ok
    real(wp) :: m(size(b), size(b) + 1), row(size(b) + 1), f
    integer :: n, i, k, piv
    n = size(b)
    m(:, 1:n) = a
    m(:, n + 1) = b
    ok = .true.
    do k = 1, n
      piv = k - 1 + maxloc(abs(m(k:n, k)), dim=1)
      if (.not. abs(m(piv, k)) > tiny(1.0_wp)*maxval(abs(m(:, 1:n)))) then
        ok = .false.
        x = 0.0_wp
        return
      end if
      if (piv /= k) then
        row = m(k, :)
        m(k, :) = m(piv, :)
        m(piv, :) = row
      end if
      do i = k + 1, n
        f = m(i, k)/m(k, k)
        m(i, k:) = m(i, k:) - f*m(k, k:)
      end do
    end do
    do i = n, 1, -1
      x(i) = (m(i, n + 1) - dot_product(m(i, i + 1:n), x(i + 1:n)))/m(i, i)
    end do
  end subroutine solve_small

  !> One stress update of the point by the strain increment deps over dt: the velocity
  !> gradient is the strain rate deps / dt (symmetric, no spin), as stress_update takes it
  !> from the grid in a time step.
  subroutine update(mat, dt, deps, s, vol, defgrad, state)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt, deps(6)
    real(wp), intent(inout) :: s(6), vol, defgrad(9), state(:)
    real(wp) :: vg(9, 1), sv(6, 1), vv(1), v0(1), fv(9, 1), stv(size(state), 1)
    integer :: pmat(1)
    ! column-major 3x3: (1,1) (2,1) (3,1) (1,2) (2,2) (3,2) (1,3) (2,3) (3,3), half shears
    vg(:, 1) = [deps(1), 0.5_wp*deps(6), 0.5_wp*deps(5), 0.5_wp*deps(6), deps(2), &
                0.5_wp*deps(4), 0.5_wp*deps(5), 0.5_wp*deps(4), deps(3)]/dt
    sv(:, 1) = s
    vv(1) = vol
    v0(1) = 1.0_wp
    fv(:, 1) = defgrad
    stv(:, 1) = state
    pmat(1) = 1
    call stress_update(mat, 1, dt, 1, pmat, vg, sv, vv, v0, fv, stv, plane=.false.)
    s = sv(:, 1)
    vol = vv(1)
    defgrad = fv(:, 1)
    state = stv(:, 1)
  end subroutine update

  !> Allocate the records of a path of nsteps steps and ns state values.
  subroutine allocate_history(h, nsteps, ns, with_void)
    type(element_history_t), intent(inout) :: h
    integer, intent(in) :: nsteps, ns
    logical, intent(in) :: with_void
    integer :: n
    n = nsteps + 1
    allocate (h%time(n), h%cycle(n), h%strain(6, n), h%stress(6, n), h%state(ns, n), &
              h%volume_ratio(n), h%p(n), h%q(n), h%axial_strain(n), h%volumetric_strain(n), &
              h%shear_strain(n), h%shear_stress(n), h%excess_pore_pressure(n), h%void_ratio(n), &
              h%iterations(n), h%residual(n))
    if (.not. with_void) h%void_ratio = 0.0_wp
  end subroutine allocate_history

  !> Keep record k (after step k) and its derived quantities.
  subroutine record(h, cfg, path, k, t, cyc, eps, s, s0, state, vol, it, res)
    type(element_history_t), intent(inout) :: h
    type(element_cfg_t), intent(in) :: cfg
    integer, intent(in) :: path, k, it
    real(wp), intent(in) :: t, cyc, eps(6), s(6), s0(6), state(:), vol, res
    integer :: i
    i = k + 1
    h%nrec = i
    h%time(i) = t
    h%cycle(i) = cyc
    h%strain(:, i) = eps
    h%stress(:, i) = s
    h%state(:, i) = state
    h%volume_ratio(i) = vol
    h%p(i) = pmean(s)
    h%q(i) = qdev(s)
    if (path == path_plane_strain_undrained) h%q(i) = qplane(s)
    h%axial_strain(i) = -eps(3)
    h%volumetric_strain(i) = -sum(eps(1:3))
    h%shear_strain(i) = eps(5)
    h%shear_stress(i) = s(5)
    h%excess_pore_pressure(i) = 0.0_wp
    ! Undrained at a constant total stress (the cell pressure; the vertical stress of
    ! simple shear): the pore pressure takes what the effective stress lets go of.
    if (path == path_triaxial_undrained) &
      h%excess_pore_pressure(i) = 0.5_wp*(s(1) + s(2)) - 0.5_wp*(s0(1) + s0(2))
    if (path == path_simple_shear_undrained) h%excess_pore_pressure(i) = s(3) - s0(3)
    if (path == path_plane_strain_undrained) h%excess_pore_pressure(i) = s(1) - s0(1)
    ! e from V/V0 = exp(tr eps): the strain is the sum of D dt, so tr eps = ln(V/V0)
    if (cfg%void_ratio > 0.0_wp) h%void_ratio(i) = (1.0_wp + cfg%void_ratio)*exp(sum(eps(1:3))) &
                                                    - 1.0_wp
    h%iterations(i) = it
    h%residual(i) = res
  end subroutine record

  !> p' = -tr(sigma)/3 (compression positive).
  pure real(wp) function pmean(s)
    real(wp), intent(in) :: s(6)
    pmean = -(s(1) + s(2) + s(3))/3.0_wp
  end function pmean

  !> sigma'_r = -(sigma_xx + sigma_yy)/2 (compression positive).
  pure real(wp) function prad(s)
    real(wp), intent(in) :: s(6)
    prad = -0.5_wp*(s(1) + s(2))
  end function prad

  !> q = sigma'_a - sigma'_r (compression positive; radial the mean of x and y).
  pure real(wp) function qdev(s)
    real(wp), intent(in) :: s(6)
    qdev = 0.5_wp*(s(1) + s(2)) - s(3)
  end function qdev

  !> The deviator of plane strain, sigma'_a - sigma'_x = sigma_xx - sigma_zz (compression
  !> positive; y the direction without strain).
  pure real(wp) function qplane(s)
    real(wp), intent(in) :: s(6)
    qplane = s(1) - s(3)
  end function qplane

  !> A real as short text.
  pure function num(x) result(t)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: t
    character(len=24) :: buf
    write (buf, '(es10.3)') x
    t = trim(adjustl(buf))
  end function num

end module dpmpm_element_path
