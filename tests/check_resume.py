#!/usr/bin/env python3
"""A restarted run continues the output file of the run it continues: no frame or
diagnostics record missing or repeated, and the same frames as a run without a break.

Usage: check_resume.py --dpmpm BIN --mpiexec MPIEXEC --scene SCENE.nml --workdir DIR
                       [--ranks N]

Runs SCENE (benchmark group removed) for 40 steps in one go, and in pieces: 20 steps with
a checkpoint, kept aside; 30 steps continued from it (frames after step 20 are written, as
a run killed after its checkpoint leaves them); 40 steps continued again from the step-20
checkpoint. The last file must equal the unbroken one frame by frame (tests/frames_by_id.py,
to 1e-12 of each dataset's largest value: the same ranks do the same arithmetic), its
diagnostics must hold the unbroken run's steps, each once, and the step it restarted
from, and scripts/check_output.py must pass.
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from frames_by_id import compare, scene_arguments, scene_text  # noqa: E402


def run_scene(args, name, nml_name, sets):
    """Write SCENE with the given variables (t_end far beyond max_steps) and run it."""
    text = scene_text(args.scene, name, args.workdir, [("t_end", "1.0")] + sets)
    nml = os.path.join(args.workdir, nml_name)
    with open(nml, "w") as f:
        f.write(text)
    return subprocess.run([args.mpiexec, "--oversubscribe", "-n", str(args.ranks), args.dpmpm,
                           nml], capture_output=True, text=True)


def run(args, name, extra, restart=None):
    sets = [("max_steps", str(extra)), ("frame_interval", "0.002"),
            ("output.checkpoint_every", "20"), ("output.compression", "1")]
    if restart:
        sets.append(("restart", f"'{restart}'"))
    r = run_scene(args, name, f"{name}_{extra}.nml", sets)
    if r.returncode != 0:
        print(r.stdout + r.stderr)
        raise SystemExit(f"run {name}_{extra}.nml ended with {r.returncode}")
    return r.stdout


def wall_clock_checkpoints(args, failed):
    """checkpoint_seconds alone (no checkpoint_every) writes checkpoints at the looks for a
    stop (every 10 steps); a torn <name>.ckpt.h5.tmp of an earlier run is removed."""
    w = args.workdir
    tmp = os.path.join(w, "wall.ckpt.h5.tmp")
    with open(tmp, "w") as f:
        f.write("torn")
    r = run_scene(args, "wall", "wall.nml", [("max_steps", "25"),
                                            ("output.checkpoint_seconds", "1.0e-9")])
    if r.returncode != 0:
        failed.append(f"the wall-clock checkpoint run ended with {r.returncode}")
        return
    if os.path.exists(tmp) or "removed " + tmp not in r.stdout:
        failed.append("the torn temporary checkpoint was not removed with a message")
    ckpt = os.path.join(w, "wall.ckpt.h5")
    if not os.path.exists(ckpt):
        failed.append("checkpoint_seconds wrote no checkpoint")
        return
    with h5py.File(ckpt, "r") as f:
        step = int(np.ravel(f["state"][...])[0])
    print(f"checkpoint_seconds: last checkpoint at step {step} of 25")
    if step != 20:
        failed.append(f"the last wall-clock checkpoint is at step {step}, expected 20 (the "
                      "looks come every 10 steps, none at the last step)")


def main():
    ap = scene_arguments(__doc__)
    ap.add_argument("--ranks", type=int, default=2)
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    w = args.workdir
    run(args, "whole", 40)
    run(args, "piece", 20)
    ckpt20 = os.path.join(w, "piece20.ckpt.h5")
    shutil.copy(os.path.join(w, "piece.ckpt.h5"), ckpt20)
    log30 = run(args, "piece", 30, restart=ckpt20)
    log40 = run(args, "piece", 40, restart=ckpt20)
    print(log40.strip().splitlines()[1] if log40.strip() else "")
    failed = []
    if "continuing" not in log30 or "continuing" not in log40:
        failed.append("the restarted runs did not say they continue the file")
    whole, piece = os.path.join(w, "whole.h5"), os.path.join(w, "piece.h5")
    bad, worst = compare(whole, piece, 1e-12)
    failed += bad
    with h5py.File(whole, "r") as a, h5py.File(piece, "r") as b:
        nfa, nfb = len(a["frames"]), len(b["frames"])
        print(f"frames: {nfb} continued, {nfa} unbroken; largest relative deviation {worst:.1e}")
        # The continued run adds one record: the state it starts from, at step 20.
        sa, sb = a["diagnostics/step"][...], b["diagnostics/step"][...]
        if not np.all(np.diff(sb) > 0):
            failed.append(f"diagnostics steps not increasing: {sb.tolist()}")
        if sorted(set(sb.tolist()) - set(sa.tolist())) not in ([], [20]) or \
                not set(sa.tolist()) <= set(sb.tolist()):
            failed.append(f"diagnostics steps {sb.tolist()} against {sa.tolist()}")
    wall_clock_checkpoints(args, failed)
    r = subprocess.run([sys.executable, os.path.join(HERE, "..", "scripts", "check_output.py"),
                        piece], capture_output=True, text=True)
    print(r.stdout.strip())
    if r.returncode != 0:
        failed.append("check_output.py failed on the continued file")
    for f in failed[:20]:
        print("  " + f)
    print(f"{0 if failed else 1} passed, {1 if failed else 0} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
