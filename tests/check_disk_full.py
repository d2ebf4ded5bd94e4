#!/usr/bin/env python3
"""A write that fails says what the system said and which file, and leaves no cut sidecar.

    check_disk_full.py <mpiexec> <dpmpm> <ranks> <work dir> sidecar|tmpfs

sidecar: the run's <name>.xmf.tmp is a link to /dev/full, so that writing the XDMF sidecar
fails with ENOSPC: the run must stop with a line naming that file and 'No space left on
device', and the sidecar of the run before must be left as it was (whole XML).
tmpfs: the output goes to a small tmpfs (mounted here; exit code 77, a skip, where mounting
is not allowed) that fills while frames are written: the run must stop with exit code 1 and
one line naming a file under it and 'No space left on device', without HDF5's error stack;
the sidecar, where there is one, must be whole XML, and the last checkpoint must still pass
its checksums.
"""
import os
import pathlib
import shutil
import subprocess
import sys
import xml.dom.minidom

import h5py

from checkpoint_checksum import checksum
from check_runs import RunChecks

mpiexec, dpmpm, ranks, work, mode = sys.argv[1:6]
work = pathlib.Path(work)
if work.is_mount():
    subprocess.run(["umount", str(work)])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)


def scene(out):
    return f"""&run name = 'full', t_end = 1.0, max_steps = 60, gravity = 0.0, -9.81 /
&grid ndim = 2, ncells = 16, 16 /
&material id = 1, youngs_modulus = 1.0e6, poisson_ratio = 0.3, density = 1000.0 /
&region lo = 0.25, 0.0, hi = 0.75, 0.5 /
&boundary face = 'y-', condition = 'fixed' /
&output dir = '{out}', frame_interval = 1.0e-4, checkpoint_every = 2 /
"""


checks = RunChecks(mpiexec, dpmpm, ranks, work)
expect = checks.expect


def run(name, text):
    return checks.run(name, text, tail=2000)


def whole_xml(path):
    try:
        xml.dom.minidom.parse(str(path))
        return True
    except Exception as e:  # a cut file: any parse error
        print(f"{path}: {e}")
        return False


def expect_reason(p, name, path_text):
    expect(p.returncode == 1, f"{name}: exit code 1 (got {p.returncode})")
    lines = [ln for ln in p.stderr.splitlines() if ln.startswith("dpmpm: error")]
    expect(any("No space left on device" in ln and path_text in ln for ln in lines),
           f"{name}: a line names {path_text}... and 'No space left on device'")
    expect("HDF5-DIAG" not in p.stderr, f"{name}: no HDF5 error stack")


if mode == "sidecar":
    if not os.path.exists("/dev/full"):
        print("SKIP: no /dev/full")
        sys.exit(77)
    p = run("first.nml", scene("out"))
    xmf = work / "out" / "full.xmf"
    expect(p.returncode == 0 and whole_xml(xmf), "the first run writes a whole sidecar")
    before = xmf.read_bytes()
    (work / "out" / "full.xmf.tmp").symlink_to("/dev/full")
    p = run("again.nml", scene("out"))
    expect_reason(p, "sidecar on a full disk", "cannot write out/full.xmf.tmp")
    expect(xmf.read_bytes() == before, "the sidecar of the run before is left as it was")
else:
    full = work / "full"
    full.mkdir()
    m = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(full)],
                       capture_output=True, text=True)
    if m.returncode != 0:
        print(f"SKIP: cannot mount a tmpfs here: {m.stderr.strip()}")
        sys.exit(77)
    try:
        p = run("full.nml", scene("full/out"))
        expect_reason(p, "output on a full disk", "full/out/full.")
        xmf = full / "out" / "full.xmf"
        expect(not xmf.exists() or whole_xml(xmf), "the sidecar is whole XML")
        ckpt = full / "out" / "full.ckpt.h5"
        expect(ckpt.exists(), "a checkpoint was written before the disk filled")
        if ckpt.exists():
            with h5py.File(ckpt, "r") as f:
                for name, ds in f.items():
                    expect(int(ds.attrs["checksum"]) == checksum(ds[...]),
                           f"the last checkpoint's /{name} passes its checksum")
    finally:
        subprocess.run(["umount", str(full)])

checks.finish()
