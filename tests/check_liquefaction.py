#!/usr/bin/env python3
"""The level-ground liquefaction scene (inputs/liquefaction_1d.nml) in two short checks.

    check_liquefaction.py records <dpmpm> <mpiexec> <scene.nml> <work dir> [<h5contract.py>]
    check_liquefaction.py liquefaction <dpmpm> <mpiexec> <scene.nml> <work dir>

records: the scene's first 0.1 s (geostatic start, then the base motion), its sides on
rollers and its skeleton elastic, every step recorded, on 1 and on 2 ranks. The probes' records of their followed points (displacement,
stress, pore pressure) are the points' own values in every frame, to the bit; the first
record is the geostatic state at the point's depth; 1 and 2 ranks follow the same points
and record the same values to round-off; the file keeps the layout contract.

liquefaction: the scene's shaking, 2 s (four cycles of 0.15 g), on 1 rank: r_u reaches 0.9
at the five probes from 1 to 5 m depth, where the cyclic stress ratio (0.2 to 0.27) is
above the element resistance, and stays below 0.5 at the probe under the surface (CSR
0.07, below it); the surface acceleration falls as the sand softens. Bounds from the
measurements in doc/verification.md, "Liquefaction of level ground".
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_site_response import finish, run_text  # noqa: E402

G = 9.81
RHO_S, RHO_F, N_F, Q = 2650.0, 1000.0, 0.4594594594594595, 1.0e4


def scene_text(scene, t_end, extra_output):
    """The scene with its base record by absolute path, its output here, a shorter run."""
    text = open(scene).read()
    rec = os.path.join(os.path.dirname(os.path.abspath(scene)), "liquefaction_base_2hz.txt")
    text = text.replace("file_x = 'liquefaction_base_2hz.txt'", f"file_x = '{rec}'")
    text = re.sub(r"t_end = [0-9.]+", f"t_end = {t_end}", text)
    text = text.replace("dir = 'out'", "dir = '.'")
    text = re.sub(r"probe_every = \d+", "", text)
    text = re.sub(r"frame_interval = [0-9.]+", extra_output, text)
    return text


def run(exe, mpiexec, ranks, text, work):
    return run_text(exe, mpiexec, ranks, text, work, "liquefaction_1d.h5", timeout=600)


def probes(path):
    with h5py.File(path, "r") as f:
        return {k: v[...] for k, v in f["probes"].items()}


def check_records(exe, mpiexec, scene, work, contract):
    # Roller sides instead of the tied ones and an elastic skeleton instead of SANISAND: the
    # records are compared here, and SANISAND's adaptive integration is not rank-invariant
    # beyond round-off (doc/verification.md, "Liquefaction of level ground"); the tied
    # sides of the saturated column are, since the pairs were joined (ctest
    # tied_saturated_np1_np2).
    text = scene_text(scene, 0.1, "frame_interval = 0.025, probe_every = 1")
    text = text.replace("condition = 'tied'", "condition = 'roller'")
    text = text.replace("model = 'sanisand'", "model = 'linear_elastic', youngs_modulus = 3.0e7")
    text = re.sub(r"\n *(critical_state_ratio|void_ratio) = [0-9.]+", "", text)
    fails = []
    recs = {}
    for ranks in (1, 2):
        path = run(exe, mpiexec, ranks, text, os.path.join(work, f"np{ranks}"))
        if contract and os.path.exists(contract):
            c = subprocess.run([sys.executable, contract, path], capture_output=True, text=True)
            if c.returncode != 0:
                fails.append(f"{ranks} ranks: layout contract: {c.stdout.strip()}")
        p = probes(path)
        recs[ranks] = p
        m, n = len(p["time"]), len(p["solid_id"])
        for name, shape in (("displacement", (m, 2 * n)), ("stress", (m, 6 * n)),
                            ("pore_pressure", (m, n)), ("solid_position", (n, 2)),
                            ("solid_id", (n,)), ("fluid_id", (n,)), ("velocity", (m, 2 * n))):
            if p[name].shape != shape:
                fails.append(f"{ranks} ranks: /probes/{name} shape {p[name].shape}, not {shape}")
        sig = p["stress"].reshape(m, n, 6)
        disp = p["displacement"].reshape(m, n, 2)
        pw = p["pore_pressure"]
        # the records against the frames: the followed points' own values, to the bit
        nframes = 0
        with h5py.File(path, "r") as f:
            for key in sorted(f["frames"]):
                fr = f["frames"][key]
                step = fr.attrs["step"]
                r = np.nonzero(p["step"] == step)[0]
                if step == 0 or r.size == 0:
                    continue
                r = r[0]
                nframes += 1
                sid, fid = fr["solid"]["id"][...], fr["fluid"]["id"][...]
                for k in range(n):
                    i = np.nonzero(sid == p["solid_id"][k])[0][0]
                    j = np.nonzero(fid == p["fluid_id"][k])[0][0]
                    same = (np.array_equal(fr["solid"]["stress"][i], sig[r, k])
                            and np.array_equal(fr["solid"]["displacement"][i], disp[r, k])
                            and fr["fluid"]["pore_pressure"][j] == pw[r, k])
                    if not same:
                        fails.append(f"{ranks} ranks: probe {k} at step {step}: the records "
                                     "are not the point's values in the frame")
        if nframes < 3:
            fails.append(f"{ranks} ranks: only {nframes} frames matched a record")
        # the first record: the geostatic state at the point's depth (surface at 6 m, the
        # surcharge Q on it, the water table at the surface)
        depth = 6.0 - p["solid_position"][:, 1]
        sv_ref = Q + (1 - N_F) * (RHO_S - RHO_F) * G * depth
        u_ref = RHO_F * G * depth
        e_sv = np.abs(-sig[0, :, 1] - sv_ref).max() / sv_ref.max()
        e_u = np.abs(pw[0] - u_ref).max() / u_ref.max()
        print(f"{ranks} ranks: {m} records, {nframes} frames matched to the bit; first record "
              f"against the geostatic state: sigma'_v0 {e_sv:.2e}, u_0 {e_u:.2e} of the "
              "largest")
        # measured 9.8e-8 and 3.2e-4 (the first step of the base motion against the roller
        # sides), on both rank counts; bound 1e-3
        if not (e_sv < 1e-3 and e_u < 1e-3):
            fails.append(f"{ranks} ranks: first record off the geostatic state "
                         f"({e_sv:.2e}, {e_u:.2e})")
    a, b = recs[1], recs[2]
    for name in ("solid_id", "fluid_id", "solid_position", "position", "step"):
        if not np.array_equal(a[name], b[name]):
            fails.append(f"1 and 2 ranks: /probes/{name} differ")
    worst = 0.0
    for name in ("displacement", "stress", "pore_pressure", "velocity", "acceleration", "time"):
        if a[name].shape != b[name].shape:
            fails.append(f"1 and 2 ranks: /probes/{name} shapes differ")
            continue
        dev = np.abs(a[name] - b[name]).max() / max(np.abs(a[name]).max(), 1e-300)
        worst = max(worst, dev)
        print(f"  1 against 2 ranks: {name}: {dev:.2e} of the largest")
    # measured: 1.3e-13 (acceleration), 1.0e-14 (velocity), 2.2e-15 and less the others
    # (debug build); bound 1e-10
    # as for the frames (doc/verification.md, "Rank-count invariance")
    if not worst < 1e-10:
        fails.append(f"1 and 2 ranks: records differ by {worst:.2e} of the largest")
    return fails


def check_liquefaction(exe, mpiexec, scene, work):
    text = scene_text(scene, 2.0, "frame_interval = 2.0, probe_every = 10")
    path = run(exe, mpiexec, 1, text, work)
    p = probes(path)
    t, n = p["time"], len(p["solid_id"])
    m = len(t)
    sig = p["stress"].reshape(m, n, 6)
    ru = (p["pore_pressure"] - p["pore_pressure"][0]) / -sig[0, :, 1]
    csr = np.abs(sig[t <= 0.5, :, 5]).max(axis=0) / -sig[0, :, 1]
    acc = np.abs(p["acceleration"].reshape(m, n, 2)[:, 0, 0])
    a1 = acc[t <= 1.0].max()
    a3 = acc[(t > 1.5) & (t <= 2.0)].max()
    fails = []
    for k in range(n):
        print(f"probe {k}: CSR over the first cycle {csr[k]:.3f}, largest r_u {ru[:, k].max():.3f}")
    print(f"peak surface acceleration: {a1:.3f} m/s^2 in the first two cycles, {a3:.3f} in the "
          "fourth")
    # measured (debug build, records every 10 steps): largest r_u 0.962 to 0.996 at probes
    # 1-5 (CSR 0.20-0.27) and 0.306 at probe 0 (CSR 0.069); the surface acceleration 1.804
    # m/s^2 in the first two cycles, 0.522 in the fourth. Bounds: r_u > 0.9 and < 0.5, the
    # CSRs above 0.15 and below 0.1, the acceleration at least halved (measured: 0.29 of it)
    if not np.all(ru[:, 1:].max(axis=0) > 0.9):
        fails.append("r_u stays below 0.9 at a depth whose CSR exceeds the resistance")
    if not ru[:, 0].max() < 0.5:
        fails.append("r_u reaches 0.5 under the surface, where the CSR is below the resistance")
    if not np.all(csr[1:] > 0.15) or not csr[0] < 0.1:
        fails.append("the cyclic stress ratios are not those measured")
    if not a3 < 0.5 * a1:
        fails.append("the surface acceleration does not fall as the sand softens")
    return fails


def main():
    mode, exe, mpiexec, scene, work = sys.argv[1:6]
    contract = sys.argv[6] if len(sys.argv) > 6 else ""
    if mode == "records":
        fails = check_records(exe, mpiexec, scene, work, contract)
    elif mode == "liquefaction":
        fails = check_liquefaction(exe, mpiexec, scene, work)
    else:
        print(f"unknown mode {mode}")
        return 2
    return finish(fails)


if __name__ == "__main__":
    sys.exit(main())
