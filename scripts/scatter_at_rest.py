#!/usr/bin/env python3
"""Saturated soil at rest on scattered points: the pore pressure of every fluid point
against hydrostatic (doc/verification.md, "Saturated soil at rest on scattered points").

The scene of inputs/submerged_layer_2d.nml (2 m x 1.5 m of sand, n = 0.4, k = 1e-4 m/s,
K_f = 2.2 GPa, hydrostatic and geostatic start, rollers at the sides, fixed
impermeable base), with 0.5 m of free water above (`--water free`) or without it
(`--water none`: the grid ends at the soil's drained top). For each placement of the
points (stirred: the regular points after rounds of area-preserving shears, as after a
large deformation) and each shape choice it runs the scene to --t-end and prints, for the last
frame, the RMS and the largest |p - p_h| of the fluid points in units of the
hydrostatic pressure at the base (p_h = rho_f g (water level - y) at the point), the
largest |mean p - mean p_h| over the rows of cells (band means), and the largest speed
of either phase.

    python3 scripts/scatter_at_rest.py [--bin build/release/dpmpm] [--np 2]
        [--water free,none] [--placements regular,random,uniform,stirred]
        [--shapes standard,quadratic,cubic,linear_gauss,pair] [--smoothing none,cell]
        [--t-end 0.2] [--out DIR]
"""
import argparse
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import dpmpm  # noqa: E402
from dpmpm.run import open_run  # noqa: E402
from long_runs import SHAPES  # noqa: E402  (the shape choices of the long-run survey)

RHO_F, G = 1000.0, 9.81


def scene(water, placement, shape, smoothing, t_end, out, name, pgrad=None):
    """One case as a dpmpm.Scene, and its water level (pgrad: porosity_gradient, by default
    on with the free water only)."""
    free = water == "free"
    if pgrad is None:
        pgrad = free
    level = 2.0 if free else 1.5
    place = {} if placement == "regular" else {"placement": placement, "seed": 5}
    s = dpmpm.Scene()
    s.add("run", name=name, t_end=t_end, cfl=0.5, drag="implicit", gravity=[0.0, -9.81],
          porosity_gradient=pgrad, pressure_smoothing=smoothing)
    s.add("grid", ndim=2, ncells=[20, 30 if free else 15], origin=[0.0, 0.0],
          length=[2.0, 3.0 if free else 1.5])
    s.replace("shape", SHAPES[shape])
    s.add("material", id=1, model="linear_elastic", density=2650.0, youngs_modulus=5.0e7,
          poisson_ratio=0.3, conductivity=1.0e-4)
    s.add("material", id=2, model="fluid", density=1000.0, bulk_modulus=2.2e9)
    s.add("region", dict(lo=[0.0, 0.0], hi=[2.0, 1.5], material=1, phase="saturated",
                         fluid_material=2, porosity=0.4, geostatic=True, water_level=level,
                         **place))
    if free:
        s.add("region", dict(lo=[0.0, 1.5], hi=[2.0, 2.0], material=2, phase="fluid",
                             geostatic=True, **place))
    s.add("boundary", face="y-", condition="fixed", fluid="impermeable")
    s.add("boundary", face="x-", condition="roller")
    s.add("boundary", face="x+", condition="roller")
    s.add("boundary", face="y+", condition="free", fluid="drained")
    s.add("output", dir=out, frame_interval=t_end / 2)
    return s, level


def measure(path, level, h):
    """RMS and largest |p - p_h| / p_base of the fluid points, the largest band-mean
    error / p_base and the largest speed, at the last frame."""
    with open_run(path) as run:
        fr = run.frames[-1]
        f = fr["fluid"]
        x, p = f["x"], f["pore_pressure"]
        ph = RHO_F * G * (level - x[:, 1])
        pb = RHO_F * G * level
        e = (p - ph) / pb
        rows = np.floor(x[:, 1] / h).astype(int)
        band = max(abs(np.mean(p[rows == r] - ph[rows == r])) for r in np.unique(rows)) / pb
        vmax = max(np.sqrt((fr[s]["v"] ** 2).sum(axis=1)).max() for s in ("solid", "fluid"))
        return fr.time, np.sqrt(np.mean(e ** 2)), np.abs(e).max(), band, vmax


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--np", type=int, default=2)
    ap.add_argument("--water", default="free,none")
    ap.add_argument("--placements", default="regular,random,uniform")
    ap.add_argument("--shapes", default="standard,quadratic,cubic,linear_gauss,pair")
    ap.add_argument("--smoothing", default="none")
    ap.add_argument("--t-end", type=float, default=0.2)
    ap.add_argument("--porosity-gradient", choices=("default", "on", "off"), default="default",
                    help="porosity_gradient: by default on with the free water only")
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "scatter_at_rest"))
    args = ap.parse_args()
    out = os.path.abspath(args.out)
    print("| water | placement | shape | smoothing | t (s) | RMS | largest | band mean | "
          "largest speed (m/s) | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for water in args.water.split(","):
        for placement in args.placements.split(","):
            for shape in args.shapes.split(","):
                for smoothing in args.smoothing.split(","):
                    pg = {"default": None, "on": True, "off": False}[args.porosity_gradient]
                    name = f"{water}_{placement}_{shape}_{smoothing}"
                    if pg is not None:
                        name += "_pg" if pg else "_nopg"
                    sc, level = scene(water, placement, shape, smoothing, args.t_end, out,
                                      name, pg)
                    row = f"| {water} | {placement} | {shape} | {smoothing} |"
                    try:
                        r = dpmpm.simulate(sc, ranks=args.np, binary=args.bin, progress=False)
                    except dpmpm.RunError as e:
                        why = e.lines[-1][:100] if e.lines else ""
                        print(f"{row} exit {e.status}: {why} | | | | | |", flush=True)
                        continue
                    wall = r.wall
                    t, rms, big, band, vmax = measure(r.output, level, 0.1)
                    print(f"{row} {t:.3f} | {rms:.3g} | {big:.3g} | {band:.3g} | {vmax:.2g} | "
                          f"{wall:.0f} |", flush=True)


if __name__ == "__main__":
    main()
