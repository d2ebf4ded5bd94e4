#!/usr/bin/env python3
"""A file that cannot continue a run is refused before it is used: exit code 2 and one line.

    check_restart_files.py <mpiexec> <dpmpm> <ranks> <work dir>

A short run writes a checkpoint, whose datasets must carry the checksums of their definition
(tests/checkpoint_checksum.py). Given as `restart`, each of these must stop the run with exit
code 2, one line on stderr from dpmpm (saying what is wrong) and no HDF5 error stack or
runtime error: the run's output .h5, its .xmf, a directory, an empty file, the checkpoint cut
to half its length, the checkpoint with its last 64 KiB (or its second half) zeroed, one point
of zero mass and one of negative volume (checksums stamped again, so that the points are what
is found), and a checkpoint of a later format. A checkpoint as earlier versions wrote it (no
format_version, no checksums) still continues, with a note. `--restart` where the output
holds a finished run and there is no checkpoint stops with exit code 2, and `--restart
--start-over` runs it again.
"""
import pathlib
import shutil
import sys

import h5py

from checkpoint_checksum import checksum, restamp
from check_runs import RunChecks

mpiexec, dpmpm, ranks, work = sys.argv[1], sys.argv[2], sys.argv[3], pathlib.Path(sys.argv[4])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)


def scene(restart="", checkpoint_every=5):
    rs = f", restart = '{restart}'" if restart else ""
    return f"""&run name = 'ckpt', t_end = 1.0, max_steps = 10, gravity = 0.0, -9.81{rs} /
&grid ndim = 2, ncells = 8, 8 /
&material id = 1, youngs_modulus = 1.0e6, poisson_ratio = 0.3, density = 1000.0 /
&region lo = 0.25, 0.0, hi = 0.75, 0.5 /
&boundary face = 'y-', condition = 'fixed' /
&output dir = 'out', checkpoint_every = {checkpoint_every} /
"""


checks = RunChecks(mpiexec, dpmpm, ranks, work)
run, expect = checks.run, checks.expect


def expect_refused(p, name, text):
    """Exit code 2, one line from dpmpm on stderr holding text, nothing from HDF5 or the
    Fortran runtime (mpirun's own lines about the exit code are not dpmpm's)."""
    expect(p.returncode == 2, f"{name}: exit code 2 (got {p.returncode})")
    ours = [ln for ln in p.stderr.splitlines() if ln.startswith("dpmpm")]
    expect(len(ours) == 1, f"{name}: one line from dpmpm on stderr (got {len(ours)})")
    expect(any(text in ln for ln in ours), f"{name}: the line says: {text}")
    for bad in ("HDF5-DIAG", "Backtrace", "At line", "Error termination", "MPI_ABORT"):
        expect(bad not in p.stdout + p.stderr, f"{name}: no {bad} in the output")


p = run("first.nml", scene())
out = work / "out"
ckpt = out / "ckpt.ckpt.h5"
expect(p.returncode == 0 and ckpt.exists(), "the first run writes a checkpoint")
keep = work / "keep"
shutil.copytree(out, keep)

with h5py.File(ckpt, "r") as f:
    expect(int(f.attrs.get("format_version", 0)) == 2, "the checkpoint carries format_version 2")
    for name, ds in f.items():
        expect("checksum" in ds.attrs and int(ds.attrs["checksum"]) == checksum(ds[...]),
               f"/{name} carries the checksum of its definition")

p = run("same.nml", scene(restart="keep/ckpt.ckpt.h5"))
expect(p.returncode == 0, "a restart from the checkpoint runs")
expect("carries no checksums" not in p.stdout, "a checked checkpoint has no note")

bad = work / "bad"
bad.mkdir()
data = ckpt.read_bytes()
(bad / "empty.ckpt.h5").write_bytes(b"")
(bad / "cut.ckpt.h5").write_bytes(data[: len(data) // 2])
zeroed = bytearray(data)
nz = min(65536, len(data) // 2)
zeroed[-nz:] = bytes(nz)
(bad / "zeroed.ckpt.h5").write_bytes(bytes(zeroed))


def changed(name, change):
    path = bad / name
    shutil.copy(ckpt, path)
    with h5py.File(path, "r+") as f:
        change(f)
    return path


def point_field(column, value):
    def change(f):
        # Columns of particle_set_t%pack in 2D: id, material, x(2), x0(2), v(2), mass, volume.
        pts = f["solid"][...]
        pts[3, column] = value
        f["solid"][...] = pts
        restamp(f)
    return change


changed("mass.ckpt.h5", point_field(8, 0.0))
changed("volume.ckpt.h5", point_field(9, -1.0))
changed("later.ckpt.h5", lambda f: f.attrs.modify("format_version", 99))

cases = [
    ("output", "keep/ckpt.h5", "is the output of a run"),
    ("sidecar", "keep/ckpt.xmf", "is not an HDF5 file"),
    ("directory", "bad", "is a directory"),
    ("empty", "bad/empty.ckpt.h5", "is not an HDF5 file"),
    ("cut", "bad/cut.ckpt.h5", "truncated or damaged"),
    ("zeroed", "bad/zeroed.ckpt.h5", "fails its checksum"),
    ("mass", "bad/mass.ckpt.h5", "1 of its 64 solid points have a mass or volume that is not positive"),
    ("volume", "bad/volume.ckpt.h5", "1 of its 64 solid points have a mass or volume that is not positive"),
    ("later", "bad/later.ckpt.h5", "was written by a later dpmpm (checkpoint format 99"),
]
for name, path, text in cases:
    p = run(f"{name}.nml", scene(restart=path))
    expect_refused(p, name, text)


def earlier(f):
    del f.attrs["format_version"]
    for ds in f.values():
        del ds.attrs["checksum"]


changed("earlier.ckpt.h5", earlier)
p = run("earlier.nml", scene(restart="bad/earlier.ckpt.h5"))
expect(p.returncode == 0, "a checkpoint without checksums (earlier versions) continues")
expect("carries no checksums" in p.stdout, "the log says it is used unchecked")

# A finished run without a checkpoint: --restart says so and stops; --start-over runs it again.
shutil.rmtree(out)
p = run("nockpt.nml", scene(checkpoint_every=0))
expect(p.returncode == 0 and not ckpt.exists(), "a run without checkpoints finishes")
before = (out / "ckpt.h5").stat().st_mtime_ns
p = run("nockpt.nml", scene(checkpoint_every=0), "--restart")
expect_refused(p, "--restart of a finished run", "holds a finished run (step 10")
expect((out / "ckpt.h5").stat().st_mtime_ns == before, "the finished run's output is kept")
p = run("nockpt.nml", scene(checkpoint_every=0), "--restart", "--start-over")
expect(p.returncode == 0, "--restart --start-over runs it again")
expect("running the finished run" in p.stdout, "--start-over: the log says so")

checks.finish()
