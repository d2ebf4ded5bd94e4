#!/usr/bin/env python3
"""ParaView reads dpmpm's XDMF sidecar right: the same block names (the point sets) at
every time, the frame times, and the values of every array, stress components by name,
equal to the HDF5 datasets matched by id.

Usage: test_paraview.py WORKDIR FILE.h5 [FILE.h5 ...]
Runs tests/paraview_dump.py with pvpython; exits 77 (skipped) where ParaView's pvpython
is not installed (Debian: apt-get install paraview).
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
STRESS = ("xx", "yy", "zz", "yz", "xz", "xy")


def expected_arrays(g, ndim):
    """Arrays as ParaView should show them, from the HDF5 point set g."""
    want = {}
    n = len(g["id"])
    for name in ("v", "displacement", "mass", "volume", "material", "porosity",
                 "pore_pressure"):
        if name in g:
            want[name] = g[name][...]
    # ParaView pads 2D vectors with a zero z component.
    if ndim == 2:
        for name in ("v", "displacement"):
            want[name] = np.hstack([want[name].reshape(n, 2), np.zeros((n, 1))])
    for j, c in enumerate(STRESS):
        if "stress" in g:
            want["stress_" + c] = g["stress"][:, j]
    x = g["x"][...].reshape(len(g["id"]), -1)
    want["points"] = np.hstack([x, np.zeros((x.shape[0], 3 - ndim))])
    return want


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
    bad = []
    with h5py.File(h5path, "r") as f:
        ndim = int(f.attrs["ndim"])
        frames = sorted(f["frames"])
        all_sets = {s for fr in frames for s in f["frames"][fr]}
        times = [float(f["frames"][fr].attrs["time"]) for fr in frames]
        if not np.allclose(pv["times"], times, rtol=1e-12, atol=0.0):
            bad.append(f"times {pv['times']} against {times}")
        for k, fr in enumerate(frames):
            sets = [s for s in f["frames"][fr] if f["frames"][fr][s]["id"].shape[0] > 0]
            names = []
            b = 0
            while f"t{k}/b{b}/name" in pv:
                names.append(str(pv[f"t{k}/b{b}/name"]))
                b += 1
            # A file of one set shows its cloud without a block name.
            if names == [""] and len(all_sets) == 1:
                names = list(all_sets)
            # Block names come from the sidecar, one per set, the same at every time.
            if names != [s for s in ("solid", "fluid") if s in sets]:
                bad.append(f"frame {fr}: blocks {names}, sets {sets}")
                continue
            for b, s in enumerate(names):
                g = f["frames"][fr][s]
                key = f"t{k}/b{b}/"
                ids = pv[key + "id"].astype(np.int64)
                if not np.array_equal(np.sort(ids), np.sort(g["id"][...])):
                    bad.append(f"frame {fr}/{s}: ids differ")
                    continue
                order = np.argsort(g["id"][...])[np.argsort(np.argsort(ids))]
                for name, val in expected_arrays(g, ndim).items():
                    if key + name not in pv:
                        bad.append(f"frame {fr}/{s}: ParaView shows no array {name}")
                        continue
                    got = pv[key + name].reshape(len(ids), -1)
                    exp = val[order].reshape(len(ids), -1)
                    if got.shape != exp.shape or not np.array_equal(got, exp.astype(got.dtype)):
                        bad.append(f"frame {fr}/{s}: {name} differs from the HDF5 file")
    for b in bad[:20]:
        print("  " + b)
    print(f"ParaView read {len(frames)} frames of {h5path}: "
          f"{'all arrays equal the file' if not bad else str(len(bad)) + ' differences'}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
