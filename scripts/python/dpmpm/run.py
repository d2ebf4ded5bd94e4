"""Reading one dpmpm output file (layout: doc/output.md).

``open_run(path)`` gives a ``Run``: the root attributes, the echoed input and its grid,
the frames with their time and step, per frame and point set the datasets as numpy
arrays sorted by point id, the diagnostics and the verification data. Datasets are read
when first asked for; the file stays open until ``Run.close()`` (or the end of a
``with`` block), after which frames, point sets and datasets raise ``ClosedRunError``.
"""
import os

import h5py
import numpy as np

from . import namelist

#: Set names in the order the Fortran writer lists them; other names follow, sorted.
SET_ORDER = ("solid", "fluid")
#: Stress columns of the (n, 6) ``stress`` dataset (Voigt order, tension positive).
STRESS_COMPONENTS = ("xx", "yy", "zz", "yz", "xz", "xy")
#: Colourings of solid points in plots: von Mises, speed or one stress component.
SOLID_COLORS = ("von_mises", "speed") + tuple("stress_" + c for c in STRESS_COMPONENTS)


def _text(value):
    """An attribute or string dataset as str (h5py gives fixed-length strings as bytes)."""
    if isinstance(value, bytes):
        return value.decode(errors="replace").rstrip("\0")
    if isinstance(value, np.ndarray) and value.shape == ():
        return _text(value[()])
    return value


def set_names(names):
    """Point-set names in writer order: solid, fluid, then the rest sorted."""
    names = list(names)
    return [n for n in SET_ORDER if n in names] + sorted(n for n in names if n not in SET_ORDER)


def von_mises(stress):
    """Von Mises stress of Voigt rows (n, 6): xx, yy, zz, yz, xz, xy."""
    s = np.asarray(stress, dtype=float).reshape(-1, 6)
    sxx, syy, szz, syz, sxz, sxy = (s[:, k] for k in range(6))
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                   + 3.0 * (syz ** 2 + sxz ** 2 + sxy ** 2))


class Grid:
    """The background grid of the echoed ``&grid`` group (defaults of doc/input.md)."""

    def __init__(self, ndim=2, ncells=(1, 1, 1), origin=(0.0, 0.0, 0.0),
                 length=(1.0, 1.0, 1.0), axisymmetric=False):
        self.ndim = int(ndim)
        self.ncells = np.array(ncells, dtype=int)[:self.ndim]
        self.origin = np.array(origin, dtype=float)[:self.ndim]
        self.length = np.array(length, dtype=float)[:self.ndim]
        #: r-z about the axis x = 0 (``&grid axisymmetric``): x is r, y is z, and the
        #: points' ``vol`` and ``mass`` are per radian (times 2 pi for the whole ring), in
        #: the pore water's set as in the skeleton's; with origin[0] > 0 the grid is a
        #: hollow cylinder from r = origin[0].
        self.axisymmetric = bool(axisymmetric)

    @property
    def spacing(self):
        """Cell size per axis (m)."""
        return self.length / self.ncells

    @classmethod
    def from_input(cls, text):
        """The grid of a namelist text; variables not given keep their defaults."""
        g = namelist.group(text, "grid")
        defaults = {"ndim": [2], "ncells": [1, 1, 1], "origin": [0.0, 0.0, 0.0],
                    "length": [1.0, 1.0, 1.0]}
        vals = {}
        for key, dflt in defaults.items():
            got = list(g.get(key, []))
            vals[key] = [got[k] if k < len(got) and got[k] is not None else dflt[k]
                         for k in range(len(dflt))]
        axi = list(g.get("axisymmetric", [False]))
        return cls(vals["ndim"][0], vals["ncells"], vals["origin"], vals["length"],
                   bool(axi[0]) if axi else False)

    def __repr__(self):
        extra = ", axisymmetric=True" if self.axisymmetric else ""
        return (f"Grid(ndim={self.ndim}, ncells={self.ncells.tolist()}, "
                f"origin={self.origin.tolist()}, length={self.length.tolist()}{extra})")


class ClosedRunError(ValueError):
    """A frame, point set or dataset of a Run asked for after the file was closed."""


class PointSet:
    """One point set of one frame. ``ps["x"]`` is a dataset as a numpy array, its rows
    in increasing id order (``ps.id`` is sorted), whatever order the ranks wrote."""

    def __init__(self, group, name, frame):
        self._group = group
        self.name = name
        self.frame = frame
        self._order = None
        self._cache = {}

    @property
    def _g(self):
        self.frame._check_open()
        return self._group

    @property
    def order(self):
        """Permutation from file order to id order."""
        if self._order is None:
            self._order = np.argsort(self._g["id"][...], kind="stable")
        return self._order

    def __len__(self):
        return int(self._g["id"].shape[0])

    def keys(self):
        """The datasets stored for this set (``stress`` and others may be absent)."""
        return sorted(self._g.keys())

    def __contains__(self, name):
        return name in self._g

    def __getitem__(self, name):
        self.frame._check_open()
        if name not in self._cache:
            if name not in self._g:
                raise KeyError(f"/frames/{self.frame.name}/{self.name} has no dataset "
                               f"{name!r} (it has {', '.join(self.keys())})")
            self._cache[name] = self._g[name][...][self.order]
        return self._cache[name]

    def get(self, name, default=None):
        """The dataset, or default when the set does not store it."""
        return self[name] if name in self._g else default

    @property
    def id(self):
        return self["id"]

    def stress_component(self, comp):
        """One stress column by name (``xx`` ... ``xy``, or ``stress_xx``), or the von
        Mises stress for ``von_mises``."""
        comp = comp.replace("stress_", "")
        if comp == "von_mises":
            return von_mises(self["stress"])
        return self["stress"][:, STRESS_COMPONENTS.index(comp)]

    def __repr__(self):
        return f"PointSet({self.name!r}, frame {self.frame.index}, n={len(self)})"


class Frame:
    """One output frame: ``time``, ``step`` and its point sets by name."""

    def __init__(self, group, index, name, run=None):
        self._group = group
        self._run = run
        self.index = index
        self.name = name
        self.time = float(group.attrs["time"])
        self.step = int(group.attrs["step"])
        self._sets = {}

    def _check_open(self):
        if self._run is not None:
            self._run._check_open()

    @property
    def _g(self):
        self._check_open()
        return self._group

    @property
    def set_names(self):
        return set_names(self._g.keys())

    def __contains__(self, name):
        return name in self._g

    def __getitem__(self, name):
        self._check_open()
        if name not in self._sets:
            if name not in self._g:
                raise KeyError(f"frame {self.name} has no point set {name!r}")
            self._sets[name] = PointSet(self._g[name], name, self)
        return self._sets[name]

    def get(self, name):
        """The point set, or None when the frame has no such set."""
        return self[name] if name in self._g else None

    def __repr__(self):
        return f"Frame({self.index}, t={self.time:.6g}, step={self.step}, sets={self.set_names})"


class Run:
    """One dpmpm output file opened for reading."""

    def __init__(self, path):
        self.path = os.fspath(path)
        self.file = h5py.File(self.path, "r")
        f = self.file
        self.attrs = {k: _text(v) for k, v in f.attrs.items()}
        self.ndim = int(self.attrs.get("ndim", 0))
        self.nranks = int(self.attrs.get("nranks", 0))
        self.version = self.attrs.get("dpmpm_version")
        self.input = _text(f["input"][()]) if "input" in f else ""
        names = sorted(f["frames"]) if "frames" in f else []
        self.frames = [Frame(f["frames"][n], k, n, self) for k, n in enumerate(names)]
        self._grid = None

    # ---- context manager
    def _check_open(self):
        """Raise ClosedRunError once the file is closed: a closed file's groups look
        empty to h5py, which would read as missing sets and empty profiles."""
        if self.file is None:
            raise ClosedRunError(f"{self.path} is closed: read its frames, points and "
                                 "diagnostics inside the `with open_run(...)` block "
                                 "(or before run.close())")

    @property
    def closed(self):
        return self.file is None

    def close(self):
        if self.file:
            self.file.close()
            self.file = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ---- frames
    @property
    def times(self):
        return np.array([fr.time for fr in self.frames])

    @property
    def steps(self):
        return np.array([fr.step for fr in self.frames], dtype=np.int64)

    def __len__(self):
        return len(self.frames)

    def __getitem__(self, k):
        return self.frames[k]

    def frame_at(self, time):
        """The frame whose time is nearest to time."""
        if not self.frames:
            raise IndexError(f"{self.path} has no frames")
        return self.frames[int(np.argmin(np.abs(self.times - time)))]

    @property
    def set_names(self):
        """Every point-set name that occurs in some frame, writer order."""
        names = set()
        for fr in self.frames:
            names.update(fr.set_names)
        return set_names(names)

    # ---- input, grid
    @property
    def grid(self):
        """The background grid from the echoed ``&grid`` group."""
        if self._grid is None:
            self._grid = Grid.from_input(self.input)
            if self.ndim and self._grid.ndim != self.ndim:
                raise ValueError(f"{self.path}: &grid ndim = {self._grid.ndim} but the "
                                 f"file says ndim = {self.ndim}")
        return self._grid

    def input_groups(self, name):
        """Every echoed namelist group called name, as dicts of lists."""
        return namelist.groups(self.input, name)

    @property
    def scene(self):
        """The echoed input as a ``dpmpm.Scene`` (to run it again, changed)."""
        from .scene import Scene
        return Scene.from_text(self.input, self.path)

    # ---- diagnostics, verification
    @property
    def diagnostics(self):
        """``/diagnostics`` as a dict of 1D numpy arrays (empty when absent)."""
        self._check_open()
        d = self.file.get("diagnostics")
        return {k: d[k][...] for k in d} if d is not None else {}

    @property
    def verification(self):
        """``/verification`` datasets as a dict of numpy arrays (empty when absent)."""
        self._check_open()
        v = self.file.get("verification")
        return {k: v[k][...] for k in v} if v is not None else {}

    @property
    def verification_attrs(self):
        """``/verification`` scalar attributes as a dict of floats (empty when absent)."""
        self._check_open()
        v = self.file.get("verification")
        return {k: _text(a) if isinstance(a, bytes) else float(np.asarray(a).ravel()[0])
                for k, a in v.attrs.items()} if v is not None else {}

    def __repr__(self):
        if self.closed:
            return f"Run({self.path!r}, closed)"
        return (f"Run({self.path!r}, ndim={self.ndim}, nranks={self.nranks}, "
                f"frames={len(self.frames)}, sets={self.set_names})")


def open_run(path):
    """Open a dpmpm output file (``.h5``) for reading; use as ``with open_run(p) as run:``."""
    return Run(path)
