!> The XDMF 2 sidecar <name>.xmf of a run's HDF5 output, for ParaView: the frames and
!> point sets written so far, each dataset referred to in the HDF5 file (doc/output.md).
!> The layout is one that ParaView's three XDMF readers (the Xdmf2 "XDMF Reader",
!> Xdmf3ReaderS and Xdmf3ReaderT) all read whole: no hyperslab and no function item (the
!> Xdmf3 readers skip both), the stress as one six-component Matrix attribute.
!> Written by rank 0 alone; no HDF5 call here. The text is made in memory and written
!> with one checked write(2) (posix_write_file): Fortran's formatted output dropped the
!> error of a full disk and left a cut sidecar behind.
module dpmpm_xdmf
  use dpmpm_kinds, only: wp, i8
  use dpmpm_error, only: fatal
  use dpmpm_config, only: optional_fields
  use dpmpm_h5, only: rename_file
  use dpmpm_posix, only: posix_write_file, posix_strerror
  implicit none
  private
  public :: frame_rec_t, set_rec_t, write_xdmf

  !> Lines of text in one growing buffer (its capacity doubles).
  type :: text_t
    character(len=:), allocatable :: buf
    integer :: n = 0
  contains
    procedure :: add => text_add
  end type text_t

  !> One frame as listed in the XDMF sidecar.
  type :: frame_rec_t
    integer(i8) :: step = 0
    real(wp) :: time = 0.0_wp
  end type frame_rec_t

  !> One point set written in a frame (for the XDMF sidecar), with the optional
  !> datasets it holds.
  type :: set_rec_t
    integer :: frame = 0
    character(len=16) :: name = ''
    integer(i8) :: n = 0
    !> Which of optional_fields (displacement, stress, material, porosity, pore_pressure,
    !> state, rank) the set holds in this frame.
    logical :: has(size(optional_fields)) = .false.
  end type set_rec_t

contains

  !> The XDMF 2 sidecar: one temporal collection of frames, each frame a spatial collection
  !> holding, per set with points in it, a spatial collection named after the set around the
  !> set's cloud. The XDMF Reader names its blocks after these inner collections, the same
  !> at every time (solid, fluid); the Xdmf3 readers see every set at every time.
  !> Written to a temporary file and renamed.
  subroutine write_xdmf(xmf_path, h5_base, ndim, frames, sets, state_names)
    character(len=*), intent(in) :: xmf_path, h5_base
    integer, intent(in) :: ndim
    type(frame_rec_t), intent(in) :: frames(:)
    type(set_rec_t), intent(in) :: sets(:)
    character(len=*), intent(in) :: state_names(:)  !< the datasets of the state values
    character(len=*), parameter :: where = 'output%end_frame'
    character(len=:), allocatable :: tmp_path
    character(len=16) :: names(8)
    character(len=32) :: tstr
    character(len=8) :: fstr
    type(text_t) :: doc
    integer :: err, s, k, f, nnames
    tmp_path = xmf_path//'.tmp'
    allocate (character(len=65536) :: doc%buf)
    ! The set names in the order they first appear: the order of the blocks in a frame.
    nnames = 0
    do s = 1, size(sets)
      if (any(names(1:nnames) == sets(s)%name)) cycle
      if (nnames == size(names)) call fatal('more point sets than the sidecar lists', where)
      nnames = nnames + 1
      names(nnames) = sets(s)%name
    end do
    call doc%add('<?xml version="1.0" ?>')
    call doc%add('<Xdmf Version="2.0">')
    call doc%add(' <Domain>')
    call doc%add('  <Grid Name="frames" GridType="Collection" CollectionType="Temporal">')
    do f = 1, size(frames)
      write (tstr, '(es24.16e3)') frames(f)%time
      write (fstr, '(i6.6)') f - 1
      call doc%add('   <Grid Name="frame '//trim(fstr)// &
        '" GridType="Collection" CollectionType="Spatial">')
      call doc%add('    <Time Value="'//trim(adjustl(tstr))//'"/>')
      do k = 1, nnames
        do s = 1, size(sets)
          if (sets(s)%frame /= f - 1 .or. sets(s)%name /= names(k) .or. sets(s)%n == 0) cycle
          call doc%add('    <Grid Name="'//xml_escape(trim(names(k)))// &
            '" GridType="Collection" CollectionType="Spatial">')
          call write_xdmf_set(h5_base, ndim, doc, sets(s), state_names)
          call doc%add('    </Grid>')
        end do
      end do
      call doc%add('   </Grid>')
    end do
    call doc%add('  </Grid>')
    call doc%add(' </Domain>')
    call doc%add('</Xdmf>')
    ! On a failure the previous sidecar stays as it was (one frame behind, whole).
    err = posix_write_file(tmp_path, doc%buf(1:doc%n))
    if (err /= 0) call fatal('cannot write '//tmp_path//': '//posix_strerror(err)// &
                             ' (the sidecar '//xmf_path//' is left as it was)', where)
    call rename_file(tmp_path, xmf_path, where)
  end subroutine write_xdmf

  !> One grid of a set at one frame: a Polyvertex cloud at x in 2D and 3D; in 1D a
  !> rectilinear grid of 1 x 1 x n nodes with x as its first axis and y = z = 0 (the Xdmf3
  !> readers read no X_Y_Z geometry, nor the function items that made y and z before). The
  !> other datasets are node attributes, the (n, 6) stress one Matrix attribute.
  subroutine write_xdmf_set(h5_base, ndim, doc, set, state_names)
    character(len=*), intent(in) :: h5_base
    integer, intent(in) :: ndim
    type(text_t), intent(inout) :: doc
    type(set_rec_t), intent(in) :: set
    character(len=*), intent(in) :: state_names(:)
    character(len=:), allocatable :: base, nstr, vec
    character(len=24) :: buf
    character(len=16) :: fstr
    integer :: j, k, order(size(state_names))
    order = [(j, j=1, size(state_names))]
    do j = 2, size(order)
      k = j
      do while (k > 1)
        if (llt(state_names(order(k - 1)), state_names(order(k)))) exit
        order(k - 1:k) = order([k, k - 1])
        k = k - 1
      end do
    end do
    write (buf, '(i0)') set%n
    nstr = trim(buf)
    write (fstr, '(i6.6)') set%frame
    base = xml_escape(h5_base)//':/frames/'//trim(fstr)//'/'//xml_escape(trim(set%name))//'/'
    write (buf, '(i0)') ndim
    vec = nstr//' '//trim(buf)
    call doc%add('     <Grid Name="'//xml_escape(trim(set%name))//'" GridType="Uniform">')
    select case (ndim)
    case (1)
      call doc%add('      <Topology TopologyType="3DRectMesh" Dimensions="1 1 '//nstr//'"/>')
      call doc%add('      <Geometry GeometryType="VXVYVZ">')
      call doc%add('       '//item(vec, 'Float', '8', base//'x'))
      call doc%add('       <DataItem Dimensions="1" NumberType="Float" Precision="8" '// &
        'Format="XML">0</DataItem>')
      call doc%add('       <DataItem Dimensions="1" NumberType="Float" Precision="8" '// &
        'Format="XML">0</DataItem>')
    case (2)
      call doc%add('      <Topology TopologyType="Polyvertex" NumberOfElements="'//nstr// &
        '" NodesPerElement="1"/>')
      call doc%add('      <Geometry GeometryType="XY">')
      call doc%add('       '//item(vec, 'Float', '8', base//'x'))
    case default
      call doc%add('      <Topology TopologyType="Polyvertex" NumberOfElements="'//nstr// &
        '" NodesPerElement="1"/>')
      call doc%add('      <Geometry GeometryType="XYZ">')
      call doc%add('       '//item(vec, 'Float', '8', base//'x'))
    end select
    call doc%add('      </Geometry>')
    if (ndim == 1) then
      call attribute('v', 'Scalar', vec, 'Float', '8')
      if (set%has(1)) call attribute('displacement', 'Scalar', vec, 'Float', '8')
    else
      call attribute('v', 'Vector', vec, 'Float', '8')
      if (set%has(1)) call attribute('displacement', 'Vector', vec, 'Float', '8')
    end if
    call attribute('mass', 'Scalar', nstr, 'Float', '8')
    call attribute('volume', 'Scalar', nstr, 'Float', '8')
    ! The columns in file order xx yy zz yz xz xy; ParaView labels any six components
    ! XX YY ZZ XY YZ XZ (doc/output.md, "Viewing in ParaView").
    if (set%has(2)) call attribute('stress', 'Matrix', nstr//' 6', 'Float', '8')
    if (set%has(3)) call attribute('material', 'Scalar', nstr, 'Int', '4')
    if (set%has(7)) call attribute('rank', 'Scalar', nstr, 'Int', '4')
    if (set%has(4)) call attribute('porosity', 'Scalar', nstr, 'Float', '8')
    if (set%has(5)) call attribute('pore_pressure', 'Scalar', nstr, 'Float', '8')
    ! the state values of the models in name order (as the Python package's sidecar lists them)
    do j = 1, merge(size(state_names), 0, set%has(6))
      call attribute(trim(state_names(order(j))), 'Scalar', nstr, 'Float', '8')
    end do
    call attribute('id', 'Scalar', nstr, 'Int', '8')
    call doc%add('     </Grid>')

  contains

    !> In 1D the XDMF Reader reads a node attribute of the 1 x 1 x n grid whole only when
    !> its dimensions start with those of the grid (1 1 n); the Xdmf3 readers take either.
    subroutine attribute(name, atype, dims, ntype, prec)
      character(len=*), intent(in) :: name, atype, dims, ntype, prec
      character(len=:), allocatable :: full
      full = dims
      if (ndim == 1) full = '1 1 '//dims
      call doc%add('      <Attribute Name="'//name//'" AttributeType="'//atype// &
        '" Center="Node">'//item(full, ntype, prec, base//name)//'</Attribute>')
    end subroutine attribute

  end subroutine write_xdmf_set

  !> Append one line (and its newline) to the text.
  subroutine text_add(self, line)
    class(text_t), intent(inout) :: self
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: tmp
    integer :: need
    need = self%n + len(line) + 1
    if (need > len(self%buf)) then
      allocate (character(len=max(need, 2*len(self%buf))) :: tmp)
      tmp(1:self%n) = self%buf(1:self%n)
      call move_alloc(tmp, self%buf)
    end if
    self%buf(self%n + 1:need) = line//new_line('a')
    self%n = need
  end subroutine text_add

  !> An HDF DataItem referring to a dataset of the sidecar's HDF5 file.
  function item(dims, ntype, prec, ref) result(s)
    character(len=*), intent(in) :: dims, ntype, prec, ref
    character(len=:), allocatable :: s
    s = '<DataItem Dimensions="'//dims//'" NumberType="'//ntype//'" Precision="'//prec// &
        '" Format="HDF">'//ref//'</DataItem>'
  end function item

  !> Escape the XML special characters of a name.
  pure function xml_escape(text) result(s)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, len(text)
      select case (text(k:k))
      case ('&')
        s = s//'&amp;'
      case ('<')
        s = s//'&lt;'
      case ('>')
        s = s//'&gt;'
      case ('"')
        s = s//'&quot;'
      case default
        s = s//text(k:k)
      end select
    end do
  end function xml_escape

end module dpmpm_xdmf
