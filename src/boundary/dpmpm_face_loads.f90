!> Face loads: the nodal forces of the &load tractions and of the prescribed pore
!> pressure of drained faces (the boundary terms of the weak form, paper eq. 5),
!> each ramped in time and shared among the nodes by their grid functions at the
!> face, with the exterior share of a mirror wall given to its image; the
!> dashpots of absorbing faces; and the incoming traction of a compliant base.
module dpmpm_face_loads
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, load_cfg_t, region_cfg_t, table_factor, bc_free, fbc_drained, &
                          fbc_impermeable, motion_series_t
  use dpmpm_motion, only: motion_velocity
  use dpmpm_base_motion, only: compliant_face
  use dpmpm_generate, only: point_in_polygon
  use dpmpm_grid, only: grid_t
  use dpmpm_walls, only: walls_t
  use dpmpm_kernels, only: bspline_1d
  implicit none
  private
  public :: face_loads_t, ramp_factor, load_factor, load_area

  !> The loaded faces of a scene: tractions, pore-fluid conditions and pressures.
  type :: face_loads_t
    type(grid_t) :: grid
    type(walls_t) :: walls                !< the faces' kinds and rough walls
    integer :: nd = 1
    integer :: kernel = 1                 !< grid function (B-spline order)
    type(load_cfg_t), allocatable :: loads(:)
    integer :: fbc(6) = 0                 !< resolved pore-fluid condition per face
    real(wp) :: pore_pressure(6) = 0.0_wp, pore_pressure_ramp(6) = 0.0_wp
    real(wp) :: pore_pressure_gradient(3, 6) = 0.0_wp !< Pa/m along each drained face
    !> Dashpots of absorbing faces, force per area and velocity (Pa s/m): on the skeleton
    !> normal and tangential to the face, on the pore fluid normal to it
    real(wp) :: z_normal(6) = 0.0_wp, z_shear(6) = 0.0_wp, z_fluid(6) = 0.0_wp
    logical :: absorbing = .false.        !< some face absorbs
    logical :: axisym = .false.           !< r-z (&grid axisymmetric): tractions on rings per radian
    !> The compliant base (&motion base on an absorbing face), 0 none: its face, the
    !> motion's histories (the outcrop velocity) and the time they start at
    integer :: inflow = 0
    type(motion_series_t) :: motion(3)
    real(wp) :: motion_start = 0.0_wp
    type(region_cfg_t), allocatable :: regions(:) !< initial states (absorbing faces' static load)
    !> axes whose tied pairs the coupled update takes as one node at the lower face
    !> (join_pairs): there the lower node carries the pair's share of a face's area, the
    !> upper none (edge_share)
    logical :: joined(3) = .false.
  contains
    procedure :: init => face_loads_init
    procedure :: free => face_loads_free
    procedure :: traction => face_traction
    procedure :: pore_pressure_force => face_pore_pressure
    procedure :: pore_pressure_at
    procedure :: fluid_ties
    procedure :: dashpot
    procedure :: incoming
    procedure :: absorbing_static
    procedure :: near_face
    procedure :: inner_nodes
    procedure :: node_volume
  end type face_loads_t

contains

  !> The loads of cfg on grid with the grid functions of kernel; fbc the resolved
  !> pore-fluid condition of each face.
  subroutine face_loads_init(self, cfg, grid, kernel, fbc)
    class(face_loads_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: grid
    integer, intent(in) :: kernel, fbc(6)
    self%grid = grid
    call self%walls%init(cfg)
    self%nd = cfg%ndim
    self%kernel = kernel
    if (allocated(cfg%loads)) then
      self%loads = cfg%loads
    else
      allocate (self%loads(0))
    end if
    self%fbc = fbc
    self%pore_pressure = cfg%pore_pressure
    self%pore_pressure_ramp = cfg%pore_pressure_ramp
    self%pore_pressure_gradient = cfg%pore_pressure_gradient
    call absorbing_impedances(self, cfg)
    self%axisym = cfg%axisymmetric
    self%inflow = compliant_face(cfg)
    if (self%inflow > 0) then
      self%motion = cfg%motion
      self%motion_start = cfg%equilibrium_time
    end if
  end subroutine face_loads_init

  !> Dashpot coefficients of the absorbing faces (doc/theory.md 6.6), matched to a plane
  !> wave of the face's material leaving the body normally: with the constrained modulus
  !> E_c, shear modulus G, porosity n and pore-fluid modulus K_f of its first region (n = 0
  !> for a dry body), the mixture density rho and the undrained speed c = sqrt((E_c +
  !> K_f/n)/rho), a wave with both phases moving at v carries sigma' = -E_c v/c and p =
  !> K_f v/(n c); the skeleton takes sigma' and its share (1 - n) of p, the pore fluid its
  !> share n of p, so that z_normal = E_c/c + (1 - n) K_f/(n c), z_fluid = K_f/c, and the
  !> sum is rho c. Shear: z_shear = sqrt(G rho). A fluid material: z_fluid = z_normal =
  !> sqrt(K_f rho_f), no shear.
  subroutine absorbing_impedances(self, cfg)
    class(face_loads_t), intent(inout) :: self
    type(config_t), intent(in) :: cfg
    integer :: f, m, r, mf
    real(wp) :: e, nu, ec, g, n, kf, rhof, rho, c
    self%z_normal = 0.0_wp
    self%z_shear = 0.0_wp
    self%z_fluid = 0.0_wp
    self%absorbing = any(cfg%absorbing(1:2*cfg%ndim) /= 0)
    if (self%absorbing) self%regions = cfg%regions
    do f = 1, 2*cfg%ndim
      if (cfg%absorbing(f) == 0) cycle
      m = findloc(cfg%materials%id, cfg%absorbing(f), dim=1)
      associate (mat => cfg%materials(m))
        if (mat%model == 'fluid') then
          ! Free water: the points of a one-phase scene are its only set.
          self%z_fluid(f) = sqrt(mat%bulk_modulus*mat%density)
          self%z_normal(f) = self%z_fluid(f)
          cycle
        end if
        e = mat%youngs_modulus
        nu = mat%poisson_ratio
        ec = e*(1.0_wp - nu)/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
        g = e/(2.0_wp*(1.0_wp + nu))
        n = 0.0_wp; kf = 0.0_wp; rhof = 0.0_wp
        do r = 1, size(cfg%regions)
          if (cfg%regions(r)%material /= cfg%absorbing(f)) cycle
          if (cfg%regions(r)%phase == 'saturated') then
            mf = findloc(cfg%materials%id, cfg%regions(r)%fluid_material, dim=1)
            n = cfg%regions(r)%porosity
            kf = cfg%materials(mf)%bulk_modulus
            rhof = cfg%materials(mf)%density
          end if
          exit
        end do
        rho = (1.0_wp - n)*mat%density + n*rhof
        if (n > 0.0_wp) then
          c = sqrt((ec + kf/n)/rho)
          self%z_normal(f) = ec/c + (1.0_wp - n)*kf/(n*c)
          self%z_fluid(f) = kf/c
        else
          self%z_normal(f) = sqrt(ec*rho)
        end if
        self%z_shear(f) = sqrt(g*rho)
      end associate
    end do
  end subroutine absorbing_impedances

  !> Dashpot coefficients (force per velocity, per component) of node idx on the
  !> skeleton (fluid = .false.) or the pore fluid: the face impedances times the node's
  !> share of the face area (face_weight, face_area); zero away from absorbing faces.
  function dashpot(self, idx, fluid, only) result(cd)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    logical, intent(in) :: fluid
    integer, intent(in), optional :: only   !< this face's dashpots alone
    real(wp) :: cd(3), w, zn, zt
    integer :: f, d
    cd = 0.0_wp
    if (.not. self%absorbing) return
    do f = 1, 2*self%nd
      if (present(only)) then
        if (f /= only) cycle
      end if
      zn = merge(self%z_fluid(f), self%z_normal(f), fluid)
      zt = merge(0.0_wp, self%z_shear(f), fluid)
      if (zn == 0.0_wp .and. zt == 0.0_wp) cycle
      w = face_weight(self, idx, f, self%walls%bc)
      if (w == 0.0_wp) cycle
      d = (f + 1)/2
      w = w*face_area(self, idx, d)
      cd(1:self%nd) = cd(1:self%nd) + w*zt
      cd(d) = cd(d) + w*(zn - zt)
    end do
  end function dashpot

  !> The incoming force of the compliant base on the skeleton at node idx at time t: the
  !> base face's dashpots at the outcrop velocity, c_base v_out(t) (Joyner & Chen 1975; the
  !> dashpots themselves, -c v, act with the other absorbing faces'); zero away from the
  !> base and before the motion's start (the end of the equilibrium phase).
  function incoming(self, t, idx) result(fin)
    class(face_loads_t), intent(in) :: self
    real(wp), intent(in) :: t
    integer, intent(in) :: idx(3)
    real(wp) :: fin(3), cb(3)
    integer :: d
    fin = 0.0_wp
    if (self%inflow == 0 .or. t < self%motion_start) return
    cb = dashpot(self, idx, .false., self%inflow)
    if (all(cb == 0.0_wp)) return
    do d = 1, self%nd
      fin(d) = cb(d)*motion_velocity(self%motion(d), t - self%motion_start)
    end do
  end function incoming

  !> Release what init made; the faces carry no load afterwards.
  subroutine face_loads_free(self)
    class(face_loads_t), intent(inout) :: self
    if (allocated(self%loads)) deallocate (self%loads)
    self%fbc = 0
    self%joined = .false.
    self%pore_pressure = 0.0_wp
    self%pore_pressure_ramp = 0.0_wp
    self%z_normal = 0.0_wp
    self%z_shear = 0.0_wp
    self%z_fluid = 0.0_wp
    self%absorbing = .false.
    if (allocated(self%regions)) deallocate (self%regions)
  end subroutine face_loads_free

  !> Nodal force of the &load tractions at node idx (zero away from the loaded
  !> faces): the traction, ramped over its ramp time, times the node's share of
  !> the face area.
  function face_traction(self, time, idx) result(fext)
    class(face_loads_t), intent(in) :: self
    real(wp), intent(in) :: time
    integer, intent(in) :: idx(3)
    real(wp) :: fext(3)
    integer :: l, f
    real(wp) :: w
    fext = 0.0_wp
    do l = 1, size(self%loads)
      if (self%loads(l)%surface) cycle     ! on the body's surface: surface_forces
      f = self%loads(l)%face
      w = face_weight(self, idx, f, self%walls%bc)
      if (w == 0.0_wp) cycle
      fext(1:self%nd) = fext(1:self%nd) + w*load_factor(self%loads(l), time)* &
                        load_area(self, idx, self%loads(l))*self%loads(l)%traction(1:self%nd)
    end do
  end function face_traction

  !> The factor of load ld at time t: ramp_factor over ramp_time (ramp); sin(2 pi f t)
  !> for t < duration, 0 after (sine; duration 0 = for ever); the table's factors
  !> interpolated linearly in time, the first before its first time and the last after its
  !> last (table).
  real(wp) function load_factor(ld, t) result(r)
    type(load_cfg_t), intent(in) :: ld
    real(wp), intent(in) :: t
    real(wp), parameter :: two_pi = 6.283185307179586476925286766559_wp
    select case (trim(ld%time_function))
    case ('sine')
      r = 0.0_wp
      if (ld%duration <= 0.0_wp .or. t < ld%duration) r = sin(two_pi*ld%frequency*t)
    case ('table')
      r = table_factor(ld%times, ld%factors, t)
    case default
      r = ramp_factor(t, ld%ramp_time)
    end select
  end function load_factor

  !> The share of the face area of load ld that node idx carries: face_area along the
  !> axes of the face where the load covers the whole face; along an axis where it acts
  !> on lo..hi only, h times the integral of the node's grid function over lo..hi (within
  !> the grid), so that a uniform traction on part of a face gives its exact resultant.
  !> Axisymmetry: the ring's face area per radian (ring_area).
  real(wp) function load_area(self, idx, ld) result(a)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    type(load_cfg_t), intent(in) :: ld
    if (self%axisym) then
      a = ring_area(self, idx, ld)
    else
      a = plane_area(self, idx, ld)
    end if
  end function load_area

  !> The plane share of load_area.
  real(wp) function plane_area(self, idx, ld) result(a)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    type(load_cfg_t), intent(in) :: ld
    integer :: t, d
    real(wp) :: lo, hi, xi, share
    d = (ld%face + 1)/2
    if (all(ld%hi(1:self%nd) <= ld%lo(1:self%nd) .or. [(t == d, t=1, self%nd)])) then
      a = face_area(self, idx, d)
      return
    end if
    a = 1.0_wp
    do t = 1, self%nd
      if (t == d) cycle
      if (ld%hi(t) > ld%lo(t)) then
        lo = max(ld%lo(t), self%grid%origin(t))
        hi = min(ld%hi(t), self%grid%origin(t) + real(self%grid%ncells(t), wp)*self%grid%h(t))
        xi = self%grid%origin(t) + real(idx(t), wp)*self%grid%h(t)
        share = kernel_integral(self%kernel, (lo - xi)/self%grid%h(t), (hi - xi)/self%grid%h(t))
        if (self%joined(t) .and. idx(t) == self%grid%ncells(t)) then
          share = 0.0_wp
        else if (self%joined(t) .and. idx(t) == 0) then
          ! the pair's node: the upper face's node's share too
          xi = self%grid%origin(t) + real(self%grid%ncells(t), wp)*self%grid%h(t)
          share = share + kernel_integral(self%kernel, (lo - xi)/self%grid%h(t), (hi - xi)/self%grid%h(t))
        end if
        a = a*self%grid%h(t)*share
      else
        a = a*self%grid%h(t)*edge_share(self, idx, t)
      end if
    end do
  end function plane_area

  !> Axisymmetry (doc/theory.md 4.8): node idx's share of load ld's face area per radian,
  !> the integral of its function along the face times r. On a face of constant r (x-, x+)
  !> r is the face's, and the share is the plane one (plane_area) times the node's r. On a
  !> face of constant z (y-, y+) the share is the integral of N_I(r) r dr along the face:
  !> over the whole face with the linear hats of the plane share (h r_I inside, h (r_I/2 +
  !> h/6) at the face's first node, h (r_I/2 - h/6) at its last: h^2/6 on the axis, where
  !> r_I times the plane share is 0); over lo..hi with the node's grid function (Gauss
  !> points, exact). The shares sum to the ring's area per radian, (r_hi^2 - r_lo^2)/2.
  real(wp) function ring_area(self, idx, ld) result(a)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    type(load_cfg_t), intent(in) :: ld
    real(wp) :: h, ri, lo, hi
    integer :: n
    h = self%grid%h(1)
    n = self%grid%ncells(1)
    ri = self%grid%origin(1) + real(idx(1), wp)*h
    if ((ld%face + 1)/2 == 1) then
      a = plane_area(self, idx, ld)*max(0.0_wp, ri)
      return
    end if
    a = 0.0_wp
    if (idx(1) < 0 .or. idx(1) > n) return
    if (ld%hi(1) > ld%lo(1)) then
      lo = max(ld%lo(1), self%grid%origin(1))
      hi = min(ld%hi(1), self%grid%origin(1) + real(n, wp)*h)
      a = h*h*kernel_integral(self%kernel, (lo - ri)/h, (hi - ri)/h, ri/h)
    else
      if (idx(1) > 0) a = a + h*(0.5_wp*ri - h/6.0_wp)
      if (idx(1) < n) a = a + h*(0.5_wp*ri + h/6.0_wp)
    end if
  end function ring_area

  !> The integral of the 1D B-spline grid function of kernel over a..b (cell units), or
  !> with c given of the function times (c + x), its first moment about -c: three Gauss
  !> points on each piece between the half-integers (exact for the cubic pieces times a
  !> line); 0 where b <= a.
  real(wp) function kernel_integral(kernel, a, b, c) result(s)
    integer, intent(in) :: kernel
    real(wp), intent(in) :: a, b
    real(wp), intent(in), optional :: c
    real(wp), parameter :: gx(3) = [-0.774596669241483377035853079956_wp, 0.0_wp, &
                                    0.774596669241483377035853079956_wp]
    real(wp), parameter :: gw(3) = [5.0_wp/9.0_wp, 8.0_wp/9.0_wp, 5.0_wp/9.0_wp]
    real(wp) :: x0, x1, w(3), dw(3)
    s = 0.0_wp
    x0 = max(a, -2.0_wp)
    do while (x0 < min(b, 2.0_wp))
      x1 = min(b, 2.0_wp, (floor(2.0_wp*x0 + 1.0e-12_wp) + 1)*0.5_wp)
      call bspline_1d(kernel, 0.5_wp*(x0 + x1) + 0.5_wp*(x1 - x0)*gx, w, dw)
      if (present(c)) w = w*(c + 0.5_wp*(x0 + x1) + 0.5_wp*(x1 - x0)*gx)
      s = s + 0.5_wp*(x1 - x0)*sum(gw*w)
      x0 = x1
    end do
  end function kernel_integral

  !> The volume of node idx's grid function inside the grid, the integral of N_I over
  !> the grid's box: h^d inside, less at the faces and for the nodes beyond them.
  real(wp) function node_volume(self, idx) result(v)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    integer :: t
    v = 1.0_wp
    do t = 1, self%nd
      v = v*self%grid%h(t)*kernel_integral(self%kernel, real(-idx(t), wp), real(self%grid%ncells(t) - idx(t), wp))
    end do
  end function node_volume

  !> Nodal force of the prescribed pore pressure p_b of drained faces at node idx
  !> (ramped over pore_pressure_ramp), per unit porosity: A p_b n_out, shared with
  !> the face conditions bc of the phase that takes it (face_weight). The solid
  !> takes n_f times it, the fluid minus n_f times it (the split of the total
  !> traction of the weak form, paper eq. 5).
  function face_pore_pressure(self, time, idx, bc) result(fp)
    class(face_loads_t), intent(in) :: self
    real(wp), intent(in) :: time
    integer, intent(in) :: idx(3), bc(6)
    real(wp) :: fp(3), w, x(3)
    integer :: f, d
    fp = 0.0_wp
    do f = 1, 2*self%nd
      if (self%fbc(f) /= fbc_drained .or. self%pore_pressure(f) == 0.0_wp) cycle
      w = face_weight(self, idx, f, bc)
      if (w == 0.0_wp) cycle
      d = (f + 1)/2
      x = 0.0_wp
      x(1:self%nd) = self%grid%origin(1:self%nd) + real(idx(1:self%nd), wp)*self%grid%h(1:self%nd)
      fp(d) = fp(d) + w*merge(-1.0_wp, 1.0_wp, mod(f, 2) == 1)*face_area(self, idx, d)* &
              self%pore_pressure_at(time, f, x)
    end do
  end function face_pore_pressure

  !> Prescribed pore pressure of drained face f at the point x at time t: pore_pressure
  !> (plus pore_pressure_gradient . x, not below 0, where a gradient is given), ramped.
  pure real(wp) function pore_pressure_at(self, time, f, x) result(p)
    class(face_loads_t), intent(in) :: self
    real(wp), intent(in) :: time, x(3)
    integer, intent(in) :: f
    p = self%pore_pressure(f)
    if (any(self%pore_pressure_gradient(:, f) /= 0.0_wp)) &
      p = max(0.0_wp, p + dot_product(self%pore_pressure_gradient(:, f), x))
    p = p*ramp_factor(time, self%pore_pressure_ramp(f))
  end function pore_pressure_at

  !> Static load of the absorbing faces at node idx on the skeleton (fluid = .false.) or
  !> the pore fluid: the initial state of the body at the face, which the dashpots cannot
  !> carry, as a constant traction (doc/theory.md 6.6). At the node's point on the face
  !> the first &region that holds it gives the effective stress sigma' and, when
  !> saturated, the pore pressure p and porosity n (stress, stress_gradient, pore_pressure,
  !> pore_pressure_gradient); with the outward normal e the skeleton takes (sigma' e -
  !> (1 - n) p e) A and the fluid -n p e A (A the node's share of the face area).
  function absorbing_static(self, idx, fluid) result(fs)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    logical, intent(in) :: fluid
    real(wp) :: fs(3), w, x(3), sg, sig(6), p, n
    integer :: f, d, r, k
    integer, parameter :: col(3, 3) = reshape([1, 6, 5, 6, 2, 4, 5, 4, 3], [3, 3])
    fs = 0.0_wp
    if (.not. self%absorbing) return
    do f = 1, 2*self%nd
      if (self%z_normal(f) == 0.0_wp .and. self%z_fluid(f) == 0.0_wp) cycle
      w = face_weight(self, idx, f, self%walls%bc)
      if (w == 0.0_wp) cycle
      d = (f + 1)/2
      sg = merge(-1.0_wp, 1.0_wp, mod(f, 2) == 1)
      x = 0.0_wp
      x(1:self%nd) = self%grid%origin(1:self%nd) + real(idx(1:self%nd), wp)*self%grid%h(1:self%nd)
      ! On the face, a hair inside the body.
      x(d) = self%grid%origin(d) + merge(0.0_wp, real(self%grid%ncells(d), wp), sg < 0.0_wp)* &
             self%grid%h(d) - sg*1.0e-9_wp*self%grid%h(d)
      r = region_at(self, x)
      if (r == 0) cycle
      associate (reg => self%regions(r))
        sig = reg%stress
        do k = 1, 3
          sig = sig + reg%stress_gradient(:, k)*x(k)
        end do
        n = 0.0_wp
        p = 0.0_wp
        if (reg%phase == 'saturated') then
          n = reg%porosity
          p = reg%pore_pressure + dot_product(reg%pore_pressure_gradient, x)
        end if
      end associate
      w = w*face_area(self, idx, d)
      if (fluid) then
        fs(d) = fs(d) - w*n*p*sg
      else
        fs(1:self%nd) = fs(1:self%nd) + w*sg*sig(col(1:self%nd, d))
        fs(d) = fs(d) - w*(1.0_wp - n)*p*sg
      end if
    end do
  end function absorbing_static

  !> The first region that holds x (boxes with their faces, polygons in 2D); 0 for none.
  integer function region_at(self, x) result(r)
    class(face_loads_t), intent(in) :: self
    real(wp), intent(in) :: x(3)
    integer :: nd
    nd = self%nd
    do r = 1, size(self%regions)
      associate (reg => self%regions(r))
        if (reg%shape == 'polygon') then
          if (point_in_polygon(x(1:2), reg%poly(:, 1:reg%npoly))) return
        else
          if (all(x(1:nd) >= reg%lo(1:nd)) .and. all(x(1:nd) <= reg%hi(1:nd))) return
        end if
      end associate
    end do
    r = 0
  end function region_at

  !> Share of node idx in a load on grid face f: the grid function of the node at
  !> the face, Psi_I(x_face) along the face normal (zero for nodes beyond the grid
  !> along the other axes), so that a uniform face load balances the internal
  !> forces of a uniform stress node by node, as in the weak form; with linear
  !> grid functions only the face nodes carry it. Behind a fixed or roller face
  !> of bc (mirror-folded exterior nodes) the exterior share goes to the mirror
  !> image: the solid's conditions for the solid, fluid_mirror_bc for the fluid,
  !> which is free at a drained face even where the solid is held.
  real(wp) function face_weight(self, idx, f, bc) result(w)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3), f, bc(6)
    integer :: t, d, r
    real(wp) :: dw, wm
    d = (f + 1)/2
    w = 0.0_wp
    do t = 1, self%nd
      if (t /= d .and. (idx(t) < 0 .or. idx(t) > self%grid%ncells(t))) return
    end do
    if (mod(f, 2) == 1) then
      r = idx(d)
    else
      r = self%grid%ncells(d) - idx(d)
    end if
    if (bc(f) /= bc_free) then
      if (r < 0) return
      call bspline_1d(self%kernel, real(r, wp), w, dw)
      if (r > 0) then
        call bspline_1d(self%kernel, real(-r, wp), wm, dw)
        w = w + wm
      end if
    else
      call bspline_1d(self%kernel, real(r, wp), w, dw)
    end if
  end function face_weight

  !> False for a node that no face condition reaches: two or more nodes inside every
  !> face, beyond the support of every grid function's face weight (|r| < 2 cells for
  !> the cubic B-spline) and away from the face nodes that conditions hold. There the
  !> traction, pore-pressure, dashpot and static loads are zero and nothing is held.
  pure logical function near_face(self, idx)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    integer :: ilo(3), ihi(3)
    call self%inner_nodes(ilo, ihi)
    near_face = any(idx < ilo .or. idx > ihi)
  end function near_face

  !> The nodes that no face condition reaches (near_face false): the box ilo..ihi,
  !> unbounded along the unused axes. Node loops test it inline instead of calling
  !> near_face at every node.
  pure subroutine inner_nodes(self, ilo, ihi)
    class(face_loads_t), intent(in) :: self
    integer, intent(out) :: ilo(3), ihi(3)
    call self%grid%interior_nodes(2, ilo, ihi)
  end subroutine inner_nodes

  !> Factor of a load ramped linearly from 0 over t_ramp (1 at once when t_ramp = 0).
  pure real(wp) function ramp_factor(t, t_ramp) result(r)
    real(wp), intent(in) :: t, t_ramp
    r = 1.0_wp
    if (t_ramp > 0.0_wp) r = min(1.0_wp, t/t_ramp)
  end function ramp_factor

  !> The share of a cell's width along axis t of node idx in a face's area: 1 inside, 1/2
  !> at the grid's edges; along an axis of joined tied pairs (joined) 1 at the lower face's
  !> node (the pair's node) and 0 at the upper face's.
  pure real(wp) function edge_share(self, idx, t) result(s)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3), t
    s = 1.0_wp
    if (idx(t) /= 0 .and. idx(t) /= self%grid%ncells(t)) return
    if (self%joined(t)) then
      s = merge(1.0_wp, 0.0_wp, idx(t) == 0)
    else
      s = 0.5_wp
    end if
  end function edge_share

  !> Share of the face area (normal to axis d) that node idx carries.
  real(wp) function face_area(self, idx, d)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3), d
    integer :: t
    face_area = 1.0_wp
    do t = 1, self%nd
      if (t == d) cycle
      face_area = face_area*self%grid%h(t)*edge_share(self, idx, t)
    end do
  end function face_area

  !> Fluid velocity components tied to the solid at node idx: the normal
  !> components at impermeable faces where the solid is free to move.
  function fluid_ties(self, idx) result(tie)
    class(face_loads_t), intent(in) :: self
    integer, intent(in) :: idx(3)
    logical :: tie(3)
    integer :: d, side, f
    tie = .false.
    do d = 1, self%nd
      do side = 1, 2
        f = 2*(d - 1) + side
        if (self%fbc(f) /= fbc_impermeable .or. self%walls%bc(f) /= bc_free) cycle
        if (side == 1 .and. idx(d) <= 0) tie(d) = .true.
        if (side == 2 .and. idx(d) >= self%grid%ncells(d)) tie(d) = .true.
      end do
    end do
  end function fluid_ties

end module dpmpm_face_loads
