#!/usr/bin/env python3
"""The damped site-response scene through the file route: inputs/site_response_1d_damped.nml
(the layer of site_response_1d.nml with Rayleigh damping of 5 % at 2.5 and 12.5 Hz) run by
dpmpm on the given ranks; the probe's surface velocity and acceleration against the
frequency-domain solution of the damped layer, computed here with numpy's FFT apart from
the code's own (doc/theory.md 4.7, eq. 4.7c), and the 5 %-damped response spectra of the
two surface accelerations (dpmpm.motion.response_spectrum). Bounds: doc/verification.md,
"Site response with Rayleigh damping".

    check_site_response_damped.py <dpmpm> <mpiexec> <nranks> <scene.nml> <work dir>
"""
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts", "python"))
from dpmpm.motion import response_spectrum  # noqa: E402

from check_site_response import finish, read_at2, run_scene  # noqa: E402

H, C = 10.0, 100.0
XI, F1, F2 = 0.05, 2.5, 12.5


def damped_surface_velocity(dt, vb, alpha, beta):
    """Surface velocity of the damped layer for the base velocity vb sampled every dt from
    rest: the transfer function 1 - s/(s + alpha) (1 - 1/cosh(kH)), k^2 = s (s + alpha) /
    (C^2 (1 + s beta)), on the complex frequency s = a + i omega (samples weighted by
    exp(-a t), a = ln(1e8)/T_fft, so that the undamped poles leave the axis)."""
    n = len(vb)
    nfft = 1 << (4 * n - 1).bit_length()
    a = math.log(1e8) / (nfft * dt)
    t = dt * np.arange(nfft)
    x = np.zeros(nfft)
    x[:n] = vb * np.exp(-a * t[:n])
    s = a + 2j * np.pi * np.fft.rfftfreq(nfft, dt)
    kh = H / C * np.sqrt(s * (s + alpha) / (1.0 + s * beta))
    kh = np.where(kh.real < 0, -kh, kh)
    sech = 2.0 * np.exp(-kh) / (1.0 + np.exp(-2.0 * kh))
    y = np.fft.irfft(np.fft.rfft(x) * (1.0 - s / (s + alpha) * (1.0 - sech)), nfft)
    return y[:n] * np.exp(a * t[:n])


def main():
    exe, mpiexec, nranks, scene, work = sys.argv[1:6]
    if not run_scene(exe, mpiexec, nranks, scene, work):
        return 1
    with h5py.File(os.path.join(work, "site_response_1d_damped.h5"), "r") as f:
        t = f["probes/time"][...]
        v = f["probes/velocity"][:, 0]
        acc = f["probes/acceleration"][:, 0]
    w1, w2 = 2 * math.pi * F1, 2 * math.pi * F2
    alpha, beta = 2 * XI * w1 * w2 / (w1 + w2), 2 * XI / (w1 + w2)
    # the base velocity as the code takes it: the record by the trapezoid rule, linear between
    # samples, resampled every 0.1 ms
    tr, ar = read_at2(os.path.join(os.path.dirname(scene), "ricker_5hz.AT2"))
    vr = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(tr) * (ar[1:] + ar[:-1]))])
    dt = 1.0e-4
    tu = dt * np.arange(int(t[-1] / dt) + 2)
    vs = damped_surface_velocity(dt, np.interp(tu, tr, vr, left=0.0, right=vr[-1]), alpha, beta)
    vref = np.interp(t, tu, vs)
    aref = np.diff(np.concatenate([[0.0], vref])) / np.diff(np.concatenate([[0.0], t]))
    e_v = np.sqrt(np.mean((v - vref) ** 2)) / np.abs(vref).max()
    e_a = np.sqrt(np.mean((acc - aref) ** 2)) / np.abs(aref).max()
    # 5 %-damped spectra of the two surface accelerations, resampled every 0.1 ms
    periods = np.geomspace(0.02, 2.0, 60)
    t0 = np.concatenate([[0.0], t])
    sa = response_spectrum(dt, np.interp(tu, t0, np.concatenate([[0.0], acc])), periods).sa
    sr = response_spectrum(dt, np.interp(tu, t0, np.concatenate([[0.0], aref])), periods).sa
    e_s = np.abs(sa / sr - 1.0).max()
    print(f"{nranks} ranks: alpha {alpha:.4f} 1/s, beta {beta:.4e} s; RMS error of the surface "
          f"velocity {e_v:.3e}, of the acceleration {e_a:.3e} of their peaks; largest relative "
          f"difference of the 5 % spectra {e_s:.3e} (peak Sa {sr.max():.4f} m/s^2)")
    fails = []
    # bounds: measured + 50 % (doc/verification.md)
    for name, val, bound in (("velocity", e_v, 1.7e-3), ("acceleration", e_a, 2.7e-3),
                             ("spectrum", e_s, 1.9e-3)):
        if not val <= bound:
            fails.append(f"{name} error {val:.3e} above {bound:.1e}")
    return finish(fails)


if __name__ == "__main__":
    sys.exit(main())
