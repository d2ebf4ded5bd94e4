#!/usr/bin/env python3
"""Liquefaction of level ground: inputs/liquefaction_1d.nml against element tests.

Usage: scripts/liquefaction_1d.py [FILE.h5] [--dpmpm EXE] [--element EXE] [--ranks N]
                                  [--scale S] [--work DIR] [--png FILE] [--base-record]

Without FILE.h5 the scene is run first (in --work, on --ranks ranks, the base motion scaled
by --scale). For each probe below the surface the table gives the state of its followed
points: sigma'_v0 and u_0 (the first record), the cyclic stress ratio the depth sees (the
largest |tau_xy| / sigma'_v0 over the first cycle of shaking, before the sand softens), the
time and cycles of shaking to r_u >= 0.9, the largest r_u, r_u at the end of shaking and
at the end of the run, and the settlement. Beside it the element tests
(dpmpm_element, cyclic undrained simple shear, stress controlled, the same sand, density,
sigma'_v0 and K0): the cycles to r_u >= 0.9 at the CSR the depth sees, and the CSR that
liquefies the element in the cycles of the base motion (its resistance). Then the peak
surface acceleration in each cycle, and a figure (r_u, surface acceleration, settlement).
--base-record writes the record of the base motion (inputs/liquefaction_base_2hz.txt) and
stops.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

G = 9.81
FREQ, CYCLES, PGA = 2.0, 4, 0.15          # the base motion of the scene
K0, E0 = 0.5, 0.85                        # the scene's sand
RU_LIQ = 0.9                              # liquefied: r_u at least this
CSRS = [0.04, 0.05, 0.06, 0.08, 0.10, 0.12, 0.15, 0.20, 0.25, 0.30]


def write_base_record(path, dt=0.0025):
    """The base velocity v = V sin(2 pi f t) over CYCLES cycles, V = PGA g / (2 pi f): the
    acceleration is PGA g cos(2 pi f t), the displacement V/(2 pi f) (1 - cos) ends at 0."""
    v = PGA * G / (2 * math.pi * FREQ)
    n = int(round(CYCLES / FREQ / dt))
    with open(path, "w") as f:
        f.write(f"# Base velocity of inputs/liquefaction_1d.nml: v = V sin(2 pi f t), f = {FREQ:g} "
                f"Hz, {CYCLES} cycles,\n# V = {PGA:g} g / (2 pi f) = {v:.6f} m/s, so that the "
                f"acceleration is {PGA:g} g cos(2 pi f t);\n# {1000 * dt:g} ms samples; at rest "
                "after the last. Written by scripts/liquefaction_1d.py.\n")
        for i in range(n + 1):
            f.write(f"{i * dt:.4f} {v * math.sin(2 * math.pi * FREQ * i * dt) if i < n else 0.0:.9e}\n")


def run_scene(exe, ranks, scale, work):
    """Run the scene in work (its base record by absolute path); the output file."""
    os.makedirs(work, exist_ok=True)
    text = open(os.path.join(ROOT, "inputs", "liquefaction_1d.nml")).read()
    rec = os.path.join(ROOT, "inputs", "liquefaction_base_2hz.txt")
    text = text.replace("file_x = 'liquefaction_base_2hz.txt'",
                        f"file_x = '{rec}', scale = {scale!r}, 1.0, 1.0")
    scene = os.path.join(work, "liquefaction_1d.nml")
    with open(scene, "w") as f:
        f.write(text)
    cmd = [exe, scene] if ranks == 1 else ["mpiexec", "--oversubscribe", "-n", str(ranks), exe, scene]
    subprocess.run(cmd, cwd=work, check=True, stdout=subprocess.DEVNULL)
    return os.path.join(work, "out", "liquefaction_1d.h5")


def element_cycles(exe, sv0, csr, work, cycles=12):
    """Cycles to r_u >= RU_LIQ (None: not in `cycles`) of the element at sigma'_v0, CSR."""
    name = os.path.join(work, f"el_{sv0:.0f}_{csr:.3f}")
    with open(name + ".nml", "w") as f:
        f.write(f"""&material model = 'sanisand', critical_state_ratio = 1.25, void_ratio = {E0},
          poisson_ratio = 0.05 /
&element path = 'simple_shear_undrained', control = 'stress', k0 = {K0},
         p0 = {float(sv0 * (1 + 2 * K0) / 3)!r}, cycles = {cycles},
         amplitude = {float(csr * sv0)!r},
         steps = 200, void_ratio = {E0}, tolerance = 1.0e-6, output = '{name}.h5' /
""")
    subprocess.run([exe, name + ".nml"], check=True, stdout=subprocess.DEVNULL)
    with h5py.File(name + ".h5", "r") as f:
        e = f["element"]
        ru = e["excess_pore_pressure"][...] / sv0
        hit = np.nonzero(ru >= RU_LIQ)[0]
        return float(e["cycle"][hit[0]]) if hit.size else None


def resistance(table, n):
    """The CSR at which the element liquefies in n cycles: log N linear in CSR between the
    two tested ratios around it (None outside the tested range)."""
    pts = [(c, m) for c, m in table if m is not None]
    for (c1, n1), (c2, n2) in zip(pts, pts[1:]):
        if n1 >= n >= n2 and n1 > n2:
            w = (math.log(n1) - math.log(n)) / (math.log(n1) - math.log(n2))
            return c1 + w * (c2 - c1)
    return None


def show(x, fmt):
    """x in fmt, or '-' (None) as wide."""
    if x is not None:
        return fmt % x
    width = int(fmt[1:].split(".")[0].rstrip("sd") or 0)
    return "-".rjust(width)


def read_probes(path):
    with h5py.File(path, "r") as f:
        g = f["probes"]
        t = g["time"][...]
        m, n = len(t), len(g["solid_id"])
        d = np.atleast_2d(g["position"][...]).shape[1]
        return dict(t=t, n=n, sig=g["stress"][...].reshape(m, n, 6),
                    pw=g["pore_pressure"][...].reshape(m, n),
                    acc=g["acceleration"][...].reshape(m, n, d),
                    disp=g["displacement"][...].reshape(m, n, d),
                    place=g["solid_position"][...], node=np.atleast_2d(g["position"][...]))


def analyse(path, element_exe, work, png, scale=1.0):
    p = read_probes(path)
    t, n = p["t"], p["n"]
    shake = CYCLES / FREQ
    surface = p["node"][:, -1].max()
    rows = []
    print(f"{path}: {len(t)} records to t = {t[-1]:.2f} s; shaking to {shake:g} s "
          f"({CYCLES} cycles of {FREQ:g} Hz)")
    print(" probe  depth  sigma'_v0   u_0   CSR seen   element N   element CSR   column  "
          "   column   largest  r_u at   r_u at   settle-")
    print("          (m)    (kPa)   (kPa)  (cycle 1)  at that CSR  for N = %d    t(r_u>=.9)  N    r_u   "
          "%4.1f s  %5.1f s  ment (mm)" % (CYCLES, shake, t[-1]))
    for k in range(n):
        sv0 = -p["sig"][0, k, 1]
        depth = surface - p["place"][k, 1]
        ru = (p["pw"][:, k] - p["pw"][0, k]) / sv0
        tau = p["sig"][:, k, 5]
        csr = float(np.abs(tau[t <= 1.0 / FREQ]).max() / sv0)
        hit = np.nonzero(ru >= RU_LIQ)[0]
        tl = float(t[hit[0]]) if hit.size else None
        if element_exe:
            table = [(c, element_cycles(element_exe, sv0, c, work)) for c in CSRS]
            n_el = element_cycles(element_exe, sv0, csr, work)
            crr = resistance(table, CYCLES)
        else:
            table, n_el, crr = [], None, None
        settle = -1000 * p["disp"][-1, k, 1]
        rows.append((k, depth, sv0, csr, n_el, crr, tl, float(ru.max()),
                     float(np.interp(shake, t, ru)), float(ru[-1]), settle, table))
        print(f"{k:5d} {depth:6.2f} {sv0 / 1e3:8.1f} {p['pw'][0, k] / 1e3:7.1f} {csr:9.3f} "
              f"{show(n_el, '%11.2f')} {show(crr, '%12.3f')} {show(tl, '%11.2f')} "
              f"{show(tl * FREQ if tl is not None else None, '%6.2f')} {ru.max():8.3f} "
              f"{rows[-1][8]:8.3f} {ru[-1]:8.3f} {settle:8.2f}")
    if element_exe:
        print(f"element cycles to r_u >= {RU_LIQ} (12 cycles tried; '-' = not reached) at sigma'_v0:")
        print("   CSR " + " ".join(f"{r[2] / 1e3:7.1f}" for r in rows))
        for i, c in enumerate(CSRS):
            print(f" {c:5.2f} " + " ".join(show(r[11][i][1], "%7.2f") for r in rows))
    a = p["acc"][:, int(np.argmax(p["node"][:, -1])), 0]
    peaks = []
    for c in range(int(math.ceil(t[-1] * FREQ))):
        sel = (t > c / FREQ) & (t <= (c + 1) / FREQ)
        peaks.append(float(np.abs(a[sel]).max()) if sel.any() else 0.0)
    print("peak surface acceleration in each cycle of 0.5 s (m/s^2; the base's "
          f"{scale * PGA * G:.3f} while shaken): " + " ".join(f"{x:.3f}" for x in peaks[:12]))
    if png:
        plot(p, rows, png, surface)
    return rows, peaks


def plot(p, rows, png, surface):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = p["t"]
    fig, ax = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for r in rows:
        k = r[0]
        ax[0].plot(t, (p["pw"][:, k] - p["pw"][0, k]) / r[2], lw=0.9, label=f"{r[1]:.2f} m")
        ax[2].plot(t, 1000 * p["disp"][:, k, 1], lw=0.9, label=f"{r[1]:.2f} m")
    k = int(np.argmax(p["node"][:, -1]))
    ax[1].plot(t, p["acc"][:, k, 0] / G, lw=0.6)
    ax[0].set_ylabel("r_u")
    ax[0].legend(fontsize=8, ncol=3, title="depth of the point")
    ax[1].set_ylabel("surface acceleration (g)")
    ax[2].set_ylabel("vertical displacement (mm)")
    ax[2].set_xlabel("time (s)")
    for a in ax:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
    print(f"figure {png}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file", nargs="?", help="an output of the scene (else it is run)")
    ap.add_argument("--dpmpm", default=os.path.join(ROOT, "build", "release", "dpmpm"))
    ap.add_argument("--element", default=os.path.join(ROOT, "build", "release", "dpmpm_element"),
                    help="dpmpm_element ('' = no element tests)")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--scale", type=float, default=1.0, help="factor of the base motion (of "
                    "FILE.h5: the factor it was run with, for the table)")
    ap.add_argument("--work", default=None, help="folder of the run and the element tests")
    ap.add_argument("--png", default="liquefaction_1d.png")
    ap.add_argument("--base-record", action="store_true")
    args = ap.parse_args()
    if args.base_record:
        write_base_record(os.path.join(ROOT, "inputs", "liquefaction_base_2hz.txt"))
        return 0
    work = args.work or tempfile.mkdtemp(prefix="liquefaction_1d_")
    os.makedirs(work, exist_ok=True)
    path = args.file or run_scene(os.path.abspath(args.dpmpm), args.ranks, args.scale, work)
    analyse(path, args.element and os.path.abspath(args.element), work, args.png, args.scale)
    return 0


if __name__ == "__main__":
    sys.exit(main())
