"""Results as labelled arrays (xarray) on the short runs made here: every value equals
the Run's own reading by id and frame."""
import numpy as np

import dpmpm


def test_points_dataset(run_np2):
    with dpmpm.open_run(run_np2) as run:
        ds = dpmpm.points_dataset(run, "fluid")
        assert ds.sizes["time"] == len(run.frames) and ds.sizes["component"] == 2
        np.testing.assert_array_equal(ds.time.values, run.times)
        np.testing.assert_array_equal(ds.step.values, run.steps)
        for k, fr in enumerate(run.frames):
            ps = fr["fluid"]
            sel = ds.sel(time=fr.time)
            np.testing.assert_array_equal(sel.id.values, ps.id)
            np.testing.assert_array_equal(sel.pore_pressure.values, ps["pore_pressure"])
            np.testing.assert_array_equal(sel.x.sel(component="y").values, ps["x"][:, 1])
        # The nearest frame to a time, as users select it.
        near = ds.pore_pressure.sel(time=0.012, method="nearest")
        np.testing.assert_array_equal(near.values, run.frame_at(0.012)["fluid"]["pore_pressure"])
        solid = dpmpm.points_dataset(run, "solid", frames=[0, -1])
        assert list(solid.stress_component.values) == ["xx", "yy", "zz", "yz", "xz", "xy"]
        np.testing.assert_array_equal(solid.stress.sel(stress_component="yy").values[-1],
                                      run.frames[-1]["solid"].stress_component("yy"))
        # Grouped by material: one group per material id of the set.
        assert set(solid.groupby("material_id").groups) == set(
            np.unique(run.frames[0]["solid"]["material"]).astype(float))
        diag = dpmpm.diagnostics_dataset(run)
        np.testing.assert_array_equal(diag.kinetic_energy.values,
                                      run.diagnostics["kinetic_energy"])
        prof = dpmpm.profile(run, "pore_pressure", frame=-1)
    da = dpmpm.profile_dataarray(prof)
    np.testing.assert_array_equal(da.values, prof.mean)
    np.testing.assert_array_equal(da.position.values, prof.centres)
