!> P1 "peaks" table (doc/theory.md 9.5): relative L2 error of the MLS reconstruction for every
!> kernel x basis x spacing, printed and written to HDF5.
!> Usage: dpmpm_peaks [output.h5]   (default out/peaks.h5)
!> File layout (shapes as h5py shows them):
!>   /peaks/error     (nkernel, nbasis, nh)  relative L2 error
!>   /peaks/h         (nh)                   site spacing
!>   /peaks/radius    (nkernel, nbasis)      kernel radius in units of h (0: tensor product)
!>   /peaks/fallback  (nkernel, nbasis, nh, 5) evaluation points per fallback path
!>   /peaks/seed_error (nkernel, nbasis, nh, nseed) the errors for other jitter draws
!>                    (seeds peaks_seed + 0..nseed-1; the first is /peaks/error)
!>   /peaks/field/{x, y (49), exact, reconstruction (49, 49) indexed [j_y, i_x]} for one case
!>   attributes on /peaks: kernels, bases, fallback_paths (comma-separated), seed, jitter;
!>   on /peaks/field: kernel, basis, h.
program dpmpm_peaks_table
  use, intrinsic :: iso_fortran_env, only: output_unit
  use, intrinsic :: iso_c_binding, only: c_loc
  use dpmpm_mpi_start, only: start_mpi
  use mpi_f08, only: MPI_Finalize
  use hdf5, only: hid_t, hsize_t, h5open_f, h5close_f, h5fcreate_f, h5fclose_f, &
                  h5gcreate_f, h5gclose_f, h5screate_simple_f, h5sclose_f, &
                  h5dcreate_f, h5dwrite_f, h5dclose_f, H5F_ACC_TRUNC_F, &
                  H5T_NATIVE_DOUBLE, H5T_STD_I64LE, h5kind_to_type, H5_INTEGER_KIND
  use dpmpm_kinds, only: wp, i8, i4
  use dpmpm_h5, only: h5check, make_dir, attr_string, attr_i4, attr_real
  use dpmpm_error, only: fatal
  use dpmpm_kernels, only: kernel_names, kernel_cubic
  use dpmpm_mls, only: basis_names, basis_linear, mls_stats_t
  use dpmpm_peaks, only: peaks_error, peaks_case, peaks_neval, peaks_eval_grid, peaks, &
                         peaks_seed, peaks_jitter
  implicit none
  integer, parameter :: nkernel = 5, nbasis = 3, nh = 3, npath = 5, nseed = 8
  real(wp), parameter :: hs(nh) = [0.3_wp, 0.15_wp, 0.075_wp]
  ! The case saved as a field for a figure.
  integer, parameter :: field_kernel = kernel_cubic, field_basis = basis_linear, field_ih = 1
  real(wp) :: err(nh, nbasis, nkernel), radius(nbasis, nkernel), r
  real(wp) :: serr(nseed, nh, nbasis, nkernel)
  integer(i8) :: counts(npath, nh, nbasis, nkernel)
  real(wp), allocatable :: fh(:), xe(:, :)
  type(mls_stats_t) :: st
  integer :: k, b, ih, nargs, is
  logical :: radial
  character(len=512) :: path

  call start_mpi()
  path = 'out/peaks.h5'
  nargs = command_argument_count()
  if (nargs >= 1) call get_command_argument(1, path)
  allocate (fh(peaks_neval**2), xe(2, peaks_neval**2))

  write (output_unit, '(a)') 'P1 peaks: relative L2 error on the 49x49 grid'
  write (output_unit, '(a12,a11,a8,3(a11),a)') 'kernel', 'basis', 'R/h', 'h=0.3', 'h=0.15', &
    'h=0.075', '   fallbacks (full reduced regularised constant empty, all h)'
  do k = 1, nkernel
    do b = 0, nbasis - 1
      call peaks_case(b, k, r, radial)
      radius(b + 1, k) = merge(r, 0.0_wp, radial)
      do ih = 1, nh
        st = mls_stats_t()
        if (k == field_kernel .and. b == field_basis .and. ih == field_ih) then
          call peaks_error(k, b, hs(ih), err(ih, b + 1, k), st, fh)
        else
          call peaks_error(k, b, hs(ih), err(ih, b + 1, k), st)
        end if
        counts(:, ih, b + 1, k) = [st%nfull, st%nreduced, st%nregularised, st%nconstant, &
                                   st%nempty]
        serr(1, ih, b + 1, k) = err(ih, b + 1, k)
        do is = 2, nseed
          st = mls_stats_t()
          call peaks_error(k, b, hs(ih), serr(is, ih, b + 1, k), st, seed=peaks_seed + is - 1)
        end do
      end do
      write (output_unit, '(a12,a11,a8,3es11.3,a,5(1x,i0))') trim(kernel_names(k)), &
        trim(basis_names(b)), merge(fmt_r(r), 'tensor', radial), err(:, b + 1, k), '  ', &
        sum(counts(:, :, b + 1, k), dim=2)
    end do
  end do
  call write_file(trim(path))
  write (output_unit, '(a)') 'written '//trim(path)
  call MPI_Finalize()

contains

  !> Radius as text for the table.
  function fmt_r(x) result(s)
    real(wp), intent(in) :: x
    character(len=6) :: s
    write (s, '(f6.1)') x
  end function fmt_r

  !> Write the table, the counts and the field case (serial HDF5 file access).
  subroutine write_file(fname)
    character(len=*), intent(in) :: fname
    integer(hid_t) :: fid, gid, fgid
    integer :: ierr, i
    real(wp) :: ax(peaks_neval)
    if (index(fname, '/', back=.true.) > 1) &
      call make_dir(fname(1:index(fname, '/', back=.true.) - 1))
    call h5open_f(ierr)
    call h5check(ierr, 'h5open_f', 'dpmpm_peaks')
    call h5fcreate_f(fname, H5F_ACC_TRUNC_F, fid, ierr)
    call h5check(ierr, 'h5fcreate_f('//fname//')', 'dpmpm_peaks')
    call h5gcreate_f(fid, 'peaks', gid, ierr)
    call h5check(ierr, 'h5gcreate_f(/peaks)', 'dpmpm_peaks')
    call put_real(gid, 'error', reshape(err, [size(err)]), &
                  [integer(hsize_t) :: nh, nbasis, nkernel])
    call put_real(gid, 'h', hs, [integer(hsize_t) :: nh])
    call put_real(gid, 'seed_error', reshape(serr, [size(serr)]), &
                  [integer(hsize_t) :: nseed, nh, nbasis, nkernel])
    call put_real(gid, 'radius', reshape(radius, [size(radius)]), &
                  [integer(hsize_t) :: nbasis, nkernel])
    call put_i8(gid, 'fallback', reshape(counts, [size(counts)]), &
                [integer(hsize_t) :: npath, nh, nbasis, nkernel])
    call attr_string(gid, 'kernels', join_names(kernel_names))
    call attr_string(gid, 'bases', join_names(basis_names))
    call attr_string(gid, 'fallback_paths', 'full,reduced,regularised,constant,empty')
    call attr_i4(gid, 'seed', int(peaks_seed, i4))
    call attr_real(gid, 'jitter', peaks_jitter)
    call h5gcreate_f(gid, 'field', fgid, ierr)
    call h5check(ierr, 'h5gcreate_f(/peaks/field)', 'dpmpm_peaks')
    call peaks_eval_grid(xe)
    ax = xe(1, 1:peaks_neval)
    call put_real(fgid, 'x', ax, [integer(hsize_t) :: peaks_neval])
    call put_real(fgid, 'y', ax, [integer(hsize_t) :: peaks_neval])
    call put_real(fgid, 'exact', [(peaks(xe(1, i), xe(2, i)), i=1, size(xe, 2))], &
                  [integer(hsize_t) :: peaks_neval, peaks_neval])
    call put_real(fgid, 'reconstruction', fh, [integer(hsize_t) :: peaks_neval, peaks_neval])
    call attr_string(fgid, 'kernel', trim(kernel_names(field_kernel)))
    call attr_string(fgid, 'basis', trim(basis_names(field_basis)))
    call attr_real(fgid, 'h', hs(field_ih))
    call h5gclose_f(fgid, ierr)
    call h5check(ierr, 'h5gclose_f(/peaks/field)', 'dpmpm_peaks')
    call h5gclose_f(gid, ierr)
    call h5check(ierr, 'h5gclose_f(/peaks)', 'dpmpm_peaks')
    call h5fclose_f(fid, ierr)
    call h5check(ierr, 'h5fclose_f', 'dpmpm_peaks')
    call h5close_f(ierr)
    call h5check(ierr, 'h5close_f', 'dpmpm_peaks')
  end subroutine write_file

  !> Names joined by commas, blanks trimmed.
  function join_names(names) result(s)
    character(len=*), intent(in) :: names(:)
    character(len=:), allocatable :: s
    integer :: i
    s = trim(names(1))
    do i = 2, size(names)
      s = s//','//trim(names(i))
    end do
  end function join_names

  !> A double dataset of the given (Fortran-order) dims from the flat values v.
  subroutine put_real(loc, name, v, dims)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: v(:)
    integer(hsize_t), intent(in) :: dims(:)
    integer(hid_t) :: space, dset
    integer :: ierr
    call h5screate_simple_f(size(dims), dims, space, ierr)
    call h5check(ierr, 'h5screate_simple_f('//name//')', 'dpmpm_peaks')
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, space, dset, ierr)
    call h5check(ierr, 'h5dcreate_f('//name//')', 'dpmpm_peaks')
    call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, v, dims, ierr)
    call h5check(ierr, 'h5dwrite_f('//name//')', 'dpmpm_peaks')
    call h5dclose_f(dset, ierr)
    call h5check(ierr, 'h5dclose_f('//name//')', 'dpmpm_peaks')
    call h5sclose_f(space, ierr)
    call h5check(ierr, 'h5sclose_f('//name//')', 'dpmpm_peaks')
  end subroutine put_real

  !> An int64 dataset of the given (Fortran-order) dims from the flat values v.
  subroutine put_i8(loc, name, v, dims)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(i8), intent(in), target :: v(:)
    integer(hsize_t), intent(in) :: dims(:)
    integer(hid_t) :: space, dset
    integer :: ierr
    call h5screate_simple_f(size(dims), dims, space, ierr)
    call h5check(ierr, 'h5screate_simple_f('//name//')', 'dpmpm_peaks')
    call h5dcreate_f(loc, name, H5T_STD_I64LE, space, dset, ierr)
    call h5check(ierr, 'h5dcreate_f('//name//')', 'dpmpm_peaks')
    call h5dwrite_f(dset, h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(v), ierr)
    call h5check(ierr, 'h5dwrite_f('//name//')', 'dpmpm_peaks')
    call h5dclose_f(dset, ierr)
    call h5check(ierr, 'h5dclose_f('//name//')', 'dpmpm_peaks')
    call h5sclose_f(space, ierr)
    call h5check(ierr, 'h5sclose_f('//name//')', 'dpmpm_peaks')
  end subroutine put_i8

end program dpmpm_peaks_table
