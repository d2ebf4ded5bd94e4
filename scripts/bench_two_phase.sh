#!/usr/bin/env bash
# Cost of a two-phase step relative to a one-phase step with the same solid points:
# a 2D block of 96 x 96 cells, 2 x 2 points per cell, loaded on top, as a dry solid
# and as a saturated soil (the same solid points plus as many fluid points, implicit
# drag), with the linear and cubic kernels. The step time is the wall-time
# difference between 120 and 20 steps (set-up and output cancel).
# Usage: scripts/bench_two_phase.sh   (release build)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
dpmpm_build release >/dev/null
work=$(mktemp -d)
scene() { # phase kernel steps
  local fluid=""
  [ "$1" = saturated ] && fluid="fluid_material = 2 porosity = 0.3"
  cat <<NML
&run name = 'bench_$1_$2' t_end = 1.0 max_steps = $3 cfl = 0.3 drag = 'implicit' /
&grid ndim = 2 ncells = 96 96 origin = 0.0 0.0 length = 1.0 1.0 /
&shape kernel = '$2' /
&material id = 1 model = 'linear_elastic' density = 2650.0 youngs_modulus = 1.0e7
  poisson_ratio = 0.2 conductivity = 1.0e-5 /
&material id = 2 model = 'fluid' density = 1000.0 bulk_modulus = 2.2e9 /
&region shape = 'box' lo = 0.0 0.0 hi = 1.0 1.0 material = 1 phase = '$1' $fluid
  ppc = 2 placement = 'random' /
&boundary face = 'y-' condition = 'fixed' /
&boundary face = 'x-' condition = 'roller' /
&boundary face = 'x+' condition = 'roller' /
&load face = 'y+' traction = 0.0 -1000.0 /
&output dir = '$work' /
NML
}
wall() { scene "$@" > "$work/s.nml"
  mpirun --oversubscribe -n 1 build/release/dpmpm "$work/s.nml" | sed -n 's/^dpmpm: done.* in \([0-9.]*\) s$/\1/p'; }
printf "%-8s %-10s %12s %18s\n" kernel phase ms_per_step "solid pt-steps/s"
for kernel in linear cubic; do
  for phase in solid saturated; do
    a=$(wall "$phase" "$kernel" 20); b=$(wall "$phase" "$kernel" 120)
    python3 -c "import sys; a,b=float('$a'),float('$b'); ms=(b-a)/100*1e3; print(f'{\"$kernel\":<8s} {\"$phase\":<10s} {ms:12.2f} {36864/(ms/1e3):18.3e}')"
  done
done
rm -rf "$work"
