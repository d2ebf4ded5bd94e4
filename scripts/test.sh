#!/usr/bin/env bash
# Build dpmpm with full runtime checks (debug preset) and run the whole test suite; then
# build the optimised binary that users run (release preset: -O3 -march=native, which
# contracts into fused multiply-adds where the machine has them) and run the suite's
# numerical tests on it (labels verification, unit and mpi), so that a test resting on one
# build's round-off fails here. Installs what is missing first. Extra arguments go to both
# ctest runs. DPMPM_TEST_RELEASE=all runs the whole suite on the release build too, =none
# skips it. Both runs go to the end; the exit status is non-zero if either failed.
# The release part costs about 75 s of CPU to build and 165 s to test (51 tests; 2 min
# and 3.3 min of wall time on 2 cores that four other jobs shared); the whole suite on it
# would cost 8.6 min of CPU, most of it in the input and output tests.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
dpmpm_require_packages
dpmpm_require_test_clients
release_tests=${DPMPM_TEST_RELEASE:-numerical}
case "$release_tests" in
  numerical) release_labels=(-L 'verification|unit|mpi') ;;
  all) release_labels=() ;;
  none) ;;
  *) echo "dpmpm: DPMPM_TEST_RELEASE=$release_tests: the choices are numerical, all, none"; exit 2 ;;
esac
status=0
dpmpm_build debug
ctest --preset debug -j "$(nproc)" "$@" || status=1
if [ "$release_tests" != none ]; then
  dpmpm_build release
  echo "dpmpm: the release build, tests: $release_tests"
  ctest --preset release -j "$(nproc)" ${release_labels[@]+"${release_labels[@]}"} "$@" || status=1
fi
command -v pvpython >/dev/null 2>&1 \
  || echo "dpmpm: WARNING: ParaView's pvpython is missing: what ParaView reads was not checked"
exit $status
