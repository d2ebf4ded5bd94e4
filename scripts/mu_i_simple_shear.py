#!/usr/bin/env python3
"""Drained simple shear of a mu_i material in an element test (dpmpm_element) against the
rheology's closed form.

Reads the element file, takes the constants of the run's mu_i material and the step of
its echoed input, and compares the shear stress of the last half of the path (the steady
state) with mu(I) p', mu(I) = mu_s + (mu_2 - mu_s)/(I_0/I + 1), I = gdot d/sqrt(p'/rho_s)
with gdot the rate of the path's shear strain; prints the largest relative difference and
fails (exit 1) beyond --bound.

    python3 scripts/mu_i_simple_shear.py out/element_mu_i_simple_shear.h5 [--bound 1e-12]
"""
import argparse
import sys

import h5py
import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0] + "/python")
from dpmpm import namelist  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("h5")
    ap.add_argument("--bound", type=float, default=1e-12)
    args = ap.parse_args()
    with h5py.File(args.h5, "r") as f:
        text = f["input"][()]
        text = text.decode() if isinstance(text, bytes) else str(text)
        mat = namelist.groups(text, "material")[0]
        if str(mat["model"][0]).strip().lower() != "mu_i":
            raise SystemExit("the element's material is not mu_i")
        mus, mu2, i0 = (float(mat[k][0]) for k in ("mu_s", "mu_2", "i_0"))
        d = float(mat["grain_diameter"][0])
        rhos = float(mat.get("grain_density", [0.0])[0]) or float(mat["density"][0])
        e = f["element"]
        t, gam, tau, p = (np.asarray(e[k]) for k in ("time", "shear_strain", "shear_stress",
                                                     "p"))
    gdot = np.diff(gam) / np.diff(t)
    half = len(gdot) // 2
    inum = gdot[half:] * d / np.sqrt(p[half + 1:] / rhos)
    ref = (mus + (mu2 - mus) / (i0 / inum + 1.0)) * p[half + 1:]
    err = np.max(np.abs(tau[half + 1:] / ref - 1.0))
    print(f"steady simple shear at I = {inum.mean():.4g}: tau = {tau[-1]:.6g} Pa, "
          f"mu(I) p' = {ref[-1]:.6g} Pa, largest relative difference {err:.2e} "
          f"(bound {args.bound:g})")
    sys.exit(0 if err <= args.bound else 1)


if __name__ == "__main__":
    main()
