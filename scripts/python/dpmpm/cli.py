"""Command line: python -m dpmpm {info,plot,profile,compare,xdmf,terzaghi,element,motion} FILE...

Exit status: 0 success (compare: the runs agree within --rtol; also when the reader of
the output stops early, as `| head` does), 1 the runs differ (compare), 2 bad arguments
or a file that cannot be read.
"""
import argparse
import os
import sys

import numpy as np

from . import __version__
from .compare import compare_runs
from .consolidation import terzaghi_setup
from .profile import profile
from .run import SOLID_COLORS, open_run
from .xdmf import write_xdmf


def cmd_info(args):
    for path in args.files:
        with open_run(path) as run:
            print(f"{path}: dpmpm {run.version}, commit {run.attrs.get('git_commit')}, "
                  f"{run.ndim}D, {run.nranks} ranks")
            print(f"  grid: {run.grid.ncells.tolist()} cells, origin "
                  f"{run.grid.origin.tolist()}, length {run.grid.length.tolist()}")
            t = run.times
            if len(t):
                print(f"  {len(run.frames)} frames, t = {t[0]:.6g} ... {t[-1]:.6g} s, "
                      f"steps {run.steps[0]} ... {run.steps[-1]}")
                last = run.frames[-1]
                for s in run.set_names:
                    ps = last.get(s)
                    if ps is not None:
                        print(f"  {s}: {len(ps)} points; {', '.join(ps.keys())}")
            else:
                print("  no frames")
            d = run.diagnostics
            if d:
                n = len(d["time"])
                print(f"  diagnostics: {n} records"
                      + (f", last at t = {d['time'][-1]:.6g} s, wall {d['wall_time'][-1]:.3g} s"
                         if n else ""))
            v, va = run.verification, run.verification_attrs
            if v or va:
                print("  verification: " + ", ".join(
                    [f"{k}[{len(a)}] (last {a[-1]:.3e})" if len(a) else f"{k}[0]"
                     for k, a in v.items()]
                    + [f"{k} = {x:.6g}" if isinstance(x, float) else f"{k} = {x}"
                       for k, x in va.items()]))
    return 0


def cmd_plot(args):
    from .plot import plot_run
    with open_run(args.file) as run:
        out = args.output or os.path.splitext(args.file)[0] + ".png"
        plot_run(run, out, color=args.color)
    print(out)
    return 0


def cmd_profile(args):
    with open_run(args.file) as run:
        if args.time is not None:
            frames = [run.frame_at(t) for t in args.time]
        else:
            frames = [run.frames[k] for k in (args.frame or [-1])]
        where = {}
        for spec in args.where or []:
            ax, lo, hi = spec.split(":")
            where[int(ax)] = (float(lo), float(hi))
        profs = [profile(run, args.quantity, fr, axis=args.axis, width=args.width,
                         where=where or None,
                         weight=None if args.unweighted else "volume") for fr in frames]
        for pr in profs:
            print(f"# {pr.quantity} at t = {pr.time:.9g} s, axis {pr.axis}: "
                  f"centre, mean, count")
            for c, m, n in zip(pr.centres, pr.mean, pr.count):
                print(f"{c:.9g} {m:.9g} {n}")
        if args.output:
            from .plot import plot_profiles
            top = None
            if args.depth_from is not None:
                top = args.depth_from
            plot_profiles(profs, args.output, xlabel=args.quantity, top=top)
            print(args.output)
    return 0


def cmd_compare(args):
    with open_run(args.a) as a, open_run(args.b) as b:
        c = compare_runs(a, b)
    for line in c.table():
        print(line)
    ok = c.agrees(args.rtol)
    print(f"{'agree' if ok else 'differ'} (rtol {args.rtol:g}, largest relative difference "
          f"{c.max_rel:.3e})")
    return 0 if ok else 1


def cmd_xdmf(args):
    if args.output and len(args.files) > 1:
        raise SystemExit("dpmpm xdmf: -o needs a single FILE")
    for path in args.files:
        print(write_xdmf(path, args.output))
    return 0


def cmd_terzaghi(args):
    from .consolidation import plot_terzaghi
    with open_run(args.file) as run:
        setup = terzaghi_setup(run)
        out = args.output or os.path.splitext(args.file)[0] + ".png"
        out, results = plot_terzaghi(run, out, times=args.time, setup=setup)
        print(f"# Terzaghi: H = {setup.h:g} m, q = {setup.q:g} Pa, p0 = {setup.p0:.6g} Pa, "
              f"c_v = {setup.c_v:.6g} m^2/s, load ramp {setup.ramp:g} s")
        print("# t (s), T_v, max |p - p_ref| / p0, max |sigma' - sigma'_ref| / p0 "
              "(cell averages)")
        for r in results:
            print(f"{r.time:.6g} {r.time_factor:.4f} {r.err_p:.3e} {r.err_sigma:.3e}")
        worst = max((max(r.err_p, r.err_sigma) for r in results), default=np.nan)
    print(out)
    if args.tolerance is not None and not worst <= args.tolerance:
        print(f"error {worst:.3e} p0 above the tolerance {args.tolerance:g}")
        return 1
    return 0


def cmd_element(args):
    from .element import plot_element, read_element
    test = read_element(args.file)
    out = args.output or os.path.splitext(args.file)[0] + ".png"
    plot_element(test, out)
    last = -1
    print(f"# {test.model}: {test.path}, {test.control} control, {test.steps_done} of "
          f"{test.steps} steps ({test.status}); at the end p' = {test['p'][last]:.6g} Pa, "
          f"q = {test['q'][last]:.6g} Pa, eps_a = {test['axial_strain'][last]:.6g}, "
          f"eps_v = {test['volumetric_strain'][last]:.6g}")
    if not test.complete:
        print(f"# stopped: {test.message}")
    print(out)
    return 0


def probe_acceleration(path, k, axis):
    """(time step, acceleration, title) of probe k of a run's file along axis (x, y, z).
    Records at uneven times (a run whose step follows the CFL condition) are resampled,
    linearly, at their median step."""
    from . import motion, open_run
    with open_run(path) as run:
        pr = motion.probe_history(run, k)
    a = "xyz".index(axis)
    if a >= pr.acceleration.shape[1]:
        raise ValueError(f"{path}: axis {axis} in a {pr.acceleration.shape[1]}D run")
    if len(pr.time) < 2:
        raise ValueError(f"{path}: probe {k} has {len(pr.time)} record(s); a motion needs two")
    acc = pr.acceleration[:, a]
    at = ", ".join(f"{x:g}" for x in pr.position)
    title = f"probe {k} ({at}) along {axis}"
    try:
        dt = motion.time_step(pr.time)
    except ValueError:
        dt = float(np.median(np.diff(pr.time)))
        t = pr.time[0] + dt * np.arange(int(np.floor((pr.time[-1] - pr.time[0]) / dt + 1e-9)) + 1)
        acc = np.interp(t, pr.time, acc)
        title += f", resampled at {dt:.6g} s"
    return dt, acc, title


def cmd_motion(args):
    from . import motion
    if args.file.endswith(".h5"):
        dt, acc, name = probe_acceleration(args.file, args.probe, args.axis)
        acc = args.scale * acc
        print(f"# {name}")
    else:
        rec = motion.read_record(args.file, units=args.units, scale=args.scale)
        if rec.quantity != "acceleration":
            raise ValueError(f"{args.file}: holds {rec.quantity}; give an acceleration record")
        dt, acc, name = rec.dt, rec.values, rec.name
    s = motion.summarize(dt, acc, baseline=not args.no_baseline)
    periods = motion.default_periods(args.periods, args.t_min, args.t_max)
    sp = motion.response_spectrum(dt, s.acceleration, periods, args.damping)
    out = args.output or os.path.splitext(args.file)[0] + ".png"
    motion.plot_motion(s, sp, out, title=name)
    k = int(np.argmax(sp.psa))
    print(f"# {args.file}: {len(s.time)} samples, dt = {dt:.6g} s, duration "
          f"{s.time[-1]:.6g} s, baseline {'not corrected' if args.no_baseline else 'corrected'}")
    print(f"PGA = {s.pga / motion.G:.6g} g ({s.pga:.6g} m/s^2)")
    print(f"PGV = {s.pgv:.6g} m/s")
    print(f"PGD = {s.pgd:.6g} m")
    print(f"Arias intensity = {s.arias:.6g} m/s")
    print(f"D5-95 = {s.d5_95:.6g} s")
    print(f"peak PSA = {sp.psa[k] / motion.G:.6g} g at T = {sp.periods[k]:.4g} s "
          f"({100 * args.damping:g} % damping)")
    if args.spectrum:
        with open(args.spectrum, "w") as fh:
            fh.write(f"# {args.file}, damping {args.damping:g}: period (s), S_d (m), "
                     "PSV (m/s), PSA (m/s^2), SA (m/s^2)\n")
            for row in zip(sp.periods, sp.sd, sp.psv, sp.psa, sp.sa):
                fh.write(" ".join(f"{x:.9g}" for x in row) + "\n")
        print(args.spectrum)
    print(out)
    return 0


def parser():
    ap = argparse.ArgumentParser(prog="dpmpm-py", description="Read, plot and check dpmpm "
                                 "output files (HDF5, doc/output.md).")
    ap.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = ap.add_subparsers(dest="command", required=True)

    p = sub.add_parser("info", help="summary of files: frames, sets, datasets, diagnostics")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.set_defaults(func=cmd_info)

    p = sub.add_parser("plot", help="PNG of the point sets at three frames and the energies")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-o", "--output", help="PNG to write (default: FILE with .png)")
    p.add_argument("--color", choices=SOLID_COLORS, default="von_mises",
                   help="colouring of solid points (fluid points: pore pressure)")
    p.set_defaults(func=cmd_plot)

    p = sub.add_parser("profile", help="cell-averaged profile of a quantity along an axis")
    p.add_argument("file", metavar="FILE")
    p.add_argument("quantity", help="pore_pressure, stress_xx ... stress_xy, von_mises, "
                   "total_stress_xx ..., or SET:DATASET[:COLUMN]")
    p.add_argument("--axis", type=int, help="axis of the profile (default: the last)")
    p.add_argument("--frame", type=int, action="append", help="frame index (repeatable; "
                   "default: the last)")
    p.add_argument("--time", type=float, action="append", help="frame nearest to this time "
                   "(repeatable)")
    p.add_argument("--width", type=float, help="bin width (default: one grid cell)")
    p.add_argument("--where", action="append", metavar="AXIS:LO:HI",
                   help="keep points with LO <= x[AXIS] <= HI (repeatable)")
    p.add_argument("--unweighted", action="store_true", help="plain means, not volume-weighted")
    p.add_argument("-o", "--output", help="also plot into this PNG")
    p.add_argument("--depth-from", type=float, help="plot against depth below this coordinate")
    p.set_defaults(func=cmd_profile)

    p = sub.add_parser("compare", help="two runs matched by id: largest differences")
    p.add_argument("a", metavar="FILE_A")
    p.add_argument("b", metavar="FILE_B")
    p.add_argument("--rtol", type=float, default=1e-10,
                   help="largest relative difference counted as agreement (default 1e-10)")
    p.set_defaults(func=cmd_compare)

    p = sub.add_parser("xdmf", help="rewrite the XDMF sidecar of files from their content")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("-o", "--output", help="sidecar to write (default: FILE with .xmf)")
    p.set_defaults(func=cmd_xdmf)

    p = sub.add_parser("terzaghi", help="a consolidating layer against Terzaghi: PNG and errors")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-o", "--output", help="PNG to write (default: FILE with .png)")
    p.add_argument("--time", type=float, action="append", help="frame nearest to this time "
                   "(repeatable; default: five frames)")
    p.add_argument("--tolerance", type=float, help="exit 1 when an error exceeds this (/ p0)")
    p.set_defaults(func=cmd_terzaghi)

    p = sub.add_parser("element", help="an element test (dpmpm_element): q-p', q-eps_a, "
                       "e-log p' and pore pressure against cycles in a PNG")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-o", "--output", help="PNG to write (default: FILE with .png)")
    p.set_defaults(func=cmd_element)

    p = sub.add_parser("motion", help="a ground-motion record (two columns or PEER .AT2), or "
                       "a probe's acceleration in a run's .h5 (/probes): histories, Fourier "
                       "and response spectra in a PNG; PGA, PGV, PGD, Arias intensity, D5-95")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--probe", type=int, default=0, help="a run's .h5: the probe, 0-based "
                   "(default 0)")
    p.add_argument("--axis", default="x", choices=("x", "y", "z"), help="a run's .h5: the "
                   "component (default x)")
    p.add_argument("-o", "--output", help="PNG to write (default: FILE with .png)")
    p.add_argument("--units", help="units of a two-column file: m/s2 (default), g, cm/s2, "
                   "gal (a PEER file states its own)")
    p.add_argument("--scale", type=float, default=1.0, help="factor on the values")
    p.add_argument("--damping", type=float, default=0.05, help="damping ratio of the "
                   "response spectrum (default 0.05)")
    p.add_argument("--periods", type=int, default=100, help="number of periods, evenly "
                   "spaced in log (default 100)")
    p.add_argument("--t-min", type=float, default=0.01, help="shortest period, s (0.01)")
    p.add_argument("--t-max", type=float, default=10.0, help="longest period, s (10)")
    p.add_argument("--no-baseline", action="store_true", help="no baseline correction")
    p.add_argument("--spectrum", metavar="TXT", help="also write the response spectrum "
                   "as text")
    p.set_defaults(func=cmd_motion)
    return ap


def main(argv=None):
    args = parser().parse_args(argv)
    for path in [getattr(args, k) for k in ("file", "a", "b") if hasattr(args, k)] + \
            list(getattr(args, "files", [])):
        if not os.path.isfile(path):
            print(f"dpmpm: {path}: no such file", file=sys.stderr)
            return 2
    try:
        status = args.func(args)
        sys.stdout.flush()
        return status
    except BrokenPipeError:
        # The reader of our output stopped early (`... | head -3`): not an error. Point
        # stdout at /dev/null so that the interpreter's last flush does not fail again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except (OSError, KeyError, ValueError, IndexError) as e:
        print(f"dpmpm: {type(e).__name__}: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
