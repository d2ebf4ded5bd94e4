#!/usr/bin/env python3
"""The site-response layer on a compliant base: inputs/site_response_1d_compliant.nml (the
10 m layer of site_response_1d.nml on rock of 2500 kg/m^3 and 400 m/s, the Ricker record as
the outcrop motion) run by dpmpm on the given ranks; the probe's surface velocity against
the layer's transfer function on an elastic half-space driven by the outcrop motion,

    V_surface / V_outcrop = 1 / (cos(w H/c) + i a sin(w H/c)),   a = rho c / (rho_r c_r),

(Kramer 1996, ch. 7; doc/theory.md 6.6), computed here with numpy's FFT; and the
ring-down, the largest surface velocity after 0.9 s, which the base's radiation sets
(each return reflected by (1 - a)/(1 + a)). Bounds: doc/verification.md,
"Site response on a compliant base".

    check_site_response_compliant.py <dpmpm> <mpiexec> <nranks> <scene.nml> <work dir>
"""
import os
import re
import sys

import h5py
import numpy as np

from check_site_response import finish, read_at2, run_scene

H, C = 10.0, 100.0
RHO, RHO_R, C_R = 2000.0, 2500.0, 400.0


def surface_velocity(dt, vout, alpha):
    """Surface velocity for the outcrop velocity vout sampled every dt from rest: the
    transfer function above, on a record padded with zeros to 8 times its length (the
    layer rings down by radiation into the rock; its residue at the end of the padding is
    below 1e-10 of the peak)."""
    n = len(vout)
    nfft = 1 << (8 * n - 1).bit_length()
    x = np.zeros(nfft)
    x[:n] = vout
    w = 2.0 * np.pi * np.fft.rfftfreq(nfft, dt)
    kh = w * H / C
    y = np.fft.irfft(np.fft.rfft(x) / (np.cos(kh) + 1j * alpha * np.sin(kh)), nfft)
    return y[:n]


def main():
    exe, mpiexec, nranks, scene, work = sys.argv[1:6]
    if not run_scene(exe, mpiexec, nranks, scene, work):
        return 1
    name = re.search(r"name\s*=\s*'([^']+)'", open(scene).read()).group(1)
    with h5py.File(os.path.join(work, name + ".h5"), "r") as f:
        t = f["probes/time"][...]
        v = f["probes/velocity"][:, 0]
    alpha = RHO * C / (RHO_R * C_R)
    # the outcrop velocity as the code takes it: the record by the trapezoid rule
    tr, ar = read_at2(os.path.join(os.path.dirname(scene), "ricker_5hz.AT2"))
    vr = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(tr) * (ar[1:] + ar[:-1]))])
    dt = 1.0e-4
    tu = dt * np.arange(int(t[-1] / dt) + 2)
    vout = np.interp(tu, tr, vr, left=0.0, right=vr[-1])
    vs = surface_velocity(dt, vout, alpha)
    vref = np.interp(t, tu, vs)
    e_v = np.sqrt(np.mean((v - vref) ** 2)) / np.abs(vref).max()
    e_peak = abs(np.abs(v).max() / np.abs(vref).max() - 1.0)
    # the ring-down: what is left in the layer late in the run (on a rigid base the layer
    # would ring on undamped; here the base lets each return out but a share (1 - a)/(1 + a))
    late = t > 0.9
    left = np.abs(v[late]).max() / np.abs(vref).max()
    left_ref = np.abs(vref[late]).max() / np.abs(vref).max()
    print(f"{nranks} ranks: impedance ratio {alpha:.3f}; RMS error of the surface velocity "
          f"{e_v:.3e} of its peak, peak {e_peak:.3e}; largest surface velocity after 0.9 s "
          f"{left:.4f} of the peak (transfer function: {left_ref:.4f})")
    fails = []
    # bounds: measured + 50 % (doc/verification.md)
    for name, val, bound in (("velocity", e_v, BOUND_V), ("peak", e_peak, BOUND_PEAK)):
        if not val <= bound:
            fails.append(f"{name} error {val:.3e} above {bound:.1e}")
    if not abs(left / left_ref - 1.0) <= BOUND_LATE:
        fails.append(f"late surface velocity {left:.4f} against {left_ref:.4f}")
    return finish(fails)


BOUND_V, BOUND_PEAK, BOUND_LATE = 1.7e-3, 1.0e-3, 1.0e-2

if __name__ == "__main__":
    sys.exit(main())
