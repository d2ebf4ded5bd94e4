#!/usr/bin/env python3
"""Cavity expansion in Tresca soil against the closed forms of doc/theory.md: cylindrical,
plane strain (inputs/cavity_cylindrical_2d.nml, 9.7), or spherical, axisymmetric
(--geometry spherical: inputs/cavity_spherical_2d.nml, 9.9).

A quarter of a thick cylinder a0 < r < b0 with a free outer face; the cavity pressure p
rises linearly over ramp_time and is then held. Each frame gives the cavity radius a from
a ring of points in the soil (initial radius 1.5 a0 <= r0 < 2 a0, away from the loaded
nodes at the wall): the body keeps its volume, so every ring keeps r^2 - r0^2, and
a^2 = a0^2 + mean(r^2 - r0^2). The pressure p(t) is the load's ramp. Compared:

- before first yield (p < s_u (1 - a0^2/b0^2)), the radial displacement of the ring's
  points against Lame's thick cylinder (compressible, small strain): the relative error
  of its mean;
- after it, p against the incompressible large-strain closed form
  p = s_u (1 - c^2/b^2) + 2 s_u ln(c/a),  c^2 = (G/s_u)(a^2 - a0^2),  b^2 = b0^2 + a^2 - a0^2
  (fully plastic, c >= b: p = 2 s_u ln(b/a)), evaluated at the measured a: the error in
  units of s_u, and the radius a_ref(p) the closed form gives at the pressure reached;
- the part of the resultant p a that the surface loads put on free nodes (the rest goes
  to the roller faces: load_fraction), and the error against the pressure so taken.

The sphere alike, with the sphere's closed forms: every shell keeps R^3 - R0^3, so
a^3 = a0^3 + mean(R^3 - R0^3) over the ring; Lame's thick sphere before first yield
((4/3) s_u (1 - a0^3/b0^3)); after it
  p = (4/3) s_u (1 - c^3/b^3) + 4 s_u ln(c/a),  c^3 = (G/s_u)(a^3 - a0^3),  b^3 = b0^3 + a^3 - a0^3
(fully plastic: 4 s_u ln(b/a); infinite medium (4/3) s_u [1 + ln((G/s_u)(1 - a0^3/a^3))], limit
(4/3) s_u (1 + ln(G/s_u))); the load on free nodes is that of the axial component (the
radial one of the lines past the cavity ends on the axis, where r = 0).

Runs the scene at the grid spacings h = a0/n for n in --cells-per-radius (the cylinder,
material, points per cell and load kept), and prints a table; --plot draws p/s_u against
a/a0 with the closed form and the infinite medium's curve
p = s_u [1 + ln((G/s_u)(1 - a0^2/a^2))] (limit s_u (1 + ln(G/s_u))).

    python3 scripts/cavity_expansion.py --bin build/release/dpmpm --cells-per-radius 4 8 \\
        --workdir out/cavity --plot doc/figures/cavity_cylindrical.png
"""
import argparse
import math
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402

SCENE = os.path.join(ROOT, "inputs", "cavity_cylindrical_2d.nml")
SCENES = {"cylindrical": SCENE, "spherical": os.path.join(ROOT, "inputs", "cavity_spherical_2d.nml")}


class Cylinder:
    """The cylinder, soil and load of a cavity scene (read from its groups)."""

    shape = "cylindrical"

    def __init__(self, s, a0, b0):
        mat = s.find("material", id=1)[0]
        e, nu = float(mat["youngs_modulus"]), float(mat["poisson_ratio"])
        self.G = e / (2.0 * (1.0 + nu))
        self.lam = 2.0 * self.G * nu / (1.0 - 2.0 * nu)
        self.su = float(mat["cohesion"])
        if float(mat.get("friction_angle", 0.0)) != 0.0:
            raise SystemExit("cavity_expansion: the soil must have friction_angle = 0 (Tresca)")
        load = s.find("load", face="x-")[0]
        self.p_end = float(load["traction"][0])
        self.ramp = float(load["ramp_time"])
        self.a0, self.b0 = a0, b0

    def pressure(self, t):
        return self.p_end * np.minimum(np.asarray(t) / self.ramp, 1.0)

    def first_yield(self):
        """Cavity pressure at first yield (Tresca at the wall of the elastic cylinder,
        incompressible: sigma_theta - sigma_r = 2 p b^2/(b^2 - a^2) (a/r)^2)."""
        return self.su * (1.0 - (self.a0 / self.b0) ** 2)

    def lame_u(self, p, r):
        """Radial displacement at r of the elastic thick cylinder a0 < r < b0 under an
        internal pressure p, free outside, plane strain, small strain."""
        a2, b2 = self.a0 ** 2, self.b0 ** 2
        B = p * a2 * b2 / (2.0 * self.G * (b2 - a2))
        A = self.G * B / ((self.lam + self.G) * b2)
        return A * r + B / r

    def p_ref(self, a):
        """Closed-form cavity pressure at radius a (incompressible, large strain)."""
        a = np.asarray(a, dtype=float)
        da = np.maximum(a ** 2 - self.a0 ** 2, 1e-300)
        c2 = (self.G / self.su) * da
        b2 = self.b0 ** 2 + da
        part = self.su * (1.0 - c2 / b2) + self.su * np.log(c2 / a ** 2)
        full = self.su * np.log(b2 / a ** 2)
        p = np.where(c2 < b2, part, full)
        return np.where(p > self.first_yield(), p, np.nan)

    def p_infinite(self, a):
        a = np.asarray(a, dtype=float)
        return self.su * (1.0 + np.log((self.G / self.su) * (1.0 - (self.a0 / a) ** 2)))

    def limit(self):
        """The infinite medium's limit pressure over s_u."""
        return 1.0 + math.log(self.G / self.su)

    def cavity_radius(self, r, r0):
        """The cavity radius from a ring's radii now and at the start (the body keeps its
        volume: every ring keeps r^2 - r0^2)."""
        return math.sqrt(self.a0 ** 2 + float(np.mean(r ** 2 - r0 ** 2)))

    def load_fraction(self, x, h, a):
        return load_fraction(x, h, a)

    def curve(self, n=4000, a_max=None):
        """The closed form on a fine set of radii from first yield to a_max (default: the
        fully plastic end at 3 a0)."""
        # first yield: c = a, i.e. a^2 - a0^2 = (s_u/G) a^2
        a_y = self.a0 / math.sqrt(1.0 - self.su / self.G)
        a = np.linspace(a_y * (1.0 + 1e-9), a_max or 3.0 * self.a0, n)
        return a, self.p_ref(a)

    def a_ref(self, p):
        """Smallest radius where the closed form reaches p (nan when p exceeds its peak)."""
        a, pr = self.curve()
        k = np.nonzero(pr >= p)[0]
        if len(k) == 0:
            return float("nan")
        i = k[0]
        if i == 0:
            return float(a[0])
        return float(np.interp(p, pr[i - 1:i + 1], a[i - 1:i + 1]))


class Sphere(Cylinder):
    """The thick sphere a0 < R < b0 of an axisymmetric cavity scene (doc/theory.md 9.8, 9.9)."""

    shape = "spherical"

    def first_yield(self):
        """Cavity pressure at first yield (Tresca at the wall of the elastic sphere,
        incompressible: sigma_theta - sigma_R = 3 p b^3/(2 (b^3 - a^3)) (a/R)^3)."""
        return 4.0 / 3.0 * self.su * (1.0 - (self.a0 / self.b0) ** 3)

    def lame_u(self, p, r):
        """Radial displacement at R of the elastic thick sphere under an internal pressure
        p, free outside, small strain (doc/theory.md 9.8)."""
        a3, b3 = self.a0 ** 3, self.b0 ** 3
        nu = self.lam / (2.0 * (self.lam + self.G))
        e = 2.0 * self.G * (1.0 + nu)
        return p * a3 * r / (e * (b3 - a3)) * ((1.0 - 2.0 * nu) + 0.5 * (1.0 + nu) * b3 / r ** 3)

    def p_ref(self, a):
        a = np.asarray(a, dtype=float)
        da = np.maximum(a ** 3 - self.a0 ** 3, 1e-300)
        c3 = (self.G / self.su) * da
        b3 = self.b0 ** 3 + da
        part = 4.0 / 3.0 * self.su * (1.0 - c3 / b3) + 4.0 / 3.0 * self.su * np.log(c3 / a ** 3)
        full = 4.0 / 3.0 * self.su * np.log(b3 / a ** 3)
        p = np.where(c3 < b3, part, full)
        return np.where(p > self.first_yield(), p, np.nan)

    def p_infinite(self, a):
        a = np.asarray(a, dtype=float)
        return 4.0 / 3.0 * self.su * (1.0 + np.log((self.G / self.su) * (1.0 - (self.a0 / a) ** 3)))

    def limit(self):
        return 4.0 / 3.0 * (1.0 + math.log(self.G / self.su))

    def curve(self, n=4000, a_max=None):
        # first yield: c = a, i.e. a^3 - a0^3 = (s_u/G) a^3
        a_y = self.a0 / (1.0 - self.su / self.G) ** (1.0 / 3.0)
        a = np.linspace(a_y * (1.0 + 1e-9), a_max or 3.0 * self.a0, n)
        return a, self.p_ref(a)

    def cavity_radius(self, r, r0):
        """The cavity radius from a shell's radii now and at the start (every shell keeps
        R^3 - R0^3)."""
        return (self.a0 ** 3 + float(np.mean(r ** 3 - r0 ** 3))) ** (1.0 / 3.0)

    def load_fraction(self, x, h, a):
        """The part of the axial resultant p a^2/2 (per radian) that the surface load puts on
        free nodes: along each line r = i h (i h < a + h) the load's ring share (h^2/6 at
        i = 0, h r_i inside) goes to the roller z = 0 whenever the node (i h, 0) has mass."""
        near = x[x[:, 1] < h, 0]
        lost = 0.0
        for i in range(int((a + h) / h) + 1):
            r = i * h
            if r >= a:
                break
            share = h * h / 6.0 if i == 0 else h * r
            if np.any(np.abs(near - r) < h):
                lost += share
        return 1.0 - lost / (0.5 * a * a)


def polygon(a0, b0, n_in=16, n_out=45):
    """The quarter annulus a0 < r < b0 as a polygon: the outer arc in n_out chords
    counter-clockwise, the cavity's in n_in chords back."""
    xs, ys = [a0], [0.0]
    for k in range(n_out + 1):
        t = 0.5 * math.pi * k / n_out
        xs.append(b0 * math.cos(t))
        ys.append(b0 * math.sin(t))
    for k in range(n_in, 0, -1):
        t = 0.5 * math.pi * k / n_in
        xs.append(a0 * math.cos(t))
        ys.append(a0 * math.sin(t))
    clean = [[0.0 if abs(v) < 1e-12 else round(v, 9) for v in vs] for vs in (xs, ys)]
    return clean[0], clean[1]


def scene(path, n, workdir, a0=1.0, b0=8.0, ramp=None, p_end=None, t_end=None, name=None):
    """The cavity scene with h = a0/n and outer radius b0 (the grid reaching b0 + a0),
    optionally another ramp time, end pressure and end time (as a dpmpm.Scene)."""
    s = dpmpm.Scene.read(path)
    h = a0 / n
    ncell = int(math.ceil((b0 + a0) / h - 1e-9))
    xs, ys = polygon(a0, b0)
    reg = s.groups("region")[0]
    reg.update(npoly=len(xs), poly_x=xs, poly_y=ys)
    for ld in s.groups("load"):
        if ramp is not None:
            ld["ramp_time"] = ramp
        if p_end is not None:
            ld["traction"] = [p_end if abs(v) > 0 else 0.0 for v in ld["traction"]]
    run = {"name": name or f"cavity_n{n}_b{b0:g}"}
    if t_end is not None:
        run["t_end"] = t_end
    s.set(run=run, grid={"ncells": [ncell, ncell], "length": [ncell * h, ncell * h]},
          output={"dir": workdir})
    return s


def load_fraction(x, h, a):
    """The part of the cavity pressure's resultant p a along x that the surface load puts
    on free nodes: along each grid line y = j h (j h < a + h) the load's share h (h/2 at
    j = 0) goes to the roller face, where the constraint takes it, whenever the node
    (0, j h) has mass (a point within a cell of it in x and y); the load's range reaches
    past the cavity. By symmetry the same holds for the y-load."""
    near = x[x[:, 0] < h, 1]
    got = 0.0
    for j in range(int((a + h) / h) + 1):
        y = j * h
        share = 0.5 * h if j == 0 else h
        if not np.any(np.abs(near - y) < h):
            got += share
    return got / a


def measure(h5, cyl, ring_r0=(1.5, 2.0)):
    """Frame times, pressures, cavity radii and the ring's mean radial displacement
    measured and after Lame (the elastic check) from a run's frames, and the fraction of
    the pressure's resultant that the surface loads put on free nodes (load_fraction).
    The ring: the points whose initial radius lies in ring_r0 (times a0)."""
    h = run_h(h5)
    ts, ps, aa, um, ul, fx = [], [], [], [], [], []
    with dpmpm.open_run(h5) as run:
        ring = None
        for fr in run.frames:
            sol = fr["solid"]
            x, u, ids = sol["x"][:, :2], sol["displacement"][:, :2], sol["id"]
            order = np.argsort(ids)
            x, u = x[order], u[order]
            x0 = x - u
            r0 = np.hypot(x0[:, 0], x0[:, 1])
            if ring is None:
                ring = (r0 >= ring_r0[0] * cyl.a0) & (r0 < ring_r0[1] * cyl.a0)
            r = np.hypot(x[:, 0], x[:, 1])
            t = fr.time
            p = float(cyl.pressure(t))
            ts.append(t)
            a = cyl.cavity_radius(r[ring], r0[ring])
            aa.append(a)
            ps.append(p)
            fx.append(cyl.load_fraction(x, h, a))
            um.append(np.mean(r[ring] - r0[ring]))
            ul.append(np.mean(cyl.lame_u(p, r0[ring])))
    return tuple(np.array(v) for v in (ts, ps, aa, um, ul, fx))


def run_h(h5):
    with dpmpm.open_run(h5) as run:
        return float(run.grid.spacing[0])


def compare(cyl, t, p, a, um, ul, fx):
    """The measures of one run: the elastic ring displacement's relative error (mean over
    frames with 0.2 < p/p_y < 0.9), the largest |p - p_ref(a)|/s_u over the frames after
    first yield (from 1.1 p_y on), the last frame's (the end of the hold: the settled
    state), the same with the pressure the free nodes took (p times load_fraction), and
    the radius at the end against a_ref(p_end)."""
    py = cyl.first_yield()
    el = (p > 0.2 * py) & (p < 0.9 * py)
    e_el = float(np.mean(um[el] / ul[el] - 1.0)) if el.any() else float("nan")
    pl = p >= 1.1 * py
    dp = (p - cyl.p_ref(a)) / cyl.su
    return {"elastic": e_el, "dp_max": float(np.nanmax(np.abs(dp[pl]))) if pl.any() else float("nan"),
            "dp_end": float(dp[-1]), "a_end": float(a[-1]), "a_ref_end": cyl.a_ref(p[-1]),
            "p_end": float(p[-1]), "load_end": float(fx[-1]),
            "dp_end_taken": float((p[-1] * fx[-1] - cyl.p_ref(a[-1])) / cyl.su)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--cells-per-radius", type=int, nargs="+", default=[4, 8])
    ap.add_argument("--b0", type=float, default=8.0, help="outer radius over a0")
    ap.add_argument("--geometry", choices=["cylindrical", "spherical"], default="cylindrical")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--workdir", default="out/cavity")
    ap.add_argument("--rerun", action="store_true")
    ap.add_argument("--plot")
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    rows = []
    for n in args.cells_per_radius:
        sc = scene(SCENES[args.geometry], n, args.workdir, b0=args.b0,
                   name=f"cavity_sph_n{n}_b{args.b0:g}" if args.geometry == "spherical" else None)
        try:
            r = dpmpm.simulate(sc, ranks=args.ranks, binary=args.bin, reuse=not args.rerun,
                               progress=sys.stderr.isatty())
            if not r.reused:
                print(f"{sc.name}: exit code 0, {r.wall:.0f} s", flush=True)
        except dpmpm.RunError as e:
            print(f"{sc.name}: exit code {e.status}: {e}", flush=True)
        cyl = (Sphere if args.geometry == "spherical" else Cylinder)(sc, 1.0, args.b0)
        data = measure(sc.output_file(), cyl)
        rows.append((n, cyl, data, compare(cyl, *data)))
    cyl = rows[0][1]
    a_pk, p_pk = cyl.curve()
    k = int(np.nanargmax(p_pk))
    print(f"G/s_u = {cyl.G / cyl.su:.3g}, b0/a0 = {args.b0:g}: first yield p/s_u = "
          f"{cyl.first_yield() / cyl.su:.4f}, peak {p_pk[k] / cyl.su:.4f} at a/a0 = {a_pk[k]:.3f}; "
          f"infinite medium limit {cyl.limit():.4f}")
    print("| h/a0 | elastic ring displacement vs Lame | max abs(p - p_ref(a))/s_u on the ramp "
          "after yield | at the end | a/a0 at the end | closed form a_ref(p_end)/a0 | "
          "load on free nodes / p a at the end | (p taken - p_ref(a))/s_u at the end |")
    print("|---|---|---|---|---|---|---|---|")
    for n, cyl, data, m in rows:
        print(f"| 1/{n} | {m['elastic']:+.2%} | {m['dp_max']:.3f} | {m['dp_end']:+.3f} | "
              f"{m['a_end']:.4f} | {m['a_ref_end']:.4f} | {m['load_end']:.3f} | "
              f"{m['dp_end_taken']:+.3f} |")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        for n, cyl, (t, p, a, um, ul, fx), m in rows:
            ax.plot(a, p / cyl.su, ".-", ms=3, lw=0.8, label=f"dpmpm, h = a0/{n}")
        ax.plot(a_pk, p_pk / cyl.su, "k-", lw=1.0, label=f"closed form, b0 = {args.b0:g} a0")
        ax.plot(a_pk, cyl.p_infinite(a_pk) / cyl.su, "k--", lw=0.8, label="infinite medium")
        ax.axhline(cyl.limit(), color="0.5", ls=":", lw=0.8,
                   label="limit (4/3)(1 + ln(G/s_u))" if cyl.shape == "spherical" else "limit 1 + ln(G/s_u)")
        ax.set_xlim(1.0, max(2.0, max(r[3]["a_end"] for r in rows) + 0.2))
        ax.set_ylim(0.0, 1.1 * cyl.limit())
        ax.set_xlabel("a / a0")
        ax.set_ylabel("p / s_u")
        ax.set_title(f"{cyl.shape.capitalize()} cavity in Tresca soil, G/s_u = {cyl.G / cyl.su:.3g}")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"figure: {args.plot}")


if __name__ == "__main__":
    main()
