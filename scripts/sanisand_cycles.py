#!/usr/bin/env python3
"""Cycles to liquefaction of cyclic undrained element tests of dpmpm_element.

Usage: scripts/sanisand_cycles.py FILE.h5 [FILE.h5 ...] [--require]

For each file (a cyclic undrained triaxial or simple shear test) prints the cyclic stress
ratio (triaxial: q_amp/(2 p'0); simple shear: tau_amp/sigma'_v0), the cycles done when
the excess pore pressure ratio r_u = u/p'0 (simple shear: u/sigma'_v0) first reaches 0.95,
and when the double-amplitude strain (eps_a, or gamma) over one cycle first reaches 5 %,
with the largest r_u and the largest double-amplitude strain over a cycle. --require: exit 1 unless every file reaches r_u >= 0.95.
"""
import argparse
import sys

import h5py
import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0] + "/python")
from dpmpm import namelist  # noqa: E402


def cycles_to_liquefaction(path):
    """CSR, cycles to r_u >= 0.95 (None if never), cycles to 5 % double amplitude, max r_u."""
    with h5py.File(path, "r") as f:
        text = f["input"][()]
        text = text.decode() if isinstance(text, bytes) else str(text)
        el = namelist.groups(text, "element")[0]
        kind = str(el["path"][0]).strip().lower()
        amp = float(el["amplitude"][0])
        steps = int(el["steps"][0])
        e = f["element"]
        cyc = e["cycle"][...]
        u = e["excess_pore_pressure"][...]
        if kind.startswith("simple_shear"):
            ref = -e["stress"][0, 2] if e["stress"].shape[0] == 6 else -e["stress"][0][2]
            strain = e["shear_strain"][...]
            csr = amp / ref
        else:
            ref = e["p"][0]
            strain = e["axial_strain"][...]
            csr = amp / (2.0 * ref)
    ru = u / ref
    hit = np.nonzero(ru >= 0.95)[0]
    n_ru = float(cyc[hit[0]]) if hit.size else None
    # double amplitude: the range of the strain over the last cycle (steps records)
    n_da = None
    da_max = 0.0
    for k in range(steps, len(strain)):
        window = strain[k - steps:k + 1]
        da = window.max() - window.min()
        da_max = max(da_max, da)
        if da >= 0.05 and n_da is None:
            n_da = float(cyc[k])
    return csr, n_ru, n_da, float(ru.max()), da_max


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--require", action="store_true",
                    help="exit 1 unless every file reaches r_u >= 0.95")
    args = ap.parse_args()
    bad = 0
    print(f"{'CSR':>6} {'N (r_u >= 0.95)':>16} {'N (DA 5 %)':>11} {'max r_u':>8} "
          f"{'max DA':>7}  file")
    for path in args.files:
        csr, n_ru, n_da, rmax, da_max = cycles_to_liquefaction(path)
        show = (lambda n: f"{n:.2f}" if n is not None else "-")
        print(f"{csr:6.3f} {show(n_ru):>16} {show(n_da):>11} {rmax:8.3f} {100 * da_max:6.2f}%  "
              f"{path}")
        bad += n_ru is None
    return 1 if args.require and bad else 0


if __name__ == "__main__":
    sys.exit(main())
