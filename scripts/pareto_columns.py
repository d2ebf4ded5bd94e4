#!/usr/bin/env python3
"""Speed against error of the shape choices on saturated columns of other physics: W1, W2,
W3 (doc/theory.md 9.1: strong drag, weak drag, stiff water) and W4 (a softer, more porous
and more permeable column with softer water, where linear grid functions with one Gauss
point per cell lose), each in 2D (100 x 2 cells of 0.1 m, rollers on the sides, 2 x 2
points per cell and phase) with the placements regular, random (per cell) and uniform.

Each run is one dpmpm process on one rank, one at a time (release build). The reference is
scripts/biot_laplace.py at the points' own depths (checked against the run's /verification
profiles, which dpmpm computes with src/verify/dpmpm_biot_column.f90). Measures, behind the
front (depth z < c_u t - 3 h, as overshoot_sigma_eff of src/verify/dpmpm_two_phase_verify.f90),
in units of the load q:
  * points: volume-weighted RMS over the solid points of sigma'_p - sigma'_ref(z_p), over the
    fluid points of p_p - p_ref(z_p);
  * cell means: in each grid column along x (the slab of cells at one x) the volume-weighted
    mean of (field - reference) over its points, RMS over the columns behind the front;
  * ms per step: wall_time_step_loop / steps of the run's /verification.
With --diagnose, the variants of the linear + one Gauss point choice on W4 that look for the
cause of its loss (doc/verification.md, "Empty Gauss points of linear + one Gauss point").

Writes the tables between <!-- columns:begin --> and <!-- columns:end --> of
doc/performance.md (--diagnose: <!-- columns_diag:begin/end --> of doc/verification.md).

Usage: scripts/pareto_columns.py [--diagnose] [--skip-runs | --missing] [--only REGEX] [--no-doc]
       [--out out/pareto_columns] [--build build/release]
"""
import argparse
import hashlib
import json
import os
import re
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import biot_laplace  # noqa: E402
import dpmpm  # noqa: E402
from pareto import LINEAR_GAUSS, run  # noqa: E402  (the choice and the launch of the M1/W1 study)

PERF = os.path.join(ROOT, "doc", "performance.md")
VERIF = os.path.join(ROOT, "doc", "verification.md")
CFL = 0.3
NCELLS, LENGTH, WIDTH = 100, 10.0, 0.2
H = LENGTH / NCELLS
FRONT_MARGIN = 3.0

# Columns: W1 of doc/theory.md 9.1 and the three that change one regime each.
W1 = dict(porosity=0.3, rho_s=2650.0, rho_f=1000.0, youngs=1.0e7, k_f=3.0e6, k=1.0e-5,
          t_end=0.05, drag="implicit")
COLUMNS = {
    "W1": W1,
    "W2": dict(W1, k=1.0, t_end=0.08, drag="explicit"),
    "W3": dict(W1, k_f=2.2e9, k=1.0e-4, t_end=0.004),
    "W4": dict(W1, porosity=0.4, rho_s=2600.0, youngs=2.0e7, k_f=3.0e7, k=1.0e-3, t_end=0.03),
}
PLACEMENTS = ["regular", "random", "uniform"]

CHOICES = {
    "Standard MPM": "kernel = 'linear'",
    "quadratic B-spline": "kernel = 'quadratic'",
    "cubic B-spline": "kernel = 'cubic'",
    "linear + one Gauss point": LINEAR_GAUSS,
    "pair, 3 Gauss points": ("kernel = 'cubic', quadrature = 'gauss', gauss_points = 3, "
                             "field_kernel = 'wendland_c2', field_radius = 2.0"),
    "pair, 2 Gauss points": ("kernel = 'cubic', quadrature = 'gauss', "
                             "field_kernel = 'wendland_c2', field_radius = 2.0"),
}

# The diagnosis (--diagnose). Table 1: W4 with uniform points, seeds 1-10, three choices.
# Table 2: variants of linear + one Gauss point, and the other columns, on the placements
# regular and random and on uniform seeds where it lost (5, 7) or not (1).
SEEDS = list(range(1, 11))
SCAN = ["Standard MPM", "linear + one Gauss point", "pair, 2 Gauss points"]
VARIANTS = {
    "linear + one Gauss point (r 0.75)": ("W4", LINEAR_GAUSS),
    "the same, 2 x 2 Gauss points": ("W4", LINEAR_GAUSS.replace("gauss_points = 1", "gauss_points = 2")),
    "the same, radius 1.0": ("W4", LINEAR_GAUSS.replace("0.75", "1.0")),
    "the same, box of half-width 0.65": ("W4", LINEAR_GAUSS.replace("0.75", "0.65")
                                         + ", field_support = 'box'"),
    "the same, Wendland C2 of radius 2": ("W4", LINEAR_GAUSS.replace(
        "field_kernel = 'linear', field_radius = 0.75", "field_kernel = 'wendland_c2', field_radius = 2.0")),
    "Standard MPM": ("W4", CHOICES["Standard MPM"]),
    "W1 column, linear + one Gauss point": ("W1", LINEAR_GAUSS),
    "W1 column, linear + one Gauss point, radius 1.0": ("W1", LINEAR_GAUSS.replace("0.75", "1.0")),
    "W1 column, Standard MPM": ("W1", CHOICES["Standard MPM"]),
    "W2 column, linear + one Gauss point": ("W2", LINEAR_GAUSS),
    "W2 column, linear + one Gauss point, radius 1.0": ("W2", LINEAR_GAUSS.replace("0.75", "1.0")),
    "W2 column, Standard MPM": ("W2", CHOICES["Standard MPM"]),
    "W3 column, linear + one Gauss point": ("W3", LINEAR_GAUSS),
    "W3 column, linear + one Gauss point, radius 1.0": ("W3", LINEAR_GAUSS.replace("0.75", "1.0")),
    "W3 column, Standard MPM": ("W3", CHOICES["Standard MPM"]),
}
VARIANT_PLACEMENTS = [("regular", 1), ("random", 1), ("uniform", 1), ("uniform", 5), ("uniform", 7)]


def place_label(placement, seed):
    return f"uniform, seed {seed}" if placement == "uniform" else placement


def scene(tag, outdir, col, shape, placement, seed, extra=None):
    """2D column along x (as inputs/w1_2d.nml): 100 x 2 cells, rollers on y- and y+, the
    drained loaded top x-, the fixed impermeable bottom x+, a 1 Pa step load, benchmark
    biot_column, as a dpmpm.Scene. extra may set cfl, flip, scheme, ppc, fluid_seed, ncells
    (along x) and the column's parameters, for runs beside the study's."""
    extra = extra or {}
    c = dict(col, **{k: v for k, v in extra.items() if k in col})
    nx = extra.get("ncells", NCELLS)
    ny = max(2, round(WIDTH / (LENGTH / nx)))
    s = dpmpm.Scene()
    s.add("run", name=tag, t_end=c["t_end"], cfl=extra.get("cfl", CFL), drag=c["drag"],
          flip=extra.get("flip", 1.0), scheme=extra.get("scheme", "musl"))
    s.add("grid", ndim=2, ncells=[nx, ny], origin=[0.0, 0.0], length=[LENGTH, WIDTH])
    s.replace("shape", shape)
    s.add("material", id=1, model="linear_elastic", density=c["rho_s"],
          youngs_modulus=c["youngs"], poisson_ratio=0.0, conductivity=c["k"])
    s.add("material", id=2, model="fluid", density=c["rho_f"], bulk_modulus=c["k_f"])
    s.add("region", shape="box", lo=[0.0, 0.0], hi=[LENGTH, WIDTH], material=1,
          phase="saturated", fluid_material=2, porosity=c["porosity"], ppc=extra.get("ppc", 2),
          placement=placement, seed=seed, fluid_seed=extra.get("fluid_seed", -1))
    s.add("boundary", face="x-", condition="free", fluid="drained")
    s.add("boundary", face="x+", condition="fixed", fluid="impermeable")
    s.add("boundary", face="y-", condition="roller")
    s.add("boundary", face="y+", condition="roller")
    s.add("load", face="x-", traction=[1.0, 0.0], ramp_time=0.0)
    s.add("output", dir=outdir, frame_interval=0.0)
    s.add("benchmark", name="biot_column")
    return s


_REF = {}


def reference(col, t_end):
    """Reference fields of a column on 4001 depths (2.5 mm apart), cached per column."""
    key = json.dumps(col, sort_keys=True) + f"{t_end:.9g}"
    if key not in _REF:
        bc = biot_laplace.column(LENGTH, col["porosity"], col["rho_s"], col["rho_f"], col["youngs"],
                                 col["k_f"], col["k"])
        z = np.linspace(0.0, LENGTH, 4001)
        _REF[key] = (bc, z, biot_laplace.fields(bc, t_end, z))
    return _REF[key]


def log_step_time(outdir, tag):
    """ms per step from the log line 'time per step X ms over N steps'."""
    m = re.search(r"time per step\s+([0-9.eE+-]+) ms", open(os.path.join(outdir, tag + ".log")).read())
    return float(m.group(1)) if m else np.nan


def log_empty_solves(outdir, tag):
    """Gauss-point reconstructions that found no point in reach, summed over the run (the
    last number of the log line 'MLS solves: ... empty'); 0 without Gauss quadrature."""
    m = re.search(r"MLS solves:[^:]*empty:\s+(?:\d+\s+){4}(\d+)", open(os.path.join(outdir, tag + ".log")).read())
    return int(m.group(1)) if m else 0


def measure(outdir, tag, col, ncells=NCELLS):
    """The measures of the module header for one finished run, or None."""
    path = os.path.join(outdir, tag + ".h5")
    if not os.path.exists(path):
        return None
    with dpmpm.open_run(path) as run:
        if "verification" not in run.file or not run.frames:
            return None
        v, va = run.verification, run.verification_attrs
        last = run.frames[-1]
        t = last.time
        solid, fluid = last["solid"], last["fluid"]
        xs, sig, vs = solid["x"][:, 0], solid["stress"][:, 0], solid["volume"]
        xf, p, vf = fluid["x"][:, 0], fluid["pore_pressure"], fluid["volume"]
        if "wall_time_step_loop" in va:
            ms = 1e3 * va["wall_time_step_loop"] / va["steps"]
        else:
            ms = log_step_time(outdir, tag)
        prof = (v["profile_z"], v["profile_p"], v["profile_sigma_eff"]) if "profile_z" in v else None
        run_err = va.get("final_error_sigma_eff", np.nan)
    bc, z, ref = reference(col, t)
    c_u = biot_laplace.wave_speed(bc)
    h = LENGTH / ncells
    front = c_u * t - FRONT_MARGIN * h
    check = np.nan
    if prof is not None:
        # The reference against the run's own (dpmpm_biot_column) away from the front.
        far = np.abs(prof[0] - c_u * t) > FRONT_MARGIN * h
        check = max(np.abs(np.interp(prof[0], z, ref["p"]) - prof[1])[far].max(),
                    np.abs(np.interp(prof[0], z, ref["sigma_eff"]) - prof[2])[far].max())
    out = dict(ms=ms, ref_check=float(check), run_error_sigma_eff=run_err, time=t,
               empty_solves=log_empty_solves(outdir, tag))
    edges = np.linspace(0.0, LENGTH, ncells + 1)
    for name, x, val, vol, field in (("sig", xs, sig, vs, "sigma_eff"), ("p", xf, p, vf, "p")):
        d = val - np.interp(x, z, ref[field])
        sel = x < front
        out[f"{name}_points"] = float(np.sqrt(np.sum(vol[sel] * d[sel] ** 2) / np.sum(vol[sel])))
        idx = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, ncells - 1)
        w = np.bincount(idx, weights=vol, minlength=ncells)
        s = np.bincount(idx, weights=vol * d, minlength=ncells)
        centre = 0.5 * (edges[:-1] + edges[1:])
        cells = (w > 0) & (centre < front)
        out[f"{name}_cells"] = float(np.sqrt(np.mean((s[cells] / w[cells]) ** 2)))
        # Grid columns along x without points of this set, over the whole column.
        out[f"{name}_empty_columns"] = int(np.sum(w == 0))
    return out


def cases(diagnose):
    """(table, row, column label, tag, column parameters, scene maker) of every run."""
    out = []

    def add(table, row, cname, shape, placement, seed):
        col = COLUMNS[cname]
        # The same column, points and shape give the same tag, so that --missing runs them once.
        key = hashlib.sha1(shape.encode()).hexdigest()[:10]
        tag = f"{'diag' if diagnose else 'col'}_{cname.lower()}_{placement}_{seed}_{key}"
        out.append((table, row, place_label(placement, seed) if diagnose else placement, tag, col,
                    lambda outdir, tag=tag, col=col, shape=shape, p=placement, s=seed:
                    scene(tag, outdir, col, shape, p, s)))
    if diagnose:
        for label in SCAN:
            for seed in SEEDS:
                add("seeds", label, "W4", CHOICES[label], "uniform", seed)
        for label, (cname, shape) in VARIANTS.items():
            for placement, seed in VARIANT_PLACEMENTS:
                add("variants", label, cname, shape, placement, seed)
        return out
    for cname in COLUMNS:
        for placement in PLACEMENTS:
            for label, shape in CHOICES.items():
                add(cname, label, cname, shape, placement, 1)
    return out


def quad(r, keys=("sig_points", "p_points", "sig_cells", "p_cells")):
    return " / ".join(f"{r[k]:.3f}" for k in keys) if r else "failed"


def tables(res):
    md = ["Measured by `scripts/pareto_columns.py` (release build, one rank, one run at a time, "
          f"Courant number {CFL}): RMS errors behind the front (depth below c_u t - 3 cells) in "
          "units of the load, at the points and of the cell means, against the Laplace-domain "
          "solution at the points' depths (`scripts/biot_laplace.py`), and the wall time of the "
          "step loop per step (lowest to highest of the three runs; the host was shared, so "
          "read the costs as ratios). 2D column of 100 x 2 cells, 2 x 2 points per cell and "
          "phase; `uniform` scatters the 800 + 800 points over the whole column (seed 1), "
          "`random` scatters 4 per cell. Each entry: sigma' points / p points / sigma' cell "
          "means / p cell means.", ""]
    for cname, col in COLUMNS.items():
        md.append(f"**{cname}** (n_f {col['porosity']}, rho_s {col['rho_s']:g}, E_c "
                  f"{col['youngs'] / 1e6:g} MPa, K_f {col['k_f'] / 1e6:g} MPa, k {col['k']:g} m/s, "
                  f"{col['drag']} drag, t = {col['t_end']:g} s)\n")
        md.append("| choice | " + " | ".join(PLACEMENTS) + " | ms / step |")
        md.append("|---|" + "---|" * (len(PLACEMENTS) + 1))
        for label in CHOICES:
            rs = [res.get(f"{cname}|{label}|{p}") for p in PLACEMENTS]
            costs = [r["ms"] for r in rs if r]
            md.append(f"| {label} | " + " | ".join(quad(r) for r in rs) + " | "
                      + (f"{min(costs):.2f}-{max(costs):.2f}" if costs else "") + " |")
        md.append("")
    return "\n".join(md)


def diag_table(res):
    md = ["Measured by `scripts/pareto_columns.py --diagnose` (as the tables of "
          "doc/performance.md, \"Saturated columns of other physics\"). W4 with `uniform` "
          "points, ten seeds (the fluid points take seed + 1): sigma' points / p points / "
          "sigma' cell means / p cell means behind the front, in units of the load; under "
          "each seed the Gauss-point reconstructions of linear + one Gauss point that found "
          "no point (the log's `MLS solves ... empty`, summed over the steps).", ""]
    md.append("| choice | " + " | ".join(f"seed {s}" for s in SEEDS) + " |")
    md.append("|---|" + "---|" * len(SEEDS))
    for label in SCAN:
        md.append(f"| {label} | " + " | ".join(quad(res.get(f"seeds|{label}|uniform, seed {s}"))
                                               for s in SEEDS) + " |")
    lg = [res.get(f"seeds|linear + one Gauss point|uniform, seed {s}") for s in SEEDS]
    md.append("| empty reconstructions | " + " | ".join(str(r["empty_solves"]) if r else "-" for r in lg)
              + " |")
    cols = [place_label(p, s) for p, s in VARIANT_PLACEMENTS]
    md += ["", "Variants on W4, and the other columns, on the same points: sigma' points / p "
           "points, and in brackets the empty reconstructions.", ""]
    md.append("| variant | " + " | ".join(cols) + " | ms / step |")
    md.append("|---|" + "---|" * (len(cols) + 1))
    for label in VARIANTS:
        rs = [res.get(f"variants|{label}|{c}") for c in cols]
        costs = [r["ms"] for r in rs if r]
        md.append(f"| {label} | " + " | ".join(
            f"{quad(r, ('sig_points', 'p_points'))} ({r['empty_solves']})" if r else "failed" for r in rs)
            + " | " + (f"{min(costs):.2f}-{max(costs):.2f}" if costs else "") + " |")
    return "\n".join(md)


def write_between(path, name, text):
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    doc = open(path).read()
    if begin not in doc or end not in doc:
        print(f"pareto_columns: no markers {name} in {path}; not written", file=sys.stderr)
        return
    doc = doc[:doc.index(begin) + len(begin)] + "\n" + text + "\n" + doc[doc.index(end):]
    open(path, "w").write(doc)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "pareto_columns"))
    ap.add_argument("--diagnose", action="store_true", help="the W4 variants instead of the matrix")
    ap.add_argument("--skip-runs", action="store_true", help="use the outputs already in --out")
    ap.add_argument("--missing", action="store_true", help="run only the cases without an output")
    ap.add_argument("--only", default="", help="run only the cases whose tag matches this regex")
    ap.add_argument("--no-doc", action="store_true")
    a = ap.parse_args()
    outdir = os.path.abspath(a.out)
    os.makedirs(outdir, exist_ok=True)
    res = {}
    for table, row, column, tag, col, make in cases(a.diagnose):
        if a.only and not re.search(a.only, tag):
            continue
        r = measure(outdir, tag, col) if a.skip_runs or a.missing else None
        if not a.skip_runs and r is None:
            rc = run(a.build, make(outdir))
            r = measure(outdir, tag, col)
            print(f"pareto_columns: {tag} rc {rc} "
                  + (" ".join(f"{k} {v:.4g}" for k, v in r.items()) if r else "failed"),
                  file=sys.stderr, flush=True)
        res[f"{table}|{row}|{column}"] = r
    with open(os.path.join(outdir, "diagnose.json" if a.diagnose else "columns.json"), "w") as f:
        json.dump(res, f, indent=1)
    text = diag_table(res) if a.diagnose else tables(res)
    print(text)
    if not a.no_doc:
        if a.diagnose:
            write_between(VERIF, "columns_diag", text)
        else:
            write_between(PERF, "columns", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
