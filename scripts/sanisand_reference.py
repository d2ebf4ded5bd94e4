#!/usr/bin/env python3
"""An independent integration of SANISAND along an undrained triaxial path, against dpmpm.

Usage: scripts/sanisand_reference.py FILE.h5 [--refine K] [--bound B]

FILE.h5 is an element test of dpmpm_element (path = 'triaxial_undrained', strain
control, sense compression) of a 'sanisand' material. This script integrates the same
rate equations (Dafalias & Manzari 2004; doc/theory.md 5.8) written in the scalars of a
triaxial test, p', q, the back-stress ratio a (alpha = sqrt(2/3) a t with the unit axial
tensor t), a_in and the fabric scalar zeta (z = zeta t), by forward Euler in K steps per
step of the file (default 500), with no substeps and no error control: at constant volume
d(eps_q) = d(eps_a) and d(eps_v) = 0; the void ratio follows the volume of the element
driver, whose steps keep it only to first order: (1 + e) is multiplied by
det(I + deps) = (1 + deps_a/2)^2 (1 - deps_a) after each of its steps. Triaxial compression has
cos 3theta = 1, where B - C tr(n^3) = 1 and R' = n + D I/3, so that

    L  = 2G sqrt(3/2) s deps_q / (K_p + 2G - K N D),   s = sign(eta - a), N = sqrt(2/3)(s a + m)
    dq = 3G deps_q - sqrt(6) G s L,   dp = -K L D,   da = (2/3) L h (a^b - a),
    dzeta = -c_z <-L D> (z_max s + zeta),   K_p = (2/3) p h sqrt(2/3) (a^b - a) s,
    h = b0 / max(sqrt(2/3) (a - a_in) s, 1e-10),   D = A0 (1 + <s zeta>) sqrt(2/3) (a^d - a) s,
    a^b,d = s (g M exp(-+ n_b,d psi) - m),   g = 1 (s > 0) or c,

elastic while |eta - a| < m. After each step a plastic point is put back on the yield
surface (a = eta - s m). Forward Euler being first order, the reference is the Richardson
extrapolation 2 x(2K) - x(K) of the runs in K and 2K steps per file step. The largest
differences of q and p' from the file's records, over p'0, are printed, with the size of
the extrapolation (x(2K) - x(K): the error of the run in K steps); the exit status is 1
when the difference exceeds --bound.
"""
import argparse
import math
import sys

import h5py
import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0] + "/python")
from dpmpm import namelist  # noqa: E402

DEFAULTS = {"shear_constant": 125.0, "extension_ratio": 0.712, "csl_lambda": 0.019,
            "csl_void_ratio": 0.934, "csl_exponent": 0.7, "yield_radius": 0.01,
            "hardening_h0": 7.05, "hardening_ch": 0.968, "bounding_nb": 1.1,
            "dilatancy_a0": 0.704, "dilatancy_nd": 3.5, "fabric_zmax": 4.0, "fabric_cz": 600.0,
            "atmospheric_pressure": 101.0e3, "poisson_ratio": 0.3}
S23 = math.sqrt(2.0 / 3.0)


def constants(f):
    """The sanisand constants of the element test's echoed &material."""
    text = f["input"][()]
    text = text.decode() if isinstance(text, bytes) else str(text)
    m = namelist.groups(text, "material")[0]
    if str(m.get("model", [""])[0]).strip().lower() != "sanisand":
        raise SystemExit("the element test's material is not sanisand")
    c = {k: float(m[k][0]) if k in m else v for k, v in DEFAULTS.items()}
    c["M"] = float(m["critical_state_ratio"][0])
    c["e0"] = float(m["void_ratio"][0])
    return c


def integrate(c, p0, eps_end, nsteps, every):
    """p' and q after each of nsteps forward-Euler steps to axial strain eps_end; the void
    ratio follows the element driver's volume, updated after each of its steps (every
    `every` steps here)."""
    p, q, a, a_in, zeta, e = p0, 0.0, 0.0, 0.0, 0.0, c["e0"]
    de = eps_end / nsteps
    big = de * every
    jac = (1.0 + 0.5 * big) ** 2 * (1.0 - big)
    pat = c["atmospheric_pressure"]
    nu = c["poisson_ratio"]
    ps = np.empty(nsteps + 1)
    qs = np.empty(nsteps + 1)
    ps[0], qs[0] = p, q
    for k in range(nsteps):
        g_mod = c["shear_constant"] * pat * (2.97 - e) ** 2 / (1.0 + e) * math.sqrt(p / pat)
        k_mod = 2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu)) * g_mod
        eta = q / p
        lam = 0.0
        if abs(eta - a) >= c["yield_radius"] * (1.0 - 1e-12):
            s = 1.0 if eta >= a else -1.0
            g = 1.0 if s > 0 else c["extension_ratio"]
            psi = e - (c["csl_void_ratio"] - c["csl_lambda"] * (p / pat) ** c["csl_exponent"])
            ab = s * (g * c["M"] * math.exp(-c["bounding_nb"] * psi) - c["yield_radius"])
            ad = s * (g * c["M"] * math.exp(c["dilatancy_nd"] * psi) - c["yield_radius"])
            b0 = c["shear_constant"] * c["hardening_h0"] * (1.0 - c["hardening_ch"] * e) \
                / math.sqrt(p / pat)
            if S23 * (a - a_in) * s < 0.0:
                a_in = a
            h = b0 / max(S23 * (a - a_in) * s, 1e-10)
            kp = 2.0 / 3.0 * p * h * S23 * (ab - a) * s
            dil = c["dilatancy_a0"] * (1.0 + max(s * zeta, 0.0)) * S23 * (ad - a) * s
            nn = S23 * (s * a + c["yield_radius"])
            num = 2.0 * g_mod * math.sqrt(1.5) * s * de
            den = kp + 2.0 * g_mod - k_mod * nn * dil
            if num > 0.0 and den > 0.0:
                lam = num / den
        if lam > 0.0:
            q += 3.0 * g_mod * de - math.sqrt(6.0) * g_mod * s * lam
            p += -k_mod * lam * dil
            a += 2.0 / 3.0 * lam * h * (ab - a)
            zeta += -c["fabric_cz"] * max(-lam * dil, 0.0) * (c["fabric_zmax"] * s + zeta)
            a = q / p - s * c["yield_radius"]
        else:
            q += 3.0 * g_mod * de
        ps[k + 1], qs[k + 1] = p, q
        if (k + 1) % every == 0:
            e = (1.0 + e) * jac - 1.0
    return ps, qs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--refine", type=int, default=500, help="reference steps per file step")
    ap.add_argument("--bound", type=float, default=None,
                    help="largest difference of q and p' over p'0 allowed")
    args = ap.parse_args()
    with h5py.File(args.file, "r") as f:
        c = constants(f)
        el = f["element"]
        p = el["p"][...]
        q = el["q"][...]
        ea = el["axial_strain"][...]
    n = len(p) - 1
    p0 = p[0]
    ref_p, ref_q = integrate(c, p0, ea[-1], n * args.refine, args.refine)
    fine_p, fine_q = integrate(c, p0, ea[-1], 2 * n * args.refine, 2 * args.refine)
    # forward Euler is first order: the Richardson extrapolation 2 fine - coarse is the
    # reference, and the difference of the two its own error (of the coarse one)
    cp, cq = ref_p[::args.refine], ref_q[::args.refine]
    fp, fq = fine_p[::2 * args.refine], fine_q[::2 * args.refine]
    own = max(np.abs(fp - cp).max(), np.abs(fq - cq).max()) / p0
    rp, rq = 2.0 * fp - cp, 2.0 * fq - cq
    diff = max(np.abs(p - rp).max(), np.abs(q - rq).max()) / p0
    print(f"e0 = {c['e0']}, p'0 = {p0:.6g} Pa, eps_a to {ea[-1]:.4g} in {n} steps: "
          f"end p' = {p[-1]:.6g} (reference {rp[-1]:.6g}), q = {q[-1]:.6g} (reference "
          f"{rq[-1]:.6g})")
    print(f"largest |difference| of p', q over p'0: {diff:.3e}; forward Euler's own error "
          f"in {n * args.refine} steps (against {2 * n * args.refine}): {own:.3e}")
    if args.bound is not None and not diff <= args.bound:
        print(f"exceeds the bound {args.bound:.3e}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
