#!/usr/bin/env python3
"""Plot a dpmpm output file: the points at the first, middle and last frame and
the energies from /diagnostics over time, into one PNG.

Usage: plot_frames.py FILE.h5 [-o OUT.png] [--color von_mises|speed]

2D: points coloured by the von Mises stress (or |v|), equal aspect.
1D: the velocity and the axial stress along x.
3D: projection on the x-y plane, coloured like 2D.
Prints the path of the PNG.
"""
import argparse
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def von_mises(s):
    """Von Mises stress of Voigt rows (xx, yy, zz, yz, xz, xy)."""
    sxx, syy, szz, syz, sxz, sxy = (s[:, k] for k in range(6))
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                   + 3.0 * (syz ** 2 + sxz ** 2 + sxy ** 2))


def load_points(frame):
    """Concatenate the point sets of a frame: x (n, ndim), v, stress (n, 6)."""
    xs, vs, ss = [], [], []
    for name in ("solid", "fluid"):
        if name in frame and frame[name]["id"].shape[0] > 0:
            g = frame[name]
            xs.append(g["x"][...])
            vs.append(g["v"][...])
            # Fluid sets carry pore_pressure instead of a stress: -p on the diagonal.
            if "stress" in g:
                ss.append(g["stress"][...])
            else:
                p = g["pore_pressure"][...] if "pore_pressure" in g else np.zeros(len(g["id"]))
                ss.append(np.column_stack([-p, -p, -p] + [np.zeros_like(p)] * 3))
    if not xs:
        return None
    return np.concatenate(xs), np.concatenate(vs), np.concatenate(ss)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", help="dpmpm HDF5 output file")
    ap.add_argument("-o", "--output", help="PNG to write (default: FILE with .png)")
    ap.add_argument("--color", choices=("von_mises", "speed"), default="von_mises",
                    help="colour of the points in 2D and 3D (default von_mises)")
    args = ap.parse_args()
    out = args.output or os.path.splitext(args.file)[0] + ".png"

    with h5py.File(args.file, "r") as f:
        ndim = int(f.attrs["ndim"])
        names = sorted(f["frames"].keys())
        picks = sorted({0, len(names) // 2, len(names) - 1}) if names else []
        fig, axes = plt.subplots(1, len(picks) + 1, figsize=(4.2 * (len(picks) + 1), 4.0),
                                 squeeze=False)
        axes = axes[0]
        for ax, k in zip(axes, picks):
            fr = f["frames"][names[k]]
            t = float(fr.attrs["time"])
            ax.set_title(f"frame {names[k]}, t = {t:.4g} s")
            pts = load_points(fr)
            if pts is None:
                ax.text(0.5, 0.5, "no points", ha="center", transform=ax.transAxes)
                continue
            x, v, s = pts
            if ndim == 1:
                order = np.argsort(x[:, 0])
                ax.plot(x[order, 0], v[order, 0], ".-", label="v (m/s)")
                ax.set_xlabel("x (m)")
                ax.set_ylabel("v (m/s)")
                ax2 = ax.twinx()
                ax2.plot(x[order, 0], s[order, 0], ".-", color="tab:red", label="stress xx")
                ax2.set_ylabel("stress xx (Pa)", color="tab:red")
            else:
                c = von_mises(s) if args.color == "von_mises" else np.linalg.norm(v, axis=1)
                label = "von Mises (Pa)" if args.color == "von_mises" else "|v| (m/s)"
                sc = ax.scatter(x[:, 0], x[:, 1], c=c, s=6, cmap="viridis")
                fig.colorbar(sc, ax=ax, label=label, shrink=0.8)
                ax.set_aspect("equal")
                ax.set_xlabel("x (m)")
                ax.set_ylabel("y (m)" if ndim == 2 else "y (m), projected along z")

        ax = axes[-1]
        d = f.get("diagnostics")
        ax.set_title("energies")
        if d is not None and d["time"].shape[0] > 0:
            t = d["time"][...]
            ke, se, w = (d[n][...] for n in ("kinetic_energy", "strain_energy", "external_work"))
            ax.plot(t, ke, label="kinetic")
            ax.plot(t, se, label="strain")
            ax.plot(t, w, label="external work")
            ax.plot(t, ke + se, "k--", label="kinetic + strain")
            ax.legend(fontsize="small")
        else:
            ax.text(0.5, 0.5, "no diagnostics", ha="center", transform=ax.transAxes)
        ax.set_xlabel("t (s)")
        units = {1: "J per m² of cross-section", 2: "J per m of thickness"}.get(ndim, "J")
        ax.set_ylabel(f"energy ({units})")
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
