#!/usr/bin/env bash
# One command for the speed of dpmpm: builds the release binary, runs the cases of
# scripts/bench.py (one phase 2D/3D with the Taichi peer side by side, two phases,
# the MLS pair, scaling on 1 and 2 ranks) and writes the tables into
# doc/performance.md between its bench markers. About 10 minutes with 3 rounds.
# Usage: scripts/bench.sh [--rounds N] [--quick] [--no-doc] [--cases one,peer,two,mls,scaling]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
dpmpm_build release >/dev/null
python3 -c "import taichi" 2>/dev/null || pip install --quiet taichi >/dev/null 2>&1 || \
  echo "bench: taichi not installed; the peer comparison is left out" >&2
exec python3 scripts/bench.py "$@"
