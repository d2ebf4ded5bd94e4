"""Building and running dpmpm scenes, and reading, plotting and checking their output
files (doc/python.md).

    import dpmpm
    scene = dpmpm.Scene.read("inputs/consolidation_2d.nml")
    scene["run"]["t_end"] = 0.1
    result = dpmpm.simulate(scene, ranks=2)               # a progress bar; out/...h5
    with dpmpm.open_run("out/consolidation_2d.h5") as run:
        fr = run.frames[-1]
        p = fr["fluid"]["pore_pressure"]          # sorted by point id
        prof = dpmpm.profile(run, "pore_pressure", frame=-1)
"""
from . import motion
from .compare import Comparison, compare_runs
from .consolidation import compare_terzaghi, terzaghi_setup
from .element import ElementTest, read_element
from .profile import Profile, bin_edges, cell_average, profile
from .errors import InputError, MonitorStop, RunError, StoppedEarly
from .launch import find_binary, find_mpirun
from .scene import Scene, read_scene
from .simulate import Result, simulate, study
from .run import (STRESS_COMPONENTS, ClosedRunError, Frame, Grid, PointSet, Run, open_run,
                  von_mises)
from .xdmf import write_xdmf, xdmf_text


# The plotting functions import matplotlib when first called, not with the package.
def plot_run(run, out, color="von_mises", frames=None, dpi=110):
    """A PNG of the point sets at a few frames and the energies (dpmpm.plot.plot_run)."""
    from . import plot
    return plot.plot_run(run, out, color=color, frames=frames, dpi=dpi)


def plot_profiles(profiles, out, xlabel="value", top=None, dpi=110):
    """Profiles against position or depth in a PNG (dpmpm.plot.plot_profiles)."""
    from . import plot
    return plot.plot_profiles(profiles, out, xlabel=xlabel, top=top, dpi=dpi)


def plot_terzaghi(run, out, times=None, setup=None, dpi=120):
    """p and sigma' against depth beside Terzaghi (dpmpm.consolidation.plot_terzaghi)."""
    from . import consolidation
    return consolidation.plot_terzaghi(run, out, times=times, setup=setup, dpi=dpi)


# The labelled arrays import xarray (and pandas) when first called, not with the package.
def points_dataset(run, name, frames=None):
    """A point set over the frames as an xarray.Dataset (dpmpm.labelled.points_dataset)."""
    from . import labelled
    return labelled.points_dataset(run, name, frames=frames)


def diagnostics_dataset(run):
    """/diagnostics as an xarray.Dataset along time (dpmpm.labelled.diagnostics_dataset)."""
    from . import labelled
    return labelled.diagnostics_dataset(run)


def verification_dataset(run):
    """/verification as an xarray.Dataset (dpmpm.labelled.verification_dataset)."""
    from . import labelled
    return labelled.verification_dataset(run)


def profile_dataarray(prof):
    """A Profile as an xarray.DataArray (dpmpm.labelled.profile_dataarray)."""
    from . import labelled
    return labelled.profile_dataarray(prof)


def plot_element(test, out, dpi=110):
    """The calibration plots of an element test in a PNG (dpmpm.element.plot_element)."""
    from . import element
    return element.plot_element(test, out, dpi=dpi)


__version__ = "0.1.0"

__all__ = ["Scene", "read_scene", "simulate", "study", "Result", "RunError", "InputError",
           "StoppedEarly", "MonitorStop", "find_binary", "find_mpirun", "open_run", "Run",
           "ClosedRunError", "Frame", "PointSet", "Grid", "STRESS_COMPONENTS", "von_mises",
           "profile", "Profile", "bin_edges", "cell_average", "plot_run", "plot_profiles",
           "compare_runs", "Comparison", "write_xdmf", "xdmf_text", "terzaghi_setup",
           "compare_terzaghi", "plot_terzaghi", "read_element", "ElementTest", "plot_element",
           "points_dataset", "diagnostics_dataset", "verification_dataset", "profile_dataarray",
           "motion"]
