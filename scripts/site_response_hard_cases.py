#!/usr/bin/env python3
"""Hard cases of the site-response scenes (doc/verification.md, "Site response: 20 s of
shaking and after"): each scene shaken by a long broadband motion (scripts/long_motion.py:
15 s of shaking, then 5 s at rest) in place of its record, to t = 20 s at its own time step,
with each shape choice of the list (a choice that the input refuses is listed with the
reason) on each rank count. Reports how each run ended, the monitor's warnings, its largest
(kinetic + stored) / (work + initial) and balance error, and from /diagnostics the largest
speed during the shaking and over the last second, the kinetic + stored energy at the end of
the shaking and at 20 s, and the smallest and largest time step (the last, shortened step
left out); with --series also the largest speed in each 2.5 s and the energy at its end.

usage: scripts/site_response_hard_cases.py [--bin build/release/dpmpm] [--out DIR]
       [--scenes a,b] [--shapes standard,linear_gauss,...] [--np 1,2] [--t-end 20]
       [--flip F] [--series] [--reuse]
"""
import argparse
import os
import re
import subprocess
import sys
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
from dpmpm.scene import Scene  # noqa: E402

SCENES = ("site_response_1d", "site_response_1d_damped", "site_response_1d_compliant",
          "site_response_2d_compliant", "site_response_layered_1d_rigid",
          "site_response_layered_1d_compliant", "site_response_layered_2d_compliant",
          "site_response_layered_3d_rigid")

# The shape choices: the base motion and the tied sides take linear grid functions and a
# velocity projection or a linear MLS velocity; the forces from the points or from Gauss
# points. The wider grid functions are listed to show that the input refuses them.
SHAPES = {
    "standard": "kernel = 'linear'",
    "linear_gauss": "kernel = 'linear', quadrature = 'gauss', gauss_points = 1, "
                    "field_kernel = 'linear', field_radius = 0.75",
    "linear_gauss_box": "kernel = 'linear', quadrature = 'gauss', gauss_points = 1, "
                        "field_kernel = 'linear', field_radius = 0.65, field_support = 'box'",
    "mls_velocity": "kernel = 'linear', velocity_kernel = 'linear', velocity_basis = 'linear'",
    "linear_pair": "kernel = 'linear', quadrature = 'gauss', gauss_points = 2, "
                   "field_kernel = 'wendland_c2', field_radius = 2.0",
    "quadratic": "kernel = 'quadratic'",
    "cubic_pair": "kernel = 'cubic', quadrature = 'gauss', gauss_points = 3, "
                  "field_kernel = 'wendland_c2', field_radius = 2.0",
}


def make(path, shape, name, record, t_end, flip=None):
    s = Scene.read(path)
    m = s["motion"]
    for a in "xyz":
        if str(m.get("file_" + a, "")).strip():
            m["file_" + a] = record
    s.replace("shape", SHAPES[shape])
    s.set(run={"name": name, "t_end": t_end, "progress_seconds": 600.0},
          output={"frame_interval": t_end / 4})
    if flip is not None:
        s.set(run={"flip": flip})
    return s


def summary(rc, log, h5, t_shaking):
    m = re.search(r"largest \(kinetic \+ stored\) / \(work \+ initial\)\s+([-+\d.E]+), largest "
                  r"balance error\s+([-+\d.E]+)", log)
    out = dict(ratio=float(m.group(1)) if m else float("nan"),
               bal=float(m.group(2)) if m else float("nan"),
               warns=len(re.findall(r"monitor: warning", log)))
    if rc == 0:
        out["how"] = "completed"
    elif "monitor: the run is unstable" in log:
        out["how"] = "stopped by the monitor (growth)"
    else:
        out["how"] = "exit %d" % rc
    if os.path.exists(h5):
        with h5py.File(h5, "r") as f:
            d = f["diagnostics"]
            t, vmax, dt = d["time"][...], d["max_speed"][...], d["dt"][...]
            e = d["kinetic_energy"][...] + d["strain_energy"][...]
        shake = t <= t_shaking
        out.update(t=t[-1], vshake=vmax[shake].max(), vlate=vmax[t >= t[-1] - 1.0].max(),
                   eshake=e[shake][-1], eend=e[-1], emax=e.max(), dtmin=dt[:-1].min(),
                   dtmax=dt[:-1].max())
        # over time: the largest speed in each window of 2.5 s and the energy at its end
        edges = np.arange(2.5, t[-1] + 1e-9, 2.5)
        out["series"] = [(b, vmax[(t > b - 2.5) & (t <= b)].max(), e[min(np.searchsorted(t, b), len(t) - 1)])
                         for b in edges]
    m = re.search(r"done, (\d+) steps to t", log)
    out["steps"] = int(m.group(1)) if m else -1
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--mpiexec", default="mpiexec")
    ap.add_argument("--out", default="/tmp/dpmpm_site_response_hard")
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--shapes", default="standard,linear_gauss,mls_velocity,linear_pair,quadratic")
    ap.add_argument("--np", default="1,2")
    ap.add_argument("--t-end", type=float, default=20.0)
    ap.add_argument("--shaking", type=float, default=15.0)
    ap.add_argument("--series", action="store_true", help="print the monitor over time too")
    ap.add_argument("--reuse", action="store_true",
                    help="summarize the runs already in --out (their logs and outputs); run nothing")
    ap.add_argument("--flip", type=float, default=None, help="&run flip (default: the scene's)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    record = os.path.join(args.out, "long_motion.AT2")
    if not args.reuse:
        subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "long_motion.py"), record,
                        "--shaking", str(args.shaking), "--silence", str(args.t_end - args.shaking)],
                       check=True)
    print("| scene | shape | ranks | how it ended | steps | dt min-max [s] | monitor warnings "
          "| (KE + stored) / (work + initial) | balance error | largest speed while shaking "
          "[m/s] | over the last second | KE + stored at the end of shaking [J] | at the end "
          "| wall [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    label = f", flip {args.flip:g}" if args.flip is not None else ""
    for scene in args.scenes.split(","):
        path = os.path.join(ROOT, "inputs", scene + ".nml")
        for shape in args.shapes.split(","):
            for np_ in [int(x) for x in args.np.split(",")]:
                name = f"{scene}_{shape}_np{np_}"
                if args.flip is not None:
                    name += f"_flip{args.flip:g}"
                nml = make(path, shape, name, record, args.t_end, args.flip).write(
                    os.path.join(args.out, name + ".nml"))
                logfile = os.path.join(args.out, name + ".log")
                if args.reuse and not os.path.exists(logfile):
                    print(f"| {scene} | {shape}{label} | {np_} | not run | | | | | | | | | | |")
                    continue
                if args.reuse:
                    # the run made before: its log and output summarized again
                    log = open(logfile).read()
                    rc = 2 if "input error" in log else 4 if "the run is unstable" in log else \
                        0 if "dpmpm: done," in log else 1
                    wall = float("nan")
                else:
                    t0 = time.time()
                    # ranks that wait yield the core (more ranks than cores on small machines)
                    env = dict(os.environ, OMPI_MCA_mpi_yield_when_idle="1")
                    p = subprocess.run([args.mpiexec, "--oversubscribe", "-n", str(np_), args.bin, nml],
                                       cwd=args.out, capture_output=True, text=True, env=env)
                    wall = time.time() - t0
                    log, rc = p.stdout + p.stderr, p.returncode
                    with open(logfile, "w") as f:
                        f.write(log)
                if rc == 2 and "input error" in log:
                    why = re.search(r"input error: (.*)", log).group(1).strip()
                    print(f"| {scene} | {shape}{label} | {np_} | refused by the input: "
                          f"{why.replace('|', '/')[:200]} | | | | | | | | | | |", flush=True)
                    continue
                s = summary(rc, log, os.path.join(args.out, name + ".h5"), args.shaking)
                if "t" in s:
                    def num(x, f):
                        return "-" if x != x or x < 0 else format(x, f)
                    print(f"| {scene} | {shape}{label} | {np_} | {s['how']} (t = {s['t']:.3g} s) | "
                          f"{num(s['steps'], 'd')} | {s['dtmin']:.3e}-{s['dtmax']:.3e} | {s['warns']} | "
                          f"{num(s['ratio'], '.3g')} | {num(s['bal'], '.3g')} | {s['vshake']:.3e} | "
                          f"{s['vlate']:.3e} | {s['eshake']:.3e} | {s['eend']:.3e} | {num(wall, '.0f')} |",
                          flush=True)
                    if args.series:
                        print("    over time (t, largest speed over the 2.5 s before, kinetic + stored): "
                              + "; ".join(f"{b:g} s {v:.2e} m/s {e:.2e} J" for b, v, e in s["series"]))
                else:
                    print(f"| {scene} | {shape}{label} | {np_} | {s['how']}: {log[-200:]!r} | | | | | | | "
                          f"| | | {wall:.0f} |", flush=True)


if __name__ == "__main__":
    main()
