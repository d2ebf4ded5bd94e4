#!/usr/bin/env bash
# Build dpmpm (release) and run the default scene on 2 ranks; installs what is
# missing first. Usage: scripts/run.sh [scene.nml] [ranks]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
scene=${1:-inputs/default.nml}
ranks=${2:-2}
dpmpm_require_packages
dpmpm_build release
log=$(mktemp)
mpirun --oversubscribe -n "$ranks" build/release/dpmpm "$scene" | tee "$log"
h5=$(sed -n 's/^dpmpm: output //p' "$log" | tail -1)
rm -f "$log"
python3 scripts/plot_frames.py "$h5" -o "${h5%.h5}.png"
echo "dpmpm: HDF5 output: $h5"
echo "dpmpm: plot:        ${h5%.h5}.png"
