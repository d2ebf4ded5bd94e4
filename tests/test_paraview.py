#!/usr/bin/env python3
"""ParaView reads dpmpm's XDMF sidecar whole with each of its three XDMF readers (XDMF
Reader, Xdmf3ReaderS, Xdmf3ReaderT): every frame time, at every time one dataset per set
with points in that frame, named after the set where the reader names blocks, and every
dataset of the set (stress included) as a point array equal to the HDF5 file, matched by
id. Fails on a reader that misses a time, a set or an array.

Usage: test_paraview.py WORKDIR FILE.h5 [FILE.h5 ...]
Runs tests/paraview_dump.py with pvpython; exits 77 (skipped) where ParaView's pvpython
is not installed (Debian: apt-get install paraview).
"""
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
READERS = ("XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT")


def set_name(reader, names):
    """The set a dataset stands for, as the reader names it: the XDMF Reader names the
    block of the set's collection; Xdmf3ReaderT names the dataset itself, numbered from its
    second time on (solid[1]); Xdmf3ReaderS names nothing (None: matched by order)."""
    if reader == "XDMFReader":
        return names[0] if names else ""
    if reader == "Xdmf3ReaderT":
        return re.sub(r"\[\d+\]$", "", names[-2] if len(names) > 1 else "")
    return None


def main():
    workdir = sys.argv[1]
    pvpython = shutil.which("pvpython")
    if pvpython is None:
        print("skipped: ParaView's pvpython is not installed (apt-get install paraview)")
        return 77
    os.makedirs(workdir, exist_ok=True)
    return max(check_file(pvpython, h5path, workdir) for h5path in sys.argv[2:])


def check_file(pvpython, h5path, workdir):
    dump = os.path.join(workdir, os.path.basename(h5path) + ".npz")
    xmf = os.path.splitext(h5path)[0] + ".xmf"
    r = subprocess.run([pvpython, os.path.join(HERE, "paraview_dump.py"), xmf, dump],
                       capture_output=True, text=True, timeout=240)
    if r.returncode != 0:
        print(r.stdout + r.stderr)
        return 1
    pv = np.load(dump)
    status = 0
    with h5py.File(h5path, "r") as f:
        for reader in READERS:
            bad = check_reader(pv, reader, f)
            for b in bad[:20]:
                print(f"  {reader}: {b}")
            print(f"{reader} read {len(f['frames'])} frames of {h5path}: "
                  f"{'all arrays equal the file' if not bad else str(len(bad)) + ' differences'}")
            status = max(status, 1 if bad else 0)
    return status


def check_reader(pv, reader, f):
    bad = []
    ndim = int(f.attrs["ndim"])
    frames = sorted(f["frames"])
    times = [float(f["frames"][fr].attrs["time"]) for fr in frames]
    got_times = pv[reader + "/times"]
    if len(got_times) != len(times) or not np.allclose(got_times, times, rtol=1e-12, atol=0):
        bad.append(f"times {[float(t) for t in got_times]} against {times}")
        return bad
    for k, fr in enumerate(frames):
        sets = [s for s in ("solid", "fluid") if s in f["frames"][fr]
                and f["frames"][fr][s]["id"].shape[0] > 0]
        blocks = []
        while f"{reader}/t{k}/b{len(blocks)}/names" in pv:
            blocks.append(f"{reader}/t{k}/b{len(blocks)}/")
        names = [set_name(reader, list(pv[key + "names"])) for key in blocks]
        if reader == "Xdmf3ReaderS":
            names = sets[:len(names)] if len(names) <= len(sets) else names
        if names != sets:
            bad.append(f"frame {fr}: datasets {names}, sets with points {sets}")
            continue
        for key, s in zip(blocks, sets):
            bad += compare_set(pv, key, f["frames"][fr][s], ndim, f"frame {fr}/{s}")
    return bad


def compare_set(pv, key, g, ndim, where):
    """Every dataset of the HDF5 point set g against the arrays ParaView shows."""
    bad = []
    ids = pv[key + "id"].astype(np.int64) if key + "id" in pv else None
    if ids is None or not np.array_equal(np.sort(ids), np.sort(g["id"][...])):
        return [f"{where}: ids differ"]
    n = len(ids)
    order = np.argsort(g["id"][...])[np.argsort(np.argsort(ids))]
    want = {name: g[name][...].reshape(n, -1) for name in g if name != "x"}
    want["points"] = g["x"][...].reshape(n, -1)
    for name, val in want.items():
        if key + name not in pv:
            bad.append(f"{where}: no array {name}")
            continue
        got = pv[key + name].reshape(n, -1)
        exp = val[order]
        # Positions have three components, 2D vectors too in the XDMF Reader: the ones
        # beyond the file's are zero.
        if got.shape[1] > exp.shape[1] and name in ("points", "v", "displacement"):
            if np.any(got[:, exp.shape[1]:] != 0):
                bad.append(f"{where}: {name} has non-zero components beyond {ndim}")
            got = got[:, :exp.shape[1]]
        if got.shape != exp.shape or not np.array_equal(got, exp.astype(got.dtype)):
            bad.append(f"{where}: {name} differs from the HDF5 file")
    return bad


if __name__ == "__main__":
    sys.exit(main())
