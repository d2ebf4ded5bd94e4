#!/usr/bin/env python3
"""Bearing capacity of a rigid strip footing against Prandtl (inputs/footing_prandtl_2d.nml).

With --phi the soil is Mohr-Coulomb with that friction angle (and, with associated flow
as Prandtl's solution has it, the same dilatancy angle unless --psi says otherwise); the
limit of a weightless soil is then q = c N_c with N_c = (N_q - 1) cot phi,
N_q = exp(pi tan phi) tan^2(45 deg + phi/2); 2 + pi at phi = 0.

--scene inputs/footing_prandtl_saturated_2d.nml runs the same footing on saturated soil
(undrained: the limit of a soil with phi = 0 does not change).

Runs the scene with the binary BIN at the grid spacings of --cells-per-metre (the points
per cell, the footing and the soil kept; the footing's nodes span half a cell more than
the footing on each refinement), reads the drive force /verification/drive_force_y and
reports the bearing pressure q = -F/(B/2) over c against the settlement, the mean of q/c
over settlements from 5 % to 10 % of B (the plateau; --band sets another range) beside Prandtl's 2 + pi, and draws
the curves with --plot.

    python3 scripts/footing_prandtl.py --bin build/release/dpmpm --cells-per-metre 10 20 \\
        --workdir out/prandtl --plot prandtl.png
"""
import argparse
import math
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402

SCENE = os.path.join(ROOT, "inputs", "footing_prandtl_2d.nml")
B = 1.0          #: footing width (m); the scene holds half of it
C = 1.0e4        #: cohesion (Pa)
V = 0.05         #: footing speed (m/s)


def prandtl_nc(phi_deg):
    """Prandtl's bearing factor N_c of a weightless soil (2 + pi at phi = 0)."""
    if phi_deg == 0.0:
        return 2.0 + math.pi
    phi = math.radians(phi_deg)
    nq = math.exp(math.pi * math.tan(phi)) * math.tan(math.pi / 4 + phi / 2) ** 2
    return (nq - 1.0) / math.tan(phi)


def scene(path, cpm, workdir, phi, psi, tensile):
    """The footing scene at cpm cells per metre (5 m by 3.6 m, the cells rounded) with the
    soil's friction and dilatancy angles (and tensile strength) as asked, as a dpmpm.Scene."""
    s = dpmpm.Scene.read(path)
    tag = "prandtl_saturated" if s.find("region", phase="saturated") else "prandtl"
    name = f"{tag}_{cpm}" + (f"_phi{phi:g}_psi{psi:g}" if phi > 0 else "")
    soil = [m for m in s.groups("material") if "cohesion" in m]
    if len(soil) != 1:
        raise SystemExit(f"footing_prandtl: {path} has {len(soil)} materials with a cohesion, not 1")
    if tensile is not None:
        name += f"_t{tensile:g}"
        soil[0]["tensile_strength"] = tensile
    soil[0].update(friction_angle=phi, dilatancy_angle=psi)
    ny = round(3.6 * cpm)
    s.set(run={"name": name}, grid={"ncells": [5 * cpm, ny], "length": [5.0, round(ny / cpm, 4)]},
          output={"dir": workdir})
    return s


def curve(h5):
    with dpmpm.open_run(h5) as run:
        t = run.verification["drive_time"][:]
        fy = run.verification["drive_force_y"][:]
    return V * t / B, -fy / (0.5 * B) / C


def plot_fields(h5, path):
    """The last frame of a saturated run: the soil points coloured by their plastic strain
    (the mechanism) and the water points by their pore pressure over c."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with dpmpm.open_run(h5) as run:
        fr = run.frames[-1]
        t = fr.time
        xs, mat, ep = fr["solid"]["x"], fr["solid"]["material"], fr["solid"]["plastic_strain"]
        xf, pf = fr["fluid"]["x"], fr["fluid"]["pore_pressure"]
    soil = mat == 1
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
    a = axs[0].scatter(xs[soil, 0], xs[soil, 1], c=ep[soil], s=2, cmap="viridis",
                       vmax=max(np.percentile(ep[soil], 99.5), 1e-9))
    axs[0].scatter(xs[~soil, 0], xs[~soil, 1], c="0.3", s=2)
    fig.colorbar(a, ax=axs[0], label="plastic strain")
    lim = np.percentile(np.abs(pf), 99.5) / C   # a few points at the footing's corner go further
    b = axs[1].scatter(xf[:, 0], xf[:, 1], c=pf / C, s=2, cmap="RdBu_r", vmin=-lim, vmax=lim)
    axs[1].scatter(xs[~soil, 0], xs[~soil, 1], c="0.3", s=2)
    fig.colorbar(b, ax=axs[1], label="pore pressure / c")
    for ax in axs:
        ax.set_xlim(0.0, 3.0)
        ax.set_ylim(1.0, 3.3)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
    axs[0].set_ylabel("y (m)")
    fig.suptitle(f"Footing on saturated Tresca soil, t = {t:.2f} s (settlement {V * t / B:.1%} of B)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"figure: {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--cells-per-metre", type=int, nargs="+", default=[10, 20])
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--workdir", default="out/prandtl")
    ap.add_argument("--rerun", action="store_true")
    ap.add_argument("--phi", type=float, default=0.0, help="friction angle (degrees)")
    ap.add_argument("--psi", type=float, default=None, help="dilatancy angle (default: phi)")
    ap.add_argument("--scene", default=SCENE,
                    help="the footing scene (inputs/footing_prandtl_saturated_2d.nml: saturated soil)")
    ap.add_argument("--tensile", type=float, default=None,
                    help="tensile_strength of the soil (Pa), replacing the scene's")
    ap.add_argument("--band", type=float, nargs=2, default=[0.05, 0.10],
                    help="settlements / B over which the plateau is averaged")
    ap.add_argument("--plot")
    ap.add_argument("--fields", help="figure of the last frame of the finest run: plastic strain and "
                    "pore pressure (saturated scenes)")
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    psi = args.phi if args.psi is None else args.psi
    nc = prandtl_nc(args.phi)
    rows = []
    for cpm in args.cells_per_metre:
        sc = scene(args.scene, cpm, args.workdir, args.phi, psi, args.tensile)
        try:
            r = dpmpm.simulate(sc, ranks=args.ranks, binary=args.bin, reuse=not args.rerun,
                               progress=sys.stderr.isatty())
            if not r.reused:
                print(f"{sc.name}: exit code 0, {r.wall:.0f} s", flush=True)
        except dpmpm.RunError as e:
            print(f"{sc.name}: exit code {e.status}: {e}", flush=True)
        s, q = curve(sc.output_file())
        band = (s >= args.band[0]) & (s <= args.band[1])
        rows.append((cpm, s, q, q[band].mean(), q[band].min(), q[band].max()))
    print(f"phi = {args.phi} deg, psi = {psi} deg: Prandtl N_c = {nc:.3f}")
    print(f"| h (m) | q/c, mean over settlement {args.band[0]:.1%}-{args.band[1]:.1%} of B | range | "
          f"against N_c = {nc:.3f} |")
    print("|---|---|---|---|")
    for cpm, s, q, mean, lo, hi in rows:
        print(f"| {1.0 / cpm:.3f} | {mean:.3f} | {lo:.2f} - {hi:.2f} | {mean / nc - 1.0:+.1%} |")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        for cpm, s, q, *_ in rows:
            ax.plot(s, q, label=f"h = {1.0 / cpm:.3f} m")
        ax.axhline(nc, color="k", ls="--", lw=0.8, label=f"Prandtl N_c = {nc:.2f}")
        ax.set_xlabel("settlement / B")
        ax.set_ylabel("q / c")
        ax.set_title(f"Rigid strip footing, φ = {args.phi:g}°, ψ = {psi:g}°")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"figure: {args.plot}")
    if args.fields:
        cpm = max(args.cells_per_metre)
        plot_fields(scene(args.scene, cpm, args.workdir, args.phi, psi, args.tensile).output_file(),
                    args.fields)


if __name__ == "__main__":
    main()
