#!/usr/bin/env python3
"""A run killed inside one of HDF5's metadata flushes, at a chosen place, loses nothing once
it is continued.

    check_flush_kill.py <mpiexec> <dpmpm> <stop_at_flush.so> <work dir> [flush]

tests/stop_at_flush.c, loaded into the ranks, stops rank 0 right before its first write to
the output file in its `flush`-th call of H5Fflush (253: the flush after frame 251 of the
scene of check_frame_kill.py, 26 frames after the checkpoint of step 225); a second later,
rank 1 having gone on to where it waits for rank 0, the job is killed (SIGKILL). Every frame
and dataset of the file left then opens and reads, yet a run continued in it in place failed
at its end every time, inside HDF5 (h5dset_extent_f of a diagnostics dataset:
MPI_ERR_TRUNCATE from H5C_protect), as 2 of 10 runs of check_frame_kill.py did before the
output was marked while open. Checked: the killed run leaves the mark <name>.h5.writing; the
continued run rebuilds the file, ends with exit code 0 and leaves no mark nor temporary file;
its frames equal those of a run without a break to the last bit, its diagnostics hold the
reference's steps (and the record of the step it continued from), and
scripts/check_output.py passes on it. Exit code 77 (a skip) where the stop is not reached
(an MPI-IO layer that writes otherwise, an HDF5 without H5Fflush calls there).
"""
import os
import pathlib
import subprocess
import sys
import time

import h5py
import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from frames_by_id import compare  # noqa: E402
from kill_scene import KillCheck, kill_run  # noqa: E402

mpiexec, dpmpm, shim = sys.argv[1], sys.argv[2], sys.argv[3]
K = KillCheck(mpiexec, dpmpm, sys.argv[4])
work, expect, scene, run, check_output = K.work, K.expect, K.scene, K.run, K.check_output
flush = int(sys.argv[5]) if len(sys.argv) > 5 else 253


rc, log = run([scene("ref")])
expect(rc == 0, "the run without a break ends with exit code 0")
if rc != 0:
    print(log)
    sys.exit(1)
ref = work / "out" / "ref.h5"

flag = work / "stopped"
env = dict(os.environ, LD_PRELOAD=shim, DPMPM_STOP_FILE="/out/kill.h5", DPMPM_STOP_RANK="0",
           DPMPM_STOP_FLUSH=str(flush), DPMPM_STOP_FLAG=str(flag))
p = subprocess.Popen([mpiexec, "--oversubscribe", "-n", "2", dpmpm, scene("kill")], cwd=work,
                     env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
begin = time.monotonic()
while not flag.exists() and p.poll() is None and time.monotonic() - begin < 600:
    time.sleep(0.05)
if not flag.exists():
    p.kill()
    p.wait()
    print(f"SKIP: rank 0 was never stopped in its flush {flush} (the run ended with exit "
          f"code {p.returncode}): this MPI-IO layer or HDF5 writes otherwise")
    sys.exit(77)
time.sleep(1.0)
kill_run(p)
h5 = work / "out" / "kill.h5"
try:
    with h5py.File(h5, "r") as f:
        nframes = len(f["frames"])
        for k in f["frames"]:
            for st in f["frames"][k]:
                f["frames"][k][st]["id"][...]
        for d in f["diagnostics"]:
            f["diagnostics"][d][...]
    print(f"killed in flush {flush} with {nframes} frames, every frame and diagnostics "
          f"dataset readable")
except (OSError, RuntimeError, KeyError) as err:
    print(f"killed in flush {flush}; the file does not read whole ({err})")
expect((work / "out" / "kill.h5.writing").exists(), "the killed run left its output marked as open")

rc, log = run(["--restart", "kill.nml"])
expect(rc == 0, "the continued run ends with exit code 0")
if rc != 0:
    print(log)
    sys.exit(1)
said = [line for line in log.splitlines() if "continuing" in line or "damaged" in line]
print("  " + "\n  ".join(said[:3]))
expect(any("not continued in place" in line for line in said) and
       not any("lost" in line for line in said),
       "the continued run rebuilt the file, no frame lost")
left = sorted(q.name for q in (work / "out").glob("kill.h5.*"))
expect(not left, f"no mark or temporary file left ({left})")
bad, worst = compare(ref, h5, 0.0)
expect(not bad, f"every frame equal to the run without a break (largest relative deviation "
                f"{worst:.1e})")
for b in bad[:5]:
    print("    " + b)
with h5py.File(ref, "r") as f, h5py.File(h5, "r") as g:
    want, got = f["diagnostics/step"][...].tolist(), g["diagnostics/step"][...].tolist()
extra = sorted(set(got) - set(want))
expect(all(np.diff(got) > 0) and set(want) <= set(got) and len(extra) <= 1,
       f"diagnostics at the reference's steps, each once (and {extra})")
rc, out = check_output(h5)
expect(rc == 0, "check_output.py passes on the continued file")
if rc != 0:
    print(out)
K.finish()
