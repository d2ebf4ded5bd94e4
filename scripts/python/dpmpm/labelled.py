"""Results as labelled arrays (xarray): the points of a set over the frames, the
diagnostics, the verification records and a profile.

    with dpmpm.open_run("out/consolidation_2d.h5") as run:
        ds = dpmpm.points_dataset(run, "fluid")      # dims time, id (and component)
    ds.pore_pressure.sel(time=0.2, method="nearest")
    ds.x.sel(component="y")
    dpmpm.diagnostics_dataset(run).kinetic_energy.plot()

A point absent from a frame (it left a drained face, or entered later) is NaN there;
integer datasets become floats so that they can hold NaN, except ``id`` (a coordinate).
"""
import numpy as np
import xarray as xr

from .run import STRESS_COMPONENTS

AXES = ("x", "y", "z")


def points_dataset(run, name, frames=None):
    """The point set ``name`` over the frames (all, or the indices given) as an
    ``xarray.Dataset``: coordinates ``time``, ``step`` (along time), ``id`` (every id
    that occurs, sorted), ``component`` (x, y, z up to ndim) and ``stress_component``
    (xx ... xy); one variable per dataset of the set."""
    frames = [run.frames[k] for k in frames] if frames is not None else list(run.frames)
    sets = [fr.get(name) for fr in frames]
    ids = np.unique(np.concatenate([ps.id for ps in sets if ps is not None]
                                   or [np.zeros(0, dtype=np.int64)]))
    names = sorted({d for ps in sets if ps is not None for d in ps.keys()} - {"id"})
    comps = list(AXES[:run.ndim])
    data = {}
    for d in names:
        first = next(ps[d] for ps in sets if ps is not None and d in ps)
        tail = first.shape[1:]
        arr = np.full((len(frames), len(ids)) + tail, np.nan)
        for k, ps in enumerate(sets):
            if ps is None or d not in ps:
                continue
            arr[k, np.searchsorted(ids, ps.id)] = ps[d]
        dims = ["time", "id"]
        if tail == (6,) and d == "stress":
            dims.append("stress_component")
        elif tail:
            dims.append("component")
            if tail[0] != len(comps):
                raise ValueError(f"{name}/{d}: {tail[0]} columns for ndim {run.ndim}")
        data[d] = (dims, arr)
    coords = {"time": [fr.time for fr in frames], "id": ids,
              "step": ("time", [fr.step for fr in frames])}
    if any("component" in v[0] for v in data.values()):
        coords["component"] = comps
    if "stress" in data:
        coords["stress_component"] = list(STRESS_COMPONENTS)
    ds = xr.Dataset(data, coords=coords, attrs={"file": run.path, "set": name,
                                                "ndim": run.ndim})
    if "material" in ds:
        # The material of a point does not change: one value per id, as a coordinate.
        mat = ds["material"].max("time").values
        ds = ds.assign_coords(material_id=("id", mat.astype(float)))
    return ds


def diagnostics_dataset(run):
    """``/diagnostics`` as an ``xarray.Dataset`` along ``time`` (``step`` a coordinate)."""
    d = run.diagnostics
    if not d:
        return xr.Dataset()
    t = d["time"]
    return xr.Dataset({k: ("time", v) for k, v in d.items() if k not in ("time", "step")},
                      coords={"time": t, "step": ("time", d["step"])},
                      attrs={"file": run.path})


#: The records of /verification (doc/output.md) and the datasets along each: a one-phase
#: benchmark's errors along ``time`` (its diagnostics records), a two-phase benchmark's
#: along ``frame_time`` (its frames) with the reference profiles along ``profile_z``, and
#: a rigid drive's mean force along ``drive_time``.
VERIFICATION_AXES = (("profile_z", "profile_"), ("drive_time", "drive_force_"),
                     ("frame_time", ""), ("time", ""))


def verification_dataset(run):
    """``/verification`` as an ``xarray.Dataset``: each series along the record it
    belongs to (dims ``time``, ``frame_time``, ``profile_z``, ``drive_time``, those the
    file has; see VERIFICATION_AXES), the scalar attributes (``max_...``, ``final_...``,
    ``steps``, ...) as the dataset's attrs. Empty without /verification."""
    v = run.verification
    attrs = dict(run.verification_attrs, file=run.path)
    if not v:
        return xr.Dataset(attrs=attrs)
    coords = {name: np.asarray(v[name]) for name, _ in VERIFICATION_AXES if name in v}
    data = {}
    for key, arr in v.items():
        if key in coords:
            continue
        arr = np.asarray(arr)
        dim = next((name for name, prefix in VERIFICATION_AXES if name in coords
                    and key.startswith(prefix) and len(coords[name]) == len(arr)), None)
        data[key] = ((dim,) if dim else (f"{key}_record",), arr)
    return xr.Dataset(data, coords=coords, attrs=attrs)


def profile_dataarray(prof):
    """A ``Profile`` as an ``xarray.DataArray`` of the bin means along its axis (coordinate
    ``position``: the bin centres; ``count`` the points per bin)."""
    return xr.DataArray(prof.mean, dims=["position"],
                        coords={"position": prof.centres, "count": ("position", prof.count)},
                        name=prof.quantity, attrs={"time": prof.time, "axis": prof.axis})
