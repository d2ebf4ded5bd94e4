#!/usr/bin/env python3
"""A saturated SANISAND element of the full code against the element driver's path.

Usage: scripts/sanisand_undrained_2d.py RUN.h5 ELEMENT.h5 [--bound B] [--spread S]

RUN.h5: the output of inputs/sanisand_undrained_2d.nml (a 2D element loaded vertically,
undrained, the cell pressure held). ELEMENT.h5: dpmpm_element's plane_strain_undrained
test of the same sand (inputs/element/sanisand_plane_strain_undrained.nml, stress
controlled). In the run, the vertical is y and x is the lateral direction, so the deviator
of the plane is t = sigma'_yy - sigma'_xx (compression positive); in the element test it
is sigma'_a - sigma'_x. For every frame the mean p' and von Mises q of the solid points are
compared with the element test's at the same t (linear interpolation between its steps),
as differences over p'0, with the spread of p' over the points. Exit status 1 when the
largest difference exceeds --bound or the spread --spread.
"""
import argparse
import sys

import h5py
import numpy as np


def invariants(s):
    """p' (compression positive), von Mises q and t = sigma'_v - sigma'_h (y vertical) of
    Voigt stresses (n, 6) or (6, n), tension positive."""
    s = np.asarray(s)
    if s.shape[0] == 6 and s.ndim == 2 and s.shape[1] != 6:
        s = s.T
    p = -(s[:, 0] + s[:, 1] + s[:, 2]) / 3.0
    d = s.copy()
    d[:, :3] += p[:, None]
    q = np.sqrt(1.5 * (d[:, 0] ** 2 + d[:, 1] ** 2 + d[:, 2] ** 2 + 2.0 * (d[:, 3:] ** 2).sum(1)))
    return p, q


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run")
    ap.add_argument("element")
    ap.add_argument("--bound", type=float, default=None)
    ap.add_argument("--spread", type=float, default=None)
    args = ap.parse_args()
    with h5py.File(args.element, "r") as f:
        s = f["element"]["stress"][...]
    s = s.T if s.shape[0] == 6 else s
    ep, eq = invariants(s)
    et = s[:, 0] - s[:, 2]  # sigma'_a - sigma'_x: z axial in the element test
    with h5py.File(args.run, "r") as f:
        frames = f["frames"]
        names = sorted(frames, key=lambda k: frames[k].attrs["time"])
        rows = []
        for k in names:
            fr = frames[k]
            st = fr["solid"]["stress"][...]
            st = st if st.shape[-1] == 6 else st.T
            p, q = invariants(st)
            t = (st[:, 0] - st[:, 1]).mean()
            u = fr["fluid"]["pore_pressure"][...].mean() if "fluid" in fr else float("nan")
            rows.append((fr.attrs["time"], t, p.mean(), q.mean(), p.max() - p.min(), u))
    p0 = rows[0][2]
    worst = 0.0
    spread = 0.0
    print(f"{'t (s)':>6} {'sv-sh (kPa)':>11} {'p run':>9} {'p elem':>9} {'dp/p0':>9} "
          f"{'dq/p0':>9} {'spread/p0':>9} {'u (kPa)':>8}")
    for time, t, p, q, sp, u in rows:
        if t > et.max() * (1.0 + 1e-9):
            print(f"{time:6.2f}: deviator {t:.6g} beyond the element test's end {et.max():.6g}")
            return 1
        pe = np.interp(t, et, ep)
        qe = np.interp(t, et, eq)
        dp = abs(p - pe) / p0
        dq = abs(q - qe) / p0
        worst = max(worst, dp, dq)
        spread = max(spread, sp / p0)
        print(f"{time:6.2f} {t / 1e3:11.3f} {p / 1e3:9.3f} {pe / 1e3:9.3f} {dp:9.2e} {dq:9.2e} "
              f"{sp / p0:9.2e} {u / 1e3:8.3f}")
    print(f"largest difference over p'0 {worst:.3e}, largest spread of p' over the points "
          f"{spread:.3e}")
    bad = args.bound is not None and not worst <= args.bound
    bad = bad or (args.spread is not None and not spread <= args.spread)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
