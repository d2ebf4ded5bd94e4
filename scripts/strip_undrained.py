#!/usr/bin/env python3
"""Excess pore pressure under a strip load against the undrained elastic estimate.

Reads an output of inputs/footing_saturated_2d.nml (or a scene like it: the strip on the
top face from x = 0, its half-width and pressure from the echoed &load, the symmetry
plane at x = 0) and prints, for each frame after the start, the mean pore pressure of
the fluid points of the cell column next to the axis at several depths z against
q alpha / pi, alpha = 2 atan(b / z): the mean in-plane total stress under the centre of
a strip of half-width b on an elastic half-space (Flamant/Boussinesq), which an
undrained saturated soil (pore fluid much stiffer than the skeleton) carries in its pore
pressure. Finite depth and width of the model raise the pressure deeper down.

    python3 scripts/strip_undrained.py out/footing_saturated_2d.h5 [--depths 0.25 0.5 1 2]
"""
import argparse
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
from dpmpm.run import open_run  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("file")
    ap.add_argument("--depths", type=float, nargs="+", default=[0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0])
    args = ap.parse_args()
    with open_run(args.file) as run:
        load = run.input_groups("load")[0]
        q = -float(load["traction"][1])
        b = float(load["hi"][0]) - float(load["lo"][0])
        g = run.grid
        h = g.spacing
        top = g.origin[1] + g.length[1]
        print(f"strip half-width b = {b} m, q = {q:.0f} Pa, cells {h[0]} x {h[1]} m")
        print("| t (s) | z (m) | p (kPa) | q alpha/pi (kPa) | ratio |")
        print("|---|---|---|---|---|")
        for fr in run.frames[1:]:
            s = fr["fluid"]
            x = s["x"]
            p = s["pore_pressure"]
            for z in args.depths:
                sel = (x[:, 0] < h[0]) & (np.abs(top - x[:, 1] - z) < 0.5 * h[1])
                if not sel.any():
                    continue
                zz = top - x[sel, 1]
                exact = np.mean(q * 2.0 * np.arctan(b / zz) / np.pi)
                pm = p[sel].mean()
                print(f"| {fr.time:.3f} | {z:.2f} | {pm / 1e3:.1f} | {exact / 1e3:.1f} | {pm / exact:.3f} |")


if __name__ == "__main__":
    main()
