"""A run of a consolidating saturated layer against Terzaghi's solution.

``terzaghi_setup(run)`` reads the layer from the echoed input: the first saturated
``&region`` (a box), its soil ``material`` (E, nu -> constrained modulus E_c,
conductivity k) and ``fluid_material`` (bulk modulus K_f), its porosity, and the
``&load`` on a face of the grid (q = the compressive normal traction, ramp_time). The
loaded face is the drained top; depth is measured from it along its axis.
``compare_terzaghi(run, frame)`` gives cell-averaged profiles of p and sigma' (the
normal effective stress along the layer axis) with the reference averaged over the
same points with the same weights, and their largest deviations.

A linear load ramp of length t_r delays the response by about t_r / 2 (inputs/t1.nml):
the reference is evaluated at t - t_r / 2.
"""
import numpy as np

from . import terzaghi
from .profile import bin_edges, cell_average


class TerzaghiSetup:
    """Parameters of the layer: axis, top (loaded face coordinate), sign (+1 when depth
    grows along +axis), h, q, ramp, e_c, n_f, k_f, k, c_v, p0."""

    def depth(self, x):
        return self.sign * (np.asarray(x) - self.top)

    def time_factor(self, t):
        return self.c_v * max(t - self.ramp / 2.0, 0.0) / self.h ** 2

    def p_ref(self, depth, t):
        te = t - self.ramp / 2.0
        if te <= 0.0:
            return np.zeros_like(np.asarray(depth, dtype=float))
        return terzaghi.pore_pressure(np.clip(depth, 0.0, self.h), te, self.h, self.c_v,
                                      self.p0)


def _one(d, key, default=None):
    v = d.get(key)
    return v[0] if v else default


def _vec(d, key, n):
    v = list(d.get(key) or [])
    return [float(v[k]) if k < len(v) and v[k] is not None else 0.0 for k in range(n)]


def terzaghi_setup(run):
    """The Terzaghi parameters of a run's scene (see the module doc); ValueError when
    the scene is not a loaded saturated layer."""
    ndim = run.ndim
    regions = [r for r in run.input_groups("region") if _one(r, "phase") == "saturated"]
    if not regions:
        raise ValueError("the scene has no saturated region")
    reg = regions[0]
    mats = {_one(m, "id"): m for m in run.input_groups("material")}
    soil, fluid = mats.get(_one(reg, "material")), mats.get(_one(reg, "fluid_material"))
    if soil is None or fluid is None:
        raise ValueError("the saturated region's materials are not in the input")
    loads = run.input_groups("load")
    if len(loads) != 1:
        raise ValueError(f"expected one &load, found {len(loads)}")
    load = loads[0]
    face = _one(load, "face")
    axis, side = "xyz".index(face[0]), face[1]
    if any(_vec(g, "gravity", 3) != [0.0, 0.0, 0.0] for g in run.input_groups("run")):
        raise ValueError("gravity is on: the layer has more than the excess pore pressure")
    s = TerzaghiSetup()
    lo, hi = _vec(reg, "lo", ndim), _vec(reg, "hi", ndim)
    s.axis = axis
    s.sign = -1.0 if side == "+" else 1.0
    s.top = hi[axis] if side == "+" else lo[axis]
    s.h = hi[axis] - lo[axis]
    s.q = s.sign * _vec(load, "traction", ndim)[axis]
    s.ramp = float(_one(load, "ramp_time", 0.0))
    e, nu = float(_one(soil, "youngs_modulus")), float(_one(soil, "poisson_ratio", 0.0))
    s.e_c = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
    s.k = float(_one(soil, "conductivity"))
    s.n_f = float(_one(reg, "porosity"))
    s.k_f = float(_one(fluid, "bulk_modulus"))
    s.c_v = terzaghi.consolidation_coefficient(s.k, s.e_c, s.n_f, s.k_f)
    s.p0 = terzaghi.initial_pressure(s.q, s.e_c, s.n_f, s.k_f)
    return s


class TerzaghiProfile:
    """One frame against Terzaghi: ``depth`` (bin centres), ``p``, ``p_ref``,
    ``sigma`` (compression positive: -sigma'_axis), ``sigma_ref`` (q - p_ref), all cell
    averages; ``err_p``, ``err_sigma``: largest |difference| over the bins / p0;
    ``time``, ``time_factor``."""


def compare_terzaghi(run, frame, setup=None, width=None):
    """Cell-averaged p and sigma' of a frame (index or Frame) against Terzaghi."""
    s = setup or terzaghi_setup(run)
    fr = run.frames[frame] if isinstance(frame, (int, np.integer)) else frame
    lo, hi = min(s.top, s.top + s.sign * s.h), max(s.top, s.top + s.sign * s.h)
    edges = bin_edges(run.grid, s.axis, width, lo, hi)
    comp = s.axis  # normal component along the layer axis (xx, yy or zz)
    out = TerzaghiProfile()
    out.time, out.time_factor = fr.time, s.time_factor(fr.time)
    out.depth = np.sort(s.depth(0.5 * (edges[:-1] + edges[1:])))
    order = np.argsort(s.depth(0.5 * (edges[:-1] + edges[1:])))

    fl, so = fr["fluid"], fr["solid"]
    xf, xs = fl["x"][:, s.axis], so["x"][:, s.axis]
    pref_f = s.p_ref(s.depth(xf), fr.time)
    pref_s = s.p_ref(s.depth(xs), fr.time)
    out.p = cell_average(xf, fl["pore_pressure"], edges, fl["volume"])[0][order]
    out.p_ref = cell_average(xf, pref_f, edges, fl["volume"])[0][order]
    out.sigma = cell_average(xs, -so["stress"][:, comp], edges, so["volume"])[0][order]
    sig_ref = s.q - pref_s if fr.time >= s.ramp else (fr.time / s.ramp) * s.q - pref_s
    out.sigma_ref = cell_average(xs, sig_ref, edges, so["volume"])[0][order]
    out.err_p = float(np.nanmax(np.abs(out.p - out.p_ref))) / s.p0
    out.err_sigma = float(np.nanmax(np.abs(out.sigma - out.sigma_ref))) / s.p0
    return out


def plot_terzaghi(run, out, times=None, setup=None, dpi=120):
    """Pore pressure and effective stress against depth at a few frame times (default:
    five frames spread over the run (log scale), the first after the ramp), cell averages as
    markers beside the Terzaghi series as lines. Returns (out, [TerzaghiProfile])."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = setup or terzaghi_setup(run)
    if times is None:
        later = [fr for fr in run.frames if fr.time > 2.0 * s.ramp]
        pick = sorted({int(round(k)) for k in np.geomspace(1, len(later), 5)}) if later else []
        frames = [later[k - 1] for k in pick]
    else:
        frames = [run.frame_at(t) for t in times]
    results = [compare_terzaghi(run, fr, s) for fr in frames]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10.5, 7.0), sharey=True)
    zz = np.linspace(0.0, s.h, 201)
    for k, r in enumerate(results):
        col = f"C{k}"
        lab = f"t = {r.time:.3g} s, $T_v$ = {r.time_factor:.3g}"
        pr = s.p_ref(zz, r.time)
        ax1.plot(pr / s.p0, zz, "-", color=col, lw=1.2)
        ax1.plot(r.p / s.p0, r.depth, "o", color=col, ms=4, mfc="none",
                 label=f"{lab}: max err {r.err_p:.1e} $p_0$")
        ax2.plot((s.q - pr) / s.q, zz, "-", color=col, lw=1.2)
        ax2.plot(r.sigma / s.q, r.depth, "o", color=col, ms=4, mfc="none",
                 label=f"{lab}: max err {r.err_sigma:.1e} $p_0$")
    ax1.set_xlabel("excess pore pressure  p / $p_0$")
    ax2.set_xlabel("vertical effective stress  $-\\sigma'$ / q  (compression > 0)")
    ax1.set_ylabel("depth below the drained, loaded top (m)")
    ax1.invert_yaxis()
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.set_xlim(-0.02, 1.05)
    for ax, what in ((ax1, "p"), (ax2, "$\\sigma'$")):
        ax.legend(fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.12),
                  title=f"largest |{what} - Terzaghi| over the cells", title_fontsize="small")
    fig.suptitle(f"{run.grid.ndim}D consolidation: dpmpm cell averages (circles) against "
                 f"Terzaghi (lines)\nH = {s.h:g} m, q = {s.q:g} Pa, $p_0$ = {s.p0:.1f} Pa, "
                 f"$c_v$ = {s.c_v:.4g} m²/s", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out, results
