#!/usr/bin/env bash
# API documentation of dpmpm generated from the sources by FORD (PyPI `ford`, the Fortran
# community's generator), with the project file doc/ford_project.md: one page per module,
# type and procedure from their `!>` comments, into build/api_docs/html (index.html).
# FORD is installed, pinned, into a virtual environment under build/api_docs the first
# time. Not part of the test suite: it takes about a minute.
# Usage: scripts/api_docs.sh
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$DPMPM_ROOT"
ford_version=7.0.13
venv=build/api_docs/venv
if [ "$("$venv/bin/python" -m pip show ford 2>/dev/null | sed -n 's/^Version: //p')" != "$ford_version" ]; then
  echo "api_docs: installing ford==$ford_version into $venv"
  python3 -m venv "$venv"
  "$venv/bin/python" -m pip install -q "ford==$ford_version"
fi
command -v gfortran >/dev/null || { echo "api_docs: gfortran missing (FORD preprocesses the sources with it)"; exit 2; }
# The generated Fortran that the build compiles (doc/architecture.md, "Generated code"):
# the transfers from their fypp templates, the input variables from their lists.
gen=build/api_docs/generated
mkdir -p "$gen/solver" "$gen/config"
command -v fypp >/dev/null || { echo "api_docs: fypp missing (pip install $DPMPM_PY_TOOLS)"; exit 2; }
fypp -I src/solver src/solver/dpmpm_transfer.fypp "$gen/solver/dpmpm_transfer.f90"
for width in 2 3 4; do
  fypp -I src/solver -DWIDTH=$width src/solver/dpmpm_transfer_kernels.fypp "$gen/solver/dpmpm_transfer_w$width.f90"
done
python3 scripts/gen_input_vars.py "$gen/config" src/config/dpmpm_vars_*.inc
"$venv/bin/ford" --quiet doc/ford_project.md
echo "api_docs: build/api_docs/html/index.html"
