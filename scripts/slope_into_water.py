#!/usr/bin/env python3
"""A saturated slope sliding into a pool of water (inputs/slope_into_water_2d.nml).

Runs the scene (or reads an earlier run in the work directory) and prints what the scene
is for, frame by frame: the runout of the soil front into the pool, the height of the
water surface at a few places in the pool (the wave the slide raises), the deposit of the
last frame (height of the soil surface across the grid), the pore pressure of the water in
the soil against the hydrostatic pressure of the pool, and the largest speeds. With
--compare it gives the largest difference of positions and pore pressures (points matched
by id) against another run of the scene, frame by frame. It draws the soil points
coloured by their plastic strain and the water points at four times, and the front and
the water levels against time (doc/verification.md, "Saturated slope sliding into water").
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "python"))
import dpmpm  # noqa: E402
from dpmpm.launch import scene_arguments  # noqa: E402

SCENE = "inputs/slope_into_water_2d.nml"
RHO_G = 1000.0 * 9.81  # unit weight of the water (N/m^3)
LEVEL = 1.5            # initial pool level (m)
HALF = 0.025           # half the initial point spacing (0.1 m cells, 2 x 2 points)
PROBES = (7.0, 9.0, 11.0)      # where the water surface is measured (m)
DEPOSIT = np.arange(0.0, 12.01, 1.0)  # where the soil surface is measured (m)


def scene(args):
    """The scene with its output in the work directory and the kernel, end time and
    porosity_gradient asked (each but the kernel named in the run's name)."""
    s = dpmpm.Scene.read(SCENE)
    name = f"slope_into_water_2d_{args.kernel}_np{args.ranks}"
    if args.porosity_gradient:
        name += f"_pg{args.porosity_gradient}"
        s["run"]["porosity_gradient"] = args.porosity_gradient == "on"
    if args.t_end:
        name += f"_t{args.t_end:g}"
        s["run"]["t_end"] = args.t_end
    s.set(run={"name": name}, output={"dir": os.path.abspath(args.workdir)},
          shape={"kernel": args.kernel})
    return s


def run(args):
    """Runs the scene unless its output is in the work directory; returns the output file."""
    r = dpmpm.simulate(scene(args), ranks=args.ranks, binary=args.bin, reuse=not args.rerun,
                       progress=sys.stderr.isatty())
    return r.output


def frames(h5):
    """The frames of a run as dicts of arrays, sorted by point id, and the diagnostics."""
    out = []
    with dpmpm.open_run(h5) as run:
        for g in run.frames:
            fr = {"time": g.time, "step": g.step}
            for s, names in (("solid", ("id", "x", "v", "plastic_strain")),
                             ("fluid", ("id", "x", "v", "porosity", "pore_pressure"))):
                for n in names:
                    fr[s + "/" + n] = g[s][n]
            out.append(fr)
        diag = run.diagnostics
    return out, diag


def top(x, y, at, half=0.05):
    """Height of the highest point within half of `at` (the surface: + half a point
    spacing), NaN where there is none."""
    sel = np.abs(x - at) <= half
    return y[sel].max() + HALF if sel.any() else float("nan")


def front(xs):
    """The soil front: the right edge of the last 0.1 m column holding at least two
    soil points (a point or two thrown ahead do not count)."""
    cols = np.floor(xs[:, 0] / 0.1).astype(int)
    n = np.bincount(cols)
    full = np.nonzero(n >= 2)[0]
    return (full.max() + 1) * 0.1


def measure(fr):
    xs, xf = fr["solid/x"], fr["fluid/x"]
    m = {"t": fr["time"], "front": front(xs), "x_max": xs[:, 0].max()}
    m["water"] = [top(xf[:, 0], xf[:, 1], x) for x in PROBES]
    m["soil"] = [top(xs[:, 0], xs[:, 1], x) for x in DEPOSIT]
    m["vs"] = np.linalg.norm(fr["solid/v"], axis=1).max()
    m["vf"] = np.linalg.norm(fr["fluid/v"], axis=1).max()
    m["ep"] = fr["solid/plastic_strain"].max()
    # The water in the soil: its excess over the hydrostatic pressure of the pool.
    pore = fr["fluid/porosity"] < 0.99
    y = xf[pore, 1]
    dp = fr["fluid/pore_pressure"][pore] - RHO_G * np.maximum(LEVEL - y, 0.0)
    m["dp"] = np.percentile(dp, [1, 50, 99]) if dp.size else [np.nan] * 3
    m["cav"] = int(np.count_nonzero(fr["fluid/pore_pressure"] <= -0.999e5))
    m["pmax"] = fr["fluid/pore_pressure"].max()
    return m


def compare(a, b):
    """Largest differences of two runs' frames at the same times (points by id)."""
    print("time (s)  largest |x1 - x2| solid, fluid (m)   largest |p1 - p2| (Pa)")
    for fa in a:
        fb = min(b, key=lambda f: abs(f["time"] - fa["time"]))
        if abs(fb["time"] - fa["time"]) > 1e-6:
            continue
        dx = []
        for s in ("solid", "fluid"):
            ids = np.intersect1d(fa[s + "/id"], fb[s + "/id"])
            ia = np.searchsorted(fa[s + "/id"], ids)
            ib = np.searchsorted(fb[s + "/id"], ids)
            dx.append(np.abs(fa[s + "/x"][ia] - fb[s + "/x"][ib]).max())
            if s == "fluid":
                dp = np.abs(fa[s + "/pore_pressure"][ia] - fb[s + "/pore_pressure"][ib]).max()
        print(f"  {fa['time']:6.2f}   {dx[0]:.2e}  {dx[1]:.2e}   {dp:.2e}")


def plot(frs, ms, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t_end = frs[-1]["time"]
    pick = [min(frs, key=lambda f: abs(f["time"] - s * t_end)) for s in (0.0, 1 / 3, 2 / 3, 1.0)]
    fig = plt.figure(figsize=(10, 13))
    for i, fr in enumerate(pick):
        ax = fig.add_subplot(5, 1, i + 1)
        xf, xs = fr["fluid/x"], fr["solid/x"]
        # every water point, the pore water included: the soil points drawn over them hide
        # the pores, and the water beside the soil that takes its porosity (within the
        # reach of its nodes) shows as water
        ax.scatter(xf[:, 0], xf[:, 1], s=0.6, c="tab:blue", label="water")
        a = ax.scatter(xs[:, 0], xs[:, 1], s=1.6, c=fr["solid/plastic_strain"], cmap="YlOrBr",
                       vmin=0.0, vmax=2.0)
        fig.colorbar(a, ax=ax, label="plastic strain", pad=0.01)
        ax.set_aspect("equal")
        ax.set_xlim(0.0, 12.0)
        ax.set_ylim(0.0, 3.5)
        ax.set_ylabel("y (m)")
        ax.text(0.2, 3.15, f"t = {fr['time']:.2f} s")
    ax.set_xlabel("x (m)")
    ax = fig.add_subplot(5, 1, 5)
    t = [m["t"] for m in ms]
    ax.plot(t, [m["front"] for m in ms], "k-", label="soil front x (m)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("soil front x (m)")
    ax2 = ax.twinx()
    for j, x in enumerate(PROBES):
        ax2.plot(t, [m["water"][j] for m in ms], label=f"water surface at x = {x:g} m")
    ax2.set_ylabel("water surface y (m)")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, loc="lower right", fontsize=8)
    ax.grid(True, alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    print(f"figure: {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    scene_arguments(ap, 3.0, "out/slope_into_water")
    ap.add_argument("--porosity-gradient", choices=("on", "off"),
                    help="replace the scene's choice of porosity_gradient (off)")
    ap.add_argument("--h5", help="read this output file instead of running the scene")
    ap.add_argument("--compare", help="another run's output file: largest differences by id")
    ap.add_argument("--plot", default="doc/figures/slope_into_water.png")
    args = ap.parse_args()
    h5 = args.h5 or run(args)
    frs, diag = frames(h5)
    ms = [measure(fr) for fr in frs]
    dt = diag["dt"][diag["step"] > 0]
    print(f"{h5}: {frs[-1]['step']} steps to t = {frs[-1]['time']:.3f} s; time step first "
          f"{diag['dt'][0]:.4e} s, smallest before the last {dt[:-1].min():.4e} s")
    print("  t (s)  front (m)  runout (m)  x_max (m)  water surface at x = "
          + ", ".join(f"{x:g}" for x in PROBES) + " m   |v_s|, |v_f| (m/s)  "
          "excess p in the soil, 1/50/99 % (kPa)  at cavitation")
    for m in ms:
        print(f"  {m['t']:5.2f}  {m['front']:8.2f}  {m['front'] - ms[0]['front']:9.2f}  "
              f"{m['x_max']:8.2f}   " + "  ".join(f"{h:6.3f}" for h in m["water"])
              + f"          {m['vs']:5.2f} {m['vf']:5.2f}      "
              + " / ".join(f"{v / 1e3:6.1f}" for v in m["dp"]) + f"     {m['cav']}")
    rise = np.array([m["water"] for m in ms]) - LEVEL
    for j, x in enumerate(PROBES):
        i = np.nanargmax(rise[:, j])
        print(f"wave at x = {x:g} m: largest rise {rise[i, j]:.3f} m at t = {ms[i]['t']:.2f} s, "
              f"lowest {np.nanmin(rise[:, j]):.3f} m")
    print("deposit (last frame), soil surface y at x = " + ", ".join(f"{x:g}" for x in DEPOSIT)
          + " m:\n  " + "  ".join(f"{h:.2f}" for h in ms[-1]["soil"]))
    print(f"  front {ms[-1]['front']:.2f} m (runout {ms[-1]['front'] - ms[0]['front']:.2f} m), "
          f"largest plastic strain {ms[-1]['ep']:.2f}, largest pore pressure "
          f"{ms[-1]['pmax'] / 1e3:.1f} kPa")
    print(f"largest speed over the run (diagnostics): {diag['max_speed'].max():.3f} m/s")
    if args.compare:
        compare(frs, frames(args.compare)[0])
    if args.plot:
        os.makedirs(os.path.dirname(os.path.abspath(args.plot)), exist_ok=True)
        plot(frs, ms, args.plot, f"Saturated slope sliding into water ({args.kernel}, "
             f"{args.ranks} rank{'s' if args.ranks > 1 else ''})")


if __name__ == "__main__":
    main()
