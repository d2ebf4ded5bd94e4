"""Ground motions and what a seismologist reads from them: reading a record (two-column
text, PEER NGA .AT2), baseline correction and integration, the Fourier amplitude
spectrum, the response spectrum of a damped oscillator, Arias intensity and its
significant duration, and the excess pore-pressure ratio (doc/python.md, "Ground
motions").

Every function works on plain arrays (a time step or times, and a signal) in SI units:
accelerations in m/s^2, velocities in m/s, displacements in m, times in s. The readers
convert a record's units on reading.

    from dpmpm import motion
    rec = motion.read_record("RSN6_IMPVALL.I_I-ELC180.AT2")     # m/s^2 from g
    a = motion.baseline_correct(rec.dt, rec.values)
    v, d = motion.integrate(rec.dt, a)
    T = motion.default_periods()
    sp = motion.response_spectrum(rec.dt, a, T, damping=0.05)   # sp.psa, sp.sd
    f, fas = motion.fourier_amplitude(rec.dt, a)
    ia = motion.arias_intensity(rec.dt, a); d595 = motion.significant_duration(rec.dt, a)
"""
import math
import os
import re
from dataclasses import dataclass, field

import numpy as np

#: Standard gravity (m/s^2), used for records in g and for Arias intensity.
G = 9.80665

#: Factors from the units a record may carry to SI.
UNITS = {"m/s2": 1.0, "m/s^2": 1.0, "g": G, "cm/s2": 0.01, "cm/s^2": 0.01, "gal": 0.01,
         "m/s": 1.0, "cm/s": 0.01, "m": 1.0, "cm": 0.01}

QUANTITIES = ("acceleration", "velocity", "displacement")


class MotionFileError(ValueError):
    """A record file that cannot be read; the message names the file and the line."""

    def __init__(self, path, line, message):
        self.path = path
        self.line = line
        where = f"{path}:{line}" if line else str(path)
        super().__init__(f"{where}: {message}")


@dataclass
class Record:
    """A sampled history read from a file: ``time`` (s, from 0 for .AT2), ``values`` in SI
    units, ``quantity`` (acceleration, velocity or displacement), the file's ``header``
    lines and its ``path``. ``dt`` is the (uniform) step."""
    time: np.ndarray
    values: np.ndarray
    quantity: str = "acceleration"
    path: str = ""
    header: list = field(default_factory=list)

    @property
    def dt(self):
        return time_step(self.time)

    @property
    def name(self):
        return os.path.basename(self.path)


# ---------------------------------------------------------------------------- reading
def read_record(path, units=None, quantity=None, scale=1.0):
    """Read a record: the PEER NGA format (.AT2, .VT2, .DT2; recognised by its header) or
    two columns of text (time, value; lines starting with #, % or ! and blank lines are
    skipped). ``units`` gives the unit of a two-column file (a key of UNITS, default m/s^2
    and the quantity from it); an NGA file states its own. ``scale`` multiplies the values.
    Raises MotionFileError naming the file and line of the first problem."""
    with open(path, "r", errors="replace") as fh:
        lines = fh.read().splitlines()
    if _looks_like_nga(lines):
        rec = _read_nga(path, lines)
        if units is not None:
            raise ValueError(f"{path}: a PEER NGA file states its units; do not give units")
    else:
        rec = _read_columns(path, lines, units or "m/s2")
    if quantity is not None and quantity != rec.quantity:
        raise MotionFileError(path, 0, f"holds {rec.quantity}, not {quantity}")
    rec.values = rec.values * float(scale)
    return rec


def _looks_like_nga(lines):
    """An NGA file: its fourth line gives NPTS and DT, or a header line (not a comment
    of a two-column file) names NPTS or PEER (then a fourth line that cannot be read is
    an error of that line)."""
    if len(lines) >= 4 and _nga_step_line(lines[3]) is not None:
        return True
    return any(re.search(r"NPTS|PEER", line, re.I) for line in lines[:4]
               if not line.lstrip().startswith(("#", "%", "!")))


_NUMBER = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?)"
# NGA-West2: "NPTS=  3930, DT=   .0050 SEC"; also without the comma or with spaces around
# "=", and the older "  3930    .0050    NPTS, DT" of NGA-West1.
_NGA_KEYED = (re.compile(r"NPTS\s*=\s*(\d+)", re.I), re.compile(r"DT\s*=\s*" + _NUMBER, re.I))
_NGA_OLD = re.compile(r"^\s*(\d+)\s*,?\s+" + _NUMBER + r"\s*,?\s*NPTS\s*,?\s*DT", re.I)


def _nga_step_line(line):
    """(npts, dt) from the fourth line of an NGA file, or None."""
    n, d = (r.search(line) for r in _NGA_KEYED)
    if n and d:
        return int(n.group(1)), _float(d.group(1))
    m = _NGA_OLD.search(line)
    if m:
        return int(m.group(1)), _float(m.group(2))
    return None


def _float(text):
    return float(text.replace("d", "e").replace("D", "e"))


def _nga_units(path, line):
    """Quantity and SI factor from the third header line ("ACCELERATION TIME SERIES IN
    UNITS OF G", "VELOCITY ... CM/S", "DISPLACEMENT ... CM")."""
    up = line.upper()
    quantity = next((q for q in QUANTITIES if q.upper() in up), None)
    if quantity is None:
        raise MotionFileError(path, 3, "no ACCELERATION, VELOCITY or DISPLACEMENT in the "
                              f"header line {line.strip()!r}")
    m = re.search(r"UNITS?\s+OF\s+([A-Z/0-9^*]+)", up) or re.search(r"IN\s+([A-Z/0-9^*]+)\s*$",
                                                                  up.strip())
    unit = m.group(1).lower().replace("sec", "s").replace("**", "^") if m else None
    expected = {"acceleration": ("g", "cm/s2", "cm/s^2", "m/s2", "m/s^2", "gal"),
                "velocity": ("cm/s", "m/s"), "displacement": ("cm", "m")}[quantity]
    if unit not in expected:
        raise MotionFileError(path, 3, f"units of {quantity} not understood in "
                              f"{line.strip()!r} (expected one of {', '.join(expected)})")
    return quantity, UNITS[unit]


def _read_nga(path, lines):
    if len(lines) < 4:
        raise MotionFileError(path, len(lines), "a PEER NGA file has four header lines")
    quantity, factor = _nga_units(path, lines[2])
    step = _nga_step_line(lines[3])
    if step is None:
        raise MotionFileError(path, 4, f"no NPTS and DT in {lines[3].strip()!r} (expected "
                              "'NPTS= 3930, DT= .0050 SEC' or '3930 .0050 NPTS, DT')")
    npts, dt = step
    if not dt > 0 or not math.isfinite(dt):
        raise MotionFileError(path, 4, f"time step DT = {dt:g}: must be positive")
    if npts < 2:
        raise MotionFileError(path, 4, f"NPTS = {npts}: at least 2 values are needed")
    values = []
    for k, line in enumerate(lines[4:], start=5):
        for tok in line.replace(",", " ").split():
            try:
                x = _float(tok)
            except ValueError:
                raise MotionFileError(path, k, f"{tok!r} is not a number") from None
            if not math.isfinite(x):
                raise MotionFileError(path, k, f"value {tok} is not finite")
            values.append(x)
        if len(values) > npts:
            raise MotionFileError(path, k, f"more values than NPTS = {npts} of line 4")
    if len(values) < npts:
        raise MotionFileError(path, len(lines), f"{len(values)} values, NPTS = {npts} on "
                              "line 4: the file is cut short")
    time = dt * np.arange(npts)
    return Record(time, np.asarray(values) * factor, quantity, str(path), lines[:4])


def _read_columns(path, lines, units):
    key = units.lower()
    if key not in UNITS:
        raise ValueError(f"units {units!r}: one of {', '.join(UNITS)}")
    quantity = ("displacement" if key in ("m", "cm") else
                "velocity" if key in ("m/s", "cm/s") else "acceleration")
    rows, where, header = [], [], []
    for k, line in enumerate(lines, start=1):
        s = line.strip()
        if not s or s[0] in "#%!":
            if not rows:
                header.append(line)
            continue
        parts = s.replace(",", " ").split()
        if len(parts) != 2:
            raise MotionFileError(path, k, f"{len(parts)} columns, expected 2 (time, value)")
        try:
            t, x = (_float(p) for p in parts)
        except ValueError:
            raise MotionFileError(path, k, f"not two numbers: {s!r}") from None
        if not (math.isfinite(t) and math.isfinite(x)):
            raise MotionFileError(path, k, f"not finite: {s!r}")
        if rows and not t > rows[-1][0]:
            raise MotionFileError(path, k, f"time {t:g} does not follow {rows[-1][0]:g} of "
                                  f"line {where[-1]}: times must increase")
        rows.append((t, x))
        where.append(k)
    if len(rows) < 2:
        raise MotionFileError(path, 0, f"{len(rows)} data lines: at least 2 are needed")
    a = np.asarray(rows)
    k = _first_uneven(a[:, 0])
    if k is not None:
        raise MotionFileError(path, where[k + 1], _uneven_message(a[:, 0], k))
    return Record(a[:, 0], a[:, 1] * UNITS[key], quantity, str(path), header)


def _first_uneven(t, rtol=1e-6):
    """Index of the first step of t that differs from the mean step by more than rtol of
    it, or None."""
    dt = (t[-1] - t[0]) / (len(t) - 1)
    bad = np.nonzero(np.abs(np.diff(t) - dt) > rtol * dt)[0]
    return int(bad[0]) if len(bad) else None


def _uneven_message(t, k):
    dt = (t[-1] - t[0]) / (len(t) - 1)
    return (f"uneven times: step {t[k + 1] - t[k]:.9g} s from {t[k]:.9g} s, the mean step "
            f"is {dt:.9g} s (resample the record to a constant step)")


def time_step(time, rtol=1e-6):
    """The uniform step of a series of times; ValueError naming the first step that
    differs from the mean step by more than rtol of it."""
    t = np.asarray(time, dtype=float)
    if t.ndim != 1 or len(t) < 2:
        raise ValueError("a series needs at least two times")
    k = _first_uneven(t, rtol)
    if k is not None:
        raise ValueError(_uneven_message(t, k))
    return (t[-1] - t[0]) / (len(t) - 1)


def write_record(path, time, values, header=""):
    """Two columns (time, value) as text, readable by read_record."""
    with open(path, "w") as fh:
        for line in header.splitlines():
            fh.write(f"# {line}\n")
        for t, x in zip(np.asarray(time), np.asarray(values)):
            fh.write(f"{t:.10g} {x:.10e}\n")


# --------------------------------------------------------- integration and baseline
def integrate(dt, acc, v0=0.0, d0=0.0):
    """Velocity and displacement of an acceleration taken linear between samples,
    integrated exactly: v_{n+1} = v_n + dt (a_n + a_{n+1})/2,
    d_{n+1} = d_n + dt v_n + dt^2 (2 a_n + a_{n+1})/6."""
    a = np.asarray(acc, dtype=float)
    v = np.empty_like(a)
    d = np.empty_like(a)
    v[0], d[0] = v0, d0
    v[1:] = v0 + np.cumsum(0.5 * dt * (a[:-1] + a[1:]))
    d[1:] = d0 + np.cumsum(dt * v[:-1] + dt * dt * (2.0 * a[:-1] + a[1:]) / 6.0)
    return v, d


def baseline_correct(dt, acc):
    """The acceleration less the linear baseline c0 + c1 t whose two coefficients make
    the integrated velocity and displacement (integrate) both end at zero. The
    correction is integrated exactly, so both end values are zero to round-off; a
    record at rest before it starts keeps v(0) = d(0) = 0."""
    a = np.asarray(acc, dtype=float)
    n = len(a)
    if n < 3:
        raise ValueError("baseline correction needs at least three samples")
    T = dt * (n - 1)
    v, d = integrate(dt, a)
    # A baseline c0 + c1 t integrates to v = c0 t + c1 t^2/2, d = c0 t^2/2 + c1 t^3/6.
    m = np.array([[T, T * T / 2.0], [T * T / 2.0, T ** 3 / 6.0]])
    c0, c1 = np.linalg.solve(m, [v[-1], d[-1]])
    return a - (c0 + c1 * dt * np.arange(n))


# ----------------------------------------------------------------- spectra
def fourier_amplitude(dt, acc):
    """One-sided Fourier amplitude spectrum: frequencies f_k = k/(N dt) from 0 to the
    Nyquist frequency (Hz) and |X(f_k)| = |dt sum_n a_n exp(-2 pi i f_k n dt)|, the
    modulus of the continuous Fourier transform of the record (units of the signal times
    s: m/s for an acceleration in m/s^2). Not doubled: Parseval reads
    sum a_n^2 dt = (2 sum_k |X_k|^2 - |X_0|^2 - [|X_N/2|^2 for even N]) / (N dt)."""
    a = np.asarray(acc, dtype=float)
    return np.fft.rfftfreq(len(a), dt), dt * np.abs(np.fft.rfft(a))


def default_periods(n=100, t_min=0.01, t_max=10.0):
    """n periods spaced evenly in log from t_min to t_max (s)."""
    return np.geomspace(t_min, t_max, n)


@dataclass
class ResponseSpectrum:
    """Peaks of the relative response of linear oscillators to a base acceleration, per
    period: ``sd`` = max |u| (m), ``psv`` = omega sd (m/s), ``psa`` = omega^2 sd (m/s^2),
    ``sa`` = max |u'' + a_g| (total acceleration, m/s^2), at ``damping`` (ratio)."""
    periods: np.ndarray
    damping: float
    sd: np.ndarray
    psv: np.ndarray
    psa: np.ndarray
    sa: np.ndarray


def oscillator_coefficients(omega, damping, dt):
    """Matrices A (2, 2, m) and B (2, 2, m) of the exact step of u'' + 2 z w u' + w^2 u =
    f(t) for f linear over the step (Nigam and Jennings 1969): [u, u']_{n+1} =
    A [u, u']_n + B [f_n, f_{n+1}]. Written through the particular solution of a linear
    force, u_p(s) = c0 + c1 s with c1 = (f_{n+1} - f_n)/(dt w^2), c0 = (f_n - 2 z w c1)/w^2:
    the state less u_p evolves freely by A. Needs 0 <= damping < 1."""
    w = np.asarray(omega, dtype=float)
    z = float(damping)
    if not 0.0 <= z < 1.0:
        raise ValueError(f"damping ratio {z:g}: the recurrence needs 0 <= damping < 1")
    s = math.sqrt(1.0 - z * z)
    wd = w * s
    e = np.exp(-z * w * dt)
    sn, cs = np.sin(wd * dt), np.cos(wd * dt)
    A = np.array([[e * (cs + z / s * sn), e * sn / wd],
                  [-e * w / s * sn, e * (cs - z / s * sn)]])
    # u_p(0) = c0, u_p'(0) = c1, u_p(dt) = c0 + c1 dt, u_p'(dt) = c1, each linear in
    # (f_n, f_{n+1}): c1 = (f1 - f0)/(dt w^2), c0 = f0/w^2 - 2 z (f1 - f0)/(dt w^3).
    w2 = w * w
    c1 = np.array([-1.0 / (dt * w2), 1.0 / (dt * w2)])            # d c1 / d (f0, f1)
    c0 = np.array([1.0 / w2 + 2.0 * z / (dt * w2 * w), -2.0 * z / (dt * w2 * w)])
    B = np.empty_like(A)
    for j in range(2):
        B[0, j] = c0[j] + c1[j] * dt - (A[0, 0] * c0[j] + A[0, 1] * c1[j])
        B[1, j] = c1[j] - (A[1, 0] * c0[j] + A[1, 1] * c1[j])
    return A, B


def oscillator_response(dt, acc, period, damping=0.05):
    """Relative displacement and velocity histories (m, m/s) of the oscillator of this
    period and damping ratio on a base accelerating by acc (linear between samples),
    from rest: u'' + 2 z w u' + w^2 u = -a_g, stepped exactly (oscillator_coefficients)."""
    a = np.asarray(acc, dtype=float)
    A, B = oscillator_coefficients(np.array([2.0 * math.pi / period]), damping, dt)
    A, B = A[:, :, 0], B[:, :, 0]
    u = np.zeros_like(a)
    v = np.zeros_like(a)
    for n in range(len(a) - 1):
        f0, f1 = -a[n], -a[n + 1]
        u[n + 1] = A[0, 0] * u[n] + A[0, 1] * v[n] + B[0, 0] * f0 + B[0, 1] * f1
        v[n + 1] = A[1, 0] * u[n] + A[1, 1] * v[n] + B[1, 0] * f0 + B[1, 1] * f1
    return u, v


def response_spectrum(dt, acc, periods=None, damping=0.05, points_per_period=10):
    """The response spectrum of a base acceleration (m/s^2, linear between samples) for
    linear oscillators of the given periods (s) and damping ratio, by the exact
    piecewise-linear recurrence of Nigam and Jennings (1969), all periods at once.
    The response is exact at the samples whatever the step. So that a peak between
    samples is not missed, the response of a period shorter than points_per_period
    steps is also evaluated, exactly, at points within each step, at least
    points_per_period per period; a peak half a spacing from the nearest point is then
    read short by at most 1 - cos(pi/points_per_period) (4.9e-2 for 10).
    Round-off grows as the step shrinks against the period, about 1e-15/(omega dt)^2 of
    S_d: 1e-10 at T = 2000 dt, 1e-6 at T = 2e5 dt (doc/verification.md). Returns a
    ResponseSpectrum."""
    a = np.asarray(acc, dtype=float)
    T = default_periods() if periods is None else np.atleast_1d(np.asarray(periods, float))
    if np.any(~(T > 0)):
        raise ValueError("periods must be positive")
    if len(a) < 2:
        raise ValueError("a response spectrum needs at least two samples")
    w = 2.0 * math.pi / T
    z = float(damping)
    A, B = oscillator_coefficients(w, z, dt)
    f = -a
    # The states at every sample, all periods: (samples, periods).
    U = np.zeros((len(a), len(w)))
    V = np.zeros((len(a), len(w)))
    for n in range(len(a) - 1):
        U[n + 1] = A[0, 0] * U[n] + A[0, 1] * V[n] + B[0, 0] * f[n] + B[0, 1] * f[n + 1]
        V[n + 1] = A[1, 0] * U[n] + A[1, 1] * V[n] + B[1, 0] * f[n] + B[1, 1] * f[n + 1]
    c = 2.0 * z * w
    sd = np.max(np.abs(U), axis=0)
    sa = np.max(np.abs(c * V + w * w * U), axis=0)
    # Points within the steps: from the state at the start of a step, the exact step of
    # length s = j dt/m to the input interpolated there.
    sub = np.ones(len(T), dtype=int)
    if points_per_period:
        sub = np.maximum(1, np.ceil(points_per_period * dt / T - 1e-9)).astype(int)
    for j in range(1, int(sub.max())):
        k = np.nonzero(sub > j)[0]
        frac = j / sub[k]
        As, Bs = oscillator_coefficients(w[k], z, dt * frac)
        fs = f[:-1, None] + frac * (f[1:, None] - f[:-1, None])
        u = (As[0, 0] * U[:-1, k] + As[0, 1] * V[:-1, k] + Bs[0, 0] * f[:-1, None]
             + Bs[0, 1] * fs)
        v = (As[1, 0] * U[:-1, k] + As[1, 1] * V[:-1, k] + Bs[1, 0] * f[:-1, None]
             + Bs[1, 1] * fs)
        sd[k] = np.maximum(sd[k], np.max(np.abs(u), axis=0))
        sa[k] = np.maximum(sa[k], np.max(np.abs(c[k] * v + w[k] ** 2 * u), axis=0))
    return ResponseSpectrum(T, z, sd, w * sd, w * w * sd, sa)


# ------------------------------------------------------ intensity and duration
def husid(dt, acc):
    """The running integral of a^2 (m^2/s^3), exact for a linear between samples:
    dt (a_n^2 + a_n a_{n+1} + a_{n+1}^2)/3 per step; zero at the first sample."""
    a = np.asarray(acc, dtype=float)
    out = np.zeros_like(a)
    out[1:] = np.cumsum(dt * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2) / 3.0)
    return out


def arias_intensity(dt, acc, g=G):
    """Arias intensity I_a = pi/(2 g) int a^2 dt (m/s) of an acceleration in m/s^2."""
    return math.pi / (2.0 * g) * husid(dt, acc)[-1]


def significant_duration(dt, acc, start=0.05, end=0.95):
    """The time between the instants at which the running integral of a^2 reaches the
    fractions start and end of its total (D5-95 by default, s); each instant is found
    by linear interpolation of the running integral between samples."""
    h = husid(dt, acc)
    if not h[-1] > 0:
        raise ValueError("significant duration of a record without motion")
    t = dt * np.arange(len(h))
    t0, t1 = np.interp([start * h[-1], end * h[-1]], h, t)
    return t1 - t0


# ------------------------------------------------------------- pore pressure
def pore_pressure_ratio(pore_pressure, vertical_effective_stress, initial=None):
    """r_u = (u - u_0) / sigma'_v0, the excess pore pressure over the initial vertical
    effective stress. pore_pressure: (times, ...) in Pa; vertical_effective_stress:
    sigma'_v0 as a positive (compressive) magnitude in Pa, broadcast against one time;
    initial: u_0 (default: the first time). r_u = 1 where the effective stress is
    lost (liquefaction)."""
    u = np.asarray(pore_pressure, dtype=float)
    s = np.asarray(vertical_effective_stress, dtype=float)
    if np.any(~(s > 0)):
        raise ValueError("sigma'_v0 must be positive (a compressive magnitude in Pa)")
    u0 = u[0] if initial is None else np.asarray(initial, dtype=float)
    return (u - u0) / s


# ----------------------------------------------------------------- readers of runs
def diagnostics_series(run, name):
    """(time, values) of one /diagnostics dataset of an open run (doc/output.md)."""
    d = run.diagnostics
    if name not in d:
        raise KeyError(f"{run.path}: no diagnostics {name!r}; it has {', '.join(sorted(d))}")
    return d["time"], d[name]


@dataclass
class ProbeRecord:
    """The records of one probe of a run (/probes, doc/output.md): times (s), the nearest
    node's velocity (m/s) and acceleration (m/s^2) as (records, ndim) arrays, and the
    node's position (m); where the run has them, the followed solid point's displacement
    (records, ndim) and stress (records, 6; Voigt xx yy zz yz xz xy, tension positive, the
    effective stress in saturated soil) and the followed fluid point's pore pressure
    (records,; Pa, compression positive), else None."""
    time: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    position: np.ndarray
    displacement: np.ndarray = None
    stress: np.ndarray = None
    pore_pressure: np.ndarray = None


def probe_history(run, k):
    """Probe k (0-based, in the order of &output probe_x, ...) of an open run."""
    f = run.file
    if f is None or "probes" not in f:
        raise KeyError(f"{run.path}: no /probes (the run had no &output nprobes)")
    g = f["probes"]
    pos = np.atleast_2d(g["position"][...])
    n, d = pos.shape
    if not 0 <= k < n:
        raise KeyError(f"{run.path}: probe {k} of {n} (0 to {n - 1})")
    m = len(g["time"])
    vel = g["velocity"][...].reshape(m, n, d)[:, k, :]
    acc = g["acceleration"][...].reshape(m, n, d)[:, k, :]
    disp = g["displacement"][...].reshape(m, n, d)[:, k, :] if "displacement" in g else None
    sig = g["stress"][...].reshape(m, n, 6)[:, k, :] if "stress" in g else None
    pw = g["pore_pressure"][...].reshape(m, n)[:, k] if "pore_pressure" in g else None
    return ProbeRecord(g["time"][...], vel, acc, pos[k], disp, sig, pw)


def probe_pore_pressure_ratio(record, vertical=None):
    """r_u(t) of a probe record (probe_history): the excess pore pressure of its fluid point
    over the vertical effective stress of its solid point, both taken from the first record,
    r_u = (u - u_0) / sigma'_v0. vertical: the axis of gravity (0-based; default the last
    axis of the run, as a geostatic start has it)."""
    if record.pore_pressure is None or record.stress is None:
        raise KeyError("the probe has no pore pressure and stress (a run of one phase, or "
                       "written before the probes recorded them)")
    a = len(record.position) - 1 if vertical is None else vertical
    sv0 = -record.stress[0, a]
    if not sv0 > 0:
        raise ValueError(f"sigma'_v0 = {sv0:g} Pa at the first record: not compressive")
    return pore_pressure_ratio(record.pore_pressure, sv0)


def plot_pore_pressure_ratios(run, out, dpi=110):
    """A PNG of r_u(t) of every probe of an open run that has pore pressures, labelled by the
    probe's place."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(np.atleast_2d(run.file["probes"]["position"][...]))
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for k in range(n):
        pr = probe_history(run, k)
        try:
            ru = probe_pore_pressure_ratio(pr)
        except ValueError:
            continue   # a probe at the surface: no effective stress to divide by
        ax.plot(pr.time, ru, lw=0.9, label=f"probe {k} at {', '.join(f'{x:g}' for x in pr.position)} m")
    ax.axhline(1.0, color="k", lw=0.5, ls="--")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("excess pore pressure ratio r_u")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out


def point_history(run, set_name, dataset, point_id, column=None):
    """(time, values) of one point, found by id, over the frames of an open run: e.g. the
    pore pressure of a fluid point, or a column of the solid's velocity."""
    times, vals = [], []
    for fr in run.frames:
        ps = fr.get(set_name)
        if ps is None:
            continue
        ids = ps.id
        k = np.searchsorted(ids, point_id)
        if k >= len(ids) or ids[k] != point_id:
            continue
        x = ps[dataset][k]
        times.append(fr.time)
        vals.append(x if column is None else x[column])
    if not times:
        raise KeyError(f"{run.path}: no point {point_id} in set {set_name!r}")
    return np.asarray(times), np.asarray(vals)


# --------------------------------------------------------------------- summary
@dataclass
class MotionSummary:
    """A record's corrected histories and what is read from them (SI units)."""
    time: np.ndarray
    acceleration: np.ndarray
    velocity: np.ndarray
    displacement: np.ndarray
    pga: float
    pgv: float
    pgd: float
    arias: float
    d5_95: float


def summarize(dt, acc, baseline=True):
    """Histories and peaks of an acceleration record: the baseline-corrected (optional)
    acceleration, its velocity and displacement, PGA, PGV, PGD, I_a and D5-95."""
    a = baseline_correct(dt, acc) if baseline else np.asarray(acc, dtype=float)
    v, d = integrate(dt, a)
    return MotionSummary(dt * np.arange(len(a)), a, v, d, float(np.max(np.abs(a))),
                         float(np.max(np.abs(v))), float(np.max(np.abs(d))),
                         arias_intensity(dt, a), significant_duration(dt, a))


def plot_motion(summary, spectrum, out, title="", dpi=110):
    """A PNG: acceleration, velocity and displacement histories, the Fourier amplitude
    spectrum and the response spectrum (pseudo-acceleration, in g)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = summary
    fig = plt.figure(figsize=(11, 8))
    grid = fig.add_gridspec(3, 2)
    for k, (y, lab) in enumerate([(s.acceleration / G, "acceleration (g)"),
                                  (s.velocity, "velocity (m/s)"),
                                  (s.displacement, "displacement (m)")]):
        ax = fig.add_subplot(grid[k, 0])
        ax.plot(s.time, y, lw=0.7)
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3)
        if k == 2:
            ax.set_xlabel("time (s)")
    dt = s.time[1] - s.time[0]
    f, fas = fourier_amplitude(dt, s.acceleration)
    ax = fig.add_subplot(grid[0:1, 1])
    ax.loglog(f[1:], fas[1:], lw=0.7)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("Fourier amplitude (m/s)")
    ax.grid(alpha=0.3, which="both")
    ax = fig.add_subplot(grid[1:3, 1])
    ax.semilogx(spectrum.periods, spectrum.psa / G, lw=1.2)
    ax.set_xlabel("period (s)")
    ax.set_ylabel(f"pseudo-acceleration, {100 * spectrum.damping:g} % damping (g)")
    ax.grid(alpha=0.3, which="both")
    fig.suptitle(f"{title}  PGA {s.pga / G:.3g} g, PGV {s.pgv:.3g} m/s, PGD {s.pgd:.3g} m, "
                 f"I_a {s.arias:.3g} m/s, D5-95 {s.d5_95:.3g} s", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out
