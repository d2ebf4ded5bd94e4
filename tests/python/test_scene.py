"""Scenes as Python objects (dpmpm.Scene, on f90nml): reading every scene of inputs/,
changing repeated groups, writing back, and dpmpm --check's problems as a list."""
import glob
import os

import f90nml
import pytest

import dpmpm
from conftest import ROOT

SCENES = sorted(glob.glob(os.path.join(ROOT, "inputs", "*.nml")))


def binary():
    exe = os.environ.get("DPMPM_BIN")
    if not exe:
        pytest.skip("DPMPM_BIN not set: no dpmpm executable to check scenes with")
    return os.path.abspath(exe)


def test_every_scene_reads_and_writes_back():
    assert len(SCENES) > 10
    for path in SCENES:
        s = dpmpm.Scene.read(path)
        again = f90nml.reads(s.text())
        assert again.todict() == f90nml.read(path).todict(), path
        assert s.names() == [n for n, _ in f90nml.read(path).items()], path


def test_repeated_groups():
    s = dpmpm.Scene.read(os.path.join(ROOT, "inputs", "consolidation_2d.nml"))
    assert len(s.groups("material")) == 2 and len(s.groups("boundary")) == 4
    with pytest.raises(ValueError, match="occurs 4 times"):
        s["boundary"]
    with pytest.raises(KeyError, match="no &benchmark"):
        s["benchmark"]
    water = s.find("material", model="fluid")
    assert len(water) == 1
    top = s.find("boundary", face="y+")
    assert len(top) == 1
    # A third material after the last one, a region using it; remove a boundary.
    s.add("material", id=3, model="linear_elastic", density=2000.0, youngs_modulus=5e6,
          poisson_ratio=0.3)
    mats = [k for k, n in enumerate(s.names()) if n == "material"]
    assert mats == [mats[0], mats[0] + 1, mats[0] + 2]      # kept together, in order
    assert s.remove("boundary", face="x-") == 1 and len(s.groups("boundary")) == 3
    # A variable called name (&benchmark name, &run name) matches and is set like any other.
    t1 = dpmpm.Scene.read(os.path.join(ROOT, "inputs", "t1.nml"))
    assert len(t1.find("benchmark", name="terzaghi")) == 1
    assert t1.remove("benchmark", name="terzaghi") == 1 and "benchmark" not in t1
    t1.add("benchmark", name="terzaghi")
    assert t1.find("benchmark", name="Terzaghi") == [{"name": "terzaghi"}]
    s.set({"run.t_end": 0.05}, output={"dir": "elsewhere"}, shape={"kernel": "cubic"})
    assert s["run"]["t_end"] == 0.05 and s.output_dir == "elsewhere"
    assert s.output_file("/w") == "/w/elsewhere/consolidation_2d.h5"
    back = dpmpm.Scene.from_text(s.text())
    assert [g["id"] for g in back.groups("material")] == [1, 2, 3]
    assert back["shape"]["kernel"] == "cubic"
    # A copy is independent.
    c = back.copy()
    c["run"]["t_end"] = 9.0
    assert back["run"]["t_end"] == 0.05


def test_replace_a_group():
    # A group anew in its place, from namelist text (with an element assignment) or a
    # dict; appended when missing; refused for a repeated group.
    s = dpmpm.Scene.read(os.path.join(ROOT, "inputs", "w1.nml"))
    before = s.names()
    g = s.replace("shape", "kernel = 'cubic', quadrature = 'gauss', field_radius = 2.0")
    assert s.names() == before and s["shape"] is g
    assert dict(g) == {"kernel": "cubic", "quadrature": "gauss", "field_radius": 2.0}
    s.replace("grid", "ndim = 2, ncells(2) = 4", origin=[0.0, 0.0])
    back = dpmpm.Scene.from_text(s.text())
    assert "ncells(2) = 4" in s.text() and back["grid"].start_index == {"ncells": [2]}
    assert back["grid"]["origin"] == [0.0, 0.0]
    assert "length" not in back["grid"] and back["shape"]["field_radius"] == 2.0
    s.remove("benchmark")
    s.replace("benchmark", {"name": "biot_column"})
    assert s.names()[-1] == "benchmark" and s["benchmark"]["name"] == "biot_column"
    with pytest.raises(ValueError, match="occurs 2 times"):
        s.replace("material", id=1)


def test_check_returns_the_problems():
    exe = binary()
    s = dpmpm.Scene.read(os.path.join(ROOT, "inputs", "consolidation_2d.nml"))
    assert s.check(exe) == []
    bad = s.copy()
    bad["run"]["t_end"] = -1.0
    bad.find("region")[0]["porosity"] = 1.3
    bad.add("material", id=9, model="no_such_model")
    problems = bad.check(exe)
    assert any(p.startswith("&run t_end = -1.0: must be > 0") for p in problems), problems
    assert any("&region porosity = 1.3" in p for p in problems), problems
    assert any("no_such_model" in p for p in problems), problems
    with pytest.raises(dpmpm.InputError) as e:
        bad.resolved(exe)
    assert e.value.problems == problems


def test_write_back_reads_the_same_in_dpmpm(tmp_path):
    # dpmpm resolves the written scene to the same parameters as the original file, for
    # scenes with repeated groups, element assignments and loads.
    exe = binary()
    for name in ("consolidation_2d", "w1_2d", "slope_into_water_2d"):
        path = os.path.join(ROOT, "inputs", name + ".nml")
        a = dpmpm.Scene.read(path).resolved(exe)
        b = dpmpm.Scene.from_text(dpmpm.Scene.read(path).text()).resolved(exe)
        assert a.text() == b.text(), name
        assert len(a.text()) > len(dpmpm.Scene.read(path).text())   # defaults filled in


def test_run_scene_of_a_file(run_np2):
    with dpmpm.open_run(run_np2) as run:
        s = run.scene
    assert s.name == "short_np2" and s["run"]["t_end"] == 0.03
