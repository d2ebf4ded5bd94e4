#!/usr/bin/env python3
"""Two dpmpm builds run the same scenes; their outputs are compared by point id.

Usage: scripts/equivalence.py --before BIN --after BIN [--scenes NAME ...]
                              [--ranks 1 2] [--rtol 0] [--workdir DIR] [--markdown FILE]

Every scene of inputs/ (and the variants below: other shape choices the input accepts)
runs with both binaries on each rank count of --ranks, cut to a short end time with
four frames, its &benchmark group kept. The outputs are then compared:

- frames: the same frames, steps and times; in each frame the same point sets with the
  same ids; every dataset matched by id;
- diagnostics: every column but the wall clock;
- verification: every dataset and every attribute but the wall-clock ones.

A scene is *identical* when every value agrees bit for bit; otherwise the largest
difference relative to the largest magnitude of its dataset is shown. The exit status
is 0 when every scene agrees within --rtol (0 by default: bit-identical), 1 otherwise.
This is the check for a change that must not alter results (a refactoring): run the
build before the change against the build after it.
"""
import argparse
import os
import sys
import tempfile

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402
from dpmpm import namelist  # noqa: E402
from dpmpm.compare import compare_runs  # noqa: E402
from dpmpm.run import open_run  # noqa: E402

#: Scene -> end time of the comparison (short enough for a debug build: a few seconds).
SCENES = {
    "axial_bar": 0.1,
    "c1_a2": 0.05,
    "cam_clay_undrained_2d": 0.2,
    "c1_3d": 0.02,
    "c1_mu_i_a2": 0.05,
    "consolidation_2d": 0.1,
    "dam_break_dry_bed_2d": 0.05,
    "dam_seepage_2d": 0.1,
    "default": 0.1,
    "dry_block_2d": 0.05,
    "footing_dry_2d": 0.05,
    "footing_prandtl_2d": 0.2,
    "footing_prandtl_saturated_2d": 0.01,
    "footing_saturated_2d": 0.01,
    "footing_consolidation_2d": 0.05,
    "incline_slide_2d": 0.1,
    "loaded_block_2d": 0.05,
    "mms": 0.02,
    "seepage_layers_1d": 0.4,
    "site_response_1d": 0.2,
    "slope_equilibrium_2d": 0.05,
    "slope_saturated_2d": 0.1,
    "slope_into_water_2d": 0.1,
    "strip_pulse_2d": 0.05,
    "submerged_layer_2d": 0.05,
    "t1": 0.2,
    "tutorial_column": 0.1,
    "w1": 0.05,
    "w1_2d": 0.01,
    "w1_3d": 0.002,
    "w2": 0.08,
    "w3": 0.004,
}

#: Variants: scene name -> (base scene, extra variables). The other shape choices and
#: schemes the inputs accept, so that every path of the step is covered.
VARIANTS = {
    "default_linear": ("default", {"shape.kernel": "'linear'"}),
    "default_paper_mls": ("default", {"shape.kernel": "'cubic'", "shape.velocity_kernel": "'cubic'",
                                      "shape.velocity_basis": "'linear'",
                                      "shape.quadrature": "'gauss'",
                                      "shape.field_kernel": "'cubic'",
                                      "shape.field_radius": "0.0"}),
    "mms_velocity_mls": ("mms", {"shape.kernel": "'quadratic'",
                                 "shape.velocity_kernel": "'wendland_c2'",
                                 "shape.velocity_radius": "2.0"}),
    "w1_explicit_drag": ("w1", {"run.drag": "'explicit'", "run.t_end": "0.002"}),
    "w1_2d_pair": ("w1_2d", {"shape.kernel": "'cubic'", "shape.quadrature": "'gauss'",
                             "shape.field_kernel": "'wendland_c2'",
                             "shape.field_radius": "2.0"}),
    "w1_quadratic_usl": ("w1", {"shape.kernel": "'quadratic'", "run.scheme": "'usl'"}),
    "w1_pair": ("w1", {"shape.kernel": "'cubic'", "shape.quadrature": "'gauss'",
                       "shape.field_kernel": "'wendland_c2'", "shape.field_radius": "2.0"}),
    "w1_2d_linear_gauss": ("w1_2d", {"shape.quadrature": "'gauss'", "shape.gauss_points": "1",
                                     "shape.field_kernel": "'linear'", "shape.field_radius": "0.75"}),
    "w1_3d_pair": ("w1_3d", {"shape.kernel": "'cubic'", "shape.quadrature": "'gauss'",
                             "shape.field_kernel": "'wendland_c2'", "shape.field_radius": "2.0",
                             "run.t_end": "0.0005"}),
    "w1_3d_linear_gauss_box": ("w1_3d", {"shape.quadrature": "'gauss'", "shape.gauss_points": "1",
                                         "shape.field_kernel": "'linear'",
                                         "shape.field_radius": "0.65",
                                         "shape.field_support": "'box'"}),
}


def scene_of(scene, outdir, name, extra):
    """The scene cut for the comparison, as a dpmpm.Scene: short end time, four frames,
    output in outdir. The variants' and --set's values are namelist text."""
    base, sets = (VARIANTS[scene][0], dict(VARIANTS[scene][1])) if scene in VARIANTS \
        else (scene, {})
    s = dpmpm.Scene.read(os.path.join(ROOT, "inputs", base + ".nml"))
    t_end = float(namelist.value(sets.pop("run.t_end", repr(SCENES[base]))))
    s.set(run={"name": name, "t_end": t_end}, output={"dir": outdir, "frame_interval": t_end / 4})
    # an equilibrium phase longer than the cut run is refused by the input: cut it with the run
    if float(s["run"].get("equilibrium_time", 0.0)) > t_end:
        s["run"]["equilibrium_time"] = t_end
    # a motion file named relative to the scene stays found from the copy in outdir
    if "motion" in s:
        for axis in "xyz":
            path = str(s["motion"].get(f"file_{axis}", "") or "").strip()
            if path and not os.path.isabs(path):
                s["motion"][f"file_{axis}"] = os.path.join(ROOT, "inputs", path)
    s.set({key: namelist.value(val) for key, val in dict(sets, **extra).items()})
    return s


def run(binary, scene, ranks, workdir, tag, extra):
    """Run one scene; the output path and the wall time (s)."""
    r = dpmpm.simulate(scene_of(scene, os.path.join(workdir, tag), f"{scene}_np{ranks}", extra),
                       ranks=ranks, binary=binary, progress=False)
    return r.output, r.wall


def _rel(a, b):
    """Largest |a - b| relative to the largest |a| (0 when equal bit for bit)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape:
        return np.inf
    if np.array_equal(a, b, equal_nan=True):
        return 0.0
    scale = float(np.nanmax(np.abs(a))) if a.size else 0.0
    dev = float(np.nanmax(np.abs(a - b)))
    return dev / scale if scale > 0 else np.inf


def compare(path_a, path_b):
    """(problems, largest relative difference, whether bit-identical, what differed most)."""
    with open_run(path_a) as a, open_run(path_b) as b:
        c = compare_runs(a, b)
        problems = list(c.problems)
        worst, where = c.max_rel, ""
        if c.datasets:
            (s, d), r = max(c.datasets.items(), key=lambda kv: kv[1]["max_rel"])
            where = f"{s}/{d}"
        identical = not problems and all(r["max_abs"] == 0 for r in c.datasets.values())
        identical = identical and c.max_time_diff == 0
        if identical:
            where = ""
        pairs = [("diagnostics", a.diagnostics, b.diagnostics, ("wall_time",)),
                 ("verification", a.verification, b.verification, ())]
        va, vb = a.verification_attrs, b.verification_attrs
        pairs.append(("verification attrs", {k: v for k, v in va.items() if "wall" not in k},
                      {k: v for k, v in vb.items() if "wall" not in k}, ()))
        for group, da, db, skip in pairs:
            if sorted(da) != sorted(db):
                problems.append(f"{group}: {sorted(da)} against {sorted(db)}")
                continue
            for k in da:
                if k in skip or isinstance(da[k], str):
                    continue
                r = _rel(da[k], db[k])
                if r > 0:
                    identical = False
                    where = where or f"{group}/{k}"
                if r > worst:
                    worst, where = r, f"{group}/{k}"
    return problems, worst, identical, where


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", required=True, help="dpmpm binary before the change")
    ap.add_argument("--after", required=True, help="dpmpm binary after the change")
    ap.add_argument("--scenes", nargs="+", default=list(SCENES) + list(VARIANTS))
    ap.add_argument("--ranks", nargs="+", type=int, default=[1, 2])
    ap.add_argument("--rtol", type=float, default=0.0)
    ap.add_argument("--set", action="append", default=[], type=lambda s: s.split("=", 1),
                    help="GROUP.VARIABLE=VALUE added to every scene (namelist syntax)")
    ap.add_argument("--workdir", help="keep the runs here (default: a temporary directory)")
    ap.add_argument("--markdown", help="also write the table as Markdown to this file")
    args = ap.parse_args()
    for s in args.scenes:
        if s not in SCENES and s not in VARIANTS:
            ap.error(f"unknown scene {s!r}; known: {', '.join(list(SCENES) + list(VARIANTS))}")
    workdir = args.workdir or tempfile.mkdtemp(prefix="dpmpm_equivalence_")
    extra = dict(args.set)
    rows, failed = [], 0
    head = f"{'scene':22s} {'ranks':>5s} {'result':>14s} {'largest rel. diff':>18s}  " \
           f"{'where':28s} {'before s':>8s} {'after s':>8s}"
    print(head, flush=True)
    for scene in args.scenes:
        for n in args.ranks:
            try:
                pa, ta = run(args.before, scene, n, workdir, "before", extra)
                pb, tb = run(args.after, scene, n, workdir, "after", extra)
                problems, worst, identical, where = compare(pa, pb)
            except (dpmpm.RunError, OSError, KeyError) as e:
                problems, worst, identical, where, ta, tb = [str(e)], np.inf, False, "", 0, 0
            ok = not problems and worst <= args.rtol
            failed += not ok
            result = "identical" if identical else ("within rtol" if ok else "DIFFERENT")
            rows.append((scene, n, result, worst, where, ta, tb))
            print(f"{scene:22s} {n:5d} {result:>14s} {worst:18.3e}  {where:28s} "
                  f"{ta:8.1f} {tb:8.1f}", flush=True)
            for p in problems[:5]:
                print("    " + p)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write("| scene | ranks | result | largest relative difference | where |\n")
            f.write("|---|---|---|---|---|\n")
            for scene, n, result, worst, where, _, _ in rows:
                f.write(f"| {scene} | {n} | {result} | {worst:.3e} | {where} |\n")
    print(f"{len(rows) - failed} of {len(rows)} agree (rtol {args.rtol:g}); runs in {workdir}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
