#!/usr/bin/env python3
"""A scheduler's stop loses nothing: a run stopped by SIGTERM (what Slurm sends every task
before the kill) or by max_wall_time writes a checkpoint, says how to continue, and the
continued run ends with the same final frame, to the last bit, as a run without a break.

    check_stop_signal.py <mpiexec> <dpmpm> <work dir>

Every run uses 2 ranks. SIGTERM goes to the rank processes of the mpirun job, as Slurm
delivers it; it is sent once the run has printed a progress line (the time loop runs).
max_wall_time is set far below the time of a step loop, so that the stop comes at the first
look (step 10) however fast the machine is.
"""
import pathlib
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

mpiexec, dpmpm, work = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
MAX_STEPS = 1200
STOPPED = 3  # exit code of a run stopped early with a checkpoint (doc/input.md)

failures = []


def expect(cond, what):
    print(("ok:   " if cond else "FAIL: ") + what, flush=True)
    if not cond:
        failures.append(what)


def scene(name, extra=""):
    """A saturated column beside a dry neo-Hookean block, both on a fixed floor under gravity
    (the scene of tests/test_restart.f90): both point sets go through the checkpoint."""
    text = f"""&run name = '{name}', t_end = 100.0, max_steps = {MAX_STEPS}, cfl = 0.4,
  gravity = 0.0, -9.81, progress_seconds = 0.05, drag = 'implicit' {extra} /
&grid ndim = 2, ncells = 8, 8, length = 1.0, 1.0 /
&shape kernel = 'quadratic' /
&material id = 1, density = 2650.0, youngs_modulus = 1.0e6, poisson_ratio = 0.3,
  conductivity = 1.0e-3 /
&material id = 2, model = 'fluid', density = 1000.0, bulk_modulus = 2.0e7 /
&material id = 3, model = 'neo_hookean', density = 2000.0, youngs_modulus = 5.0e5,
  poisson_ratio = 0.3 /
&region lo = 0.0, 0.0, hi = 0.375, 0.5, material = 1, phase = 'saturated',
  fluid_material = 2, porosity = 0.4, placement = 'random' /
&region lo = 0.625, 0.0, hi = 1.0, 0.25, material = 3, placement = 'random', seed = 7 /
&boundary face = 'x-', condition = 'roller' /
&boundary face = 'x+', condition = 'roller' /
&boundary face = 'y-', condition = 'fixed' /
&output dir = 'out' /
"""
    path = work / f"{name}.nml"
    path.write_text(text)
    return path.name


def launch(nml):
    return subprocess.Popen([mpiexec, "--oversubscribe", "-n", "2", dpmpm, nml], cwd=work,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def finish(p, name):
    out, err = p.communicate(timeout=180)
    print(f"--- {name}: exit code {p.returncode}\n{out}{err}", flush=True)
    return out, err


def run(nml):
    p = launch(nml)
    out, err = finish(p, nml)
    return p.returncode, out, err


def final_frame(path):
    """Every dataset of the last frame, each point set sorted by id, with time and step."""
    with h5py.File(path, "r") as f:
        g = f["frames"][sorted(f["frames"])[-1]]
        data = {"time": g.attrs["time"], "step": g.attrs["step"]}
        for s in g:
            order = np.argsort(g[s]["id"][...])
            for k in g[s]:
                data[f"{s}/{k}"] = g[s][k][...][order]
    return data


def same_frame(a, b, what):
    expect(sorted(a) == sorted(b), f"{what}: the same datasets")
    for k in sorted(a):
        if k in b:
            expect(np.array_equal(a[k], b[k]), f"{what}: {k} equal to the last bit")


def continued(name, out):
    """Restart from the checkpoint the stop message names; the continued run goes on in the
    stopped run's file, whose frames must then be those of the run without a break."""
    line = [l for l in out.splitlines() if "to continue, run the same input with restart" in l]
    expect(len(line) == 1, f"{name}: the stop message says how to continue")
    ckpt = work / "out" / f"{name}.ckpt.h5"
    expect(ckpt.exists(), f"{name}: the checkpoint is written")
    expect(not (work / "out" / f"{name}.h5.writing").exists(),
           f"{name}: the stopped run closed its file (no mark left)")
    rc, out2, _ = run(scene(name, f", restart = 'out/{name}.ckpt.h5'"))
    expect(rc == 0, f"{name}: the continued run ends with exit code 0")
    expect("dpmpm: continuing out/" in out2 and "not continued in place" not in out2,
           f"{name}: the continued run goes on in its file, in place")
    path = work / "out" / f"{name}.h5"
    with h5py.File(path, "r") as f, h5py.File(work / "out" / "ref.h5", "r") as r:
        steps = [int(f["frames"][k].attrs["step"]) for k in sorted(f["frames"])]
        want = [int(r["frames"][k].attrs["step"]) for k in sorted(r["frames"])]
    expect(steps == want, f"{name}: frames at steps {steps}, without a break {want}")
    return path


# The reference: no break.
rc, out, err = run(scene("ref"))
expect(rc == 0, "the run without a break ends with exit code 0")
ref = final_frame(work / "out" / "ref.h5")
expect(ref["step"] == MAX_STEPS, f"the run without a break makes {MAX_STEPS} steps")

# SIGTERM to the ranks once the time loop runs.
p = launch(scene("sig"))
seen = False
for line in p.stdout:
    print(line, end="")
    if re.match(r"step \d+  t = ", line):  # a progress line of the time loop
        seen = True
        break
ranks = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
for pid in ranks:
    subprocess.run(["kill", "-TERM", pid])
out, err = finish(p, "sig.nml")
expect(seen and len(ranks) == 2, "SIGTERM sent to the 2 ranks while the time loop runs")
expect(p.returncode == STOPPED, f"stopped by SIGTERM: exit code {STOPPED}")
expect("dpmpm: stopped on SIGTERM at step" in out, "the stop is reported with its signal")
stop_step = int(out.split("stopped on SIGTERM at step ")[1].split(",")[0]) if \
    "stopped on SIGTERM at step " in out else MAX_STEPS
expect(stop_step < MAX_STEPS, f"stopped before the end (step {stop_step} of {MAX_STEPS})")
more = continued("sig", out)
if more:
    same_frame(ref, final_frame(more), "SIGTERM and restart")

# max_wall_time: a limit that start-up alone exceeds.
rc, out, err = run(scene("wall", ", max_wall_time = 1.0e-3"))
expect(rc == STOPPED, f"stopped by max_wall_time: exit code {STOPPED}")
expect("dpmpm: stopped at max_wall_time" in out, "the stop is reported with max_wall_time")
more = continued("wall", out)
if more:
    same_frame(ref, final_frame(more), "max_wall_time and restart")

print("PASS" if not failures else f"{len(failures)} check(s) failed")
sys.exit(1 if failures else 0)
