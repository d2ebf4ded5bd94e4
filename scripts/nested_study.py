#!/usr/bin/env python3
"""The busiest rank over the mean with the grid split by points and by nested cuts
(doc/performance.md, "Nested cuts, measured").

restart: a checkpoint of a scene in flow (--checkpoint, with the input it was written from,
--input) restarted for --steps steps on each rank count with each split; the busiest rank
over the mean at the start of the restarted run, from the start line of its log ("per rank
min N max M"). scene: a scene of inputs/ run to its end on each rank count with each split,
the rank of every point written in each frame (&output solid_fields = 'all rank'); the
busiest rank over the mean at the start, averaged over the frames, and the largest. Ranks
may outnumber cores: the counts do not depend on the timing.

    python3 scripts/nested_study.py restart --input flow.nml --checkpoint out/flow.ckpt.h5
        --step 6000 [--ranks 4,8,16] [--balance points,nested] [--out build/nested]
    python3 scripts/nested_study.py scene [--scene c1_a2] [--ranks 4,8]
        [--balance cells,points,nested] [--out build/nested]
"""
import argparse
import os
import re
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")


def with_split(text, balance, outdir):
    """The input text with the split chosen and its output in outdir."""
    text = re.sub(r"(?m)^\s*dir\s*=.*$", f"  dir = '{outdir}'", text)
    text = re.sub(r"(?m)^\s*balance\s*=.*$", "", text)
    return re.sub(r"(?m)^&grid\b", f"&grid\n  balance = '{balance}'", text, count=1)


def run(build, outdir, tag, text, ranks):
    """Run dpmpm on the text; the log's text."""
    os.makedirs(outdir, exist_ok=True)
    nml = os.path.join(outdir, tag + ".nml")
    with open(nml, "w") as f:
        f.write(text)
    logpath = os.path.join(outdir, tag + ".log")
    with open(logpath, "w") as log:
        subprocess.run(["mpirun", "--oversubscribe", "-n", str(ranks), os.path.join(build, "dpmpm"), nml],
                       stdout=log, stderr=subprocess.STDOUT, env=ENV, check=True)
    with open(logpath) as f:
        return f.read()


def start_ratio(log, ranks):
    """Busiest rank over the mean from the start line of a log."""
    m = re.search(r"; (\d+) solid points; per rank min (\d+) max (\d+)", log)
    total, busiest = int(m.group(1)), int(m.group(3))
    return busiest / (total / ranks)


def frame_ratios(path, ranks):
    """Busiest rank over the mean in every frame of an output file."""
    import h5py
    import numpy as np
    out = []
    with h5py.File(path, "r") as f:
        for key in sorted(f["frames"].keys()):
            fr = f["frames"][key]
            counts = np.zeros(ranks)
            for s in ("solid", "fluid"):
                if s in fr and "rank" in fr[s]:
                    counts += np.bincount(np.asarray(fr[s]["rank"][()], dtype=int), minlength=ranks)
            if counts.sum() > 0:
                out.append(counts.max() / counts.mean())
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mode", choices=["restart", "scene"])
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--ranks", default=None)
    ap.add_argument("--balance", default=None)
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "nested"))
    ap.add_argument("--input")
    ap.add_argument("--checkpoint")
    ap.add_argument("--step", type=int, help="the checkpoint's step")
    ap.add_argument("--steps", type=int, default=25)
    ap.add_argument("--scene", default="c1_a2")
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    if a.mode == "restart":
        ranks = [int(r) for r in (a.ranks or "4,8,16").split(",")]
        balances = (a.balance or "points,nested").split(",")
        with open(a.input) as f:
            base = f.read()
        base = re.sub(r"(?m)^&run\b", f"&run\n  restart = '{os.path.abspath(a.checkpoint)}'\n"
                      f"  max_steps = {a.step + a.steps}", base, count=1)
        print("ranks " + " ".join(f"{b:>8}" for b in balances))
        for n in ranks:
            row = []
            for b in balances:
                tag = f"restart_{b}_np{n}"
                log = run(a.build, os.path.join(out, tag), tag, with_split(base, b, os.path.join(out, tag)), n)
                row.append(start_ratio(log, n))
            print(f"{n:5d} " + " ".join(f"{r:8.2f}" for r in row), flush=True)
    else:
        ranks = [int(r) for r in (a.ranks or "4,8").split(",")]
        balances = (a.balance or "cells,points,nested").split(",")
        with open(os.path.join(ROOT, "inputs", a.scene + ".nml")) as f:
            base = f.read()
        base = re.sub(r"(?m)^&output\b", "&output\n  solid_fields = 'all rank'\n  fluid_fields = 'all rank'",
                      base, count=1)
        name = re.search(r"(?m)^\s*name\s*=\s*'([^']+)'", base).group(1)
        print(f"{a.scene}: busiest rank / mean: start, mean over the frames, largest")
        for n in ranks:
            for b in balances:
                tag = f"{a.scene}_{b}_np{n}"
                d = os.path.join(out, tag)
                run(a.build, d, tag, with_split(base, b, d), n)
                r = frame_ratios(os.path.join(d, name + ".h5"), n)
                print(f"  {n:3d} ranks {b:>7}: {r[0]:5.2f} {sum(r) / len(r):5.2f} {max(r):5.2f}"
                      f"  ({len(r)} frames)", flush=True)


if __name__ == "__main__":
    main()
