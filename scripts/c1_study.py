#!/usr/bin/env python3
"""Granular column collapse (C1) at several aspect ratios a = H0/L0 (doc/theory.md 9.6).

Builds one scene per aspect ratio from inputs/c1_a2.nml (same material, grid spacing,
points per cell, base and wall; the column height H0 = a L0, the grid long and high
enough for the deposit, the initial state geostatic with K0 = 1 - sin(phi), the end time
grown with sqrt(H0)), runs each with BIN on --ranks ranks in --workdir (unless its output
is there already and --rerun is not given), and reports for the last frame of each run the
runout (L - L0)/L0 and the height H/L0 (farthest and highest point plus half the point
spacing) beside the scaling laws of Lube et al. (2005) and Lajeunesse et al. (2005), and
the kinetic energy left against its peak. --plot draws runout and height against a with
the laws, and the deposits.

--model mu_i replaces the Mohr-Coulomb soil by the mu(I) rheology with the glass beads of
Jop, Forterre & Pouliquen (2006) (mu_s = 0.38, mu_2 = 0.64, I_0 = 0.279; --grain-diameter,
1 mm by default; bulk density 1500 kg/m^3 of grains of 2500, E = 1 MPa, nu = 0.3,
max_dilation 2 unless --max-dilation says otherwise, geostatic K0 = 1 - sin(atan mu_s)).
--cell sets the grid spacing (2 x 2 points per cell throughout). The runout is reported
twice: from the farthest point, and from the end of the connected deposit, the last point
before the first gap along x wider than one cell between neighbouring points (what the
spray of single points thrown ahead does not move). The run time and the steps, the
monitor's largest (kinetic + stored) / (work + initial) and balance error and its
warnings come from the run's log.

    python3 scripts/c1_study.py --bin build/release/dpmpm --ratios 0.5 1 2 4 8 \\
        --workdir out/c1 --plot c1_study.png [--base fixed|rough] [--shape standard|pair]
        [--max-dilation J] [--ranks 2] [--model mohr_coulomb|mu_i] [--cell 0.01]
        [--t-scale 1] [--room 1.5] [--friction-angle PHI] [--slab]

--slab runs the 3D slab of inputs/c1_3d.nml (0.1 m thick between smooth walls) instead.
"""
import argparse
import json
import math
import os
import re
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402

TEMPLATE = os.path.join(ROOT, "inputs", "c1_a2.nml")
TEMPLATE_3D = os.path.join(ROOT, "inputs", "c1_3d.nml")
L0 = 0.2          #: column length (m)
H_CELL = 0.01     #: grid spacing of the template (m)
SPACING = 0.005   #: initial point spacing (2 x 2 points per cell)


def lube(a):
    return 1.2 * a if a < 1.8 else 1.9 * a ** (2.0 / 3.0)


def lajeunesse(a):
    return 1.8 * a if a < 3.0 else 2.3 * a ** (2.0 / 3.0)


#: the MLS pair of doc/theory.md 3.6 (doc/input.md, &shape)
PAIR = {"kernel": "cubic", "quadrature": "gauss", "field_kernel": "wendland_c2",
        "field_radius": 2.0}


#: the glass beads of Jop, Forterre & Pouliquen (2006): the mu(I) soil of --model mu_i
MU_S, MU_2, I_0 = 0.38, 0.64, 0.279
RHO_B, RHO_S = 1500.0, 2500.0


def mu_i_material(grain_diameter):
    """The &material of the mu(I) soil (id 1)."""
    return {"id": 1, "model": "mu_i", "density": RHO_B, "grain_density": RHO_S,
            "youngs_modulus": 1.0e6, "poisson_ratio": 0.3, "mu_s": MU_S, "mu_2": MU_2,
            "i_0": I_0, "grain_diameter": grain_diameter}


def build_scene(a, base, workdir, shape="standard", max_dilation=0.0, smoothing=False,
                model="mohr_coulomb", cell=H_CELL, grain_diameter=1.0e-3, t_scale=1.0,
                room=1.5, friction_angle=None):
    """The template with column height a L0, a grid of spacing cell that holds room times the
    larger law's runout and a geostatic start (and, with max_dilation > 0, that bound on the
    points' volume, doc/theory.md 5.4; with smoothing, the volumetric smoothing of
    doc/theory.md 4.5; with model 'mu_i' the mu(I) soil), as a dpmpm.Scene."""
    s = dpmpm.Scene.read(TEMPLATE)
    h0 = a * L0
    # room for `room` times the larger scaling law's runout, and 5 cm above the column
    length = L0 * (1.0 + room * max(lube(a), lajeunesse(a))) + 0.1
    nx = int(math.ceil(length / cell - 1e-9))
    ny = int(math.ceil((h0 + 0.05) / cell - 1e-9))
    t_end = round(t_scale * (1.0 * math.sqrt(a / 2.0) + 0.5), 2)
    name = (f"c1_a{a:g}".replace(".", "p") + ("_mui" if model == "mu_i" else "")
            + ("_rough" if base == "rough" else "")
            + ("_pair" if shape == "pair" else "")
            + (f"_j{max_dilation:g}".replace(".", "p") if max_dilation > 0 else "")
            + ("_vs" if smoothing else "")
            + (f"_h{cell:g}".replace(".", "p") if cell != H_CELL else "")
            + (f"_t{t_scale:g}".replace(".", "p") if t_scale != 1.0 else "")
            + (f"_phi{friction_angle:g}".replace(".", "p") if friction_angle else ""))
    s.set(run={"name": name, "t_end": t_end},
          grid={"ncells": [nx, ny], "length": [round(nx * cell, 6), round(ny * cell, 6)]},
          output={"dir": workdir, "frame_interval": 0.1})
    [region] = s.groups("region")
    region["hi"] = [L0, round(h0, 4)]
    for initial in ("stress", "stress_gradient"):
        del region[initial]
    region["geostatic"], region["k0"] = True, 0.5
    if friction_angle and model == "mohr_coulomb":
        s["material"]["friction_angle"] = friction_angle
        region["k0"] = round(1.0 - math.sin(math.radians(friction_angle)), 4)
    if model == "mu_i":
        s["material"].clear()
        s.set(material=mu_i_material(grain_diameter))
        # at rest: tau/p' of K0 = 1 - sin(atan mu_s) = 0.645 is 0.27, below mu_s
        region["k0"] = round(1.0 - math.sin(math.atan(MU_S)), 4)
    if shape == "pair":
        s["shape"].clear()
        s.set(shape=PAIR)
    if max_dilation > 0:
        s["material"]["max_dilation"] = max_dilation
    if smoothing:
        s["run"]["volumetric_smoothing"] = "cell"
    if base == "rough":
        [floor] = s.find("boundary", face="y-", condition="fixed")
        floor.update(condition="roller", friction=0.577, lift_off=False)
    return s


def deposit_end(x, cell):
    """The end of the connected deposit: the last point along x before the first gap wider
    than one cell between neighbouring points."""
    xs = np.sort(x)
    gaps = np.nonzero(np.diff(xs) > cell)[0]
    return xs[gaps[0]] if len(gaps) else xs[-1]


def log_summary(log):
    """From a run's log: steps, the monitor's largest (kinetic + stored) / (work + initial)
    and largest balance error, and the number of its warnings (NaN, -1 where absent)."""
    text = open(log).read() if os.path.exists(log) else ""
    m = re.search(r"largest \(kinetic \+ stored\) / \(work \+ initial\)\s+([-+\d.E]+), "
                  r"largest balance error\s+([-+\d.E]+)", text)
    steps = re.search(r"done, (\d+) steps to t =", text)
    return dict(ratio=float(m.group(1)) if m else float("nan"),
                balance=float(m.group(2)) if m else float("nan"),
                steps=int(steps.group(1)) if steps else -1,
                warnings=len(re.findall(r"monitor: warning", text)))


def build_slab(a, workdir, model="mohr_coulomb", cell=0.02, grain_diameter=1.0e-3,
               t_scale=1.0, room=1.5, max_dilation=0.0):
    """The 3D slab of inputs/c1_3d.nml (0.1 m thick between smooth walls, z up) with column
    height a L0, a grid of spacing cell across x and z that holds room times the larger law's
    runout, as build_scene does in 2D."""
    s = dpmpm.Scene.read(TEMPLATE_3D)
    h0 = a * L0
    length = L0 * (1.0 + room * max(lube(a), lajeunesse(a))) + 0.1
    nx = int(math.ceil(length / cell - 1e-9))
    nz = int(math.ceil((h0 + 0.05) / cell - 1e-9))
    ny = int(round(0.1 / cell))
    t_end = round(t_scale * (1.0 * math.sqrt(a / 2.0) + 0.5), 2)
    name = (f"c1_3d_a{a:g}".replace(".", "p") + ("_mui" if model == "mu_i" else "")
            + (f"_h{cell:g}".replace(".", "p")) + (f"_t{t_scale:g}".replace(".", "p")))
    s.set(run={"name": name, "t_end": t_end},
          grid={"ncells": [nx, ny, nz],
                "length": [round(nx * cell, 6), round(ny * cell, 6), round(nz * cell, 6)]},
          output={"dir": workdir, "frame_interval": 0.1})
    [region] = s.groups("region")
    region["hi"] = [L0, 0.1, round(h0, 4)]
    if model == "mu_i":
        s["material"].clear()
        s.set(material=mu_i_material(grain_diameter))
        region["k0"] = round(1.0 - math.sin(math.atan(MU_S)), 4)
    if max_dilation > 0:
        s["material"]["max_dilation"] = max_dilation
    return s


def measure(path, a, cell=H_CELL):
    with dpmpm.open_run(path) as run:
        first, last = run.frames[0], run.frames[-1]
        t = last.time
        x = last["solid"]["x"].copy()
        x0 = first["solid"]["x"].copy()
        # the frame half a second before the last: the front's motion since then
        back = run.frame_at(max(0.0, t - 0.5))
        xb = back["solid"]["x"][:, 0].max()
        tb = back.time
        ke = np.asarray(run.diagnostics["kinetic_energy"])
    half = 0.5 * cell / 2.0     # half the point spacing (2 x 2 points per cell)
    runout = (x[:, 0].max() + half - L0) / L0
    end = (deposit_end(x[:, 0], cell) + half - L0) / L0
    height = (x[:, -1].max() + half) / L0   # the last axis is up
    front_speed = (x[:, 0].max() - xb) / max(t - tb, 1e-12)
    stem = os.path.splitext(path)[0]
    wall = float("nan")
    if os.path.exists(stem + ".wall.json"):
        wall = json.load(open(stem + ".wall.json"))["wall"]
    return dict(a=a, t=t, runout=runout, end=end, height=height, ke=ke[-1] / ke.max(),
                front_speed=front_speed, wall=wall, x=x, x0=x0, **log_summary(stem + ".log"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.5, 1.0, 2.0, 4.0, 8.0])
    ap.add_argument("--base", choices=["fixed", "rough"], default="fixed")
    ap.add_argument("--shape", choices=["standard", "pair"], default="standard",
                    help="Standard MPM (the template's linear grid functions) or the MLS pair")
    ap.add_argument("--max-dilation", type=float, default=0.0,
                    help="&material max_dilation of the soil (0: no bound)")
    ap.add_argument("--volumetric-smoothing", action="store_true",
                    help="volumetric_smoothing = 'cell' (doc/theory.md 4.5)")
    ap.add_argument("--model", choices=["mohr_coulomb", "mu_i"], default="mohr_coulomb",
                    help="the soil: the template's Mohr-Coulomb or the mu(I) glass beads")
    ap.add_argument("--grain-diameter", type=float, default=1.0e-3,
                    help="d (m) of the mu(I) soil")
    ap.add_argument("--cell", type=float, default=H_CELL, help="grid spacing (m)")
    ap.add_argument("--t-scale", type=float, default=1.0,
                    help="end time: this times 1.0 sqrt(a/2) + 0.5 s")
    ap.add_argument("--room", type=float, default=1.5,
                    help="the grid holds this times the larger law's runout")
    ap.add_argument("--friction-angle", type=float,
                    help="the Mohr-Coulomb soil's friction angle (degrees; the template's 30 if "
                    "not given), with K0 = 1 - sin(phi)")
    ap.add_argument("--slab", action="store_true",
                    help="the 3D slab of inputs/c1_3d.nml instead of the 2D column")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--workdir", default="out/c1")
    ap.add_argument("--rerun", action="store_true", help="run again when the output exists")
    ap.add_argument("--plot", help="figure of runout and height against a, and the deposits")
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    rows = []
    max_dilation = args.max_dilation
    if args.model == "mu_i" and max_dilation == 0.0:
        max_dilation = 2.0
    for a in args.ratios:
        if args.slab:
            scene = build_slab(a, args.workdir, args.model, args.cell, args.grain_diameter,
                               args.t_scale, args.room, max_dilation)
        else:
            scene = build_scene(a, args.base, args.workdir, args.shape, max_dilation,
                                args.volumetric_smoothing, args.model, args.cell,
                                args.grain_diameter, args.t_scale, args.room,
                                args.friction_angle)
        h5 = scene.output_file()
        if args.rerun or not os.path.exists(h5):
            try:
                r = dpmpm.simulate(scene, ranks=args.ranks, binary=args.bin,
                                   progress=sys.stderr.isatty())
                print(f"{scene.name}: exit code 0, {r.wall:.0f} s", flush=True)
                with open(os.path.splitext(h5)[0] + ".wall.json", "w") as f:
                    json.dump({"wall": r.wall, "ranks": args.ranks}, f)
            except dpmpm.RunError as e:
                print(f"{scene.name}: exit code {e.status}: {e}", flush=True)
                continue
        else:
            scene.write(os.path.join(args.workdir, scene.name + ".nml"))
        rows.append(measure(h5, a, args.cell))
    print("| a | t end (s) | (L−L0)/L0 farthest | deposit end | Lube 2005 | Lajeunesse 2005 | "
          "H/L0 | a (a < 1.15), a^0.4 | kinetic energy left | front speed, last 0.5 s (m/s) | "
          "steps | wall (s) | monitor (KE + stored)/(work + initial) | balance error | "
          "warnings |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        a = r["a"]
        hl = a if a < 1.15 else a ** 0.4
        print(f"| {a:g} | {r['t']:.2f} | {r['runout']:.2f} | {r['end']:.2f} | {lube(a):.2f} | "
              f"{lajeunesse(a):.2f} | {r['height']:.2f} | {hl:.2f} | {r['ke']:.1e} | "
              f"{r['front_speed']:.1e} | {r['steps']} | {r['wall']:.0f} | {r['ratio']:.3f} | "
              f"{r['balance']:.1e} | {r['warnings']} |")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig = plt.figure(figsize=(10, 6))
        ax1 = fig.add_subplot(2, 2, 1)
        ax2 = fig.add_subplot(2, 2, 2)
        aa = np.geomspace(0.4, 10, 100)
        ax1.loglog(aa, [lube(v) for v in aa], "k-", lw=0.8, label="Lube et al. 2005")
        ax1.loglog(aa, [lajeunesse(v) for v in aa], "k--", lw=0.8, label="Lajeunesse et al. 2005")
        ax1.loglog([r["a"] for r in rows], [r["runout"] for r in rows], "o",
                   label="dpmpm, farthest point")
        ax1.loglog([r["a"] for r in rows], [r["end"] for r in rows], "s", mfc="none",
                   label="dpmpm, end of the deposit")
        ax1.set_xlabel("a = H0/L0")
        ax1.set_ylabel("(L∞ − L0)/L0")
        ax1.legend(fontsize=7)
        ax2.loglog(aa, np.where(aa < 1.15, aa, aa ** 0.4), "k-", lw=0.8, label="a, a^0.4")
        ax2.loglog([r["a"] for r in rows], [r["height"] for r in rows], "o", label="dpmpm")
        ax2.set_xlabel("a = H0/L0")
        ax2.set_ylabel("H∞/L0")
        ax2.legend(fontsize=7)
        ax3 = fig.add_subplot(2, 1, 2)
        for r in sorted(rows, key=lambda r: -r["a"]):   # the largest first, the rest on top
            ax3.scatter(r["x"][:, 0], r["x"][:, 1], s=0.3, label=f"a = {r['a']:g}")
        ax3.set_aspect("equal")
        ax3.set_xlabel("x (m)")
        ax3.set_ylabel("y (m)")
        ax3.legend(fontsize=7, markerscale=10)
        fig.suptitle(f"Column collapse, {args.model}, {args.base} base, {args.shape}, "
                     f"h = {args.cell:g} m: runout, height, final deposits")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"figure: {args.plot}")


if __name__ == "__main__":
    sys.exit(main())
