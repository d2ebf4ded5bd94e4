#!/usr/bin/env python3
"""The site-response scene through the file route: inputs/site_response_1d.nml (a PEER .AT2
record, the rigid base, a probe at the surface) run by dpmpm on the given ranks; the output
keeps the layout contract, /probes has its promised shapes, and the probe's surface
velocity follows d'Alembert's sum of delayed copies of the base velocity (doc/verification.md,
"Site response on a rigid base"): the same bound as tests/test_site_response.f90.

    check_site_response.py <dpmpm> <mpiexec> <nranks> <scene.nml> <work dir> [<h5contract.py>]
"""
import os
import subprocess
import sys

import h5py
import numpy as np

G = 9.80665
H, C = 10.0, 100.0


def read_at2(path):
    """Times and accelerations (m/s^2) of an .AT2 file of the NGA-West2 header."""
    with open(path) as f:
        lines = f.read().splitlines()
    head = lines[3].upper().replace(",", " ").split()
    npts = int(head[head.index("NPTS=") + 1])
    dt = float(head[head.index("DT=") + 1])
    vals = np.array([float(w) for line in lines[4:] for w in line.split()])
    assert len(vals) == npts, (len(vals), npts)
    return dt * np.arange(npts), G * vals


def run_scene(exe, mpiexec, nranks, scene, work, text=None, timeout=300):
    """Run scene with dpmpm on nranks ranks in work (made if missing; with text, that text
    is first written to the file scene there); True when it ends well, else the ends of its
    output are printed. One rank runs the binary itself, as a plain `dpmpm scene.nml` does
    (MPI as a singleton), without the start of mpiexec."""
    os.makedirs(work, exist_ok=True)
    if text is not None:
        scene = os.path.join(work, scene)
        with open(scene, "w") as f:
            f.write(text)
    cmd = [os.path.abspath(exe), os.path.abspath(scene)]
    if int(nranks) > 1:
        cmd = [mpiexec, "--oversubscribe", "-n", str(nranks)] + cmd
    run = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=timeout)
    if run.returncode != 0:
        print(run.stdout[-3000:], run.stderr[-3000:])
    return run.returncode == 0


def run_text(exe, mpiexec, nranks, text, work, output, timeout=300):
    """The scene text run as scene.nml in work (run_scene): the path of its output file
    output there; on a failure the ends of its output are printed and the check stops."""
    if not run_scene(exe, mpiexec, nranks, "scene.nml", work, text=text, timeout=timeout):
        raise SystemExit(1)
    return os.path.join(work, output)


def finish(fails):
    """Each failure on a line of its own; the exit code, 1 when there is one."""
    for msg in fails:
        print("FAIL:", msg)
    return 1 if fails else 0


def main():
    exe, mpiexec, nranks, scene, work = sys.argv[1:6]
    contract = sys.argv[6] if len(sys.argv) > 6 else ""
    if not run_scene(exe, mpiexec, nranks, scene, work):
        return 1
    out = os.path.join(work, "site_response_1d.h5")
    fails = []
    if contract and os.path.exists(contract):
        c = subprocess.run([sys.executable, contract, out], capture_output=True, text=True)
        print(c.stdout.strip())
        if c.returncode != 0:
            fails.append("layout contract: " + c.stdout.strip())
    with h5py.File(out, "r") as f:
        p = f["probes"]
        t, v, a, pos = (p[n][...] for n in ("time", "velocity", "acceleration", "position"))
        m = len(t)
        for name, arr, shape in (("step", p["step"][...], (m,)), ("velocity", v, (m, 1)),
                                 ("acceleration", a, (m, 1)), ("position", pos, (1, 1))):
            if arr.shape != shape:
                fails.append(f"/probes/{name} shape {arr.shape}, expected {shape}")
        if abs(pos[0, 0] - H) > 1e-12:
            fails.append(f"probe node at {pos[0, 0]}, expected {H}")
    # The base velocity as the code takes it: the record integrated by the trapezoid rule,
    # linear between samples; at rest before the first.
    tr, ar = read_at2(os.path.join(os.path.dirname(scene), "ricker_5hz.AT2"))
    vr = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(tr) * (ar[1:] + ar[:-1]))])
    T = H / C
    vs = np.zeros_like(t)
    for n in range(int(t[-1] / (2 * T)) + 2):
        vs += 2.0 * (-1) ** n * np.interp(t - (2 * n + 1) * T, tr, vr, left=0.0, right=vr[-1])
    peak = np.abs(vs).max()
    rms = np.sqrt(np.mean((v[:, 0] - vs) ** 2)) / peak
    # the probe's acceleration is its velocity's change over each step
    dv = np.diff(np.concatenate([[0.0], v[:, 0]])) / np.diff(np.concatenate([[0.0], t]))
    acc_err = np.abs(a[:, 0] - dv).max() / np.abs(dv).max()
    print(f"{nranks} ranks: {m} records; RMS error of the surface velocity {rms:.3e} of the "
          f"peak {peak:.4e} m/s; acceleration against the velocity's steps {acc_err:.1e}")
    # measured 2.71e-3 (doc/verification.md); bound measured + 50 %
    if not rms <= 4.1e-3:
        fails.append(f"RMS error {rms:.3e} above 4.1e-3")
    if not acc_err <= 1e-12:
        fails.append(f"acceleration is not the velocity's change over the step ({acc_err:.1e})")
    return finish(fails)


if __name__ == "__main__":
    sys.exit(main())
