#!/usr/bin/env python3
"""Plot a dpmpm output file: each point set at the first, middle and last frame and
the energies from /diagnostics over time, into one PNG.

Usage: plot_frames.py FILE.h5 [-o OUT.png] [--color von_mises|speed|stress_xx|...]

One row of panels per point set (solid and fluid are never drawn as one cloud):
2D: solid points coloured by the von Mises stress (or |v|, or one stress component),
fluid points by their pore pressure, equal aspect.
1D: the velocity and the axial stress (fluid: pore pressure) along x.
3D: projection on the x-y plane, coloured like 2D.
Prints the path of the PNG. The plotting is the package dpmpm's (scripts/python,
doc/python.md); this script works without installing it.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "python"))

from dpmpm import open_run, plot_run  # noqa: E402
from dpmpm.plot import SOLID_COLORS  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", help="dpmpm HDF5 output file")
    ap.add_argument("-o", "--output", help="PNG to write (default: FILE with .png)")
    ap.add_argument("--color", choices=SOLID_COLORS, default="von_mises",
                    help="colour of the solid points in 2D and 3D (default von_mises)")
    args = ap.parse_args()
    out = args.output or os.path.splitext(args.file)[0] + ".png"
    with open_run(args.file) as run:
        plot_run(run, out, color=args.color)
    print(out)


if __name__ == "__main__":
    main()
