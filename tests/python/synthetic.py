"""A small output file written with h5py in the layout of doc/output.md, with values
chosen by hand, for tests that need exact expectations."""
import h5py
import numpy as np

INPUT = """! synthetic
&run name = 'synthetic' /
&grid
  ndim = 2
  ncells = 2, 4      ! cells of 0.5 m
  origin = 0.0, 0.0
  length = 1.0, 2.0
/
"""

# Solid points: (id, x, y, volume, stress_yy). Fluid points: (id, x, y, volume, p).
SOLID = [(7, 0.1, 0.1, 1.0, -10.0), (3, 0.2, 0.4, 3.0, -20.0), (12, 0.1, 0.7, 2.0, -30.0),
         (5, 0.2, 1.9, 1.0, -40.0), (9, 0.1, 2.0, 1.0, -50.0), (1, 0.8, 0.3, 5.0, -99.0)]
FLUID = [(20, 0.1, 0.2, 1.0, 5.0), (22, 0.2, 0.3, 1.0, 7.0), (21, 0.1, 1.2, 2.0, 9.0),
         (24, 0.2, 1.6, 1.0, 1.0), (23, 0.1, 1.7, 3.0, 3.0), (25, 0.9, 1.7, 1.0, 100.0)]


def _write_set(g, rows, order, kind):
    rows = [rows[k] for k in order]
    n = len(rows)
    ids = np.array([r[0] for r in rows], dtype=np.int64)
    x = np.array([[r[1], r[2]] for r in rows])
    g["id"] = ids
    g["x"] = x
    g["v"] = np.zeros((n, 2))
    g["displacement"] = np.zeros((n, 2))
    g["mass"] = np.ones(n)
    g["volume"] = np.array([r[3] for r in rows])
    g["material"] = np.ones(n, dtype=np.int32)
    if kind == "solid":
        s = np.zeros((n, 6))
        s[:, 1] = [r[4] for r in rows]
        s[:, 0] = 0.5 * s[:, 1]        # xx: half of yy
        s[:, 5] = 0.1 * ids            # xy: by id, to see the matching
        g["stress"] = s
    else:
        g["porosity"] = np.full(n, 0.3)
        g["pore_pressure"] = np.array([r[4] for r in rows])


def write_synthetic(path, fluid_stress=False):
    """Two frames (t = 0 and 0.5) with the points in different file orders; the fluid set
    has porosity and pore_pressure and, unless fluid_stress, no stress; the solid set no
    porosity."""
    with h5py.File(path, "w") as f:
        f.attrs["dpmpm_version"] = np.bytes_("0.0.0")
        f.attrs["git_commit"] = np.bytes_("synthetic")
        f.attrs["nranks"] = np.int32(1)
        f.attrs["ndim"] = np.int32(2)
        f["input"] = np.bytes_(INPUT)
        for k, (t, step) in enumerate([(0.0, 0), (0.5, 10)]):
            fr = f.create_group(f"frames/{k:06d}")
            fr.attrs["time"] = np.float64(t)
            fr.attrs["step"] = np.int64(step)
            rng = np.random.default_rng(k)
            _write_set(fr.create_group("solid"), SOLID, rng.permutation(len(SOLID)), "solid")
            g = fr.create_group("fluid")
            _write_set(g, FLUID, rng.permutation(len(FLUID)), "fluid")
            if fluid_stress:
                n = len(FLUID)
                g["stress"] = -np.outer(g["pore_pressure"][...], [1, 1, 1, 0, 0, 0]).reshape(n, 6)
        d = f.create_group("diagnostics")
        for name in ("time", "kinetic_energy", "strain_energy", "external_work"):
            d.create_dataset(name, data=np.array([0.0, 0.5]), maxshape=(None,))
        v = f.create_group("verification")
        v["error_pore_pressure"] = np.array([0.0, 0.25])
        v.attrs["l2_error"] = np.float64(1.5e-3)
    return path
