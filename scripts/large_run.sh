#!/bin/bash
# A large run (doc/performance.md, "A run of 20 million points"): a saturated cube of
# N^3 cells (default 108: 2 x 2 x 2 points per cell and phase, 10.1 M points per phase),
# linear, implicit drag, a surface load (case B of scripts/many_cores/scenes.py); STEPS
# steps on RANKS ranks with a frame at the start and the end and a checkpoint at the end,
# then a restart from that checkpoint on RANKS2 ranks for 4 more steps. Prints the lines of the logs that give the memory per point and
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
scene() {  # max_steps restart: the saturated cube of scripts/many_cores/scenes.py (case B)
  python3 -c "import sys; sys.path.insert(0, '$ROOT/scripts/many_cores'); import scenes
print(scenes.sat3d($N, $1, 'out', name='large', restart='$2', checkpoint_every=$STEPS))"
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
