"""Files written by dpmpm during the test: reading, matching by id across rank counts,
comparison, the XDMF rewrite and the command line."""
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

import dpmpm
from conftest import ROOT
from synthetic import write_synthetic

PYENV = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "scripts", "python"))


def cli(*args):
    return subprocess.run([sys.executable, "-m", "dpmpm", *args], capture_output=True,
                          text=True, env=PYENV)


def test_read_run(run_np2):
    with dpmpm.open_run(run_np2) as run, h5py.File(run_np2, "r") as f:
        assert run.ndim == 2 and run.nranks == 2
        assert len(run.frames) == len(f["frames"]) == 4
        assert np.all(np.diff(run.times) > 0)
        assert run.set_names == ["solid", "fluid"]
        assert run.grid.ncells.tolist() == [4, 20]
        for fr in run.frames:
            for s in ("solid", "fluid"):
                ps = fr[s]
                raw = f["frames"][fr.name][s]
                ids = raw["id"][...]
                assert np.all(np.diff(ps.id) > 0)
                assert sorted(ids.tolist()) == ps.id.tolist()
                for d in ps.keys():
                    # Each row is the file's row of the same id.
                    where = {i: k for k, i in enumerate(ids)}
                    rows = [where[i] for i in ps.id]
                    np.testing.assert_array_equal(ps[d], raw[d][...][rows])
        d = run.diagnostics
        assert set(d) >= {"time", "step", "kinetic_energy", "wall_time"}
        np.testing.assert_array_equal(d["step"], f["diagnostics/step"][...])
        assert run.input == f["input"][()].decode()


def test_ranks_match_by_id(run_np1, run_np2):
    with dpmpm.open_run(run_np1) as a, dpmpm.open_run(run_np2) as b:
        # The test means something only when the two files order the points differently.
        with h5py.File(run_np1, "r") as f1, h5py.File(run_np2, "r") as f2:
            last = sorted(f1["frames"])[-1]
            assert not np.array_equal(f1[f"frames/{last}/fluid/id"][...],
                                      f2[f"frames/{last}/fluid/id"][...])
        c = dpmpm.compare_runs(a, b)
        assert not c.problems, c.problems
        assert c.max_rel <= 1e-10, "\n".join(c.table())
        assert ("fluid", "pore_pressure") in c.datasets
        # The pore pressure has built up: a comparison of zeros would prove nothing.
        assert np.max(np.abs(a.frames[-1]["fluid"]["pore_pressure"])) > 100.0


def perturbed_copy(src, dst, edit):
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        edit(f)
    return dst


def test_compare_sees_differences(run_np2, tmp_path):
    last = None

    def bump(f):
        nonlocal last
        last = sorted(f["frames"])[-1]
        ds = f[f"frames/{last}/fluid/pore_pressure"]
        v = ds[...]
        v[3] += 0.5
        ds[...] = v

    bad = perturbed_copy(run_np2, str(tmp_path / "bumped.h5"), bump)
    with dpmpm.open_run(run_np2) as a, dpmpm.open_run(bad) as b:
        c = dpmpm.compare_runs(a, b)
        r = c.datasets[("fluid", "pore_pressure")]
        assert r["max_abs"] == pytest.approx(0.5, rel=1e-9)
        assert r["frame"] == last
        scale = np.max(np.abs(a.frames[-1]["fluid"]["pore_pressure"]))
        assert r["max_rel"] == pytest.approx(0.5 / scale, rel=1e-9)
        assert c.datasets[("solid", "x")]["max_abs"] == 0.0
        assert not c.agrees(1e-6)

    def swap_rows(f):
        # Two rows of x exchanged without their ids: matching by id must see it.
        ds = f["frames/000001/solid/x"]
        v = ds[...]
        v[[0, 1]] = v[[1, 0]]
        ds[...] = v

    bad2 = perturbed_copy(run_np2, str(tmp_path / "swapped.h5"), swap_rows)
    with dpmpm.open_run(run_np2) as a, dpmpm.open_run(bad2) as b:
        assert dpmpm.compare_runs(a, b).datasets[("solid", "x")]["max_abs"] > 0.0


def xml_tree(path):
    """The sidecar as nested tuples (tag, attributes, text, children); times as floats."""
    def conv(e):
        attrs = dict(e.attrib)
        if e.tag == "Time":
            attrs["Value"] = float(attrs["Value"])
        return (e.tag, attrs, (e.text or "").strip(), [conv(c) for c in e])
    return conv(ET.parse(path).getroot())


def test_xdmf_rewrite_equals_the_writer(run_np1, run_np2, tmp_path):
    for h5 in (run_np1, run_np2):
        out = str(tmp_path / (os.path.basename(h5) + ".xmf"))
        dpmpm.write_xdmf(h5, out)
        assert xml_tree(out) == xml_tree(os.path.splitext(h5)[0] + ".xmf")


def test_xdmf_rewrite_passes_check_output(run_np2, tmp_path):
    copy = str(tmp_path / "copy.h5")
    shutil.copy(run_np2, copy)
    r = cli("xdmf", copy)
    assert r.returncode == 0, r.stderr
    assert os.path.exists(str(tmp_path / "copy.xmf"))
    chk = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "check_output.py"),
                          copy], capture_output=True, text=True)
    assert chk.returncode == 0, chk.stdout


def test_xdmf_without_fluid_stress(tmp_path):
    h5 = write_synthetic(str(tmp_path / "nofs.h5"))
    tree = ET.fromstring(dpmpm.xdmf_text(h5))
    frames = tree.findall("Domain/Grid/Grid")
    assert len(frames) == 2
    for frame in frames:
        colls = frame.findall("Grid")
        assert [c.get("Name") for c in colls] == ["solid", "fluid"]
        for c in colls:
            names = [a.get("Name") for a in c.iter("Attribute")]
            types = {a.get("Name"): a.get("AttributeType") for a in c.iter("Attribute")}
            assert ("stress" in names) == (c.get("Name") == "solid")
            assert types.get("stress", "Matrix") == "Matrix"
            assert ("pore_pressure" in names) == (c.get("Name") == "fluid")
    with h5py.File(h5, "r") as f:
        for item in tree.iter("DataItem"):
            if item.get("Format") == "HDF":
                fname, _, dset = item.text.partition(":")
                assert fname == "nofs.h5" and dset in f
                assert tuple(int(k) for k in item.get("Dimensions").split()) == f[dset].shape


def main(*args):
    """The command line in this process: its exit status (argparse errors give 2)."""
    from dpmpm.cli import main as cli_main
    try:
        return cli_main(list(args))
    except SystemExit as e:
        return e.code


def test_cli_exit_codes(run_np1, run_np2, tmp_path, capsys):
    # As a module in its own process once; the rest in this process (faster).
    r = cli("info", run_np2)
    assert r.returncode == 0 and "fluid: 320 points" in r.stdout, r.stdout + r.stderr
    assert main("compare", run_np1, run_np2) == 0

    def bump(f):
        ds = f["frames/000002/solid/stress"]
        v = ds[...]
        v[0, 1] *= 1.01
        ds[...] = v
    bad = perturbed_copy(run_np2, str(tmp_path / "b.h5"), bump)
    capsys.readouterr()
    assert main("compare", run_np2, bad) == 1
    assert "differ" in capsys.readouterr().out
    assert main("compare", run_np2, bad, "--rtol", "0.02") == 0
    assert main("info", str(tmp_path / "missing.h5")) == 2
    assert main("profile", run_np2, "no_such_quantity") == 2
    assert main("nonsense") == 2
    png = str(tmp_path / "p.png")
    assert main("plot", run_np2, "-o", png, "--color", "stress_yy") == 0
    assert os.path.getsize(png) > 0
    capsys.readouterr()
    assert main("profile", run_np2, "pore_pressure", "--frame", "3") == 0
    lines = [l for l in capsys.readouterr().out.splitlines() if not l.startswith("#")]
    assert len(lines) == 20
    assert main("terzaghi", run_np2, "-o", str(tmp_path / "t.png")) == 0
    # A dry scene is no consolidation: a clear error, status 2.
    assert main("terzaghi", write_synthetic(str(tmp_path / "dry.h5"))) == 2


def test_plot_frames_script(run_np2, tmp_path):
    png = str(tmp_path / "frames.png")
    r = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "plot_frames.py"),
                        run_np2, "-o", png], capture_output=True, text=True)
    assert r.returncode == 0 and r.stdout.strip() == png and os.path.getsize(png) > 0


def test_closed_run_says_so(run_np2):
    # After its `with` block a Run must not answer as if the file had no sets (a closed
    # h5py group looks empty): every read says the file is closed.
    with dpmpm.open_run(run_np2) as run:
        fr = run.frames[-1]
        inside = fr["fluid"]["pore_pressure"].copy()
    assert run.closed and "closed" in repr(run)
    assert len(inside) > 0
    reads = [lambda: fr["fluid"], lambda: fr.get("fluid"), lambda: "fluid" in fr,
             lambda: fr.set_names, lambda: run.set_names, lambda: run.diagnostics,
             lambda: run.verification, lambda: dpmpm.profile(run, "pore_pressure")]
    for read in reads:
        with pytest.raises(dpmpm.ClosedRunError, match="is closed"):
            read()
    # A point set taken inside the block says so too, even for a dataset it had read.
    with dpmpm.open_run(run_np2) as run:
        ps = run.frames[-1]["fluid"]
        ps["pore_pressure"]
    with pytest.raises(dpmpm.ClosedRunError, match="is closed"):
        ps["pore_pressure"]
    # The command line turns it into exit status 2 like any unreadable input, not a NaN.
    assert issubclass(dpmpm.ClosedRunError, ValueError)


def test_cli_into_a_closed_pipe(run_np2):
    # `python3 -m dpmpm profile ... | head -3`: the reader goes away before the output is
    # written; no traceback, exit status 0. The pipe is closed before the program starts
    # writing, the case that `head` makes by chance.
    cmd = [sys.executable, "-m", "dpmpm", "profile", run_np2, "pore_pressure",
           "--frame", "0", "--frame", "1", "--frame", "2", "--frame", "3"]
    for _ in range(2):
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=PYENV)
        p.stdout.close()
        err = p.stderr.read().decode()
        p.stderr.close()
        assert p.wait() == 0 and "Error" not in err, err
    r = subprocess.run(["bash", "-c", 'set -o pipefail; "$@" | head -3', "sh", *cmd],
                       capture_output=True, text=True, env=PYENV)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    assert len(r.stdout.splitlines()) == 3


def test_energy_plot_labels_the_net_work(run_np2):
    # /diagnostics/external_work is the work of the loads and gravity net of drag and
    # plastic dissipation (doc/output.md); the legend must not call it the work alone.
    import matplotlib.pyplot as plt
    from dpmpm.plot import plot_energies
    fig, ax = plt.subplots()
    with dpmpm.open_run(run_np2) as run:
        plot_energies(ax, run)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    plt.close(fig)
    work = [s for s in labels if "work" in s]
    assert len(work) == 1 and "net of drag" in work[0] and "dissipation" in work[0], labels
