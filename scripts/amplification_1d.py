#!/usr/bin/env python3
"""Amplification matrix of the linearised 1D double-point step (doc/verification.md,
"Long runs of the two-phase step").

The step of src/solver (Standard MPM grid functions, point quadrature) is written
as a linear map of the state (v_s, sigma', v_f, p) at the points, with the points
held in place (at the benchmark loads they move about 1e-7 m). Its columns are
the step applied to unit states; the largest |eigenvalue| is the amplification
per step. Options follow &run: scheme (MUSL/USL), flip, drag (implicit/explicit)
and remap_drag (the relative velocity added by the MUSL remap gets the step's
implicit drag: the split of the locked velocity between the two point sets is
removed, and what remains is relaxed; split=False keeps the relaxation alone).

usage: scripts/amplification_1d.py [--cells 30] [--seed 1]
"""
import argparse
import numpy as np

G = 9.81
F_LOCK = 0.1


def hat_matrices(x, h, nnodes):
    """Linear hat weights and x-derivatives of nodes 0..nnodes-1 at the points x."""
    n = len(x)
    N = np.zeros((n, nnodes))
    dN = np.zeros((n, nnodes))
    i = np.minimum((x // h).astype(int), nnodes - 2)
    xi = x / h - i
    r = np.arange(n)
    N[r, i] = 1 - xi
    N[r, i + 1] = xi
    dN[r, i] = -1 / h
    dN[r, i + 1] = 1 / h
    return N, dN


def step_matrix(sc, dt, musl=True, flip=1.0, implicit=True, remap_drag=True, split=True):
    """Matrix of one step acting on (v_s, sigma', v_f, p) at the points."""
    Ns, dNs = sc['Ns'], sc['dNs']
    Nf, dNf = sc['Nf'], sc['dNf']
    ms, mf, Vs, Vf, n = sc['ms'], sc['mf'], sc['Vs'], sc['Vf'], sc['n']
    mIs, mIf = Ns.T @ ms, Nf.T @ mf
    D = Nf.T @ (sc['Q'] * Vf)                      # sum N m_f n g / k = sum N Q V

    def inverse(m):
        r = np.where(m > 0, 1 / np.where(m > 0, m, 1), 0.0)
        r[-1] = 0.0                                # fixed, impermeable bottom
        return r

    iS, iF = inverse(mIs), inverse(mIf)
    both = (mIs > 0) & (mIf > 0)
    tot = np.where(both, mIs + mIf, 1.0)
    det = np.where(both, mIs * mIf + dt * D * (mIs + mIf), 1.0)
    ns, nf = len(ms), len(mf)
    size = 2 * ns + 2 * nf
    A = np.zeros((size, size))
    for col in range(size):
        s = np.zeros(size)
        s[col] = 1.0
        vs, sg, vf, p = s[:ns], s[ns:2 * ns], s[2 * ns:2 * ns + nf], s[2 * ns + nf:]
        us, uf = iS * (Ns.T @ (ms * vs)), iF * (Nf.T @ (mf * vf))
        fs = -(dNs.T @ (Vs * sg)) + dNf.T @ (Vf * (1 - n) * p)
        ff = dNf.T @ (Vf * n * p)
        w = uf - us
        r1, r2 = fs + D * w, ff - D * w
        if implicit:
            e = dt * D
            a_s = ((mIf + e) * r1 + e * r2) / det
            a_f = (e * r1 + (mIs + e) * r2) / det
        else:
            a_s, a_f = r1 * iS, r2 * iF
        a_s = np.where(both, a_s, fs * iS)
        a_f = np.where(both, a_f, ff * iF)
        a_s[-1] = a_f[-1] = 0.0
        uns, unf = us + dt * a_s, uf + dt * a_f
        vs1 = flip * (vs + Ns @ (uns - us)) + (1 - flip) * (Ns @ uns)
        vf1 = flip * (vf + Nf @ (unf - uf)) + (1 - flip) * (Nf @ unf)
        if musl:
            rs, rf = iS * (Ns.T @ (ms * vs1)), iF * (Nf.T @ (mf * vf1))
            if implicit and remap_drag and split:
                # locked_velocity and remove_split in src/solver/dpmpm_drag.f90: the
                # increment the drag makes common, (1 - f) times the increment of the
                # mixture velocity in the update, projected through each set; their
                # difference is removed.
                f = mIs * mIf / det
                free = both.copy()
                free[-1] = False                   # the fixed bottom
                c = np.where(free, (1 - f) * (mIs * (uns - us) + mIf * (unf - uf)) / tot, 0.0)
                split_v = iF * (Nf.T @ (mf * (Nf @ c))) - iS * (Ns.T @ (ms * (Ns @ c)))
                rs = np.where(free, rs + mIf / tot * split_v, rs)
                rf = np.where(free, rf - mIs / tot * split_v, rf)
            if implicit and remap_drag:
                # drag_relax in src/solver/dpmpm_drag.f90
                f = mIs * mIf / det
                g = np.where(f < F_LOCK, f + (1 - f) * f / F_LOCK, 1.0)
                mix = (mIs * rs + mIf * rf) / tot
                wstep = unf - uns
                wr = wstep + g * (rf - rs - wstep)
                rs = np.where(both, mix - mIf / tot * wr, rs)
                rf = np.where(both, mix + mIs / tot * wr, rf)
        else:
            rs, rf = uns, unf
        sg1 = sg + dt * sc['Ec'] * (dNs @ rs)
        p1 = p - sc['Kf'] * dt / n * ((1 - n) * (dNf @ rs) + n * (dNf @ rf))
        A[:, col] = np.r_[vs1, sg1, vf1, p1]
    return A


def scene(k, Kf, cells, seed, placement):
    """A column of the W scenes (n_f = 0.3, rho_s = 2650, rho_f = 1000, E_c = 10 MPa),
    0.1 m cells, 2 solid and 2 fluid points per cell."""
    n, rhos, rhof, Ec, h = 0.3, 2650.0, 1000.0, 1.0e7, 0.1
    L = cells * h
    if placement == 'uniform':
        rng = np.random.default_rng(seed)
        xs = np.sort(rng.uniform(0, L, 2 * cells))
        xf = np.sort(rng.uniform(0, L, 2 * cells))
    else:
        xs = (np.arange(2 * cells) + 0.5) * h / 2
        xf = xs.copy()
    V = np.full(2 * cells, L / (2 * cells))
    Ns, dNs = hat_matrices(xs, h, cells + 1)
    Nf, dNf = hat_matrices(xf, h, cells + 1)
    rsat = (1 - n) * rhos + n * rhof
    return dict(Ns=Ns, dNs=dNs, Nf=Nf, dNf=dNf, ms=(1 - n) * rhos * V, mf=n * rhof * V, Vs=V,
                Vf=V, n=n, Ec=Ec, Kf=Kf, Q=n * n * rhof * G / k, h=h,
                cu=np.sqrt((Ec + Kf / n) / rsat))


def radius(A):
    return max(abs(np.linalg.eigvals(A)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--cells', type=int, default=30)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--seeds', type=int, default=1, help='also the next seeds (largest over them)')
    a = ap.parse_args()
    cfls = [0.1, 0.3, 0.5, 0.8]
    print('largest |eigenvalue| of the step at Courant numbers', cfls, '(on the undrained wave)')
    cases = [('W1', 1e-5, 3e6), ('W2', 1.0, 3e6), ('W3', 1e-4, 2.2e9)]
    variants = [('MUSL, FLIP 1, implicit drag, remap_drag off', dict(remap_drag=False)),
                ('MUSL, PIC, implicit drag, remap_drag off', dict(remap_drag=False, flip=0.0)),
                ('USL, FLIP 1, implicit drag', dict(musl=False)),
                ('MUSL, FLIP 1, implicit drag, remap_drag relaxation only', dict(split=False)),
                ('MUSL, FLIP 1, implicit drag, remap_drag on', dict())]
    for placement in ['regular', 'uniform']:
        for name, k, Kf in cases:
            scs = [scene(k, Kf, a.cells, a.seed + j, placement) for j in range(a.seeds)]
            for label, opt in variants:
                r = [max(radius(step_matrix(sc, c * sc['h'] / sc['cu'], **opt)) for sc in scs)
                     for c in cfls]
                print('%-8s %s  %-45s %s' % (placement, name, label, '  '.join('%.6f' % x for x in r)),
                      flush=True)
    # Explicit drag at fractions of the nodal drag limit 2 / (D (1/m_s + 1/m_f)).
    for name, k, Kf in cases:
        sc = scene(k, Kf, a.cells, a.seed, 'uniform')
        mIs, mIf = sc['Ns'].T @ sc['ms'], sc['Nf'].T @ sc['mf']
        D = sc['Nf'].T @ (sc['Q'] * sc['Vf'])
        ok = (mIs > 0) & (mIf > 0)
        dtd = min(2 / (D[ok] * (1 / mIs[ok] + 1 / mIf[ok])))
        r = [radius(step_matrix(sc, min(f * dtd, 0.5 * sc['h'] / sc['cu']), implicit=False))
             for f in [0.5, 0.8]]
        print('uniform  %s  MUSL, FLIP 1, explicit drag at 0.5 and 0.8 of its limit  %s' %
              (name, '  '.join('%.6f' % x for x in r)))


if __name__ == '__main__':
    main()
