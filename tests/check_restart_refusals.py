#!/usr/bin/env python3
"""A restart that would lose points is refused with a message, never run silently.

    check_restart_refusals.py <mpiexec> <dpmpm> <work dir>

A short run writes a checkpoint; restarting it with the same grid must work (the control),
while a grid with another origin or another length (same ncells) and a checkpoint with one
point made non-finite and one moved outside the grid must stop with a non-zero exit code
and a message saying why (the grid, or how many points). A checkpoint of the earlier
layout (18 numbers in /state: no drag dissipation, no monitor state) still continues, and the
log says that the energy monitor measures from the restart. The changed checkpoints are
stamped with their new checksums (tests/checkpoint_checksum.py), so that what is refused is
what was changed.
"""
import pathlib
import shutil
import sys

import h5py
import numpy as np

from checkpoint_checksum import restamp
from check_runs import RunChecks

mpiexec, dpmpm, work = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)


def scene(origin="0.0, 0.0", length="1.0, 1.0", restart=""):
    rs = f", restart = '{restart}'" if restart else ""
    return f"""&run name = 'ckpt', t_end = 1.0, max_steps = 10, gravity = 0.0, -9.81{rs} /
&grid ndim = 2, ncells = 8, 8, origin = {origin}, length = {length} /
&material id = 1, youngs_modulus = 1.0e6, poisson_ratio = 0.3, density = 1000.0 /
&region lo = 0.25, 0.0, hi = 0.75, 0.5, placement = 'random' /
&boundary face = 'y-', condition = 'fixed' /
&output dir = 'out', checkpoint_every = 5 /
"""


checks = RunChecks(mpiexec, dpmpm, 2, work)
run, expect = checks.run, checks.expect


p = run("first.nml", scene())
ckpt = work / "out" / "ckpt.ckpt.h5"
expect(p.returncode == 0 and ckpt.exists(), "the first run writes a checkpoint")

p = run("same.nml", scene(restart="out/ckpt.ckpt.h5"))
expect(p.returncode == 0, "a restart on the same grid runs")

for name, text in [("origin.nml", scene(origin="0.05, 0.0", restart="out/ckpt.ckpt.h5")),
                   ("length.nml", scene(length="1.1, 1.0", restart="out/ckpt.ckpt.h5"))]:
    p = run(name, text)
    expect(p.returncode != 0, f"{name}: refused (non-zero exit code)")
    expect("comes from another grid" in p.stderr, f"{name}: the message names the grid")
    expect(p.stderr.count("comes from another grid") == 1, f"{name}: the message is printed once")

# One point non-finite, one far outside the grid: every value of the row, so that the
# test does not depend on where the position sits in a row.
damaged = work / "out" / "damaged.ckpt.h5"
shutil.copy(ckpt, damaged)
with h5py.File(damaged, "r+") as f:
    pts = f["solid"][...]
    pts[0, :] = np.nan
    pts[1, :] = 1.0e30
    f["solid"][...] = pts
    restamp(f)  # the points, not the checksum, are to be found wrong
p = run("damaged.nml", scene(restart="out/damaged.ckpt.h5"))
expect(p.returncode != 0, "damaged checkpoint: refused (non-zero exit code)")
expect(f"1 of its {pts.shape[0]} solid points have a non-finite value and 1 lie outside the grid"
       in p.stderr, "damaged checkpoint: the message counts the points")

# The earlier layout: /state without the drag dissipation and the monitor's state (and,
# as every file of then, without format_version and checksums).
earlier = work / "out" / "earlier.ckpt.h5"
shutil.copy(ckpt, earlier)
with h5py.File(earlier, "r+") as f:
    state = f["state"][...]
    expect(state.size > 18, f"/state holds the monitor's state ({state.size} numbers)")
    del f["state"]
    f["state"] = state.reshape(-1)[:18].reshape(1, 18)
    del f.attrs["format_version"]
    del f["solid"].attrs["checksum"]
p = run("earlier.nml", scene(restart="out/earlier.ckpt.h5"))
expect(p.returncode == 0, "a checkpoint of the earlier layout continues")
expect("holds no monitor state" in p.stdout, "the log says the monitor starts over")

checks.finish()
