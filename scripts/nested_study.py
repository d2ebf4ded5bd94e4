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
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402


def with_split(scene, balance, outdir):
    """A copy of the scene with the split chosen and its output in outdir."""
    s = scene.copy()
    s.set(grid={"balance": balance}, output={"dir": outdir})
    return s


def run(build, scene, ranks):
    """Run the scene (dpmpm.simulate, the log beside the output); the log's text."""
    r = dpmpm.simulate(scene, ranks=ranks, binary=os.path.join(build, "dpmpm"), progress=False)
    with open(r.log) as f:
        return f.read()


def start_ratio(log, ranks):
    """Busiest rank over the mean from the start line of a log."""
    m = re.search(r"; (\d+) solid points; per rank min (\d+) max (\d+)", log)
    total, busiest = int(m.group(1)), int(m.group(3))
    return busiest / (total / ranks)


def frame_ratios(path, ranks):
    """Busiest rank over the mean in every frame of an output file."""
    out = []
    with dpmpm.open_run(path) as run:
        for fr in run.frames:
            counts = np.zeros(ranks)
            for s in ("solid", "fluid"):
                if s in fr and "rank" in fr[s]:
                    counts += np.bincount(np.asarray(fr[s]["rank"], dtype=int), minlength=ranks)
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
        base = dpmpm.Scene.read(a.input)
        base.set(run={"restart": os.path.abspath(a.checkpoint), "max_steps": a.step + a.steps})
        print("ranks " + " ".join(f"{b:>8}" for b in balances))
        for n in ranks:
            row = []
            for b in balances:
                tag = f"restart_{b}_np{n}"
                log = run(a.build, with_split(base, b, os.path.join(out, tag)), n)
                row.append(start_ratio(log, n))
            print(f"{n:5d} " + " ".join(f"{r:8.2f}" for r in row), flush=True)
    else:
        ranks = [int(r) for r in (a.ranks or "4,8").split(",")]
        balances = (a.balance or "cells,points,nested").split(",")
        base = dpmpm.Scene.read(os.path.join(ROOT, "inputs", a.scene + ".nml"))
        base.set(output={"solid_fields": "all rank", "fluid_fields": "all rank"})
        print(f"{a.scene}: busiest rank / mean: start, mean over the frames, largest")
        for n in ranks:
            for b in balances:
                tag = f"{a.scene}_{b}_np{n}"
                d = os.path.join(out, tag)
                scene = with_split(base, b, d)
                run(a.build, scene, n)
                r = frame_ratios(scene.output_file(), n)
                print(f"  {n:3d} ranks {b:>7}: {r[0]:5.2f} {sum(r) / len(r):5.2f} {max(r):5.2f}"
                      f"  ({len(r)} frames)", flush=True)


if __name__ == "__main__":
    main()
