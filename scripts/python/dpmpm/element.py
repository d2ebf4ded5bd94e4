"""Element tests (dpmpm_element, doc/output.md "Element tests"): reading the HDF5 file of
one material point driven along a laboratory path, and the calibration plots: q-p',
q-eps_a, e (or eps_v) against log p', and, for undrained and cyclic paths, the excess
pore pressure against the cycles.

    import dpmpm
    t = dpmpm.read_element("out/element_triaxial_drained.h5")
    t.path, t.control, t["q"], t["p"], t.state["plastic_strain"]
"""
import h5py
import numpy as np

#: The series every element file has (one value per record: the initial state, then
#: one per step); excess_pore_pressure (undrained) and void_ratio (with an initial void
#: ratio) only where the file has them.
SERIES = ("time", "cycle", "p", "q", "axial_strain", "volumetric_strain", "shear_strain",
          "shear_stress", "volume_ratio", "residual")


def _text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


class ElementTest:
    """The records of an element test, read whole (they are small): t["q"], t.stress
    (records, 6; Voigt xx yy zz yz xz xy, Pa, tension positive), t.strain, t.state (a
    dict of the model's state values by name), and the test's description (path,
    control, sense, model, cycles, steps, status, message, input text)."""

    def __init__(self, path):
        self.file = path
        with h5py.File(path, "r") as f:
            if "element" not in f:
                raise KeyError(f"{path}: no /element group: not an element-test file")
            g = f["element"]
            a = {k: _text(v) if isinstance(v, (bytes, str)) else v.item()
                 for k, v in g.attrs.items()}
            self.attrs = a
            self.path = a["path"]
            self.control = a["control"]
            self.sense = a["sense"]
            self.model = a["model"]
            self.cycles = int(a["cycles"])
            self.steps = int(a["steps"])
            self.steps_done = int(a["steps_done"])
            self.status = a["status"].strip()
            self.message = a.get("message", "")
            self.series = {k: g[k][...] for k in g if isinstance(g[k], h5py.Dataset)
                           and g[k].ndim == 1}
            self.strain = g["strain"][...]
            self.stress = g["stress"][...]
            self.state = {k: g["state"][k][...] for k in g["state"]}
            self.input = _text(f["input"][()]) if "input" in f else ""

    def __getitem__(self, name):
        try:
            return self.series[name]
        except KeyError:
            raise KeyError(f"{self.file}: no series {name!r}; it has "
                           f"{', '.join(sorted(self.series))}") from None

    def __contains__(self, name):
        return name in self.series

    @property
    def undrained(self):
        return "excess_pore_pressure" in self.series

    @property
    def cyclic(self):
        return self.cycles > 0

    @property
    def complete(self):
        return self.status == "complete"

    def pore_pressure_ratio(self):
        """Excess pore pressure over the initial vertical (simple shear) or mean (triaxial)
        effective stress, r_u, where the path is undrained; None otherwise."""
        if not self.undrained:
            return None
        if self.path.startswith("simple_shear"):
            ref = -self.stress[0, 2]
        else:
            ref = self["p"][0]
        return self["excess_pore_pressure"] / ref

    def __repr__(self):
        return (f"ElementTest({self.file!r}, path={self.path}, control={self.control}, "
                f"model={self.model}, records={len(self['time'])}, status={self.status})")


def read_element(path):
    """The element test of an HDF5 file written by dpmpm_element."""
    return ElementTest(path)


def plot_element(test, out, dpi=110):
    """A PNG of the element test: q against p' (the stress path), q against eps_a (tau
    against gamma in simple shear), e (or eps_v) against log p', and for an undrained
    path the excess pore pressure ratio against the cycles (against eps_a or gamma when
    monotonic). Returns out."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    shear = test.path.startswith("simple_shear")
    p = test["p"] / 1e3
    panels = 4 if test.undrained else 3
    fig, axs = plt.subplots(1, panels, figsize=(4.2 * panels, 3.8))
    ax = axs[0]
    if shear:
        sv = -test.stress[:, 2] / 1e3
        ax.plot(sv, test["shear_stress"] / 1e3, lw=1.2)
        ax.set_xlabel("sigma'_v (kPa)")
        ax.set_ylabel("tau (kPa)")
    else:
        ax.plot(p, test["q"] / 1e3, lw=1.2)
        ax.set_xlabel("p' (kPa)")
        ax.set_ylabel("q (kPa)")
    ax.set_title("stress path")
    ax = axs[1]
    if shear:
        ax.plot(test["shear_strain"] * 100, test["shear_stress"] / 1e3, lw=1.2)
        ax.set_xlabel("gamma (%)")
        ax.set_ylabel("tau (kPa)")
    else:
        ax.plot(test["axial_strain"] * 100, test["q"] / 1e3, lw=1.2)
        ax.set_xlabel("eps_a (%)")
        ax.set_ylabel("q (kPa)")
    ax.set_title("stress-strain")
    ax = axs[2]
    # (the first state marked: an undrained path stays on one point here)
    if "void_ratio" in test:
        ax.semilogx(p, test["void_ratio"], lw=1.2)
        ax.semilogx(p[:1], test["void_ratio"][:1], "o", ms=4)
        ax.set_ylabel("e")
    else:
        ax.semilogx(p, test["volumetric_strain"] * 100, lw=1.2)
        ax.semilogx(p[:1], test["volumetric_strain"][:1] * 100, "o", ms=4)
        ax.set_ylabel("eps_v (%, compression > 0)")
        ax.invert_yaxis()
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xlabel("p' (kPa, log)")
    ax.set_title("compression")
    if test.undrained:
        ax = axs[3]
        ru = test.pore_pressure_ratio()
        if test.cyclic:
            ax.plot(test["cycle"], ru, lw=1.2)
            ax.set_xlabel("cycles")
        elif shear:
            ax.plot(test["shear_strain"] * 100, ru, lw=1.2)
            ax.set_xlabel("gamma (%)")
        else:
            ax.plot(test["axial_strain"] * 100, ru, lw=1.2)
            ax.set_xlabel("eps_a (%)")
        ax.set_ylabel("excess pore pressure ratio r_u")
        ax.set_title("pore pressure")
    for ax in axs:
        ax.grid(True, alpha=0.3)
    title = f"{test.model}: {test.path}, {test.control} control"
    if test.cyclic:
        title += f", {test.cycles} cycles"
    if not test.complete:
        title += f" (stopped after {test.steps_done} of {test.steps} steps)"
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out
