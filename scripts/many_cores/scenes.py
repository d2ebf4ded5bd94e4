#!/usr/bin/env python3
"""Scenes of the many-core scaling study (scripts/many_cores/README.md): writes
DIR/<case>_<ranks>_<steps>.nml for 5- and 25-step runs.

A: 2D one phase, strong: a neo-Hookean block filling a 720 x 720 grid, quadratic B-splines,
   MUSL, 2 x 2 points per cell (2.07 M points).
B: 3D two phases, strong: a saturated cube of 40^3 cells, linear, implicit drag, 2 x 2 x 2
   random points per cell (512 k points per phase).
C: 2D one phase, weak: the block of A with 259 200 points per rank (360 x 180 cells per rank).
D: 16 independent one-rank runs of C at once (the machine's own limit for C).
M: C with every point moving at (1, 1) m/s and no gravity, so that points cross rank
   boundaries every step (migration at work); the block leaves 4 cells free on the + sides.
E: a column collapse caught in full flow (the 2D scene of inputs/c1_a2.nml at h = 2 mm,
   80 000 points, restarted from its checkpoint at t = 0.254 s): the grid split by cells
   (E_cells), by points (E_points) and by nested cuts (E_nested), where the points sit on
   few ranks.
Cell size 1/360 m for A, C and M, as the project's own bench block.
SCALE=small divides the sizes by 16 for a try on a small machine."""
import os
import re
import sys

small = os.environ.get("SCALE") == "small"
HERE = os.path.dirname(os.path.abspath(__file__))
H = 1.0 / 360


def block2d(nx, ny, steps, d, moving=False):
    lx, ly = nx * H, ny * H
    if moving:  # free block, every point at (1, 1) m/s; 4 cells free on the + sides
        hx, hy = (nx - 4) * H, (ny - 4) * H
        extra = "velocity = 1.0, 1.0"
        grav, bcs = "0.0, 0.0", ""
    else:
        hx, hy, extra, grav = lx, ly, "", "0.0, -10.0"
        bcs = """&boundary face = 'y-' condition = 'fixed' /
&boundary face = 'x-' condition = 'roller' /
&boundary face = 'x+' condition = 'roller' /
"""
    return f"""&run name = 'blk' t_end = 100.0 max_steps = {steps} cfl = 0.5 flip = 0.99 scheme = 'musl' gravity = {grav} /
&grid ndim = 2 ncells = {nx}, {ny} origin = 0.0, 0.0 length = {lx!r}, {ly!r} /
&shape kernel = 'quadratic' /
&material id = 1 model = 'neo_hookean' density = 1000.0 youngs_modulus = 1.0e6 poisson_ratio = 0.3 /
&region shape = 'box' lo = 0.0, 0.0 hi = {hx!r}, {hy!r} material = 1 ppc = 2 placement = 'regular' {extra} /
{bcs}&output dir = '{d}' frame_interval = 0.0 diag_every = 100 /
"""


def sat3d(n, steps, d, name="sat", restart="", checkpoint_every=0):
    """The saturated cube of B (also scripts/large_run.sh's scene)."""
    return f"""&run name = '{name}' t_end = 1.0 max_steps = {steps} cfl = 0.3 drag = 'implicit' restart = '{restart}' /
&grid ndim = 3 ncells = {n}, {n}, {n} origin = 0.0, 0.0, 0.0 length = 1.0, 1.0, 1.0 /
&shape kernel = 'linear' /
&material id = 1 model = 'linear_elastic' density = 2650.0 youngs_modulus = 1.0e7 poisson_ratio = 0.2 conductivity = 1.0e-5 /
&material id = 2 model = 'fluid' density = 1000.0 bulk_modulus = 2.2e9 /
&region shape = 'box' lo = 0.0, 0.0, 0.0 hi = 1.0, 1.0, 1.0 material = 1 phase = 'saturated' fluid_material = 2 porosity = 0.3 ppc = 2 placement = 'random' /
&boundary face = 'y-' condition = 'fixed' /
&boundary face = 'x-' condition = 'roller' /
&boundary face = 'x+' condition = 'roller' /
&boundary face = 'z-' condition = 'roller' /
&boundary face = 'z+' condition = 'roller' /
&load face = 'y+' traction = 0.0, -1000.0, 0.0 /
&output dir = '{d}' frame_interval = 0.0 diag_every = 100 checkpoint_every = {checkpoint_every} /
"""


def collapse(steps, d, balance, ckpt):
    """inputs/c1_a2.nml at h = 2 mm, restarted at step STEP0 of its checkpoint."""
    with open(os.path.join(HERE, "..", "..", "inputs", "c1_a2.nml")) as f:
        text = f.read()
    text = text.replace("name = 'c1_a2'", "name = 'flow'").replace("ncells = 120, 45", "ncells = 600, 225")
    text = re.sub(r"t_end = 1.5", f"t_end = 0.5\n  max_steps = {STEP0 + steps}\n  restart = '{ckpt}'", text)
    text = re.sub(r"(?m)^&grid", f"&grid\n  balance = '{balance}'", text)
    return re.sub(r"dir = 'out'\n  frame_interval = 0.05", f"dir = '{d}'\n  frame_interval = 0.0", text)


STEP0 = int(os.environ.get("E_STEP0", "21150"))   # the step of the collapse's checkpoint
CKPT = os.environ.get("E_CKPT", "")


def main(out):
    os.makedirs(out, exist_ok=True)
    weak = {1: (360, 180), 2: (360, 360), 4: (720, 360), 8: (720, 720), 16: (1440, 720)}
    A, B = (180, 16) if small else (720, 40)
    if small:
        weak = {r: (a // 4, b // 4) for r, (a, b) in weak.items()}
    for steps in (5, 25):
        for r in (1, 2, 4, 8, 16):
            cases = [("A", block2d(A, A, steps, f"o_A_{r}_{steps}")),
                     ("B", sat3d(B, steps, f"o_B_{r}_{steps}")),
                     ("C", block2d(*weak[r], steps, f"o_C_{r}_{steps}")),
                     ("M", block2d(*weak[r], steps, f"o_M_{r}_{steps}", moving=True))]
            if CKPT:
                cases += [(f"E_{b}", collapse(steps, f"o_E_{b}_{r}_{steps}", b, CKPT)) for b in ("cells", "points", "nested")]
            for case, text in cases:
                with open(os.path.join(out, f"{case}_{r}_{steps}.nml"), "w") as f:
                    f.write(text)
        for i in range(16):
            with open(os.path.join(out, f"D{i}_{steps}.nml"), "w") as f:
                f.write(block2d(*weak[1], steps, f"o_D{i}_{steps}"))


if __name__ == "__main__":
    main(sys.argv[1])
