#!/usr/bin/env python3
"""A footing pushed into the crest of a saturated slope (inputs/slope_saturated_2d.nml).

Runs the scene (or reads an earlier run in the work directory), prints the footing's
pressure q = -F_y / B against its settlement from the drive force
/verification/drive_force_y, the largest plastic strain, the excess pore pressure
(p minus each water point's initial p) and the largest speed of the last frame, and
draws the q-settlement curve, the plastic strain of the soil and the excess pore
pressure of the water (doc/verification.md, "Saturated slope").
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "python"))
import dpmpm  # noqa: E402
from dpmpm.launch import scene_arguments  # noqa: E402

B = 2.0      # footing width (m)
V = 0.1      # footing speed (m/s)
SCENE = "inputs/slope_saturated_2d.nml"


def scene(args):
    """The scene with its output in the work directory and the kernel and end time asked."""
    s = dpmpm.Scene.read(SCENE)
    s.set(run={"name": f"slope_saturated_2d_{args.kernel}_np{args.ranks}"},
          output={"dir": os.path.abspath(args.workdir)}, shape={"kernel": args.kernel})
    if args.t_end:
        s["run"]["t_end"] = args.t_end
    return s


def run(args):
    """Runs the scene unless its output is in the work directory; returns the output file."""
    r = dpmpm.simulate(scene(args), ranks=args.ranks, binary=args.bin, reuse=not args.rerun,
                       progress=sys.stderr.isatty())
    return r.output


def measure(h5):
    with dpmpm.open_run(h5) as run:
        v = run.verification
        t, q = v["drive_time"], -v["drive_force_y"] / B
        first, last = run.frames[0], run.frames[-1]
        p0 = dict(zip(first["fluid"]["id"], first["fluid"]["pore_pressure"]))
        fr = {f"{k}/{d}": last[k][d] for k, d in (
            ("solid", "x"), ("solid", "material"), ("solid", "plastic_strain"), ("solid", "v"),
            ("fluid", "x"), ("fluid", "id"), ("fluid", "pore_pressure"))}
        fr["time"] = last.time
    fr["dp"] = fr["fluid/pore_pressure"] - np.array([p0[i] for i in fr["fluid/id"]])
    return t, q, fr


def plot(t, q, fr, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    soil = fr["solid/material"] == 1
    xs, xf = fr["solid/x"], fr["fluid/x"]
    fig = plt.figure(figsize=(10, 9))
    ax0 = fig.add_subplot(3, 1, 1)
    ax0.plot(V * t, q / 1e3)
    ax0.set_xlabel("settlement (m)")
    ax0.set_ylabel("q = F / B (kPa)")
    ax0.grid(True, alpha=0.3)
    ax1 = fig.add_subplot(3, 1, 2)
    ep = fr["solid/plastic_strain"][soil]
    a = ax1.scatter(xs[soil, 0], xs[soil, 1], c=ep, s=2, vmax=max(np.percentile(ep, 99.5), 1e-9))
    fig.colorbar(a, ax=ax1, label="plastic strain")
    ax2 = fig.add_subplot(3, 1, 3)
    lim = np.percentile(np.abs(fr["dp"]), 99) / 1e3
    b = ax2.scatter(xf[:, 0], xf[:, 1], c=fr["dp"] / 1e3, s=2, cmap="RdBu_r", vmin=-lim, vmax=lim)
    fig.colorbar(b, ax=ax2, label="excess pore pressure (kPa)")
    for ax in (ax1, ax2):
        ax.scatter(xs[~soil, 0], xs[~soil, 1], c="0.3", s=2)
        ax.set_aspect("equal")
        ax.set_xlim(0.0, 16.0)
        ax.set_ylim(0.0, 5.5)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"figure: {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    scene_arguments(ap, 4.0, "out/slope")
    ap.add_argument("--plot", help="figure: q-settlement, plastic strain, excess pore pressure")
    args = ap.parse_args()
    h5 = run(args)
    t, q, fr = measure(h5)
    print("settlement (m)  q (kPa)")
    for s in np.arange(0.05, V * t[-1] + 1e-9, 0.05):
        i = np.argmin(abs(V * t - s))
        print(f"  {V * t[i]:.3f}  {q[i] / 1e3:8.1f}")
    soil = fr["solid/material"] == 1
    print(f"last frame t = {fr['time']:.3f} s: largest plastic strain "
          f"{fr['solid/plastic_strain'][soil].max():.3f}, excess pore pressure "
          f"{fr['dp'].min() / 1e3:.1f} ... {fr['dp'].max() / 1e3:.1f} kPa (1st/99th percentile "
          f"{np.percentile(fr['dp'], 1) / 1e3:.1f} / {np.percentile(fr['dp'], 99) / 1e3:.1f}), "
          f"largest speed {np.abs(fr['solid/v']).max():.3f} m/s")
    if args.plot:
        plot(t, q, fr, args.plot, f"Footing at the crest of a saturated slope ({args.kernel}, "
             f"{args.ranks} rank{'s' if args.ranks > 1 else ''}), t = {fr['time']:.2f} s")


if __name__ == "__main__":
    main()
