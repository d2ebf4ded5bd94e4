#!/usr/bin/env python3
"""The undrained path of a Modified Cam-Clay element in a dpmpm run against its closed form.

Usage: scripts/cam_clay_undrained.py FILE.h5 [FILE.h5 ...] [--bound B] [--png FILE]

Each file is a run's output (every solid point of every frame) or an element test's file
(dpmpm_element: every step).

For a normally consolidated soil that keeps its volume, p'/p'0 = (1 + eta^2/M^2)^(-Lambda),
Lambda = (lambda - kappa)/lambda, eta = q/p' (Wood 1990, ch. 7; doc/theory.md 5.7), along any
path of constant volume. For every solid point of every frame the relative difference of p'
from the closed form at the point's own eta is measured; lambda, kappa and M are read from
the run's echoed input, p'0 from its first frame. Prints a line per frame (mean eta, largest
difference, mean pore pressure) and exits 1 when the largest difference exceeds --bound.
--png draws q against p' of the points over the closed form.
"""
import argparse
import sys

import h5py
import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0] + "/python")
from dpmpm import namelist  # noqa: E402


def invariants(stress):
    """p' (compression positive) and q of Voigt stresses (n, 6), tension positive."""
    p = -(stress[:, 0] + stress[:, 1] + stress[:, 2]) / 3.0
    d = stress.copy()
    d[:, :3] += p[:, None]
    q = np.sqrt(1.5 * (d[:, 0] ** 2 + d[:, 1] ** 2 + d[:, 2] ** 2 + 2.0 * (d[:, 3:] ** 2).sum(1)))
    return p, q


def clay_constants(f):
    """lambda, kappa and M of the run's cam_clay material (its echoed input)."""
    text = f["input"][()]
    text = text.decode() if isinstance(text, bytes) else str(text)
    for m in namelist.groups(text, "material"):
        if str(m.get("model", [""])[0]).strip().lower() == "cam_clay":
            return (float(m["compression_index"][0]), float(m["swelling_index"][0]),
                    float(m["critical_state_ratio"][0]))
    raise SystemExit("no cam_clay material in the run's input")


def run_paths(f, big, mcs):
    """A run's solid points, frame by frame: p0 and a list of (p, q); prints each frame."""
    frames = f["frames"]
    names = sorted(frames)
    p0 = invariants(frames[names[0]]["solid"]["stress"][...])[0].mean()
    paths = []
    for k in names:
        fr = frames[k]
        p, q = invariants(fr["solid"]["stress"][...])
        ref = p0 * (1.0 + (q / p / mcs) ** 2) ** (-big)
        u = fr["fluid"]["pore_pressure"][...].mean() if "fluid" in fr else float("nan")
        print(f"t = {fr.attrs['time']:7.3f} s  eta {np.mean(q / p):6.3f}  largest "
              f"|p'/closed form - 1| {np.abs(p / ref - 1.0).max():9.2e}  mean pore pressure "
              f"{u:10.1f} Pa")
        paths.append((p, q))
    return p0, paths


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("h5", nargs="+")
    ap.add_argument("--bound", type=float, default=None)
    ap.add_argument("--png", default=None)
    a = ap.parse_args()
    worst = 0.0
    curves = []
    for name in a.h5:
        with h5py.File(name, "r") as f:
            lam, kap, mcs = clay_constants(f)
            big = 1.0 - kap / lam
            if "element" in f:
                p, q = f["element/p"][...], f["element/q"][...]
                p0 = p[0]
                paths = [(p, q)]
            else:
                p0, paths = run_paths(f, big, mcs)
            err = max(float(np.abs(p / (p0 * (1.0 + (q / p / mcs) ** 2) ** (-big)) - 1.0).max())
                      for p, q in paths)
            print(f"{name}: largest |p'/closed form - 1| {err:.3e}")
            worst = max(worst, err)
            curves.append((name, "element" in f, paths))
    print(f"largest difference {worst:.3e}")
    if a.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 4))
        eta = np.linspace(0.0, mcs * 0.999, 200)
        pc = p0 * (1.0 + (eta / mcs) ** 2) ** (-big)
        ax.plot(pc / 1e3, eta * pc / 1e3, "k-", label="closed form")
        ax.plot(np.array([0, p0]) / 1e3, mcs * np.array([0, p0]) / 1e3, "k:", label="q = M p'")
        for name, element, paths in curves:
            if element:
                p, q = paths[0]
                ax.plot(p / 1e3, q / 1e3, "--", color="tab:blue", label="element test (triaxial)")
            else:
                for p, q in paths:
                    ax.plot(p / 1e3, q / 1e3, "o", ms=2, color="tab:red")
                ax.plot([], [], "o", ms=2, color="tab:red", label="scene points, every frame")
        ax.set_xlabel("p' (kPa)")
        ax.set_ylabel("q (kPa)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(a.png, dpi=120)
    if a.bound is not None and not worst <= a.bound:
        print(f"FAIL: {worst:.3e} > {a.bound:.3e}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
