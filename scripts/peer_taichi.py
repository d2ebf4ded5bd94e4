#!/usr/bin/env python3
"""Speed peer: an explicit MLS-MPM step (APIC transfer, quadratic B-spline,
compressible neo-Hookean, plane strain in 2D) written with Taichi on the CPU, in double
precision, on one thread. It runs the block of scripts/bench.sh (the same
points, grid, kernel, material, gravity and time step as the dpmpm scene) and
prints the point-updates per second, so that scripts/bench.sh can put the two
side by side.

Usage: peer_taichi.py --ndim 2 --cells 360 --ppc 2 --steps 400 --dt 3.7e-5
"""
import argparse
import json
import sys
import time


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ndim", type=int, default=2)
    ap.add_argument("--cells", type=int, default=360, help="cells per axis of the unit box")
    ap.add_argument("--lo", type=float, default=0.3, help="block from lo to lo + size on axis 1 (and 3)")
    ap.add_argument("--base", type=float, default=0.1, help="block bottom on the vertical axis")
    ap.add_argument("--size", type=float, default=0.4, help="block edge")
    ap.add_argument("--ppc", type=int, default=2, help="points per cell and axis")
    ap.add_argument("--steps", type=int, default=400)
    ap.add_argument("--warm", type=int, default=20, help="steps before the clock starts")
    ap.add_argument("--dt", type=float, required=True)
    ap.add_argument("--young", type=float, default=1.0e6)
    ap.add_argument("--poisson", type=float, default=0.3)
    ap.add_argument("--density", type=float, default=1000.0)
    ap.add_argument("--gravity", type=float, default=-10.0)
    ap.add_argument("--json", action="store_true", help="print one JSON line")
    a = ap.parse_args()

    import taichi as ti

    ti.init(arch=ti.cpu, default_fp=ti.f64, cpu_max_num_threads=1, offline_cache=True,
            log_level=ti.ERROR)
    nd = a.ndim
    ng = a.cells
    h = 1.0 / ng
    inv_h = float(ng)
    # Points on a regular lattice, ppc per cell and axis, as dpmpm's 'regular' placement.
    ncell_block = int(round(a.size / h))
    per_axis = ncell_block * a.ppc
    n = per_axis**nd
    spacing = h / a.ppc
    vol0 = spacing**nd
    mass0 = a.density * vol0
    mu = a.young / (2.0 * (1.0 + a.poisson))
    lam = a.young * a.poisson / ((1.0 + a.poisson) * (1.0 - 2.0 * a.poisson))
    lo = [a.lo] * nd
    lo[1] = a.base
    dt = a.dt
    grav = a.gravity

    vec = ti.types.vector(nd, ti.f64)
    mat = ti.types.matrix(nd, nd, ti.f64)
    x = ti.Vector.field(nd, ti.f64, shape=n)
    v = ti.Vector.field(nd, ti.f64, shape=n)
    C = ti.Matrix.field(nd, nd, ti.f64, shape=n)
    F = ti.Matrix.field(nd, nd, ti.f64, shape=n)
    gm = ti.field(ti.f64, shape=(ng + 1,) * nd)
    gv = ti.Vector.field(nd, ti.f64, shape=(ng + 1,) * nd)

    @ti.kernel
    def seed():
        for p in range(n):
            r = p
            for d in ti.static(range(nd)):
                k = r % per_axis
                r //= per_axis
                x[p][d] = lo[d] + (k + 0.5) * spacing
            v[p] = vec(0.0)
            C[p] = mat(0.0)
            F[p] = ti.Matrix.identity(ti.f64, nd)

    @ti.kernel
    def step():
        for I in ti.grouped(gm):
            gm[I] = 0.0
            gv[I] = vec(0.0)
        for p in range(n):
            base = ti.cast(x[p] * inv_h - 0.5, ti.i32)
            fx = x[p] * inv_h - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
            Fp = (ti.Matrix.identity(ti.f64, nd) + dt * C[p]) @ F[p]
            F[p] = Fp
            J = Fp.determinant()
            # Kirchhoff stress of the compressible neo-Hookean solid.
            tau = mu * (Fp @ Fp.transpose() - ti.Matrix.identity(ti.f64, nd)) + \
                lam * ti.log(J) * ti.Matrix.identity(ti.f64, nd)
            # Force term of the fused APIC/MLS transfer: -dt V0 4/h^2 tau.
            stress = -dt * vol0 * 4.0 * inv_h * inv_h * tau
            affine = stress + mass0 * C[p]
            for off in ti.static(ti.grouped(ti.ndrange(*((3,) * nd)))):
                dpos = (off.cast(ti.f64) - fx) * h
                wt = 1.0
                for d in ti.static(range(nd)):
                    wt *= w[off[d]][d]
                gv[base + off] += wt * (mass0 * v[p] + affine @ dpos)
                gm[base + off] += wt * mass0
        for I in ti.grouped(gm):
            if gm[I] > 0:
                vel = gv[I] / gm[I]
                vel[1] += dt * grav
                # Fixed floor and walls: the outer two node layers hold no velocity.
                for d in ti.static(range(nd)):
                    if I[d] < 2 or I[d] > ng - 2:
                        vel = vec(0.0)
                gv[I] = vel
        for p in range(n):
            base = ti.cast(x[p] * inv_h - 0.5, ti.i32)
            fx = x[p] * inv_h - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
            nv = vec(0.0)
            nC = mat(0.0)
            for off in ti.static(ti.grouped(ti.ndrange(*((3,) * nd)))):
                dpos = (off.cast(ti.f64) - fx) * h
                wt = 1.0
                for d in ti.static(range(nd)):
                    wt *= w[off[d]][d]
                gvel = gv[base + off]
                nv += wt * gvel
                nC += 4.0 * inv_h * inv_h * wt * gvel.outer_product(dpos)
            v[p] = nv
            C[p] = nC
            x[p] += dt * nv

    seed()
    for _ in range(a.warm):
        step()
    ti.sync()
    t0 = time.perf_counter()
    for _ in range(a.steps):
        step()
    ti.sync()
    wall = time.perf_counter() - t0
    rate = n * a.steps / wall
    ymin = float(x.to_numpy()[:, 1].min())
    if a.json:
        print(json.dumps({"points": n, "steps": a.steps, "wall_s": wall, "updates_per_s": rate,
                          "ymin": ymin}))
    else:
        print(f"taichi {'.'.join(map(str, ti.__version__))}: {n} points, {a.steps} steps in {wall:.2f} s, "
              f"{rate:.3e} point-updates/s (one thread, f64); lowest point {ymin:.4f} m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
