#!/usr/bin/env python3
"""Granular column collapse (C1) at several aspect ratios a = H0/L0 (doc/theory.md 9.6).

Builds one scene per aspect ratio from inputs/c1_a2.nml (same material, grid spacing,
points per cell, base and wall; the column height H0 = a L0, the grid long and high
enough for the deposit, the initial state geostatic with K0 = 1 - sin(phi), the end time
grown with sqrt(H0)), runs each with BIN on --ranks ranks in --workdir (unless its output
is there already and --rerun is not given), and reports for the last frame of each run the
runout (L - L0)/L0 and the height H/L0 (farthest and highest point plus half the point
spacing) beside the scaling laws of Lube et al. (2005) and Lajeunesse et al. (2005), and
the kinetic energy left against its peak. --plot draws runout and height against a with
the laws, and the deposits.

    python3 scripts/c1_study.py --bin build/release/dpmpm --ratios 0.5 1 2 4 8 \\
        --workdir out/c1 --plot c1_study.png [--base fixed|rough] [--shape standard|pair]
        [--max-dilation J] [--ranks 2]
"""
import argparse
import math
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402

TEMPLATE = os.path.join(ROOT, "inputs", "c1_a2.nml")
L0 = 0.2          #: column length (m)
H_CELL = 0.01     #: grid spacing of the template (m)
SPACING = 0.005   #: initial point spacing (2 x 2 points per cell)


def lube(a):
    return 1.2 * a if a < 1.8 else 1.9 * a ** (2.0 / 3.0)


def lajeunesse(a):
    return 1.8 * a if a < 3.0 else 2.3 * a ** (2.0 / 3.0)


#: the MLS pair of doc/theory.md 3.6 (doc/input.md, &shape)
PAIR = {"kernel": "cubic", "quadrature": "gauss", "field_kernel": "wendland_c2",
        "field_radius": 2.0}


def build_scene(a, base, workdir, shape="standard", max_dilation=0.0, smoothing=False):
    """The template with column height a L0, a grid that holds the deposit and a geostatic start
    (and, with max_dilation > 0, that bound on the points' volume, doc/theory.md 5.4; with
    smoothing, the volumetric smoothing of doc/theory.md 4.5), as a dpmpm.Scene."""
    s = dpmpm.Scene.read(TEMPLATE)
    h0 = a * L0
    # room for 1.5 times the larger scaling law's runout, and 5 cells above the column
    length = L0 * (1.0 + 1.5 * max(lube(a), lajeunesse(a))) + 0.1
    nx = int(math.ceil(length / H_CELL))
    ny = int(math.ceil((h0 + 0.05) / H_CELL))
    t_end = round(1.0 * math.sqrt(a / 2.0) + 0.5, 2)
    name = (f"c1_a{a:g}".replace(".", "p") + ("_rough" if base == "rough" else "")
            + ("_pair" if shape == "pair" else "")
            + (f"_j{max_dilation:g}".replace(".", "p") if max_dilation > 0 else "")
            + ("_vs" if smoothing else ""))
    s.set(run={"name": name, "t_end": t_end},
          grid={"ncells": [nx, ny], "length": [round(nx * H_CELL, 2), round(ny * H_CELL, 2)]},
          output={"dir": workdir, "frame_interval": 0.1})
    [region] = s.groups("region")
    region["hi"] = [L0, round(h0, 4)]
    for initial in ("stress", "stress_gradient"):
        del region[initial]
    region["geostatic"], region["k0"] = True, 0.5
    if shape == "pair":
        s["shape"].clear()
        s.set(shape=PAIR)
    if max_dilation > 0:
        s["material"]["max_dilation"] = max_dilation
    if smoothing:
        s["run"]["volumetric_smoothing"] = "cell"
    if base == "rough":
        [floor] = s.find("boundary", face="y-", condition="fixed")
        floor.update(condition="roller", friction=0.577, lift_off=False)
    return s


def measure(path, a):
    with dpmpm.open_run(path) as run:
        first, last = run.frames[0], run.frames[-1]
        t = last.time
        x = last["solid"]["x"].copy()
        x0 = first["solid"]["x"].copy()
        ke = np.asarray(run.diagnostics["kinetic_energy"])
    half = 0.5 * SPACING
    runout = (x[:, 0].max() + half - L0) / L0
    height = (x[:, 1].max() + half) / L0
    return dict(a=a, t=t, runout=runout, height=height, ke=ke[-1] / ke.max(), x=x, x0=x0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.5, 1.0, 2.0, 4.0, 8.0])
    ap.add_argument("--base", choices=["fixed", "rough"], default="fixed")
    ap.add_argument("--shape", choices=["standard", "pair"], default="standard",
                    help="Standard MPM (the template's linear grid functions) or the MLS pair")
    ap.add_argument("--max-dilation", type=float, default=0.0,
                    help="&material max_dilation of the soil (0: no bound)")
    ap.add_argument("--volumetric-smoothing", action="store_true",
                    help="volumetric_smoothing = 'cell' (doc/theory.md 4.5)")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--workdir", default="out/c1")
    ap.add_argument("--rerun", action="store_true", help="run again when the output exists")
    ap.add_argument("--plot", help="figure of runout and height against a, and the deposits")
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    rows = []
    for a in args.ratios:
        scene = build_scene(a, args.base, args.workdir, args.shape, args.max_dilation,
                            args.volumetric_smoothing)
        h5 = scene.output_file()
        if args.rerun or not os.path.exists(h5):
            try:
                r = dpmpm.simulate(scene, ranks=args.ranks, binary=args.bin,
                                   progress=sys.stderr.isatty())
                print(f"{scene.name}: exit code 0, {r.wall:.0f} s", flush=True)
            except dpmpm.RunError as e:
                print(f"{scene.name}: exit code {e.status}: {e}", flush=True)
                continue
        else:
            scene.write(os.path.join(args.workdir, scene.name + ".nml"))
        rows.append(measure(h5, a))
    print("| a | t end (s) | (L−L0)/L0 | Lube 2005 | Lajeunesse 2005 | H/L0 | a^0.4 (or a) | "
          "kinetic energy left |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        a = r["a"]
        hl = a if a < 1.0 else a ** 0.4
        print(f"| {a:g} | {r['t']:.2f} | {r['runout']:.2f} | {lube(a):.2f} | {lajeunesse(a):.2f} | "
              f"{r['height']:.2f} | {hl:.2f} | {r['ke']:.1e} |")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig = plt.figure(figsize=(10, 6))
        ax1 = fig.add_subplot(2, 2, 1)
        ax2 = fig.add_subplot(2, 2, 2)
        aa = np.geomspace(0.4, 10, 100)
        ax1.loglog(aa, [lube(v) for v in aa], "k-", lw=0.8, label="Lube et al. 2005")
        ax1.loglog(aa, [lajeunesse(v) for v in aa], "k--", lw=0.8, label="Lajeunesse et al. 2005")
        ax1.loglog([r["a"] for r in rows], [r["runout"] for r in rows], "o", label="dpmpm")
        ax1.set_xlabel("a = H0/L0")
        ax1.set_ylabel("(L∞ − L0)/L0")
        ax1.legend(fontsize=7)
        ax2.loglog(aa, np.where(aa < 1.0, aa, aa ** 0.4), "k-", lw=0.8, label="a, a^0.4")
        ax2.loglog([r["a"] for r in rows], [r["height"] for r in rows], "o", label="dpmpm")
        ax2.set_xlabel("a = H0/L0")
        ax2.set_ylabel("H∞/L0")
        ax2.legend(fontsize=7)
        ax3 = fig.add_subplot(2, 1, 2)
        for r in sorted(rows, key=lambda r: -r["a"]):   # the largest first, the rest on top
            ax3.scatter(r["x"][:, 0], r["x"][:, 1], s=0.3, label=f"a = {r['a']:g}")
        ax3.set_aspect("equal")
        ax3.set_xlabel("x (m)")
        ax3.set_ylabel("y (m)")
        ax3.legend(fontsize=7, markerscale=10)
        fig.suptitle(f"Column collapse, {args.base} base, {args.shape}: runout, height, final deposits")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"figure: {args.plot}")


if __name__ == "__main__":
    sys.exit(main())
