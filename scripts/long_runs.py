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

With --placement random or uniform every &region of the scene places its points that way
(doc/input.md, `placement`; doc/verification.md, "Saturated soil at rest on scattered
points"); --np takes a list of rank counts (2D and 3D scenes run on each).

usage: scripts/long_runs.py [--bin build/release/dpmpm] [--np 2 | --np 1,2] [--out DIR]
       [--scenes a,b,...] [--shapes standard,quadratic,cubic,pair,linear_gauss]
       [--placement as_shipped|random|uniform] [--transits 20]

By default every scene but the W1-W3 columns, which scripts/stability_map.py covers.
"""
import argparse
import glob
import os
import re
import subprocess
import time

from stability_map import SHAPES as MAP_SHAPES  # the four shape choices of the stability map

# and linear grid functions with one Gauss point per cell (doc/input.md, "Which to pick")
SHAPES = dict(MAP_SHAPES, linear_gauss="kernel = 'linear', quadrature = 'gauss', gauss_points = 1, "
                                       "field_kernel = 'linear', field_radius = 0.75")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# the columns of the stability map (scripts/stability_map.py) are left to it
MAPPED = ('w1', 'w2', 'w3', 'w1_2d', 'w1_3d')
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
           OMPI_MCA_rmaps_base_oversubscribe='1')


def set_run(txt, key, val):
    """Set key = val inside &run (replacing it where it is given)."""
    m = re.search(r'(?s)&run\b(.*?)\n\s*/', txt)
    body = m.group(1)
    if re.search(r'(?m)^\s*%s\s*=' % key, body):
        body = re.sub(r'(?m)^(\s*)%s\s*=.*$' % key, r'\g<1>%s = %s' % (key, val), body, count=1)
    else:
        body = body + '\n  %s = %s' % (key, val)
    return txt[:m.start(1)] + body + txt[m.end(1):]


def grid(txt):
    """ndim, ncells and length of &grid (one-line or multi-line form)."""
    g = re.search(r'(?s)&grid\b(.*?)/', txt).group(1)
    ndim = int(re.search(r'ndim\s*=\s*(\d)', g).group(1))

    def vec(key, default):
        m = re.search(r'(?<!\w)%s\s*=\s*([-+\d.eE ,]+?)(?:\n|,\s*[a-z]|$)' % key, g)
        if not m:
            return [default] * ndim
        return [float(x) for x in m.group(1).replace(',', ' ').split()][:ndim]
    return ndim, vec('ncells', 1.0), vec('length', 1.0)


def set_placement(txt, placement):
    """Every &region group with its points placed as placement (one seed per region)."""
    k = [0]

    def one(m):
        body = m.group(0)
        k[0] += 1
        body = re.sub(r"(?m),?\s*\bplacement\s*=\s*'[^']*'", '', body)
        body = re.sub(r"(?m),?\s*\bseed\s*=\s*\d+", '', body)
        return body.replace('&region', "&region placement = '%s', seed = %d," % (placement, k[0]), 1)
    return re.sub(r'(?s)&region\b.*?\n?\s*/', one, txt)


def make(txt, shape, name, outdir, t_end=None, max_steps=None):
    # the reference solutions of the wave and consolidation benchmarks go; the
    # benchmarks that set the body's start and load (axial_bar, mms) stay
    for m in re.finditer(r'(?s)&benchmark\b.*?\n\s*/|&benchmark\b[^\n]*?/', txt):
        if re.search(r"name\s*=\s*'(biot_column|terzaghi)'", m.group(0)):
            txt = txt.replace(m.group(0), '')
    if shape is not None:
        if re.search(r'(?m)^\s*&shape\b', txt):
            txt = re.sub(r'(?s)&shape\b.*?/', '&shape ' + SHAPES[shape] + ' /', txt)
        else:
            txt = txt.rstrip() + '\n&shape ' + SHAPES[shape] + ' /\n'
    txt = set_run(txt, 'name', "'%s'" % name)
    if t_end is not None:
        txt = set_run(txt, 't_end', '%.6g' % t_end)
    if max_steps is not None:
        txt = set_run(txt, 'max_steps', str(max_steps))
    txt = re.sub(r"(?m)^(\s*)dir\s*=\s*'[^']*'", r"\1dir = '%s'" % outdir, txt)
    if not re.search(r'(?m)^\s*dir\s*=', txt):
        txt = txt.rstrip() + "\n&output dir = '%s' /\n" % outdir
    path = os.path.join(outdir, name + '.nml')
    open(path, 'w').write(txt)
    return path


def run(args, path, np_):
    t0 = time.time()
    r = subprocess.run(['mpirun', '-n', str(np_), args.bin, path], env=ENV, capture_output=True,
                       text=True)
    return r.returncode, r.stdout + r.stderr, time.time() - t0


def first_step(args, txt, scene):
    """Wave-CFL step of the scene's first step and its Courant number."""
    path = make(txt, None, scene + '_probe', args.out, max_steps=1)
    rc, log, _ = run(args, path, 1)
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
    ap.add_argument('--placement', default='as_shipped', choices=('as_shipped', 'random', 'uniform'))
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
        txt = open(os.path.join(ROOT, 'inputs', scene + '.nml')).read()
        if args.placement != 'as_shipped':
            txt = set_placement(txt, args.placement)
        cfl_m = re.search(r'(?m)^\s*cfl\s*=\s*([\d.eE+-]+)', txt)
        cfl = float(cfl_m.group(1)) if cfl_m else 0.5
        ndim, ncells, length = grid(txt)
        h = min(l / n for l, n in zip(length, ncells))
        dt, rc, log = first_step(args, txt, scene)
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
            path = make(txt, shape, name, args.out, t_end=t_end)
            rc, log, wall = run(args, path, np_)
            open(os.path.join(args.out, name + '.log'), 'w').write(log)
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
