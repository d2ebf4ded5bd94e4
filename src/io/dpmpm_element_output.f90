!> The HDF5 file of an element test (doc/output.md, "Element tests"), written on one rank
!> with serial HDF5: the input file and its parameters, and under /element one dataset
!> per recorded quantity (record 0 the initial state, then one per step), the stress and
!> strain as (records, 6) in Voigt order, the model's state values by their names.
module dpmpm_element_output
  use, intrinsic :: iso_c_binding, only: c_loc, c_ptr, c_char, c_null_char
  use hdf5, only: hid_t, hsize_t, h5open_f, h5fcreate_f, h5fclose_f, h5gcreate_f, h5gclose_f, &
                  h5screate_f, h5screate_simple_f, h5sclose_f, h5dcreate_f, h5dwrite_f, &
                  h5dclose_f, h5tclose_f, H5F_ACC_TRUNC_F, H5S_SCALAR_F, H5T_IEEE_F64LE, &
                  H5T_STD_I32LE, h5kind_to_type, H5_REAL_KIND, H5_INTEGER_KIND
  use dpmpm_kinds, only: wp, i4
  use dpmpm_h5, only: h5check, make_dir, string_type, attr_string, attr_i4
  use dpmpm_build_info, only: dpmpm_version, git_commit
  use dpmpm_element_config, only: element_cfg_t
  implicit none
  private
  public :: write_element_file

  character(len=*), parameter :: where = 'element output'

contains

  !> Write the records of the element test cfg into cfg%output (its directory made
  !> first): strain and stress (6, nrec), the state values state (ns, nrec) named
  !> state_names, the integer series iterations, and the real series columns(:, j) named
  !> names(j). status is 'complete' or 'stopped', message why it stopped.
  subroutine write_element_file(cfg, model, status, message, nplanned, strain, stress, &
                                state, state_names, iterations, names, columns)
    type(element_cfg_t), intent(in) :: cfg
    character(len=*), intent(in) :: model, status, message, state_names(:), names(:)
    integer, intent(in) :: nplanned, iterations(:)
    real(wp), intent(in) :: strain(:, :), stress(:, :), state(:, :), columns(:, :)
    integer(hid_t) :: file_id, gid, sid
    integer :: err, j, slash
    character(len=:), allocatable :: list

    slash = index(cfg%output, '/', back=.true.)
    if (slash > 1) call make_dir(cfg%output(1:slash - 1))
    call h5open_f(err)
    call h5check(err, 'h5open_f', where)
    call h5fcreate_f(trim(cfg%output), H5F_ACC_TRUNC_F, file_id, err)
    call h5check(err, 'h5fcreate_f('//trim(cfg%output)//')', where)
    call attr_string(file_id, 'dpmpm_version', dpmpm_version)
    call attr_string(file_id, 'git_commit', git_commit)
    call attr_string(file_id, 'kind', 'element_test')
    call write_text(file_id, 'input', cfg%input_text)
    call write_text(file_id, 'parameters', cfg%echo)

    call h5gcreate_f(file_id, 'element', gid, err)
    call h5check(err, 'h5gcreate_f(/element)', where)
    call attr_string(gid, 'path', trim(cfg%path))
    call attr_string(gid, 'control', trim(cfg%control))
    call attr_string(gid, 'sense', trim(cfg%sense))
    call attr_string(gid, 'model', trim(model))
    call attr_i4(gid, 'cycles', int(cfg%cycles, i4))
    call attr_i4(gid, 'steps', int(nplanned, i4))
    call attr_i4(gid, 'steps_done', int(size(iterations) - 1, i4))
    call attr_string(gid, 'status', status)
    call attr_string(gid, 'message', message)
    list = ''
    do j = 1, size(state_names)
      if (j > 1) list = list//','
      list = list//trim(state_names(j))
    end do
    call attr_string(gid, 'state_names', list)
    call write_real(gid, 'strain', strain)
    call write_real(gid, 'stress', stress)
    call write_int(gid, 'iterations', iterations)
    do j = 1, size(names)
      call write_real(gid, trim(names(j)), columns(:, j:j), vector=.true.)
    end do
    call h5gcreate_f(gid, 'state', sid, err)
    call h5check(err, 'h5gcreate_f(/element/state)', where)
    do j = 1, size(state_names)
      call write_real(sid, trim(state_names(j)), state(j:j, :), vector=.true.)
    end do
    call h5gclose_f(sid, err)
    call h5check(err, 'h5gclose_f(/element/state)', where)
    call h5gclose_f(gid, err)
    call h5check(err, 'h5gclose_f(/element)', where)
    call h5fclose_f(file_id, err)
    call h5check(err, 'h5fclose_f', where)
  end subroutine write_element_file

  !> A scalar fixed-length string dataset name under loc holding text.
  subroutine write_text(loc, name, text)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name, text
    character(kind=c_char, len=max(len(text), 1)), target :: buf
    integer(hid_t) :: space, stype
    integer :: err
    buf = text
    if (len(text) == 0) buf = c_null_char
    stype = string_type(len(buf))
    call h5screate_f(H5S_SCALAR_F, space, err)
    call h5check(err, 'h5screate_f(scalar)', where)
    call write_dataset(loc, name, stype, stype, space, c_loc(buf))
    call h5tclose_f(stype, err)
    call h5check(err, 'h5tclose_f', where)
  end subroutine write_text

  !> A double dataset name under loc: a (m, n) array, which h5py reads as (n, m); with
  !> vector, a (1, n) or (n, 1) array written as one axis.
  subroutine write_real(loc, name, a, vector)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: a(:, :)
    logical, intent(in), optional :: vector
    real(wp), allocatable, target :: buf(:, :)
    integer(hid_t) :: space
    integer :: err
    logical :: one
    buf = a
    one = .false.
    if (present(vector)) one = vector
    if (one) then
      call h5screate_simple_f(1, [int(size(a), hsize_t)], space, err)
    else
      call h5screate_simple_f(2, int(shape(a), hsize_t), space, err)
    end if
    call h5check(err, 'h5screate_simple_f('//name//')', where)
    call write_dataset(loc, name, H5T_IEEE_F64LE, h5kind_to_type(wp, H5_REAL_KIND), space, &
                       c_loc(buf))
  end subroutine write_real

  !> An int32 dataset name under loc of the values v.
  subroutine write_int(loc, name, v)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: v(:)
    integer(i4), target :: buf(size(v))
    integer(hid_t) :: space
    integer :: err
    buf = int(v, i4)
    call h5screate_simple_f(1, [int(size(v), hsize_t)], space, err)
    call h5check(err, 'h5screate_simple_f('//name//')', where)
    call write_dataset(loc, name, H5T_STD_I32LE, h5kind_to_type(i4, H5_INTEGER_KIND), space, &
                       c_loc(buf))
  end subroutine write_int

  !> Dataset name under loc of file type ftype over the dataspace space, written from buf
  !> (memory type mtype); closes the dataset and space.
  subroutine write_dataset(loc, name, ftype, mtype, space, buf)
    integer(hid_t), intent(in) :: loc, ftype, mtype, space
    character(len=*), intent(in) :: name
    type(c_ptr), intent(in) :: buf
    integer(hid_t) :: dset
    integer :: err
    call h5dcreate_f(loc, name, ftype, space, dset, err)
    call h5check(err, 'h5dcreate_f('//name//')', where)
    call h5dwrite_f(dset, mtype, buf, err)
    call h5check(err, 'h5dwrite_f('//name//')', where)
    call h5dclose_f(dset, err)
    call h5check(err, 'h5dclose_f('//name//')', where)
    call h5sclose_f(space, err)
    call h5check(err, 'h5sclose_f', where)
  end subroutine write_dataset

end module dpmpm_element_output
