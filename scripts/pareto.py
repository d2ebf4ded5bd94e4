#!/usr/bin/env python3
"""Speed against error: every shape-function choice at several resolutions, on the
manufactured solution M1 (both amplitudes) and the saturated column W1 (1D and 2D).

Each run is one dpmpm process on one rank, one at a time (release build); its cost is
the wall time of the step loop (verification attribute wall_time_step_loop), its error
the benchmark's own measure: e_u(T) for M1 (doc/verification.md, "Manufactured
solution M1"), error_sigma_eff for W1 (doc/verification.md, "Figure 6"). M1 runs with
diagnostics at the automatic interval (about 500 records) instead of every step, so that
the cost is that of the step.

Writes the tables and, for each benchmark, the cheapest choice that reaches each error
level between the markers <!-- pareto:begin --> and <!-- pareto:end --> of
doc/performance.md, and the log-log figure doc/figures/speed_error.png.

Usage: scripts/pareto.py [--quick] [--skip-runs | --missing] [--out out/pareto]
"""
import argparse
import json
import os
import re
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402
import figure6  # noqa: E402
import verify_mls  # noqa: E402

DOC = os.path.join(ROOT, "doc", "performance.md")
FIG = os.path.join(ROOT, "doc", "figures", "speed_error.png")
BEGIN, END = "<!-- pareto:begin -->", "<!-- pareto:end -->"

M1_CELLS = [8, 16, 32, 64]
W1_CELLS = [50, 100, 200]
# Linear grid functions with the stress taken at one Gauss point per cell instead of at
# the points: its MLS reconstruction with the radial linear hat of radius 0.75 cells as
# weight, which reaches the whole cell (half its diagonal is 0.71 cells in 2D) and, with
# 2 x 2 regular points per cell, none of the neighbours' points (0.79 cells away).
LINEAR_GAUSS = ("kernel = 'linear', quadrature = 'gauss', gauss_points = 1, "
                "field_kernel = 'linear', field_radius = 0.75")
# M1 choices of scripts/verify_mls.py plus that one.
M1_COMBOS = dict(verify_mls.COMBOS)
M1_COMBOS["linear + one Gauss point"] = LINEAR_GAUSS
# W1 variants of Figure 6 plus the B-spline choices with point quadrature and that one.
W1_VARIANTS = dict(figure6.VARIANTS)
W1_VARIANTS["quadratic B-spline"] = "kernel = 'quadratic', quadrature = 'points'"
W1_VARIANTS["cubic B-spline"] = "kernel = 'cubic', quadrature = 'points'"
W1_VARIANTS["linear + one Gauss point"] = LINEAR_GAUSS


def slug(s):
    return re.sub(r"[^a-z0-9]+", "_", s.lower()).strip("_")


def run(build, scene):
    """Run a scene on one rank (dpmpm.simulate, the log beside the output); its exit code."""
    try:
        dpmpm.simulate(scene, binary=os.path.join(build, "dpmpm"), progress=False)
        return 0
    except dpmpm.RunError as e:
        return e.status


def m1_scene(label, cells, amp, outdir, tag):
    """The M1 scene of scripts/verify_mls.py, with diagnostics at the automatic interval."""
    s = verify_mls.scene(label, cells, amp, outdir, tag, shape=M1_COMBOS[label])
    s["output"]["diag_every"] = 0
    return s


def w1_scene(dims, label, cells, outdir, tag):
    """The W1 scene of scripts/figure6.py with `cells` along the column."""
    _, s = figure6.make_scene(dims, label, outdir, shape=W1_VARIANTS[label], tag=tag)
    if s["grid"]["ncells"] != (100 if dims == 1 else [100, 2]):
        raise SystemExit(f"pareto: {figure6.scene_file(dims)} is not the column of 100 cells")
    # The cross-section keeps its 0.2 m; its cells follow the column's size.
    s["grid"]["ncells"] = cells if dims == 1 else [cells, max(2, round(2 * cells / 100))]
    return s


def attrs(outdir, tag):
    path = os.path.join(outdir, tag + ".h5")
    if not os.path.exists(path):
        return None
    with dpmpm.open_run(path) as r:
        return r.verification_attrs or None


def cases(quick):
    m1_cells = M1_CELLS[:2] if quick else M1_CELLS
    w1_cells = W1_CELLS[:2] if quick else W1_CELLS
    out = []
    for amp in verify_mls.AMPLITUDES:
        bench = f"M1, B = {amp:g}"
        for label in M1_COMBOS:
            for c in m1_cells:
                out.append((bench, label, c, f"pm1_{slug(label)}_{c}_{'small' if amp < 1e-2 else 'large'}",
                            lambda outdir, tag, label=label, c=c, amp=amp: m1_scene(label, c, amp, outdir, tag)))
    for dims in (1, 2):
        bench = f"W1 {dims}D"
        for label in W1_VARIANTS:
            for c in w1_cells:
                out.append((bench, label, c, f"pw1_{dims}d_{slug(label)}_{c}",
                            lambda outdir, tag, label=label, c=c, dims=dims: w1_scene(dims, label, c, outdir, tag)))
    return out


def error_of(bench, a):
    return a["final_error_displacement"] if bench.startswith("M1") else a["final_error_sigma_eff"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "pareto"))
    ap.add_argument("--quick", action="store_true", help="two resolutions each (a smoke run)")
    ap.add_argument("--skip-runs", action="store_true", help="use the outputs already in --out")
    ap.add_argument("--missing", action="store_true",
                    help="run only the cases without a finished output in --out")
    ap.add_argument("--no-doc", action="store_true")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    res = {}
    for bench, label, cells, tag, make in cases(a.quick):
        at = attrs(a.out, tag) if a.skip_runs or a.missing else None
        if not a.skip_runs and (at is None or "wall_time_step_loop" not in at):
            rc = run(a.build, make(a.out, tag))
            print(f"pareto: {bench:14s} {label:32s} {cells:4d} rc {rc}", file=sys.stderr)
            at = attrs(a.out, tag)
        if at is None or "wall_time_step_loop" not in at:
            res.setdefault(bench, {}).setdefault(label, []).append((cells, np.nan, np.nan))
            continue
        res.setdefault(bench, {}).setdefault(label, []).append(
            (cells, float(at["wall_time_step_loop"]), float(error_of(bench, at))))
    with open(os.path.join(a.out, "pareto.json"), "w") as f:
        json.dump(res, f, indent=1)

    md = ["Measured by `scripts/pareto.py` (release build, one rank, one run at a time): wall time "
          "of the step loop against the benchmark's error, every shape choice at each resolution "
          "(cells per unit length for M1, cells along the 10 m column for W1). M1 error: e_u(T); "
          "W1 error: error_sigma_eff at 0.05 s (both as in doc/verification.md).", ""]
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    for ax, (bench, by) in zip(axes.flat, res.items()):
        md.append(f"**{bench}**: wall s / error per resolution.\n")
        cells = sorted({c for v in by.values() for c, _, _ in v})
        md.append("| choice | " + " | ".join(f"{c} cells" for c in cells) + " |")
        md.append("|---|" + "---|" * len(cells))
        for label, rows in by.items():
            cols = {c: (w, e) for c, w, e in rows}
            md.append(f"| {label} | " + " | ".join(
                f"{cols[c][0]:.3g} s / {cols[c][1]:.3g}" if c in cols and np.isfinite(cols[c][0]) else "failed"
                for c in cells) + " |")
            pts = [(w, e) for _, w, e in rows if np.isfinite(w)]
            if pts:
                ax.loglog([p[1] for p in pts], [p[0] for p in pts], "o-", label=label, ms=4)
        # The cheapest run that reaches each error level (decades spanned by the runs).
        allrows = [(w, e, label, c) for label, rows in by.items() for c, w, e in rows if np.isfinite(w)]
        errs = [e for _, e, _, _ in allrows]
        lo, hi = int(np.floor(np.log10(min(errs)))), int(np.ceil(np.log10(max(errs))))
        picks = []
        for k in range(hi, lo - 1, -1):
            for m in (3.0, 1.0):
                level = m * 10.0**k
                ok = [r for r in allrows if r[1] <= level]
                if ok and level < max(errs):
                    w, e, label, c = min(ok)
                    picks.append(f"{level:.0e}: {label} at {c} cells ({w:.3g} s, error {e:.3g})")
        md.append("")
        md.append("Cheapest choice that reaches an error of at most " + "; ".join(picks) + ".")
        md.append("")
        ax.set_title(bench)
        ax.set_xlabel("error")
        ax.set_ylabel("wall time of the step loop (s)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    os.makedirs(os.path.dirname(FIG), exist_ok=True)
    fig.savefig(FIG, dpi=110)
    md.append("![speed against error](figures/speed_error.png)")
    text = "\n".join(md)
    print(text)
    if not a.no_doc:
        doc = open(DOC).read()
        if BEGIN in doc and END in doc:
            doc = doc[:doc.index(BEGIN) + len(BEGIN)] + "\n" + text + "\n" + doc[doc.index(END):]
            open(DOC, "w").write(doc)
        else:
            print(f"pareto: no markers in {DOC}; not written", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
