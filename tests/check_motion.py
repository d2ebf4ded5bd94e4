"""Checks of dpmpm.motion against closed forms, and of its readers and command on small
files written here (doc/verification.md, "Ground motions: spectra, intensity, records").

    python3 tests/check_motion.py [GROUP ...] [--workdir DIR]

GROUP: spectra, intensity, files, command (default: all). Each check prints its measured
error beside the bound it must stay under; a failed check raises AssertionError (exit 1).
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts", "python"))

from dpmpm import motion  # noqa: E402

G = motion.G


def report(name, err, bound):
    print(f"  {name}: {err:.3e} (bound {bound:.0e})")
    assert err <= bound, f"{name}: error {err:.3e} above {bound:.0e}"


# ----------------------------------------------------------------------- spectra
def ramp_response(t, rate, w, z):
    """Exact relative displacement of u'' + 2 z w u' + w^2 u = -rate t from rest."""
    wd = w * math.sqrt(1.0 - z * z)
    c1 = -2.0 * z * rate / w ** 3
    c2 = rate * (1.0 - 2.0 * z * z) / (w * w * wd)
    up = -rate / (w * w) * (t - 2.0 * z / w)
    return up + np.exp(-z * w * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))


def step_response(t, a0, w, z):
    """Exact relative displacement of u'' + 2 z w u' + w^2 u = -a0 from rest."""
    s = math.sqrt(1.0 - z * z)
    wd = w * s
    return -a0 / (w * w) * (1.0 - np.exp(-z * w * t) * (np.cos(wd * t)
                                                         + z / s * np.sin(wd * t)))


def check_recurrence_exact():
    """The recurrence is exact for an input linear between samples, whatever the step:
    a constant acceleration from t = 0, and a triangular pulse (three ramps superposed,
    kinks at samples), each stepped at dt = 0.37 T against the exact damped response."""
    T, z = 1.0, 0.05
    w = 2.0 * math.pi / T
    dt = 0.37 * T
    t = dt * np.arange(60)
    u, _ = motion.oscillator_response(dt, np.full(len(t), 3.0), T, z)
    ref = step_response(t, 3.0, w, z)
    report("constant acceleration 3 m/s^2, dt = 0.37 T: max |u - u_exact| / max |u|",
           np.max(np.abs(u - ref)) / np.max(np.abs(ref)), 1e-13)
    # Triangle of height 2 m/s^2 from 0 to 4 dt, peak at 2 dt: slope changes r, -2r, r.
    r = 2.0 / (2 * dt)
    acc = np.interp(t, [0, 2 * dt, 4 * dt, t[-1]], [0, 2.0, 0, 0])
    ref = sum(c * np.where(t >= tk, ramp_response(np.maximum(t - tk, 0), r, w, z), 0.0)
              for c, tk in [(1, 0.0), (-2, 2 * dt), (1, 4 * dt)])
    for zz in (0.0, 0.05, 0.2):
        u, _ = motion.oscillator_response(dt, acc, T, zz)
        ref = sum(c * np.where(t >= tk, ramp_response(np.maximum(t - tk, 0), r, w, zz), 0)
                  for c, tk in [(1, 0.0), (-2, 2 * dt), (1, 4 * dt)])
        report(f"triangular pulse, damping {zz:g}, dt = 0.37 T: max |u - u_exact| / max |u|",
               np.max(np.abs(u - ref)) / np.max(np.abs(ref)), 1e-13)
    # The spectrum routine (all periods at once, on the record interpolated to at least
    # m points per period): exact at its samples, so its S_d falls short of the exact peak
    # by at most 1 - cos(pi/m) (a peak half a step from the nearest sample).
    tf = np.linspace(0, t[-1], 400001)
    peak = np.max(np.abs(sum(c * np.where(tf >= tk, ramp_response(np.maximum(tf - tk, 0), r,
                                                                  w, 0.05), 0)
                             for c, tk in [(1, 0.0), (-2, 2 * dt), (1, 4 * dt)])))
    for m in (10, 1000):
        sp = motion.response_spectrum(dt, acc, [T], 0.05, points_per_period=m)
        report(f"spectrum of the pulse, {m} points per period: (max |u_exact| - S_d) / S_d, "
               f"within 1 - cos(pi/{m}) = {1 - math.cos(math.pi / m):.1e}",
               (peak - sp.sd[0]) / peak, 1 - math.cos(math.pi / m))
        assert sp.sd[0] <= peak * (1 + 1e-13)
    # Its points are those of the record interpolated to ceil(10 dt/T) = 4 steps per step.
    fine = np.interp(dt / 4 * np.arange(4 * (len(t) - 1) + 1), t, acc)
    u, _ = motion.oscillator_response(dt / 4, fine, T, 0.05)
    sp = motion.response_spectrum(dt, acc, [T], 0.05, points_per_period=10)
    report("spectrum, 10 points per period, against the response on the record "
           "interpolated to dt/4: |S_d - max |u|| / S_d", abs(sp.sd[0] - np.max(np.abs(u)))
           / sp.sd[0], 1e-13)


def check_resonance():
    """A harmonic base acceleration A sin(w t) at the oscillator's own period, 200
    cycles: PSA / A -> 1/(2 z) once the transient exp(-z w t) has died out (to 1e-10). The
    piecewise-linear input carries its fundamental at the amplitude A sinc^2(w dt/2)
    (linear interpolation = the samples convolved with a hat)."""
    A, T = 2.0, 1.0
    dt = T / 100
    t = dt * np.arange(200 * 100 + 1)
    a = A * np.sin(2 * math.pi * t / T)
    x = math.pi * dt / T
    for z in (0.02, 0.05, 0.1):
        sp = motion.response_spectrum(dt, a, [T], z)
        ref = A / (2 * z)
        report(f"damping {z:g}: |PSA - A/(2z)| / (A/(2z)) (the input as sampled, "
               "no sinc^2 factor)", abs(sp.psa[0] / ref - 1), 4e-4)
        report(f"damping {z:g}: |PSA - A sinc^2(w dt/2)/(2z)| / (A/(2z))",
               abs(sp.psa[0] / (ref * (math.sin(x) / x) ** 2) - 1), 1e-10)


def pulse(dt, tp=2.0, d=0.3, before=1.0, after=3.0):
    """A displacement pulse u_g = d sin^4(pi t/tp) on [0, tp], zero elsewhere: with
    s = pi t/tp its acceleration is d (pi/tp)^2 (12 sin^2 s cos^2 s - 4 sin^4 s); the
    displacement, velocity, acceleration and jerk vanish at both ends, and PGD = d at
    tp/2, PGA = 4 d (pi/tp)^2 there too. Returns times, acceleration, displacement at the
    step dt, from `before` s ahead of the pulse to `after` s past it."""
    t = dt * np.arange(int(round((before + tp + after) / dt)) + 1) - before
    s = np.clip(t, 0, tp) * math.pi / tp
    k = math.pi / tp
    inside = (t > 0) & (t < tp)
    acc = np.where(inside, d * k * k * (12 * np.sin(s) ** 2 * np.cos(s) ** 2
                                        - 4 * np.sin(s) ** 4), 0.0)
    disp = np.where(inside, d * np.sin(s) ** 4, 0.0)
    return t, acc, disp


def check_spectrum_limits():
    """Very short period: PSA -> PGA (the oscillator follows the ground rigidly); very
    long period: S_d -> PGD (the mass stays put while the ground moves). On the
    sin^4 displacement pulse (tp = 2 s, 0.3 m), dt = 0.005 s."""
    dt = 0.005
    t, acc, disp = pulse(dt)
    pga = 4 * 0.3 * (math.pi / 2.0) ** 2
    sp = motion.response_spectrum(dt, acc, [0.001, 0.01, 200.0, 2000.0], 0.05)
    # Short periods: the oscillator overshoots by about the change of slope at a kink of
    # the interpolated input over omega (9.9e-6 of PGA at 0.001 s); the lag of 2 z a'/omega
    # is smaller. Long periods: the damping force 2 z omega u' leaves O(z omega tp) of PGD
    # (1.3e-3 at 200 s, 1.4e-4 at 2000 s), the interpolated input 2.1e-5 of PGD.
    report("T = 0.001 s: |PSA - PGA| / PGA (PGA = 4 d (pi/tp)^2 of the closed form)",
           abs(sp.psa[0] - pga) / pga, 5e-5)
    report("T = 0.01 s: |PSA - PGA| / PGA", abs(sp.psa[1] - pga) / pga, 5e-5)
    report("T = 200 s: |S_d - PGD| / PGD (PGD = 0.3 m of the closed form)",
           abs(sp.sd[2] - 0.3) / 0.3, 3e-3)
    report("T = 2000 s: |S_d - PGD| / PGD", abs(sp.sd[3] - 0.3) / 0.3, 3e-4)
    report("T = 0.01 s: |SA - PSA| / PSA (total and pseudo-acceleration agree)",
           abs(sp.sa[1] - sp.psa[1]) / sp.psa[1], 1e-6)


def check_integration_baseline():
    """Integration of the sin^4 pulse against its closed-form displacement, and the
    baseline correction: the pulse plus an offset 0.05 + 0.01 t m/s^2 is restored, and
    the corrected velocity and displacement end at zero."""
    dt = 0.005
    t, acc, disp = pulse(dt)
    v, d = motion.integrate(dt, acc)
    report("displacement of the integrated pulse: max |d - d_exact| / PGD",
           np.max(np.abs(d - disp)) / 0.3, 1e-4)
    bad = acc + 0.05 + 0.01 * (t - t[0])
    fixed = motion.baseline_correct(dt, bad)
    v, d = motion.integrate(dt, fixed)
    report("corrected velocity and displacement at the end (m/s, m)",
           max(abs(v[-1]), abs(d[-1])), 1e-13)
    report("corrected pulse: max |a - a_pulse| / PGA", np.max(np.abs(fixed - acc))
           / np.max(np.abs(acc)), 1e-12)
    report("corrected pulse: max |d - d_exact| / PGD", np.max(np.abs(d - disp)) / 0.3, 1e-4)


def check_fourier():
    """A sine of amplitude A at a frequency of the FFT's grid, over Td = 10 s: |X(f0)| =
    A Td / 2 (the continuous transform over the record), and Parseval's sum."""
    dt, td, f0, A = 0.01, 10.0, 2.0, 1.5
    t = dt * np.arange(int(round(td / dt)))
    a = A * np.sin(2 * math.pi * f0 * t)
    f, fas = motion.fourier_amplitude(dt, a)
    k = int(np.argmin(np.abs(f - f0)))
    report("|FAS(f0) - A Td/2| / (A Td/2)", abs(fas[k] - A * td / 2) / (A * td / 2), 1e-12)
    n = len(a)
    rhs = (2 * np.sum(fas ** 2) - fas[0] ** 2 - (fas[-1] ** 2 if n % 2 == 0 else 0)) / (n * dt)
    report("Parseval: |sum a^2 dt - spectrum| / sum a^2 dt", abs(np.sum(a * a) * dt - rhs)
           / (np.sum(a * a) * dt), 1e-12)


# ----------------------------------------------------------------------- intensity
def check_arias():
    """A sin(2 pi t/T) over n whole cycles: I_a = pi A^2 Td / (4 g); the piecewise-linear
    integral of the samples is A^2 Td/2 (2 + cos w dt)/3 exactly; D5-95 from the
    closed-form Husid curve t/Td - sin(2 w t)/(2 w Td), its crossings found by bisection."""
    A, T, n, dt = 3.0, 0.5, 20, 0.005
    td = n * T
    t = dt * np.arange(int(round(td / dt)) + 1)
    a = A * np.sin(2 * math.pi * t / T)
    w = 2 * math.pi / T
    ia = motion.arias_intensity(dt, a)
    ref = math.pi * A * A * td / (4 * G)
    # The interpolant integrates to (2 + cos w dt)/3 of the sine's: (w dt)^2/6 = 6.6e-4 short.
    report("|I_a - pi A^2 Td/(4g)| / I_a", abs(ia - ref) / ref, 1e-3)
    report("|I_a - the same for the interpolant| / I_a",
           abs(ia - ref * (2 + math.cos(w * dt)) / 3) / ref, 1e-12)

    def cross(frac):
        lo, hi = 0.0, td
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            h = mid / td - math.sin(2 * w * mid) / (2 * w * td)
            lo, hi = (mid, hi) if h < frac else (lo, mid)
        return 0.5 * (lo + hi)
    d595 = cross(0.95) - cross(0.05)
    got = motion.significant_duration(dt, a)
    report(f"|D5-95 - {d595:.6f} s| / D5-95", abs(got - d595) / d595, 1e-6)


def check_pore_pressure_ratio():
    """r_u = (u - u0)/sigma'_v0: two points, u0 = 10 and 20 kPa, sigma'_v0 = 15 and 30
    kPa; u rising to u0 + sigma'_v0 gives r_u = 1 exactly."""
    u0 = np.array([10e3, 20e3])
    sv = np.array([15e3, 30e3])
    frac = np.linspace(0, 1, 11)[:, None]
    u = u0 + frac * sv
    ru = motion.pore_pressure_ratio(u, sv)
    report("max |r_u - fraction|", np.max(np.abs(ru - frac)), 1e-15)
    ru = motion.pore_pressure_ratio(u + 5.0, sv, initial=u0)
    report("given u0: max |r_u - fraction - 5/sigma'_v0|",
           np.max(np.abs(ru - frac - 5.0 / sv)), 1e-15)
    try:
        motion.pore_pressure_ratio(u, -sv)
    except ValueError as e:
        assert "sigma'_v0" in str(e)
    else:
        raise AssertionError("a negative sigma'_v0 was accepted")


# ----------------------------------------------------------------------- files
AT2_VALUES = [0.001, -0.002, 0.0035, 0.1, -0.25, 0.3, 0.0, -1.25e-3, 4.5e-2, -0.125, 7e-5]


def write_at2(path, step_line, units_line="ACCELERATION TIME SERIES IN UNITS OF G",
              values=AT2_VALUES, per_line=5, tail=None):
    with open(path, "w") as fh:
        fh.write("PEER NGA STRONG MOTION DATABASE RECORD\n")
        fh.write("A synthetic record, 0 deg\n")
        fh.write(units_line + "\n")
        fh.write(step_line + "\n")
        for k in range(0, len(values), per_line):
            fh.write("".join(f"{x:15.7E}" for x in values[k:k + per_line]) + "\n")
        if tail:
            fh.write(tail)


def expect_error(path, line, words, **kw):
    """read_record refuses the file with a message naming it, the line and words."""
    try:
        motion.read_record(path, **kw)
    except motion.MotionFileError as e:
        msg = str(e)
        where = f"{path}:{line}" if line else f"{path}:"
        assert msg.startswith(where), f"{msg!r} does not start with {where!r}"
        for w in words:
            assert w in msg, f"{msg!r} does not say {w!r}"
        print(f"  refused: {msg}")
    else:
        raise AssertionError(f"{path} was accepted")


def check_files(work):
    """The .AT2 reader on synthetic files in the header spellings of NGA-West2 and
    NGA-West1, values in g, five per line, the last line partial; two-column text; and
    malformed files refused with their line."""
    n, dt = len(AT2_VALUES), 0.005
    for k, step in enumerate([f"NPTS=   {n}, DT=   .0050 SEC",
                              f"NPTS= {n} DT= 0.005 SEC",
                              f"NPTS = {n}, DT = 5.0E-03 SEC,",
                              f"   {n}    .0050    NPTS, DT"]):
        p = os.path.join(work, f"synthetic_{k}.AT2")
        write_at2(p, step)
        rec = motion.read_record(p)
        assert rec.quantity == "acceleration"
        assert len(rec.values) == n and abs(rec.dt - dt) < 1e-15
        err = np.max(np.abs(rec.values - np.array(AT2_VALUES) * G)) / G
        assert err < 1e-15, f"{step!r}: values off by {err:.3e} g"
        print(f"  read {step!r}: {n} values in g, dt {rec.dt:g} s")
    p = os.path.join(work, "synthetic.VT2")
    write_at2(p, f"NPTS= {n}, DT= .0050 SEC", "VELOCITY TIME SERIES IN UNITS OF CM/SEC")
    rec = motion.read_record(p)
    assert rec.quantity == "velocity" and abs(rec.values[3] - 0.001) < 1e-15
    rec = motion.read_record(os.path.join(work, "synthetic_0.AT2"), scale=2.0)
    assert abs(rec.values[5] - 0.6 * G) < 1e-15

    p = os.path.join(work, "two_columns.txt")
    with open(p, "w") as fh:
        fh.write("# from a PEER record, NPTS = 4\n# time (s), acceleration (g)\n\n0 0.0\n"
                 "0.01 0.5\n0.02 -0.25\n0.03 1e-2\n")
    rec = motion.read_record(p, units="g")
    assert np.allclose(rec.values, np.array([0, 0.5, -0.25, 0.01]) * G, rtol=0, atol=1e-15)
    assert abs(rec.dt - 0.01) < 1e-15

    # Malformed: each refused with its line.
    bad = os.path.join(work, "bad_number.AT2")
    write_at2(bad, f"NPTS= {n}, DT= .0050 SEC", tail="  0.1  0.2x  0.3\n")
    expect_error(bad, 8, ["'0.2x'", "not a number"])
    bad = os.path.join(work, "short.AT2")
    write_at2(bad, f"NPTS= {n + 4}, DT= .0050 SEC")
    expect_error(bad, 7, ["11 values", "NPTS = 15", "cut short"])
    bad = os.path.join(work, "long.AT2")
    write_at2(bad, f"NPTS= {n - 3}, DT= .0050 SEC")
    expect_error(bad, 6, ["more values than NPTS = 8"])
    bad = os.path.join(work, "no_step.AT2")
    write_at2(bad, "NPTS= 11 and some words")
    expect_error(bad, 4, ["no NPTS and DT"])
    bad = os.path.join(work, "zero_step.AT2")
    write_at2(bad, f"NPTS= {n}, DT= 0.0 SEC")
    expect_error(bad, 4, ["must be positive"])
    bad = os.path.join(work, "units.AT2")
    write_at2(bad, f"NPTS= {n}, DT= .0050 SEC", "ACCELERATION TIME SERIES IN UNITS OF FURLONGS")
    expect_error(bad, 3, ["units of acceleration"])
    bad = os.path.join(work, "nan.AT2")
    write_at2(bad, f"NPTS= {n + 1}, DT= .0050 SEC", tail="NaN\n")
    expect_error(bad, 8, ["not finite"])
    for name, text, line, words in [
            ("backwards.txt", "0 0\n0.01 1\n# note\n0.005 2\n", 4, ["times must increase",
                                                                    "line 2"]),
            ("three_columns.txt", "0 0\n0.01 1 5\n", 2, ["3 columns"]),
            ("word.txt", "0 0\n0.01 one\n", 2, ["not two numbers"]),
            ("uneven.txt", "0 0\n0.01 1\n0.02 1\n0.035 2\n0.04 0\n", 4, ["uneven times"]),
            ("empty.txt", "# nothing\n", 0, ["0 data lines"])]:
        p = os.path.join(work, name)
        with open(p, "w") as fh:
            fh.write(text)
        expect_error(p, line, words)
    try:
        motion.read_record(os.path.join(work, "synthetic_0.AT2"), quantity="displacement")
    except motion.MotionFileError as e:
        assert "holds acceleration" in str(e)
    else:
        raise AssertionError("an acceleration record read as displacement")


def check_run_readers(work):
    """The readers of runs on a file written here with h5py in the layout of
    doc/output.md: a /diagnostics series, and one fluid point's pore pressure over three
    frames with the points in a different order in each, turned into r_u."""
    import h5py
    from dpmpm import open_run
    path = os.path.join(work, "records.h5")
    ids = np.array([4, 9, 2])
    u0 = np.array([10e3, 20e3, 30e3])                   # by id order 2, 4, 9
    sv = 15e3
    with h5py.File(path, "w") as f:
        f.attrs["ndim"] = np.int32(2)
        for k, t in enumerate([0.0, 0.5, 1.0]):
            fr = f.create_group(f"frames/{k:06d}")
            fr.attrs["time"] = np.float64(t)
            fr.attrs["step"] = np.int64(10 * k)
            order = np.roll(ids, k)
            g = fr.create_group("fluid")
            g["id"] = order
            g["pore_pressure"] = np.array([u0[np.searchsorted([2, 4, 9], i)] + t * sv * i
                                           / 9 for i in order])
            g["v"] = np.outer(order, [1.0, -2.0]) * t
        d = f.create_group("diagnostics")
        d["time"] = np.array([0.0, 0.25, 0.5])
        d["kinetic_energy"] = np.array([0.0, 1.0, 4.0])
    with open_run(path) as run:
        t, e = motion.diagnostics_series(run, "kinetic_energy")
        assert np.array_equal(t, [0, 0.25, 0.5]) and np.array_equal(e, [0, 1, 4])
        t, u = motion.point_history(run, "fluid", "pore_pressure", 9)
        assert np.array_equal(t, [0, 0.5, 1.0])
        ru = motion.pore_pressure_ratio(u, sv)
        report("r_u of point 9 from the frames: max |r_u - t|", np.max(np.abs(ru - t)), 1e-15)
        t, vy = motion.point_history(run, "fluid", "v", 4, column=1)
        assert np.array_equal(vy, [0, -4.0, -8.0]), vy
        for bad in (lambda: motion.point_history(run, "fluid", "pore_pressure", 5),
                    lambda: motion.diagnostics_series(run, "strain_energy")):
            try:
                bad()
            except KeyError as e:
                print(f"  refused: {e}")
            else:
                raise AssertionError("a missing point or series was read")


def check_probe_reader(work):
    """dpmpm.motion.probe_history on /probes written here with h5py in the layout of
    doc/output.md (3 probes in 2D, velocity column d (k - 1) + a), and python3 -m dpmpm
    motion FILE.h5 --probe --axis on it: the peak acceleration of probe 1 along y printed
    as the record gives it; a probe beyond the run's refused."""
    import h5py
    from dpmpm import open_run
    path = os.path.join(work, "probes.h5")
    m, n, d, dt = 400, 3, 2, 0.005
    t = dt * np.arange(1, m + 1)
    vel = np.zeros((m, n * d))
    acc = np.zeros((m, n * d))
    for k in range(n):
        for a in range(d):
            vel[:, d * k + a] = (k + 1) * (a + 1) * np.sin(2 * math.pi * t)
            acc[:, d * k + a] = (k + 1) * (a + 1) * 2 * math.pi * np.cos(2 * math.pi * t)
    with h5py.File(path, "w") as f:
        f.attrs["ndim"] = np.int32(d)
        g = f.create_group("probes")
        g["time"] = t
        g["step"] = np.arange(1, m + 1, dtype=float)
        g["velocity"] = vel
        g["acceleration"] = acc
        g["position"] = np.array([[0.0, 1.0], [0.5, 2.0], [1.0, 3.0]])
    with open_run(path) as run:
        pr = motion.probe_history(run, 1)
        assert np.array_equal(pr.position, [0.5, 2.0]), pr.position
        assert np.array_equal(pr.velocity[:, 1], 4 * np.sin(2 * math.pi * t))
        assert np.array_equal(pr.acceleration[:, 0], 2 * 2 * math.pi * np.cos(2 * math.pi * t))
        try:
            motion.probe_history(run, 3)
        except KeyError as e:
            print(f"  refused: {e}")
        else:
            raise AssertionError("probe 3 of 3 was read")
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "scripts", "python"))
    png = os.path.join(work, "probe.png")
    r = subprocess.run([sys.executable, "-m", "dpmpm", "motion", path, "--probe", "1", "--axis",
                        "y", "--no-baseline", "-o", png], env=env, capture_output=True, text=True)
    print("  " + r.stdout.replace("\n", "\n  ").rstrip())
    assert r.returncode == 0, r.stderr
    pga = [float(x.split("(")[1].split()[0]) for x in r.stdout.splitlines()
           if x.startswith("PGA")][0]
    ref = np.max(np.abs(acc[:, 3]))
    report("probe 1 along y: printed PGA against the record's", abs(pga - ref) / ref, 1e-5)
    # a last step cut short, as a run that ends on t_end writes it: resampled, PGA kept
    with h5py.File(path, "r+") as f:
        tt = f["probes/time"][...]
        tt[-1] = tt[-2] + dt / 3
        f["probes/time"][...] = tt
    r = subprocess.run([sys.executable, "-m", "dpmpm", "motion", path, "--probe", "1", "--axis",
                        "y", "--no-baseline", "-o", png], env=env, capture_output=True, text=True)
    assert r.returncode == 0 and "resampled at 0.005 s" in r.stdout, (r.stdout, r.stderr)
    print("  uneven last step: " + r.stdout.splitlines()[0])


def check_probe_pore_pressure_ratio(work):
    """r_u of the probes from /probes stress and pore_pressure written here with h5py in
    the layout of doc/output.md (2 probes in 2D): the pore pressure raised from its first
    value u_0 by a known fraction of the first record's sigma'_v0 = -sigma_yy, read back
    as that fraction; a record of one phase (no pore_pressure) refused."""
    import h5py
    from dpmpm import open_run
    path = os.path.join(work, "probes_ru.h5")
    m, n, d = 50, 2, 2
    t = 0.01 * np.arange(1, m + 1)
    frac = np.linspace(0.0, 1.0, m) ** 2
    sv0 = np.array([26.0e3, 52.0e3])
    u0 = np.array([49.05e3, 98.1e3])
    sig = np.zeros((m, n, 6))
    pw = np.zeros((m, n))
    for k in range(n):
        sig[:, k, 0] = -0.5 * sv0[k] * (1 - frac)
        sig[:, k, 1] = -sv0[k] * (1 - frac)
        pw[:, k] = u0[k] + frac * sv0[k]
    with h5py.File(path, "w") as f:
        f.attrs["ndim"] = np.int32(d)
        g = f.create_group("probes")
        g["time"] = t
        g["step"] = np.arange(1, m + 1, dtype=float)
        g["velocity"] = np.zeros((m, n * d))
        g["acceleration"] = np.zeros((m, n * d))
        g["position"] = np.array([[0.5, 5.0], [0.5, 3.0]])
        g["displacement"] = np.zeros((m, n * d))
        g["stress"] = sig.reshape(m, 6 * n)
        g["pore_pressure"] = pw
    with open_run(path) as run:
        err = 0.0
        for k in range(n):
            ru = motion.probe_pore_pressure_ratio(motion.probe_history(run, k))
            err = max(err, float(np.max(np.abs(ru - frac))))
        report("r_u of two probes against the fraction of sigma'_v0 raised", err, 1e-15)
        png = motion.plot_pore_pressure_ratios(run, os.path.join(work, "ru.png"))
        assert os.path.getsize(png) > 0
    with h5py.File(path, "r+") as f:
        del f["probes/pore_pressure"]
    with open_run(path) as run:
        try:
            motion.probe_pore_pressure_ratio(motion.probe_history(run, 0))
        except KeyError as e:
            print(f"  refused: {e}")
        else:
            raise AssertionError("r_u of a probe without pore pressure")


# ----------------------------------------------------------------------- command
def check_command(work):
    """python3 -m dpmpm motion on the pulse as a two-column file in g: exit 0, a PNG,
    PGA, PGV, PGD, I_a, D5-95 printed as the functions give them, and the spectrum as
    text; a malformed file: exit 2 and its line on stderr."""
    dt = 0.005
    t, acc, disp = pulse(dt)
    p = os.path.join(work, "pulse.txt")
    motion.write_record(p, t, acc / G, header="sin^4 pulse, acceleration in g")
    png = os.path.join(work, "pulse.png")
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "scripts", "python"))
    spec = os.path.join(work, "pulse_spectrum.txt")
    r = subprocess.run([sys.executable, "-m", "dpmpm", "motion", p, "--units", "g", "-o", png,
                        "--spectrum", spec], env=env, capture_output=True, text=True)
    print("  " + r.stdout.replace("\n", "\n  ").rstrip())
    assert r.returncode == 0, r.stderr
    assert os.path.getsize(png) > 10000, "no figure"
    s = motion.summarize(dt, motion.read_record(p, units="g").values)
    vals = {}
    for line in r.stdout.splitlines():
        if "=" in line and not line.startswith("#"):
            key, val = line.split("=", 1)
            vals[key.strip()] = float(val.split()[0])
    for key, ref in [("PGA", s.pga / G), ("PGV", s.pgv), ("PGD", s.pgd), ("Arias intensity",
                     s.arias), ("D5-95", s.d5_95)]:
        assert key in vals, f"{key} not printed"
        assert abs(vals[key] - ref) <= 1e-5 * abs(ref), f"{key}: {vals[key]} != {ref}"
    report("printed PGD against the closed form 0.3 m", abs(vals["PGD"] - 0.3) / 0.3, 1e-4)
    table = np.loadtxt(spec)
    assert table.shape == (100, 5), table.shape
    report("written spectrum at T = 0.01 s: |PSA - PGA| / PGA (PGA = 4 d (pi/tp)^2)",
           abs(table[0, 3] - 0.3 * math.pi ** 2) / (0.3 * math.pi ** 2), 5e-5)
    bad = os.path.join(work, "bad_number.AT2")
    write_at2(bad, f"NPTS= {len(AT2_VALUES)}, DT= .0050 SEC", tail="  0.1  0.2x  0.3\n")
    r = subprocess.run([sys.executable, "-m", "dpmpm", "motion", bad], env=env,
                       capture_output=True, text=True)
    assert r.returncode == 2 and f"{bad}:8" in r.stderr, (r.returncode, r.stderr)
    print(f"  malformed: exit {r.returncode}, {r.stderr.strip()}")


GROUPS = {"spectra": [check_recurrence_exact, check_resonance, check_spectrum_limits,
                      check_integration_baseline, check_fourier],
          "intensity": [check_arias, check_pore_pressure_ratio],
          "files": [check_files, check_run_readers, check_probe_reader,
                    check_probe_pore_pressure_ratio],
          "command": [check_command]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("groups", nargs="*", metavar="GROUP", help=", ".join(GROUPS))
    ap.add_argument("--workdir", help="where the files are written (default: a temporary "
                    "directory)")
    args = ap.parse_args()
    unknown = [g for g in args.groups if g not in GROUPS]
    if unknown:
        ap.error(f"unknown group {', '.join(unknown)} (one of {', '.join(GROUPS)})")
    work = args.workdir or tempfile.mkdtemp(prefix="check_motion_")
    os.makedirs(work, exist_ok=True)
    for g in args.groups or list(GROUPS):
        for check in GROUPS[g]:
            t0 = time.perf_counter()
            print(f"{check.__name__}: {check.__doc__.splitlines()[0]}")
            if check.__code__.co_argcount:
                check(work)
            else:
                check()
            print(f"  ({time.perf_counter() - t0:.2f} s)")
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
