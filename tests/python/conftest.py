"""Fixtures of the Python package tests: short runs of dpmpm made here, and paths.

Environment (set by ctest, tests/CMakeLists.txt):
  DPMPM_BIN        the dpmpm executable (tests that run it are skipped without it)
  DPMPM_MPIEXEC    mpiexec (default: mpiexec)
  DPMPM_PYTEST_WORKDIR  where the runs are written (default: a pytest temporary dir)
"""
import os
import re
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))

#: The default scene, shortened to 0.03 s (three frames after t = 0) and with its points
#: scattered over the layer (placement 'uniform'), so that the ranks hold ids in no
#: particular order and matching by id matters.
SCENE = os.path.join(ROOT, "inputs", "consolidation_2d.nml")
CHANGES = {"t_end": "0.03", "frame_interval": "0.01", "placement": "'uniform'"}


def short_scene(name, outdir):
    text = open(SCENE).read()
    for key, val in dict(CHANGES, name=f"'{name}'", dir=f"'{outdir}'").items():
        text, n = re.subn(rf"(?m)^(\s*{key}\s*=\s*).*$", lambda m: m.group(1) + val, text,
                          count=1)
        assert n == 1, f"{key} not in {SCENE}"
    return text


@pytest.fixture(scope="session")
def workdir(tmp_path_factory):
    d = os.environ.get("DPMPM_PYTEST_WORKDIR")
    if d:
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        return d
    return str(tmp_path_factory.mktemp("dpmpm_runs"))


def run_dpmpm(workdir, nranks):
    exe = os.environ.get("DPMPM_BIN")
    exe = os.path.abspath(exe) if exe else exe
    if not exe:
        pytest.skip("DPMPM_BIN not set: no dpmpm executable to run")
    name = f"short_np{nranks}"
    nml = os.path.join(workdir, name + ".nml")
    with open(nml, "w") as f:
        f.write(short_scene(name, workdir))
    mpiexec = os.environ.get("DPMPM_MPIEXEC", "mpiexec")
    cmd = [mpiexec, "--oversubscribe", "-n", str(nranks), exe, nml]
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=workdir)
    assert r.returncode == 0, f"{' '.join(cmd)}:\n{r.stdout}\n{r.stderr}"
    return os.path.join(workdir, name + ".h5")


@pytest.fixture(scope="session")
def run_np1(workdir):
    return run_dpmpm(workdir, 1)


@pytest.fixture(scope="session")
def run_np2(workdir):
    return run_dpmpm(workdir, 2)
