#!/usr/bin/env python3
"""A model of dpmpm's weak scaling beyond one machine, written into doc/performance.md.

Measures the costs of the parallel layer with build/release/dpmpm_comm_bench on 1 and 2
ranks (halo_sum and halo_copy of node fields split along each axis, MPI_Allreduce, a bare
MPI_Sendrecv, migrate with points crossing to the neighbour), --repeat times alternating
between the rank counts (each run gives medians over its rounds; the least disturbed run,
the smallest median, is kept for each row, since the 2 cores are shared with other work),
fits a per-stage latency alpha, a per-node cost gamma and a per-byte cost 1/beta to the
halo exchanges, and predicts the time of a step at P ranks for a fixed number of points
per rank:

    T(P) = T(1) + halo(P) + migration(P) + allreduce(P)

- T(1): the step of one rank, from the tables of doc/performance.md written by
  scripts/bench.py (it already holds the local work of the halo calls and of migrate);
- halo(P): per halo call and per split axis, two stages of alpha + slab nodes * gamma +
  slab bytes / beta, the slab gw nodes thick over the stored extent of the other axes
  (dpmpm_decomp);
- migration(P): per point set and split axis, the measured extra cost of migrate_axis
  when points cross (it bins every point; the removal moves the last points of the set
  into the places of those that left) plus a cost per crossing point; a fraction s of
  the points of the cell layer next to each face crosses it per step;
- allreduce(P): the reductions of a step, each ceil(log2 P) levels of the measured
  2-rank latency (a tree).

The efficiency is T(1)/T(P). The halo and migration counts per step are those of the
step code for the two cases of scripts/bench.py (CASES below; doc/performance.md lists
them with file and line). A second set of columns adds an InfiniBand HDR network
(documented latency and bandwidth) to the on-node costs.

Usage: scripts/scaling_model.py [--rounds 9] [--repeat 3] [--wait-load X] [--from DIR] [--quick]
                                [--no-doc] [--crossing 0.1] [--ranks-per-node 64]
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
BIN = os.path.join(ROOT, "build", "release", "dpmpm_comm_bench")
DOC = os.path.join(ROOT, "doc", "performance.md")
OUT = os.path.join(ROOT, "build", "bench")
BEGIN, END = "<!-- scaling-model:begin -->", "<!-- scaling-model:end -->"
BENCH_BEGIN, BENCH_END = "<!-- bench:begin -->", "<!-- bench:end -->"
ANCHOR = "## Earlier measurements"
TITLE = "## Beyond one machine: a model of weak scaling"
# The Open MPI settings of scripts/common.sh (root, more ranks than cores, no single-copy
# transport in containers), so that the costs are those of scripts/bench.sh's runs.
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
ENV.setdefault("OMPI_MCA_btl_vader_single_copy_mechanism", "none")

# An InfiniBand HDR network, from documentation. The adapter: 200 Gb/s per port (25 GB/s)
# and "sub-600ns latency" (NVIDIA ConnectX-6 user manual,
# https://docs.nvidia.com/networking/display/ConnectX6EN/Introduction). An MPI message
# adds the MPI software and a switch hop: an osu_latency table of MPICH over InfiniBand
# (UCX) reads 0.93 us for small messages, https://gist.github.com/jfgrimm/3af692a5475bdd4ed836b5a18197a209.
# Taken here: 1 us per message and 25 GB/s per node, added to the on-node costs measured.
NET_ALPHA = 1.0e-6
NET_BANDWIDTH = 25.0e9
NET_SOURCES = ("https://docs.nvidia.com/networking/display/ConnectX6EN/Introduction",
               "https://gist.github.com/jfgrimm/3af692a5475bdd4ed836b5a18197a209")

RANKS = (2, 64, 1000, 10000)
# The halo fits take the subdomains up to about twice the largest of the model (cells per
# axis): larger fields leave the caches, which a rank of the model's size does not see.
FIT_CELLS = {2: 512, 3: 64}
POINTS = (16384, 65536, 262144)

# What one step communicates (src/solver/dpmpm_step.f90 and the loop of
# src/solver/dpmpm_simulation.f90), per case: halo calls (exchange, components),
# reductions per step, point sets migrated. nd is the dimension.
def one_phase_calls(nd):
    """One phase, MUSL, quadratic B-spline: p2g sum, nodal copy, remap sum, remap copy."""
    return [("halo_sum", 1 + 2 * nd), ("halo_copy", 2 * nd),
            ("halo_sum", 1 + 2 * nd), ("halo_copy", 2 * nd)]


def two_phase_calls(nd):
    """Two phases, MUSL, linear, implicit drag, defaults of &run (free surface on,
    remap_drag on, porosity_gradient off)."""
    node, vel = 1 + 2 * nd, 2 * nd
    return [("halo_sum", node), ("halo_sum", node),        # p2g, both phases
            ("halo_sum", 3), ("halo_sum", 1),              # nodal porosity, drag
            ("halo_sum", 1), ("halo_copy", 1),             # free-surface volume
            ("halo_copy", 3),                              # porosity to the ghosts
            ("halo_copy", vel), ("halo_copy", vel),        # nodal velocities
            ("halo_copy", nd),                             # locked velocity (remap)
            ("halo_sum", node), ("halo_sum", node),        # remap momenta
            ("halo_sum", nd), ("halo_sum", nd),            # projections of the split
            ("halo_copy", vel), ("halo_copy", vel)]        # remapped velocities


# Reductions per step: the time step and the validity scan every step, one in each
# migrate; the stop request every 10 steps; 3 in a diagnostics record (every 100 steps
# in the scenes of scripts/bench.py).
CASES = {
    "one": {"title": "one phase, quadratic B-spline, MUSL", "gw": 2, "calls": one_phase_calls,
            "sets": 1, "allreduce": 3 + 0.1 + 3 / 100},
    "two": {"title": "two phases, linear, MUSL, implicit drag", "gw": 1, "calls": two_phase_calls,
            "sets": 2, "allreduce": 4 + 0.1 + 3 / 100},
}
PPC = {2: 4, 3: 8}   # points per cell of the benchmark blocks (2 per axis)


def run_bench(nranks, rounds, quick):
    cmd = ["mpirun", "--oversubscribe", "-n", str(nranks), BIN]
    cmd += ["--quick"] if quick else ["--rounds", str(rounds)]
    out = subprocess.run(cmd, env=ENV, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"scaling_model: dpmpm_comm_bench failed on {nranks} ranks:\n"
                 f"{out.stdout[-2000:]}\n{out.stderr[-2000:]}")
    return out.stdout


COLUMNS = ("op ndim axis n gw ncomp npoints fraction nranks stages bytes nsent calls "
           "t_median t_min t_max").split()


def parse(texts):
    """The rows of one or more runs of the bench; of a row measured in several runs, the
    run with the smallest median."""
    best = {}
    for text in texts:
        for r in parse_one(text):
            key = tuple(r[k] for k in COLUMNS[:9])
            if key not in best or r["t_median"] < best[key]["t_median"]:
                best[key] = r
    return list(best.values())


def parse_one(text):
    rows = []
    for line in text.splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        f = line.split()
        if len(f) != len(COLUMNS):
            sys.exit(f"scaling_model: unexpected line from dpmpm_comm_bench: {line}")
        r = dict(zip(COLUMNS, f))
        for k in COLUMNS[1:]:
            r[k] = float(r[k]) if k in ("fraction", "t_median", "t_min", "t_max") else int(r[k])
        rows.append(r)
    return rows


def fit_line(x, y, w=None):
    """Least squares y = a + b x (weights w on the residuals); returns a, b."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    w = np.ones_like(y) if w is None else np.asarray(w, float)
    A = np.column_stack([np.ones_like(x), x]) * w[:, None]
    (a, b), *_ = np.linalg.lstsq(A, y * w, rcond=None)
    return float(a), float(b)


def nonneg_lstsq(A, y, w):
    """Weighted least squares with coefficients >= 0 (a coefficient that comes out
    negative is dropped and the others fitted again)."""
    keep = list(range(A.shape[1]))
    while True:
        c, *_ = np.linalg.lstsq(A[:, keep] * w[:, None], y * w, rcond=None)
        if (c >= 0).all() or len(keep) == 1:
            x = np.zeros(A.shape[1])
            x[keep] = np.maximum(c, 0.0)
            return x
        keep.pop(int(np.argmin(c)))


def fit_halo(one, two):
    """Per exchange, dimension and split axis: the 2-rank time less the 1-rank time of
    the same field, fitted as stages * alpha + nodes * gamma + bytes / beta (nodes: slab
    nodes over the stages), and as stages * alpha + bytes / beta; relative residuals."""
    base = {(r["op"], r["ndim"], r["n"], r["gw"], r["ncomp"]): r["t_median"] for r in one
            if r["op"].startswith("halo")}
    groups = {}
    for r in two:
        if not r["op"].startswith("halo"):
            continue
        key = (r["op"], r["ndim"], r["n"], r["gw"], r["ncomp"])
        if key not in base or r["n"] > FIT_CELLS[r["ndim"]]:
            continue
        groups.setdefault((r["op"], r["ndim"], r["axis"]), []).append(
            (r["stages"], r["bytes"], r["t_median"] - base[key], r["t_median"], r["ncomp"]))
    fits = {}
    for g, rows in sorted(groups.items()):
        st = np.array([x[0] for x in rows], float)
        by = np.array([x[1] for x in rows], float)
        nodes = np.array([x[1] / (8 * x[4]) for x in rows], float)
        d = np.array([x[2] for x in rows], float)
        t2 = np.array([x[3] for x in rows], float)
        w = 1.0 / t2
        A = np.column_stack([st, nodes, by])
        c3 = nonneg_lstsq(A, d, w)
        c2 = nonneg_lstsq(A[:, [0, 2]], d, w)
        # the misfit: root mean square of the error relative to the exchange's cost
        mis = lambda m: float(np.sqrt(np.mean(((m - d) / d) ** 2)))  # noqa: E731
        fits[g] = {"alpha": c3[0], "gamma": c3[1], "inv_beta": c3[2], "misfit": mis(A @ c3),
                   "alpha2": c2[0], "inv_beta2": c2[1], "misfit2": mis(A[:, [0, 2]] @ c2),
                   "rows": len(rows)}
    return fits


def fit_migration(one, two):
    """Per dimension and set size: the 1-rank migrate (no neighbour: the ownership scan
    only), the 2-rank one without crossing points, the 2-rank one with crossing points
    fitted as a + c * nsent (points spread over the set, and the last points of the set),
    and from them the extra cost of one split axis."""
    res = {}
    for nd in (2, 3):
        for n in sorted({r["n"] for r in one if r["op"] == "migrate" and r["ndim"] == nd}):
            t1 = [r for r in one if r["op"] == "migrate" and r["ndim"] == nd and r["n"] == n][0]
            sel = lambda op: [r for r in two if r["op"] == op and r["ndim"] == nd and r["n"] == n]  # noqa: E731
            none = [r for r in sel("migrate") if r["nsent"] == 0]
            spread = [r for r in sel("migrate") if r["nsent"] > 0]
            tail = [r for r in sel("migrate_tail") if r["nsent"] > 0]
            if not none or not spread:
                continue
            line = lambda rows: fit_line([r["nsent"] for r in rows], [r["t_median"] for r in rows]) \
                if len(rows) >= 2 else (rows[0]["t_median"], 0.0) if rows else (float("nan"), 0.0)  # noqa: E731
            a, c = line(spread)
            at, ct = line(tail)
            res[(nd, n)] = {"npoints": t1["npoints"], "nreal": t1["ncomp"], "t1": t1["t_median"],
                            "none": none[0]["t_median"], "cross": a, "per_point": c,
                            "cross_tail": at, "per_point_tail": ct}
    return res


def dims_create(p, nd):
    """A balanced split of p ranks over nd axes, as MPI_Dims_create makes it: the prime
    factors, largest first, each to the axis with the fewest ranks so far."""
    f, q, k = [], p, 2
    while k * k <= q:
        while q % k == 0:
            f.append(k)
            q //= k
        k += 1
    if q > 1:
        f.append(q)
    dims = [1] * nd
    for x in sorted(f, reverse=True):
        dims[dims.index(min(dims))] *= x
    return sorted(dims, reverse=True)


def read_doc_costs():
    """The step times of one rank from the tables scripts/bench.py wrote."""
    with open(DOC) as f:
        doc = f.read()
    if BENCH_BEGIN not in doc or BENCH_END not in doc:
        sys.exit("scaling_model: no bench tables in doc/performance.md (run scripts/bench.sh)")
    b = doc[doc.index(BENCH_BEGIN):doc.index(BENCH_END)]

    def find(pattern, what):
        m = re.search(pattern, b)
        if not m:
            sys.exit(f"scaling_model: {what} not found in the bench tables of doc/performance.md")
        return m

    c = {}
    m = find(r"\| weak \| (\d+) \| 1 \| ([0-9.]+) \|", "the weak-scaling line on 1 rank")
    c["one", 2] = {"points": int(m.group(1)), "ms": float(m.group(2)),
                   "from": "scaling table, weak, 1 rank (a block filling a 360 x 180 grid)"}
    m = find(r"\| 3D \| quadratic \| MUSL \| (\d+) \| ([0-9.]+)", "the 3D quadratic MUSL line")
    c["one", 3] = {"points": int(m.group(1)), "ms": float(m.group(2)),
                   "from": "one-phase table, 3D quadratic MUSL"}
    for nd in (2, 3):
        m = find(rf"\| {nd}D \| (\d+) \| ([0-9.]+) \| ([0-9.]+) \| ([0-9.]+)", f"the {nd}D two-phase line")
        c["two", nd] = {"points": int(m.group(1)), "ms": float(m.group(3)),
                        "from": f"two-phase table, {nd}D saturated (per solid point)"}
    m = find(r"\| weak \| (\d+) \| 2 \| ([0-9.]+) \| [0-9.]+ \| efficiency ([0-9.]+) \(([0-9.]+) - ([0-9.]+)\)",
             "the weak-scaling line on 2 ranks")
    c["weak2"] = {"ms": float(m.group(2)), "eff": float(m.group(3)), "lo": float(m.group(4)),
                  "hi": float(m.group(5))}
    m = find(r"\| strong \| (\d+) \| 1 \| ([0-9.]+) \|", "the strong-scaling line on 1 rank")
    c["strong1"] = {"points": int(m.group(1)), "ms": float(m.group(2))}
    m = find(r"speed-up ([0-9.]+) \(([0-9.]+) - ([0-9.]+)\)", "the 2-rank speed-up")
    c["speedup"] = {"value": float(m.group(1)), "lo": float(m.group(2)), "hi": float(m.group(3))}
    return c


class Model:
    """Extra time per step at P ranks over the step of one rank."""

    def __init__(self, halo, mig, allreduce_level, crossing):
        self.halo_fit = halo
        self.mig = mig
        self.level = allreduce_level
        self.crossing = crossing
        # migration cost of one split axis per point of the set, at the measured set sizes
        # (interpolated between them, held beyond them), with points crossing (spread over
        # the set, or the last ones) and without; and the cost per crossing point
        self.mig_fit = {}
        for nd in (2, 3):
            rows = [v for (d, _), v in sorted(mig.items()) if d == nd]
            if not rows:
                continue
            npts = [v["npoints"] for v in rows]
            per = lambda key: [max(0.0, v[key] - v["t1"]) / v["npoints"] for v in rows]  # noqa: E731
            self.mig_fit[nd] = {
                "sizes": npts, "cross": per("cross"), "tail": per("cross_tail"), "none": per("none"),
                # (a slope below the noise can come out negative: no cost then)
                "per_point": max(0.0, float(np.median([v["per_point"] for v in rows]))),
                "nreal": rows[0]["nreal"]}

    def extra(self, case, nd, cells, dims, faces, net=None, removal="cross"):
        """Seconds per step added by P ranks: halo, migration, reductions. cells: cells
        per rank along each axis; dims: ranks per axis; faces: neighbour faces per axis;
        net: None (on-node costs) or (alpha, bytes per second per rank, off-node levels);
        removal: "cross" (departed points spread over the set, as the code meets them) or
        "tail" (the cost measured when they are the last points of the set, so that no
        point moves into their places)."""
        cfg = CASES[case]
        gw = cfg["gw"]
        n_alpha, n_inv_beta, levels_off = (0.0, 0.0, 0) if net is None else \
            (net[0], 1.0 / net[1], net[2])
        split = [d for d in range(nd) if dims[d] > 1]
        halo = 0.0
        for op, ncomp in cfg["calls"](nd):
            for d in split:
                f = self.halo_fit[(op, nd, d + 1)]
                nodes = gw * math.prod(cells[e] + 2 * gw for e in range(nd) if e != d)
                slab = 8 * ncomp * nodes
                halo += 2 * (f["alpha"] + n_alpha + nodes * f["gamma"] + slab * (f["inv_beta"] + n_inv_beta))
        mf = self.mig_fit[nd]
        npts = PPC[nd] * math.prod(cells)
        sent = sum(faces[d] * self.crossing * PPC[nd] * math.prod(cells[e] for e in range(nd) if e != d)
                   for d in split)
        axis_cost = npts * float(np.interp(npts, mf["sizes"], mf[removal] if sent > 0 else mf["none"]))
        mig = cfg["sets"] * (len(split) * (axis_cost + 4 * n_alpha)
                             + sent * (mf["per_point"] + 8 * mf["nreal"] * n_inv_beta))
        p = math.prod(dims)
        levels = math.ceil(math.log2(p)) if p > 1 else 0
        ar = cfg["allreduce"] * (levels * self.level + levels_off * n_alpha)
        return halo, mig, ar


def fmt_ms(s):
    return f"{1e3 * s:.3f}" if s < 0.01 else f"{1e3 * s:.2f}" if s < 0.1 else f"{1e3 * s:.1f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=9, help="rounds of each measurement (median)")
    ap.add_argument("--repeat", type=int, default=3, help="runs of the bench per rank count (the "
                    "smallest median of each row is kept)")
    ap.add_argument("--wait-load", type=float, default=0.0, help="before each run, wait (up to 10 "
                    "minutes) until the 1-minute load average is below this")
    ap.add_argument("--from", dest="src", help="read comm_np1.txt and comm_np2.txt from this "
                    "directory instead of measuring")
    ap.add_argument("--quick", action="store_true", help="tiny sizes (a smoke run of the script)")
    ap.add_argument("--no-doc", action="store_true", help="print only; leave doc/performance.md")
    ap.add_argument("--crossing", type=float, default=0.1,
                    help="fraction of a cell layer crossing each face per step (cells moved per step)")
    ap.add_argument("--ranks-per-node", type=int, default=64)
    a = ap.parse_args()
    t_start = time.time()
    os.makedirs(OUT, exist_ok=True)
    if a.src:
        with open(os.path.join(a.src, "comm_np1.txt")) as f:
            raw1 = f.read()
        with open(os.path.join(a.src, "comm_np2.txt")) as f:
            raw2 = f.read()
    else:
        if not os.path.exists(BIN):
            subprocess.run(["cmake", "--preset", "release"], cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
            subprocess.run(["cmake", "--build", "--preset", "release", "--target", "dpmpm_comm_bench"],
                           cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
        raw1, raw2 = "", ""
        for _ in range(1 if a.quick else a.repeat):
            for nranks in (1, 2):
                waited = 0
                while a.wait_load > 0 and os.getloadavg()[0] >= a.wait_load and waited < 600:
                    time.sleep(10)
                    waited += 10
                note = f"# load average before this run: {os.getloadavg()[0]:.2f}\n"
                if nranks == 1:
                    raw1 += note + run_bench(1, a.rounds, a.quick)
                else:
                    raw2 += note + run_bench(2, a.rounds, a.quick)
        for name, raw in (("comm_np1.txt", raw1), ("comm_np2.txt", raw2)):
            with open(os.path.join(OUT, name), "w") as f:
                f.write(raw)
    runs = lambda raw: re.split(r"^(?=# dpmpm_comm_bench)", raw, flags=re.M)  # noqa: E731
    one, two = parse(runs(raw1)), parse(runs(raw2))
    nruns = len(re.findall(r"^# dpmpm_comm_bench", raw2, flags=re.M))
    loads = lambda raw: ", ".join(re.findall(r"^# load average before this run: ([0-9.]+)", raw, flags=re.M)) \
        or "not recorded"  # noqa: E731
    halo = fit_halo(one, two)
    mig = fit_migration(one, two)
    get = lambda rows, op, n: [r for r in rows if r["op"] == op and r["n"] == n][0]  # noqa: E731
    ar1 = {c: get(one, "allreduce", c)["t_median"] for c in (1, 10)}
    ar2 = {c: get(two, "allreduce", c)["t_median"] for c in (1, 10)}
    level = ar2[1] - ar1[1]
    sr = [(r["bytes"], r["t_median"] - get(one, "sendrecv", r["n"])["t_median"], r["t_median"])
          for r in two if r["op"] == "sendrecv"]
    sr_a, sr_b = fit_line([x[0] for x in sr], [x[1] for x in sr], [1.0 / x[2] for x in sr])
    costs = read_doc_costs()
    model = Model(halo, mig, level, a.crossing)
    still = Model(halo, mig, level, 0.0)
    q = a.ranks_per_node
    cpu = subprocess.run(["sh", "-c", "grep -m1 'model name' /proc/cpuinfo | cut -d: -f2"],
                         capture_output=True, text=True).stdout.strip()
    mpi = subprocess.run(["mpirun", "--version"], capture_output=True, text=True).stdout.splitlines()
    mpi = re.sub(r"^mpirun \(([^)]*)\) ", r"\1 ", mpi[0]) if mpi else "MPI"

    md = []
    md.append(f"Written by `scripts/scaling_model.py`: `dpmpm_comm_bench` on 1 and 2 ranks "
              f"({os.cpu_count()} cores, {cpu}, {mpi}, shared memory; the 2 ranks share the "
              f"virtual machine's 2 cores with whatever else runs), release build; each row the "
              f"median of {a.rounds if not a.quick else 2} rounds, of the least disturbed of {nruns} "
              f"runs; 1-minute load average before each run, 1 rank: {loads(raw1)}; 2 ranks: {loads(raw2)}. "
              "Raw tables: `build/bench/comm_np1.txt`, `comm_np2.txt`.\n")

    md.append("#### Measured: one halo stage\n")
    md.append("The 2-rank time of `halo_sum` / `halo_copy` less the 1-rank time of the same field "
              f"(1 and 1 + 2 nd components, gw 1 and 2, 2D 32² to {FIT_CELLS[2]}² and 3D 16³ to "
              f"{FIT_CELLS[3]}³ cells per rank), fitted as 2 (alpha + nodes gamma + bytes / beta): two "
              "stages, each moving one slab of `nodes` nodes; relative residuals, coefficients >= 0; "
              "misfit: root mean square of the relative error of the fit. The cost per byte "
              "holds the packing of the slab, the transport and the unpacking (adding, for a sum). "
              "The last columns fit 2 (alpha + bytes / beta) alone.\n")
    md.append("| exchange | dim | split axis | alpha (us) | gamma (ns / node) | beta (GB/s) | "
              "misfit | alpha, 2 terms (us) | beta, 2 terms (GB/s) | misfit |")
    md.append("|---|---|---|---|---|---|---|---|---|---|")
    gbs = lambda inv: f"{1e-9 / inv:.2f}" if inv > 0 else "inf"  # noqa: E731
    for (op, nd, ax), f in sorted(halo.items(), key=lambda kv: (kv[0][1], kv[0][0], kv[0][2])):
        md.append(f"| {op} | {nd}D | {'xyz'[ax - 1]} | {1e6 * f['alpha']:.2f} | {1e9 * f['gamma']:.2f} | "
                  f"{gbs(f['inv_beta'])} | {100 * f['misfit']:.0f} % | {1e6 * f['alpha2']:.2f} | "
                  f"{gbs(f['inv_beta2'])} | {100 * f['misfit2']:.0f} % |")
    md.append("")
    md.append(f"Bare `MPI_Sendrecv` of 1 to 2^20 doubles between the 2 ranks: alpha "
              f"{1e6 * sr_a:.2f} us, beta {1e-9 / sr_b:.2f} GB/s. `MPI_Allreduce` of 1 double: "
              f"{1e6 * ar2[1]:.2f} us on 2 ranks ({1e6 * ar1[1]:.3f} us on 1); of 10 doubles: "
              f"{1e6 * ar2[10]:.2f} us ({1e6 * ar1[10]:.3f} us).\n")

    md.append("#### Measured: migration (split along x, 2 points per cell and axis, neo-Hookean points)\n")
    md.append("| dim | points per rank | 1 rank (ms) | 2 ranks, no point crossing (ms) | "
              "2 ranks, points crossing: intercept (ms) | the same, the last points crossing (ms) | "
              "per crossing point (us) |")
    md.append("|---|---|---|---|---|---|---|")
    for (nd, n), v in sorted(mig.items()):
        md.append(f"| {nd}D | {v['npoints']} | {fmt_ms(v['t1'])} | {fmt_ms(v['none'])} | "
                  f"{fmt_ms(v['cross'])} | {fmt_ms(v['cross_tail'])} | {1e6 * v['per_point']:.2f} |")
    md.append("")

    md.append("#### Counted: communication of one step\n")
    md.append("| case | halo_sum calls (components) | halo_copy calls (components) | "
              "reductions per step | point sets migrated |")
    md.append("|---|---|---|---|---|")
    for case, cfg in CASES.items():
        for nd in (2, 3):
            calls = cfg["calls"](nd)
            s = [c for o, c in calls if o == "halo_sum"]
            c = [c for o, c in calls if o == "halo_copy"]
            md.append(f"| {cfg['title']}, {nd}D | {len(s)} ({' + '.join(map(str, s))} = {sum(s)}) | "
                      f"{len(c)} ({' + '.join(map(str, c))} = {sum(c)}) | {cfg['allreduce']:.2f} | "
                      f"{cfg['sets']} |")
    md.append("")

    # The check: the bench's 2-rank weak-scaling run (2D, quadratic, MUSL, 360 x 360 cells
    # split in two along x: 180 x 360 cells and 259 200 points per rank).
    md.append("#### Check against the measured 2-rank run\n")
    w1 = costs["one", 2]
    t1 = w1["ms"] * 1e-3
    chk = {}
    for s in (0.0, a.crossing):
        m2 = Model(halo, mig, level, s)
        h, mg, ar = m2.extra("one", 2, [180, 360], [2, 1], [1, 0])
        chk[s] = (h, mg, ar, t1 / (t1 + h + mg + ar),
                  costs["strong1"]["ms"] * 1e-3 / (t1 + h + mg + ar))
    md.append("The block of the scaling table in the bench section (2D, quadratic, MUSL, 259 200 points "
              "per rank, 180 x 360 cells per rank on 2 ranks):\n")
    md.append("| | weak efficiency | speed-up (518 400 points) | halo (ms) | migration (ms) | reductions (ms) |")
    md.append("|---|---|---|---|---|---|")
    md.append(f"| measured (bench table) | {costs['weak2']['eff']:.2f} ({costs['weak2']['lo']:.2f} - "
              f"{costs['weak2']['hi']:.2f}) | {costs['speedup']['value']:.2f} ({costs['speedup']['lo']:.2f} - "
              f"{costs['speedup']['hi']:.2f}) | | | |")
    for s, (h, mg, ar, eff, sp) in chk.items():
        label = "model, no point crossing" if s == 0 else f"model, crossing s = {s}"
        md.append(f"| {label} | {eff:.2f} | {sp:.2f} | {fmt_ms(h)} | {fmt_ms(mg)} | {fmt_ms(ar)} |")
    md.append("")

    # The predictions.
    res = {"halo": {f"{k[0]}_{k[1]}d_{'xyz'[k[2] - 1]}": v for k, v in halo.items()},
           "migration": {f"{k[0]}d_{k[1]}": v for k, v in mig.items()},
           "allreduce": {"np1": ar1, "np2": ar2}, "sendrecv": {"alpha": sr_a, "inv_beta": sr_b},
           "predictions": []}
    for case, cfg in CASES.items():
        md.append(f"#### Predicted weak scaling: {cfg['title']}\n")
        md.append(f"The time a step adds on this machine's costs (s = {a.crossing}), and the efficiency "
                  f"T(1)/T(P): on this machine's costs (s = {a.crossing}; no point crossing; the "
                  "last points of the set crossing, so that no point moves into their places), and "
                  f"with the HDR network, 1 rank and {q} ranks per node (s = {a.crossing}).\n")
        md.append(f"| dim | {'points' if cfg['sets'] == 1 else 'points of each phase'} / rank | cells / rank | "
                  "P | dims | T(1) (ms) | halo (ms) | migration (ms) | "
                  "reductions (ms) | efficiency, on node | no crossing | last points crossing | HDR, 1 rank / node | "
                  f"HDR, {q} ranks / node |")
        md.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for nd in (2, 3):
            c = costs[case, nd]
            tpt = c["ms"] * 1e-3 / c["points"]
            for npts in POINTS:
                n = (npts / PPC[nd]) ** (1.0 / nd)
                t1 = npts * tpt
                for p in RANKS:
                    dims = dims_create(p, nd)
                    cells = [n] * nd
                    faces = [min(x - 1, 2) for x in dims]
                    h, mg, ar = model.extra(case, nd, cells, dims, faces)
                    eff = t1 / (t1 + h + mg + ar)
                    eff0 = t1 / (t1 + sum(still.extra(case, nd, cells, dims, faces)))
                    efft = t1 / (t1 + sum(model.extra(case, nd, cells, dims, faces, removal="tail")))
                    levels = math.ceil(math.log2(p))
                    net1 = model.extra(case, nd, cells, dims, faces, (NET_ALPHA, NET_BANDWIDTH, levels))
                    eff1 = t1 / (t1 + sum(net1))
                    if p <= q:
                        effq = f"{eff:.2f} (one node)"
                    else:
                        share = NET_BANDWIDTH / q ** (1.0 - 1.0 / nd)
                        off = max(0, math.ceil(math.log2(p / q)))
                        netq = model.extra(case, nd, cells, dims, faces, (NET_ALPHA, share, off))
                        effq = f"{t1 / (t1 + sum(netq)):.2f}"
                    md.append(f"| {nd}D | {npts} | {n:.0f}{'²' if nd == 2 else '³'} | {p} | "
                              f"{' x '.join(map(str, dims))} | {fmt_ms(t1)} | {fmt_ms(h)} | {fmt_ms(mg)} | "
                              f"{fmt_ms(ar)} | {eff:.2f} | {eff0:.2f} | {efft:.2f} | {eff1:.2f} | {effq} |")
                    res["predictions"].append({"case": case, "nd": nd, "points": npts, "P": p, "dims": dims,
                                               "t1": t1, "halo": h, "migration": mg, "allreduce": ar,
                                               "eff": eff, "eff_no_crossing": eff0, "eff_last_points": efft,
                                               "eff_net": eff1})
        md.append("")
        md.append(f"T(1): {costs[case, 2]['from']} ({costs[case, 2]['ms']} ms for {costs[case, 2]['points']} "
                  f"points) and {costs[case, 3]['from']} ({costs[case, 3]['ms']} ms for "
                  f"{costs[case, 3]['points']} points), per point.\n")
    md.append(f"Network: {NET_ALPHA * 1e6:.1f} us per message and {NET_BANDWIDTH / 1e9:.0f} GB/s per node "
              f"({NET_SOURCES[0]}; the MPI latency from an osu_latency table of MPICH over InfiniBand, "
              f"{NET_SOURCES[1]}), added to the on-node alpha and 1/beta; with {q} ranks per node a rank "
              f"gets 25 GB/s / {q}^(1 - 1/nd) (the "
              f"off-node share of the halo of a cube of {q} ranks), and the first log2({q}) levels of a "
              f"reduction stay on the node. Crossing points: s = {a.crossing} of a cell layer per face and "
              f"step.\n")
    md.append(f"(The measurement and the model took {time.time() - t_start:.0f} s.)")
    text = "\n".join(md)
    print(text)
    with open(os.path.join(OUT, "scaling_model.json"), "w") as f:
        json.dump(res, f, indent=1, default=float)
    if not a.no_doc:
        with open(DOC) as f:
            doc = f.read()
        if BEGIN in doc and END in doc:
            doc = doc[:doc.index(BEGIN) + len(BEGIN)] + "\n" + text + "\n" + doc[doc.index(END):]
        elif ANCHOR in doc:
            block = f"{TITLE}\n\n{BEGIN}\n{text}\n{END}\n\n"
            doc = doc.replace(ANCHOR, block + ANCHOR, 1)
        else:
            print(f"scaling_model: neither the markers nor '{ANCHOR}' in {DOC}; not written", file=sys.stderr)
            return 0
        with open(DOC, "w") as f:
            f.write(doc)
        print(f"scaling_model: {DOC} updated", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
