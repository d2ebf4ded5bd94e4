!> Checks of the grid's faces and geometry that need the whole configuration: tied faces,
!> openings of fixed and roller faces, and the axisymmetric (r-z) grid with what it refuses.
!> Called by check_config (dpmpm_input_check) once the groups they read are known.
module dpmpm_input_check_faces
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, face_names, bc_roller, bc_free, fbc_drained, fbc_default
  use dpmpm_input_problems, only: input_problems_t, add_raw
  use dpmpm_strings, only: itoa, rtoa, rtoa_list
  implicit none
  private
  public :: check_tied, check_openings, check_axisymmetric

contains

  !> Tied faces (&boundary condition = 'tied'): both faces of an axis, not along the only
  !> axis of a 1D grid, linear grid functions (a wider kernel reaches beyond the faces,
  !> where the ties do not carry it), and no fluid condition or pore pressure of their own.
  subroutine check_tied(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    integer :: f, other
    do f = 1, 2*cfg%ndim
      if (.not. cfg%tied(f)) cycle
      other = merge(f + 1, f - 1, mod(f, 2) == 1)
      if (cfg%ndim == 1) then
        call add_raw(pb, "&boundary face = '"//face_names(f)//"', condition = 'tied': a 1D grid "// &
                     'has no sides to tie (tied faces make a 2D or 3D column move as the 1D one)')
        return
      end if
      if (.not. cfg%tied(other)) call add_raw(pb, "&boundary face = '"//face_names(f)// &
        "', condition = 'tied': face "//face_names(other)//' must be tied too (the nodes of '// &
        'the two faces of an axis move together)')
      if (mod(f, 2) == 1 .and. (cfg%kernel /= 'linear' .or. .not. any(cfg%velocity_kernel == &
          [character(len=6) :: '', 'linear']))) &
        call add_raw(pb, "&boundary face = '"//face_names(f)//"', condition = 'tied' needs "// &
                     "&shape kernel = 'linear' and velocity_kernel '' or 'linear' (wider grid "// &
                     'functions reach beyond the faces, where the ties do not carry them)')
      ! The water of a tied pair is one node with the skeleton's (doc/theory.md 6.9): the face
      ! is neither drained nor impermeable, so a fluid condition or a pore pressure there
      ! would be ignored.
      if (cfg%fluid_bc(f) /= fbc_default) &
        call add_raw(pb, "&boundary face = '"//face_names(f)//"', condition = 'tied' takes no "// &
                     "fluid condition: the pore water of a tied pair flows through the tie as "// &
                     "through the column (neither drained nor impermeable); leave fluid out")
      if (cfg%pore_pressure(f) /= 0.0_wp .or. cfg%pore_pressure_ramp(f) /= 0.0_wp .or. &
          any(cfg%pore_pressure_gradient(:, f) /= 0.0_wp)) &
        call add_raw(pb, "&boundary face = '"//face_names(f)//"', condition = 'tied' takes no "// &
                     'pore_pressure, pore_pressure_ramp or pore_pressure_gradient: a tied face '// &
                     'is not drained (the water of the pair is one node); leave them out')
    end do
  end subroutine check_tied

  !> Openings of faces (&boundary opening_lo, opening_hi): in a fixed or roller face of a
  !> 2D or 3D grid, inside the face, lower corner below the upper one along the face, wide
  !> enough to free a node; linear grid functions with nodal velocities by projection (a
  !> wider kernel, or an MLS weight, reaches the mirror images behind the face, which the
  !> opening would have to leave out); scenes of one phase, not axisymmetric.
  subroutine check_openings(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    character(len=:), allocatable :: head
    integer :: f, d, n
    real(wp) :: lo, hi, h
    do f = 1, 2*cfg%ndim
      if (.not. cfg%has_opening(f)) cycle
      head = "&boundary face = '"//face_names(f)//"', opening_lo = "//rtoa_list(cfg%opening_lo(1:cfg%ndim, f))// &
             ', opening_hi = '//rtoa_list(cfg%opening_hi(1:cfg%ndim, f))//': '
      if (cfg%ndim == 1) then
        call add_raw(pb, head//'a 1D grid''s face is a point and has no opening; leave a '// &
                     "free face (condition = 'free') for the points to leave")
        cycle
      end if
      if (cfg%bc(f) == bc_free) then
        call add_raw(pb, head//"only a fixed or roller face takes an opening (a free, "// &
                     'absorbing or tied face holds no node to open)')
        cycle
      end if
      if (cfg%kernel /= 'linear' .or. cfg%velocity_kernel /= '') &
        call add_raw(pb, head//"an opening needs &shape kernel = 'linear' and velocity_kernel "// &
                     "= '' (wider grid functions and MLS weights reach the mirror images behind "// &
                     'the face, which are not left out at the opening)')
      if (any(cfg%regions%phase /= 'solid')) &
        call add_raw(pb, head//'an opening is for scenes of one phase (every &region phase '// &
                     "= 'solid'); pore fluid leaves through a drained face")
      if (cfg%axisymmetric) &
        call add_raw(pb, head//'an opening is not yet axisymmetric')
      do d = 1, cfg%ndim
        if (d == (f + 1)/2) cycle
        lo = cfg%opening_lo(d, f)
        hi = cfg%opening_hi(d, f)
        if (.not. (lo < hi)) then
          call add_raw(pb, head//'opening_lo('//itoa(d)//') must be below opening_hi('// &
                       itoa(d)//')')
        else if (lo < cfg%origin(d) .or. hi > cfg%origin(d) + cfg%length(d)) then
          call add_raw(pb, head//'the opening must lie inside the face: along axis '// &
                       itoa(d)//' the grid spans '//rtoa(cfg%origin(d))//' .. '// &
                       rtoa(cfg%origin(d) + cfg%length(d)))
        else
          ! the nodes strictly inside lo..hi (as dpmpm_walls counts them)
          h = cfg%length(d)/real(cfg%ncells(d), wp)
          n = ceiling((hi - cfg%origin(d))/h - 1.0e-9_wp) - floor((lo - cfg%origin(d))/h + 1.0e-9_wp) - 1
          if (n < 1) call add_raw(pb, head//'no node of the grid lies strictly inside the '// &
                                  'opening along axis '//itoa(d)//' (node spacing '//rtoa(h)// &
                                  '): the face would stay closed; widen it')
        end if
      end do
    end do
  end subroutine check_openings

  !> An axisymmetric scene (&grid axisymmetric): r-z on a 2D grid whose x- face, at x = 0,
  !> is the axis, held as a roller (v_r = 0); the parts of the code that do not yet carry
  !> the ring's 2 pi r (per radian: r) factor are refused (doc/theory.md, "Axisymmetry").
  subroutine check_axisymmetric(pb, cfg)
    type(input_problems_t), intent(inout) :: pb
    type(config_t), intent(in) :: cfg
    character(len=*), parameter :: head = '&grid axisymmetric = .true.: '
    integer :: k
    if (cfg%ndim /= 2) then
      call add_raw(pb, head//'needs ndim = 2 (r along x, z along y); ndim = '//itoa(cfg%ndim))
      return
    end if
    if (.not. cfg%origin(1) >= 0.0_wp) call add_raw(pb, head//'x is the radius from the axis '// &
      'at x = 0: origin(1) must be >= 0, not '//rtoa(cfg%origin(1)))
    if (cfg%origin(1) == 0.0_wp .and. (cfg%bc(1) /= bc_roller .or. cfg%tied(1) .or. &
                                       cfg%absorbing(1) /= 0 .or. cfg%wall_friction(1) /= 0.0_wp)) &
      call add_raw(pb, head//"face x- is the axis: it needs &boundary face = 'x-', "// &
                   "condition = 'roller' without friction (v_r = 0 on the axis)")
    ! (origin(1) > 0: the grid is a hollow cylinder, its x- face an inner wall at r = origin(1))
    if (cfg%origin(1) > 0.0_wp .and. (cfg%tied(1) .or. cfg%wall_friction(1) /= 0.0_wp)) &
      call add_raw(pb, head//"face x- at r = origin(1) > 0 is an inner wall: 'roller' (without "// &
                   "friction), 'fixed' or 'free'")
    if (cfg%quadrature == 'gauss') call add_raw(pb, head//"needs quadrature = 'points' (the "// &
      'hoop stress is not yet in the Gauss-point forces)')
    if (cfg%volumetric_smoothing /= 'none') call add_raw(pb, head//"needs volumetric_smoothing "// &
      "= 'none' (the cell means do not carry the hoop strain rate)")
    if (any(cfg%regions%phase /= 'solid')) then
      if (cfg%pressure_smoothing /= 'cell') call add_raw(pb, head//"pore water needs "// &
        "&run pressure_smoothing = 'cell' (v_r / r differs between the points of a cell, and "// &
        'their pressures lock the drainage without it)')
      if (cfg%porosity_gradient) call add_raw(pb, head//'&run porosity_gradient = .true. is not '// &
        'yet axisymmetric (the mixture flux lacks its hoop part)')
      if (any(cfg%fluid_bc(1:4) == fbc_drained .and. (cfg%pore_pressure(1:4) /= 0.0_wp .or. &
                                                      any(cfg%pore_pressure_gradient(:, 1:4) /= 0.0_wp, 1)))) &
        call add_raw(pb, head//'a drained face''s pore pressure is not yet axisymmetric (its '// &
                     'nodal force lacks the radius): leave pore_pressure 0 on drained faces')
    end if
    if (cfg%benchmark /= 'none') call add_raw(pb, head//'the benchmarks are plane or 1D: '// &
      "leave &benchmark name = 'none'")
    if (any(cfg%absorbing /= 0)) call add_raw(pb, head//'absorbing faces are not yet '// &
      'axisymmetric (their dashpots per area lack the radius)')
    do k = 1, size(cfg%materials)
      if (cfg%materials(k)%model == 'rigid') call add_raw(pb, head//'rigid bodies (&material '// &
        "model = 'rigid') are not yet axisymmetric")
    end do
  end subroutine check_axisymmetric

end module dpmpm_input_check_faces
