#!/usr/bin/env python3
"""Discharge of a flat-bottomed 2D silo through an orifice, against Beverloo's law.

Builds the silo of inputs/silo_mu_i_2d.nml (width --silo-width, filled to --fill, mu(I)
glass beads of d = 1 mm, fixed or rough side walls, a fixed base with an opening of width W
at its middle) for each orifice width of --widths (in cells, even, so that the opening is
centred on a node and frees W/h - 1 nodes), runs it, and measures the discharge rate Q
(kg/s per metre of depth) as the slope of /diagnostics/outflow_mass over the steady part
(--fit-from to the end; its error: the difference of the slopes over the two halves of that
part). Then fits Beverloo's 2D law Q = C rho_b sqrt(g) (W - k d)^(3/2) through
Q^(2/3) = a (W - k d), a straight line in W, and prints C and k with their standard errors.

    python3 scripts/silo_study.py --bin build/release/dpmpm --workdir out/silo \\
        [--cell 0.005] [--widths 2 4 6 8] [--t-end 1.0] [--fit-from 0.4] [--ranks 1] \\
        [--shape linear] [--walls fixed|rough] [--plot silo_study.png]

With --empty the run goes on to --t-end with the whole fill: the silo empties and the
last grains come to rest on the base beside the orifice (scripts/silo_study.py --empty
--t-end 8 ...); the table then says how much stayed, how far the points moved over the
last 0.5 s, the energy balance and the run monitor.
"""
import argparse
import os
import re
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
G = 9.81
D = 1.0e-3          # grain diameter (m)
RHO_B = 1500.0      # bulk density (kg/m^3)

#: the &shape groups an opening accepts (linear grid functions, projected velocities)
SHAPES = {
    "linear": "kernel = 'linear'",
    "linear_gauss1": "kernel = 'linear', quadrature = 'gauss', gauss_points = 1, "
                     "field_kernel = 'linear', field_radius = 0.75",
    "linear_gauss2": "kernel = 'linear', quadrature = 'gauss', gauss_points = 2, "
                     "field_kernel = 'wendland_c2', field_radius = 2.0",
}


def scene(name, cell, w_cells, t_end, shape, walls, silo_width, fill, out, diag_every,
          checkpoint_every=0):
    """The namelist text of the silo with an orifice of w_cells cells."""
    nx = int(round(silo_width/cell))
    ny = int(round((fill + 2*cell)/cell))
    w = w_cells*cell
    lo, hi = 0.5*silo_width - 0.5*w, 0.5*silo_width + 0.5*w
    if walls == "fixed":
        side = "condition = 'fixed'"
    else:
        side = "condition = 'roller', friction = 0.38, lift_off = .false."
    ckpt = f"\n  checkpoint_every = {checkpoint_every}" if checkpoint_every else ""
    return f"""&run
  name = '{name}'
  t_end = {t_end}
  cfl = 0.5
  flip = 1.0
  gravity = 0.0, -9.81, 0.0
/
&grid
  ndim = 2
  ncells = {nx}, {ny}
  length = {nx*cell!r}, {ny*cell!r}
/
&shape {SHAPES[shape]} /
&material
  id = 1
  model = 'mu_i'
  density = 1500.0
  grain_density = 2500.0
  youngs_modulus = 1.0e6
  poisson_ratio = 0.3
  mu_s = 0.38
  mu_2 = 0.64
  i_0 = 0.279
  grain_diameter = 1.0e-3
  max_dilation = 2.0
/
&region
  lo = 0.0, 0.0
  hi = {silo_width!r}, {fill!r}
  material = 1
  ppc = 2
  geostatic = .true.
  k0 = 0.6448
/
&boundary face = 'x-', {side} /
&boundary face = 'x+', {side} /
&boundary face = 'y-', condition = 'fixed', opening_lo = {lo!r}, 0.0, opening_hi = {hi!r}, 0.0 /
&output
  dir = '{out}'
  frame_interval = 0.5
  diag_every = {diag_every}{ckpt}
/
"""


def run(binary, nml, ranks, log):
    """Run dpmpm on nml with ranks MPI ranks; the exit code and the wall time."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = [binary, nml]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(ranks)] + cmd
    t0 = time.time()
    with open(log, "w") as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT, env=env)
    return rc, time.time() - t0


def rate(t, m, t0):
    """Slope of m(t) over t >= t0 (least squares), and the difference of the slopes over
    the two halves of that part (the unsteadiness of the rate)."""
    sel = t >= t0
    ts, ms = t[sel], m[sel]
    q = np.polyfit(ts, ms, 1)[0]
    half = len(ts)//2
    q1 = np.polyfit(ts[:half], ms[:half], 1)[0]
    q2 = np.polyfit(ts[half:], ms[half:], 1)[0]
    return q, abs(q2 - q1)


def beverloo_fit(w, q):
    """C and k of Q = C rho_b sqrt(g) (W - k d)^(3/2), fitted as Q^(2/3) = a W + b, with
    their standard errors (from the covariance of a and b)."""
    y = q**(2.0/3.0)
    (a, b), cov = np.polyfit(w, y, 1, cov=True) if len(w) > 2 else (np.polyfit(w, y, 1),
                                                                      np.zeros((2, 2)))
    c = a**1.5/(RHO_B*np.sqrt(G))
    k = -b/(a*D)
    sa, sb = np.sqrt(cov[0, 0]), np.sqrt(cov[1, 1])
    dc = 1.5*a**0.5*sa/(RHO_B*np.sqrt(G))
    dk = np.sqrt((sb/(a*D))**2 + (b*sa/(a*a*D))**2)
    return c, dc, k, dk


def log_values(log):
    """From the log: the energy balance, the monitor's ratio and balance error, the points
    that left, warnings."""
    text = open(log).read()
    out = {}
    m = re.search(r"energy balance: largest change / largest kinetic \+ stored energy\s+(\S+)", text)
    out["balance"] = float(m.group(1)) if m else float("nan")
    m = re.search(r"\(work \+ initial\)\s+(\S+), largest balance error\s+(\S+)", text)
    out["mon_ratio"], out["mon_balance"] = (float(m.group(1)), float(m.group(2))) if m else (
        float("nan"), float("nan"))
    m = re.search(r"points that left through openings(?: \(since this run or restart began\))?: (\d+)", text)
    out["left"] = int(m.group(1)) if m else 0
    out["warnings"] = len(re.findall(r"warning", text, flags=re.IGNORECASE))
    out["done"] = "dpmpm: done" in text
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--workdir", default="out/silo")
    ap.add_argument("--cell", type=float, default=0.005)
    ap.add_argument("--widths", type=int, nargs="+", default=[2, 4, 6, 8],
                    help="orifice widths in cells (even)")
    ap.add_argument("--silo-width", type=float, default=0.2)
    ap.add_argument("--fill", type=float, default=0.4)
    ap.add_argument("--t-end", type=float, default=1.0)
    ap.add_argument("--fit-from", type=float, default=0.4)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1])
    ap.add_argument("--shapes", nargs="+", default=["linear"], choices=list(SHAPES))
    ap.add_argument("--walls", default="fixed", choices=["fixed", "rough"])
    ap.add_argument("--empty", action="store_true",
                    help="measure the end state (a run to empty and beyond) instead of the rate")
    ap.add_argument("--diag-every", type=int, default=10)
    ap.add_argument("--plot", default="")
    args = ap.parse_args()
    import h5py
    workdir = os.path.abspath(args.workdir)
    os.makedirs(workdir, exist_ok=True)
    rows = []
    for shape in args.shapes:
        for ranks in args.ranks:
            for wc in args.widths:
                if wc % 2:
                    sys.exit("--widths: even numbers of cells only (the opening centred on a node)")
                name = (f"silo_h{args.cell*1000:g}mm_w{wc}_{shape}_{args.walls}_np{ranks}"
                        f"_t{args.t_end:g}")
                nml = os.path.join(workdir, name + ".nml")
                h5 = os.path.join(workdir, name + ".h5")
                log = os.path.join(workdir, name + ".log")
                with open(nml, "w") as f:
                    f.write(scene(name, args.cell, wc, args.t_end, shape, args.walls,
                                  args.silo_width, args.fill, workdir, args.diag_every))
                wall = float("nan")
                if not (os.path.exists(h5) and os.path.exists(log) and log_values(log)["done"]):
                    rc, wall = run(args.bin, nml, ranks, log)
                    print(f"{name}: exit code {rc}, {wall:.0f} s", flush=True)
                lv = log_values(log)
                if not os.path.exists(h5):
                    continue
                with h5py.File(h5, "r") as f:
                    d = f["diagnostics"]
                    t = d["time"][:]
                    m = d["outflow_mass"][:]
                    total = d["total_mass"][:]
                    ke = d["kinetic_energy"][:]
                    x_last = None
                    frames = sorted(f["frames"].keys())
                    if args.empty and len(frames) >= 2:
                        def ids_x(fr):
                            g = f["frames"][fr]
                            s = g[[k for k in g.keys() if "solid" in k or k == "points"][0]]
                            return s["id"][:], s["x"][:]
                        i1, x1 = ids_x(frames[-1])
                        i0, x0 = ids_x(frames[-2])
                        common, a1, a0 = np.intersect1d(i1, i0, return_indices=True)
                        x_last = np.linalg.norm(x1[a1] - x0[a0], axis=-1) if len(common) else []
                w = wc*args.cell
                row = dict(shape=shape, ranks=ranks, wc=wc, w=w, t=t[-1], wall=wall, **lv,
                           out=m[-1], left_mass=total[-1], ke_end=ke[-1], ke_peak=ke.max())
                if not args.empty:
                    row["q"], row["dq"] = rate(t, m, args.fit_from)
                if x_last is not None:
                    row["moved_max"] = float(np.max(x_last)) if len(x_last) else 0.0
                    row["moved_n"] = int(np.sum(np.asarray(x_last) > 1.0e-3))
                rows.append(row)
    if args.empty:
        print("| shape | ranks | W/d | t (s) | mass out | mass left | points left the grid | "
              "KE end / peak | largest move over the last 0.5 s (m), points > 1 mm | "
              "energy balance | monitor ratio, balance | warnings |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for r in rows:
            print(f"| {r['shape']} | {r['ranks']} | {r['w']/D:.0f} | {r['t']:.2f} | "
                  f"{r['out']:.3f} | {r['left_mass']:.3f} | {r['left']} | "
                  f"{r['ke_end']/r['ke_peak']:.1e} | {r.get('moved_max', float('nan')):.1e}, "
                  f"{r.get('moved_n', -1)} | {r['balance']:.1e} | {r['mon_ratio']:.3f}, "
                  f"{r['mon_balance']:.1e} | {r['warnings']} |")
        return 0
    print("| shape | ranks | W (mm) | W/d | Q (kg/s/m) | unsteadiness | Q/(rho_b sqrt(g) W^1.5) "
          "| energy balance | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['shape']} | {r['ranks']} | {r['w']*1000:.0f} | {r['w']/D:.0f} | "
              f"{r['q']:.4f} | {r['dq']:.4f} | {r['q']/(RHO_B*np.sqrt(G)*r['w']**1.5):.3f} | "
              f"{r['balance']:.1e} | {r['wall']:.0f} |")
    groups = sorted({(r["shape"], r["ranks"]) for r in rows})
    for shape, ranks in groups:
        sel = [r for r in rows if r["shape"] == shape and r["ranks"] == ranks]
        if len(sel) < 2:
            continue
        w = np.array([r["w"] for r in sel])
        q = np.array([r["q"] for r in sel])
        c, dc, k, dk = beverloo_fit(w, q)
        print(f"Beverloo fit ({shape}, {ranks} ranks, h = {args.cell*1000:g} mm): "
              f"C = {c:.3f} +- {dc:.3f}, k = {k:.2f} +- {dk:.2f}")
    if args.plot and rows:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 4))
        for shape, ranks in groups:
            sel = [r for r in rows if r["shape"] == shape and r["ranks"] == ranks]
            w = np.array([r["w"] for r in sel])
            q = np.array([r["q"] for r in sel])
            ax.plot(w/D, q**(2/3), "o", label=f"{shape}, h = {args.cell*1000:g} mm")
            if len(sel) >= 2:
                a, b = np.polyfit(w, q**(2/3), 1)
                ww = np.linspace(0, w.max()*1.1, 50)
                ax.plot(ww/D, a*ww + b, "-", lw=0.8)
        ax.set_xlabel("W/d")
        ax.set_ylabel("Q^(2/3)  ((kg/s/m)^(2/3))")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
