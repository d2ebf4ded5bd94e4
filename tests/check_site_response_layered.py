#!/usr/bin/env python3
"""A layered column shaken at its base (inputs/site_response_layered_*.nml): the scene run by
dpmpm on the given ranks, the probe's surface velocity and acceleration and the 5 %-damped
response spectrum of that acceleration against the frequency-domain solution of the layered
column (doc/theory.md 6.10): the propagator matrix of vertically travelling waves, on a rigid
base (the base motion prescribed) or on a compliant base (the rock half-space below, the
record its outcrop motion), applied to the record's spectrum with numpy's FFT. The layers,
the rock and the kind of wave (compression when the column is shaken along its axis, shear
when across) are read from the scene. Before the run the reference is checked on its own:
one layer against the uniform layer's solutions (d'Alembert's sum on the rigid base, the
transfer function 1/(cos kH + i a sin kH) on the compliant one), a layer split in two
against the same layer whole, and the layered column against the exact time-domain solution
of its up- and down-going waves. Bounds: doc/verification.md, "Site response of a layered
column".

    check_site_response_layered.py <dpmpm> <mpiexec> <nranks> <scene.nml> <work dir> [--cells N]
    check_site_response_layered.py --reference-only <scene.nml>
    check_site_response_layered.py --compare <scene.nml> <output.h5> [<record.AT2>]

--cells N runs the scene with N cells over the column's height (the cells kept square and
the column two cells wide) and prints the errors without bounds (the grid study).
--compare prints the errors of a run of the scene made elsewhere (its output file), with
another record in place of the scene's (the long runs of scripts/site_response_hard_cases.py).
"""
import math
import os
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "scripts", "python"))
from dpmpm.motion import response_spectrum  # noqa: E402
from dpmpm.scene import Scene  # noqa: E402

from check_site_response import finish, read_at2, run_scene  # noqa: E402

DT = 1.0e-4                              # the reference's sampling (s)
PERIODS = np.geomspace(0.02, 2.0, 60)    # of the response spectra (s)
SHOWN = (0.05, 0.1, 0.2, 0.5, 1.0)       # periods whose spectral error is printed
F_LOW = 40.0                             # Hz: the acceleration's error below it

# Bounds (measured + 50 %, doc/verification.md): RMS error of the surface velocity, of the
# surface acceleration and of its part below F_LOW over their peaks, largest relative
# difference of the 5 % spectra.
BOUNDS = {
    "site_response_layered_1d_rigid": (1.7e-3, 7.4e-3, 2.8e-3, 2.8e-3),
    "site_response_layered_1d_compliant": (9.7e-4, 3.9e-3, 8.7e-4, 1.5e-3),
    "site_response_layered_2d_compliant": (6.4e-4, 3.4e-3, 5.6e-4, 1.1e-3),
    "site_response_layered_3d_rigid": (6.7e-3, 1.27e-2, 1.16e-2, 1.19e-2),
}


# ------------------------------------------------------------------ the column from the scene
def _floats(v, n):
    v = v if isinstance(v, list) else [v]
    return [float(x) for x in v][:n]


def column(scene):
    """The column of a scene: a dict with the layers from the base up as (thickness, density,
    modulus), the base ('rigid' or 'compliant'), the rock's (density, modulus) on a compliant
    base, Rayleigh's alpha and beta, and the kind of wave. The modulus is the constrained one
    E (1 - nu)/((1 + nu)(1 - 2 nu)) when the column is shaken along its axis (the last axis
    of the grid), the shear modulus E/(2 (1 + nu)) when across."""
    ndim = int(scene["grid"]["ndim"])
    up = ndim - 1
    motion = scene["motion"]
    axes = [a for a in "xyz"[:ndim] if str(motion.get("file_" + a, "")).strip()]
    if len(axes) != 1:
        raise ValueError("the layered check needs the motion along one axis")
    along = "xyz".index(axes[0]) == up
    mats = {int(m["id"]): m for m in scene.groups("material")}

    def modulus(m):
        e, nu = float(m["youngs_modulus"]), float(m.get("poisson_ratio", 0.0))
        if along:
            return e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
        return e / (2 * (1 + nu))

    layers = []
    for r in scene.groups("region"):
        lo, hi = _floats(r["lo"], ndim)[up], _floats(r["hi"], ndim)[up]
        m = mats[int(r["material"])]
        layers.append((lo, hi - lo, float(m["density"]), modulus(m)))
    layers.sort()
    for (lo0, h0, _, _), (lo1, _, _, _) in zip(layers, layers[1:]):
        if abs(lo0 + h0 - lo1) > 1e-9:
            raise ValueError("the regions must stack without gaps")
    base_face = str(motion["base"]).strip()
    [bc] = scene.find("boundary", face=base_face)
    cond = str(bc["condition"]).strip()
    col = dict(layers=[lay[1:] for lay in layers], along=along, top=layers[-1][0] + layers[-1][1])
    if cond == "fixed":
        col.update(base="rigid", rock=None)
    elif cond == "absorbing":
        m = mats[int(bc["material"])]
        col.update(base="compliant", rock=(float(m["density"]), modulus(m)))
    else:
        raise ValueError(f"base face {base_face} is {cond}: neither fixed nor absorbing")
    run = scene["run"]
    xi = float(run.get("rayleigh_ratio", 0.0))
    if xi > 0:
        w1, w2 = 2 * math.pi * float(run["rayleigh_f1"]), 2 * math.pi * float(run["rayleigh_f2"])
        col.update(alpha=2 * xi * w1 * w2 / (w1 + w2), beta=2 * xi / (w1 + w2))
    else:
        col.update(alpha=float(run.get("rayleigh_alpha", 0.0)),
                   beta=float(run.get("rayleigh_beta", 0.0)))
    return col


# ------------------------------------------------------------- the frequency-domain solution
def propagator(s, layers, alpha=0.0, beta=0.0):
    """The 2 x 2 propagator P(s) of the displacement and the stress, [U, tau](top) =
    P [U, tau](base), through the layers from the base up (thickness, density, modulus), on
    the Laplace variable s (an array): each layer's matrix [[cosh kh, sinh kh/(G* k)],
    [G* k sinh kh, cosh kh]], G* = G (1 + s beta), k^2 = rho s (s + alpha)/G*."""
    p = np.array([[np.ones_like(s), np.zeros_like(s)], [np.zeros_like(s), np.ones_like(s)]])
    for h, rho, g in layers:
        gs = g * (1.0 + s * beta)
        k = np.sqrt(rho * s * (s + alpha) / gs)
        k = np.where(k.real < 0, -k, k)
        ch, sh = np.cosh(k * h), np.sinh(k * h)
        layer = np.array([[ch, sh / (gs * k)], [gs * k * sh, ch]])
        p = np.einsum("ij...,jk...->ik...", layer, p)
    return p


def transfer(s, col):
    """Surface motion over the input motion: on a rigid base over the base's motion,
    1 - s/(s + alpha) (1 - 1/P22) (the motion relative to the base obeys the homogeneous
    problem plus the constant -s/(s + alpha) U_b, as (4.7c)); on a compliant base over the
    outcrop's, Z_r s/(P21 + Z_r s P22), Z_r = rho_r c_r the rock's impedance."""
    p = propagator(s, col["layers"], col["alpha"], col["beta"])
    if col["base"] == "rigid":
        return 1.0 - s / (s + col["alpha"]) * (1.0 - 1.0 / p[1, 1])
    if col["alpha"] or col["beta"]:
        raise ValueError("damping on a compliant base is not in this reference")
    rho_r, g_r = col["rock"]
    z = math.sqrt(rho_r * g_r) * s
    return z / (p[1, 0] + z * p[1, 1])


def surface_velocity(dt, vin, col, tf=transfer):
    """The surface velocity for the input velocity vin (sampled every dt, from rest): the
    transfer function on the complex frequency s = a + i omega, the samples weighted by
    exp(-a t) before the transform and by exp(a t) after (a = ln(1e8)/T_fft, the record
    zero-padded to at least four times its length), so that the poles of an undamped
    column on a rigid base leave the axis and what the periodic transform folds back is
    1e-8 of itself."""
    n = len(vin)
    nfft = 1 << (4 * n - 1).bit_length()
    a = math.log(1e8) / (nfft * dt)
    t = dt * np.arange(n)
    x = np.zeros(nfft)
    x[:n] = vin * np.exp(-a * t)
    s = a + 2j * np.pi * np.fft.rfftfreq(nfft, dt)
    return np.fft.irfft(np.fft.rfft(x) * tf(s, col), nfft)[:n] * np.exp(a * t)


# ------------------------------------------------------------- independent references
def dalembert(t, tb, vb, h, c):
    """The undamped uniform layer on a rigid base: 2 sum (-1)^n v_b(t - (2n + 1) H/c)."""
    out = np.zeros_like(t)
    for n in range(int(t[-1] / (2 * h / c)) + 2):
        out += 2.0 * (-1) ** n * np.interp(t - (2 * n + 1) * h / c, tb, vb, left=0.0, right=vb[-1])
    return out


def uniform_compliant(dt, vout, h, c, a):
    """The uniform layer on an elastic half-space, 1/(cos kH + i a sin kH) on the real
    frequency, the record zero-padded to 32 times its length (it rings down by radiation)."""
    n = len(vout)
    nfft = 1 << (32 * n - 1).bit_length()
    x = np.zeros(nfft)
    x[:n] = vout
    kh = 2.0 * np.pi * np.fft.rfftfreq(nfft, dt) * h / c
    return np.fft.irfft(np.fft.rfft(x) / (np.cos(kh) + 1j * a * np.sin(kh)), nfft)[:n]


def waves(t, tin, vin, col):
    """The exact surface velocity of an undamped layered column in the time domain, by its
    up- and down-going waves: each layer's travel time a whole number of steps tau, a wave
    velocity f (up) and g (down) in each layer (v = f + g, stress Z (g - f)); at each
    interface the waves leaving are f2 = (2 Z1 f1 + (Z2 - Z1) g2)/(Z1 + Z2), g1 = f2 + g2 - f1
    (velocity and stress continuous); the free surface sends g = f back and moves at 2 f;
    the rigid base sends f = v_b - g, the rock sends f = v_out/2 up from below. Exact at the
    times t0 + j tau for every offset t0: the times t are taken as t0 + j tau."""
    times = [h / math.sqrt(g / rho) for h, rho, g in col["layers"]]
    tau = None
    for m in range(1, 400):
        cand = min(times) / m
        n = [round(x / cand) for x in times]
        if all(abs(x / cand - k) < 1e-9 * k for x, k in zip(times, n)):
            tau = cand
            break
    if tau is None:
        raise ValueError("the layers' travel times are not commensurate")
    z = [math.sqrt(rho * g) for _, rho, g in col["layers"]]
    nsteps = [round(x / tau) for x in times]
    offsets = t[t < tau]
    nj = int(t[-1] / tau) + 2
    # delay lines: up[j][k] the up-going wave entering layer j at its base k steps ago
    up = [np.zeros((nk, len(offsets))) for nk in nsteps]
    down = [np.zeros((nk, len(offsets))) for nk in nsteps]
    surf = np.zeros((nj, len(offsets)))
    inp = np.interp(offsets[None, :] + tau * np.arange(nj)[:, None], tin, vin, left=0.0,
                    right=vin[-1])
    if col["base"] == "compliant":
        zb = math.sqrt(col["rock"][0] * col["rock"][1])
    nl = len(nsteps)
    for j in range(nj):
        # waves arriving now: at the top of layer l the up-wave that entered its base nsteps
        # ago, at the base of layer l the down-wave that entered its top nsteps ago
        f_top = [up[l][-1] for l in range(nl)]
        g_bot = [down[l][-1] for l in range(nl)]
        f_new = [None] * nl
        g_new = [None] * nl
        g_new[nl - 1] = f_top[nl - 1]                      # the free surface
        surf[j] = 2.0 * f_top[nl - 1]
        for l in range(nl - 1):                            # interface between l and l + 1
            z1, z2 = z[l], z[l + 1]
            f2 = (2 * z1 * f_top[l] + (z2 - z1) * g_bot[l + 1]) / (z1 + z2)
            f_new[l + 1] = f2
            g_new[l] = f2 + g_bot[l + 1] - f_top[l]
        if col["base"] == "rigid":
            f_new[0] = inp[j] - g_bot[0]
        else:                                              # the rock: f_r = v_out/2 from below
            z1, z2 = zb, z[0]
            f_new[0] = (2 * z1 * 0.5 * inp[j] + (z2 - z1) * g_bot[0]) / (z1 + z2)
        for l in range(nl):
            up[l] = np.roll(up[l], 1, axis=0)
            up[l][0] = f_new[l]
            down[l] = np.roll(down[l], 1, axis=0)
            down[l][0] = g_new[l]
    # the surface velocity at offset + j tau: a wave entering a layer needs nsteps to cross,
    # so surf[j] is the state at time j tau, with the input taken at the same time
    tt = (offsets[None, :] + tau * np.arange(nj)[:, None]).ravel()
    order = np.argsort(tt)
    return np.interp(t, tt[order], surf.ravel()[order])


def self_checks(col, tin, vin):
    """The reference against the independent solutions; returns the failures."""
    fails = []
    tu = DT * np.arange(int(1.5 / DT) + 1)
    vu = np.interp(tu, tin, vin, left=0.0, right=vin[-1])
    h_all = sum(h for h, _, _ in col["layers"])
    rho, g = col["layers"][-1][1:]
    c = math.sqrt(g / rho)
    one = dict(col, layers=[(h_all, rho, g)], alpha=0.0, beta=0.0)
    split = dict(one, layers=[(0.4 * h_all, rho, g), (0.6 * h_all, rho, g)])
    peak = np.abs(surface_velocity(DT, vu, one)).max()
    checks = []
    if col["base"] == "rigid":
        checks.append(("one layer against d'Alembert's sum",
                       surface_velocity(DT, vu, one), dalembert(tu, tu, vu, h_all, c), 1e-7))
    else:
        a = math.sqrt(rho * g) / math.sqrt(col["rock"][0] * col["rock"][1])
        checks.append(("one layer against 1/(cos kH + i a sin kH)", surface_velocity(DT, vu, one),
                       uniform_compliant(DT, vu, h_all, c, a), 1e-7))
    checks.append(("a layer split in two against it whole", surface_velocity(DT, vu, split),
                   surface_velocity(DT, vu, one), 1e-10))
    undamped = dict(col, alpha=0.0, beta=0.0)
    vl = surface_velocity(DT, vu, undamped)
    checks.append(("the layered column against its up- and down-going waves", vl,
                   waves(tu, tu, vu, undamped), 1e-7))
    for what, x, y, bound in checks:
        scale = np.abs(y).max() if "layered" in what else peak
        err = np.abs(x - y).max() / scale
        print(f"reference: {what}: largest difference {err:.2e} of the peak")
        if not err <= bound:
            fails.append(f"reference: {what}: {err:.2e} above {bound:.0e}")
    return fails


# ------------------------------------------------------------------------ the scene's run
def refined(scene, cells, motion_dir):
    """The scene with `cells` cells over the height of the column (two empty ones above it
    as shipped, in proportion), the cells square, the column two cells wide."""
    s = scene.copy()
    g = s["grid"]
    ndim = int(g["ndim"])
    n = _floats(g["ncells"], ndim)
    ln = _floats(g["length"], ndim)
    col = column(s)
    h = col["top"] / cells
    extra = round((ln[-1] - col["top"]) / (ln[-1] / n[-1]))
    n[-1], ln[-1] = cells + extra, (cells + extra) * h
    for d in range(ndim - 1):
        ln[d] = n[d] * h
    g["ncells"] = [int(x) for x in n] if ndim > 1 else int(n[0])
    g["length"] = ln if ndim > 1 else ln[0]
    for r in s.groups("region"):
        if ndim > 1:
            hi = _floats(r["hi"], ndim)
            for d in range(ndim - 1):
                hi[d] = ln[d]
            r["hi"] = hi
    out = s["output"]
    for d, a in enumerate("xyz"[:ndim - 1]):
        out["probe_" + a] = 0.5 * ln[d]
    for a in "xyz":
        f = str(s["motion"].get("file_" + a, "")).strip()
        if f and not os.path.isabs(f):
            s["motion"]["file_" + a] = os.path.join(motion_dir, f)
    s["run"]["name"] = f"{s.name}_{cells}"
    return s


def motion_axis(scene):
    """The axis ('x', 'y' or 'z') of the scene's motion (the first with a file)."""
    m = scene["motion"]
    return [a for a in "xyz" if str(m.get("file_" + a, "")).strip()][0]


def record(scene, scene_dir, f=None):
    """Times and velocity of the input motion as the code takes it: the record's
    accelerations by the trapezoid rule, linear between samples."""
    m = scene["motion"]
    if f is None:
        f = str(m["file_" + motion_axis(scene)]).strip()
    tr, ar = read_at2(f if os.path.isabs(f) else os.path.join(scene_dir, f))
    vr = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(tr) * (ar[1:] + ar[:-1]))])
    return tr, vr


def compare(h5, col, tin, vin, axis):
    """Errors of the run's surface motion against the reference."""
    with h5py.File(h5, "r") as f:
        t = f["probes/time"][...]
        v = f["probes/velocity"][:, axis]
        acc = f["probes/acceleration"][:, axis]
    tu = DT * np.arange(int(t[-1] / DT) + 2)
    vs = surface_velocity(DT, np.interp(tu, tin, vin, left=0.0, right=vin[-1]), col)
    vref = np.interp(t, tu, vs)
    t0 = np.concatenate([[0.0], t])
    aref = np.diff(np.concatenate([[0.0], vref])) / np.diff(t0)
    e_v = np.sqrt(np.mean((v - vref) ** 2)) / np.abs(vref).max()
    e_a = np.sqrt(np.mean((acc - aref) ** 2)) / np.abs(aref).max()
    au = np.interp(tu, t0, np.concatenate([[0.0], acc]))
    ar = np.interp(tu, t0, np.concatenate([[0.0], aref]))
    # below 40 Hz: above it the acceleration holds the steps of the record's own (constant
    # between its 1 ms samples after the trapezoid rule), which the undamped column keeps and
    # the grid does not resolve
    low = np.fft.rfftfreq(len(tu), DT) < F_LOW
    e_low = (np.sqrt(np.mean(np.fft.irfft(np.fft.rfft(au - ar) * low, len(tu)) ** 2))
             / np.abs(np.fft.irfft(np.fft.rfft(ar) * low, len(tu))).max())
    sa = response_spectrum(DT, au, PERIODS).sa
    sr = response_spectrum(DT, ar, PERIODS).sa
    rel = np.abs(sa / sr - 1.0)
    shown = {p: float(np.interp(math.log(p), np.log(PERIODS), rel)) for p in SHOWN}
    k = int(np.argmax(sr))
    return dict(v=e_v, a=e_a, low=e_low, s=float(rel.max()), shown=shown, peak_T=PERIODS[k],
                peak_sa=sr[k], peak_err=rel[k], vpeak=np.abs(vref).max(), apeak=np.abs(aref).max())


def report(name, nranks, col, e):
    shown = ", ".join(f"{p:g} s {x:.2e}" for p, x in e["shown"].items())
    print(f"{name}, {nranks} ranks ({col['base']} base, {len(col['layers'])} layers, "
          f"{'compression' if col['along'] else 'shear'}): RMS error of the surface velocity "
          f"{e['v']:.3e} of its peak {e['vpeak']:.4e} m/s, of the acceleration {e['a']:.3e} of "
          f"its peak {e['apeak']:.4f} m/s^2 (below {F_LOW:g} Hz {e['low']:.3e}); 5 % spectra: "
          f"largest relative difference {e['s']:.3e}, at the peak (T = {e['peak_T']:.3f} s, "
          f"Sa = {e['peak_sa']:.4f} m/s^2) {e['peak_err']:.2e}; at {shown}")


def main():
    argv = sys.argv[1:]
    if argv and argv[0] == "--compare":
        scene = Scene.read(argv[1])
        col = column(scene)
        tin, vin = record(scene, os.path.dirname(os.path.abspath(argv[1])),
                          argv[3] if len(argv) > 3 else None)
        axis = "xyz".index(motion_axis(scene))
        report(os.path.basename(argv[2]), "-", col, compare(argv[2], col, tin, vin, axis))
        return 0
    if argv and argv[0] == "--reference-only":
        scene = Scene.read(argv[1])
        col = column(scene)
        tin, vin = record(scene, os.path.dirname(os.path.abspath(argv[1])))
        fails = self_checks(col, tin, vin)
        return finish(fails)
    exe, mpiexec, nranks, path, work = argv[:5]
    cells = int(argv[argv.index("--cells") + 1]) if "--cells" in argv else None
    scene_dir = os.path.dirname(os.path.abspath(path))
    scene = Scene.read(path)
    col = column(scene)
    tin, vin = record(scene, scene_dir)
    fails = self_checks(col, tin, vin)
    os.makedirs(work, exist_ok=True)
    if cells is not None:
        scene = refined(scene, cells, scene_dir)
        path = scene.write(os.path.join(work, scene.name + ".nml"))
    if not run_scene(exe, mpiexec, nranks, path, work):
        return 1
    axis = "xyz".index(motion_axis(scene))
    e = compare(os.path.join(work, scene.name + ".h5"), col, tin, vin, axis)
    report(scene.name, nranks, col, e)
    if cells is None:
        bounds = BOUNDS[scene.name]
        for what, val, bound in zip(("velocity", "acceleration", "acceleration below 40 Hz",
                                     "spectrum"), (e["v"], e["a"], e["low"], e["s"]), bounds):
            if bound is None:
                fails.append(f"no bound for {what} of {scene.name}")
            elif not val <= bound:
                fails.append(f"{what} error {val:.3e} above {bound:.1e}")
    return finish(fails)


if __name__ == "__main__":
    sys.exit(main())
