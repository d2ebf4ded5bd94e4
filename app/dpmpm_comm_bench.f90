!> Costs of dpmpm's communication on the machine it runs on, measured through the code's
!> own routines: halo_sum and halo_copy of node fields (decomp_t), MPI_Allreduce of a few
!> doubles, a paired MPI_Sendrecv (the bare transport of one halo stage), and migrate with
!> a given fraction of the points placed in the neighbour's cells.
!>
!> The grid is split along one axis (dims = nranks along it, 1 along the others), so every
!> rank holds n cells along each axis; on 2 ranks each rank has one neighbour, on 1 rank the
!> same calls run without any message (their local work only). The halo exchanges are
!> measured with the split along each axis in turn (a slab across x is the most scattered
!> in memory, one across the last axis contiguous), migration with the split along x.
!> A measurement repeats a batch of calls, sized to last about --min-time seconds, for
!> --rounds rounds; the time per call of a round is the largest over the ranks, and the
!> table gives the median and the range over the rounds. scripts/scaling_model.py reads
!> the table (doc/performance.md, "Beyond one machine").
!>
!> Usage: dpmpm_comm_bench [--quick] [--rounds N] [--min-time seconds]
!> Output, one line per measurement (lines starting with # are comments):
!>   op ndim axis n gw ncomp npoints fraction nranks stages bytes nsent calls t_median t_min t_max
!> op: halo_sum, halo_copy, allreduce, sendrecv, migrate (the moved points spread over the
!> set, as the points next to a face are) or migrate_tail (the moved points are the last of
!> the set, so that removing them moves no other point); axis: the split axis (on 1 rank the
!> halo rows hold for every axis); n: cells per rank and axis (the count of doubles for
!> allreduce and sendrecv); ncomp: components of the node field (reals per packed point for
!> migrate); stages: message exchanges one after the other on a rank's path (2 per split
!> axis for a halo, 4 per split axis for migrate); bytes: bytes moved over those stages;
!> nsent: points each rank sends (migrate); times in seconds per call.
program dpmpm_comm_bench
  use, intrinsic :: iso_fortran_env, only: output_unit
  use dpmpm_mpi_start, only: start_mpi
  use mpi_f08, only: MPI_Comm, MPI_COMM_WORLD, MPI_Comm_size, MPI_Comm_rank, MPI_Finalize, &
                     MPI_Barrier, MPI_Wtime, MPI_Allreduce, MPI_Sendrecv, MPI_IN_PLACE, &
                     MPI_DOUBLE_PRECISION, MPI_MAX, MPI_SUM, MPI_STATUS_IGNORE, MPI_PROC_NULL
  use dpmpm_kinds, only: wp, i8
  use dpmpm_error, only: fatal
  use dpmpm_decomp, only: decomp_t
  use dpmpm_migrate, only: migrate
  use dpmpm_particles, only: particle_set_t
  use dpmpm_stats, only: median
  implicit none

  !> Largest batch of calls in one round.
  integer, parameter :: max_batch = 100000
  !> A sizing batch is long enough once it lasts this long (s).
  real(wp), parameter :: sizing_time = 2.0e-3_wp

  type(MPI_Comm) :: comm
  integer :: nranks, rank, nround, nd, i, j, gw, ic, axis
  real(wp) :: min_time
  logical :: quick
  integer, allocatable :: sizes(:), msizes(:), counts(:)
  real(wp), allocatable :: fractions(:)

  call start_mpi()
  comm = MPI_COMM_WORLD
  call MPI_Comm_size(comm, nranks)
  call MPI_Comm_rank(comm, rank)
  call read_options(quick, nround, min_time)

  if (rank == 0) then
    write (output_unit, '(a,i0,a,i0,a)') '# dpmpm_comm_bench: nranks ', nranks, ', ', nround, &
      ' rounds; time per call, the largest over the ranks in each round, median and range'
    write (output_unit, '(a)') '# op ndim axis n gw ncomp npoints fraction nranks stages bytes '// &
      'nsent calls t_median t_min t_max'
  end if

  ! Latency of the reductions of a step (1 double; about 10 for the diagnostics).
  call bench_allreduce(1)
  call bench_allreduce(10)

  ! The bare transport of one halo stage: both neighbours send and receive at once.
  if (quick) then
    counts = [1, 64]
  else
    counts = [1, 16, 256, 4096, 65536, 1048576]
  end if
  do i = 1, size(counts)
    call bench_sendrecv(counts(i))
  end do

  ! halo_sum and halo_copy of a one-component field and of the step's mass-momentum-force
  ! field (1 + 2 ndim components), ghost widths 1 (linear) and 2 (quadratic, cubic).
  do nd = 2, 3
    if (quick) then
      sizes = [merge(16, 8, nd == 2)]
    else if (nd == 2) then
      sizes = [32, 64, 128, 256, 512, 1024]
    else
      sizes = [16, 32, 64, 128]
    end if
    do axis = 1, merge(1, nd, nranks == 1)
      do i = 1, size(sizes)
        do gw = 1, merge(1, 2, quick)
          do ic = 1, merge(1, 2, quick)
            call bench_halo(nd, axis, sizes(i), gw, merge(1, 1 + 2*nd, ic == 1))
          end do
        end do
      end do
    end do
  end do

  ! Migration of a regular set of 2 points per cell and axis, a fraction of them moved
  ! into the neighbour's cells just before the call.
  if (quick) then
    fractions = [0.0_wp, 0.05_wp]
  else
    fractions = [0.0_wp, 0.001_wp, 0.01_wp, 0.05_wp]
  end if
  do nd = 2, 3
    if (quick) then
      msizes = [merge(8, 4, nd == 2)]
    else if (nd == 2) then
      msizes = [64, 128, 256]
    else
      msizes = [13, 20, 32]
    end if
    do i = 1, size(msizes)
      do j = 1, size(fractions)
        ! One rank has no neighbour to send to.
        if (nranks == 1 .and. fractions(j) > 0.0_wp) cycle
        call bench_migrate(nd, msizes(i), fractions(j), .false.)
        if (fractions(j) > 0.0_wp) call bench_migrate(nd, msizes(i), fractions(j), .true.)
      end do
    end do
  end do

  call MPI_Finalize()

contains

  !> Command line: --quick (tiny sizes, 2 rounds: a smoke run), --rounds N, --min-time s.
  subroutine read_options(quick, nround, min_time)
    logical, intent(out) :: quick
    integer, intent(out) :: nround
    real(wp), intent(out) :: min_time
    character(len=256) :: arg, val
    integer :: k, ios
    character(len=*), parameter :: where = 'dpmpm_comm_bench'
    quick = .false.
    nround = 9
    min_time = 0.02_wp
    k = 1
    do while (k <= command_argument_count())
      call get_command_argument(k, arg)
      select case (trim(arg))
      case ('--quick')
        quick = .true.
        nround = 2
        min_time = 1.0e-3_wp
      case ('--rounds', '--min-time')
        if (k == command_argument_count()) call fatal(trim(arg)//' needs a value', where)
        call get_command_argument(k + 1, val)
        if (trim(arg) == '--rounds') then
          read (val, *, iostat=ios) nround
          if (ios /= 0 .or. nround < 1) call fatal('--rounds needs a count >= 1', where)
        else
          read (val, *, iostat=ios) min_time
          if (ios /= 0 .or. min_time <= 0.0_wp) call fatal('--min-time needs seconds > 0', where)
        end if
        k = k + 1
      case default
        call fatal('unknown argument '//trim(arg)//'; usage: dpmpm_comm_bench [--quick] '// &
                   '[--rounds N] [--min-time seconds]', where)
      end select
      k = k + 1
    end do
  end subroutine read_options

  !> The split of every measurement: n cells per rank and axis, the ranks along one axis.
  subroutine split_along(dec, nd, axis, n, gw)
    type(decomp_t), intent(inout) :: dec
    integer, intent(in) :: nd, axis, n, gw
    integer :: ncells(3), dims(3)
    ncells = 1
    ncells(1:nd) = n
    ncells(axis) = n*nranks
    dims = 1
    dims(axis) = nranks
    call dec%init(comm, nd, ncells, gw, dims)
  end subroutine split_along

  !> Batch size for the rounds from a sizing batch of k calls that took t seconds.
  integer function batch_for(t, k) result(nb)
    real(wp), intent(in) :: t
    integer, intent(in) :: k
    nb = int(min(real(max_batch, wp), max(1.0_wp, k*min_time/max(t, 1.0e-9_wp))))
  end function batch_for

  !> The largest value of t over the ranks.
  real(wp) function slowest(t) result(tmax)
    real(wp), intent(in) :: t
    tmax = t
    call MPI_Allreduce(MPI_IN_PLACE, tmax, 1, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
  end function slowest

  !> Seconds of k calls of halo_sum (op 1) or halo_copy (op 2) on field f, slowest rank.
  real(wp) function halo_batch(dec, f, op, k) result(t)
    type(decomp_t), intent(in) :: dec
    real(wp), intent(inout) :: f(:, :, :, :)
    integer, intent(in) :: op, k
    integer :: c
    real(wp) :: t0
    call MPI_Barrier(comm)
    t0 = MPI_Wtime()
    do c = 1, k
      if (op == 1) then
        call dec%halo_sum(f)
      else
        call dec%halo_copy(f)
      end if
    end do
    t = slowest(MPI_Wtime() - t0)
  end function halo_batch

  !> halo_sum and halo_copy of an ncomp-component node field on n cells per axis, the
  !> ranks along axis.
  subroutine bench_halo(nd, axis, n, gw, ncomp)
    integer, intent(in) :: nd, axis, n, gw, ncomp
    type(decomp_t) :: dec
    real(wp), allocatable :: f(:, :, :, :)
    real(wp) :: t, times(nround)
    integer :: op, k, r, d, e, stages
    integer(i8) :: bytes, slab
    character(len=*), parameter :: names(2) = [character(len=9) :: 'halo_sum', 'halo_copy']
    call split_along(dec, nd, axis, n, gw)
    allocate (f(ncomp, dec%alo(1):dec%ahi(1), dec%alo(2):dec%ahi(2), dec%alo(3):dec%ahi(3)))
    f = 1.0_wp
    ! Along a split axis the exchange runs two stages (towards the lower and the upper
    ! neighbour), each moving a slab gw nodes thick over the stored extent of the others.
    stages = 0
    bytes = 0
    do d = 1, nd
      if (dec%dims(d) == 1) cycle
      slab = int(ncomp, i8)*gw*8
      do e = 1, nd
        if (e /= d) slab = slab*(dec%ahi(e) - dec%alo(e) + 1)
      end do
      stages = stages + 2
      bytes = bytes + 2*slab
    end do
    do op = 1, 2
      k = 1
      do
        t = halo_batch(dec, f, op, k)
        if (t >= sizing_time .or. k >= max_batch) exit
        k = 2*k
      end do
      k = batch_for(t, k)
      do r = 1, nround
        times(r) = halo_batch(dec, f, op, k)/k
      end do
      call emit(trim(names(op)), nd, axis, n, gw, ncomp, 0, 0.0_wp, stages, bytes, 0, k, times)
    end do
    call dec%free()
  end subroutine bench_halo

  !> Seconds of k in-place sums of cnt doubles over all ranks, slowest rank.
  real(wp) function allreduce_batch(buf, k) result(t)
    real(wp), intent(inout) :: buf(:)
    integer, intent(in) :: k
    integer :: c
    real(wp) :: t0
    call MPI_Barrier(comm)
    t0 = MPI_Wtime()
    do c = 1, k
      call MPI_Allreduce(MPI_IN_PLACE, buf, size(buf), MPI_DOUBLE_PRECISION, MPI_SUM, comm)
      buf = 1.0_wp
    end do
    t = slowest(MPI_Wtime() - t0)
  end function allreduce_batch

  !> MPI_Allreduce (sum) of cnt doubles.
  subroutine bench_allreduce(cnt)
    integer, intent(in) :: cnt
    real(wp) :: buf(cnt), t, times(nround)
    integer :: k, r
    buf = 1.0_wp
    k = 1
    do
      t = allreduce_batch(buf, k)
      if (t >= sizing_time .or. k >= max_batch) exit
      k = 2*k
    end do
    k = batch_for(t, k)
    do r = 1, nround
      times(r) = allreduce_batch(buf, k)/k
    end do
    call emit('allreduce', 0, 0, cnt, 0, 1, 0, 0.0_wp, merge(1, 0, nranks > 1), &
              8_i8*cnt, 0, k, times)
  end subroutine bench_allreduce

  !> Seconds of k exchanges of cnt doubles with the partner rank, slowest rank.
  real(wp) function sendrecv_batch(sbuf, rbuf, partner, k) result(t)
    real(wp), intent(in) :: sbuf(:)
    real(wp), intent(inout) :: rbuf(:)
    integer, intent(in) :: partner, k
    integer :: c
    real(wp) :: t0
    call MPI_Barrier(comm)
    t0 = MPI_Wtime()
    do c = 1, k
      call MPI_Sendrecv(sbuf, size(sbuf), MPI_DOUBLE_PRECISION, partner, 31, rbuf, size(rbuf), &
                        MPI_DOUBLE_PRECISION, partner, 31, comm, MPI_STATUS_IGNORE)
    end do
    t = slowest(MPI_Wtime() - t0)
  end function sendrecv_batch

  !> One MPI_Sendrecv of cnt doubles each way between the ranks of a pair (0-1, 2-3, ...);
  !> a rank without a partner exchanges with MPI_PROC_NULL.
  subroutine bench_sendrecv(cnt)
    integer, intent(in) :: cnt
    real(wp), allocatable :: sbuf(:), rbuf(:)
    real(wp) :: t, times(nround)
    integer :: k, r, partner
    allocate (sbuf(cnt), rbuf(cnt))
    sbuf = 1.0_wp
    rbuf = 0.0_wp
    partner = ieor(rank, 1)
    if (partner >= nranks) partner = MPI_PROC_NULL
    k = 1
    do
      t = sendrecv_batch(sbuf, rbuf, partner, k)
      if (t >= sizing_time .or. k >= max_batch) exit
      k = 2*k
    end do
    k = batch_for(t, k)
    do r = 1, nround
      times(r) = sendrecv_batch(sbuf, rbuf, partner, k)/k
    end do
    call emit('sendrecv', 0, 0, cnt, 0, 1, 0, 0.0_wp, merge(1, 0, nranks > 1), &
              8_i8*cnt, 0, k, times)
  end subroutine bench_sendrecv

  !> Seconds spent in k calls of migrate, slowest rank. Before each call (not timed) the
  !> set is reset to tmpl and m of its points are moved just across a face towards a
  !> neighbour (alternating between the two where a rank has both): points spread evenly
  !> over the set, or with tail its last m points. As the step calls it: every point is
  !> inside the grid (in_grid).
  real(wp) function migrate_batch(dec, tmpl, ps, m, k, tail) result(t)
    type(decomp_t), intent(in) :: dec
    type(particle_set_t), intent(in) :: tmpl
    type(particle_set_t), intent(inout) :: ps
    integer, intent(in) :: m, k
    logical, intent(in) :: tail
    real(wp), parameter :: origin(3) = 0.0_wp, h(3) = 1.0_wp
    real(wp) :: t0, up, down
    integer :: c, i, p, stride, nlost
    logical :: to_hi
    up = real(dec%chi(1) + 1, wp) + 0.3_wp
    down = real(dec%clo(1), wp) - 0.3_wp
    stride = max(1, tmpl%n/max(m, 1))
    t = 0.0_wp
    do c = 1, k
      ps = tmpl
      do i = 1, m
        p = merge(tmpl%n - i + 1, 1 + (i - 1)*stride, tail)
        to_hi = dec%nbr_hi(1) /= MPI_PROC_NULL
        if (to_hi .and. dec%nbr_lo(1) /= MPI_PROC_NULL) to_hi = mod(i, 2) == 1
        ps%x(1, p) = merge(up, down, to_hi)
      end do
      call MPI_Barrier(comm)
      t0 = MPI_Wtime()
      call migrate(dec, origin, h, ps, nlost, in_grid=.true.)
      t = t + (MPI_Wtime() - t0)
      if (nlost /= 0) call fatal('points lost in migration', 'dpmpm_comm_bench')
    end do
    t = slowest(t)
  end function migrate_batch

  !> migrate of 2 points per cell and axis on n cells per axis (neo-Hookean points: the
  !> deformation gradient travels too) with a fraction of them moved to the neighbour
  !> (the last points of the set with tail, else points spread over it).
  subroutine bench_migrate(nd, n, fraction, tail)
    integer, intent(in) :: nd, n
    real(wp), intent(in) :: fraction
    logical, intent(in) :: tail
    type(decomp_t) :: dec
    type(particle_set_t) :: tmpl, ps
    real(wp) :: t, times(nround), x(3), zero(6)
    integer :: k, r, i, j, l, a, b, c, m, npts, stages, nsplit
    integer(i8) :: id
    call split_along(dec, nd, 1, n, 1)
    npts = (2*n)**nd
    call tmpl%init('solid', nd, .true., capacity=npts + npts/10)
    id = int(rank, i8)*npts
    x = 0.0_wp
    zero = 0.0_wp
    do l = dec%clo(3), dec%chi(3)
      do j = dec%clo(2), dec%chi(2)
        do i = dec%clo(1), dec%chi(1)
          do c = 0, merge(1, 0, nd == 3)
            do b = 0, 1
              do a = 0, 1
                x(1) = i + 0.25_wp + 0.5_wp*a
                x(2) = j + 0.25_wp + 0.5_wp*b
                if (nd == 3) x(3) = l + 0.25_wp + 0.5_wp*c
                id = id + 1
                call tmpl%append(id, 1, x, zero, 1.0_wp, 1.0_wp, zero)
              end do
            end do
          end do
        end do
      end do
    end do
    if (tmpl%n /= npts) call fatal('unexpected number of points', 'dpmpm_comm_bench')
    m = nint(fraction*npts)
    nsplit = count(dec%dims(1:nd) > 1)
    stages = 4*nsplit
    k = 1
    do
      t = migrate_batch(dec, tmpl, ps, m, k, tail)
      if (t >= sizing_time .or. k >= 64) exit
      k = 2*k
    end do
    ! (at least 3 calls a round: one call of a large set lasts a few scheduler slices)
    k = max(3, min(64, batch_for(t, k)))
    do r = 1, nround
      times(r) = migrate_batch(dec, tmpl, ps, m, k, tail)/k
    end do
    call emit(trim(merge('migrate_tail', 'migrate     ', tail)), nd, 1, n, 1, tmpl%nreal_packed(), &
              npts, fraction, stages, 8_i8*m*tmpl%nreal_packed(), m, k, times)
    call dec%free()
  end subroutine bench_migrate

  !> One line of the table (rank 0).
  subroutine emit(op, nd, axis, n, gw, ncomp, npts, fraction, stages, bytes, nsent, calls, times)
    character(len=*), intent(in) :: op
    integer, intent(in) :: nd, axis, n, gw, ncomp, npts, stages, nsent, calls
    real(wp), intent(in) :: fraction, times(:)
    integer(i8), intent(in) :: bytes
    if (rank /= 0) return
    write (output_unit, '(a,6(1x,i0),1x,es10.3,2(1x,i0),1x,i0,2(1x,i0),3(1x,es11.4))') &
      op, nd, axis, n, gw, ncomp, npts, fraction, nranks, stages, bytes, nsent, calls, &
      median(times), minval(times), maxval(times)
    flush (output_unit)
  end subroutine emit

end program dpmpm_comm_bench
