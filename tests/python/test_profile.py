"""Profiles and cell averages against hand computations on a file written here."""
import numpy as np
import pytest

import dpmpm
from synthetic import write_synthetic


@pytest.fixture
def synth(tmp_path):
    return write_synthetic(str(tmp_path / "synthetic.h5"))


def test_grid_from_input(synth):
    with dpmpm.open_run(synth) as run:
        g = run.grid
        assert g.ndim == 2
        assert g.ncells.tolist() == [2, 4]
        assert g.spacing.tolist() == [0.5, 0.5]
        assert g.origin.tolist() == [0.0, 0.0] and g.length.tolist() == [1.0, 2.0]


def test_cell_averages_volume_weighted(synth):
    # Bins along y: [0, .5), [.5, 1), [1, 1.5), [1.5, 2]; the point at y = 2 is in the last.
    # Only the strip 0 <= x <= 0.5 (the points at x = 0.8, 0.9 are left out).
    with dpmpm.open_run(synth) as run:
        strip = {0: (0.0, 0.5)}
        s = dpmpm.profile(run, "stress_yy", frame=1, axis=1, where=strip)
        assert s.centres.tolist() == [0.25, 0.75, 1.25, 1.75]
        want = [(1 * -10 + 3 * -20) / 4, -30.0, np.nan, (-40 - 50) / 2]
        np.testing.assert_allclose(s.mean, want, rtol=1e-15)
        assert s.count.tolist() == [2, 1, 0, 2]

        p = dpmpm.profile(run, "pore_pressure", frame=1, axis=1, where=strip)
        np.testing.assert_allclose(p.mean, [6.0, np.nan, 9.0, (1 * 1 + 3 * 3) / 4], rtol=1e-15)

        tot = dpmpm.profile(run, "total_stress_yy", frame=1, axis=1, where=strip)
        # sigma = sigma' - p per cell; a cell without fluid points has p = 0.
        np.testing.assert_allclose(tot.mean, [-17.5 - 6.0, -30.0, np.nan, -45.0 - 2.5],
                                   rtol=1e-15)
        # Shear components are the solid's only.
        sh = dpmpm.profile(run, "total_stress_xy", frame=1, axis=1, where=strip)
        np.testing.assert_allclose(sh.mean[0], (1 * 0.7 + 3 * 0.3) / 4, rtol=1e-15)


def test_unweighted_width_and_whole_section(synth):
    with dpmpm.open_run(synth) as run:
        s = dpmpm.profile(run, "stress_yy", frame=0, axis=1, weight=None, width=1.0)
        # Two bins of 1 m, all points (also x = 0.8): plain means.
        np.testing.assert_allclose(s.mean, [(-10 - 20 - 30 - 99) / 4, (-40 - 50) / 2])
        x = dpmpm.profile(run, "solid:x:0", frame=0, axis=0)
        assert x.centres.tolist() == [0.25, 0.75]
        np.testing.assert_allclose(x.mean[1], 0.8)


def test_point_values_sorted_by_id(synth):
    with dpmpm.open_run(synth) as run:
        for fr in run.frames:
            ps = fr["solid"]
            assert ps.id.tolist() == sorted(r[0] for r in __import__("synthetic").SOLID)
            # stress_xy was written as 0.1 * id, in the file's (shuffled) order.
            np.testing.assert_allclose(ps["stress"][:, 5], 0.1 * ps.id)
            fl = fr["fluid"]
            byid = {r[0]: r[4] for r in __import__("synthetic").FLUID}
            np.testing.assert_array_equal(fl["pore_pressure"], [byid[i] for i in fl.id])


def test_optional_datasets(synth):
    with dpmpm.open_run(synth) as run:
        fl, so = run.frames[0]["fluid"], run.frames[0]["solid"]
        assert "stress" not in fl and fl.get("stress") is None
        assert "porosity" not in so and so.get("porosity") is None
        with pytest.raises(KeyError):
            fl["stress"]
        assert run.diagnostics["time"].tolist() == [0.0, 0.5]
        assert run.verification["error_pore_pressure"].tolist() == [0.0, 0.25]
        assert run.verification_attrs == {"l2_error": 1.5e-3}
        assert "&grid" in run.input


def test_von_mises_by_hand():
    # Uniaxial stress: von Mises = |s|; pure shear tau: sqrt(3) tau.
    s = np.array([[5.0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 2.0]])
    np.testing.assert_allclose(dpmpm.von_mises(s), [5.0, 2.0 * np.sqrt(3.0)])


def test_bad_quantity(synth):
    with dpmpm.open_run(synth) as run, pytest.raises(ValueError):
        dpmpm.profile(run, "stress_ww")
