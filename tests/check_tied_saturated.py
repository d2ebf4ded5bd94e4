#!/usr/bin/env python3
"""The saturated column between tied sides on a shaken base (inputs/tied_saturated_2d.nml;
doc/verification.md, "Saturated column between tied sides").

    check_tied_saturated.py <dpmpm> <mpiexec> <scene.nml> <work dir>

The scene's first 0.5 s on 1 rank and its first 0.12 s on 2 ranks (each rank owning one
tied face):
- the column stays the free field: its two columns of points are each other's image under
  a shift of one cell, so the difference of each point's velocity, stress and pore
  pressure from its image's is round-off (bound 1e-10 of the largest value; measured
  below 4e-14; before the pairs were joined it was 6e-4 at 0.1 s);
- the surface velocity follows d'Alembert's sum of delayed copies of the base velocity for
  the shear wave of the mixture, c = sqrt(G / rho_sat) (low permeability: the water moves
  with the skeleton): RMS error over 0.5 s 1.32e-2 of the peak (12 cells over the depth),
  bound 1.7e-2;
- 1 and 2 ranks give the same frames to round-off (bound 1e-10 of the largest value;
  measured below 1e-14).
"""
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_site_response import finish, run_text  # noqa: E402

E, NU, RHO_S, RHO_F, N_F, H = 2.0e7, 0.3, 2650.0, 1000.0, 0.4594594594594595, 6.0
ROUND_OFF = 1e-10


def scene_text(scene, t_end, probe):
    """The scene with its base record by absolute path, its output here, t_end, frames
    every 0.05 s and (probe) a probe at the surface recording every step."""
    text = open(scene).read()
    rec = os.path.join(os.path.dirname(os.path.abspath(scene)), "liquefaction_base_2hz.txt")
    text = text.replace("file_x = 'liquefaction_base_2hz.txt'", f"file_x = '{rec}'")
    text = re.sub(r"t_end = [0-9.]+", f"t_end = {t_end}", text)
    text = text.replace("dir = 'out'", "dir = '.'")
    extra = ", nprobes = 1, probe_x = 0.5, probe_y = 6.0, probe_every = 1" if probe else ""
    return re.sub(r"frame_interval = [0-9.]+", "frame_interval = 0.05" + extra, text)


def run(exe, mpiexec, ranks, text, work):
    return run_text(exe, mpiexec, ranks, text, work, "tied_saturated_2d.h5", timeout=300)


def frames(path):
    """{(step, time): {set: {name: values sorted by point id}}} of every frame."""
    out = {}
    with h5py.File(path, "r") as f:
        for k in sorted(f["frames"].keys()):
            fr = f["frames"][k]
            sets = {}
            for ph in ("solid", "fluid"):
                g = fr[ph]
                order = np.argsort(g["id"][...])
                sets[ph] = {n: g[n][...][order] for n in ("id", "x", "v", "stress", "pore_pressure")
                            if n in g}
            out[(int(fr.attrs["step"]), float(fr.attrs["time"]))] = sets
    return out


def image_pairs(first):
    """Indices (in id order) of the points of x < 0.5 and of their images at x + 0.5, by
    the positions of the first frame."""
    x = first["x"]
    key = {(round(p[0] % 0.5, 9), round(p[1], 9), p[0] >= 0.5): i for i, p in enumerate(x)}
    pairs = [(i, key[(a, b, True)]) for (a, b, hi), i in key.items() if not hi]
    return np.array(pairs)


def antisymmetric(fr):
    """The largest difference of a point's velocity, stress and pore pressure from its
    image's, each over the largest value, over the frames fr."""
    t0 = min(fr)
    worst = 0.0
    for ph, names in (("solid", ("v", "stress")), ("fluid", ("v", "pore_pressure"))):
        pr = image_pairs(fr[t0][ph])
        for sets in fr.values():
            for n in names:
                a = sets[ph][n]
                scale = max(np.abs(a).max(), 1e-300)
                worst = max(worst, np.abs(a[pr[:, 0]] - a[pr[:, 1]]).max() / scale)
    return worst


def surface_error(path, record):
    """RMS difference of the probe's horizontal velocity from d'Alembert's sum, over its peak."""
    with h5py.File(path, "r") as f:
        t = f["probes/time"][...]
        v = f["probes/velocity"][...][:, 0]
    rec = np.loadtxt(record)
    c = np.sqrt(E / (2.0 * (1.0 + NU)) / ((1.0 - N_F) * RHO_S + N_F * RHO_F))
    period = H / c
    vs = np.zeros_like(t)
    for n in range(int(t[-1] / (2.0 * period)) + 2):
        vs += 2.0 * (-1) ** n * np.interp(t - (2 * n + 1) * period, rec[:, 0], rec[:, 1], left=0.0,
                                          right=0.0)
    peak = np.abs(vs).max()
    return np.sqrt(np.mean((v - vs) ** 2)) / peak, peak


def main():
    exe, mpiexec, scene, work = sys.argv[1:5]
    record = os.path.join(os.path.dirname(os.path.abspath(scene)), "liquefaction_base_2hz.txt")
    fails = []
    one = run(exe, mpiexec, 1, scene_text(scene, 0.5, True), os.path.join(work, "np1"))
    # (to 0.12 s: its frames of 0.05 and 0.1 s are those of the 1-rank run, not shortened
    # to end at t_end)
    two = run(exe, mpiexec, 2, scene_text(scene, 0.12, False), os.path.join(work, "np2"))
    f1, f2 = frames(one), frames(two)
    for ranks, fr in ((1, f1), (2, f2)):
        a = antisymmetric(fr)
        print(f"{ranks} ranks: difference of the points from their images {a:.2e} of the largest")
        if not a <= ROUND_OFF:
            fails.append(f"{ranks} ranks: the column's two halves differ by {a:.2e} (bound {ROUND_OFF})")
    rms, peak = surface_error(one, record)
    print(f"surface velocity against d'Alembert's sum (c = sqrt(G/rho_sat)): RMS {rms:.3e} of the "
          f"peak {peak:.4f} m/s")
    # measured 1.32e-2 (doc/verification.md); bound measured + 30 %
    if not rms <= 1.7e-2:
        fails.append(f"surface velocity RMS error {rms:.3e} above 1.7e-2")
    common = sorted(set(f1) & set(f2))
    if len(common) < 3:
        fails.append(f"1 and 2 ranks share {len(common)} frames")
    worst = 0.0
    for t in common:
        for ph, names in (("solid", ("x", "v", "stress")), ("fluid", ("x", "v", "pore_pressure"))):
            if not np.array_equal(f1[t][ph]["id"], f2[t][ph]["id"]):
                fails.append(f"t = {t[1]}: the {ph} points differ on 1 and 2 ranks")
                continue
            for n in names:
                a, b = f1[t][ph][n], f2[t][ph][n]
                worst = max(worst, np.abs(a - b).max() / max(np.abs(a).max(), 1e-300))
    print(f"1 and 2 ranks over {len(common)} frames to {common[-1][1]:.4f} s: {worst:.2e} of the largest")
    if not worst <= ROUND_OFF:
        fails.append(f"1 and 2 ranks differ by {worst:.2e} (bound {ROUND_OFF})")
    vmax = max(np.abs(s["solid"]["v"]).max() for s in f1.values())
    if not vmax > 0.1:
        fails.append(f"the column hardly moves (largest speed {vmax} m/s)")
    return finish(fails)


if __name__ == "__main__":
    sys.exit(main())
