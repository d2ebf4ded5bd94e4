#!/usr/bin/env python3
"""Regenerate the MLS verification report (doc/verification.md, doc/figures/).

Runs, with the release build:
  * P1: dpmpm_peaks and scripts/report_peaks.py (the peaks table);
  * M1: the manufactured solution (inputs/mms.nml) for each shape-function
    combination, h = 1/8 ... 1/64 and B = 1e-4 and 0.05, and writes the
    convergence, crack and cost tables between the m1 markers of
    doc/verification.md and the figure doc/figures/m1_convergence.png.

Usage: scripts/verify_mls.py [--build build/release] [--out out/verify_mls]
       [--max-cells 64] [--jobs 2] [--skip-runs]
"""
import argparse
import math
import os
import re
import subprocess
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402
from dpmpm.launch import MPI_ENV  # noqa: E402

# Shape-function combinations: label -> &shape settings (namelist text).
COMBOS = {
    "Standard MPM": "kernel = 'linear'",
    "quadratic B-spline": "kernel = 'quadratic'",
    "cubic B-spline": "kernel = 'cubic'",
    "cubic + linear-basis velocity": (
        "kernel = 'cubic', velocity_kernel = 'cubic', velocity_basis = 'linear', "
        "quadrature = 'gauss', field_kernel = 'cubic', field_radius = 0.0"),
    "Wendland velocity + quadratic": (
        "kernel = 'quadratic', velocity_kernel = 'wendland_c2', velocity_radius = 2.0, "
        "quadrature = 'gauss', field_kernel = 'quadratic', field_radius = 0.0"),
    "pair (theory.md 3.6)": (
        "kernel = 'cubic', quadrature = 'gauss', field_kernel = 'wendland_c2', "
        "field_radius = 2.0"),
}
AMPLITUDES = [1.0e-4, 0.05]


def tag_of(label, ncells, amp):
    slug = re.sub(r"[^a-z0-9]+", "_", label.lower()).strip("_")
    return f"m1_{slug}_{ncells}_{'small' if amp < 1e-2 else 'large'}"


def scene(label, ncells, amp, outdir, tag, shape=None):
    """inputs/mms.nml with the shape choice (COMBOS[label] unless shape is given), cells,
    amplitude, name and output folder, as a dpmpm.Scene."""
    s = dpmpm.Scene.read(os.path.join(ROOT, "inputs", "mms.nml"))
    s.set(run={"name": tag}, grid={"ncells": [ncells, ncells]}, output={"dir": outdir})
    s.replace("shape", COMBOS[label] if shape is None else shape)
    [bench] = s.find("benchmark", name="mms")
    bench["amplitude"] = amp
    return s


def load(outdir, tag):
    with h5py.File(os.path.join(outdir, tag + ".h5"), "r") as f:
        a = dict(f["verification"].attrs)
    return {
        "e_u": a["final_error_displacement"],
        "eq15": a["mean_error_velocity_mean"],
        "e_v": a["mean_error_velocity"],
        "gap": a["max_gap_ratio"],
        "empty": int(a["max_empty_cells"]),
        "step_time": a["wall_time_step_loop"] / a["steps"],
        "fallbacks": int(a.get("mls_reduced", 0) + a.get("mls_regularised", 0)
                         + a.get("mls_constant", 0) + a.get("mls_empty", 0)),
    }


def order(e, cells):
    return [math.log(e[i] / e[i + 1]) / math.log(cells[i + 1] / cells[i])
            for i in range(len(e) - 1)]


def fmt_orders(o):
    return ", ".join(f"{x:.2f}" for x in o)


def tables(res, cells):
    lines = []
    for amp in AMPLITUDES:
        lines.append(f"\n**B = {amp:g}**: e_u(T) (doc/theory.md, section 9.4) and the paper's eq. (15) "
                     "(time-averaged mean point-velocity error, m/s), with observed orders.\n")
        head = "| combination | " + " | ".join(f"e_u h=1/{c}" for c in cells) + \
               " | order e_u | " + " | ".join(f"eq15 h=1/{c}" for c in cells) + " | order eq15 |"
        lines += [head, "|" + "---|" * (2 * len(cells) + 3)]
        for label in COMBOS:
            eu = [res[(label, c, amp)]["e_u"] for c in cells]
            ev = [res[(label, c, amp)]["eq15"] for c in cells]
            lines.append(f"| {label} | " + " | ".join(f"{x:.3e}" for x in eu) +
                         f" | {fmt_orders(order(eu, cells))} | " +
                         " | ".join(f"{x:.3e}" for x in ev) +
                         f" | {fmt_orders(order(ev, cells))} |")
    amp = 0.05
    lines.append("\n**Crack measure at B = 0.05**: largest ratio over the run of the distance "
                 "between initially neighbouring points to its exact value / largest number "
                 "of empty cells.\n")
    lines += ["| combination | " + " | ".join(f"h=1/{c}" for c in cells) + " |",
              "|" + "---|" * (len(cells) + 1)]
    for label in COMBOS:
        lines.append(f"| {label} | " + " | ".join(
            f"{res[(label, c, amp)]['gap']:.3f} / {res[(label, c, amp)]['empty']}"
            for c in cells) + " |")
    c = cells[-1]
    lines.append(f"\n**Cost per step of these runs** (release build, 1 rank, h = 1/{c}, "
                 "B = 0.05), relative to Standard MPM, and MLS fallbacks over the run. The "
                 "step loop includes the diagnostics and crack measures at every step, which "
                 "dominate the cheap kernels; doc/performance.md has the cost without them.\n")
    lines += ["| combination | s per step | relative | fallbacks |", "|---|---|---|---|"]
    base = res[("Standard MPM", c, amp)]["step_time"]
    for label in COMBOS:
        r = res[(label, c, amp)]
        lines.append(f"| {label} | {r['step_time']:.3e} | {r['step_time'] / base:.1f} | "
                     f"{r['fallbacks']} |")
    return "\n".join(lines) + "\n"


def figure(res, cells, path):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    hs = [1.0 / c for c in cells]
    for ax, (amp, key, title) in zip(axes, [(1e-4, "e_u", "e_u(T), B = 1e-4"),
                                            (0.05, "e_u", "e_u(T), B = 0.05"),
                                            (0.05, "eq15", "eq. (15), B = 0.05")]):
        for label in COMBOS:
            ax.loglog(hs, [res[(label, c, amp)][key] for c in cells], "o-", label=label)
        ax.loglog(hs, [res[("pair (theory.md 3.6)", cells[0], amp)][key] * (h / hs[0]) ** 2
                       for h in hs], "k:", label="order 2")
        ax.set_xlabel("h")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def replace_section(doc, name, body):
    text = open(doc).read()
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    block = f"{begin}\n{body}{end}"
    if begin in text:
        text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda m: block, text,
                      flags=re.S)
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    with open(doc, "w") as f:
        f.write(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "verify_mls"))
    ap.add_argument("--max-cells", type=int, default=64)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--skip-runs", action="store_true", help="only rebuild the report")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    cells = [c for c in (8, 16, 32, 64, 128) if c <= args.max_cells]

    if not args.skip_runs:
        peaks = os.path.join(args.out, "peaks.h5")
        subprocess.run([os.path.join(args.build, "dpmpm_peaks"), peaks], check=True,
                       env=dict(os.environ, **MPI_ENV), stdout=subprocess.DEVNULL)
        subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "report_peaks.py"), peaks],
                       check=True)
        cases = [(label, c, amp) for amp in AMPLITUDES for c in reversed(cells)
                 for label in COMBOS]
        scenes = [scene(label, c, amp, args.out, tag_of(label, c, amp)) for label, c, amp in cases]
        dpmpm.study(scenes, jobs=args.jobs, progress=False, errors="raise",
                    binary=os.path.join(args.build, "dpmpm"))
        for case in cases:
            print("done", case, flush=True)

    res = {(label, c, amp): load(args.out, tag_of(label, c, amp))
           for label in COMBOS for c in cells for amp in AMPLITUDES}
    figure(res, cells, os.path.join(ROOT, "doc", "figures", "m1_convergence.png"))
    body = tables(res, cells) + "\n![M1 convergence](figures/m1_convergence.png)\n"
    replace_section(os.path.join(ROOT, "doc", "verification.md"), "m1", body)
    print(body)


if __name__ == "__main__":
    main()
