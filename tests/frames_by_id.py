#!/usr/bin/env python3
"""Output written on several rank counts equals the 1-rank output, frame by frame.

Usage: frames_by_id.py --dpmpm BIN --mpiexec MPIEXEC --scene SCENE.nml --workdir DIR
                       [--set KEY=VALUE ...] [--ranks 1 2 3 4] [--repeat N]
                       [--ompio-runs N] [--rtol R]

Runs SCENE (its &benchmark group removed, the variables given with --set replaced or
added) once on 1 rank, then on every rank count of --ranks, each of the counts above 2
--repeat times, and --ompio-runs more times on 3 ranks with Open MPI's OMPIO layer forced
(OMPI_MCA_io=ompio), the layer whose collective writes dpmpm reads back and repairs.
Every file is then compared with the 1-rank file: the same frames with the same times
and steps, in each frame the same point sets with the same ids (each once), and every
dataset matched by id within rtol times the largest magnitude of that dataset in the
1-rank frame. scripts/check_output.py is also run on every file (ids complete and
unique, masses, finite values, XDMF). Exit status 0 when all agree.
"""
import argparse
import os
import re
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CHECK_OUTPUT = os.path.join(HERE, "..", "scripts", "check_output.py")


def scene_text(path, name, outdir, sets):
    """The scene with &benchmark removed and name, dir and the --set variables replaced."""
    text = open(path).read()
    text = re.sub(r"(?ms)^&benchmark.*?^/\s*$", "", text)
    values = dict(sets)
    values["name"] = f"'{name}'"
    values["dir"] = f"'{outdir}'"
    for key, val in values.items():
        group, _, key = key.rpartition(".")
        group = group or ("output" if key in ("dir", "frame_interval") else "run")
        # The variable inside its group (up to the group's closing slash).
        pat = rf"(?ms)^(&{group}\b(?:(?!^/).)*?^\s*{key}\s*=\s*)[^\n]*$"
        if re.search(pat, text):
            text = re.sub(pat, lambda m: m.group(1) + val, text, count=1)
        else:
            text = re.sub(rf"(?m)^&{group}\s*$", f"&{group}\n  {key} = {val}", text, count=1)
    return text


def run(args, nranks, tag, env_extra=None):
    name = f"{tag}_np{nranks}"
    nml = os.path.join(args.workdir, name + ".nml")
    with open(nml, "w") as f:
        f.write(scene_text(args.scene, name, args.workdir, args.set))
    env = dict(os.environ)
    env.update(env_extra or {})
    cmd = [args.mpiexec, "--oversubscribe", "-n", str(nranks), args.dpmpm, nml]
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    log = r.stdout + r.stderr
    if r.returncode != 0:
        print(log)
        raise SystemExit(f"{' '.join(cmd)} ended with {r.returncode}")
    rewrites = [line for line in log.splitlines() if "rewritten" in line]
    return os.path.join(args.workdir, name + ".h5"), rewrites


def by_id(g):
    ids = g["id"][...]
    order = np.argsort(ids)
    return ids[order], order


def compare(ref, other, rtol):
    """Differences between two output files, as a list of strings (empty when equal)."""
    bad = []
    worst = 0.0
    with h5py.File(ref, "r") as a, h5py.File(other, "r") as b:
        fa, fb = sorted(a["frames"]), sorted(b["frames"])
        if fa != fb:
            return [f"frames {fa} against {fb}"], worst
        for fr in fa:
            ga, gb = a["frames"][fr], b["frames"][fr]
            # The time step is a reduction over ranks: its sums may differ in the last bit.
            ta, tb = ga.attrs["time"], gb.attrs["time"]
            if ga.attrs["step"] != gb.attrs["step"] or abs(ta - tb) > rtol * abs(ta):
                bad.append(f"frame {fr}: step {ga.attrs['step']} at {ta!r} against "
                           f"{gb.attrs['step']} at {tb!r}")
            if sorted(ga) != sorted(gb):
                bad.append(f"frame {fr}: sets {sorted(ga)} against {sorted(gb)}")
                continue
            for s in ga:
                ida, oa = by_id(ga[s])
                idb, ob = by_id(gb[s])
                if len(np.unique(idb)) != len(idb) or not np.array_equal(ida, idb):
                    bad.append(f"frame {fr}/{s}: ids differ ({len(ida)} against {len(idb)}, "
                               f"{np.setdiff1d(ida, idb).size} missing)")
                    continue
                if sorted(ga[s]) != sorted(gb[s]):
                    bad.append(f"frame {fr}/{s}: datasets {sorted(ga[s])} against "
                               f"{sorted(gb[s])}")
                    continue
                for d in ga[s]:
                    if d == "id":
                        continue
                    va, vb = ga[s][d][...][oa], gb[s][d][...][ob]
                    if va.shape != vb.shape:
                        bad.append(f"frame {fr}/{s}/{d}: shape {va.shape} against {vb.shape}")
                        continue
                    if va.dtype.kind in "iu":
                        if not np.array_equal(va, vb):
                            bad.append(f"frame {fr}/{s}/{d}: integers differ")
                        continue
                    scale = float(np.max(np.abs(va))) if va.size else 0.0
                    dev = float(np.max(np.abs(va - vb))) if va.size else 0.0
                    if not np.all(np.isfinite(vb)):
                        bad.append(f"frame {fr}/{s}/{d}: non-finite values")
                    elif dev > rtol * scale:
                        bad.append(f"frame {fr}/{s}/{d}: differs by {dev:.3e} "
                                   f"(largest value {scale:.3e})")
                    if scale > 0.0:
                        worst = max(worst, dev / scale)
    return bad, worst


def scene_arguments(doc):
    """The options of a check that runs a scene (--dpmpm, --mpiexec, --scene, --workdir),
    described by the first line of doc; the caller adds its own."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    for name in ("--dpmpm", "--mpiexec", "--scene", "--workdir"):
        ap.add_argument(name, required=True)
    return ap


def main():
    ap = scene_arguments(__doc__)
    ap.add_argument("--set", action="append", default=[], type=lambda s: s.split("=", 1),
                    help="[GROUP.]KEY=VALUE (namelist syntax; the group defaults to run, "
                         "or output for dir and frame_interval)")
    ap.add_argument("--ranks", nargs="+", type=int, default=[2, 3, 4])
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--ompio-runs", type=int, default=1)
    ap.add_argument("--rtol", type=float, default=1e-9)
    args = ap.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    tag = os.path.splitext(os.path.basename(args.scene))[0]

    ref, _ = run(args, 1, tag)
    files = []
    for n in args.ranks:
        for k in range(args.repeat if n > 2 else 1):
            files.append((f"{n} ranks, run {k + 1}", run(args, n, f"{tag}_r{k}")))
    for k in range(args.ompio_runs):
        files.append((f"3 ranks, OMPIO, run {k + 1}",
                      run(args, 3, f"{tag}_ompio{k}", {"OMPI_MCA_io": "ompio"})))

    failed = 0
    check = subprocess.run([sys.executable, CHECK_OUTPUT, ref] + [f for _, (f, _) in files],
                           capture_output=True, text=True)
    print(check.stdout.strip())
    if check.returncode != 0:
        failed += 1
    with h5py.File(ref, "r") as f:
        nframes = len(f["frames"])
    for label, (path, rewrites) in files:
        bad, worst = compare(ref, path, args.rtol)
        note = f"; {rewrites[-1].strip()}" if rewrites else ""
        print(f"{label}: {nframes} frames, largest relative deviation {worst:.2e}{note}")
        for b in bad[:10]:
            print("  " + b)
        failed += bool(bad)
    print(f"{len(files) + 1 - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
