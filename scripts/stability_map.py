#!/usr/bin/env python3
"""Stability map of the two-phase columns (doc/verification.md, "Long runs of the
two-phase step"): W1, W2 and W3 in 1D and 2D, each shape choice, run for 20
transits of the undrained wave (L / c_u each) at several Courant numbers, with
the benchmark group removed. Reports the largest kinetic energy against the
physical scale 0.5 M v_u^2 (M the mass of the column, v_u = q / (rho_sat c_u)),
the largest point speed against v_u, the monitor's ratio (kinetic + stored) /
(work done + initial energy), and the time step taken.

usage: scripts/stability_map.py [--bin build/release/dpmpm] [--np 2] [--out DIR]
       [--scenes w1,w2,w3] [--dims 1,2] [--shapes standard,quadratic,cubic,pair]
       [--cfl 0.5,0.7,0.9,1.0] [--transits 20]
"""
import argparse
import os
import re
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'scripts', 'python'))
import dpmpm  # noqa: E402

SHAPES = {
    'standard': "kernel = 'linear'",
    'quadratic': "kernel = 'quadratic'",
    'cubic': "kernel = 'cubic'",
    'pair': "kernel = 'cubic', quadrature = 'gauss', gauss_points = 3, field_kernel = 'wendland_c2', "
            "field_radius = 2.0",
}
# W2 and W3 differ from W1 only in these (doc/theory.md, section 9.1): conductivity in the
# soil (material 1), bulk_modulus in the fluid (material 2), drag in &run.
SCENE_CHANGES = {'w1': {}, 'w2': {'conductivity': 1.0, 'drag': 'explicit'},
                 'w3': {'conductivity': 1.0e-4, 'bulk_modulus': 2.2e9}}
WHERE = {'conductivity': ('material', 1), 'bulk_modulus': ('material', 2), 'drag': ('run', None)}


def make_scene(scene, dim, shape, cfl, outdir, transits=20):
    """W1 of inputs/ (w1.nml, w1_2d.nml) turned into the scene, the shape choice and the
    Courant number asked, without its benchmark group and run for `transits` transits, as a
    dpmpm.Scene; with v_u per unit load and the end time."""
    s = dpmpm.Scene.read(os.path.join(ROOT, 'inputs', 'w1.nml' if dim == 1 else 'w1_2d.nml'))
    s.remove('benchmark')
    for key, val in SCENE_CHANGES[scene].items():
        group, mat = WHERE[key]
        [g] = s.find(group, id=mat) if mat else [s[group]]
        g[key] = val
    s.replace('shape', SHAPES[shape])
    [soil] = s.find('material', id=1)
    [water] = s.find('material', id=2)
    rs, E = float(soil['density']), float(soil['youngs_modulus'])
    rf, kf = float(water['density']), float(water['bulk_modulus'])
    [region] = s.groups('region')
    n = float(region['porosity'])
    rsat = (1 - n) * rs + n * rf
    cu = np.sqrt((E + kf / n) / rsat)
    length = 10.0
    t_end = float('%.6g' % (transits * length / cu))
    name = '%s_%dd_%s_%g' % (scene, dim, shape, cfl)
    s.set(run={'name': name, 't_end': t_end, 'cfl': cfl}, output={'dir': outdir})
    return s, 1.0 / (rsat * cu), t_end


def run(args, scene, dim, shape, cfl):
    s, vu, t_end = make_scene(scene, dim, shape, cfl, args.out, args.transits)
    t0 = time.time()
    try:
        r = dpmpm.simulate(s, ranks=args.np, binary=args.bin, progress=False)
        rc, log = 0, r.log
    except dpmpm.RunError as e:
        rc, log = e.status, e.log
    log = open(log).read()
    m = re.search(r'largest \(kinetic \+ stored\) / \(work \+ initial\)\s+([-+\d.E]+)', log)
    ratio = float(m.group(1)) if m else float('nan')
    stop = re.search(r'monitor: at t = \s*([-+\d.E]+) s .*?growing field: ([\w ]+ of the \w+ points)', log)
    with dpmpm.open_run(s.output_file()) as out:
        d = out.diagnostics
        t, ke, vmax = d['time'][:], d['kinetic_energy'][:], d['max_speed'][:]
        ep = 0.5 * d['total_mass'][0] * vu ** 2
        steps = d['step'][-1]
    dt = t[-1] / steps if t[-1] < t_end * (1 - 1e-9) else t_end / steps
    half = ke[np.searchsorted(t, 0.5 * t[-1])]
    return dict(name=s.name, rc=rc, t=t[-1], t_end=t_end, ke=ke.max() / ep,
                late=ke[-1] / max(half, 1e-300),
                ke_end=ke[-1] / ep, v=vmax.max() / vu, ratio=ratio, dt=dt,
                stop=(float(stop.group(1)), stop.group(2)) if stop else None, wall=time.time() - t0)


def verdict(res):
    """bounded: kinetic energy within 5x the physical scale; noisy: above it but
    not growing over the second half of the run; cut: growing like t^2 (a part
    of the column accelerating freely under the load, its energy accounted for
    by the work of the load); grows: anything faster, or a monitor stop."""
    if res['rc'] != 0 or res['t'] < res['t_end'] * (1 - 1e-9):
        return 'stopped'
    if res['ke'] <= 5.0:
        return 'bounded'
    if res['late'] <= 1.5:
        return 'noisy'
    return 'cut' if res['late'] <= 6.0 and res['ratio'] <= 2.0 else 'grows'


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--bin', default=os.path.join(ROOT, 'build', 'release', 'dpmpm'))
    ap.add_argument('--np', type=int, default=2)
    ap.add_argument('--out', default='/tmp/dpmpm_stability')
    ap.add_argument('--scenes', default='w1,w2,w3')
    ap.add_argument('--dims', default='1,2')
    ap.add_argument('--shapes', default='standard,quadratic,cubic,pair')
    ap.add_argument('--cfl', default='0.5,0.7,0.9,1.0')
    ap.add_argument('--transits', type=float, default=20.0, help='run length in transits L / c_u')
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    print('| scene | shape | Courant number | dt [s] | verdict | largest KE / (0.5 M v_u^2) | at the end '
          '| KE(end) / KE(end / 2) | largest speed / v_u | (KE + stored) / (work + initial) | monitor stop |')
    print('|---|---|---|---|---|---|---|---|---|---|---|')
    for dim in [int(x) for x in args.dims.split(',')]:
        for scene in args.scenes.split(','):
            for shape in args.shapes.split(','):
                for cfl in [float(x) for x in args.cfl.split(',')]:
                    res = run(args, scene, dim, shape, cfl)
                    stop = '-' if res['stop'] is None else 't = %.3g s, %s' % res['stop']
                    print('| %s %dD | %s | %g | %.3e | %s | %.3g | %.3g | %.3g | %.3g | %.3g | %s |' % (
                        scene.upper(), dim, shape, cfl, res['dt'], verdict(res), res['ke'],
                        res['ke_end'], res['late'], res['v'], res['ratio'], stop), flush=True)


if __name__ == '__main__':
    main()
