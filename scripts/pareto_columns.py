#!/usr/bin/env python3
"""Speed against error of the shape choices on saturated columns of other physics: W1, W2,
W3 (doc/theory.md 9.1: strong drag, weak drag, stiff water) and W4 (a more porous and more
permeable column with a stiffer skeleton and water than W1's: n_f 0.4, E 20 MPa, K_f 30 MPa,
k 1e-3 m/s; where linear grid functions with one Gauss point per cell lost), each in 2D (100 x 2 cells of 0.1 m, rollers on the sides, 2 x 2
points per cell and phase) with the placements regular, random (per cell), uniform (over
the whole column; seed 1, and seed 7 whose fluid points leave two cells empty) and stirred
(the regular points after shears, as after a large deformation).

Each run is one dpmpm process on one rank (an MPI singleton), one at a time (release
build). The reference is scripts/biot_laplace.py at the points' own depths (checked, per
column, against the reference profile of one run with the benchmark biot_column, which
dpmpm computes with src/verify/dpmpm_biot_column.f90). Measures, behind the front (depth
z < c_u t - 3 h, as overshoot_sigma_eff of src/verify/dpmpm_two_phase_verify.f90), in
units of the load q:
  * points: volume-weighted RMS over the solid points of sigma'_p - sigma'_ref(z_p), over the
    fluid points of p_p - p_ref(z_p);
  * cell means: in each grid column along x (the slab of cells at one x) the volume-weighted
    mean of (field - reference) over its points, RMS over the columns behind the front;
  * CPU ms per step: the CPU time of the process less that of the same scene stopped after
    SHORT_STEPS steps, over the steps between (the host is shared, so not the wall time).
With --diagnose, the variants of the linear + one Gauss point choice on W4 that look for the
cause of its loss (doc/verification.md, "Empty Gauss points of linear + one Gauss point");
with --cause, the runs that isolate it (one thing changed at a time on the user's points).

Writes the tables between <!-- columns:begin --> and <!-- columns:end --> of
doc/performance.md (--diagnose: <!-- columns_diag:begin/end --> of doc/verification.md,
--cause: <!-- columns_cause:begin/end --> there).

Usage: scripts/pareto_columns.py [--diagnose | --cause] [--skip-runs | --missing] [--only REGEX]
       [--no-doc] [--out out/pareto_columns] [--build build/release]
"""
import argparse
import hashlib
import json
import os
import re
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import biot_laplace  # noqa: E402
import dpmpm  # noqa: E402
from pareto import LINEAR_GAUSS  # noqa: E402  (the choice of the M1/W1 study)

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
# The placements of the matrix: (placement, seed). Uniform on seed 1 (no cell without a
# point of a set behind the front) and on seed 7 (the points of the user's measurement:
# two cells without a fluid point, doc/verification.md "Empty Gauss points of linear + one
# Gauss point"); stirred as after a large deformation (doc/input.md, "Placement").
PLACEMENTS = [("regular", 1), ("random", 1), ("uniform", 1), ("uniform", 7), ("stirred", 1)]

CHOICES = {
    "Standard MPM": "kernel = 'linear'",
    "quadratic B-spline": "kernel = 'quadratic'",
    "cubic B-spline": "kernel = 'cubic'",
    "linear + one Gauss point": LINEAR_GAUSS,
    "linear + one Gauss point, field_widen": LINEAR_GAUSS + ", field_widen = .true.",
    "pair, 2 Gauss points": ("kernel = 'cubic', quadrature = 'gauss', "
                             "field_kernel = 'wendland_c2', field_radius = 2.0"),
    "cubic + linear-basis velocity": ("kernel = 'cubic', velocity_kernel = 'cubic', "
                                      "velocity_basis = 'linear', quadrature = 'gauss', "
                                      "field_kernel = 'cubic', field_radius = 0.0"),
    "Wendland velocity + quadratic": ("kernel = 'quadratic', velocity_kernel = 'wendland_c2', "
                                      "velocity_radius = 2.0, quadrature = 'gauss', "
                                      "field_kernel = 'quadratic', field_radius = 0.0"),
}
# The pair with 3 x 3 Gauss points per cell (the stability map's) gave the errors of 2 x 2
# to 0.002 q on every column and placement of the earlier tables for 1.5-1.9 times the
# cost; it is left out of the matrix.

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

# The cause (--cause): W4 on the user's points (uniform, seed 7; the fluid points on seed
# 8, a set with two cells without a point), one thing changed at a time: the time step,
# the set of points that has the holes (the fluid points of seed 7 under the solid points
# of seed 1, and the fluid points of seed 1 under those of seed 7), and the reach of the
# empty Gauss points alone (field_widen). (label, choice, seed, extra of scene()).
CAUSE = [
    ("linear + one Gauss point, as measured", "linear + one Gauss point", 7, {}),
    ("the same, Courant number 0.15", "linear + one Gauss point", 7, dict(cfl=0.15)),
    ("the same, Courant number 0.075", "linear + one Gauss point", 7, dict(cfl=0.075)),
    ("the same, solid points of seed 7, fluid points of seed 1 (set 2)", "linear + one Gauss point", 7,
     dict(fluid_seed=2)),
    ("the same, solid points of seed 1, fluid points of seed 7 (set 8)", "linear + one Gauss point", 1,
     dict(fluid_seed=8)),
    ("the same, field_widen", "linear + one Gauss point, field_widen", 7, {}),
    ("the same, field_widen, Courant number 0.15", "linear + one Gauss point, field_widen", 7,
     dict(cfl=0.15)),
    ("Standard MPM", "Standard MPM", 7, {}),
    ("Standard MPM, Courant number 0.15", "Standard MPM", 7, dict(cfl=0.15)),
    ("Standard MPM, fluid points of seed 1 (set 2)", "Standard MPM", 7, dict(fluid_seed=2)),
    ("pair, 2 Gauss points", "pair, 2 Gauss points", 7, {}),
]


def place_label(placement, seed):
    return f"uniform, seed {seed}" if placement == "uniform" else placement


def scene(tag, outdir, col, shape, placement, seed, extra=None):
    """2D column along x (as inputs/w1_2d.nml): 100 x 2 cells, rollers on y- and y+, the
    drained loaded top x-, the fixed impermeable bottom x+, a 1 Pa step load, as a
    dpmpm.Scene. extra may set cfl, flip, scheme, ppc, fluid_seed, ncells (along x) and the
    column's parameters, for runs beside the study's, and benchmark = True for the benchmark
    biot_column (its reference profile checks scripts/biot_laplace.py; the benchmark's
    reference costs seconds of CPU per run, so the timed runs go without it)."""
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
    if extra.get("benchmark", False):
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


SHORT_STEPS = 5
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}


def launch(binary, scene, outdir):
    """Run a scene as one process (an MPI singleton, no launcher), the log beside its
    output; its exit code and the CPU seconds (user + system) the process took."""
    nml = os.path.join(outdir, scene.name + ".nml")
    scene.write(nml)
    with open(os.path.join(outdir, scene.name + ".log"), "w") as log:
        p = subprocess.Popen([binary, nml], cwd=outdir, stdout=log, stderr=subprocess.STDOUT,
                             env=dict(os.environ, **MPI_ENV))
        _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    return p.returncode, usage.ru_utime + usage.ru_stime


def run_timed(binary, make, outdir, tag):
    """The run of a case and the same scene stopped after SHORT_STEPS steps: the CPU time
    of the steps is the difference of the two processes' CPU times (start-up, reading
    the input, placing the points and writing the last frame cancel), written to
    <tag>.cpu.json for measure(). The exit code of the full run."""
    rc, cpu = launch(binary, make(outdir), outdir)
    short = make(outdir)
    short.set(run={"name": tag + "_short", "max_steps": SHORT_STEPS})
    rc_short, cpu_short = launch(binary, short, outdir)
    with open(os.path.join(outdir, tag + ".cpu.json"), "w") as f:
        json.dump(dict(cpu=cpu, cpu_short=cpu_short, rc=rc, rc_short=rc_short,
                       short_steps=SHORT_STEPS), f)
    return rc


def cpu_per_step(outdir, tag, steps):
    """CPU ms per step from <tag>.cpu.json (run_timed), or nan."""
    path = os.path.join(outdir, tag + ".cpu.json")
    if not os.path.exists(path):
        return np.nan
    c = json.load(open(path))
    if c["rc"] != 0 or c["rc_short"] != 0 or steps <= c["short_steps"]:
        return np.nan
    return 1e3 * (c["cpu"] - c["cpu_short"]) / (steps - c["short_steps"])


def occupancy(frame, ncells):
    """Points of each set per cell of the nx x ny grid in a frame: the fewest, the most,
    and the cells without a point of the set (over the whole column)."""
    nx = ncells
    ny = max(2, round(WIDTH / (LENGTH / nx)))
    h = LENGTH / nx
    out = {}
    for name in ("solid", "fluid"):
        x = frame[name]["x"]
        i = np.clip((x[:, 0] / h).astype(int), 0, nx - 1)
        j = np.clip((x[:, 1] / h).astype(int), 0, ny - 1)
        n = np.bincount(i * ny + j, minlength=nx * ny)
        out[name] = (int(n.min()), int(n.max()), int(np.sum(n == 0)))
    return out


def log_step_time(outdir, tag):
    """ms per step from the log line 'time per step X ms over N steps'."""
    m = re.search(r"time per step\s+([0-9.eE+-]+) ms", open(os.path.join(outdir, tag + ".log")).read())
    return float(m.group(1)) if m else np.nan


def log_empty_solves(outdir, tag):
    """Gauss-point reconstructions that found no point in reach, summed over the run (the
    last number of the log line 'MLS solves: ... empty'); 0 without Gauss quadrature."""
    m = re.search(r"MLS solves:[^:]*empty:\s+(?:\d+\s+){4}(\d+)", open(os.path.join(outdir, tag + ".log")).read())
    return int(m.group(1)) if m else 0


def log_steps(outdir, tag):
    """Steps of the run from the log line 'dpmpm: done, N steps'."""
    m = re.search(r"done,\s+(\d+) steps", open(os.path.join(outdir, tag + ".log")).read())
    return int(m.group(1)) if m else 0


def log_widened(outdir, tag):
    """Gauss points that widened their reach over the run (field_widen), from the log."""
    m = re.search(r"widened their reach[^:]*:\s+(\d+) times", open(os.path.join(outdir, tag + ".log")).read())
    return int(m.group(1)) if m else 0


def measure(outdir, tag, col, ncells=NCELLS):
    """The measures of the module header for one finished run, or None."""
    path = os.path.join(outdir, tag + ".h5")
    if not os.path.exists(path):
        return None
    with dpmpm.open_run(path) as run:
        if not run.frames:
            return None
        has_v = "verification" in run.file
        v, va = (run.verification, run.verification_attrs) if has_v else ({}, {})
        last = run.frames[-1]
        t = last.time
        solid, fluid = last["solid"], last["fluid"]
        xs, sig, vs = solid["x"][:, 0], solid["stress"][:, 0], solid["volume"]
        xf, p, vf = fluid["x"][:, 0], fluid["pore_pressure"], fluid["volume"]
        if "wall_time_step_loop" in va:
            ms = 1e3 * va["wall_time_step_loop"] / va["steps"]
        else:
            ms = log_step_time(outdir, tag)
        steps = int(va["steps"]) if "steps" in va else log_steps(outdir, tag)
        occ = occupancy(run.frames[0], ncells)
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
    out = dict(ms=ms, cpu_ms=cpu_per_step(outdir, tag, steps), steps=steps,
               ref_check=float(check), run_error_sigma_eff=run_err, time=t,
               empty_solves=log_empty_solves(outdir, tag), widened=log_widened(outdir, tag),
               occupancy=occ)
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


# --seeds: uniform points on ten seeds on every column, for the choices that lead the
# matrix (seeds 1 and 7 are the matrix's own runs).
# Without field_widen the runs are those with it bit for bit where no Gauss point is empty,
# and its count of widened Gauss points is the count of empty ones without it.
SEED_ROWS = ["linear + one Gauss point, field_widen", "pair, 2 Gauss points"]


def seed_cases():
    """The runs of --seeds as cases(), with the tags of the matrix's runs."""
    out = []
    for label in SEED_ROWS:
        for cname, col in COLUMNS.items():
            for seed in SEEDS:
                shape = CHOICES[label]
                key = hashlib.sha1(shape.encode()).hexdigest()[:10]
                tag = f"col_{cname.lower()}_uniform_{seed}_{key}"
                out.append((cname, label, f"seed {seed}", tag, col,
                            lambda outdir, tag=tag, col=col, shape=shape, seed=seed:
                            scene(tag, outdir, col, shape, "uniform", seed)))
    return out


def seed_table(res):
    md = ["Measured by `scripts/pareto_columns.py --seeds` (as the matrix above): `uniform` points "
          f"on seeds {SEEDS[0]}-{SEEDS[-1]} (the fluid points on seed + 1), every column. Per "
          "choice the median and the largest over the seeds of sigma' points / p points behind "
          "the front (in q), and the seeds with Gauss points that found no point within their "
          "radius (widened ones, with `field_widen`, in brackets).", "",
          "| column | choice | median | largest | seeds with empty Gauss points |",
          "|---|---|---|---|---|"]
    for cname in COLUMNS:
        for label in SEED_ROWS:
            rs = [res.get(f"{cname}|{label}|seed {sd}") for sd in SEEDS]
            ok = [r for r in rs if r]
            if not ok:
                md.append(f"| {cname} | {label} | failed | | |")
                continue
            sig = np.array([r["sig_points"] for r in ok])
            p = np.array([r["p_points"] for r in ok])
            holes = [str(sd) for sd, r in zip(SEEDS, rs) if r and r["empty_solves"]]
            wide = [str(sd) for sd, r in zip(SEEDS, rs) if r and r.get("widened")]
            md.append(f"| {cname} | {label} | {np.median(sig):.3f} / {np.median(p):.3f} | "
                      f"{sig.max():.3f} / {p.max():.3f} | " + (", ".join(holes) or "none")
                      + (f" ({', '.join(wide)})" if wide else "")
                      + ("" if len(ok) == len(rs) else f"; {len(rs) - len(ok)} failed") + " |")
    return "\n".join(md)


def cause_cases():
    """The runs of CAUSE as cases()."""
    out = []
    col = COLUMNS["W4"]
    for k, (label, choice, seed, extra) in enumerate(CAUSE):
        shape = CHOICES[choice]
        key = hashlib.sha1((shape + json.dumps(extra, sort_keys=True)).encode()).hexdigest()[:10]
        tag = f"cause_w4_uniform_{seed}_{key}"
        out.append(("cause", label, "", tag, col,
                    lambda outdir, tag=tag, shape=shape, seed=seed, extra=extra:
                    scene(tag, outdir, col, shape, "uniform", seed, extra)))
    return out


def cause_table(res):
    md = ["Measured by `scripts/pareto_columns.py --cause` (release build, one rank): W4 with "
          "`uniform` points, one thing changed at a time. Errors behind the front in units of the "
          "load (sigma' points / p points / sigma' cell means / p cell means), the Gauss-point "
          "reconstructions that found no point over the run (widened ones: found points within "
          "1.0 or 1.25 cells), the cells without a point of each set at the start, and the steps.",
          "", "| run | errors | empty (widened) | empty cells solid / fluid | steps |",
          "|---|---|---|---|---|"]
    for label, *_ in CAUSE:
        r = res.get(f"cause|{label}|")
        if not r:
            md.append(f"| {label} | failed | | | |")
            continue
        o = r["occupancy"]
        md.append(f"| {label} | {quad(r)} | {r['empty_solves']} ({r['widened']}) | "
                  f"{o['solid'][2]} / {o['fluid'][2]} | {r['steps']} |")
    return "\n".join(md)


def cases(diagnose):
    """(table, row, column label, tag, column parameters, scene maker) of every run."""
    out = []

    def add(table, row, cname, shape, placement, seed):
        col = COLUMNS[cname]
        # The same column, points and shape give the same tag, so that --missing runs them once.
        key = hashlib.sha1(shape.encode()).hexdigest()[:10]
        tag = f"{'diag' if diagnose else 'col'}_{cname.lower()}_{placement}_{seed}_{key}"
        out.append((table, row, place_label(placement, seed), tag, col,
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
        for placement, seed in PLACEMENTS:
            for label, shape in CHOICES.items():
                add(cname, label, cname, shape, placement, seed)
    return out


def checks(outdir, binary, skip_runs):
    """Per column, the regular Standard MPM run with the benchmark biot_column: the largest
    difference of scripts/biot_laplace.py from the run's reference profile (in q)."""
    out = {}
    for cname, col in COLUMNS.items():
        tag = f"check_{cname.lower()}"
        r = measure(outdir, tag, col)
        if r is None and not skip_runs:
            launch(binary, scene(tag, outdir, col, CHOICES["Standard MPM"], "regular", 1,
                                 dict(benchmark=True)), outdir)
            r = measure(outdir, tag, col)
        out[cname] = r["ref_check"] if r else np.nan
    return out


def quad(r, keys=("sig_points", "p_points", "sig_cells", "p_cells")):
    return " / ".join(f"{r[k]:.3f}" for k in keys) if r else "failed"


def tables(res, check):
    labels = [place_label(p, sd) for p, sd in PLACEMENTS]
    md = ["Measured by `scripts/pareto_columns.py` (release build, one rank as an MPI singleton, "
          f"one run at a time, Courant number {CFL}): RMS errors behind the front (depth below "
          "c_u t - 3 cells) in units of the load, at the points and of the cell means, against "
          "the Laplace-domain solution at the points' depths (`scripts/biot_laplace.py`, within "
          f"{np.nanmax(list(check.values())):.1e} q of the run's own reference "
          "`src/verify/dpmpm_biot_column.f90` on every column, away from the front), and the "
          "CPU time per step: the CPU time (user + system) of the run less that of the same "
          f"run stopped after {SHORT_STEPS} steps, over the steps between (lowest to highest of "
          "the placements; the host was shared, read them as ratios). 2D column of 100 x 2 "
          "cells of 0.1 m, 2 x 2 points per cell and phase (800 + 800); `random` scatters 4 per "
          "cell, `uniform` the 800 over the whole column (the fluid points on seed + 1), "
          "`stirred` moves the regular points by 3 rounds of shears of strain 1. Each entry: "
          "sigma' points / p points / sigma' cell means / p cell means; a run that found a Gauss "
          "point without a point in reach has the count of such reconstructions after it in "
          "brackets (widened ones with w).", ""]
    std = [res.get(f"{c}|Standard MPM|{lab}") for c in COLUMNS for lab in labels]
    for cname, col in COLUMNS.items():
        md.append(f"**{cname}** (n_f {col['porosity']}, rho_s {col['rho_s']:g}, E_c "
                  f"{col['youngs'] / 1e6:g} MPa, K_f {col['k_f'] / 1e6:g} MPa, k {col['k']:g} m/s, "
                  f"{col['drag']} drag, t = {col['t_end']:g} s)\n")
        md.append("| choice | " + " | ".join(labels) + " | CPU ms / step |")
        md.append("|---|" + "---|" * (len(labels) + 1))
        for label in CHOICES:
            rs = [res.get(f"{cname}|{label}|{lab}") for lab in labels]
            costs = [r["cpu_ms"] for r in rs if r and np.isfinite(r["cpu_ms"])]

            def entry(r):
                if not r:
                    return "failed"
                note = f" ({r['empty_solves']})" if r["empty_solves"] else ""
                note += f" ({r['widened']} w)" if r.get("widened") else ""
                return quad(r) + note
            md.append(f"| {label} | " + " | ".join(entry(r) for r in rs) + " | "
                      + (f"{min(costs):.2f}-{max(costs):.2f}" if costs else "") + " |")
        md.append("")
    # The cost of each choice against Standard MPM's, over every run of the matrix.
    md.append("CPU time per step against Standard MPM's on the same column and points "
              "(median and range over the 20 runs of each choice):\n")
    md.append("| choice | median | range |")
    md.append("|---|---|---|")
    for label in CHOICES:
        ratios = []
        for c in COLUMNS:
            for lab in labels:
                r, r0 = res.get(f"{c}|{label}|{lab}"), res.get(f"{c}|Standard MPM|{lab}")
                if r and r0 and np.isfinite(r["cpu_ms"]) and np.isfinite(r0["cpu_ms"]) and r0["cpu_ms"] > 0:
                    ratios.append(r["cpu_ms"] / r0["cpu_ms"])
        if ratios:
            md.append(f"| {label} | {np.median(ratios):.1f} | {min(ratios):.1f}-{max(ratios):.1f} |")
    md.append("")
    # The placements: points of a set per cell at the start (the same on every column).
    md.append("Points of each set per cell at the start (fewest-most, and cells without one, "
              "over the 200 cells):\n")
    md.append("| placement | solid | fluid |")
    md.append("|---|---|---|")
    for lab in labels:
        r = next((x for x in std if x and x is res.get(f"W4|Standard MPM|{lab}")), None)
        if r:
            o = r["occupancy"]
            md.append(f"| {lab} | " + " | ".join(f"{o[k][0]}-{o[k][1]}, {o[k][2]} empty"
                                                 for k in ("solid", "fluid")) + " |")
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
    ap.add_argument("--seeds", action="store_true",
                    help="uniform points on ten seeds on every column, the leading choices")
    ap.add_argument("--cause", action="store_true",
                    help="the runs that isolate the loss of linear + one Gauss point on W4")
    ap.add_argument("--skip-runs", action="store_true", help="use the outputs already in --out")
    ap.add_argument("--missing", action="store_true", help="run only the cases without an output")
    ap.add_argument("--only", default="", help="run only the cases whose tag matches this regex")
    ap.add_argument("--no-doc", action="store_true")
    a = ap.parse_args()
    outdir = os.path.abspath(a.out)
    os.makedirs(outdir, exist_ok=True)
    res = {}
    todo = cause_cases() if a.cause else seed_cases() if a.seeds else cases(a.diagnose)
    for table, row, column, tag, col, make in todo:
        if a.only and not re.search(a.only, tag):
            continue
        r = measure(outdir, tag, col) if a.skip_runs or a.missing else None
        if not a.skip_runs and r is None:
            rc = run_timed(os.path.join(a.build, "dpmpm"), make, outdir, tag)
            r = measure(outdir, tag, col)
            print(f"pareto_columns: {tag} rc {rc} "
                  + (" ".join(f"{k} {v:.4g}" for k, v in r.items() if not isinstance(v, dict))
                     if r else "failed"),
                  file=sys.stderr, flush=True)
        res[f"{table}|{row}|{column}"] = r
    name = "cause" if a.cause else "seeds" if a.seeds else "diagnose" if a.diagnose else "columns"
    with open(os.path.join(outdir, name + ".json"), "w") as f:
        json.dump(res, f, indent=1)
    if a.cause:
        text = cause_table(res)
    elif a.seeds:
        text = seed_table(res)
    elif a.diagnose:
        text = diag_table(res)
    else:
        text = tables(res, checks(outdir, os.path.join(a.build, "dpmpm"), a.skip_runs))
    print(text)
    if not a.no_doc:
        if a.cause:
            write_between(VERIF, "columns_cause", text)
        elif a.seeds:
            write_between(PERF, "columns_seeds", text)
        elif a.diagnose:
            write_between(VERIF, "columns_diag", text)
        else:
            write_between(PERF, "columns", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
