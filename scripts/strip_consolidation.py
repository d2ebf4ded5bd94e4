#!/usr/bin/env python3
"""A strip load on saturated soil from undrained to drained (inputs/footing_consolidation_2d.nml).

Runs the scene and its dry twin (the same skeleton as a one-phase solid under the same
load, with local damping over the whole run so that it comes to rest: the drained state)
with BIN on --ranks ranks in --workdir (unless their outputs are there and --rerun is not
given), and reports:

- the settlement s(t) under the strip (mean vertical displacement of the solid points of
  the top cell row with x < b) against the dry twin's s_d, and the degree of
  consolidation U = (s - s_u) / (s_d - s_u), s_u the mean settlement over the 0.2 s after
  the ramp (undrained);
- the excess pore pressure under the axis (fluid points of the first cell column) at
  depths z against q alpha / pi, alpha = 2 atan(b / z), the mean in-plane total stress of
  an elastic half-space under the strip, which the water carries while the soil is
  undrained;
- at the end: the settlement averaged over the last third of the run (the skeleton still
  rings about its rest state, undamped) against s_d, and the largest |p| against q.

    python3 scripts/strip_consolidation.py --bin build/release/dpmpm --workdir out/consolidation \\
        [--plot doc/figures/strip_consolidation.png] [--ranks 1] [--rerun]
"""
import argparse
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402
from dpmpm.run import open_run  # noqa: E402

SCENE = os.path.join(ROOT, "inputs", "footing_consolidation_2d.nml")


def scenes(workdir):
    """The saturated scene and its dry twin, as dpmpm.Scenes."""
    sat = dpmpm.Scene.read(SCENE)
    sat.set(run={"name": "saturated"}, output={"dir": workdir})
    # the dry twin: local damping over the whole run (there is no gravity to ramp)
    dry = sat.copy()
    dry.set(run={"name": "dry", "equilibrium_time": sat["run"]["t_end"],
                 "equilibrium_damping": 0.3})
    [region] = dry.groups("region")
    region.update(phase="solid", fluid_material=0, porosity=0.0)
    return [sat, dry]


def settlement(fr, b, top, h):
    s = fr["solid"]
    x = s["x"]
    sel = (x[:, 0] < b) & (x[:, 1] > top - h)
    return s["displacement"][sel, 1].mean()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--workdir", default="out/consolidation")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--rerun", action="store_true")
    ap.add_argument("--plot")
    ap.add_argument("--depths", type=float, nargs="+", default=[0.5, 1.0, 2.0])
    args = ap.parse_args()
    workdir = os.path.abspath(args.workdir)
    os.makedirs(workdir, exist_ok=True)
    for scene in scenes(workdir):
        try:
            r = dpmpm.simulate(scene, ranks=args.ranks, binary=args.bin, reuse=not args.rerun,
                               progress=sys.stderr.isatty())
        except dpmpm.RunError as e:
            print(f"{scene.name}: exit code {e.status}", flush=True)
            sys.exit(f"{scene.name} failed: {e}")
        if not r.reused:
            print(f"{scene.name}: exit code 0, {r.wall:.0f} s", flush=True)

    with open_run(os.path.join(workdir, "dry.h5")) as run:
        g = run.grid
        top, h = g.origin[1] + g.length[1], g.spacing[1]
        load = run.input_groups("load")[0]
        q = -float(load["traction"][1])
        b = float(load["hi"][0]) - float(load["lo"][0])
        ramp = float(np.ravel(load["ramp_time"])[0])
        s_dry = settlement(run.frames[-1], b, top, h)
        s_dry_prev = settlement(run.frames[-11], b, top, h)
    with open_run(os.path.join(workdir, "saturated.h5")) as run:
        t = run.times
        s = np.array([settlement(fr, b, top, h) for fr in run.frames])
        pz = {z: [] for z in args.depths}
        pmax = []
        for fr in run.frames:
            f = fr["fluid"]
            x, p = f["x"], f["pore_pressure"]
            pmax.append(np.abs(p).max())
            for z in args.depths:
                sel = (x[:, 0] < g.spacing[0]) & (np.abs(top - x[:, 1] - z) < 0.5 * h)
                pz[z].append(p[sel].mean())
        pz = {z: np.array(v) for z, v in pz.items()}
        pmax = np.array(pmax)
    und = (t > ramp) & (t <= ramp + 0.2 + 1e-9)
    s_u = s[und].mean()
    U = (s - s_u) / (s_dry - s_u)
    print(f"strip half-width b = {b} m, q = {q / 1e3:.0f} kPa, ramp {ramp} s, cells {h} m")
    print(f"dry twin (drained): settlement {s_dry * 1e3:.3f} mm "
          f"(a second earlier {s_dry_prev * 1e3:.3f} mm)")
    print(f"undrained (mean over {ramp}-{ramp + 0.2:.1f} s): settlement {s_u * 1e3:.3f} mm "
          f"= {s_u / s_dry:.3f} of drained")
    print("| t (s) | settlement (mm) | s / s_d | U | " +
          " | ".join(f"p(z = {z:g} m) / (q alpha/pi)" for z in args.depths) + " |")
    print("|---|---|---|---|" + "---|" * len(args.depths))
    exact = {z: q * 2.0 * np.arctan(b / z) / np.pi for z in args.depths}
    for tt in [ramp, 0.2, 0.5, 1.0, 2.0, 3.0, 5.0, 7.5, 10.0, t[-1]]:
        k = int(np.argmin(np.abs(t - tt)))
        print(f"| {t[k]:.2f} | {s[k] * 1e3:.3f} | {s[k] / s_dry:.3f} | {U[k]:.3f} | " +
              " | ".join(f"{pz[z][k] / exact[z]:.3f}" for z in args.depths) + " |")
    last = t >= t[-1] * 2.0 / 3.0
    s_end, s_sd = s[last].mean(), s[last].std()
    print(f"end (mean over t >= {t[-1] * 2 / 3:.1f} s, {last.sum()} frames): settlement "
          f"{s_end * 1e3:.3f} mm (std {s_sd * 1e3:.3f}) = {s_end / s_dry:.4f} of drained "
          f"({s_end / s_dry - 1:+.2%}); largest |p| {pmax[last].max() / q:.4f} q, "
          f"at the last frame {pmax[-1] / q:.4f} q")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
        ax[0].plot(t, s / s_dry, lw=1, label="saturated")
        ax[0].axhline(1.0, color="k", ls="--", lw=0.8, label="drained (dry twin)")
        ax[0].axhline(s_u / s_dry, color="0.5", ls=":", lw=0.8, label="undrained (after the ramp)")
        ax[0].set_xlabel("t (s)")
        ax[0].set_ylabel("settlement under the strip / drained")
        ax[0].legend(fontsize=8)
        for z in args.depths:
            ax[1].plot(t, pz[z] / exact[z], lw=1, label=f"z = {z:g} m")
        ax[1].axhline(1.0, color="k", ls="--", lw=0.8)
        ax[1].set_xscale("log")
        ax[1].set_xlim(0.05, t[-1])
        ax[1].set_xlabel("t (s)")
        ax[1].set_ylabel("excess pore pressure / (q α/π)")
        ax[1].legend(fontsize=8)
        fig.suptitle("Strip load on saturated soil: consolidation (inputs/footing_consolidation_2d.nml)",
                     fontsize=10)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"figure: {args.plot}")


if __name__ == "__main__":
    main()
