"""Runs from Python (dpmpm.simulate, dpmpm.study) on short runs of the consolidating
column made here: the output and progress of a run, each exit code as its exception with
the log's message, a restart from the checkpoint, and a study of three scenes."""
import os

import numpy as np
import pytest

import dpmpm
from conftest import ROOT


@pytest.fixture(autouse=True)
def need_binary():
    if not os.environ.get("DPMPM_BIN"):
        pytest.skip("DPMPM_BIN not set: no dpmpm executable to run")


def column(name, t_end=0.02, **run):
    s = dpmpm.Scene.read(os.path.join(ROOT, "inputs", "consolidation_2d.nml"))
    s.set(run=dict({"name": name, "t_end": t_end, "progress_seconds": 0.001}, **run),
          output={"dir": "out", "frame_interval": t_end / 2})
    return s


def test_run_with_progress(tmp_path, capsys):
    r = dpmpm.simulate(column("sim"), ranks=2, workdir=tmp_path)
    assert r.output == str(tmp_path / "out" / "sim.h5") and os.path.isfile(r.log)
    assert os.path.isfile(tmp_path / "out" / "sim.nml")
    assert r.read(lambda run: (run.nranks, len(run.frames))) == (2, 3)
    # The bar follows the log's progress lines ("... NN.N%  ETA ...") to 100 %.
    assert r.progress and all(0.0 <= p <= 100.0 for p in r.progress)
    assert np.all(np.diff(r.progress) >= 0)
    err = capsys.readouterr().err
    assert "sim: 100.0%" in err and "done" in err, err[-500:]


def test_bad_input_raises_with_the_problems(tmp_path):
    with pytest.raises(dpmpm.InputError) as e:
        dpmpm.simulate(column("bad", t_end=-1.0), workdir=tmp_path, progress=False)
    assert e.value.status == 2
    assert any(p.startswith("&run t_end = -1.0: must be > 0") for p in e.value.problems)
    assert "t_end = -1.0" in str(e.value) and e.value.log.endswith("bad.log")


def test_stop_with_checkpoint_then_restart(tmp_path):
    s = column("stop", t_end=0.3, max_wall_time=0.05)
    with pytest.raises(dpmpm.StoppedEarly) as e:
        dpmpm.simulate(s, workdir=tmp_path, progress=False)
    assert e.value.status == 3 and "max_wall_time" in str(e.value)
    assert e.value.checkpoint == str(tmp_path / "out" / "stop.ckpt.h5")
    assert os.path.isfile(e.value.checkpoint)
    # Continue it: the same scene without the wall limit, from the checkpoint.
    s["run"]["max_wall_time"] = 0.0
    r = dpmpm.simulate(s, workdir=tmp_path, restart=True, progress=False)
    assert "restart from" in open(r.log).read()
    assert abs(r.read(lambda run: run.times[-1]) - 0.3) < 1e-3


def test_monitor_stop(tmp_path):
    with pytest.raises(dpmpm.MonitorStop) as e:
        dpmpm.simulate(column("grows", growth_limit=1e-3), workdir=tmp_path, progress=False)
    assert e.value.status == 4 and "monitor" in str(e.value)
    assert "mpirun" not in str(e.value)       # dpmpm's lines, not the launcher's


def test_study_side_by_side(tmp_path):
    # Three conductivities (one refused), two at a time on one rank each: the outcomes
    # come back in order, the refused one as its error.
    scenes = []
    for k, perm in enumerate([1e-4, 1e-3, -1.0]):
        s = column(f"perm{k}")
        [soil] = [m for m in s.groups("material") if "conductivity" in m]
        soil["conductivity"] = perm
        scenes.append(s)
    out = dpmpm.study(scenes, ranks=1, jobs=2, workdir=tmp_path, progress=False)
    assert [type(o) for o in out] == [dpmpm.Result, dpmpm.Result, dpmpm.InputError]
    assert [o.name for o in out[:2]] == ["perm0", "perm1"]
    finals = [o.read(lambda run: run.frames[-1]["fluid"]["pore_pressure"].mean())
              for o in out[:2]]
    assert finals[0] != finals[1]
    with pytest.raises(dpmpm.InputError):
        dpmpm.study(scenes[2:], workdir=tmp_path, progress=False, errors="raise")


def test_reuse_runs_only_what_is_missing(tmp_path):
    # With reuse a scene whose output exists is not run again: not even the binary is
    # looked for. A scene without output runs.
    first = dpmpm.simulate(column("again"), workdir=tmp_path, progress=False, reuse=True)
    assert not first.reused and first.command and first.wall > 0
    stamp = os.path.getmtime(first.output)
    again = dpmpm.simulate(column("again"), workdir=tmp_path, progress=False, reuse=True,
                           binary="/no/such/dpmpm")
    assert again.reused and again.command is None and again.output == first.output
    assert os.path.getmtime(again.output) == stamp
    assert again.read(lambda run: len(run.frames)) == 3
    with pytest.raises(FileNotFoundError, match="/no/such/dpmpm"):
        dpmpm.simulate(column("other"), workdir=tmp_path, progress=False, reuse=True,
                       binary="/no/such/dpmpm")


def test_no_launcher():
    with pytest.raises(FileNotFoundError, match="no-such-mpirun"):
        dpmpm.simulate(column("x"), mpirun="no-such-mpirun", progress=False)
