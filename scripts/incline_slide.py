#!/usr/bin/env python3
"""A block on a rough incline (inputs/incline_slide_2d.nml, doc/theory.md 6.7).

With output files: reads each, takes the mean displacement along x of the solid points
at every frame and compares it with the Coulomb motion x = a t^2/2,
a = max(0, g_t - mu g_n), from the file's own gravity (g_t along x, g_n = -g_y) and the
friction of face y-; prints a table per file and, with --plot, draws x(t) of all of them
beside the closed form.

    python3 scripts/incline_slide.py out/incline_slide_2d.h5 [more.h5 ...] [--plot p.png]

With --study BIN: runs the scene with the variants of doc/verification.md ("Rough
walls": flip, friction, grid functions) with the binary BIN in --workdir, then reports
them as above, with one line per run at t_end.
"""
import argparse
import os
import re
import subprocess
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
from dpmpm.run import open_run  # noqa: E402

SCENE = os.path.join(ROOT, "inputs", "incline_slide_2d.nml")
#: (tag, flip, friction, kernel) of --study
VARIANTS = [("flip0", 0.0, 0.3, "linear"), ("flip05", 0.5, 0.3, "linear"),
            ("flip09", 0.9, 0.3, "linear"), ("flip1", 1.0, 0.3, "linear"),
            ("hold05", 0.5, 0.7, "linear"), ("hold1", 1.0, 0.7, "linear"),
            ("smooth", 0.5, 0.0, "linear")]


def boundary_friction(run):
    """The friction of face y- from the echoed input (0 when none)."""
    for grp in run.input_groups("boundary"):
        if str(grp.get("face", [""])[0]).strip() == "y-":
            return float(grp.get("friction", [0.0])[0])
    return 0.0


def motion(path):
    """Times, mean x displacement of the solid points, and the closed form, of one file."""
    with open_run(path) as run:
        g = np.zeros(3)
        gv = run.input_groups("run")[0].get("gravity", [0.0])
        g[:len(gv)] = gv
        mu = boundary_friction(run)
        gt, gn = g[0], -g[1]
        a = max(0.0, gt - mu * gn)
        t, ux = [], []
        for fr in run.frames:
            s = fr["solid"]
            m = s["mass"]
            t.append(fr.time)
            ux.append(float(np.sum(m * s["displacement"][:, 0]) / np.sum(m)))
    t = np.array(t)
    return t, np.array(ux), 0.5 * a * t ** 2, mu, a


def report(path):
    t, ux, ex, mu, a = motion(path)
    print(f"{path}: friction {mu}, Coulomb a = {a:.4f} m/s^2")
    print("   t (s)     x (m)  closed form    rel. error")
    for ti, u, e in zip(t, ux, ex):
        rel = (u - e) / e if e > 0 else float("nan")
        print(f"  {ti:6.3f}  {u:9.5f}  {e:11.5f}  {rel:+12.4f}")
    return t, ux, ex, mu


def study(binary, workdir):
    os.makedirs(workdir, exist_ok=True)
    text = open(SCENE).read()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    files = []
    for tag, flip, mu, kernel in VARIANTS:
        s = re.sub(r"name = '[^']*'", f"name = 'slide_{tag}'", text)
        s = re.sub(r"flip = [0-9.]+", f"flip = {flip}", s)
        s = re.sub(r"friction = [0-9.]+", f"friction = {mu}", s)
        s = re.sub(r"kernel = '[^']*'", f"kernel = '{kernel}'", s)
        s = s.replace("dir = 'out'", f"dir = '{workdir}'")
        nml = os.path.join(workdir, f"slide_{tag}.nml")
        open(nml, "w").write(s)
        subprocess.run(["mpirun", "--oversubscribe", "-n", "1", binary, nml], env=env,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        files.append((tag, flip, mu, kernel, os.path.join(workdir, f"slide_{tag}.h5")))
    print("| run | flip | μ | x at t_end (m) | Coulomb x (m) | rel. error |")
    print("|---|---|---|---|---|---|")
    for tag, flip, mu, kernel, h5 in files:
        t, ux, ex, _, _ = motion(h5)
        rel = f"{(ux[-1] - ex[-1]) / ex[-1]:+.4f}" if ex[-1] > 0 else "(stays)"
        print(f"| {tag} | {flip} | {mu} | {ux[-1]:.5f} | {ex[-1]:.5f} | {rel} |")
    return [f[-1] for f in files]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="*")
    ap.add_argument("--study", metavar="BIN", help="run the variants with this dpmpm binary")
    ap.add_argument("--workdir", default="out/incline_study")
    ap.add_argument("--plot", help="figure of x(t) against the closed form")
    args = ap.parse_args()
    files = list(args.files)
    if args.study:
        files += study(args.study, args.workdir)
    curves = [(f, *report(f)) for f in files]
    if args.plot and curves:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        for f, t, ux, ex, mu in curves:
            line, = ax.plot(t, ux, "o-", ms=3, label=f"{os.path.basename(f)} (μ = {mu})")
            tt = np.linspace(0.0, t[-1], 100)
            a = 2.0 * ex[-1] / t[-1] ** 2 if t[-1] > 0 else 0.0
            ax.plot(tt, 0.5 * a * tt ** 2, "--", color=line.get_color(), lw=0.8)
        ax.set_xlabel("t (s)")
        ax.set_ylabel("mean displacement along the incline (m)")
        ax.set_title("Block on a rough incline: points, and Coulomb's a t²/2 (dashed)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"figure: {args.plot}")


if __name__ == "__main__":
    main()
