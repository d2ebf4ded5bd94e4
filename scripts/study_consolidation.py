#!/usr/bin/env python3
"""A parametric study of the consolidation column (doc/study_tutorial.md): the soil's
hydraulic conductivity k swept over three values, the scenes built from
inputs/consolidation_2d.nml as dpmpm.Scene objects, run with dpmpm.study, and the
settlement of the top and the degree of consolidation of each run set beside Terzaghi's
closed form (dpmpm.terzaghi) in one figure, with a table of the errors.

    python3 scripts/study_consolidation.py                  # the tutorial's figure and table
    python3 scripts/study_consolidation.py --quick --tolerance 0.05   # the test (ctest)

--quick runs a coarse grid (2 x 10 cells) for 0.3 s, a few seconds in all. The exit status
is 1 when a settlement or U error of the table is above --tolerance or the figure was
not written.

The cells are marked "# %%" as in a notebook; the page shows them in order.
"""
# %% [1] The base scene and the sweep
import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm                                   # noqa: E402
from dpmpm import terzaghi                     # noqa: E402

CONDUCTIVITIES = (2.5e-4, 1.0e-3, 4.0e-3)      # m/s: c_v = 0.247, 0.990, 3.96 m^2/s


def build_scenes(quick=False, outdir="out/study_consolidation"):
    """One scene per conductivity, from the default consolidation column."""
    base = dpmpm.Scene.read(os.path.join(ROOT, "inputs", "consolidation_2d.nml"))
    if quick:   # 2 x 10 cells of 10 cm: 4 times fewer points and twice the time step
        base.set(grid={"ncells": [2, 10]}, run={"t_end": 0.3}, output={"frame_interval": 0.02})
    else:
        base.set(run={"t_end": 1.0}, output={"frame_interval": 0.01})
    base.set(run={"progress_seconds": 1.0}, output={"dir": outdir})
    scenes = []
    for k in CONDUCTIVITIES:
        s = base.copy()
        s.set(run={"name": f"column_k{k:.1e}".replace("+", "").replace(".", "p")})
        [soil] = s.find("material", model="linear_elastic")
        soil["conductivity"] = k
        scenes.append(s)
    return scenes


# %% [2] Settlement and degree of consolidation of one run, beside Terzaghi
def measure(result):
    """Per frame after the load ramp: the settlement of the top row of solid points and
    its Terzaghi value at the same points, and the degree of consolidation from the
    cell-averaged pore pressure, U = 1 - <p> / p0, with the same average of Terzaghi's p."""
    with result.open() as run:
        setup = dpmpm.terzaghi_setup(run)                 # H, q, E_c, c_v, p0, ramp
        solid = dpmpm.points_dataset(run, "solid")        # labelled: time, id, component
        later = [k for k, t in enumerate(run.times) if t > 2.0 * setup.ramp]
        cells = [dpmpm.compare_terzaghi(run, k, setup) for k in later]
        cell = run.grid.length[setup.axis] / run.grid.ncells[setup.axis]
    ax = "xyz"[setup.axis]
    u = solid.displacement.sel(component=ax)
    depth0 = setup.sign * ((solid.x.sel(component=ax) - u).isel(time=0) - setup.top)
    top = solid.id.values[(depth0 < 0.5 * cell).values]                 # the points of the top cells
    d_top = float(depth0.sel(id=top).mean())
    m = {"setup": setup, "depth": d_top, "wall": result.wall}
    m["t"] = solid.time.values[later]
    m["te"] = m["t"] - setup.ramp / 2.0                   # the ramp delays by half its length
    m["tv"] = setup.c_v * m["te"] / setup.h ** 2
    m["settlement"] = setup.sign * u.sel(id=top).mean("id").values[later]
    m["settlement_ref"] = np.array([
        terzaghi.settlement(depth0.sel(id=top).values, te, setup.h, setup.c_v, setup.p0,
                            setup.q, setup.e_c).mean() for te in m["te"]])
    m["U"] = np.array([1.0 - np.nanmean(c.p) / setup.p0 for c in cells])
    m["U_ref"] = np.array([1.0 - np.nanmean(c.p_ref) / setup.p0 for c in cells])
    # Errors: settlement in units of the consolidation settlement H p0 / E_c (from the
    # undrained to the final one), U as it is, p in p0 (the largest over cells and frames).
    scale = setup.h * setup.p0 / setup.e_c
    m["err_settlement"] = float(np.max(np.abs(m["settlement"] - m["settlement_ref"]))) / scale
    m["err_U"] = float(np.max(np.abs(m["U"] - m["U_ref"])))
    m["err_p"] = float(max(c.err_p for c in cells))
    return m


# %% [3] The figure
def plot(runs, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.ticker
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11.0, 4.6))
    for k, (kk, m) in enumerate(runs):
        s, col = m["setup"], f"C{k}"
        lab = f"k = {kk:.2g} m/s, $c_v$ = {s.c_v:.3g} m²/s"
        tt = np.geomspace(m["t"][0], m["t"][-1], 200)
        ref = [terzaghi.settlement(m["depth"], t - s.ramp / 2.0, s.h, s.c_v, s.p0, s.q, s.e_c)
               for t in tt]
        a1.plot(tt, 1e3 * np.array(ref), "-", color=col, lw=1.2)
        a1.plot(m["t"], 1e3 * m["settlement"], "o", color=col, ms=3.5, mfc="none", label=lab)
        a2.plot(m["tv"], m["U"], "o", color=col, ms=3.5, mfc="none", label=lab)
    tv = np.geomspace(min(m["tv"][0] for _, m in runs), max(m["tv"][-1] for _, m in runs), 200)
    a2.plot(tv, terzaghi.degree(tv), "k-", lw=1.2, label="Terzaghi U($T_v$)")
    s = runs[0][1]["setup"]
    a1.axhline(1e3 * s.q * (s.h - runs[0][1]["depth"]) / s.e_c, color="0.6", ls=":", lw=1)
    a1.set_xlabel("time t (s)")
    a1.set_ylabel(f"settlement of the top points (mm), depth {runs[0][1]['depth'] * 100:.3g} cm")
    a1.set_title("settlement: dpmpm (circles), Terzaghi (lines)", fontsize=10)
    a2.set_xlabel("time factor $T_v = c_v (t - t_r/2) / H^2$")
    a2.set_ylabel("degree of consolidation U = 1 - <p> / $p_0$")
    a2.set_title("all runs on Terzaghi's one curve", fontsize=10)
    for a in (a1, a2):
        a.set_xscale("log")
        a.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize="small", loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


# %% [4] The table of errors against Terzaghi
def table(runs):
    rows = ["| k (m/s) | c_v (m²/s) | T_v at the end | U at the end | settlement error "
            "(H p0/E_c) | U error | p error (p0) | wall (s) |",
            "|---|---|---|---|---|---|---|---|"]
    for kk, m in runs:
        rows.append(f"| {kk:.2g} | {m['setup'].c_v:.4g} | {m['tv'][-1]:.3g} | "
                    f"{m['U'][-1]:.4f} | {m['err_settlement']:.2e} | {m['err_U']:.2e} | "
                    f"{m['err_p']:.2e} | {m['wall']:.1f} |")
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="coarse grid, 0.3 s (the test)")
    ap.add_argument("--workdir", default=".", help="where out/study_consolidation/ is made")
    ap.add_argument("--figure", default=os.path.join(ROOT, "doc", "figures",
                                                     "study_consolidation.png"))
    ap.add_argument("--ranks", type=int, default=1, help="ranks per run (default 1)")
    ap.add_argument("--jobs", type=int, default=2, help="runs side by side (default 2)")
    ap.add_argument("--binary", help="the dpmpm executable (default: dpmpm.find_binary)")
    ap.add_argument("--tolerance", type=float,
                    help="exit 1 when a settlement or U error is above this")
    ap.add_argument("--no-progress", action="store_true", help="no progress bars")
    a = ap.parse_args(argv)

    t0 = time.perf_counter()
    scenes = build_scenes(a.quick)
    results = dpmpm.study(scenes, ranks=a.ranks, jobs=a.jobs, workdir=a.workdir,
                          binary=a.binary, progress=not a.no_progress, errors="raise")
    runs = [(k, measure(r)) for k, r in zip(CONDUCTIVITIES, results)]
    os.makedirs(os.path.dirname(os.path.abspath(a.figure)), exist_ok=True)
    plot(runs, a.figure)
    print("\n".join(table(runs)))
    print(f"{a.figure}  ({len(runs)} runs, {time.perf_counter() - t0:.1f} s in all)")

    bad = []
    if not os.path.getsize(a.figure) > 0:
        bad.append(f"{a.figure} is empty")
    if a.tolerance is not None:
        for kk, m in runs:
            for what in ("err_settlement", "err_U"):
                if not m[what] <= a.tolerance:
                    bad.append(f"k = {kk:g}: {what} = {m[what]:.3g} > {a.tolerance:g}")
    for b in bad:
        print("FAILED:", b, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
