"""Figures of a run: the point sets at a few frames, each set on its own (the fluid
coloured by pore pressure, the solid by a stress component or the von Mises stress),
and the energies over time. Uses matplotlib's Agg backend (no display needed)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .run import SOLID_COLORS  # noqa: E402,F401


#: The legend of /diagnostics/external_work, which is net of dissipation (doc/output.md).
EXTERNAL_WORK_LABEL = "work of loads and gravity\nnet of drag and plastic dissipation"


def pick_frames(run, count=3):
    """Indices of first, middle and last frame (fewer when the run has fewer)."""
    n = len(run.frames)
    if n == 0:
        return []
    return sorted({0, n // 2, n - 1}) if count == 3 else \
        sorted({int(round(k)) for k in np.linspace(0, n - 1, count)})


def set_colour(ps, color):
    """(values, label) to colour the points of a set: pore pressure for a fluid set that
    has it, else the chosen solid colouring (speed when the set has no stress)."""
    if ps.name == "fluid" and "pore_pressure" in ps:
        return ps["pore_pressure"], "pore pressure p (Pa, compression > 0)"
    if color == "speed" or "stress" not in ps:
        return np.linalg.norm(ps["v"], axis=1), "|v| (m/s)"
    if color == "von_mises":
        return ps.stress_component("von_mises"), "von Mises stress (Pa)"
    return ps.stress_component(color), f"{color} (Pa, tension > 0)"


def _draw_set_2d(fig, ax, run, ps, color):
    c, label = set_colour(ps, color)
    x = ps["x"]
    sc = ax.scatter(x[:, 0], x[:, 1], c=c, s=6, cmap="viridis")
    fig.colorbar(sc, ax=ax, label=label, shrink=0.8)
    ax.set_aspect("equal")
    # A narrow body (a column): x ticks at the grid's ends only, so they stay readable.
    if np.ptp(x[:, 0]) < np.ptp(x[:, 1]) / 3.0:
        lo = run.grid.origin[0]
        ax.set_xticks([lo, lo + run.grid.length[0]])
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)" if run.ndim == 2 else "y (m), projected along z")


def _draw_set_1d(ax, ps, color):
    x = ps["x"][:, 0]
    order = np.argsort(x)
    ax.plot(x[order], ps["v"][order, 0], ".-", label="v (m/s)")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("v (m/s)")
    if ps.name == "fluid" and "pore_pressure" in ps:
        y, label = ps["pore_pressure"], "pore pressure p (Pa)"
    elif "stress" in ps:
        y, label = ps["stress"][:, 0], "stress xx (Pa)"
    else:
        return
    ax2 = ax.twinx()
    ax2.plot(x[order], y[order], ".-", color="tab:red")
    ax2.set_ylabel(label, color="tab:red")


def plot_energies(ax, run):
    """Kinetic and strain energy and the net work from /diagnostics over time.

    ``external_work`` is the work of the loads and gravity minus what the drag and plastic
    flow dissipated (doc/output.md), so on a consolidating layer it lies on kinetic +
    strain: the label says so."""
    d = run.diagnostics
    ax.set_title("energies")
    if d and d["time"].shape[0] > 0:
        t = d["time"]
        ke, se, w = d["kinetic_energy"], d["strain_energy"], d["external_work"]
        ax.plot(t, ke, label="kinetic")
        ax.plot(t, se, label="strain")
        ax.plot(t, w, label=EXTERNAL_WORK_LABEL)
        ax.plot(t, ke + se, "k--", label="kinetic + strain")
        ax.legend(fontsize="small")
    else:
        ax.text(0.5, 0.5, "no diagnostics", ha="center", transform=ax.transAxes)
    ax.set_xlabel("t (s)")
    units = {1: "J per m² of cross-section", 2: "J per m of thickness"}.get(run.ndim, "J")
    ax.set_ylabel(f"energy ({units})")


def plot_run(run, out, color="von_mises", frames=None, dpi=110):
    """One PNG: a row per point set with a panel per frame (first, middle, last unless
    frames lists indices), and the energies over time. Returns out."""
    if color not in SOLID_COLORS:
        raise ValueError(f"colour {color!r}: one of {', '.join(SOLID_COLORS)}")
    picks = pick_frames(run) if frames is None else list(frames)
    sets = run.set_names or ["solid"]
    ncol = max(1, len(picks)) + 1
    fig, axes = plt.subplots(len(sets), ncol, figsize=(4.2 * ncol, 3.8 * len(sets)),
                             squeeze=False)
    for row, sname in enumerate(sets):
        for col, k in enumerate(picks):
            ax = axes[row][col]
            fr = run.frames[k]
            ax.set_title(f"{sname}, frame {fr.name}, t = {fr.time:.4g} s")
            ps = fr.get(sname)
            if ps is None or len(ps) == 0:
                ax.text(0.5, 0.5, "no points", ha="center", transform=ax.transAxes)
                continue
            if run.ndim == 1:
                _draw_set_1d(ax, ps, color)
            else:
                _draw_set_2d(fig, ax, run, ps, color)
        if not picks:
            axes[row][0].text(0.5, 0.5, "no frames", ha="center",
                              transform=axes[row][0].transAxes)
    plot_energies(axes[0][-1], run)
    for row in range(1, len(sets)):
        axes[row][-1].axis("off")
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out


def plot_profiles(profiles, out, xlabel="value", top=None, dpi=110):
    """Bin averages (lines) and points (dots) of profiles against position, or against
    depth below top when given. Returns out."""
    fig, ax = plt.subplots(figsize=(5.5, 5.0))
    for pr in profiles:
        pos = pr.centres if top is None else top - pr.centres
        line, = ax.plot(pr.mean, pos, "-o", ms=3, label=f"{pr.quantity}, t = {pr.time:.4g} s")
        ppos = pr.x if top is None else top - pr.x
        ax.plot(pr.values, ppos, ".", ms=2, color=line.get_color(), alpha=0.4)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("depth (m)" if top is not None else f"position along axis {profiles[0].axis} (m)")
    if top is not None:
        ax.invert_yaxis()
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out
