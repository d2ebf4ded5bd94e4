#!/usr/bin/env bash
# Build dpmpm with full runtime checks (debug preset) and run the whole test
# suite; installs what is missing first. Extra arguments go to ctest.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
dpmpm_require_packages
dpmpm_build debug
ctest --preset debug -j "$(nproc)" "$@"
