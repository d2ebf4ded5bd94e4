#!/usr/bin/env python3
"""Runout and final height of a planar granular column collapse (doc/theory.md, section 9.6).

Reads a dpmpm output file, takes the solid points of a frame (the last one unless
--frame is given) and reports

  L  = front of the deposit: the largest x of a point plus half the initial point spacing
       (the edge of the volume the point stands for), measured from the wall at x = origin;
  H  = height of the deposit: the largest y of a point plus half the spacing;

together with (L - L0)/L0 and H/L0, the kinetic energy left in the last diagnostics
record against its peak, and the scaling laws of Lube et al. (2005) and Lajeunesse et al.
(2005) quoted in doc/theory.md, section 9.6, for the aspect ratio a = H0/L0.

    python3 scripts/collapse_profile.py out/c1_a2.h5 --L0 0.2 --H0 0.4 --spacing 0.005 [--plot p.png]
"""
import argparse

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("file")
    ap.add_argument("--L0", type=float, required=True, help="initial column length (m)")
    ap.add_argument("--H0", type=float, required=True, help="initial column height (m)")
    ap.add_argument("--spacing", type=float, required=True, help="initial point spacing (m)")
    ap.add_argument("--origin", type=float, nargs=2, default=[0.0, 0.0], help="wall x, base y")
    ap.add_argument("--frame", default=None, help="frame name (default: the last)")
    ap.add_argument("--plot", default=None, help="write the initial and final points to this PNG")
    args = ap.parse_args()

    with h5py.File(args.file, "r") as f:
        names = sorted(f["frames"])
        name = args.frame or names[-1]
        fr = f["frames"][name]
        t = float(fr.attrs["time"])
        x = fr["solid"]["x"][:]
        x_first = f["frames"][names[0]]["solid"]["x"][:]
        d = f["diagnostics"]
        ke = d["kinetic_energy"][:]
        td = d["time"][:]
        eps = fr["solid"]["plastic_strain"][:] if "plastic_strain" in fr["solid"] else None

    half = 0.5 * args.spacing
    a = args.H0 / args.L0
    L = x[:, 0].max() + half - args.origin[0]
    H = x[:, 1].max() + half - args.origin[1]
    print(f"frame {name} at t = {t:.4f} s, {x.shape[0]} points")
    print(f"kinetic energy: peak {ke.max():.4e} J at t = {td[ke.argmax()]:.3f} s, "
          f"last {ke[-1]:.4e} J at t = {td[-1]:.3f} s ({ke[-1] / ke.max():.2e} of the peak)")
    print(f"a = H0/L0 = {a:.3f}")
    print(f"runout L = {L:.4f} m, (L - L0)/L0 = {(L - args.L0) / args.L0:.3f}")
    print(f"height H = {H:.4f} m, H/L0 = {H / args.L0:.3f}")
    lube = 1.2 * a if a < 1.8 else 1.9 * a ** (2.0 / 3.0)
    lajeunesse = 1.8 * a if a < 3.0 else 2.3 * a ** (2.0 / 3.0)
    print(f"(L - L0)/L0 from the scalings: Lube 2005 {lube:.3f}, Lajeunesse 2005 {lajeunesse:.3f} "
          f"(power-law branches 1.9 a^(2/3) = {1.9 * a ** (2 / 3):.3f}, 2.3 a^(2/3) = "
          f"{2.3 * a ** (2 / 3):.3f}, linear branches 1.2 a = {1.2 * a:.3f}, 1.8 a = {1.8 * a:.3f})")
    print(f"H/L0 from the scalings: a = {a:.3f} (small a), a^0.4 = {a ** 0.4:.3f} (large a)")
    if eps is not None:
        print(f"plastic strain: max {eps.max():.3f}, median {np.median(eps):.3f}, "
              f"points with epsp > 0.01: {(eps > 0.01).mean() * 100:.1f} %")

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(8, 3.2))
        ax.scatter(x_first[:, 0], x_first[:, 1], s=1, c="0.75", label="t = 0")
        c = eps if eps is not None else None
        sc = ax.scatter(x[:, 0], x[:, 1], s=1, c=c, cmap="viridis", label=f"t = {t:.2f} s")
        if c is not None:
            fig.colorbar(sc, ax=ax, label="plastic strain")
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.legend(loc="upper right", markerscale=6)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=150)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
