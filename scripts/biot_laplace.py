#!/usr/bin/env python3
"""The 1D saturated column under a step load (doc/theory.md 2.7 and 9.2, algorithm A), in
numpy, at any depths: a reference written apart from src/verify/dpmpm_biot_column.f90, so
that a study can compare the points of a run at their own depths and check the Fortran one.

Column 0 <= z <= L, z down from the loaded, drained top: sigma(0, t) = -q H(t), p(0, t) = 0;
bottom fixed and impermeable. In the Laplace domain the velocities V = (V_s, V_f) solve
K V'' = (s^2 diag(m_s, m_f) + s Q [[1, -1], [-1, 1]]) V (doc/theory.md 2.8) exactly: two
modes e^{-lambda_j z} down and two e^{-lambda_j (L - z)} up, each reflecting on its own at the
rigid bottom (c_{j+2} = -e^{-lambda_j L} c_j), the two top conditions a 2 x 2 system. Time
signal: Fourier series on the Bromwich line s_k = alpha + i k 2 pi / T (Durbin), T = 4 t,
alpha T = 18, 2^14 frequencies, Lanczos sigma factors, summed directly at the one time asked.

Usage as a module: fields(col, t, z) -> dict of p, sigma_eff, v_s, v_f at depths z.
Run as a script: compares itself with a run's /verification profiles
(scripts/biot_laplace.py out/x.h5).
"""
import os
import sys

import numpy as np

GRAVITY = 9.81


def column(length, porosity, rho_s, rho_f, e_c, k_f, conductivity, load=1.0):
    """Parameters of a column (SI units; e_c the constrained modulus, k the hydraulic
    conductivity in m/s, load q > 0 compresses the top)."""
    return dict(L=length, n=porosity, rho_s=rho_s, rho_f=rho_f, e_c=e_c, k_f=k_f,
                k=conductivity, q=load)


def wave_speed(col):
    """Undrained speed c_u = sqrt((E_c + K_f/n_f) / rho_sat) (doc/theory.md 2.9)."""
    n = col["n"]
    return np.sqrt((col["e_c"] + col["k_f"] / n) / ((1 - n) * col["rho_s"] + n * col["rho_f"]))


def _modes(col, s):
    """lambda_j (Re > 0) and mode shapes phi_j = (phi_s, phi_f) of K^-1 B(s) for each s."""
    n = col["n"]
    ns = 1.0 - n
    m = col["k_f"] / n
    ms, mf = ns * col["rho_s"], n * col["rho_f"]
    q = n * n * col["rho_f"] * GRAVITY / col["k"]
    k11, k12, k22 = col["e_c"] + ns * ns * m, ns * n * m, n * n * m
    det = k11 * k22 - k12 * k12
    b11, b12, b22 = s * s * ms + s * q, -s * q, s * s * mf + s * q
    # A = K^-1 B, K^-1 = [[k22, -k12], [-k12, k11]] / det
    a11 = (k22 * b11 - k12 * b12) / det
    a12 = (k22 * b12 - k12 * b22) / det
    a21 = (-k12 * b11 + k11 * b12) / det
    a22 = (-k12 * b12 + k11 * b22) / det
    tr, dt = a11 + a22, a11 * a22 - a12 * a21
    root = np.sqrt(tr * tr / 4 - dt)
    mus = (tr / 2 + root, tr / 2 - root)
    out = []
    for mu in mus:
        # Eigenvector (a12, mu - a11) or (mu - a22, a21), whichever is the larger.
        v1 = np.stack([a12, mu - a11])
        v2 = np.stack([mu - a22, a21])
        use2 = np.abs(v2).sum(0) > np.abs(v1).sum(0)
        phi = np.where(use2, v2, v1)
        lam = np.sqrt(mu)
        lam = np.where(lam.real < 0, -lam, lam)
        out.append((lam, phi[0], phi[1]))
    return out, m, n, ns


def laplace_fields(col, s, z):
    """P, Sigma', V_s, V_f at depths z (shape (nz,)) for each s (shape (ns,)): arrays (ns, nz)."""
    ((l1, s1, f1), (l2, s2, f2)), m, n, ns = _modes(col, s)
    e_c, L, q = col["e_c"], col["L"], col["q"]
    # Top: Sigma'(0) = sum_j -E_c lam_j phi_s,j / s d_j = -q / s; P(0) = sum_j M lam_j psi_j / s d_j = 0.
    g1, g2 = -e_c * l1 * s1 / s, -e_c * l2 * s2 / s
    h1, h2 = m * l1 * (ns * s1 + n * f1) / s, m * l2 * (ns * s2 + n * f2) / s
    det = g1 * h2 - g2 * h1
    rhs = -q / s
    d1, d2 = rhs * h2 / det, -rhs * h1 / det
    c1 = d1 / (1 + np.exp(-2 * l1 * L))
    c2 = d2 / (1 + np.exp(-2 * l2 * L))
    zz = z[None, :]
    res = {"p": 0, "sigma_eff": 0, "v_s": 0, "v_f": 0}
    for c, lam, g, h, ps, pf in ((c1, l1, g1, h1, s1, f1), (c2, l2, g2, h2, s2, f2)):
        lam, c = lam[:, None], c[:, None]
        down = np.exp(-lam * zz)
        up = np.exp(-lam * L) * np.exp(-lam * (L - zz))
        res["sigma_eff"] = res["sigma_eff"] + g[:, None] * c * (down + up)
        res["p"] = res["p"] + h[:, None] * c * (down + up)
        res["v_s"] = res["v_s"] + ps[:, None] * c * (down - up)
        res["v_f"] = res["v_f"] + pf[:, None] * c * (down - up)
    return res


def fields(col, t, z, nfreq=2**14, period_factor=4.0, alpha_period=18.0, chunk=256):
    """p, sigma' (tension positive), v_s, v_f at time t > 0 and depths z (clipped to [0, L])."""
    z = np.clip(np.asarray(z, dtype=float), 0.0, col["L"])
    tp = period_factor * t
    alpha = alpha_period / tp
    k = np.arange(nfreq + 1)
    s = alpha + 1j * 2 * np.pi * k / tp
    weight = np.exp(1j * 2 * np.pi * k * t / tp) * np.sinc(k / (nfreq + 1))
    weight[0] = 0.5
    out = {name: np.empty(z.size) for name in ("p", "sigma_eff", "v_s", "v_f")}
    for i in range(0, z.size, chunk):
        f = laplace_fields(col, s, z[i:i + chunk])
        for name in out:
            out[name][i:i + chunk] = 2 * np.exp(alpha * t) / tp * (weight @ f[name]).real
    return out


def from_run(path):
    """The column of a dpmpm run's input (its first saturated &region, its linear elastic
    and its fluid material, as in the inputs w1*.nml) and its last frame time."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "python"))
    import dpmpm
    with dpmpm.open_run(path) as run:
        scene = run.scene
        t = run.frames[-1].time

    def first(value):
        return float(value[0] if isinstance(value, list) else value)
    soil = scene.find("material", model="linear_elastic")[0]
    water = scene.find("material", model="fluid")[0]
    region = scene.find("region", phase="saturated")[0]
    e, nu = float(soil["youngs_modulus"]), float(soil["poisson_ratio"])
    e_c = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    col = column(first(region["hi"]) - first(region["lo"]), float(region["porosity"]),
                 float(soil["density"]), float(water["density"]), e_c,
                 float(water["bulk_modulus"]), float(soil["conductivity"]),
                 first(scene.groups("load")[0]["traction"]))
    return col, t


def main():
    import h5py
    for path in sys.argv[1:]:
        col, t = from_run(path)
        with h5py.File(path, "r") as f:
            v = f["verification"]
            z = v["profile_z"][...]
            ref = {"p": v["profile_p"][...], "sigma_eff": v["profile_sigma_eff"][...]}
        mine = fields(col, t, z)
        front = wave_speed(col) * t
        h = 0.1
        for sel, what in ((z < front - 3 * h, "behind the front - 3 cells"),
                          (z > front + 3 * h, "ahead of the front + 3 cells"),
                          (np.ones_like(z, bool), "everywhere")):
            d = {n: np.abs(mine[n][sel] - ref[n][sel]).max() / col["q"] for n in ref}
            print(f"{path}: t {t:.4g} s, {what}: max |p - p_dpmpm| {d['p']:.2e} q, "
                  f"max |sigma' - sigma'_dpmpm| {d['sigma_eff']:.2e} q")


if __name__ == "__main__":
    main()
