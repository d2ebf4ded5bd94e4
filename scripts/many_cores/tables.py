#!/usr/bin/env python3
"""Tables of the many-core study from its results.txt (run_scaling.sh), in Markdown:
strong scaling (A, B, and E with either split), weak scaling (C, M) against one rank and
against D (the same one-rank run 16 times at once), and the points of the busiest rank.

    python3 scripts/many_cores/tables.py results.txt"""
import re
import sys


def parse(path):
    runs, d = {}, None
    for line in open(path):
        m = re.match(r"(\S+) ranks=(\d+) ms_per_step=([0-9.]+)", line)
        if m:
            rec = {"ms": float(m.group(3))}
            p = re.search(r"(\d+) solid points; per rank min (\d+) max (\d+)", line)
            if p:
                rec["n"], rec["max"] = int(p.group(1)), int(p.group(3))
            for name, val in re.findall(r"time in (\w+) ([0-9.]+) s", line):
                rec[name] = float(val)
            runs[(m.group(1), int(m.group(2)))] = rec
        m = re.match(r"D (\d+) independent .*mean ms_per_step=([0-9.]+) max=([0-9.]+)", line)
        if m:
            d = (int(m.group(1)), float(m.group(2)), float(m.group(3)))
    return runs, d


def main(path):
    runs, d = parse(path)
    ranks = sorted({r for _, r in runs})
    print("| case | " + " | ".join(f"{r} rank{'s' if r > 1 else ''}" for r in ranks) + " |")
    print("|---|" + "---|" * len(ranks))
    for case in ("A", "B", "E_cells", "E_points", "E_nested"):
        if (case, 1) not in runs:
            continue
        t1 = runs[(case, 1)]["ms"]
        cells = []
        for r in ranks:
            rec = runs.get((case, r))
            cells.append("-" if rec is None else f"{rec['ms']:.1f} ms, x{t1 / rec['ms']:.2f} ({t1 / rec['ms'] / r:.2f})")
        print(f"| {case} (strong) | " + " | ".join(cells) + " |")
    for case in ("C", "M"):
        if (case, 1) not in runs:
            continue
        t1 = runs[(case, 1)]["ms"]
        cells = [f"{runs[(case, r)]['ms']:.1f} ms ({t1 / runs[(case, r)]['ms']:.2f})" for r in ranks if (case, r) in runs]
        print(f"| {case} (weak) | " + " | ".join(cells) + " |")
    if d:
        print(f"\nD: {d[0]} one-rank runs of C at once: mean {d[1]:.1f} ms per step, slowest {d[2]:.1f} ms "
              f"(C on 1 rank alone: {runs[('C', 1)]['ms']:.1f} ms); C on 16 ranks against D's mean: "
              f"{d[1] / runs[('C', 16)]['ms']:.2f}" if ("C", 16) in runs else "")
    print("\n| case | ranks | busiest rank / mean | ms per step |")
    print("|---|---|---|---|")
    for case in ("E_cells", "E_points", "E_nested"):
        for r in ranks:
            rec = runs.get((case, r))
            if rec and "max" in rec:
                print(f"| {case} | {r} | {rec['max'] / (rec['n'] / r):.2f} | {rec['ms']:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1])
