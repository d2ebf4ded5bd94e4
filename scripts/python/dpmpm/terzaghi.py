"""Terzaghi's one-dimensional consolidation (doc/theory.md 9.3, the same series as
src/verify/dpmpm_terzaghi.f90, written again here): a layer of thickness H, drained loaded top,
impermeable bottom, a load q applied at t = 0.

With z the depth below the drained top, T_v = c_v t / H^2 and M_m = pi (2m + 1) / 2:
    p(z, t) = p0 sum_m (2 / M_m) sin(M_m z / H) exp(-M_m^2 T_v)
    U(T_v)  = 1 - sum_m (2 / M_m^2) exp(-M_m^2 T_v)
c_v = k / (gamma_w (1/E_c + n_f/K_f)) and p0 = q M / (E_c + M), M = K_f / n_f, for a
compressible pore fluid (k the hydraulic conductivity in m/s).

The skeleton strains by sigma' / E_c = (q - p) / E_c, so a point at depth z above the
fixed base (depth H) has settled by
    s(z, t) = [q (H - z) - p0 sum_m (2 H / M_m^2) cos(M_m z / H) exp(-M_m^2 T_v)] / E_c,
(q - p0) (H - z) / E_c at once and q (H - z) / E_c in the end; at the top,
s(0, t) = H [q - p0 (1 - U)] / E_c.
"""
import numpy as np

GAMMA_W = 9810.0  # unit weight of water used by dpmpm's verification (N/m^3)


def consolidation_coefficient(k, e_c, n_f, k_f=np.inf, gamma_w=GAMMA_W):
    """c_v (m^2/s) from the conductivity k (m/s), the constrained modulus e_c, the
    porosity n_f and the fluid bulk modulus k_f (Pa; inf for an incompressible fluid)."""
    return k / (gamma_w * (1.0 / e_c + n_f / k_f))


def initial_pressure(q, e_c, n_f, k_f=np.inf):
    """Undrained excess pore pressure p0 right after the load q."""
    if np.isinf(k_f):
        return q
    m = k_f / n_f
    return q * m / (e_c + m)


def pore_pressure(z, t, h, c_v, p0, nterms=200):
    """Excess pore pressure at depth z (below the drained top) and time t."""
    z = np.asarray(z, dtype=float)
    tv = c_v * t / h ** 2
    m = np.arange(nterms)
    mm = np.pi * (2 * m + 1) / 2.0
    terms = (2.0 / mm) * np.sin(np.multiply.outer(z / h, mm)) * np.exp(-mm ** 2 * tv)
    return p0 * terms.sum(axis=-1)


def degree(tv, nterms=200):
    """Average degree of consolidation U(T_v)."""
    m = np.arange(nterms)
    mm = np.pi * (2 * m + 1) / 2.0
    return 1.0 - np.sum((2.0 / mm ** 2) * np.exp(-np.multiply.outer(tv, mm ** 2)), axis=-1)


def settlement(z, t, h, c_v, p0, q, e_c, nterms=200):
    """Settlement (downward displacement, m) at depth z below the drained top of the layer
    at time t after the load q: the strain (q - p) / E_c integrated from z to the fixed
    base (see the module doc)."""
    z = np.asarray(z, dtype=float)
    tv = c_v * t / h ** 2
    m = np.arange(nterms)
    mm = np.pi * (2 * m + 1) / 2.0
    terms = (2.0 * h / mm ** 2) * np.cos(np.multiply.outer(z / h, mm)) * np.exp(-mm ** 2 * tv)
    return (q * (h - z) - p0 * terms.sum(axis=-1)) / e_c
