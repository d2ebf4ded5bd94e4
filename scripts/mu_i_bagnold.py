#!/usr/bin/env python3
"""Steady flow of a mu(I) layer down a rough incline against the Bagnold profile.

A layer of depth h (0.04 m), 2 m long with free ends, on the fixed (rough) face y- of a grid
that gravity tilts by theta; the grid is not tilted. It starts in the stress of the infinite
layer at rest (tau/p = tan(theta) at every depth) and accelerates. The points that started
within 0.1 m of the middle of the layer, far from both ends, are binned by height; their mean
velocity along the slope in each bin is compared at every frame with the closed form of
doc/theory.md 5.9,

    u(z) = (2/3) (I_theta/d) sqrt(phi g cos(theta)) (h^{3/2} - (h - z)^{3/2}),
    I_theta = I_0 (tan(theta) - mu_s)/(mu_2 - tan(theta)),

with phi = rho_b/rho_s, the surface velocity u_s and the flux q = (3/5) u_s h. Prints a table
per run (time, the surface and mean velocities against the closed form, the relative L2
distance of the profile), and the profile at the last frame.

    python3 scripts/mu_i_bagnold.py BIN [--workdir DIR] [--angles 25 23] [--flip 1.0]
        [--cells 10] [--t-end 2.0] [--length 2.0] [--start rest|steady] [--ranks 1]

--length sets the layer's length (its middle, where the profile is taken, lies half of it
from either end). --start steady starts the layer on the closed form instead of at rest:
each row of points is its own region (one row of the 2 x 2 points per cell) moving with
the closed-form velocity at its height, so that a run tells within a short time whether
the discrete flow stays on the closed form, before the thinning from the upslope end
arrives. Below tan(theta) = mu_s the closed form is no flow (I_theta < 0): the table then
gives the mean and the largest speed of the middle points in m/s instead. --tied fills the
grid along x with the layer and ties its two x faces (&boundary condition = 'tied'): a
layer without ends, for the angles where it should rest (a point that leaves the grid,
which a flowing layer's points do at the downslope face, stops the run).

BIN is a dpmpm binary (the release build). doc/verification.md, "The mu(I) rheology: steady
flow against the Bagnold profile", has the results.
"""
import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
from dpmpm import Scene, simulate  # noqa: E402
from dpmpm.run import open_run  # noqa: E402

G = 9.81
MU_S, MU_2, I_0 = 0.38, 0.64, 0.279
D = 5.0e-3            # grain diameter (m)
RHO_S, RHO_B = 2500.0, 1500.0
H = 0.04              # depth of the layer (m)
LENGTH = 2.0          # length of the layer (m)
X0 = 0.1              # its upslope end (m)


def regions(angle, cells, length, start, p0, t0, x0=X0):
    """The &region lines: one box from x0, or (start 'steady') one box per row of points with
    the closed-form velocity at the row's height."""
    stress = (f"  stress = {-p0:.6f}, {-p0:.6f}, {-p0:.6f}, 0.0, 0.0, {t0:.6f},\n"
              f"  stress_gradient(1:6, 2) = {p0 / H:.6f}, {p0 / H:.6f}, {p0 / H:.6f}, 0.0, "
              f"0.0, {-t0 / H:.6f} /")
    if start == "rest":
        return [f"&region lo = {x0}, 0.0, hi = {x0 + length}, {H}, material = 1, ppc = 2,",
                stress]
    dz = 0.5 * H / cells
    lines = []
    for k in range(2 * cells):
        z = (k + 0.5) * dz
        u, _, _ = closed_form(angle, np.array([z]), H)
        lines += [f"&region lo = {x0}, {k * dz:.8f}, hi = {x0 + length}, {(k + 1) * dz:.8f}, "
                  f"material = 1, ppc = 2, velocity = {max(u[0], 0.0):.8f}, 0.0, 0.0,", stress]
    return lines


def scene(tag, angle, flip, cells, t_end, workdir, length=LENGTH, start="rest", tied=False):
    """Scene text: the layer at angle (degrees), cells across its depth, length long,
    started at rest or on the closed form (start 'steady'); tied: the layer fills the grid
    along x and its two x faces are tied (a layer without ends while no point leaves)."""
    th = np.radians(angle)
    c, s = np.cos(th), np.sin(th)
    dx = H / cells
    lx = X0 + length + 0.9 + (1.0 if start == "steady" else 0.0)
    x0 = X0
    if tied:
        lx, x0 = length, 0.0
    nx, ny = int(round(lx / dx)), 2 * cells
    p0, t0 = RHO_B * G * c * H, RHO_B * G * s * H
    return "\n".join([
        f"&run name = '{tag}', t_end = {t_end}, cfl = 0.5, flip = {flip},",
        f"  gravity = {G * s:.7f}, {-G * c:.7f}, 0.0 /",
        f"&grid ndim = 2, ncells = {nx}, {ny}, length = {nx * dx:.6f}, {ny * dx:.6f} /",
        "&shape kernel = 'linear' /",
        f"&material id = 1, model = 'mu_i', density = {RHO_B}, grain_density = {RHO_S},",
        "  youngs_modulus = 2.0e5, poisson_ratio = 0.3,",
        f"  mu_s = {MU_S}, mu_2 = {MU_2}, i_0 = {I_0}, grain_diameter = {D}, max_dilation = 2.0 /",
        *regions(angle, cells, length, start, p0, t0, x0),
        "&boundary face = 'y-', condition = 'fixed' /",
        *(["&boundary face = 'x-', condition = 'tied' /",
           "&boundary face = 'x+', condition = 'tied' /"] if tied else []),
        f"&output dir = '{workdir}', frame_interval = 0.1 /", ""])


def closed_form(angle, z, h):
    """Bagnold profile u(z) of a layer of depth h, its surface value and I_theta at angle
    (degrees)."""
    th = np.radians(angle)
    t = np.tan(th)
    i_th = I_0 * (t - MU_S) / (MU_2 - t)
    a = (2.0 / 3.0) * (i_th / D) * np.sqrt(RHO_B / RHO_S * G * np.cos(th))
    return a * (h ** 1.5 - np.clip(h - z, 0.0, None) ** 1.5), a * h ** 1.5, i_th


def profile(frame, cells, length=LENGTH, x0=X0):
    """Bin centres z and mean v_x per bin of the points that started within 0.1 m of the
    layer's middle, their mean v_x, and the depth of the layer there: the highest point
    plus half the spacing of the points (a quarter cell)."""
    s = frame["solid"]
    x, v, u = s["x"], s["v"], s["displacement"]
    xs = x[:, 0] - u[:, 0]
    sel = np.abs(xs - (x0 + 0.5 * length)) < 0.1
    z = x[sel, 1]
    vx = v[sel, 0]
    edges = np.linspace(0.0, H, cells + 1)
    zc = 0.5 * (edges[1:] + edges[:-1])
    vb = np.array([vx[(z >= a) & (z < b)].mean() if np.any((z >= a) & (z < b)) else np.nan
                   for a, b in zip(edges[:-1], edges[1:])])
    return zc, vb, vx.mean(), z.max() + 0.25 * H / cells, np.abs(v[sel]).max()


def report(h5, angle, cells, length=LENGTH, x0=X0):
    with open_run(h5) as run:
        print(f"# {os.path.basename(h5)}: theta = {angle} deg")
        zc = None
        print("# time (s)  depth h (m)  u_top/u(z_top)  mean/(3/5 u_s)  L2 distance of the "
              "profile / u_s  (closed form of the depth h at that time)")
        for k in range(len(run)):
            fr = run[k]
            zc, vb, vmean, h, vmax = profile(fr, cells, length, x0)
            ref, us, i_th = closed_form(angle, zc, h)
            if i_th <= 0.0:
                if k == 0:
                    print("# below mu_s: time (s), depth h (m), mean and largest speed of the "
                          "middle points (m/s)")
                print(f"{fr.time:8.3f}  {h:8.5f}  {vmean:10.3e}  {vmax:10.3e}")
                continue
            ok = np.isfinite(vb) & (zc < h)
            l2 = np.sqrt(np.mean((vb[ok] - ref[ok]) ** 2)) / us
            print(f"{fr.time:8.3f}  {h:8.5f}  {vb[ok][-1] / ref[ok][-1]:9.4f}  "
                  f"{vmean / (0.6 * us):9.4f}  {l2:9.4f}")
        if i_th <= 0.0:
            return
        print(f"# I_theta = {i_th:.4f}, u_s = {us:.4f} m/s; last frame, z (m), u (m/s), "
              "closed form:")
        for a, b, c in zip(zc, vb, ref):
            print(f"  {a:.4f}  {b:.5f}  {c:.5f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary")
    ap.add_argument("--workdir", default="out/mu_i_bagnold")
    ap.add_argument("--angles", type=float, nargs="+", default=[25.0])
    ap.add_argument("--flip", type=float, default=1.0)
    ap.add_argument("--cells", type=int, default=10)
    ap.add_argument("--t-end", type=float, default=2.0)
    ap.add_argument("--length", type=float, default=LENGTH, help="length of the layer (m)")
    ap.add_argument("--start", choices=["rest", "steady"], default="rest",
                    help="at rest, or on the closed form")
    ap.add_argument("--tied", action="store_true",
                    help="the layer fills the grid along x between tied faces (no ends); a "
                    "point that leaves the grid stops the run, so only for a layer at rest")
    ap.add_argument("--ranks", type=int, default=1)
    args = ap.parse_args()
    workdir = os.path.abspath(args.workdir)
    for angle in args.angles:
        tag = f"bagnold_{angle:g}_f{args.flip:g}_c{args.cells}"
        if args.length != LENGTH:
            tag += f"_l{args.length:g}".replace(".", "p")
        if args.start == "steady":
            tag += "_steady"
        if args.tied:
            tag += "_tied"
        t0 = time.perf_counter()
        text = scene(tag, angle, args.flip, args.cells, args.t_end, workdir, args.length,
                     args.start, args.tied)
        result = simulate(Scene.from_text(text), ranks=args.ranks, workdir=workdir,
                          binary=args.binary, progress=False, reuse=True)
        h5 = result.output
        print(f"# {tag}: {time.perf_counter() - t0:.0f} s (0 when the output was there)")
        report(h5, angle, args.cells, args.length, 0.0 if args.tied else X0)


if __name__ == "__main__":
    main()
