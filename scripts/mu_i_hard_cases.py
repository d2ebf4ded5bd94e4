#!/usr/bin/env python3
"""The mu(I) column collapse on every shape choice, on 1 and 2 ranks, to rest and beyond.

Builds the collapse of scripts/c1_study.py with --model mu_i (a = 2 by default, on cells of
--cell, to --t-scale times the study's end time: rest comes at about 1 s) for each shape
choice that a mu(I) soil accepts (the six of tests/test_mu_i_incline.f90: linear,
quadratic and cubic grid functions, the cubic MLS pair, the quadratic/Wendland MLS pair,
linear grid functions with one Gauss point; and the cubic pair with Wendland C2 stress
fields of scripts/c1_study.py --shape pair), runs each on every rank count of --ranks, and
prints one table row per run: how it ended, the steps and run time, the monitor's largest
(kinetic + stored) / (work + initial) and largest balance error and its warnings, the
kinetic energy left against its peak, the runout (farthest point and end of the deposit),
the height, and over the last half second how far the end of the deposit moved, how many
points moved by more than 1 mm and the largest move.

    python3 scripts/mu_i_hard_cases.py --bin build/release/dpmpm --workdir out/mu_i_hard \\
        [--ratio 2] [--cell 0.02] [--t-scale 2] [--ranks 1 2] [--shapes linear pair ...]
"""
import argparse
import json
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import dpmpm  # noqa: E402
import c1_study  # noqa: E402

#: the &shape groups (doc/input.md) by name
SHAPES = {
    "linear": {"kernel": "linear"},
    "quadratic": {"kernel": "quadratic"},
    "cubic": {"kernel": "cubic"},
    "cubic_pair": {"kernel": "cubic", "velocity_kernel": "cubic", "velocity_basis": "linear",
                   "quadrature": "gauss", "field_kernel": "cubic", "field_radius": 0.0},
    "wendland_pair": {"kernel": "quadratic", "velocity_kernel": "wendland_c2",
                      "velocity_radius": 2.0, "quadrature": "gauss",
                      "field_kernel": "quadratic", "field_radius": 0.0},
    "linear_gauss1": {"kernel": "linear", "quadrature": "gauss", "gauss_points": 1,
                      "field_kernel": "linear", "field_radius": 0.75},
    "pair": c1_study.PAIR,
}


def last_motion(path, cell):
    """Over the last half second: how far the end of the connected deposit moved (m), how
    many points moved by more than 1 mm, and the largest move of a point (m)."""
    with dpmpm.open_run(path) as run:
        last = run.frames[-1]
        back = run.frame_at(max(0.0, last.time - 0.5))
        x1, x0 = last["solid"]["x"], back["solid"]["x"]
        e1 = c1_study.deposit_end(x1[:, 0], cell)
        e0 = c1_study.deposit_end(x0[:, 0], cell)
    d = np.linalg.norm(x1 - x0, axis=1)
    return e1 - e0, int((d > 1.0e-3).sum()), d.max()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--workdir", default="out/mu_i_hard")
    ap.add_argument("--ratio", type=float, default=2.0)
    ap.add_argument("--cell", type=float, default=0.02)
    ap.add_argument("--t-scale", type=float, default=2.0)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--shapes", nargs="+", default=list(SHAPES), choices=list(SHAPES))
    args = ap.parse_args()
    workdir = os.path.abspath(args.workdir)
    os.makedirs(workdir, exist_ok=True)
    rows = []
    for shape in args.shapes:
        for ranks in args.ranks:
            s = c1_study.build_scene(args.ratio, "fixed", workdir, max_dilation=2.0,
                                     model="mu_i", cell=args.cell, t_scale=args.t_scale,
                                     room=2.5)
            s["shape"].clear()
            s.set(shape=SHAPES[shape])
            s["run"]["name"] = f"{s.name}_{shape}_np{ranks}"
            h5 = s.output_file()
            how = "completed"
            if not os.path.exists(h5):
                try:
                    r = dpmpm.simulate(s, ranks=ranks, binary=args.bin, progress=False)
                    with open(os.path.splitext(h5)[0] + ".wall.json", "w") as f:
                        json.dump({"wall": r.wall, "ranks": ranks}, f)
                except dpmpm.RunError as e:
                    how = f"exit code {e.status}: {e}"[:120]
            print(f"{s.name}: {how}", flush=True)
            if not os.path.exists(h5):
                continue
            m = c1_study.measure(h5, args.ratio, args.cell)
            moved, nmoved, dmax = last_motion(h5, args.cell)
            rows.append(dict(m, shape=shape, ranks=ranks, how=how, moved=moved, nmoved=nmoved,
                             dmax=dmax))
    print("| shape | ranks | how it ended | t (s) | steps | wall (s) | monitor (KE + stored)/"
          "(work + initial) | balance error | warnings | KE left / peak | (L−L0)/L0 farthest "
          "| deposit end | H/L0 | over the last 0.5 s: end of the deposit moved (m), points "
          "moved > 1 mm, largest move (m) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['shape']} | {r['ranks']} | {r['how']} | {r['t']:.2f} | {r['steps']} | "
              f"{r['wall']:.0f} | {r['ratio']:.3f} | {r['balance']:.1e} | {r['warnings']} | "
              f"{r['ke']:.1e} | {r['runout']:.2f} | {r['end']:.2f} | {r['height']:.2f} | "
              f"{r['moved']:.1e}, {r['nmoved']}, {r['dmax']:.1e} |")
    return 0 if all(np.isfinite(r["ratio"]) for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
