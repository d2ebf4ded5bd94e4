#!/usr/bin/env python3
"""The dilation of the points of a column collapse (doc/verification.md, C1 at a = 8).

For each frame of a run of scripts/c1_study.py: the front of the continuous deposit
(the farthest point with at least --crowd points within 2 cm behind it along x), the
farthest point, the points thrown ahead of the front, and the volume of the points
against their initial one (largest V/V0, points above 10, points at --bound). --plot
draws the points of three frames coloured by V/V0.

    python3 scripts/c1_dilation.py out/c1/c1_a8_pair_j2.h5 [--bound 2] [--plot c1_a8.png]
"""
import argparse
import sys

import h5py
import numpy as np

from c1_study import L0, SPACING

HALF = 0.5 * SPACING   #: half the initial point spacing (m), as c1_study.py adds it


def volume_ratio(f, frame):
    """V/V0 of the points of a frame (matched by id to the first frame)."""
    first = f["frames"][sorted(f["frames"])[0]]["solid"]
    ids0 = first["id"][:]
    order = np.argsort(ids0)
    s = f["frames"][frame]["solid"]
    k = order[np.searchsorted(ids0[order], s["id"][:])]
    return s["volume"][:] / first["volume"][:][k]


def front(x, crowd, window=0.02):
    """The farthest x with at least crowd points in (x - window, x]."""
    xs = np.sort(x)
    behind = np.searchsorted(xs, xs - window, side="right")
    count = np.arange(1, len(xs) + 1) - behind
    ok = count >= crowd
    return xs[ok].max() if ok.any() else xs.max()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("h5")
    ap.add_argument("--bound", type=float, default=0.0, help="max_dilation of the run (0: none)")
    ap.add_argument("--crowd", type=int, default=8)
    ap.add_argument("--plot")
    args = ap.parse_args()
    with h5py.File(args.h5, "r") as f:
        frames = sorted(f["frames"])
        print("| t (s) | front (m) | (front − L0)/L0 | farthest (m) | points ahead (> front + 5 cm) | "
              "largest V/V0 | V/V0 > 10 | at the bound |")
        print("|---|---|---|---|---|---|---|---|")
        for fr in frames:
            x = f["frames"][fr]["solid"]["x"][:]
            j = volume_ratio(f, fr)
            xf = front(x[:, 0], args.crowd)
            at = int((j >= args.bound * (1 - 1e-9)).sum()) if args.bound > 0 else 0
            print(f"| {f['frames'][fr].attrs['time']:.2f} | {xf:.3f} | {(xf + HALF - L0) / L0:.2f} | "
                  f"{x[:, 0].max():.3f} | {int((x[:, 0] > xf + 0.05).sum())} | {j.max():.3g} | "
                  f"{int((j > 10).sum())} | {at} |")
        if args.plot:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            picks = [frames[len(frames) // 5], frames[len(frames) // 2], frames[-1]]
            fig, axes = plt.subplots(3, 1, figsize=(11, 7))
            vmax = args.bound if args.bound > 0 else 10.0
            xr = max(f["frames"][fr]["solid"]["x"][:, 0].max() for fr in picks) + 0.05
            yr = max(f["frames"][fr]["solid"]["x"][:, 1].max() for fr in picks[1:]) + 0.05
            for ax, fr in zip(axes, picks):
                x = f["frames"][fr]["solid"]["x"][:]
                j = volume_ratio(f, fr)
                sc = ax.scatter(x[:, 0], x[:, 1], c=j, s=0.6, vmin=1.0, vmax=vmax, cmap="viridis")
                ax.set_xlim(0.0, xr)
                ax.set_ylim(0.0, yr)
                ax.set_aspect("equal")
                ax.set_ylabel("y (m)")
                ax.set_title(f"t = {f['frames'][fr].attrs['time']:.2f} s", fontsize=9)
                fig.colorbar(sc, ax=ax, label="V / V0", shrink=0.8)
            axes[-1].set_xlabel("x (m)")
            fig.tight_layout()
            fig.savefig(args.plot, dpi=120)
            print(f"figure: {args.plot}")


if __name__ == "__main__":
    sys.exit(main())
