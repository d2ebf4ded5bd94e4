"""Element-test files (dpmpm_element, doc/output.md "Element tests"): reading, the pore
pressure ratio, and the plot command `python -m dpmpm element FILE.h5`, on a file made by
h5py with values chosen here and on the example input run by dpmpm_element."""
import math
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np
import pytest

import dpmpm
from conftest import ROOT

PYENV = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "scripts", "python"))
PNG = b"\x89PNG\r\n\x1a\n"


def cli(*args):
    return subprocess.run([sys.executable, "-m", "dpmpm", *args], capture_output=True,
                          text=True, env=PYENV)


def write_cyclic_undrained(path, n=41):
    """Two cycles of undrained triaxial loading of an elastic point, by hand: q on a
    triangle of 30 kPa, p' = 100 kPa, u = q / 3."""
    cyc = np.linspace(0.0, 2.0, n)
    f = cyc - np.floor(cyc)
    w = np.where(f <= 0.25, 4 * f, np.where(f <= 0.75, 2 - 4 * f, 4 * f - 4))
    w[-1] = 0.0
    q = 3.0e4 * w
    stress = np.zeros((n, 6))
    stress[:, 0] = stress[:, 1] = -1.0e5 + q / 3
    stress[:, 2] = -1.0e5 - 2 * q / 3
    with h5py.File(path, "w") as h:
        h.attrs["kind"] = np.bytes_("element_test")
        h["input"] = np.bytes_("&element path = 'triaxial_undrained' /\n")
        g = h.create_group("element")
        for k, v in dict(path="triaxial_undrained", control="stress", sense="compression",
                         model="linear_elastic", status="complete", message="",
                         state_names="").items():
            g.attrs[k] = np.bytes_(v)
        g.attrs["cycles"] = np.int32(2)
        g.attrs["steps"] = np.int32(n - 1)
        g.attrs["steps_done"] = np.int32(n - 1)
        g["time"] = np.arange(n, dtype=float)
        g["cycle"] = cyc
        g["p"] = np.full(n, 1.0e5)
        g["q"] = q
        g["axial_strain"] = q / 1.0e7
        for k in ("volumetric_strain", "shear_strain", "shear_stress", "residual"):
            g[k] = np.zeros(n)
        g["volume_ratio"] = np.ones(n)
        g["excess_pore_pressure"] = q / 3
        g["stress"] = stress
        g["strain"] = np.zeros((n, 6))
        g["iterations"] = np.ones(n, dtype=np.int32)
        g.create_group("state")


def test_read_element_and_pore_pressure_ratio(tmp_path):
    path = str(tmp_path / "cyclic.h5")
    write_cyclic_undrained(path)
    t = dpmpm.read_element(path)
    assert t.path == "triaxial_undrained" and t.control == "stress" and t.cyclic
    assert t.undrained and t.complete and t.steps_done == 40
    assert np.allclose(t.pore_pressure_ratio(), t["q"] / 3 / 1.0e5, rtol=0, atol=1e-15)
    assert max(t["q"]) == pytest.approx(3.0e4, rel=1e-15)
    with pytest.raises(KeyError, match="no series 'void_ratio'"):
        t["void_ratio"]


def test_element_cli_writes_png(tmp_path):
    path = str(tmp_path / "cyclic.h5")
    write_cyclic_undrained(path)
    r = cli("element", path)
    out = str(tmp_path / "cyclic.png")
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip().splitlines()[-1] == out
    with open(out, "rb") as f:
        assert f.read(8) == PNG
    assert os.path.getsize(out) > 10000


def test_element_cli_refuses_a_scene_file(tmp_path):
    path = str(tmp_path / "scene.h5")
    with h5py.File(path, "w") as h:
        h.create_group("frames")
    r = cli("element", path)
    assert r.returncode == 2 and "not an element-test file" in r.stderr


def element_run(workdir, name):
    """The dpmpm_element executable (the test skipped without one) and a fresh directory
    workdir/name to run it in."""
    exe = os.environ.get("DPMPM_ELEMENT_BIN")
    if not exe:
        pytest.skip("DPMPM_ELEMENT_BIN not set: no dpmpm_element executable to run")
    d = os.path.join(workdir, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    return os.path.abspath(exe), d


def test_example_element_test_runs_and_plots(workdir):
    exe, d = element_run(workdir, "element")
    nml = os.path.join(ROOT, "inputs", "element", "triaxial_drained.nml")
    r = subprocess.run([exe, nml], capture_output=True, text=True, cwd=d)
    assert r.returncode == 0, r.stdout + r.stderr
    h5 = os.path.join(d, "out", "element_triaxial_drained.h5")
    t = dpmpm.read_element(h5)
    # Mohr-Coulomb (phi = 32 degrees, no cohesion) from p0 = 100 kPa, cell pressure held
    s = math.sin(math.radians(32.0))
    assert t["q"][-1] == pytest.approx(2 * 1.0e5 * s / (1 - s), rel=1e-7)
    assert t["void_ratio"][0] == pytest.approx(0.7, rel=1e-15)
    png = os.path.join(d, "triaxial.png")
    r = cli("element", h5, "-o", png)
    assert r.returncode == 0, r.stderr
    with open(png, "rb") as f:
        assert f.read(8) == PNG


def test_element_check_prints_parameters_that_read_back(workdir):
    exe, d = element_run(workdir, "element_check")
    nml = os.path.join(ROOT, "inputs", "element", "triaxial_drained.nml")
    first = subprocess.run([exe, "--check", nml], capture_output=True,
                           text=True, cwd=d)
    assert first.returncode == 0, first.stderr
    assert "&material" in first.stdout and "&element" in first.stdout
    assert "friction_angle = 32.0" in first.stdout and "steps = 200" in first.stdout
    echo = os.path.join(d, "echo.nml")
    with open(echo, "w") as f:
        f.write(first.stdout)
    again = subprocess.run([os.path.abspath(exe), "--check", echo], capture_output=True,
                           text=True, cwd=d)
    assert again.returncode == 0, again.stderr
    assert again.stdout.splitlines()[1:] == first.stdout.splitlines()[1:]
    assert not os.path.exists(os.path.join(d, "out")), "--check writes no file"
