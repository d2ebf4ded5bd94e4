!> Elastic stress updates (dpmpm_materials): the plane-strain forms that 2D scenes
!> use give what the general 3x3 update gives for a velocity gradient and a
!> deformation gradient without a third row and column.
program test_materials
  use dpmpm_mpi_start, only: start_mpi
  use mpi_f08, only: MPI_Finalize
  use dpmpm_kinds, only: wp
  use dpmpm_materials, only: material_t, stress_update, model_neo_hookean, model_linear_elastic
  use dpmpm_assert, only: begin_test, check_close, finish_tests
  implicit none
  integer, parameter :: npt = 25
  !> Measured largest relative difference 6.3e-15 (release, neo-Hookean stress after 20
  !> steps; 3.3e-16 in the debug build); 5x margin.
  real(wp), parameter :: tol_rel = 3.0e-14_wp
  integer :: status
  call start_mpi()
  call test_plane_neo_hookean_matches_general()
  call test_plane_linear_elastic_matches_general()
  status = finish_tests()
  call MPI_Finalize()
  if (status /= 0) stop 1, quiet = .true.

contains

  !> A material of E = 1e7 Pa, nu = 0.3 and the given model.
  function elastic(model) result(mat)
    integer, intent(in) :: model
    type(material_t) :: mat
    mat%model = model
    mat%youngs = 1.0e7_wp
    mat%poisson = 0.3_wp
    mat%mu = mat%youngs/(2.0_wp*(1.0_wp + mat%poisson))
    mat%lambda = mat%youngs*mat%poisson/((1.0_wp + mat%poisson)*(1.0_wp - 2.0_wp*mat%poisson))
    mat%pwave = mat%lambda + 2.0_wp*mat%mu
  end function elastic

  !> In-plane velocity gradients of different size and sense at every point (3x3
  !> column-major, third row and column zero).
  subroutine plane_gradients(vgrad)
    real(wp), intent(out) :: vgrad(9, npt)
    integer :: p
    vgrad = 0.0_wp
    do p = 1, npt
      vgrad(1, p) = 0.8_wp*sin(0.7_wp*p)
      vgrad(2, p) = 0.5_wp*cos(1.1_wp*p)
      vgrad(4, p) = -0.6_wp*sin(0.3_wp*p + 1.0_wp)
      vgrad(5, p) = 0.4_wp*cos(0.9_wp*p + 0.5_wp)
    end do
  end subroutine plane_gradients

  !> Twenty steps of a large in-plane motion: F, stress and volume of the plane form
  !> against the general one.
  subroutine test_plane_neo_hookean_matches_general()
    type(material_t) :: mat
    real(wp) :: vgrad(9, npt), s1(6, npt), s2(6, npt), f1(9, npt), f2(9, npt)
    real(wp) :: vol1(npt), vol2(npt), vol0(npt)
    integer :: pmat(npt), step, p
    real(wp), parameter :: dt = 0.01_wp
    call begin_test('plane_neo_hookean_matches_general')
    mat = elastic(model_neo_hookean)
    call plane_gradients(vgrad)
    pmat = 1
    vol0 = 1.0e-3_wp
    vol1 = vol0; vol2 = vol0
    s1 = 0.0_wp; s2 = 0.0_wp
    f1 = 0.0_wp
    do p = 1, npt
      f1([1, 5, 9], p) = 1.0_wp
    end do
    f2 = f1
    do step = 1, 20
      call stress_update(mat, 1, dt, npt, pmat, vgrad, s1, vol1, vol0, defgrad=f1)
      call stress_update(mat, 1, dt, npt, pmat, vgrad, s2, vol2, vol0, defgrad=f2, plane=.true.)
    end do
    call check_close(maxval(abs(f2 - f1))/maxval(abs(f1)), 0.0_wp, 0.0_wp, tol_rel, 'F (relative)')
    call check_close(maxval(abs(s2 - s1))/maxval(abs(s1)), 0.0_wp, 0.0_wp, tol_rel, 'stress (relative)')
    call check_close(maxval(abs(vol2 - vol1))/maxval(vol1), 0.0_wp, 0.0_wp, tol_rel, 'volume (relative)')
  end subroutine test_plane_neo_hookean_matches_general

  !> Twenty steps of the hypoelastic (Jaumann) update from a plane-strain stress.
  subroutine test_plane_linear_elastic_matches_general()
    type(material_t) :: mat
    real(wp) :: vgrad(9, npt), s1(6, npt), s2(6, npt), vol1(npt), vol2(npt), vol0(npt)
    integer :: pmat(npt), step, p
    real(wp), parameter :: dt = 1.0e-3_wp
    call begin_test('plane_linear_elastic_matches_general')
    mat = elastic(model_linear_elastic)
    call plane_gradients(vgrad)
    pmat = 1
    vol0 = 1.0e-3_wp
    vol1 = vol0; vol2 = vol0
    do p = 1, npt
      s1(:, p) = [-1.0e4_wp, -2.5e4_wp, -1.2e4_wp, 0.0_wp, 0.0_wp, 3.0e3_wp]*real(1 + mod(p, 3), wp)
    end do
    s2 = s1
    do step = 1, 20
      call stress_update(mat, 1, dt, npt, pmat, vgrad, s1, vol1, vol0)
      call stress_update(mat, 1, dt, npt, pmat, vgrad, s2, vol2, vol0, plane=.true.)
    end do
    call check_close(maxval(abs(s2 - s1))/maxval(abs(s1)), 0.0_wp, 0.0_wp, tol_rel, 'stress (relative)')
    call check_close(maxval(abs(vol2 - vol1))/maxval(vol1), 0.0_wp, 0.0_wp, tol_rel, 'volume (relative)')
  end subroutine test_plane_linear_elastic_matches_general

end program test_materials
