#!/usr/bin/env python3
"""Each constitutive model in a full scene far past its benchmark time (doc/verification.md,
"Every model in a collapse"): the dry column collapse of inputs/c1_a2.nml (benchmark time
1.5 s) with its soil replaced by each model of the table that a dry soil can be, run to
--t-end (default 5 s) on each rank count of --np, at the scene's own Courant number.
Reports how each run ended (its exit code, monitor warnings and stops), the monitor's
largest (kinetic + stored) / (work + initial) and largest balance error, the steps, the
time step at the end, the largest speed over the last second, the front of the deposit
(the farthest point) and its height at the wall, and the wall time.

usage: scripts/model_runs.py [--bin build/release/dpmpm] [--np 1,2] [--t-end 5]
       [--models linear_elastic,neo_hookean,...] [--out DIR]

`umat` runs the UMAT the binary was built with: the default build's is the linear-elastic
example (src/materials/umat/umat_linear_elastic.f, PROPS E, nu), which this script gives.
"""
import argparse
import os
import sys

import numpy as np

from long_runs import run, summary

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'scripts', 'python'))
import dpmpm  # noqa: E402

# The soil of the collapse (rho 2650, E 1 MPa, nu 0.3, phi 30, no cohesion or tension) in
# each model's own variables; cam_clay: a sand-like clay whose K at 1 kPa + p_m is near
# the elastic soil's, M from phi = 30 degrees in compression, normally consolidated.
ELASTIC = dict(youngs_modulus=1.0e6, poisson_ratio=0.3)
MODELS = {
    'linear_elastic': dict(ELASTIC),
    'neo_hookean': dict(ELASTIC),
    'mohr_coulomb': dict(ELASTIC, friction_angle=30.0, dilatancy_angle=0.0, cohesion=0.0,
                         tensile_strength=0.0),
    'drucker_prager': dict(ELASTIC, friction_angle=30.0, dilatancy_angle=0.0, cohesion=0.0,
                           tensile_strength=0.0),
    'cam_clay': dict(poisson_ratio=0.3, compression_index=0.02, swelling_index=0.005,
                     critical_state_ratio=1.2, void_ratio=0.7, ocr=1.0, min_pressure=1.0e3),
    'umat': dict(ELASTIC, umat_props=[1.0e6, 0.3]),
}


def scene_for(base, model, name, outdir, t_end):
    s = base.copy()
    mat = s.find('material', id=1)[0]
    for key in list(mat.keys()):
        if key not in ('id', 'density'):
            del mat[key]
    mat['model'] = model
    mat.update(MODELS[model])
    s.set(run={'name': name, 't_end': t_end}, output={'dir': outdir, 'frame_interval': 0.5})
    return s


def deposit(output):
    """Largest speed over the last second (from /diagnostics), the time step at the end,
    the front of the deposit (largest x of a point) and the height at the wall (largest y
    of a point within 2 cm of x = 0) at the last frame."""
    with dpmpm.open_run(output) as r:
        d = r.diagnostics
        t = d['time']
        late = t >= t[-1] - 1.0
        vmax = float(np.max(d['max_speed'][late]))
        dt = float(d['dt'][-1])
        x = r[len(r) - 1]['solid']['x'][...]
    front = float(np.max(x[:, 0]))
    wall = x[:, 0] < 0.02
    height = float(np.max(x[wall, 1])) if np.any(wall) else float('nan')
    return vmax, dt, front, height


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--bin', default=os.path.join(ROOT, 'build', 'release', 'dpmpm'))
    ap.add_argument('--np', default='1,2', help='rank counts, comma-separated')
    ap.add_argument('--t-end', type=float, default=5.0)
    ap.add_argument('--models', default=','.join(MODELS))
    ap.add_argument('--out', default='/tmp/dpmpm_model_runs')
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    base = dpmpm.Scene.read(os.path.join(ROOT, 'inputs', 'c1_a2.nml'))
    print('| model | ranks | t_end [s] | steps | how it ended | monitor warnings | (KE + stored) / '
          '(work + initial) | balance error | dt at the end [s] | largest speed, last second [m/s] '
          '| front [m] | height at the wall [m] | wall [s] |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|---|')
    for model in args.models.split(','):
        for np_ in [int(v) for v in args.np.split(',')]:
            name = 'c1_%s_np%d' % (model, np_)
            scene = scene_for(base, model, name, args.out, args.t_end)
            rc, log, wall = run(args, scene, np_)
            s = summary(rc, log)
            vmax = dt = front = height = float('nan')
            out = os.path.join(args.out, name + '.h5')
            if os.path.exists(out):
                try:
                    vmax, dt, front, height = deposit(out)
                except (OSError, KeyError, ValueError) as e:
                    print('  (%s: %s)' % (out, e), file=sys.stderr)
            print('| %s | %d | %.3g | %d | %s | %d | %.3g | %.3g | %.3g | %.3g | %.3f | %.3f | %.0f |' % (
                model, np_, args.t_end, s['steps'], s['how'], s['warns'], s['ratio'], s['bal'], dt,
                vmax, front, height, wall), flush=True)


if __name__ == '__main__':
    main()
