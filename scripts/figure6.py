#!/usr/bin/env python3
"""Figure 6 analogue: the 1D shock in a saturated column (W1) for several ways of
reconstructing the fields that enter the force integrals.

Runs W1 (inputs/w1.nml, or the column inputs/w1_2d.nml or w1_3d.nml with --dims 2 or 3)
with the release build for each variant of VARIANTS:
  * Standard MPM: linear grid functions, point quadrature;
  * MLS at Gauss points: cubic grid functions, 3 Gauss points per cell and axis, the
    effective stress and the pore pressure reconstructed there with a constant basis and
    the linear, quadratic or cubic B-spline weight (natural support) or Wendland C2
    (radius 2 cells).
All variants run with the same Courant number (CFL below), hence the same time step.

From each run it reads the last frame (solid x, stress[:, 0] = sigma'_xx, volume; fluid
x, pore_pressure, volume) and /verification (the attributes final_<measure> of the
two-phase measures, src/verify/dpmpm_two_phase_verify.f90, and the reference profiles
profile_z, profile_p, profile_sigma_eff), then
  * draws one panel per variant with sigma', p and the total stress sigma' - p as means
    over the grid cells along x (point volumes as weights; in 2D and 3D over the whole
    slab of cells at one x) against the reference, into doc/figures/figure6.png
    (figure6_2d.png, figure6_3d.png for --dims 2, 3);
  * writes the table of error_sigma_eff, error_pore_pressure, overshoot_sigma_eff,
    total_stress_behind_front and the cost per step between <!-- fig6:begin --> and
    <!-- fig6:end --> (fig6_2d, fig6_3d for --dims 2, 3) in doc/verification.md, adding the section
    "Figure 6: 1D shock in a saturated column" with its markers if they are missing.

Usage: scripts/figure6.py [--dims 1|2|3] [--build build/release] [--out out/figure6]
       [--ranks 1] [--jobs 2] [--skip-runs]
"""
import argparse
import json
import os
import re
import subprocess
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402

CFL = 0.3

# Variant label -> &shape settings (namelist text).
MLS = "kernel = 'cubic', quadrature = 'gauss', gauss_points = 3, field_basis = 'constant', "
VARIANTS = {
    "Standard MPM": "kernel = 'linear', quadrature = 'points'",
    "MLS linear": MLS + "field_kernel = 'linear', field_radius = 0.0",
    "MLS quadratic": MLS + "field_kernel = 'quadratic', field_radius = 0.0",
    "MLS cubic": MLS + "field_kernel = 'cubic', field_radius = 0.0",
    "MLS Wendland C2": MLS + "field_kernel = 'wendland_c2', field_radius = 2.0",
}
MEASURES = ["error_sigma_eff", "error_pore_pressure", "overshoot_sigma_eff",
            "total_stress_behind_front"]

SECTION = """## Figure 6: 1D shock in a saturated column

W1 of doc/theory.md, section 9.1 (`inputs/w1.nml`): a step total stress of q = 1 Pa on
the drained top of a 10 m saturated column, 100 cells, 200 solid and 200 fluid
points scattered uniformly over the column, compared at 0.05 s with the
column reference (`src/verify/dpmpm_biot_column.f90`). The measures are those of
`src/verify/dpmpm_two_phase_verify.f90`: error_sigma_eff and
error_pore_pressure are volume-weighted RMS errors over the points divided by
q; overshoot_sigma_eff is the largest |sigma' - sigma'_ref| in Pa over the
solid points more than 3 cells behind the fast front, and the next column the
same without the 3 cells below the loaded top; total_stress_behind_front
is the mean over the grid cells behind the front of (cell mean sigma' - cell
mean p), which should be -q = -1 Pa. Regenerate with `scripts/figure6.py`
(`--dims 2` and `--dims 3` for the columns `inputs/w1_2d.nml` and `w1_3d.nml`).
"""


def slug(label):
    return re.sub(r"[^a-z0-9]+", "_", label.lower()).strip("_")


def scene_file(dims):
    return os.path.join(ROOT, "inputs", "w1.nml" if dims == 1 else f"w1_{dims}d.nml")


def tag_of(label, dims):
    return f"fig6_{dims}d_{slug(label)}"


def make_scene(dims, label, outdir, shape=None, tag=None):
    """One variant as a dpmpm.Scene: W1 with its &shape (VARIANTS[label] unless given), the
    common CFL, own name (tag_of unless given) and dir; returns (tag, scene)."""
    s = dpmpm.Scene.read(scene_file(dims))
    tag = tag or tag_of(label, dims)
    s.set(run={"name": tag, "cfl": CFL}, output={"dir": outdir})
    s.replace("shape", shape or VARIANTS[label])
    return tag, s


def first(value):
    """The first element of a namelist value (a scalar in 1D scenes, a list otherwise)."""
    return value[0] if isinstance(value, list) else value


def load(outdir, tag):
    with dpmpm.open_run(os.path.join(outdir, tag + ".h5")) as run:
        last = run.frames[-1]
        solid, fluid = last["solid"], last["fluid"]
        d = {
            "time": last.time,
            "step": last.step,
            "xs": solid["x"][:, 0], "sig": solid["stress"][:, 0], "vs": solid["volume"],
            "xf": fluid["x"][:, 0], "p": fluid["pore_pressure"], "vf": fluid["volume"],
        }
        ver, a = run.verification, run.verification_attrs
        for name in MEASURES:
            d[name] = a.get("final_" + name, np.nan)
        for name in ("z", "p", "sigma_eff"):
            d["ref_" + name] = ver["profile_" + name]
        if "wall_time_step_loop" in a and "steps" in a:
            d["cost"] = a["wall_time_step_loop"] / a["steps"]
        else:
            wall = run.diagnostics["wall_time"]
            d["cost"] = float(wall[-1]) / max(d["step"], 1) if wall.size else np.nan
        grid = run.grid
        region = run.scene.find("region", phase="saturated")[0]
    d["x_top"] = float(first(region["lo"]))
    d["edges"] = grid.origin[0] + np.linspace(0.0, grid.length[0], int(grid.ncells[0]) + 1)
    d["interior"] = interior_error(d)
    return d


def interior_error(d):
    """Largest |sigma' - sigma'_ref| [Pa] over the solid points between 3 cells below
    the loaded top and 3 cells behind the front (where the reference sigma' falls to
    half its largest magnitude): the overshoot without the loaded face."""
    h = d["edges"][1] - d["edges"][0]
    z = d["xs"] - d["x_top"]
    ref = np.interp(z, d["ref_z"], d["ref_sigma_eff"])
    big = np.abs(d["ref_sigma_eff"]) >= 0.5 * np.abs(d["ref_sigma_eff"]).max()
    front = d["ref_z"][big].max()
    sel = (z >= 3 * h) & (z <= front - 3 * h)
    return float(np.abs(d["sig"][sel] - ref[sel]).max()) if sel.any() else np.nan


def cell_means(x, value, vol, edges):
    """Volume-weighted mean of value over the points in each cell [edges[i], edges[i+1])."""
    idx = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, len(edges) - 2)
    w = np.bincount(idx, weights=vol, minlength=len(edges) - 1)
    s = np.bincount(idx, weights=vol * value, minlength=len(edges) - 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(w > 0, s / w, np.nan)


def figure(res, path, dims):
    labels = list(VARIANTS)
    fig, axes = plt.subplots(len(labels), 1, figsize=(9, 2.6 * len(labels)), sharex=True)
    for ax, label in zip(np.atleast_1d(axes), labels):
        d = res[label]
        edges = d["edges"] - d["x_top"]
        centres = 0.5 * (edges[:-1] + edges[1:])
        sig = cell_means(d["xs"] - d["x_top"], d["sig"], d["vs"], edges)
        p = cell_means(d["xf"] - d["x_top"], d["p"], d["vf"], edges)
        z = d["ref_z"]
        ax.plot(z, d["ref_sigma_eff"], "C0-", lw=1, label="sigma' reference")
        ax.plot(z, d["ref_p"], "C1-", lw=1, label="p reference")
        ax.plot(z, d["ref_sigma_eff"] - d["ref_p"], "k-", lw=1, label="sigma' - p reference")
        ax.plot(centres, sig, "C0.", ms=4, label="sigma' (cell mean)")
        ax.plot(centres, p, "C1.", ms=4, label="p (cell mean)")
        ax.plot(centres, sig - p, "k.", ms=4, label="sigma' - p (cell mean)")
        ax.set_ylabel("Pa")
        ax.set_title(f"{label}: error sigma' {d['error_sigma_eff']:.3g} q, "
                     f"p {d['error_pore_pressure']:.3g} q", fontsize=9)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("depth below the loaded top z [m]")
    handles, names = axes[0].get_legend_handles_labels()
    fig.legend(handles, names, fontsize=8, ncol=3, loc="upper center", bbox_to_anchor=(0.5, 0.985))
    fig.suptitle(f"W1, {dims}D, t = {res[labels[0]]['time']:.3g} s", fontsize=10, y=0.998)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    fig.savefig(path, dpi=110)


def table(res, dims, figname):
    base = res["Standard MPM"]["cost"]
    lines = [f"\n{dims}D column, t = {res['Standard MPM']['time']:.3g} s, Courant number "
             f"{CFL} for every variant (release build).\n",
             "| variant | error_sigma_eff | error_pore_pressure | overshoot_sigma_eff [Pa] | "
             "same, 3 cells below the top [Pa] | total_stress_behind_front [Pa] | "
             "s per step (relative) |",
             "|---|---|---|---|---|---|---|"]
    for label in VARIANTS:
        d = res[label]
        lines.append(f"| {label} | {d['error_sigma_eff']:.3e} | {d['error_pore_pressure']:.3e} | "
                     f"{d['overshoot_sigma_eff']:.3e} | {d['interior']:.3e} | "
                     f"{d['total_stress_behind_front']:.4f} | "
                     f"{d['cost']:.2e} ({d['cost'] / base:.1f}) |")
    lines.append(f"\n![Figure 6, {dims}D](figures/{figname})\n")
    return "\n".join(lines)


def replace_section(doc, name, body, heading):
    text = open(doc).read()
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    block = f"{begin}\n{body}{end}"
    if begin in text:
        text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda m: block, text,
                      flags=re.S)
    else:
        text = text.rstrip("\n") + "\n\n" + heading + "\n" + block + "\n"
    with open(doc, "w") as f:
        f.write(text)


def ensure_build(build):
    exe = os.path.join(build, "dpmpm")
    if not os.path.exists(exe):
        preset = os.path.basename(os.path.normpath(build))
        subprocess.run(["cmake", "--preset", preset], cwd=ROOT, check=True)
        subprocess.run(["cmake", "--build", "--preset", preset, "-j", str(os.cpu_count() or 2)],
                       cwd=ROOT, check=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dims", type=int, choices=(1, 2, 3), default=1)
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "figure6"))
    ap.add_argument("--ranks", type=int, default=1, help="MPI ranks per run")
    ap.add_argument("--jobs", type=int, default=2, help="runs at the same time")
    ap.add_argument("--skip-runs", action="store_true", help="reuse the outputs in --out")
    args = ap.parse_args()
    outdir = os.path.abspath(args.out)
    os.makedirs(outdir, exist_ok=True)

    if not args.skip_runs:
        ensure_build(args.build)
        scenes = [make_scene(args.dims, label, outdir)[1] for label in VARIANTS]
        results = dpmpm.study(scenes, ranks=args.ranks, jobs=args.jobs, progress=False,
                              errors="raise", binary=os.path.join(args.build, "dpmpm"))
        for label, r in zip(VARIANTS, results):
            with open(os.path.join(outdir, r.name + ".json"), "w") as f:
                json.dump({"wall_seconds": r.wall, "ranks": args.ranks}, f)
            print("done", label, flush=True)

    res = {label: load(outdir, tag_of(label, args.dims)) for label in VARIANTS}
    figname = "figure6.png" if args.dims == 1 else f"figure6_{args.dims}d.png"
    os.makedirs(os.path.join(ROOT, "doc", "figures"), exist_ok=True)
    figure(res, os.path.join(ROOT, "doc", "figures", figname), args.dims)
    body = table(res, args.dims, figname)
    heading = SECTION if args.dims == 1 else \
        f"### The same column in {args.dims}D (`inputs/w1_{args.dims}d.nml`)\n"
    replace_section(os.path.join(ROOT, "doc", "verification.md"),
                    "fig6" if args.dims == 1 else f"fig6_{args.dims}d", body, heading)
    print(body)


if __name__ == "__main__":
    sys.exit(main())
