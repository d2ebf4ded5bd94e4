#!/usr/bin/env python3
"""Speed of dpmpm, measured and written into doc/performance.md (release build).

Every case runs dpmpm twice with the same scene cut at two step counts (max_steps); the
difference of the two step loops' times (the log's time per step times its steps: the
timer of the loop, without set-up and output) over the difference of the steps is the
time of a step, and the first, slower steps cancel. (The wall times of whole runs differ
by their output too: writing the last frame and the checkpoint took 22-51 ms more after
45 steps than after 5 in the 2-rank scaling run, 0.5-1.3 ms per step of a 21 ms step.) Each table runs --rounds rounds, and in each round
every case of the table once, in turn (one run at a time but for the pair of the
scaling case), so that the cases compared with one another, the peer included, run
within minutes of each other on this shared host; ratios are taken round by round. The
tables give the median and the range. Cases:

- one phase, a neo-Hookean block falling onto a fixed floor (2D: 82 944 points on a
  360 x 360 grid; 3D: 110 592 points on 64^3), linear and quadratic kernels, USL and
  MUSL, one rank; with the share of each stage of the step (timers of the longer run)
  and the memory per point;
- the speed peer: the same block with an MLS-MPM step written with Taichi
  (scripts/peer_taichi.py: CPU, one thread, double precision), when taichi imports;
- two phases: a saturated block against the dry one with the same solid points
  (2D and 3D, linear, implicit drag), and the dry one with twice its points (a second
  set over the first): what the saturated step costs beyond its number of points;
- the MLS pair of doc/theory.md 3.6, linear grid functions with one Gauss point per
  cell and the cubic B-spline (the pair's grid functions with point quadrature) against
  Standard MPM on inputs/w1_2d.nml and w1_3d.nml: wall time per simulated second;
- scaling: a balanced block filling the grid (2D, quadratic, MUSL): strong, 518 400
  points on 1 and 2 ranks; weak, 259 200 points on 1 rank against 518 400 on 2; and the
  host's own limit, two independent 1-rank runs of 259 200 points at once against one
  alone (twice the one's time over the pair's).

Usage: scripts/bench.py [--rounds 3] [--quick] [--no-doc] [--cases one,peer,...]
"""
import argparse
import importlib.util
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))
import dpmpm  # noqa: E402
# (DPMPM_BIN measures another build, e.g. the one before a change, with the same driver)
BIN = os.environ.get("DPMPM_BIN", os.path.join(ROOT, "build", "release", "dpmpm"))
DOC = os.path.join(ROOT, "doc", "performance.md")
BEGIN, END = "<!-- bench:begin -->", "<!-- bench:end -->"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")

# Neo-Hookean block: E, nu, rho as the peer; its P-wave speed sets the time step.
E, NU, RHO = 1.0e6, 0.3, 1000.0


def block_scene(nd, cells, kernel, scheme, steps, workdir, lo=0.3, base=0.1, size=0.4,
                name="bench_block", walls=""):
    """A neo-Hookean block of edge `size` (unit box, `cells` per axis), ppc 2 per axis."""
    vec = lambda v: ", ".join(f"{x}" for x in v)  # noqa: E731
    lo_v = [lo] * nd
    lo_v[1] = base
    hi_v = [x + size for x in lo_v]
    return f"""&run name = '{name}' t_end = 100.0 max_steps = {steps} cfl = 0.5 flip = 0.99
  scheme = '{scheme}' gravity = {vec([0.0, -10.0] + [0.0] * (nd - 2))} /
&grid ndim = {nd} ncells = {vec([cells] * nd)} origin = {vec([0.0] * nd)} length = {vec([1.0] * nd)} /
&shape kernel = '{kernel}' /
&material id = 1 model = 'neo_hookean' density = {RHO} youngs_modulus = {E} poisson_ratio = {NU} /
&region shape = 'box' lo = {vec(lo_v)} hi = {vec(hi_v)} material = 1 ppc = 2 placement = 'regular' /
&boundary face = 'y-' condition = 'fixed' /
{walls}&output dir = '{workdir}' frame_interval = 0.0 diag_every = 100 /
"""


def two_phase_scene(nd, cells, phase, steps, workdir):
    """The block of scripts/bench_two_phase.sh: a column loaded on top, dry or saturated;
    "twice" is the dry block with a second set of solid points over the first (as many
    points as the saturated block, without its coupling)."""
    vec = lambda v: ", ".join(f"{x}" for x in v)  # noqa: E731
    fluid = "fluid_material = 2 porosity = 0.3" if phase == "saturated" else ""
    region = (f"&region shape = 'box' lo = {vec([0.0] * nd)} hi = {vec([1.0] * nd)} material = 1 "
              f"phase = '{'saturated' if phase == 'saturated' else 'solid'}' {fluid}\n"
              "  ppc = 2 placement = 'random' /\n")
    if phase == "twice":
        region = 2 * region
    sides = "".join(f"&boundary face = '{f}' condition = 'roller' /\n"
                     for f in (["x-", "x+"] + (["z-", "z+"] if nd == 3 else [])))
    return f"""&run name = 'bench_{phase}' t_end = 1.0 max_steps = {steps} cfl = 0.3 drag = 'implicit' /
&grid ndim = {nd} ncells = {vec([cells] * nd)} origin = {vec([0.0] * nd)} length = {vec([1.0] * nd)} /
&shape kernel = 'linear' /
&material id = 1 model = 'linear_elastic' density = 2650.0 youngs_modulus = 1.0e7
  poisson_ratio = 0.2 conductivity = 1.0e-5 /
&material id = 2 model = 'fluid' density = 1000.0 bulk_modulus = 2.2e9 /
{region}&boundary face = 'y-' condition = 'fixed' /
{sides}&load face = 'y+' traction = {vec([0.0, -1000.0] + [0.0] * (nd - 2))} /
&output dir = '{workdir}' frame_interval = 0.0 diag_every = 100 /
"""


def mls_variants(scene, shapes, workdir):
    """The scene of inputs/ (a W1 column) without its benchmark, ending at t = 10 s (cut by
    max_steps) and writing into workdir, as dpmpm.Scenes: as it is ("Standard MPM") and with
    each shape choice of shapes (label -> &shape text)."""
    w1 = dpmpm.Scene.read(os.path.join(ROOT, "inputs", scene + ".nml"))
    w1.remove("benchmark")
    w1.set(run={"t_end": 10.0}, output={"dir": workdir})
    variants = {"Standard MPM": w1}
    for name, shape in shapes.items():
        variants[name] = w1.copy()
        variants[name].replace("shape", shape)
    return variants


def cut(scene, steps):
    """The text of a scene cut at `steps` steps."""
    scene = scene.copy()
    scene["run"]["max_steps"] = steps
    return scene.text()


def scaling_block(cy, steps, workdir):
    """The block of the scaling table: 2D, quadratic, MUSL, filling the grid of 360 x cy
    cells (unit cells across), rollers at the sides; its text."""
    s = dpmpm.Scene.from_text(block_scene(
        2, 360, "quadratic", "musl", steps, workdir, lo=0.0, base=0.0, size=1.0,
        walls="&boundary face = 'x-' condition = 'roller' /\n"
              "&boundary face = 'x+' condition = 'roller' /\n"))
    s["grid"].update(ncells=[360, cy], length=[1.0, cy / 360])
    s["region"]["hi"] = [1.0, cy / 360]
    return s.text()


def write_scene(text, workdir, ranks=1):
    """The scene written into workdir; the command that runs it on the given ranks."""
    path = os.path.join(workdir, "scene.nml")
    with open(path, "w") as f:
        f.write(text)
    return ["mpirun", "--oversubscribe", "-n", str(ranks), BIN, path]


def parse_log(out):
    """Steps, end time, wall time, stage timers, points and memory line of a dpmpm run."""
    if out.returncode != 0:
        sys.exit(f"bench: dpmpm failed ({out.returncode}):\n{out.stdout[-2000:]}\n{out.stderr[-2000:]}")
    log = out.stdout
    m = re.search(r"done, (\d+) steps to t = +(\S+) in ([0-9.]+) s", log)
    loop = re.search(r"time per step ([0-9.]+) ms over (\d+) steps", log)
    if not (m and loop):
        sys.exit(f"bench: no end line or time per step in the log of dpmpm:\n{log[-2000:]}")
    timers = {k: float(v) for k, v in re.findall(r"time in (\w+) +([0-9.]+) s", log)}
    pts = re.search(r"; (\d+) solid points", log)
    mem = re.search(r"memory: (\d+) bytes per solid point(?:, (\d+) per fluid point)?; grid fields "
                    r"([0-9.]+) MiB on rank 0 \((\d+) bytes per node\)(?:; peak resident ([0-9.]+) MiB)?", log)
    return {"steps": int(m.group(1)), "t": float(m.group(2)), "wall": float(m.group(3)),
            "loop": float(loop.group(1)) * int(loop.group(2)) / 1e3,
            "timers": timers, "points": int(pts.group(1)) if pts else 0,
            "mem": mem.groups() if mem else None}


def run_dpmpm(text, workdir, ranks=1):
    return parse_log(subprocess.run(write_scene(text, workdir, ranks), env=ENV, capture_output=True, text=True))


def step_time(make, n1, n2, workdir, ranks=1):
    """Seconds per step from the runs cut at n1 and n2 steps, and the longer run."""
    a = run_dpmpm(make(n1), workdir, ranks)
    b = run_dpmpm(make(n2), workdir, ranks)
    return (b["loop"] - a["loop"]) / (b["steps"] - a["steps"]), b


def pair_step_time(make, n1, n2, workdirs):
    """Seconds per step of two independent 1-rank runs at once, make(steps, workdir) each
    writing into its own directory: the mean of the two, from runs cut at n1 and n2 steps."""
    def both(steps):
        # (each on a core of its own, as the ranks of a 2-rank job are: mpirun would bind
        # both one-rank jobs to the first core)
        cmds = [write_scene(make(steps, d), d) for d in workdirs]
        procs = [subprocess.Popen(["taskset", "-c", str(i)] + c[:2] + ["--bind-to", "none"] + c[2:], env=ENV,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                 for i, c in enumerate(cmds)]
        outs = []
        for p in procs:
            o, e = p.communicate()
            outs.append(parse_log(subprocess.CompletedProcess(p.args, p.returncode, o, e)))
        return outs
    a, b = both(n1), both(n2)
    return statistics.mean((y["loop"] - x["loop"]) / (y["steps"] - x["steps"]) for x, y in zip(a, b)), b[0]


def interleaved(fns, k):
    """k rounds, each running every case of fns (name -> function returning a value and the
    run's log) once, in turn: the cases compared with one another run within the same
    minute or two of this shared host, and a ratio is taken round by round."""
    vals = {name: [] for name in fns}
    last = {}
    for _ in range(k):
        for name, fn in fns.items():
            vals[name].append(None)
            vals[name][-1], last[name] = fn()
    return vals, last


def med(v):
    return statistics.median(v)


def rng(v, fmt):
    return (fmt % min(v)) + (" - " + fmt % max(v) if len(v) > 1 else "")


def block_points(nd, cells, size=0.4):
    return (round(size * cells) * 2) ** nd


def block_dt(cells):
    """The time step of the dpmpm block at rest (cfl 0.5, P-wave speed)."""
    pwave = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
    return 0.5 * (1.0 / cells) / (pwave / RHO) ** 0.5


def peer(nd, cells, size, steps):
    """Point-updates per second of one run of the peer on the block, None without taichi."""
    if importlib.util.find_spec("taichi") is None:
        return None
    out = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "peer_taichi.py"),
                          "--ndim", str(nd), "--cells", str(cells), "--size", str(size),
                          "--steps", str(steps),
                          "--dt", f"{block_dt(cells):.6e}", "--json"],
                         capture_output=True, text=True)
    if out.returncode != 0:
        print(out.stderr[-2000:], file=sys.stderr)
        return None
    return json.loads(out.stdout.strip().splitlines()[-1])["updates_per_s"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="fewer steps (a smoke run of the driver)")
    ap.add_argument("--no-doc", action="store_true", help="print only; leave doc/performance.md")
    ap.add_argument("--cases", default="one,peer,two,mls,scaling")
    a = ap.parse_args()
    cases = set(a.cases.split(","))
    k = a.rounds
    q = 0.25 if a.quick else 1.0
    n = lambda x: max(4, int(x * q))  # noqa: E731
    if not os.path.exists(BIN):
        sys.exit("bench: no release build; run scripts/bench.sh (it builds first)")
    work = tempfile.mkdtemp(prefix="dpmpm_bench_")
    md = []
    res = {}
    t_start = time.time()
    cpu = subprocess.run(["sh", "-c", "grep -m1 'model name' /proc/cpuinfo | cut -d: -f2"],
                         capture_output=True, text=True).stdout.strip()
    md.append(f"Measured by `scripts/bench.sh` on {os.cpu_count()} cores ({cpu}), release build, "
              f"{k} rounds (median, range in brackets); in each round every case of a table runs once, "
              f"in turn, and ratios are taken round by round.\n")

    if "one" in cases or "peer" in cases:
        md.append("### One phase: a neo-Hookean block, one core\n")
        md.append("| dim | kernel | scheme | points | ms / step | M point-updates / s | against the peer |"
                  " bytes / point | stages (share of the step) |")
        md.append("|---|---|---|---|---|---|---|---|---|")
        # (In 3D the runs differ by 60 steps of about 20 ms: a run's first steps are its
        # slow ones, and the log gives the wall time to 1 ms.)
        for nd, cells, size, s1, s2 in ((2, 360, 0.4, 20, 120), (3, 64, 0.375, 4, 64)):
            npts = block_points(nd, cells, size)
            fns = {}
            if "peer" in cases and importlib.util.find_spec("taichi") is not None:
                fns["peer"] = lambda nd=nd, cells=cells, size=size: (peer(nd, cells, size, n(200 if nd == 2 else 30)),
                                                                     None)
            if "one" in cases:
                for kernel in ("linear", "quadratic"):
                    for scheme in ("usl", "musl"):
                        def case(nd=nd, cells=cells, size=size, s1=s1, s2=s2, kernel=kernel, scheme=scheme):
                            return step_time(lambda steps: block_scene(nd, cells, kernel, scheme, steps, work,
                                                                       size=size), n(s1), n(s2), work)
                        fns[(kernel, scheme)] = case
            vals, last = interleaved(fns, k)
            peer_rate = vals.get("peer")
            if peer_rate and None in peer_rate:
                peer_rate = None  # (a run of the peer failed; its error is printed)
            if peer_rate:
                res[f"peer_{nd}d"] = peer_rate
            for key in fns:
                if key == "peer":
                    continue
                kernel, scheme = key
                v = vals[key]
                if last[key]["points"] != npts:
                    sys.exit(f"bench: dpmpm made {last[key]['points']} points, the peer {npts}")
                rate = [npts / x / 1e6 for x in v]
                tm = last[key]["timers"]
                tot = sum(tm.get(x, 0) for x in ("stencil", "p2g", "halo", "nodal", "g2p", "stress", "migrate"))
                stages = ", ".join(f"{x} {100 * tm.get(x, 0) / tot:.0f} %" for x in
                                   ("p2g", "g2p", "stress", "stencil", "nodal", "migrate")) if tot else ""
                ratio = ""
                if peer_rate and kernel == "quadratic":
                    # round by round: dpmpm and the peer ran within the same round
                    rr = [r_ * 1e6 / p_ for r_, p_ in zip(rate, peer_rate)]
                    ratio = f"{med(rr):.2f}x ({rng(rr, '%.2f')})"
                mem = last[key]["mem"][0] if last[key]["mem"] else ""
                md.append(f"| {nd}D | {kernel} | {scheme.upper()} | {npts} | {1e3 * med(v):.1f} "
                          f"({rng([1e3 * x for x in v], '%.1f')}) | {med(rate):.2f} ({rng(rate, '%.2f')}) | "
                          f"{ratio} | {mem} | {stages} |")
                res[f"one_{nd}d_{kernel}_{scheme}"] = {"s_per_step": v, "mupdates": rate, "timers": tm,
                                                      "mem": last[key]["mem"]}
            if peer_rate:
                pr = [x / 1e6 for x in peer_rate]
                md.append(f"| {nd}D | quadratic | peer: Taichi MLS-MPM (APIC), one thread, f64 | {npts} | "
                          f"{1e3 * npts / med(peer_rate):.1f} | {med(pr):.2f} ({rng(pr, '%.2f')}) | 1 | | |")
        md.append("")

    if "two" in cases:
        md.append("### Two phases against one (the same solid points, linear kernel, implicit drag)\n")
        md.append("A third block splits the ratio: the dry one with a second set of solid points over the "
                  "first, as many points as the saturated block has, without the coupling. Its ratio to the "
                  "dry block is what the second set of points costs; the saturated step's time beyond it, in "
                  "dry steps, is what the coupling costs (drag, pore-pressure forces on both phases, "
                  "porosity, the remap's locked velocity, the pressure update).\n")
        md.append("| dim | solid points | dry ms / step | dry, twice the points, ms / step | saturated ms / step | ratio "
                  "| twice the points against dry | coupling in dry steps |")
        md.append("|---|---|---|---|---|---|---|---|")
        # (80 steps apart in 3D: the first steps of the short run are the slow ones)
        for nd, cells, s1, s2 in ((2, 96, 20, 220), (3, 20, 4, 84)):
            vals, _ = interleaved({phase: (lambda nd=nd, cells=cells, s1=s1, s2=s2, phase=phase: step_time(
                lambda steps: two_phase_scene(nd, cells, phase, steps, work), n(s1), n(s2), work))
                for phase in ("solid", "twice", "saturated")}, k)
            ratio = [s / d for s, d in zip(vals["saturated"], vals["solid"])]
            twice = [t / d for t, d in zip(vals["twice"], vals["solid"])]
            coupling = [(s - t) / d for s, t, d in zip(vals["saturated"], vals["twice"], vals["solid"])]
            npts = (2 * cells) ** nd
            md.append(f"| {nd}D | {npts} | {1e3 * med(vals['solid']):.1f} | {1e3 * med(vals['twice']):.1f} | "
                      f"{1e3 * med(vals['saturated']):.1f} | {med(ratio):.2f} ({rng(ratio, '%.2f')}) | "
                      f"{med(twice):.2f} ({rng(twice, '%.2f')}) | {med(coupling):.2f} ({rng(coupling, '%.2f')}) |")
            res[f"two_{nd}d"] = vals
        md.append("")

    if "mls" in cases:
        # The shape choices as scripts/pareto.py spells them (imported here only: it
        # brings h5py and matplotlib). In 3D linear + one Gauss point takes the box weight
        # of half-width 0.65 cells (doc/input.md, &shape).
        import pareto
        box = pareto.LINEAR_GAUSS.replace("field_radius = 0.75", "field_radius = 0.65, field_support = 'box'")
        for nd, scene, gauss, steps in ((2, "w1_2d", pareto.LINEAR_GAUSS, (200, 2200)),
                                        (3, "w1_3d", box, (50, 550))):
            md.append(f"### The MLS pair against Standard MPM (inputs/{scene}.nml)\n")
            # (the cubic B-spline with point quadrature: the pair's grid functions without
            # its Gauss-point work)
            variants = mls_variants(scene, {"MLS pair": pareto.M1_COMBOS["pair (theory.md 3.6)"],
                                            "linear + one Gauss point": gauss,
                                            "cubic B-spline": "kernel = 'cubic', quadrature = 'points'"},
                                    work)
            md.append("| shape | ms / step | steps per simulated second | wall s per simulated second | against Standard MPM |")
            md.append("|---|---|---|---|---|")
            fns = {}
            for name, sc in variants.items():
                # (A step of these 800- and 3200-point columns takes a fraction of a millisecond
                # to a few; the 3D pair 10-50 times more, hence fewer steps.)
                s1, s2 = (5, 25) if (nd == 3 and name == "MLS pair") else steps
                fns[name] = lambda sc=sc, s1=s1, s2=s2: step_time(lambda st: cut(sc, st), n(s1), n(s2),
                                                                   work)
            vals, last = interleaved(fns, k)
            for name in fns:
                v = vals[name]
                per_s = last[name]["steps"] / last[name]["t"]
                # against Standard MPM round by round (the steps per simulated second are the same)
                rr = [x / b_ for x, b_ in zip(v, vals["Standard MPM"])]
                md.append(f"| {name} | {1e3 * med(v):.2f} | {per_s:.0f} | {med(v) * per_s:.2f} | "
                          f"{med(rr):.1f}x ({rng(rr, '%.1f')}) |")
                res[f"{scene}_{name}"] = {"s_per_step": v, "steps_per_s": per_s}
            rr = [x / b_ for x, b_ in zip(vals["MLS pair"], vals["cubic B-spline"])]
            md.append(f"\nThe pair against the cubic B-spline with point quadrature (its grid functions "
                      f"without the Gauss-point work): {med(rr):.1f}x ({rng(rr, '%.1f')}).")
            md.append("")

    if "scaling" in cases:
        md.append("### Scaling: a block filling the grid (2D, quadratic, MUSL)\n")
        md.append("| scene | points | ranks | ms / step | M point-updates / s / core | speed-up or efficiency |")
        md.append("|---|---|---|---|---|---|")

        def full(cy):
            return lambda steps: scaling_block(cy, steps, work)
        # The host's own limit: two independent 1-rank runs of the half block at once (no
        # communication) against one alone; the 2-rank speed-up cannot beat it.
        pair_dirs = [os.path.join(work, f"pair{i}") for i in (1, 2)]
        for d in pair_dirs:
            os.makedirs(d, exist_ok=True)
        vals, _ = interleaved({
            "one": lambda: step_time(full(360), n(5), n(45), work, 1),
            "two": lambda: step_time(full(360), n(5), n(45), work, 2),
            "half": lambda: step_time(full(180), n(5), n(45), work, 1),
            "pair": lambda: pair_step_time(lambda steps, wd: scaling_block(180, steps, wd), n(5), n(45),
                                           pair_dirs)}, k)
        one, two, half, pair = vals["one"], vals["two"], vals["half"], vals["pair"]
        big, small = 720 * 720, 720 * 360
        sp = [a_ / b_ for a_, b_ in zip(one, two)]
        eff = [h_ / b_ for h_, b_ in zip(half, two)]
        ceil = [2 * h_ / p_ for h_, p_ in zip(half, pair)]
        md.append(f"| strong | {big} | 1 | {1e3 * med(one):.1f} | {big / med(one) / 1e6:.2f} | |")
        md.append(f"| strong | {big} | 2 | {1e3 * med(two):.1f} | {big / med(two) / 2e6:.2f} | "
                  f"speed-up {med(sp):.2f} ({rng(sp, '%.2f')}) |")
        md.append(f"| weak | {small} | 1 | {1e3 * med(half):.1f} | {small / med(half) / 1e6:.2f} | |")
        md.append(f"| weak | {big} | 2 | {1e3 * med(two):.1f} | {big / med(two) / 2e6:.2f} | "
                  f"efficiency {med(eff):.2f} ({rng(eff, '%.2f')}) |")
        md.append(f"| two independent 1-rank runs at once | 2 x {small} | 1 + 1 | {1e3 * med(pair):.1f} | "
                  f"{small / med(pair) / 1e6:.2f} | the host's limit of a 2-rank speed-up: "
                  f"{med(ceil):.2f} ({rng(ceil, '%.2f')}) |")
        res["scaling"] = {"one": one, "two": two, "half": half, "pair": pair}
        md.append("")

    md.append(f"(The measurement took {time.time() - t_start:.0f} s.)")
    text = "\n".join(md)
    print(text)
    os.makedirs(os.path.join(ROOT, "build", "bench"), exist_ok=True)
    with open(os.path.join(ROOT, "build", "bench", "latest.json"), "w") as f:
        json.dump(res, f, indent=1)
    if not a.no_doc:
        with open(DOC) as f:
            doc = f.read()
        if BEGIN in doc and END in doc:
            doc = doc[:doc.index(BEGIN) + len(BEGIN)] + "\n" + text + "\n" + doc[doc.index(END):]
            with open(DOC, "w") as f:
                f.write(doc)
            print(f"bench: {DOC} updated", file=sys.stderr)
        else:
            print(f"bench: no {BEGIN} ... {END} markers in {DOC}; not written", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
