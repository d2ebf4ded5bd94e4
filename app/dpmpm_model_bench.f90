!> Stress updates per second of each constitutive model of the model table on one core,
!> through stress_update as a run calls it (one material, every point of it), so that the
!> cost of a scene's stress stage can be predicted from its models. The points start at an
!> isotropic effective stress of 100 kPa and are sheared and compressed a little every
!> call (velocity gradients of different size and sense), so that after the first calls the
!> plastic soils return (the plastic work of one more call is printed: 0 for the elastic
!> models).
!>
!> Usage: dpmpm_model_bench [--quick] [--rounds N]
!> Output, one line per model and dimension (lines starting with # are comments):
!>   ndim model points plastic_work Mupdates_per_s_max Mupdates_per_s_median
program dpmpm_model_bench
  use, intrinsic :: iso_fortran_env, only: output_unit, int64
  use dpmpm_kinds, only: wp
  use dpmpm_stats, only: median
  use dpmpm_config, only: material_cfg_t
  use dpmpm_materials, only: material_t, materials_from_config, stress_update, init_state
  use dpmpm_model_table, only: model_table, model_nstate
  implicit none
  integer :: nround, narg, iarg, nd, m, n
  character(len=32) :: arg
  logical :: quick
  type(material_t), allocatable :: mats(:)

  quick = .false.
  nround = 7
  narg = command_argument_count()
  iarg = 1
  do while (iarg <= narg)
    call get_command_argument(iarg, arg)
    select case (trim(arg))
    case ('--quick')
      quick = .true.
      nround = 2
    case ('--rounds')
      iarg = iarg + 1
      call get_command_argument(iarg, arg)
      read (arg, *) nround
      if (nround < 1) then
        write (output_unit, '(a)') 'dpmpm_model_bench: --rounds needs a number of at least 1'
        stop 2
      end if
    case default
      write (output_unit, '(a)') 'usage: dpmpm_model_bench [--quick] [--rounds N]'
      stop 2
    end select
    iarg = iarg + 1
  end do

  ! One material of each model with a stress: a soil of E = 10 MPa (or its Cam-Clay
  ! counterpart), phi = 30 degrees and c = 5 kPa for the plastic soils, Toyoura sand
  ! (SANISAND, the paper's constants, e = 0.85), and the mu(I) soil of glass beads.
  call materials_from_config([ &
                             material_cfg_t(id=1, model='linear_elastic', youngs_modulus=1.0e7_wp), &
                             material_cfg_t(id=2, model='neo_hookean', youngs_modulus=1.0e7_wp), &
                             material_cfg_t(id=3, model='mohr_coulomb', youngs_modulus=1.0e7_wp, &
                                            cohesion=5.0e3_wp), &
                             material_cfg_t(id=4, model='drucker_prager', youngs_modulus=1.0e7_wp, &
                                            cohesion=5.0e3_wp), &
                             material_cfg_t(id=5, model='cam_clay', compression_index=0.2_wp, &
                                            swelling_index=0.05_wp, critical_state_ratio=1.0_wp, &
                                            void_ratio=1.2_wp), &
                             material_cfg_t(id=6, model='sanisand', critical_state_ratio=1.25_wp, &
                                            void_ratio=0.85_wp, poisson_ratio=0.05_wp), &
                             material_cfg_t(id=7, model='mu_i', youngs_modulus=1.0e7_wp, &
                                            mu_s=0.38_wp, mu_2=0.64_wp, i_0=0.279_wp, &
                                            grain_diameter=1.0e-3_wp, density=2500.0_wp)], mats)
  n = merge(4096, 65536, quick)
  write (output_unit, '(a,i0,a)') '# dpmpm_model_bench: one core, ', nround, &
    ' rounds; million stress updates per second, largest and median over the rounds'
  write (output_unit, '(a)') '# ndim model points plastic_work_J Mupd_max Mupd_median'
  do nd = 2, 3
    do m = 1, size(mats)
      call measure(nd, m)
    end do
  end do

contains

  !> The updates of material m's n points, timed over nround rounds of ncall calls.
  subroutine measure(nd, m)
    integer, intent(in) :: nd, m
    real(wp), allocatable :: vgrad(:, :), stress(:, :), vol(:), vol0(:), defgrad(:, :), state(:, :)
    integer, allocatable :: pmat(:)
    integer(int64) :: c0, c1, rate
    real(wp) :: t(nround), w
    !> a step of 1e-3 s: every call strains the points by about 1e-3, so that the first 20
    !> calls take the plastic soils to their surfaces
    real(wp), parameter :: dt = 1.0e-3_wp
    integer :: p, r, c, ncall, ns
    integer, parameter :: identity(9) = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    ns = max(1, model_nstate(mats(m)%model))
    allocate (vgrad(9, n), stress(6, n), vol(n), vol0(n), defgrad(9, n), state(ns, n), pmat(n))
    vgrad = 0.0_wp
    do p = 1, n
      ! shear and compression rates of different size and sense (per unit time)
      vgrad(1, p) = -0.5_wp - 0.3_wp*sin(0.7_wp*p)
      vgrad(5, p) = 0.3_wp*cos(1.1_wp*p)
      vgrad(4, p) = 1.0_wp*sin(0.3_wp*p + 1.0_wp)
      vgrad(2, p) = 0.2_wp*cos(0.9_wp*p)
      if (nd == 3) then
        vgrad(9, p) = 0.2_wp*sin(1.3_wp*p)
        vgrad(7, p) = 0.3_wp*cos(0.5_wp*p)
      end if
    end do
    stress = spread([-1.0e5_wp, -1.0e5_wp, -1.0e5_wp, 0.0_wp, 0.0_wp, 0.0_wp], 2, n)
    vol = 1.0_wp
    vol0 = 1.0_wp
    defgrad = spread(real(identity, wp), 2, n)
    state = 0.0_wp
    pmat = m
    call init_state(mats(m), m, n, pmat, stress, state)
    ncall = merge(2, 20, quick)
    call system_clock(count_rate=rate)
    ! the first calls load the soils to their surfaces (w sums the plastic work of the calls)
    w = 0.0_wp
    do c = 1, ncall
      call stress_update(mats(m), m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, &
                         w, plane=nd == 2)
    end do
    do r = 1, nround
      call system_clock(c0)
      do c = 1, ncall
        call stress_update(mats(m), m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, &
                           state, w, plane=nd == 2)
      end do
      call system_clock(c1)
      t(r) = real(c1 - c0, wp)/real(rate, wp)
    end do
    ! the plastic work of one more call over the points' elastic energy scale shows that the
    ! plastic soils return (0 for the elastic models)
    w = 0.0_wp
    call stress_update(mats(m), m, dt, n, pmat, vgrad, stress, vol, vol0, defgrad, state, w, &
                       plane=nd == 2)
    write (output_unit, '(i0,1x,a,1x,i0,1x,es9.2,2(1x,f9.3))') nd, trim(model_table(mats(m)%model)%name), &
      n, w, real(n, wp)*ncall/minval(t)*1.0e-6_wp, real(n, wp)*ncall/median(t)*1.0e-6_wp
  end subroutine measure

end program dpmpm_model_bench
