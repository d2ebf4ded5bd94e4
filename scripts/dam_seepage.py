#!/usr/bin/env python3
"""Steady seepage through a rectangular dam on an impervious base (doc/verification.md,
"Seepage through a rectangular dam"): the free surface and pore pressure of the
exact free-boundary problem, computed with Baiocchi's transformation, against the
fluid points of a run.

The dam is L wide and H1 high, the reservoir at x = 0 stands H1 high, the tailwater
at x = L stands H2 high (the face above it is a seepage face). With the hydraulic head
phi and the free surface y = h(x), Baiocchi's variable w(x, y) = int_y^h (phi - t) dt
solves the obstacle problem w >= 0, -lap w + 1 >= 0, w (-lap w + 1) = 0 with
w = (H1 - y)^2 / 2 at x = 0, (H2 - y)_+^2 / 2 at x = L, 0 at the top and
H1^2 / 2 (1 - x / L) + H2^2 x / (2 L) on the base; the wet region is w > 0, the pore
pressure is p = -rho_f g dw/dy, and the discharge is k (H1^2 - H2^2) / (2 L) (Charny).
It is solved here by projected SOR on a regular grid (red-black ordering).

usage: scripts/dam_seepage.py [RUN.h5] [--length 1] [--height 1] [--tail 0]
       [--cells 20] [--n 80] [--plot FIG.png]
  without RUN.h5: the reference free surface at a few x and its convergence
  with RUN.h5: per frame, the free surface of each column of cells (the highest water
  point plus half the point spacing of 2 points per cell) against the reference at the
  column's centre, and the pore pressure of the water points more than a cell below
  the reference surface against the reference (RMS over the points and over the cell
  means, in rho_f g H1); --plot draws the last frame
"""
import argparse

import numpy as np

RHO_G = 1000.0 * 9.81


def baiocchi(L=1.0, H1=1.0, H2=0.0, n=80, tol=1e-11, omega=1.9):
    """w on an (n L / H1 + 1) x (n + 1) grid; returns x, y, w, h(x)."""
    nx, ny = int(round(n * L / H1)), n
    x, y = np.linspace(0.0, L, nx + 1), np.linspace(0.0, H1, ny + 1)
    dx, dy = x[1] - x[0], y[1] - y[0]
    X, Y = np.meshgrid(x, y, indexing='ij')
    w = np.maximum(0.0, 0.5 * (H1 - Y) ** 2 * (1.0 - X / L))
    w[0, :] = 0.5 * (H1 - y) ** 2
    w[-1, :] = 0.5 * np.clip(H2 - y, 0.0, None) ** 2
    w[:, 0] = 0.5 * H1 ** 2 * (1.0 - x / L) + 0.5 * H2 ** 2 * x / L
    w[:, -1] = 0.0
    cx, cy = 1.0 / dx ** 2, 1.0 / dy ** 2
    diag = 2.0 * (cx + cy)
    I, J = np.meshgrid(np.arange(1, nx), np.arange(1, ny), indexing='ij')
    colours = [((I + J) % 2 == c) for c in (0, 1)]
    for _ in range(500000):
        change = 0.0
        for m in colours:
            i, j = I[m], J[m]
            gs = (cx * (w[i + 1, j] + w[i - 1, j]) + cy * (w[i, j + 1] + w[i, j - 1]) - 1.0) / diag
            new = np.maximum(0.0, w[i, j] + omega * (gs - w[i, j]))
            change = max(change, np.abs(new - w[i, j]).max())
            w[i, j] = new
        if change < tol:
            break
    h = np.zeros(nx + 1)
    for i in range(nx + 1):
        wet = np.nonzero(w[i, :] > 0.0)[0]
        if len(wet) == 0:
            continue
        j = wet.max()
        # w ~ c (h - y)^2 below the surface: place h where sqrt(w) reaches 0
        if j >= 1 and w[i, j - 1] > w[i, j]:
            s1, s0 = np.sqrt(w[i, j]), np.sqrt(w[i, j - 1])
            h[i] = y[j] + dy * s1 / (s0 - s1)
        else:
            h[i] = y[j]
    return x, y, w, h


def frame_errors(g, x, y, h, dwdy, args):
    """Free surface and pore-pressure errors of one frame (doc/verification.md)."""
    dx = args.length / args.cells
    xc = (np.arange(args.cells) + 0.5) * dx
    xf, p = g['fluid/x'][:], g['fluid/pore_pressure'][:]
    col = np.clip((xf[:, 0] / dx).astype(int), 0, args.cells - 1)
    top = np.array([xf[col == c, 1].max() if np.any(col == c) else 0.0 for c in range(args.cells)])
    surf = top + 0.25 * dx - np.interp(xc, x, h)
    i = np.clip(np.rint(xf[:, 0] / (x[1] - x[0])).astype(int), 0, len(x) - 1)
    j = np.clip(np.rint(xf[:, 1] / (y[1] - y[0])).astype(int), 0, len(y) - 1)
    err = (p + RHO_G * dwdy[i, j]) / (RHO_G * args.height)
    below = xf[:, 1] < np.interp(xf[:, 0], x, h) - dx
    cell = col * 100000 + (xf[:, 1] / dx).astype(int)
    means = np.array([err[below & (cell == c)].mean() for c in np.unique(cell[below])])
    return {'t': g.attrs['time'], 'n': len(xf), 'surf': surf, 'rms': np.sqrt(np.mean(err[below] ** 2)),
            'cells': np.sqrt(np.mean(means ** 2)), 'bias': err[below].mean(), 'xf': xf, 'p': p, 'err': err}


def compare(path, args):
    import h5py
    x, y, w, h = baiocchi(args.length, args.height, args.tail, args.n)
    dwdy = np.gradient(w, y, axis=1)
    print('| t [s] | fluid points | free surface - reference: mean | largest | '
          'pore pressure - reference / (rho_f g H1): RMS over points | RMS of cell means | mean |')
    print('|---|---|---|---|---|---|---|')
    f = h5py.File(path, 'r')
    for key in f['frames']:
        e = frame_errors(f['frames'][key], x, y, h, dwdy, args)
        print('| %.2f | %d | %+.3f | %.3f | %.3f | %.3f | %+.3f |' % (
            e['t'], e['n'], e['surf'].mean(), np.abs(e['surf']).max(), e['rms'], e['cells'], e['bias']))
    if args.plot:
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(11, 5.2))
        for a, val, cmap, lim, title in (
                (ax[0], e['p'] / (RHO_G * args.height), 'viridis', (0.0, 1.0), 'p / (rho_f g H1)'),
                (ax[1], e['err'], 'RdBu_r', (-0.3, 0.3), '(p - p_ref) / (rho_f g H1)')):
            sc = a.scatter(e['xf'][:, 0], e['xf'][:, 1], c=val, s=5, cmap=cmap, vmin=lim[0], vmax=lim[1])
            fig.colorbar(sc, ax=a, shrink=0.8)
            a.plot(x, h, 'k-', lw=1.2, label='free surface (Baiocchi)')
            a.plot(x, np.sqrt(np.clip(args.height ** 2 - (args.height ** 2 - args.tail ** 2) * x / args.length,
                                      0.0, None)), 'k:', lw=1, label='Dupuit parabola')
            a.set_aspect('equal')
            a.set_xlim(0.0, args.length)
            a.set_ylim(0.0, 1.2 * args.height)
            a.set_xlabel('x (m)')
            a.set_title('%s, t = %.1f s' % (title, e['t']))
        ax[0].set_ylabel('y (m)')
        ax[0].legend(loc='upper right', fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
        print('figure: ' + args.plot)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('run', nargs='?')
    ap.add_argument('--length', type=float, default=1.0)
    ap.add_argument('--height', type=float, default=1.0)
    ap.add_argument('--tail', type=float, default=0.0)
    ap.add_argument('--cells', type=int, default=20, help='cells of the run across the dam')
    ap.add_argument('--n', type=int, default=80, help='reference grid: intervals over the height')
    ap.add_argument('--plot', help='figure of the last frame (PNG)')
    args = ap.parse_args()
    if args.run:
        compare(args.run, args)
        return
    xs = [0.25, 0.5, 0.75, 0.9]
    print('| reference intervals over H1 | ' + ' | '.join('h(%g L)' % v for v in xs) + ' |')
    print('|---|' + '---|' * len(xs))
    for n in (40, 80, 160):
        x, y, w, h = baiocchi(args.length, args.height, args.tail, n)
        print('| %d | ' % n + ' | '.join('%.4f' % np.interp(v * args.length, x, h) for v in xs) + ' |')
    print('Dupuit parabola: ' + ', '.join('%.4f' % np.sqrt(args.height ** 2 - (args.height ** 2 - args.tail ** 2)
                                                        * v) for v in xs))


if __name__ == '__main__':
    main()
