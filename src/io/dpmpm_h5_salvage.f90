!> Reading what a kill may have damaged in an output file: whether the file, a frame or
!> an object still opens, and the diagnostics records it holds. Used when a continued
!> run checks and rebuilds its output (dpmpm_output, salvage).
module dpmpm_h5_salvage
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc
  use hdf5, only: hid_t, hsize_t, h5open_f, h5fopen_f, h5fclose_f, h5lexists_f, h5oopen_f, h5oclose_f, &
                  h5dopen_f, h5dclose_f, h5dread_f, h5dget_space_f, h5sclose_f, &
                  h5sget_simple_extent_dims_f, h5eset_auto_f, h5kind_to_type, H5F_ACC_RDONLY_F, &
                  H5_INTEGER_KIND, H5_REAL_KIND, h5gopen_f, h5gclose_f, h5gget_info_f, &
                  h5lget_name_by_idx_f, H5_INDEX_NAME_F, H5_ITER_INC_F
  use dpmpm_kinds, only: wp, i8
  use dpmpm_diagnostics, only: diag_record_t, ndiag_real, nfirst_diag_real, diag_real_names
  implicit none
  private
  public :: file_sound, frame_sound, object_sound, read_diag_records, read_column, last_record

contains

  !> The file opens, its first nframes frames and the diagnostics can be read (every
  !> frame group opens with its point sets' ids), and so can the later frames that a
  !> continued run deletes (every rank looks on its own; the answer is the same on all).
  !> The index of /frames must list the frames 000000, 000001, ... in order, each once:
  !> a kill during a frame write can leave it listing a frame twice or under another
  !> place while every frame still opens by its name.
  !> HDF5's error printing is off meanwhile: damage is an answer here.
  logical function file_sound(path, nframes) result(sound)
    character(len=*), intent(in) :: path
    integer, intent(in) :: nframes
    integer(hid_t) :: file
    integer :: err, k, e2
    character(len=32) :: gname
    logical :: exists
    call h5eset_auto_f(0, err)
    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, err)
    sound = err >= 0
    if (sound) then
      sound = diagnostics_sound(file)
      if (sound) sound = index_sound(file)
      do k = 0, nframes - 1
        if (.not. sound) exit
        sound = frame_sound(file, k)
      end do
      ! The frames after the checkpoint are deleted: each must open for that.
      k = nframes
      do while (sound)
        write (gname, '(a,i6.6)') 'frames/', k
        call h5lexists_f(file, trim(gname), exists, err)
        if (err < 0) sound = .false.
        if (err < 0 .or. .not. exists) exit
        sound = object_sound(file, trim(gname))
        k = k + 1
      end do
      call h5fclose_f(file, e2)
    end if
    call h5eset_auto_f(1, e2)
  end function file_sound

  !> Every dataset of /diagnostics of an open file opens and holds as many records as
  !> diagnostics/step: the continued run extends them all together, and a kill between
  !> two of their extensions (or inside one) leaves them apart.
  logical function diagnostics_sound(file) result(sound)
    integer(hid_t), intent(in) :: file
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(1), maxdims(1), nstep
    integer :: err, e2, k
    character(len=64) :: name
    logical :: exists
    sound = object_sound(file, 'diagnostics/step')
    nstep = 0
    do k = 0, ndiag_real + 1
      if (.not. sound) exit
      select case (k)
      case (0)
        name = 'diagnostics/step'
      case (1)
        name = 'diagnostics/npoints'
      case default
        name = 'diagnostics/'//trim(diag_real_names(k - 1))
      end select
      ! (a file written before the later columns has none of them)
      if (k - 1 > nfirst_diag_real) then
        call h5lexists_f(file, trim(name), exists, err)
        if (err >= 0 .and. .not. exists) cycle
      end if
      sound = object_sound(file, trim(name))
      if (.not. sound) exit
      call h5dopen_f(file, trim(name), dset, err)
      sound = err >= 0
      if (.not. sound) exit
      call h5dget_space_f(dset, space, err)
      sound = err >= 0
      if (sound) then
        call h5sget_simple_extent_dims_f(space, dims, maxdims, err)
        sound = err >= 0
        call h5sclose_f(space, e2)
      end if
      call h5dclose_f(dset, e2)
      if (k == 0) nstep = dims(1)
      if (sound) sound = dims(1) == nstep
    end do
  end function diagnostics_sound

  !> The link index of /frames of an open file lists 000000, 000001, ... in name order,
  !> each once and nothing else.
  logical function index_sound(file) result(sound)
    integer(hid_t), intent(in) :: file
    integer(hid_t) :: group
    integer :: err, e2, storage, max_corder, nlinks, k
    character(len=32) :: name, want
    sound = object_sound(file, 'frames')
    if (.not. sound) return
    call h5gopen_f(file, 'frames', group, err)
    sound = err >= 0
    if (.not. sound) return
    call h5gget_info_f(group, storage, nlinks, max_corder, err)
    sound = err >= 0
    do k = 0, nlinks - 1
      if (.not. sound) exit
      name = ''
      call h5lget_name_by_idx_f(group, '.', H5_INDEX_NAME_F, H5_ITER_INC_F, int(k, hsize_t), &
                                name, err)
      write (want, '(i6.6)') k
      sound = err >= 0 .and. name == want
    end do
    call h5gclose_f(group, e2)
  end function index_sound

  !> Frame k of an open file can be opened, and so can the ids of its point sets.
  logical function frame_sound(file, k) result(sound)
    integer(hid_t), intent(in) :: file
    integer, intent(in) :: k
    character(len=32) :: gname
    write (gname, '(a,i6.6)') 'frames/', k
    sound = object_sound(file, trim(gname))
    if (sound) sound = object_sound(file, trim(gname)//'/solid/id')
  end function frame_sound

  !> The object at path opens (links and header readable).
  logical function object_sound(file, path) result(sound)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    integer(hid_t) :: obj
    integer :: err, e2
    logical :: exists
    call h5lexists_f(file, path, exists, err)
    sound = err >= 0 .and. exists
    if (.not. sound) return
    call h5oopen_f(file, path, obj, err)
    sound = err >= 0
    if (sound) call h5oclose_f(obj, e2)
  end function object_sound

  !> The diagnostics records of an open file up to the first with a step at or after step
  !> (none when they cannot be read).
  subroutine read_diag_records(file, step, recs, n)
    integer(hid_t), intent(in) :: file
    integer(i8), intent(in) :: step
    type(diag_record_t), allocatable, intent(out) :: recs(:)
    integer, intent(out) :: n
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(1), maxdims(1)
    integer(i8), allocatable, target :: steps(:), npts(:)
    real(wp), allocatable, target :: vals(:)
    type(c_ptr) :: cp
    integer :: err, e2, k, m
    logical :: exists
    n = 0
    allocate (recs(0))
    call h5dopen_f(file, 'diagnostics/step', dset, err)
    if (err < 0) return
    call h5dget_space_f(dset, space, err)
    call h5sget_simple_extent_dims_f(space, dims, maxdims, err)
    call h5sclose_f(space, e2)
    m = int(dims(1))
    allocate (steps(max(m, 1)), npts(max(m, 1)), vals(max(m, 1)))
    cp = c_loc(steps)
    if (m > 0) call h5dread_f(dset, h5kind_to_type(i8, H5_INTEGER_KIND), cp, err)
    call h5dclose_f(dset, e2)
    if (err < 0 .or. m == 0) return
    ! The records before the first at or after step: a kill can leave records after them
    ! that were never written (read as 0).
    do while (n < m)
      if (steps(n + 1) >= step) exit
      n = n + 1
    end do
    deallocate (recs)
    allocate (recs(n))
    do k = 1, n
      recs(k)%step = steps(k)
    end do
    call read_column(file, 'diagnostics/npoints', h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(npts), err)
    if (err < 0) then
      n = 0
      return
    end if
    recs(1:n)%npoints = npts(1:n)
    do k = 1, ndiag_real
      if (k > nfirst_diag_real) then
        ! (0 where a file written before the later columns has not got them)
        call h5lexists_f(file, 'diagnostics/'//trim(diag_real_names(k)), exists, err)
        if (err >= 0 .and. .not. exists) then
          recs(1:n)%values(k) = 0.0_wp
          cycle
        end if
      end if
      call read_column(file, 'diagnostics/'//trim(diag_real_names(k)), &
                       h5kind_to_type(wp, H5_REAL_KIND), c_loc(vals), err)
      if (err < 0) then
        n = 0
        return
      end if
      recs(1:n)%values(k) = vals(1:n)
    end do
  end subroutine read_diag_records

  !> The step and time of the last diagnostics record of the output file path (serial, on
  !> one rank); found is false where the file or its records cannot be read or there are
  !> none. HDF5's error printing is off meanwhile.
  subroutine last_record(path, step, time, found)
    character(len=*), intent(in) :: path
    integer(i8), intent(out) :: step
    real(wp), intent(out) :: time
    logical, intent(out) :: found
    integer(hid_t) :: file, dset, space
    integer(hsize_t) :: dims(1), maxdims(1)
    integer(i8), allocatable, target :: steps(:)
    real(wp), allocatable, target :: times(:)
    integer :: err, e2
    found = .false.
    step = 0
    time = 0.0_wp
    call h5open_f(err)
    if (err < 0) return
    call h5eset_auto_f(0, err)
    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, err)
    if (err >= 0) then
      call h5dopen_f(file, 'diagnostics/step', dset, err)
      if (err >= 0) then
        call h5dget_space_f(dset, space, err)
        if (err >= 0) call h5sget_simple_extent_dims_f(space, dims, maxdims, err)
        if (err >= 0) call h5sclose_f(space, e2)
        call h5dclose_f(dset, e2)
      end if
      if (err >= 0 .and. dims(1) > 0) then
        allocate (steps(dims(1)), times(dims(1)))
        call read_column(file, 'diagnostics/step', h5kind_to_type(i8, H5_INTEGER_KIND), &
                         c_loc(steps), err)
        if (err >= 0) call read_column(file, 'diagnostics/time', &
                                       h5kind_to_type(wp, H5_REAL_KIND), c_loc(times), err)
        if (err >= 0) then
          found = .true.
          step = steps(dims(1))
          time = times(dims(1))
        end if
      end if
      call h5fclose_f(file, e2)
    end if
    call h5eset_auto_f(1, e2)
  end subroutine last_record

  !> Read a whole 1D dataset into buf (err < 0 when it cannot be read).
  subroutine read_column(file, path, mtype, buf, err)
    integer(hid_t), intent(in) :: file, mtype
    character(len=*), intent(in) :: path
    type(c_ptr), intent(in) :: buf
    integer, intent(out) :: err
    integer(hid_t) :: dset
    type(c_ptr) :: p
    integer :: e2
    call h5dopen_f(file, path, dset, err)
    if (err < 0) return
    p = buf
    call h5dread_f(dset, mtype, p, err)
    call h5dclose_f(dset, e2)
  end subroutine read_column

end module dpmpm_h5_salvage
