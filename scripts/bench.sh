#!/usr/bin/env bash
# Throughput of the one-phase solver: the default scene (2D, quadratic B-spline,
# neo-Hookean, MUSL) with the linear and quadratic kernels on 1 and 2 ranks.
# Prints point-steps per second per core, and the 2-rank speed-up.
# Usage: scripts/bench.sh [t_end]   (release build; frames off)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
dpmpm_build release >/dev/null
t_end=${1:-0.5}
work=$(mktemp -d)
printf "%-10s %6s %10s %10s %10s %16s\n" kernel ranks points steps wall_s "pt-steps/s/core"
for kernel in linear quadratic; do
  for ranks in 1 2; do
    sed -e "s/t_end = 1.5/t_end = $t_end/" -e "s/kernel = 'quadratic'/kernel = '$kernel'/" \
        -e "s/frame_interval = 0.05/frame_interval = 0.0/" -e "s|dir = 'out'|dir = '$work'|" \
        inputs/default.nml > "$work/scene.nml"
    log=$(mpirun --oversubscribe -n "$ranks" build/release/dpmpm "$work/scene.nml")
    points=$(echo "$log" | sed -n 's/.*; \([0-9]*\) solid points.*/\1/p')
    steps=$(echo "$log" | sed -n 's/^dpmpm: done, \([0-9]*\) steps.*/\1/p')
    wall=$(echo "$log" | sed -n 's/.* in \([0-9.]*\) s$/\1/p' | head -1)
    python3 - "$kernel" "$ranks" "$points" "$steps" "$wall" <<'PY'
import sys
k, r, n, s, w = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
print(f"{k:<10s} {r:6d} {n:10d} {s:10d} {w:10.2f} {n * s / w / r:16.3e}")
PY
  done
done
rm -rf "$work"
