"""Profiles along one axis: point values and their averages over bins (grid cells by
default), for pore pressure, effective stress and total stress.

Quantities (``profile(..., quantity=...)``):

- ``pore_pressure``: fluid points, p (compression positive).
- ``stress_xx`` ... ``stress_xy``, ``von_mises``: solid points, the stress of the
  solid set (in a saturated region the effective stress sigma', tension positive).
- ``total_stress_xx`` ... ``total_stress_xy``: sigma = sigma' - p I per bin, the bin
  average of the solid stress minus the bin average of the fluid pore pressure (normal
  components; shear components are the solid ones). Without fluid points (a dry
  scene) it is the solid stress.
- ``SET:DATASET`` or ``SET:DATASET:COLUMN``: any dataset of a set, e.g.
  ``solid:porosity``, ``solid:displacement:1``.
"""
import numpy as np

from .run import STRESS_COMPONENTS


def bin_edges(grid, axis, width=None, lo=None, hi=None):
    """Bin edges along axis: from lo to hi (the grid's extent by default) in steps of
    width (one grid cell by default); the last bin ends at hi."""
    lo = grid.origin[axis] if lo is None else float(lo)
    hi = grid.origin[axis] + grid.length[axis] if hi is None else float(hi)
    width = grid.spacing[axis] if width is None else float(width)
    if not width > 0 or not hi > lo:
        raise ValueError(f"bins need width > 0 and hi > lo (width {width}, lo {lo}, hi {hi})")
    n = max(1, int(round((hi - lo) / width)))
    return lo + (hi - lo) * np.arange(n + 1) / n


def cell_average(positions, values, edges, weights=None):
    """Average of values over the points in each bin [edges[k], edges[k+1]) (the last
    bin includes its upper edge), weighted by weights if given. Returns (mean, count);
    mean is NaN in a bin without points. Points outside the edges are left out."""
    positions = np.asarray(positions, dtype=float)
    values = np.asarray(values, dtype=float)
    w = np.ones_like(values) if weights is None else np.asarray(weights, dtype=float)
    nb = len(edges) - 1
    k = np.searchsorted(edges, positions, side="right") - 1
    k[positions == edges[-1]] = nb - 1
    inside = (k >= 0) & (k < nb)
    k, values, w = k[inside], values[inside], w[inside]
    count = np.bincount(k, minlength=nb)
    wsum = np.bincount(k, weights=w, minlength=nb)
    vsum = np.bincount(k, weights=w * values, minlength=nb)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(count > 0, vsum / np.where(wsum == 0, 1.0, wsum), np.nan)
    return mean, count


class Profile:
    """A profile along one axis at one frame.

    ``centres``, ``edges``: the bins; ``mean``: bin averages (NaN where empty);
    ``count``: points per bin; ``x``, ``values``: the points themselves (position along
    the axis and value), sorted by position; ``time``: frame time; ``quantity``, ``axis``.
    """

    def __init__(self, quantity, axis, time, edges, mean, count, x, values):
        self.quantity, self.axis, self.time = quantity, axis, time
        self.edges = edges
        self.centres = 0.5 * (edges[:-1] + edges[1:])
        self.mean, self.count = mean, count
        order = np.argsort(x, kind="stable")
        self.x, self.values = x[order], values[order]

    def depth(self, top):
        """Bin centres as depth below top (top - centre)."""
        return top - self.centres

    def __repr__(self):
        return (f"Profile({self.quantity!r}, axis {self.axis}, t={self.time:.6g}, "
                f"{len(self.centres)} bins)")


def _selected(ps, where):
    """Boolean mask of the points of ps inside every (axis: (lo, hi)) of where."""
    mask = np.ones(len(ps), dtype=bool)
    if where:
        x = ps["x"]
        for ax, (lo, hi) in where.items():
            mask &= (x[:, ax] >= lo) & (x[:, ax] <= hi)
    return mask


def _set_values(frame, setname, getter, axis, where, weight):
    """(positions, values, weights) of the selected points of a set; empty when the
    frame has no such set."""
    ps = frame.get(setname)
    if ps is None or len(ps) == 0:
        e = np.zeros(0)
        return e, e, e
    m = _selected(ps, where)
    w = ps["volume"][m] if weight == "volume" else np.ones(int(m.sum()))
    return ps["x"][m, axis], np.asarray(getter(ps), dtype=float)[m], w


def profile(run, quantity, frame=-1, axis=None, width=None, lo=None, hi=None, where=None,
            weight="volume"):
    """The profile of quantity (see the module doc) along axis (default: the last axis,
    the vertical one in 2D and 3D) at frame (an index into run.frames, or a Frame).

    Bins are grid cells unless width is given; lo, hi limit them (default the grid).
    where = {axis: (lo, hi), ...} keeps only the points inside those ranges (a strip
    along the line). weight: 'volume' (point volume, the default) or None (plain mean).
    """
    fr = run.frames[frame] if isinstance(frame, (int, np.integer)) else frame
    axis = run.ndim - 1 if axis is None else int(axis)
    if not 0 <= axis < run.ndim:
        raise ValueError(f"axis {axis} outside 0..{run.ndim - 1}")
    edges = bin_edges(run.grid, axis, width, lo, hi)
    q = quantity

    if q == "pore_pressure":
        x, v, w = _set_values(fr, "fluid", lambda ps: ps["pore_pressure"], axis, where, weight)
        mean, count = cell_average(x, v, edges, w)
    elif q == "von_mises" or q.replace("stress_", "") in STRESS_COMPONENTS and \
            q.startswith("stress_"):
        x, v, w = _set_values(fr, "solid", lambda ps: ps.stress_component(q), axis, where,
                              weight)
        mean, count = cell_average(x, v, edges, w)
    elif q.startswith("total_stress_") and q[13:] in STRESS_COMPONENTS:
        comp = q[13:]
        x, v, w = _set_values(fr, "solid", lambda ps: ps.stress_component(comp), axis,
                              where, weight)
        mean, count = cell_average(x, v, edges, w)
        if comp in ("xx", "yy", "zz"):
            fp = fr.get("fluid")
            if fp is not None and "pore_pressure" in fp:
                xf, pf, wf = _set_values(fr, "fluid", lambda ps: ps["pore_pressure"], axis,
                                         where, weight)
                pmean, pcount = cell_average(xf, pf, edges, wf)
                mean = mean - np.where(pcount > 0, pmean, 0.0)
                # The points of a total stress are the solid points with sigma' only.
    elif ":" in q:
        parts = q.split(":")
        setname, dset = parts[0], parts[1]
        col = int(parts[2]) if len(parts) > 2 else None
        x, v, w = _set_values(fr, setname,
                              lambda ps: ps[dset] if col is None else ps[dset][:, col],
                              axis, where, weight)
        mean, count = cell_average(x, v, edges, w)
    else:
        raise ValueError(f"unknown quantity {quantity!r}: pore_pressure, stress_xx ... "
                         "stress_xy, von_mises, total_stress_xx ..., or SET:DATASET[:COLUMN]")
    return Profile(quantity, axis, fr.time, edges, mean, count, x, v)
