#!/usr/bin/env python3
"""Long runs of every scene in inputs/ (doc/verification.md, "Every scene over 20
transits"): each scene with each shape choice its input accepts (Standard MPM,
quadratic and cubic B-splines with point quadrature, the pair of doc/theory.md
3.6), the reference groups of the wave and consolidation benchmarks removed, run for a number of transits of the fastest wave
across the grid at the scene's own Courant number. The wave speed is read from
the scene's first step: c = cfl h_min / dt_wave (dt_wave is the wave-CFL step,
printed by two-phase scenes; otherwise the first step). Reports how the run
ended (its exit code, monitor warnings and stops), the monitor's largest
(kinetic + stored) / (work + initial) and its largest balance error, the steps
and the wall time. A shape that the input refuses is listed with the reason.

With --placement random, uniform or stirred every &region of the scene places its points
that way (doc/input.md, `placement`; doc/verification.md, "Saturated soil at rest on
scattered points"; stirred: the regular points after the default rounds of shears, as
after a large deformation); --np takes a list of rank counts (2D and 3D scenes run on each).

usage: scripts/long_runs.py [--bin build/release/dpmpm] [--np 2 | --np 1,2] [--out DIR]
       [--scenes a,b,...] [--shapes standard,quadratic,cubic,pair,linear_gauss]
       [--placement as_shipped|random|uniform|stirred] [--transits 20]

By default every scene but the W1-W3 columns, which scripts/stability_map.py covers.
"""
import argparse
import glob
import os
import re
import sys
import time

import f90nml

from stability_map import SHAPES as MAP_SHAPES  # the four shape choices of the stability map

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'scripts', 'python'))
import dpmpm  # noqa: E402

# and linear grid functions with one Gauss point per cell (doc/input.md, "Which to pick")
SHAPES = dict(MAP_SHAPES, linear_gauss="kernel = 'linear', quadrature = 'gauss', gauss_points = 1, "
                                       "field_kernel = 'linear', field_radius = 0.75")

# the columns of the stability map (scripts/stability_map.py) are left to it
MAPPED = ('w1', 'w2', 'w3', 'w1_2d', 'w1_3d')


def shape_group(shape):
    """The &shape variables of a shape choice, as a dict."""
    return dict(f90nml.reads('&shape %s /' % SHAPES[shape])['shape'])


def _list(v, default, n):
    v = v if isinstance(v, list) else [v] if v is not None else []
    return [float(x) if x is not None else default for x in v][:n] + [default] * (n - len(v))


def grid(scene):
    """ndim, ncells and length of &grid."""
    g = scene['grid']
    ndim = int(g['ndim'])
    return ndim, _list(g.get('ncells'), 1.0, ndim), _list(g.get('length'), 1.0, ndim)


def set_placement(scene, placement):
    """Every &region group with its points placed as placement (one seed per region)."""
    for k, region in enumerate(scene.groups('region'), start=1):
        region.update(placement=placement, seed=k)


def make(base, shape, name, outdir, t_end=None, max_steps=None):
    s = base.copy()
    # the reference solutions of the wave and consolidation benchmarks go; the
    # benchmarks that set the body's start and load (axial_bar, mms) stay
    for bench in ('biot_column', 'terzaghi'):
        s.remove('benchmark', name=bench)
    if shape is not None:
        s.group('shape', create=True).clear()
        s.set(shape=shape_group(shape))
    s.set(run={'name': name}, output={'dir': outdir})
    if t_end is not None:
        s['run']['t_end'] = float('%.6g' % t_end)
    if max_steps is not None:
        s['run']['max_steps'] = max_steps
    return s


def run(args, scene, np_):
    """Exit code, log text and wall time of a run (dpmpm.simulate; the log beside the output)."""
    t0 = time.time()
    try:
        r = dpmpm.simulate(scene, ranks=np_, binary=args.bin, progress=False)
        rc, log = 0, r.log
    except dpmpm.RunError as e:
        rc, log = e.status, e.log
    return rc, open(log).read(), time.time() - t0


def first_step(args, base, scene):
    """Wave-CFL step of the scene's first step and its Courant number."""
    rc, log, _ = run(args, make(base, None, scene + '_probe', args.out, max_steps=1), 1)
    m = re.search(r'wave CFL\s+([-+\d.E]+) s', log)
    if m:
        return float(m.group(1)), rc, log
    m = re.search(r'time step\s+([-+\d.E]+) s set by the wave CFL', log)
    if m:
        return float(m.group(1)), rc, log
    m = re.search(r'done, 1 steps to t =\s*([-+\d.E]+)', log)
    return (float(m.group(1)) if m else float('nan')), rc, log


def summary(rc, log):
    m = re.search(r'largest \(kinetic \+ stored\) / \(work \+ initial\)\s+([-+\d.E]+), largest balance '
                  r'error\s+([-+\d.E]+)', log)
    ratio, bal = (float(m.group(1)), float(m.group(2))) if m else (float('nan'), float('nan'))
    steps = re.search(r'done, (\d+) steps to t =\s*([-+\d.E]+)', log)
    warns = len(re.findall(r'monitor: warning', log))
    cut = 'is cut' in log
    if rc == 0:
        how = 'completed'
    elif 'monitor: the run is unstable' in log:
        how = 'stopped by the monitor (growth)'
    elif 'monitor: no frame of this state' in log:
        how = 'stopped: invalid state'
    else:
        how = 'exit %d' % rc
    return dict(ratio=ratio, bal=bal, steps=int(steps.group(1)) if steps else -1,
                t=float(steps.group(2)) if steps else float('nan'), warns=warns, cut=cut, how=how)


def refusal(log):
    m = re.search(r'input error: (.*)', log)
    return m.group(1).strip() if m else log.strip().splitlines()[-1][:160]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--bin', default=os.path.join(ROOT, 'build', 'release', 'dpmpm'))
    ap.add_argument('--np', default='2', help='rank counts of 2D and 3D scenes, comma-separated')
    ap.add_argument('--placement', default='as_shipped', choices=('as_shipped', 'random', 'uniform', 'stirred'))
    ap.add_argument('--out', default='/tmp/dpmpm_long_runs')
    ap.add_argument('--scenes', default='', help='scene names (default: every file in inputs/)')
    ap.add_argument('--shapes', default='standard,quadratic,cubic,pair')
    ap.add_argument('--transits', type=float, default=20.0)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    scenes = args.scenes.split(',') if args.scenes else sorted(
        os.path.basename(p)[:-4] for p in glob.glob(os.path.join(ROOT, 'inputs', '*.nml'))
        if os.path.basename(p)[:-4] not in MAPPED)
    print('| scene | shape | ranks | transit [s] | t_end [s] | steps | how it ended | monitor warnings '
          '| (KE + stored) / (work + initial) | balance error | cut warned | wall [s] |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|')
    for scene in scenes:
        base = dpmpm.Scene.read(os.path.join(ROOT, 'inputs', scene + '.nml'))
        if args.placement != 'as_shipped':
            set_placement(base, args.placement)
        cfl = float(base['run'].get('cfl', 0.5)) if 'run' in base else 0.5
        ndim, ncells, length = grid(base)
        h = min(l / n for l, n in zip(length, ncells))
        dt, rc, log = first_step(args, base, scene)
        if rc != 0:
            print('| %s | (as shipped) | 1 | | | | probe failed: %s | | | | | |' % (scene, refusal(log)))
            continue
        transit = max(length) / (cfl * h / dt)
        t_end = args.transits * transit
        for shape, np_ in [(sh, n) for sh in args.shapes.split(',')
                           for n in ([1] if ndim == 1 else [int(v) for v in args.np.split(',')])]:
            name = '%s_%s_np%d' % (scene, shape, np_)
            if args.placement != 'as_shipped':
                name += '_' + args.placement
            rc, log, wall = run(args, make(base, shape, name, args.out, t_end=t_end), np_)
            if rc == 2 and 'input error' in log:
                print('| %s | %s | %d | %.3g | %.3g | | refused by the input: %s | | | | | |' % (
                    scene, shape, np_, transit, t_end, refusal(log).replace('|', '/')), flush=True)
                continue
            s = summary(rc, log)
            print('| %s | %s | %d | %.3g | %.3g | %d | %s | %d | %.3g | %.3g | %s | %.0f |' % (
                scene, shape, np_, transit, t_end, s['steps'], s['how'], s['warns'], s['ratio'],
                s['bal'], 'yes' if s['cut'] else 'no', wall), flush=True)


if __name__ == '__main__':
    main()
