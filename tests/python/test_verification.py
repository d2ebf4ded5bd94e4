"""/verification as labelled arrays (dpmpm.verification_dataset): each series along its
record, on a file written with h5py and on short runs of a one-phase benchmark
(inputs/axial_bar.nml) and a two-phase one (inputs/t1.nml, Terzaghi) made here."""
import os

import h5py
import numpy as np
import pytest

import dpmpm
from conftest import ROOT
from synthetic import write_synthetic


def test_every_record_on_its_axis(tmp_path):
    path = write_synthetic(str(tmp_path / "v.h5"))
    with h5py.File(path, "a") as f:
        del f["verification"]
        v = f.create_group("verification")
        v["time"] = np.array([0.0, 0.1, 0.2])
        v["error_velocity"] = np.array([0.0, 1e-3, 2e-3])
        v["frame_time"] = np.array([0.0, 0.5])
        v["error_pore_pressure"] = np.array([0.0, 0.25])
        v["profile_z"] = np.linspace(0, 1, 5)
        v["profile_p"] = np.arange(5.0)
        v["drive_time"] = np.array([0.0, 0.3, 0.6])
        v["drive_force_x"] = np.array([0.0, -4.0, -5.0])
        v["mls_counts"] = np.array([1.0, 2.0, 3.0, 4.0])     # a series of no known record
        v.attrs["max_error_velocity"] = 2e-3
    with dpmpm.open_run(path) as run:
        ds = dpmpm.verification_dataset(run)
    assert ds.error_velocity.dims == ("time",) and ds.error_pore_pressure.dims == ("frame_time",)
    assert ds.profile_p.dims == ("profile_z",) and ds.drive_force_x.dims == ("drive_time",)
    assert ds.mls_counts.dims == ("mls_counts_record",)
    assert float(ds.error_pore_pressure.sel(frame_time=0.5)) == 0.25
    assert float(ds.drive_force_x.sel(drive_time=0.3)) == -4.0
    assert ds.attrs["max_error_velocity"] == 2e-3 and ds.attrs["file"] == path


def test_no_verification(tmp_path):
    path = write_synthetic(str(tmp_path / "none.h5"))
    with h5py.File(path, "a") as f:
        del f["verification"]
    with dpmpm.open_run(path) as run:
        ds = dpmpm.verification_dataset(run)
    assert len(ds.data_vars) == 0 and ds.attrs == {"file": path}


def short(scene, t_end, tmp_path):
    if not os.environ.get("DPMPM_BIN"):
        pytest.skip("DPMPM_BIN not set: no dpmpm executable to run")
    s = dpmpm.Scene.read(os.path.join(ROOT, "inputs", scene + ".nml"))
    s.set(run={"t_end": t_end}, output={"dir": "out", "frame_interval": t_end / 2})
    return dpmpm.simulate(s, workdir=tmp_path, progress=False)


def test_one_phase_benchmark(tmp_path):
    r = short("axial_bar", 0.02, tmp_path)
    with r.open() as run:
        ds = dpmpm.verification_dataset(run)
        v, attrs = run.verification, run.verification_attrs
    assert set(ds.dims) == {"time"} and ds.sizes["time"] == len(v["time"])
    for name in ("error_velocity", "error_displacement"):
        np.testing.assert_array_equal(ds[name].values, v[name])
        assert float(ds[name].max()) == attrs["max_" + name]
        assert float(ds[name].isel(time=-1)) == attrs["final_" + name]
    assert ds.attrs["steps"] == attrs["steps"] > 0


def test_two_phase_benchmark(tmp_path):
    r = short("t1", 0.04, tmp_path)
    with r.open() as run:
        ds = dpmpm.verification_dataset(run)
        times, v = run.times, run.verification
    np.testing.assert_allclose(ds.frame_time.values, times, rtol=1e-12)
    assert ds.error_pore_pressure.dims == ("frame_time",)
    assert ds.profile_p.dims == ("profile_z",) and ds.sizes["profile_z"] == 401
    np.testing.assert_array_equal(ds.time_factor.values, v["time_factor"])
    assert float(ds.error_settlement.isel(frame_time=-1)) == ds.attrs["final_error_settlement"]
