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

With --flutter BIN: a long block (1.6 m x 0.1 m, elastic, on the rough face y-) at several
incline angles, friction coefficients and flip, dry and saturated, each run to 0.2 s, the dry
ones also with lift_off = .false.; prints the mean displacement of the points that start
within 0.2 m of the block's middle over the Coulomb distance, and the friction force it
implies over Coulomb's (doc/verification.md, "Larger friction: frictional flutter").
"""
import argparse
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402
from dpmpm.run import open_run  # noqa: E402

SCENE = os.path.join(ROOT, "inputs", "incline_slide_2d.nml")
#: (tag, flip, friction, kernel) of --study
VARIANTS = [("flip0", 0.0, 0.3, "linear"), ("flip05", 0.5, 0.3, "linear"),
            ("flip09", 0.9, 0.3, "linear"), ("flip1", 1.0, 0.3, "linear"),
            ("hold05", 0.5, 0.7, "linear"), ("hold1", 1.0, 0.7, "linear"),
            ("smooth", 0.5, 0.0, "linear")]


#: (tag, angle (deg), friction, flip, cells per 0.02 m, block length (m), saturated, K_f (Pa))
FLUTTER = [("d30_mu03", 30, 0.3, 0.5, 1, 1.6, False, 0.0),
           ("d30_mu04", 30, 0.4, 0.5, 1, 1.6, False, 0.0),
           ("d30_mu05", 30, 0.5, 0.5, 1, 1.6, False, 0.0),
           ("d30_mu05_pic", 30, 0.5, 0.0, 1, 1.6, False, 0.0),
           ("d45_mu05", 45, 0.5, 0.5, 1, 1.6, False, 0.0),
           ("d45_mu05_f025", 45, 0.5, 0.25, 1, 1.6, False, 0.0),
           ("d45_mu05_pic", 45, 0.5, 0.0, 1, 1.6, False, 0.0),
           ("d45_mu07", 45, 0.7, 0.5, 1, 1.6, False, 0.0),
           ("d45_mu07_f025", 45, 0.7, 0.25, 1, 1.6, False, 0.0),
           ("d45_mu07_pic", 45, 0.7, 0.0, 1, 1.6, False, 0.0),
           ("d45_mu07_fine", 45, 0.7, 0.5, 2, 1.6, False, 0.0),
           ("d45_mu07_short", 45, 0.7, 0.5, 1, 0.2, False, 0.0),
           ("d45_mu09", 45, 0.9, 0.5, 1, 1.6, False, 0.0),
           ("d45_mu09_pic", 45, 0.9, 0.0, 1, 1.6, False, 0.0),
           ("s30_mu03", 30, 0.3, 0.5, 1, 1.6, True, 2.2e7),
           ("s30_mu07", 30, 0.7, 0.5, 1, 1.6, True, 2.2e7),
           ("s30_mu07_pic", 30, 0.7, 0.0, 1, 1.6, True, 2.2e7),
           ("s30_mu07_fine", 30, 0.7, 0.5, 2, 1.6, True, 2.2e7),
           ("s30_mu07_kf6", 30, 0.7, 0.5, 1, 1.6, True, 2.2e6),
           ("s30_mu07_kf8", 30, 0.7, 0.5, 1, 1.6, True, 2.2e8),
           ("s30_mu15", 30, 1.5, 0.5, 1, 1.6, True, 2.2e7)]


def long_block(tag, angle, mu, flip, refine, length, saturated, kf, workdir, lift_off=True):
    """The scene (a dpmpm.Scene) of a block of the given length, 0.1 m thick, at rest in its geostatic state
    on the rough face y- of a grid tilted by gravity (as tests/test_wall_friction.f90 builds
    it): dry (1000 kg/m^3, K0 = 3/7) or saturated (grains 2650 kg/m^3, n = 0.4, k = 1e-8 m/s,
    water of bulk modulus kf; sigma'_xx = p so that no total stress acts across its ends)."""
    g = 9.81
    th = np.radians(angle)
    gx, gn = g * np.sin(th), g * np.cos(th)
    nx, ny = int(round((length + 0.8) / 0.02)) * refine, 10 * refine
    lines = [f"&run name = '{tag}', t_end = 0.2, cfl = 0.5, flip = {flip},",
             f"  gravity = {gx:.7f}, {-gn:.7f}, 0.0" + (", drag = 'implicit' /" if saturated else " /"),
             f"&grid ndim = 2, ncells = {nx}, {ny}, length = {length + 0.8}, 0.2 /",
             "&shape kernel = 'linear' /"]
    if saturated:
        rho = 0.6 * 1650.0
        lines += ["&material id = 1, model = 'linear_elastic', density = 2650.0, youngs_modulus = 1.0e7,",
                  "  poisson_ratio = 0.3, conductivity = 1.0e-8 /",
                  f"&material id = 2, model = 'fluid', density = 1000.0, bulk_modulus = {kf} /",
                  "&region lo = 0.1, 0.0, hi = " + f"{0.1 + length}, 0.1, material = 1, ppc = 2,",
                  "  phase = 'saturated', fluid_material = 2, porosity = 0.4,",
                  f"  pore_pressure = {1000 * gn * 0.1:.6f}, pore_pressure_gradient = 0.0, {-1000 * gn:.6f}, 0.0,",
                  f"  stress = {1000 * gn * 0.1:.6f}, {-rho * gn * 0.1:.6f}, {-rho * gn * 0.1 * 3 / 7:.6f}, 0.0, 0.0, 0.0,",
                  f"  stress_gradient(1:6, 2) = {-1000 * gn:.6f}, {rho * gn:.6f}, {rho * gn * 3 / 7:.6f}, 0.0, 0.0, 0.0 /"]
    else:
        rho = 1000.0
        lines += ["&material id = 1, model = 'linear_elastic', density = 1000.0, youngs_modulus = 1.0e7,",
                  "  poisson_ratio = 0.3 /",
                  "&region lo = 0.1, 0.0, hi = " + f"{0.1 + length}, 0.1, material = 1, ppc = 2,",
                  f"  stress = {-rho * gn * 0.1 * 3 / 7:.6f}, {-rho * gn * 0.1:.6f}, {-rho * gn * 0.1 * 3 / 7:.6f}, 0.0, 0.0, 0.0,",
                  f"  stress_gradient(1:6, 2) = {rho * gn * 3 / 7:.6f}, {rho * gn:.6f}, {rho * gn * 3 / 7:.6f}, 0.0, 0.0, 0.0 /"]
    hold = "" if lift_off else ", lift_off = .false."
    lines += [f"&boundary face = 'y-', condition = 'roller', friction = {mu}{hold} /",
              f"&output dir = '{workdir}', frame_interval = 0.01 /", ""]
    return dpmpm.Scene.from_text("\n".join(lines))


def normal_share(saturated):
    """The share of the weight that the friction takes: all of it dry, the buoyant weight
    over the saturated weight with pore water (doc/theory.md 6.7)."""
    return (0.6 * 1650.0) / (0.6 * 2650.0 + 400.0) if saturated else 1.0


def middle_slide(path, length, saturated, mu):
    """Mean x displacement at the last frame of the solid points that start within 0.2 m of
    the block's middle, and the Coulomb distance (0 where friction holds the block)."""
    with open_run(path) as run:
        g = np.zeros(3)
        gv = run.input_groups("run")[0].get("gravity", [0.0])
        g[:len(gv)] = gv
        fr = run.frames[-1]
        s = fr["solid"]
        x0 = s["x"][:, 0] - s["displacement"][:, 0]
        m = np.abs(x0 - (0.1 + 0.5 * length)) < 0.2
        ux = float(np.mean(s["displacement"][m, 0]))
        t = fr.time
    a = max(0.0, g[0] + mu * normal_share(saturated) * g[1])
    return t, ux, 0.5 * a * t * t


def flutter(binary, workdir):
    """Runs the FLUTTER cases, each dry one also with lift_off = .false. (the wall holding
    its nodes whatever their motion; the wall holds the skeleton with pore water either way),
    and prints one table."""
    workdir = os.path.abspath(workdir)

    def slide(tag, case, lift_off):
        angle, mu, flip, refine, length, sat, kf = case
        name = tag if lift_off else tag + "_held"
        scene = long_block(name, angle, mu, flip, refine, length, sat, kf, workdir, lift_off)
        r = dpmpm.simulate(scene, binary=binary, reuse=True, progress=False)
        t, ux, ex = middle_slide(r.output, length, sat, mu)
        # the mean friction (per unit mass) that the distance slid implies, against mu g_n
        # (times the buoyant share with pore water): a = g_t - f
        th = np.radians(angle)
        force = (9.81 * np.sin(th) - 2.0 * ux / t ** 2) / (mu * normal_share(sat) * 9.81 * np.cos(th))
        return ux, ex, force

    print("| run | angle | μ | flip | h (m) | block (m) | pore water K_f (Pa) | Coulomb x (m) "
          "| x at 0.2 s (m) | ratio | friction force against Coulomb's "
          "| lift_off = .false.: x (m) | ratio | friction force |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for tag, *case in FLUTTER:
        angle, mu, flip, refine, length, sat, kf = case
        ux, ex, force = slide(tag, case, True)
        water = f"{kf:.1e}" if sat else "dry"
        row = (f"| {tag} | {angle}° | {mu} | {flip} | {0.02 / refine:.2f} | {length} | {water} "
               f"| {ex:.3e} | {ux:.3e} | ")
        row += f"{ux / ex:.3f} | {force:.3f} |" if ex > 0 else "(stays) | |"
        if sat:
            row += " (the same) | | |"
        else:
            ux, ex, force = slide(tag, case, False)
            row += f" {ux:.3e} | " + (f"{ux / ex:.3f} | {force:.3f} |" if ex > 0 else "(stays) | |")
        print(row)


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


def variant(tag, flip, mu, kernel, workdir):
    """The scene of one --study variant, as a dpmpm.Scene."""
    s = dpmpm.Scene.read(SCENE)
    s.set(run={"name": f"slide_{tag}", "flip": flip}, shape={"kernel": kernel},
          output={"dir": workdir})
    [floor] = s.find("boundary", face="y-")
    floor["friction"] = mu
    return s


def study(binary, workdir):
    files = []
    for tag, flip, mu, kernel in VARIANTS:
        scene = variant(tag, flip, mu, kernel, workdir)
        try:
            dpmpm.simulate(scene, binary=binary, progress=False)
        except dpmpm.RunError as e:     # reported by the table below as what it wrote
            print(f"{scene.name}: {e}", file=sys.stderr)
        files.append((tag, flip, mu, kernel, scene.output_file()))
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
    ap.add_argument("--flutter", metavar="BIN", help="run the long-block study with this binary")
    ap.add_argument("--workdir", default="out/incline_study")
    ap.add_argument("--plot", help="figure of x(t) against the closed form")
    args = ap.parse_args()
    files = list(args.files)
    if args.flutter:
        flutter(args.flutter, args.workdir)
        return
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
