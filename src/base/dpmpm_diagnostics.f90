!> One record of the global diagnostics written over time to /diagnostics.
module dpmpm_diagnostics
  use dpmpm_kinds, only: wp, i8
  implicit none
  private
  public :: diag_record_t, ndiag_real, nfirst_diag_real, diag_real_names

  !> Names of the real-valued entries of a record, in the order of diag_record_t%values.
  !> (inflow_mass and outflow_mass, the mass of the fluid points that entered and left
  !> through drained faces since the run's start, came after the others: a file written
  !> before has not got them, nfirst_diag_real say how many it has)
  integer, parameter :: ndiag_real = 13, nfirst_diag_real = 11
  character(len=24), parameter :: diag_real_names(ndiag_real) = [character(len=24) :: &
    'time', 'dt', 'kinetic_energy', 'strain_energy', 'external_work', 'max_speed', &
    'wall_time', 'total_mass', 'momentum_x', 'momentum_y', 'momentum_z', 'inflow_mass', &
    'outflow_mass']

  !> Global (all-rank) quantities at one step. Every rank holds the same record.
  type :: diag_record_t
    integer(i8) :: step = 0
    integer(i8) :: npoints = 0                  !< global number of points, all sets
    real(wp) :: values(ndiag_real) = 0.0_wp     !< see diag_real_names
  end type diag_record_t

end module dpmpm_diagnostics
