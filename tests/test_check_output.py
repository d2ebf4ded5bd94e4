#!/usr/bin/env python3
"""scripts/check_output.py finds what a corrupt output file looks like.

Usage: test_check_output.py FILE.h5 WORKDIR

FILE.h5 (with its .xmf) is a good dpmpm output file of at least two frames. Each test
copies it into WORKDIR, damages one thing in the last frame, and expects check_output.py
to fail with the message that names it; the untouched copy must pass.
"""
import os
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


def main():
    src, workdir = sys.argv[1], sys.argv[2]
    os.makedirs(workdir, exist_ok=True)
    tests = [test_good_file_passes, test_ids_overwritten_by_doubles, test_mass_changed,
             test_non_finite_velocity, test_xdmf_time_differs, test_truncated_file_is_reported]
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
