!> Read-back check of collective writes (write_check_t in dpmpm_h5): a clean collective
!> write reads back unchanged and is left alone; a block that one rank's data did not
!> reach in the file (simulated here by overwriting it after the write) is found,
!> rewritten and then holds the right values, and the other ranks' blocks are untouched.
program test_write_check
  use, intrinsic :: iso_c_binding, only: c_loc, c_ptr
  use mpi_f08, only: MPI_COMM_WORLD, MPI_Comm_size, MPI_Exscan, MPI_Allreduce, MPI_SUM, &
                     MPI_INFO_NULL, MPI_Barrier
  use hdf5, only: hid_t, hsize_t, h5open_f, h5fcreate_f, h5fclose_f, h5pcreate_f, h5pclose_f, &
                  h5pset_fapl_mpio_f, h5pset_dxpl_mpio_f, h5dopen_f, h5dclose_f, h5dwrite_f, &
                  h5dread_f, h5dget_space_f, h5sselect_hyperslab_f, h5screate_simple_f, &
                  h5sclose_f, h5sselect_none_f, h5kind_to_type, H5_REAL_KIND, H5_INTEGER_KIND, &
                  H5F_ACC_TRUNC_F, &
                  H5P_FILE_ACCESS_F, H5P_DATASET_XFER_F, H5P_DEFAULT_F, &
                  H5FD_MPIO_COLLECTIVE_F, H5S_SELECT_SET_F, H5T_IEEE_F64LE, H5T_STD_I64LE
  use dpmpm_kinds, only: wp, i8, mpi_i8
  use dpmpm_h5, only: h5check, make_dir, write_columns, write_check_t
  use dpmpm_assert, only: begin_test, check, check_equal_int
  use dpmpm_test_main, only: start_tests, end_tests, test_dir
  implicit none
  character(len=:), allocatable :: dir   !< out/test_write_check_np<ranks>
  integer, parameter :: m = 3
  integer :: rank, nranks, err
  integer(i8) :: nloc, offset, nglob
  integer(hid_t) :: file, dxpl, fapl
  call start_tests(rank)
  dir = test_dir('test_write_check')
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  ! Rank r holds 4 + r points (the last rank none when there are 3 or more).
  nloc = merge(0_i8, int(4 + rank, i8), nranks >= 3 .and. rank == nranks - 1)
  offset = 0
  call MPI_Exscan(nloc, offset, 1, mpi_i8(), MPI_SUM, MPI_COMM_WORLD)
  if (rank == 0) offset = 0
  call MPI_Allreduce(nloc, nglob, 1, mpi_i8(), MPI_SUM, MPI_COMM_WORLD)

  call h5open_f(err)
  if (rank == 0) call make_dir(dir)
  call MPI_Barrier(MPI_COMM_WORLD)
  call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, err)
  call h5pset_fapl_mpio_f(fapl, MPI_COMM_WORLD%MPI_VAL, MPI_INFO_NULL%MPI_VAL, err)
  call h5fcreate_f(dir//'/check.h5', H5F_ACC_TRUNC_F, file, err, access_prp=fapl)
  call h5check(err, 'h5fcreate_f', 'test_write_check')
  call h5pclose_f(fapl, err)
  call h5pcreate_f(H5P_DATASET_XFER_F, dxpl, err)
  call h5pset_dxpl_mpio_f(dxpl, H5FD_MPIO_COLLECTIVE_F, err)

  call test_clean_write_is_left_alone()
  call test_overwritten_block_is_found_and_rewritten()
  call test_compressed_block_is_rewritten_collectively()

  call h5pclose_f(dxpl, err)
  call h5fclose_f(file, err)
  call end_tests()

contains

  !> Global point k (0-based) has id 1000 + k and coordinates k + 0.25 j, j = 1..m.
  subroutine write_pair(suffix, check, compression)
    character(len=*), intent(in) :: suffix
    type(write_check_t), intent(inout) :: check
    integer, intent(in), optional :: compression
    integer(i8), allocatable, target :: ids(:)
    real(wp), allocatable, target :: x(:, :)
    integer :: k, j
    allocate (ids(max(nloc, 1_i8)), x(m, max(nloc, 1_i8)))
    ids = 0
    x = 0.0_wp
    do k = 1, int(nloc)
      ids(k) = 1000 + offset + k - 1
      x(:, k) = [(real(offset + k - 1, wp) + 0.25_wp*j, j=1, m)]
    end do
    call write_columns(file, dxpl, 'id'//suffix, H5T_STD_I64LE, &
                       h5kind_to_type(i8, H5_INTEGER_KIND), 0, nloc, offset, nglob, c_loc(ids), &
                       'test', check, compression)
    call write_columns(file, dxpl, 'x'//suffix, H5T_IEEE_F64LE, &
                       h5kind_to_type(wp, H5_REAL_KIND), m, nloc, offset, nglob, c_loc(x), &
                       'test', check, compression)
  end subroutine write_pair

  !> Every rank reads both whole datasets and compares with the values write_pair wrote.
  logical function pair_is_right(suffix) result(ok)
    character(len=*), intent(in) :: suffix
    integer(i8), allocatable, target :: ids(:)
    real(wp), allocatable, target :: x(:, :)
    integer(hid_t) :: dset
    type(c_ptr) :: p
    integer :: k, j
    allocate (ids(nglob), x(m, nglob))
    call h5dopen_f(file, 'id'//suffix, dset, err)
    p = c_loc(ids)
    call h5dread_f(dset, h5kind_to_type(i8, H5_INTEGER_KIND), p, err)
    call h5check(err, 'h5dread_f', 'test')
    call h5dclose_f(dset, err)
    call h5dopen_f(file, 'x'//suffix, dset, err)
    p = c_loc(x)
    call h5dread_f(dset, h5kind_to_type(wp, H5_REAL_KIND), p, err)
    call h5check(err, 'h5dread_f', 'test')
    call h5dclose_f(dset, err)
    ok = .true.
    do k = 1, int(nglob)
      ok = ok .and. ids(k) == 1000 + k - 1
      ok = ok .and. all(x(:, k) == [(real(k - 1, wp) + 0.25_wp*j, j=1, m)])
    end do
  end function pair_is_right

  subroutine test_clean_write_is_left_alone()
    type(write_check_t) :: wc
    integer :: nrew
    call begin_test('clean_write_is_left_alone')
    call write_pair('_a', wc)
    call check_equal_int(wc%n, 2, 'one record per dataset on every rank')
    call wc%verify(file, MPI_COMM_WORLD, 'test', nrew)
    call check_equal_int(nrew, 0, 'blocks rewritten after a clean write')
    call check_equal_int(wc%n, 0, 'blocks kept after verify')
    call check(pair_is_right('_a'), 'file holds every rank''s block')
  end subroutine test_clean_write_is_left_alone

  !> Rank 0 overwrites its block of both datasets with -1 after the collective write, as a
  !> misplaced collective write leaves it; verify must find both blocks and restore them.
  subroutine test_overwritten_block_is_found_and_rewritten()
    type(write_check_t) :: wc
    integer(i8), allocatable, target :: junk_ids(:)
    real(wp), allocatable, target :: junk_x(:, :)
    integer :: nrew
    call begin_test('overwritten_block_is_found_and_rewritten')
    call write_pair('_b', wc)
    call MPI_Barrier(MPI_COMM_WORLD)
    if (rank == 0) then
      allocate (junk_ids(nloc), junk_x(m, nloc))
      junk_ids = -1
      junk_x = -1.0_wp
      call overwrite('id_b', 1, [int(offset, hsize_t)], [int(nloc, hsize_t)], &
                     h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(junk_ids))
      call overwrite('x_b', 2, [0_hsize_t, int(offset, hsize_t)], &
                     [int(m, hsize_t), int(nloc, hsize_t)], h5kind_to_type(wp, H5_REAL_KIND), &
                     c_loc(junk_x))
    end if
    call MPI_Barrier(MPI_COMM_WORLD)
    call wc%verify(file, MPI_COMM_WORLD, 'test', nrew)
    call check_equal_int(nrew, 2, 'blocks rewritten (rank 0: id and x)')
    call check(pair_is_right('_b'), 'file holds every rank''s block after the rewrite')
  end subroutine test_overwritten_block_is_found_and_rewritten

  !> A compressed dataset (chunked, shuffle + gzip) is written collectively only; rank 0's
  !> block is overwritten collectively (the others with empty selections), and verify must
  !> find it and have every rank rewrite its block collectively.
  subroutine test_compressed_block_is_rewritten_collectively()
    type(write_check_t) :: wc
    integer(i8), allocatable, target :: junk_ids(:)
    real(wp), allocatable, target :: junk_x(:, :)
    integer(i8) :: n0
    integer :: nrew
    call begin_test('compressed_block_is_rewritten_collectively')
    call write_pair('_c', wc, compression=1)
    n0 = merge(nloc, 0_i8, rank == 0)
    allocate (junk_ids(max(n0, 1_i8)), junk_x(m, max(n0, 1_i8)))
    junk_ids = -1
    junk_x = -1.0_wp
    call overwrite('id_c', 1, [0_hsize_t], [int(n0, hsize_t)], &
                   h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(junk_ids), collective=.true.)
    call overwrite('x_c', 2, [0_hsize_t, 0_hsize_t], [int(m, hsize_t), int(n0, hsize_t)], &
                   h5kind_to_type(wp, H5_REAL_KIND), c_loc(junk_x), collective=.true.)
    call check(.not. pair_is_right('_c'), 'the overwrite reached the file')
    call wc%verify(file, MPI_COMM_WORLD, 'test', nrew)
    call check_equal_int(nrew, 2, 'blocks found wrong (rank 0: id and x)')
    call check(pair_is_right('_c'), 'file holds every rank''s block after the rewrite')
  end subroutine test_compressed_block_is_rewritten_collectively

  !> Write of a block into an existing dataset (bypassing the check): independent, or
  !> collective (every rank calls; a count of 0 selects nothing).
  subroutine overwrite(name, r, start, cnt, mtype, ptr, collective)
    character(len=*), intent(in) :: name
    integer, intent(in) :: r
    integer(hsize_t), intent(in) :: start(r), cnt(r)
    integer(hid_t), intent(in) :: mtype
    type(c_ptr), intent(in) :: ptr
    logical, intent(in), optional :: collective
    integer(hid_t) :: dset, fspace, mspace, xfer
    xfer = H5P_DEFAULT_F
    if (present(collective)) xfer = dxpl
    call h5dopen_f(file, name, dset, err)
    call h5dget_space_f(dset, fspace, err)
    if (product(cnt) > 0) then
      call h5sselect_hyperslab_f(fspace, H5S_SELECT_SET_F, start, cnt, err)
      call h5screate_simple_f(r, cnt, mspace, err)
    else
      call h5sselect_none_f(fspace, err)
      call h5screate_simple_f(1, [1_hsize_t], mspace, err)
      call h5sselect_none_f(mspace, err)
    end if
    call h5dwrite_f(dset, mtype, ptr, err, mem_space_id=mspace, file_space_id=fspace, &
                    xfer_prp=xfer)
    call h5check(err, 'h5dwrite_f', 'test overwrite')
    call h5sclose_f(mspace, err)
    call h5sclose_f(fspace, err)
    call h5dclose_f(dset, err)
  end subroutine overwrite

end program test_write_check
