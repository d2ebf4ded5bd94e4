"""The Terzaghi series against independent limits."""
import numpy as np
from math import erf

from dpmpm import terzaghi


def test_boundaries_and_start():
    z = np.linspace(0, 1, 11)
    p = terzaghi.pore_pressure(z, 1e-9 + 0.2, 1.0, 1.0, 100.0)
    assert abs(p[0]) < 1e-12                                  # drained top
    assert np.all(np.diff(p) > 0)                             # grows with depth
    # Early times: the layer looks like a half-space, p = p0 erf(z / (2 sqrt(c_v t))).
    t = 1e-3
    zz = np.linspace(0, 0.2, 9)
    want = 100.0 * np.array([erf(v / (2 * np.sqrt(t))) for v in zz])
    np.testing.assert_allclose(terzaghi.pore_pressure(zz, t, 1.0, 1.0, 100.0, nterms=2000),
                               want, atol=1e-3)


def test_degree_of_consolidation():
    tv = np.array([1e-3, 1e-2, 5e-2])
    np.testing.assert_allclose(terzaghi.degree(tv, nterms=4000), 2 * np.sqrt(tv / np.pi),
                               rtol=1e-3)
    # U is one minus the mean of p / p0 over the layer.
    z = (np.arange(4000) + 0.5) / 4000
    for t in (0.1, 0.5):
        mean = np.mean(terzaghi.pore_pressure(z, t, 1.0, 1.0, 1.0))
        np.testing.assert_allclose(terzaghi.degree(t), 1 - mean, atol=1e-6)


def test_coefficients():
    # Incompressible fluid: c_v = k E_c / gamma_w, p0 = q.
    np.testing.assert_allclose(terzaghi.consolidation_coefficient(1e-3, 1e7, 0.3),
                               1e-3 * 1e7 / 9810.0, rtol=1e-15)
    assert terzaghi.initial_pressure(1e3, 1e7, 0.3) == 1e3
    np.testing.assert_allclose(terzaghi.initial_pressure(1e3, 1e7, 0.3, 1e8),
                               1e3 * (1e8 / 0.3) / (1e7 + 1e8 / 0.3))


def test_settlement():
    h, c_v, p0, q, e_c = 2.0, 0.5, 90.0, 100.0, 1e4
    z = np.linspace(0, h, 9)
    # At once the skeleton carries q - p0 (the series' tail at t = 0 falls as 1 / nterms);
    # in the end q; the base never moves.
    np.testing.assert_allclose(terzaghi.settlement(z, 0.0, h, c_v, p0, q, e_c, nterms=20000),
                               (q - p0) * (h - z) / e_c, atol=2e-5 * q * h / e_c)
    np.testing.assert_allclose(terzaghi.settlement(z, 1e3, h, c_v, p0, q, e_c),
                               q * (h - z) / e_c, rtol=1e-12, atol=1e-15)
    assert abs(terzaghi.settlement(h, 0.3, h, c_v, p0, q, e_c)) < 1e-15
    # At the top: H (q - p0 (1 - U)) / E_c; below it, the strain (q - p) / E_c integrated.
    for t in (0.05, 0.4):
        tv = c_v * t / h ** 2
        np.testing.assert_allclose(terzaghi.settlement(0.0, t, h, c_v, p0, q, e_c),
                                   h * (q - p0 * (1 - terzaghi.degree(tv))) / e_c, rtol=1e-12)
        zz = (np.arange(4000) + 0.5) / 4000 * (h - 0.5) + 0.5
        strain = (q - terzaghi.pore_pressure(zz, t, h, c_v, p0)) / e_c
        np.testing.assert_allclose(terzaghi.settlement(0.5, t, h, c_v, p0, q, e_c),
                                   strain.mean() * (h - 0.5), rtol=1e-6)
