"""dpmpm.namelist (on f90nml) on the forms dpmpm inputs use."""
import os

from dpmpm import namelist
from dpmpm.run import Grid

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")


def test_forms():
    text = """! comment with &grid inside
&region lo = 1*0.0, 2*1.5 stress_gradient(1:6, 2) = 3884.8, 9712.0 name='a/b!c' / ! x
&grid ncells(2) = 4 /
&run name = 'it''s', flag = .true., dt=1.0d-3
/
&boundary face = 'x-' /
&boundary face = 'x+' /
"""
    groups = namelist.parse(text)
    assert [g for g, _ in groups] == ["region", "grid", "run", "boundary", "boundary"]
    region = groups[0][1]
    assert region["lo"] == [0.0, 1.5, 1.5]
    assert region["stress_gradient"] == [[3884.8, 9712.0]]
    assert region["name"] == ["a/b!c"]
    assert groups[1][1] == {"ncells": [None, 4]}
    assert groups[2][1] == {"name": ["it's"], "flag": [True], "dt": [1.0e-3]}
    assert [b["face"] for b in namelist.groups(text, "boundary")] == [["x-"], ["x+"]]


def test_grid_defaults_and_elements():
    g = Grid.from_input("&grid ndim = 3, ncells(3) = 7 /")
    assert g.ncells.tolist() == [1, 1, 7]
    assert g.length.tolist() == [1.0, 1.0, 1.0]


def test_axisymmetric_grid():
    # &grid axisymmetric: per-radian volumes and masses (doc/theory.md 4.8).
    g = Grid.from_input("&grid ndim = 2, ncells = 32, 2, axisymmetric = .true. /")
    assert g.axisymmetric and "axisymmetric=True" in repr(g)
    assert not Grid.from_input("&grid ndim = 2 /").axisymmetric


def test_every_scene_has_its_grid():
    # Each scene of inputs/ gives a grid whose cell count matches its ndim.
    for name in os.listdir(os.path.join(ROOT, "inputs")):
        if name.endswith(".nml"):
            text = open(os.path.join(ROOT, "inputs", name)).read()
            g = Grid.from_input(text)
            assert g.ndim in (1, 2, 3) and len(g.ncells) == g.ndim, name
            assert all(g.spacing > 0), name


def test_edit_replaces_adds_and_drops():
    text = ("&run\n  name = 'a'\n  t_end = 1.0 ! end\n/\n&output\n  dir = 'out'\n/\n"
            "&benchmark\n  name = 'biot_column'\n/\n")
    out = namelist.edit(text, {"t_end": "0.5", "output.dir": "'x'", "output.frame_interval": "0.1",
                               "shape.kernel": "'cubic'"}, drop=("benchmark",))
    assert namelist.group(out, "run") == {"name": ["a"], "t_end": [0.5]}
    assert namelist.group(out, "output") == {"dir": ["x"], "frame_interval": [0.1]}
    assert namelist.group(out, "shape") == {"kernel": ["cubic"]}
    assert namelist.groups(out, "benchmark") == []
    # Without drop, the layout and the comments are kept.
    kept = namelist.edit(text, {"t_end": "0.5"})
    assert "t_end = 0.5 ! end" in kept and "&benchmark" in kept
