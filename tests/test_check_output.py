#!/usr/bin/env python3
"""scripts/check_output.py finds what a corrupt output file looks like.

Usage: test_check_output.py FILE.h5 WORKDIR
       test_check_output.py --drained DPMPM MPIEXEC SCENE WORKDIR

FILE.h5 (with its .xmf) is a good dpmpm output file of at least two frames. Each test
copies it into WORKDIR, damages one thing in the last frame, and expects check_output.py
to fail with the message that names it; the untouched copy must pass.

With --drained, SCENE (inputs/seepage_layers_1d.nml) is first run on 2 ranks, shortened
and with ten times the head so that fluid points leave at x = 1 m and enter at x = 0
between frames, and the damage is done to the fluid points of that run.
"""
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CHECK = os.path.join(HERE, "..", "scripts", "check_output.py")


def copy(src, workdir, name):
    base = os.path.join(workdir, name)
    shutil.copy(src, base + ".h5")
    text = open(os.path.splitext(src)[0] + ".xmf").read()
    src_base = os.path.basename(os.path.splitext(src)[0])
    with open(base + ".xmf", "w") as f:
        f.write(text.replace(src_base + ".h5:", name + ".h5:"))
    return base + ".h5"


def check(path):
    r = subprocess.run([sys.executable, CHECK, path], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


def last_set(f):
    return f["frames"][sorted(f["frames"])[-1]]["solid"]


def test_good_file_passes(src, workdir):
    rc, out = check(copy(src, workdir, "good"))
    return rc == 0, out


def test_ids_overwritten_by_doubles(src, workdir):
    path = copy(src, workdir, "ids")
    with h5py.File(path, "r+") as f:
        ids = last_set(f)["id"]
        half = ids.shape[0] // 2
        # A block of doubles where the ids should be, as a misplaced collective write left it.
        ids[:half] = np.arange(half, dtype=np.float64).view(np.int64) + 1
    rc, out = check(path)
    return rc != 0 and "ids differ from the first frame" in out, out


def test_mass_changed(src, workdir):
    path = copy(src, workdir, "mass")
    with h5py.File(path, "r+") as f:
        m = last_set(f)["mass"]
        m[0] = 2.0 * m[0]
    rc, out = check(path)
    return rc != 0 and "total mass" in out, out


def test_non_finite_velocity(src, workdir):
    path = copy(src, workdir, "nan")
    with h5py.File(path, "r+") as f:
        v = last_set(f)["v"]
        v[0, 0] = np.nan
    rc, out = check(path)
    return rc != 0 and "/v has non-finite values" in out, out


def test_xdmf_time_differs(src, workdir):
    path = copy(src, workdir, "time")
    with h5py.File(path, "r+") as f:
        g = f["frames"][sorted(f["frames"])[-1]]
        g.attrs.modify("time", g.attrs["time"] + 1.0)
    rc, out = check(path)
    return rc != 0 and "frame 1 at time" in out, out


def test_truncated_file_is_reported(src, workdir):
    path = copy(src, workdir, "torn")
    size = os.path.getsize(path)
    with open(path, "r+b") as f:
        f.truncate(size // 2)
    rc, out = check(path)
    return rc == 1 and "cannot be read" in out and "Traceback" not in out, out


def fluid_frames(f):
    return [f["frames"][k]["fluid"] for k in sorted(f["frames"])]


def test_drained_run_passes(src, workdir):
    path = copy(src, workdir, "drained_good")
    with h5py.File(path, "r") as f:
        ids = [set(g["id"][...].tolist()) for g in fluid_frames(f)]
    left = set.union(*ids[:-1]) - ids[-1]
    entered = ids[-1] - ids[0]
    rc, out = check(path)
    # The run must exchange points, or the test checks nothing.
    return rc == 0 and len(left) > 0 and len(entered) > 0, out + f"left {left}, entered {entered}"


def test_drained_mass_records(src, workdir):
    """The diagnostics record the mass through the drained faces: the mass that left by
    the end is that of the ids gone between the first and the last frame (a point's mass
    is fixed), and the outflow record made larger by a thousandth of the first frame's
    fluid mass breaks the balance of the records."""
    path = copy(src, workdir, "drained_records")
    with h5py.File(path, "r") as f:
        frames = fluid_frames(f)
        first, last = frames[0], frames[-1]
        gone = ~np.isin(first["id"][...], last["id"][...])
        left_first = float(np.sum(first["mass"][...][gone]))
        out = f["diagnostics"]["outflow_mass"][...]
        inflow = f["diagnostics"]["inflow_mass"][...]
        fluid0 = float(np.sum(first["mass"][...]))
    ok_good = out[-1] > 0 and inflow[-1] > 0 and abs(out[-1] - left_first) <= 1e-12 * fluid0
    with h5py.File(path, "r+") as f:
        d = f["diagnostics"]["outflow_mass"]
        d[-1] = d[-1] + 1e-3 * fluid0
    rc, text = check(path)
    return ok_good and rc != 0 and "not the first record's + inflow - outflow" in text, \
        text + f" outflow {out[-1]!r}, left since the first frame {left_first!r}, inflow {inflow[-1]!r}"


def test_drained_id_repeated(src, workdir):
    path = copy(src, workdir, "drained_twice")
    with h5py.File(path, "r+") as f:
        ids = fluid_frames(f)[-1]["id"]
        ids[1] = ids[0]
    rc, out = check(path)
    return rc != 0 and "1 ids repeated" in out, out


def test_drained_mass_changed(src, workdir):
    path = copy(src, workdir, "drained_mass")
    with h5py.File(path, "r+") as f:
        m = fluid_frames(f)[-1]["mass"]
        m[0] = 1.001 * m[0]
    rc, out = check(path)
    return rc != 0 and "fluid: total mass" in out and "changed their mass" in out, out


def test_drained_departed_id_back(src, workdir):
    path = copy(src, workdir, "drained_back")
    with h5py.File(path, "r+") as f:
        frames = fluid_frames(f)
        gone = sorted(set(frames[0]["id"][...].tolist()) - set(frames[-1]["id"][...].tolist()))
        ids = frames[-1]["id"]
        ids[0] = gone[0]
    rc, out = check(path)
    return rc != 0 and "ids that left come back" in out, out


def test_drained_new_id_below(src, workdir):
    path = copy(src, workdir, "drained_low")
    with h5py.File(path, "r+") as f:
        ids = fluid_frames(f)[-1]["id"]
        ids[0] = 0
    rc, out = check(path)
    return rc != 0 and "new ids not above every earlier id" in out, out


def test_drained_solid_stays_strict(src, workdir):
    path = copy(src, workdir, "drained_solid")
    with h5py.File(path, "r+") as f:
        ids = last_set(f)["id"]
        ids[0] = ids[...].max() + 1
    rc, out = check(path)
    return rc != 0 and "solid: ids differ from the first frame" in out, out


def run_drained(dpmpm, mpiexec, scene, workdir):
    """The scene run into workdir on 2 ranks; returns its output file."""
    text = open(scene).read()
    for pat, val in ((r"t_end\s*=\s*[^\s,/]+", "t_end = 0.2"),
                     (r"frame_interval\s*=\s*[^\s,/]+", "frame_interval = 0.04"),
                     (r"dir\s*=\s*'[^']*'", f"dir = '{workdir}'"),
                     (r"pore_pressure\s*=\s*9810\.0", "pore_pressure = 98100.0")):
        text, n = re.subn(pat, val, text, count=1)
        if n != 1:
            sys.exit(f"{scene}: {pat} not found")
    nml = os.path.join(workdir, "drained.nml")
    with open(nml, "w") as f:
        f.write(text)
    r = subprocess.run([mpiexec, "--oversubscribe", "-n", "2", dpmpm, nml], cwd=workdir,
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"the run failed:\n{r.stdout}\n{r.stderr}")
    name = re.search(r"name\s*=\s*'([^']*)'", text).group(1)
    return os.path.join(workdir, name + ".h5")


def main():
    if sys.argv[1] == "--drained":
        dpmpm, mpiexec, scene, workdir = sys.argv[2:6]
        os.makedirs(workdir, exist_ok=True)
        src = run_drained(os.path.abspath(dpmpm), mpiexec, os.path.abspath(scene),
                          os.path.abspath(workdir))
        tests = [test_drained_run_passes, test_drained_mass_records, test_drained_id_repeated,
                 test_drained_mass_changed,
                 test_drained_departed_id_back, test_drained_new_id_below,
                 test_drained_solid_stays_strict]
    else:
        src, workdir = sys.argv[1], sys.argv[2]
        os.makedirs(workdir, exist_ok=True)
        tests = [test_good_file_passes, test_ids_overwritten_by_doubles, test_mass_changed,
                 test_non_finite_velocity, test_xdmf_time_differs,
                 test_truncated_file_is_reported]
    failed = 0
    for t in tests:
        ok, out = t(src, workdir)
        print(f"test: {t.__name__[5:]}: {'ok' if ok else 'FAILED'}")
        if not ok:
            failed += 1
            print("  " + out.replace("\n", "\n  "))
    print(f"{len(tests) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
