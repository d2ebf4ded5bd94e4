!> The run state of a simulation (simulation_t extends it with the run's
!> procedures): the scene, the list of phases, the coupling node fields, the
!> step's bookkeeping, schedules, records and the run monitor's state. The
!> modules of the step (dpmpm_step, dpmpm_time_step, dpmpm_energy, ...) work on it.
module dpmpm_state
  use dpmpm_kinds, only: wp, i8
  use dpmpm_log, only: log_t
  use dpmpm_timer, only: timer_set_t
  use dpmpm_config, only: config_t
  use dpmpm_grid, only: grid_t
  use dpmpm_decomp, only: decomp_t
  use dpmpm_shape_plan, only: shape_plan_t
  use dpmpm_mls, only: mls_stats_t
  use dpmpm_materials, only: material_t
  use dpmpm_output, only: output_t
  use dpmpm_two_phase_verify, only: error_name_len
  use dpmpm_mirror, only: mirror_t
  use dpmpm_boundary, only: boundary_t
  use dpmpm_phase, only: phase_t, coupling_t
  use dpmpm_rigid, only: bodies_t
  implicit none
  private
  public :: state_t, monitor_t, exit_bad_input, exit_stopped, exit_monitor

  integer, parameter :: exit_bad_input = 2  !< exit status: bad input, restart or time step
  integer, parameter :: exit_stopped = 3    !< exit status: stopped early with a checkpoint
  integer, parameter :: exit_monitor = 4    !< exit status: stopped by the run monitor

  !> The run monitor (doc/verification.md, "Long runs"): energies against the work done
  !> on the body and the energy it started with, not against the run's own maximum.
  type :: monitor_t
    logical :: started = .false.              !< the first record of this run was taken
    real(wp) :: e0 = 0.0_wp                   !< kinetic + stored energy at the first record
    real(wp) :: w0 = 0.0_wp                   !< work of the loads at the first record
    real(wp) :: d0 = 0.0_wp                   !< drag dissipation at the first record
    real(wp) :: input = 0.0_wp                !< e0 + largest |work of the loads| so far
    real(wp) :: ratio = 0.0_wp                !< largest (kinetic + stored) / input so far
    real(wp) :: ke_max = 0.0_wp               !< largest kinetic energy at a record so far
    real(wp) :: balance = 0.0_wp              !< largest |E + D - W - E0| / (input + D) so far
    logical :: warned = .false.               !< the growth warning was given
    real(wp) :: prev(4) = 0.0_wp              !< field maxima at the previous record
    real(wp) :: prev_time = 0.0_wp            !< time of the previous record
    logical :: growth_stop = .false.          !< the monitor stopped the run for growth
  end type monitor_t

  !> The state of a run: the scene, its phases, the step's bookkeeping, the run's
  !> schedules and records (what init makes and free releases).
  type :: state_t
    type(config_t) :: cfg
    type(decomp_t) :: dec
    type(grid_t) :: grid
    type(material_t), allocatable :: mats(:)
    !> The phases of the step: the solid points and, in two-phase scenes, the fluid
    !> points (pore or free fluid), each with its transfer arrays and node fields.
    type(phase_t) :: phase(2)
    integer :: nph = 1                        !< phases present (1 or 2)
    logical :: two_phase = .false.            !< the scene has fluid points
    type(log_t) :: log
    type(timer_set_t) :: timers
    type(output_t) :: out
    logical :: write_output = .true.
    type(shape_plan_t) :: plan                !< grid functions and MLS choices (&shape)
    integer :: kernel = 1
    type(mirror_t) :: mirror                  !< the mirror walls of this rank's node block
    !> the faces' conditions (dpmpm_boundary): each phase's kinds, the pore fluid's, tied
    !> faces, the rigid base, the face loads
    type(boundary_t) :: bnd
    !> the node fields that couple the two phases: nodal porosity, porous mass, 1/k, drag
    type(coupling_t) :: cpl
    real(wp) :: kf_max = 0.0_wp, rhof_min = 0.0_wp !< stiffest, lightest pore fluid (CFL)
    real(wp) :: dt_wave = 0.0_wp, dt_drag = huge(1.0_wp) !< the two limits of the last step
    integer :: governing = 0                  !< limit that set the last step: 1 wave, 2 drag
    real(wp) :: dt_first = 0.0_wp             !< the run's first wave step (dt_falls)
    integer :: dt_drops = 0                   !< decades the wave step has fallen below dt_first
    ! Occupancy of the Gauss cells (one component; see gauss_occupancy).
    real(wp), allocatable :: occ(:, :, :, :), occ2(:, :, :, :)
    integer :: fill = 1                       !< half-width of the occupancy closing (cells)
    type(mls_stats_t) :: mls_stats            !< fallback counts of the MLS solves on this rank
    integer(i8) :: nkept = 0                  !< point gradients left point-wise (no quadrature weight)
    integer(i8) :: nthin = 0                  !< node-steps whose internal force was cleared (thin)
    integer :: kib_start = -1                 !< peak resident memory (KiB) before the points
    integer(i8) :: nwall = 0                  !< points put back inside a wall they had crossed
    integer(i8) :: ncavitated = 0             !< fluid point-steps cut at the cavitation pressure
    integer(i8) :: nfree_surface = 0          !< fluid point-steps at the free surface (p = 0)
    !> points that left: fluid points through drained faces, or points through openings
    !> (a scene has one or the other: openings are for scenes of one phase)
    integer(i8) :: noutflow = 0
    real(wp) :: outflow_mass = 0.0_wp         !< and their mass (kg, or kg/m^(3-ndim))
    real(wp) :: inflow_mass = 0.0_wp          !< mass of the fluid points added at drained faces
    integer(i8) :: inflow_id0 = 0             !< largest fluid point id of the run's start
    integer(i8) :: ninflow = 0                !< fluid points this rank added at inflow faces
    integer :: nd = 1
    !> Node box of this step (local node indices, step_box): the nodes that point
    !> stencils, mirror walls and halo sums can write this step; and the box of the
    !> step before merged with it, outside of which every node field is zero. Unknown
    !> (box_known false) before the first step: the whole block.
    integer :: wlo(3) = 0, whi(3) = -1, zlo(3) = 0, zhi(3) = -1
    logical :: box_known = .false.
    !> a model of the scene has a stiffness that follows the pressure: the time step takes
    !> each point's modulus (point_moduli)
    logical :: pressure_dependent = .false.
    !> the step has found every point valid before its migration (state_valid), so that
    !> check_state after it need not scan the points again
    logical :: checked_valid = .false.
    !> &load surface = .true. (dpmpm_surface_loads): their nodal forces this step
    logical :: has_surface_loads = .false.
    real(wp), allocatable :: sforce(:, :, :, :)
    !> Times the grid was split again by the points during the run (&grid balance_every)
    integer :: nrebalance = 0
    !> Rigid bodies (dpmpm_rigid): whether the scene has any, their share of the node
    !> fields (mass, momentum), the drive's impulse on this rank since the last diagnostics
    !> record and the time of that record, and the mean drive force over each interval
    !> (time, force(3)) for the output.
    logical :: has_rigid = .false.
    real(wp), allocatable :: rnode(:, :, :, :)
    real(wp) :: drive_impulse(3) = 0.0_wp, drive_t0 = 0.0_wp
    real(wp), allocatable :: drive_hist(:, :)
    integer :: ndrive = 0
    !> a rigid body with a frictional contact (dpmpm_contact)
    type(bodies_t) :: bodies
    real(wp) :: time = 0.0_wp
    real(wp) :: dt = 0.0_wp
    !> work of gravity and tractions on this rank, minus the energy dissipated by drag
    real(wp) :: ext_work = 0.0_wp
    integer(i8) :: step = 0
    real(wp) :: wall_start = 0.0_wp
    real(wp) :: wall_checkpoint = 0.0_wp      !< wall clock of the last checkpoint (or start)
    integer :: nframes = 0
    integer(i8) :: last_frame_step = -1       !< step of the last frame written
    real(wp) :: next_frame = 0.0_wp
    real(wp), allocatable :: err_hist(:, :)   !< benchmark errors over diagnostics (time, errors)
    integer :: nerr = 0
    !> Two-phase benchmarks: error names and their values at each frame (time, errors).
    character(len=error_name_len), allocatable :: fnames(:)
    real(wp), allocatable :: ferr(:, :)
    integer :: nferr = 0
    real(wp) :: energy0 = 0.0_wp              !< kinetic + strain - external work at the start
    real(wp) :: energy_scale = 0.0_wp         !< largest of |energy0| and kinetic + strain so far
    real(wp) :: energy_error = 0.0_wp         !< largest |energy - energy0| so far
    real(wp) :: energy_drift = 0.0_wp         !< energy_error / energy_scale
    !> why the last run stopped before t_end: a signal number, -1 for max_wall_time, 0 not
    integer :: stopped = 0
    !> exit status of the run: 0 to go on; 2 bad input, restart or time step, 3 stopped
    !> early with a checkpoint, 4 stopped by the run monitor (collective conditions: every
    !> rank sets the same status and returns)
    integer :: exit_code = 0
    real(wp) :: drag_loss = 0.0_wp            !< energy dissipated by drag on this rank
    type(monitor_t) :: mon                    !< the run monitor's state
    !> time at which the body loaded on each face was found cut (dpmpm_load_path), -1 never
    real(wp) :: cut_time(6) = -1.0_wp
  end type state_t

end module dpmpm_state
