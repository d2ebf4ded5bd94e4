!> The echo of a configuration: every resolved parameter, defaults included, written as
!> namelist groups that read back as input (dpmpm --check prints it).
module dpmpm_config_echo
  use dpmpm_kinds, only: wp
  use dpmpm_config, only: config_t, face_names, bc_names, fbc_names
  use dpmpm_strings, only: quote, itoa_list, rtoa_list
  implicit none
  private
  public :: print_config

contains

  !> Print every resolved parameter, defaults included, as namelist groups that can be read
  !> back as input.
  subroutine print_config(cfg, unit)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: unit
    integer :: k, f
    write (unit, '(a)') '! dpmpm: resolved parameters of '//trim(cfg%input_file)
    write (unit, '(a)') '&run'
    call put_s(unit, 'name', cfg%name)
    call put_r(unit, 't_end', [cfg%t_end])
    call put_r(unit, 'dt', [cfg%dt])
    call put_r(unit, 'cfl', [cfg%cfl])
    write (unit, '(a,i0)') '  max_steps = ', cfg%max_steps
    call put_s(unit, 'scheme', cfg%scheme)
    call put_r(unit, 'flip', [cfg%flip])
    call put_r(unit, 'gravity', cfg%gravity)
    call put_r(unit, 'progress_seconds', [cfg%progress_seconds])
    call put_s(unit, 'drag', cfg%drag)
    call put_r(unit, 'drag_safety', [cfg%drag_safety])
    call put_l(unit, 'porosity_gradient', cfg%porosity_gradient)
    call put_l(unit, 'remap_drag', cfg%remap_drag)
    call put_r(unit, 'growth_limit', [cfg%growth_limit])
    call put_s(unit, 'restart', cfg%restart)
    call put_r(unit, 'max_wall_time', [cfg%max_wall_time])
    write (unit, '(a)') '/', '&grid'
    call put_i(unit, 'ndim', [cfg%ndim])
    call put_i(unit, 'ncells', cfg%ncells)
    call put_r(unit, 'origin', cfg%origin)
    call put_r(unit, 'length', cfg%length)
    call put_i(unit, 'dims', cfg%dims)
    write (unit, '(a)') '/', '&shape'
    call put_s(unit, 'kernel', cfg%kernel)
    call put_s(unit, 'velocity_kernel', cfg%velocity_kernel)
    call put_s(unit, 'velocity_basis', cfg%velocity_basis)
    call put_r(unit, 'velocity_radius', [cfg%velocity_radius])
    call put_s(unit, 'quadrature', cfg%quadrature)
    call put_i(unit, 'gauss_points', [cfg%gauss_points])
    call put_s(unit, 'field_kernel', cfg%field_kernel)
    call put_s(unit, 'field_basis', cfg%field_basis)
    call put_r(unit, 'field_radius', [cfg%field_radius])
    write (unit, '(a)') '/'
    if (allocated(cfg%materials)) then
      do k = 1, size(cfg%materials)
        associate (m => cfg%materials(k))
          write (unit, '(a)') '&material'
          call put_i(unit, 'id', [m%id])
          call put_s(unit, 'model', m%model)
          call put_r(unit, 'density', [m%density])
          call put_r(unit, 'youngs_modulus', [m%youngs_modulus])
          call put_r(unit, 'poisson_ratio', [m%poisson_ratio])
          call put_r(unit, 'bulk_modulus', [m%bulk_modulus])
          call put_r(unit, 'conductivity', [m%conductivity])
          if (m%model == 'mohr_coulomb' .or. m%model == 'drucker_prager') then
            call put_r(unit, 'friction_angle', [m%friction_angle])
            call put_r(unit, 'dilatancy_angle', [m%dilatancy_angle])
            call put_r(unit, 'cohesion', [m%cohesion])
            call put_r(unit, 'tensile_strength', [m%tensile_strength])
            call put_r(unit, 'cohesion_softening', [m%cohesion_softening])
            call put_r(unit, 'residual_cohesion', [m%residual_cohesion])
            if (m%model == 'drucker_prager') call put_s(unit, 'dp_match', m%dp_match)
          end if
          write (unit, '(a)') '/'
        end associate
      end do
    end if
    if (allocated(cfg%regions)) then
      do k = 1, size(cfg%regions)
        associate (r => cfg%regions(k))
          write (unit, '(a)') '&region'
          call put_s(unit, 'shape', r%shape)
          if (r%shape == 'polygon') then
            call put_i(unit, 'npoly', [r%npoly])
            call put_r(unit, 'poly_x', r%poly(1, 1:r%npoly))
            call put_r(unit, 'poly_y', r%poly(2, 1:r%npoly))
          else
            call put_r(unit, 'lo', r%lo)
            call put_r(unit, 'hi', r%hi)
          end if
          call put_i(unit, 'material', [r%material])
          call put_s(unit, 'phase', r%phase)
          call put_i(unit, 'fluid_material', [r%fluid_material])
          call put_r(unit, 'porosity', [r%porosity])
          call put_i(unit, 'ppc', [r%ppc])
          call put_s(unit, 'placement', r%placement)
          call put_i(unit, 'seed', [r%seed])
          call put_i(unit, 'fluid_seed', [r%fluid_seed])
          call put_r(unit, 'velocity', r%velocity)
          call put_r(unit, 'stress', r%stress)
          call put_r(unit, 'stress_gradient', reshape(r%stress_gradient, [18]))
          call put_r(unit, 'pore_pressure', [r%pore_pressure])
          call put_r(unit, 'pore_pressure_gradient', r%pore_pressure_gradient)
          write (unit, '(a)') '/'
        end associate
      end do
    end if
    do f = 1, 2*max(1, min(3, cfg%ndim))
      write (unit, '(a)') '&boundary'
      call put_s(unit, 'face', face_names(f))
      call put_s(unit, 'condition', bc_names(cfg%bc(f)))
      call put_s(unit, 'fluid', fbc_names(cfg%fluid_bc(f)))
      call put_r(unit, 'pore_pressure', [cfg%pore_pressure(f)])
      call put_r(unit, 'pore_pressure_ramp', [cfg%pore_pressure_ramp(f)])
      write (unit, '(a)') '/'
    end do
    if (allocated(cfg%loads)) then
      do k = 1, size(cfg%loads)
        write (unit, '(a)') '&load'
        call put_s(unit, 'face', face_names(max(1, cfg%loads(k)%face)))
        call put_r(unit, 'traction', cfg%loads(k)%traction)
        call put_r(unit, 'ramp_time', [cfg%loads(k)%ramp_time])
        write (unit, '(a)') '/'
      end do
    end if
    write (unit, '(a)') '&output'
    call put_s(unit, 'dir', cfg%output_dir)
    call put_r(unit, 'frame_interval', [cfg%frame_interval])
    call put_i(unit, 'diag_every', [cfg%diag_every])
    call put_i(unit, 'checkpoint_every', [cfg%checkpoint_every])
    call put_r(unit, 'checkpoint_seconds', [cfg%checkpoint_seconds])
    call put_i(unit, 'compression', [cfg%compression])
    call put_s(unit, 'solid_fields', cfg%solid_fields)
    call put_s(unit, 'fluid_fields', cfg%fluid_fields)
    write (unit, '(a)') '/', '&benchmark'
    call put_s(unit, 'name', cfg%benchmark)
    call put_r(unit, 'amplitude', [cfg%amplitude])
    write (unit, '(a)') '/'
  end subroutine print_config

  !> "  var = 'text'" with quotes doubled inside.
  subroutine put_s(unit, var, value)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: var, value
    write (unit, '(a)') '  '//var//' = '//quote(value)
  end subroutine put_s

  !> "  var = a, b, c" for reals.
  subroutine put_r(unit, var, values)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: var
    real(wp), intent(in) :: values(:)
    write (unit, '(a)') '  '//var//' = '//rtoa_list(values)
  end subroutine put_r

  !> "  var = .true." or "  var = .false.".
  subroutine put_l(unit, var, value)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: var
    logical, intent(in) :: value
    write (unit, '(a)') '  '//var//' = '//trim(merge('.true. ', '.false.', value))
  end subroutine put_l

  !> "  var = a, b, c" for integers.
  subroutine put_i(unit, var, values)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: var
    integer, intent(in) :: values(:)
    write (unit, '(a)') '  '//var//' = '//itoa_list(values)
  end subroutine put_i

end module dpmpm_config_echo
