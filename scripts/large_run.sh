#!/bin/bash
# A large run (doc/performance.md, "A run of 20 million points"): a saturated cube of
# N^3 cells (default 108: 2 x 2 x 2 points per cell and phase, 10.1 M points per phase),
# linear, implicit drag, a surface load; STEPS steps on RANKS ranks with a frame at the start
# and the end and a checkpoint at the end, then a restart from that checkpoint on RANKS2
# ranks for 4 more steps. Prints the lines of the logs that give the memory per point and
# the time of the frames, the checkpoints and the steps.
#   scripts/large_run.sh [BUILD_DIR] [OUT_DIR]   (N, STEPS, RANKS, RANKS2 from the environment)
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/build/release}/dpmpm
OUT=${2:-$ROOT/build/large_run}
N=${N:-108}; STEPS=${STEPS:-8}; RANKS=${RANKS:-2}; RANKS2=${RANKS2:-1}
source "$ROOT/scripts/common.sh"
MPIRUN=${MPIRUN:-mpirun}
mkdir -p "$OUT"; cd "$OUT"
scene() {  # max_steps restart
  cat <<NML
&run name = 'large' t_end = 1.0 max_steps = $1 cfl = 0.3 drag = 'implicit' restart = '$2' /
&grid ndim = 3 ncells = $N, $N, $N origin = 0.0, 0.0, 0.0 length = 1.0, 1.0, 1.0 /
&shape kernel = 'linear' /
&material id = 1 model = 'linear_elastic' density = 2650.0 youngs_modulus = 1.0e7 poisson_ratio = 0.2 conductivity = 1.0e-5 /
&material id = 2 model = 'fluid' density = 1000.0 bulk_modulus = 2.2e9 /
&region shape = 'box' lo = 0.0, 0.0, 0.0 hi = 1.0, 1.0, 1.0 material = 1 phase = 'saturated' fluid_material = 2 porosity = 0.3 ppc = 2 placement = 'random' /
&boundary face = 'y-' condition = 'fixed' /
&boundary face = 'x-' condition = 'roller' /
&boundary face = 'x+' condition = 'roller' /
&boundary face = 'z-' condition = 'roller' /
&boundary face = 'z+' condition = 'roller' /
&load face = 'y+' traction = 0.0, -1000.0, 0.0 /
&output dir = 'out' frame_interval = 0.0 checkpoint_every = $STEPS /
NML
}
scene "$STEPS" '' > first.nml
scene $((STEPS + 4)) 'out/large.ckpt.h5' > again.nml
keep='points;|memory|time in|time per step|done|restart|read-back'
/usr/bin/time -v $MPIRUN -n "$RANKS" "$BIN" first.nml > first.log 2> first.time || { tail first.log; exit 1; }
grep -E "$keep" first.log; grep -E "Maximum resident|Elapsed" first.time
ls -l out/
/usr/bin/time -v $MPIRUN -n "$RANKS2" "$BIN" again.nml > again.log 2> again.time || { tail again.log; exit 1; }
grep -E "$keep" again.log; grep -E "Maximum resident|Elapsed" again.time
ls -l out/
