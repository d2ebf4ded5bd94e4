#!/usr/bin/env bash
# Build dpmpm (release) and run a scene on 2 ranks; installs what is missing first.
# Usage: scripts/run.sh [scene.nml] [ranks]
# Without a scene: the 2D consolidation of inputs/consolidation_2d.nml, plotted against
# Terzaghi's solution (out/consolidation_2d.png) and as point clouds per set
# (out/consolidation_2d_points.png). With a scene: its point sets and energies.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
default_scene=inputs/consolidation_2d.nml
scene=${1:-$default_scene}
ranks=${2:-2}
dpmpm_require_packages
dpmpm_build release
log=$(mktemp)
mpirun --oversubscribe -n "$ranks" build/release/dpmpm "$scene" | tee "$log"
h5=$(sed -n 's/^dpmpm: output //p' "$log" | tail -1)
rm -f "$log"
if [ "$scene" = "$default_scene" ]; then
  python3 -m dpmpm terzaghi "$h5" -o "${h5%.h5}.png"
  python3 scripts/plot_frames.py "$h5" -o "${h5%.h5}_points.png" --color stress_yy >/dev/null
  echo "dpmpm: points:      ${h5%.h5}_points.png"
else
  python3 scripts/plot_frames.py "$h5" -o "${h5%.h5}.png"
fi
echo "dpmpm: HDF5 output: $h5"
echo "dpmpm: plot:        ${h5%.h5}.png"
