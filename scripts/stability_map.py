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
import subprocess
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = {
    'standard': "kernel = 'linear'",
    'quadratic': "kernel = 'quadratic'",
    'cubic': "kernel = 'cubic'",
    'pair': "kernel = 'cubic', quadrature = 'gauss', gauss_points = 3, field_kernel = 'wendland_c2', "
            "field_radius = 2.0",
}
# W2 and W3 differ from W1 only in these (doc/theory.md, section 9.1).
SCENE_CHANGES = {'w1': {}, 'w2': {'conductivity': '1.0', 'drag': "'explicit'"},
                 'w3': {'conductivity': '1.0e-4', 'bulk_modulus': '2.2e9'}}


def set_var(txt, key, val):
    """Set key = val in the first place it is assigned, or add it to &run."""
    if re.search(r'(?m)^\s*%s\s*=' % key, txt):
        return re.sub(r'(?m)^(\s*)%s\s*=.*$' % key, r'\g<1>%s = %s' % (key, val), txt, count=1)
    return txt.replace('&run', '&run\n  %s = %s' % (key, val), 1)


def number(txt, key):
    return float(re.search(r'(?m)^\s*%s\s*=\s*([-+\d.eE]+)' % key, txt).group(1))


def make_scene(scene, dim, shape, cfl, outdir, transits=20):
    base = 'w1.nml' if dim == 1 else 'w1_2d.nml'
    txt = open(os.path.join(ROOT, 'inputs', base)).read()
    txt = re.sub(r'(?s)&benchmark.*?/', '', txt)
    # the material blocks: conductivity in the soil, bulk_modulus in the fluid
    for key, val in SCENE_CHANGES[scene].items():
        txt = set_var(txt, key, val)
    txt = re.sub(r'(?s)&shape.*?/', '&shape ' + SHAPES[shape] + ' /', txt)
    mats = re.findall(r'(?s)&material(.*?)/', txt)
    rs, E = number(mats[0], 'density'), number(mats[0], 'youngs_modulus')
    rf, kf = number(mats[1], 'density'), number(mats[1], 'bulk_modulus')
    n = number(txt, 'porosity')
    rsat = (1 - n) * rs + n * rf
    cu = np.sqrt((E + kf / n) / rsat)
    length = 10.0
    t_end = float('%.6g' % (transits * length / cu))
    name = '%s_%dd_%s_%g' % (scene, dim, shape, cfl)
    txt = set_var(txt, 'name', "'%s'" % name)
    txt = set_var(txt, 't_end', '%.6g' % t_end)
    txt = set_var(txt, 'cfl', cfl)
    txt = re.sub(r"dir = '\w+'", "dir = '%s'" % outdir, txt)
    path = os.path.join(outdir, name + '.nml')
    open(path, 'w').write(txt)
    return name, path, 1.0 / (rsat * cu), t_end


def run(args, scene, dim, shape, cfl):
    name, path, vu, t_end = make_scene(scene, dim, shape, cfl, args.out, args.transits)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OMPI_MCA_rmaps_base_oversubscribe='1')
    t0 = time.time()
    r = subprocess.run(['mpirun', '-n', str(args.np), args.bin, path], env=env, capture_output=True,
                       text=True)
    log = r.stdout + r.stderr
    open(os.path.join(args.out, name + '.log'), 'w').write(log)
    m = re.search(r'largest \(kinetic \+ stored\) / \(work \+ initial\)\s+([-+\d.E]+)', log)
    ratio = float(m.group(1)) if m else float('nan')
    stop = re.search(r'monitor: at t = \s*([-+\d.E]+) s .*?growing field: ([\w ]+ of the \w+ points)', log)
    d = h5py.File(os.path.join(args.out, name + '.h5'), 'r')['diagnostics']
    t, ke, vmax = d['time'][:], d['kinetic_energy'][:], d['max_speed'][:]
    ep = 0.5 * d['total_mass'][0] * vu ** 2
    steps = d['step'][-1]
    dt = t[-1] / steps if t[-1] < t_end * (1 - 1e-9) else t_end / steps
    half = ke[np.searchsorted(t, 0.5 * t[-1])]
    return dict(name=name, rc=r.returncode, t=t[-1], t_end=t_end, ke=ke.max() / ep,
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
