# Shared set-up for scripts/run.sh and scripts/test.sh: system packages, Python
# modules and the Open MPI settings that small machines and containers need.

DPMPM_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
DPMPM_DEB_PACKAGES="gfortran libopenmpi-dev openmpi-bin libhdf5-openmpi-dev hdf5-tools libfftw3-dev cmake ninja-build python3 python3-pip"
DPMPM_PY_MODULES="h5py numpy matplotlib pytest f90nml tqdm xarray"
# The source formatters (scripts/format.sh), pinned: another version may lay out differently;
# and fypp, which writes the grid transfers from their templates (src/solver/*.fypp) at build
# time, pinned so that the generated Fortran stays the same.
DPMPM_PY_TOOLS="fprettify==0.3.7 findent==4.3.6 fypp==3.3"

# Open MPI refuses to run as root and to put more ranks than cores on a machine
# unless told; both are harmless elsewhere.
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none

# ParaView, the client whose reading of the output the tests check (tests/test_paraview.py):
# installed by scripts/test.sh where it is missing (as root, without its recommended
# packages: 208 MB to fetch); where that cannot be done, the suite says loudly that the
# check is skipped.
DPMPM_TEST_DEB_PACKAGES="paraview python3-paraview"
dpmpm_require_test_clients() {
  command -v pvpython >/dev/null 2>&1 && return 0
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "dpmpm: installing $DPMPM_TEST_DEB_PACKAGES (the tests read the output with ParaView)"
    apt-get update -qq || true
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      $DPMPM_TEST_DEB_PACKAGES >/dev/null || true
  fi
  command -v pvpython >/dev/null 2>&1 && return 0
  echo "dpmpm: WARNING: ParaView's pvpython is missing and could not be installed;"
  echo "dpmpm: WARNING: the test of what ParaView reads (output_paraview_reads_np2) is skipped."
  echo "dpmpm: WARNING: install it with:  sudo apt-get install -y $DPMPM_TEST_DEB_PACKAGES"
}

# Install missing Debian packages (as root) or print the exact list and stop.
dpmpm_require_packages() {
  local missing=() p
  if command -v dpkg-query >/dev/null 2>&1; then
    for p in $DPMPM_DEB_PACKAGES; do
      dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
  else
    for p in gfortran mpifort mpirun cmake ninja python3; do
      command -v "$p" >/dev/null 2>&1 || missing+=("$p")
    done
  fi
  if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
      echo "dpmpm: installing ${missing[*]}"
      apt-get update -qq
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
    else
      echo "dpmpm: missing system packages: ${missing[*]}"
      echo "install them with:  sudo apt-get install -y ${missing[*]}"
      echo "(on a cluster: load the modules for gfortran, Open MPI, parallel HDF5, FFTW and CMake)"
      exit 1
    fi
  fi
  local pymissing=() m
  for m in $DPMPM_PY_MODULES; do
    python3 -c "import $m" 2>/dev/null || pymissing+=("$m")
  done
  if [ ${#pymissing[@]} -gt 0 ]; then
    echo "dpmpm: installing Python modules ${pymissing[*]}"
    python3 -m pip install -q "${pymissing[@]}" 2>/dev/null \
      || python3 -m pip install -q --break-system-packages "${pymissing[@]}"
  fi
  local toolmissing=() t
  for t in $DPMPM_PY_TOOLS; do
    [ "$(python3 -m pip show "${t%%==*}" 2>/dev/null | sed -n 's/^Version: //p')" = "${t##*==}" ] \
      || toolmissing+=("$t")
  done
  if [ ${#toolmissing[@]} -gt 0 ]; then
    echo "dpmpm: installing ${toolmissing[*]}"
    python3 -m pip install -q "${toolmissing[@]}" 2>/dev/null \
      || python3 -m pip install -q --break-system-packages "${toolmissing[@]}"
  fi
  # The package dpmpm of this checkout (scripts/python/dpmpm, pyproject.toml), editable.
  if ! python3 -c "import dpmpm, sys; sys.exit(not dpmpm.__file__.startswith('$DPMPM_ROOT/'))" \
      2>/dev/null; then
    echo "dpmpm: installing the Python package dpmpm (editable, from $DPMPM_ROOT)"
    python3 -m pip install -q -e "$DPMPM_ROOT" 2>/dev/null \
      || python3 -m pip install -q --break-system-packages -e "$DPMPM_ROOT"
  fi
}

# Configure and build one preset (debug, release or sanitize).
dpmpm_build() {
  local preset=$1
  cmake --preset "$preset" -S "$DPMPM_ROOT" >/dev/null
  cmake --build --preset "$preset" -j "$(nproc)"
}
