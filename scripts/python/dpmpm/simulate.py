"""Running scenes from Python: one scene on N ranks with a progress bar, and a study (a
list of scenes run in turn or side by side within the cores).

    import dpmpm
    s = dpmpm.Scene.read("inputs/consolidation_2d.nml")
    r = dpmpm.simulate(s, ranks=2, workdir="study")       # study/out/consolidation_2d.h5
    with r.open() as run:
        ...
    results = dpmpm.study([s1, s2, s3], ranks=1, jobs=2)

The exit code of dpmpm becomes an exception carrying the log's own message (dpmpm.errors):
2 InputError, 3 StoppedEarly (continue it with ``restart=True``), 4 MonitorStop, other
RunError.
"""
import os
import re
import subprocess
import threading
import time
from concurrent.futures import ThreadPoolExecutor

from .errors import InputError, MonitorStop, RunError, StoppedEarly
from .launch import MPI_ENV, find_binary, find_mpirun
from .scene import Scene

#: A progress line of the log: "step 3288  t =  2.05774E-01  dt = ...    20.6%  ETA 3.9 s".
PROGRESS = re.compile(r"^step\s+\d+\s+t\s*=.*?\s(\d+(?:\.\d*)?)%\s+ETA\s+(\S+\s*\S*)")

_OPEN_MPI = {}


def _is_open_mpi(mpirun):
    """Whether the launcher is Open MPI's (it needs --oversubscribe for more ranks than
    cores); asked once per launcher."""
    if mpirun not in _OPEN_MPI:
        try:
            out = subprocess.run([mpirun, "--version"], capture_output=True, text=True,
                                 timeout=30).stdout
        except (OSError, subprocess.SubprocessError):
            out = ""
        _OPEN_MPI[mpirun] = "Open MPI" in out or "OpenRTE" in out
    return _OPEN_MPI[mpirun]


class Result:
    """A finished run: ``output`` (its .h5), ``log``, ``scene``, ``status`` (0),
    ``wall`` (seconds), ``command``, ``progress`` (the fractions done, in %, of the log's
    progress lines), ``reused`` (True when the output was there already and nothing ran:
    ``simulate(..., reuse=True)``; command None, wall 0). ``open()`` gives the ``Run``;
    ``read(f)`` opens it, returns f(run) and closes it."""

    def __init__(self, scene, output, log, command, wall, status=0, progress=(), reused=False):
        self.scene, self.output, self.log = scene, output, log
        self.command, self.wall, self.status = command, wall, status
        self.progress = list(progress)
        self.reused = reused

    @property
    def name(self):
        return self.scene.name

    def open(self):
        from .run import open_run
        return open_run(self.output)

    def read(self, f):
        with self.open() as run:
            return f(run)

    def __repr__(self):
        return f"Result({self.name!r}, {self.output!r}, {self.wall:.3g} s)"


def _message(lines, status):
    """What the log says about how the run ended: dpmpm's error and stop lines (mpirun's
    own notes left out), else its last lines."""
    keep = [ln for ln in lines if re.match(r"dpmpm: (input )?error|dpmpm: stopped|"
                                           r"dpmpm: to continue|dpmpm: ended early", ln)]
    if not keep:
        own = [ln for ln in lines if ln.strip() and not ln.startswith("-----")
               and "mpirun" not in ln and "Primary job" not in ln]
        keep = own[-3:] or [f"dpmpm exited with status {status}"]
    return keep


def _error(status, lines, nml, checkpoint=None, **kw):
    prefix = f"dpmpm: input error: {nml}: "
    if status == 2:
        problems = [ln[len(prefix):] if ln.startswith(prefix) else ln
                    for ln in lines if "input error" in ln or ln.startswith("dpmpm: error")]
        return InputError(problems or _message(lines, status), status, **kw)
    msg = _message(lines, status)
    if status == 3:
        ckpt = checkpoint if checkpoint and os.path.exists(checkpoint) else None
        return StoppedEarly(msg, status, checkpoint=ckpt, **kw)
    if status == 4:
        return MonitorStop(msg, status, **kw)
    return RunError(msg, status, **kw)


def simulate(scene, ranks=1, workdir=None, restart=False, binary=None, mpirun=None,
             progress=True, position=None, mpi_args=(), timeout=None, reuse=False):
    """Run a scene on ``ranks`` ranks and return its ``Result``.

    scene: a ``Scene`` or the path of a scene file. A Scene is written to
    ``<workdir>/<dir>/<name>.nml`` (dir: its &output dir) and run in workdir (default: the
    current folder), so its output is ``<workdir>/<dir>/<name>.h5``; a file is run as it
    is, in workdir. The log (stdout and stderr) goes to ``<name>.log`` beside the output.
    restart: continue from the run's checkpoint (``dpmpm --restart``: from
    ``<dir>/<name>.ckpt.h5`` when it exists, else from t = 0). binary, mpirun: the
    executables (``find_binary``, ``find_mpirun``). progress: a tqdm bar fed by the log's
    progress lines (``&run progress_seconds`` sets how often they come); ``position`` is
    the bar's line when several run at once. reuse: when the output file exists already,
    run nothing (the scene file is still written) and return its Result with ``reused``
    set, so that a study run again runs only what it lacks. Raises InputError (exit code
    2), StoppedEarly (3), MonitorStop (4) or RunError (other), with the log's message.
    """
    workdir = os.path.abspath(workdir or os.getcwd())
    if isinstance(scene, Scene):
        nml = os.path.join(workdir, scene.output_dir, scene.name + ".nml")
        scene.write(nml)
    else:
        nml = os.path.abspath(os.fspath(scene))
        scene = Scene.read(nml)
    out_dir = os.path.join(workdir, scene.output_dir)
    os.makedirs(out_dir, exist_ok=True)
    output = os.path.join(out_dir, scene.name + ".h5")
    log = os.path.join(out_dir, scene.name + ".log")
    if reuse and os.path.exists(output):
        return Result(scene, output, log, None, 0.0, reused=True)
    exe, launcher = find_binary(binary), find_mpirun(mpirun)
    cmd = [launcher] + (["--oversubscribe"] if _is_open_mpi(launcher) else []) + \
        list(mpi_args) + ["-n", str(int(ranks)), exe] + (["--restart"] if restart else []) + \
        [nml]
    bar = None
    if progress:
        from tqdm.auto import tqdm
        bar = tqdm(total=100.0, desc=scene.name, unit="%", position=position, leave=True,
                   bar_format="{desc}: {percentage:5.1f}%|{bar}| {postfix}")
    lines, seen = [], []
    t0 = time.perf_counter()
    try:
        with open(log, "w") as logf:
            p = subprocess.Popen(cmd, cwd=workdir, stdout=subprocess.PIPE,
                                 stderr=subprocess.STDOUT, text=True, bufsize=1,
                                 env=dict(os.environ, **MPI_ENV))
            timer = threading.Timer(timeout, p.kill) if timeout else None
            if timer:
                timer.start()
            try:
                for line in p.stdout:
                    logf.write(line)
                    line = line.rstrip("\n")
                    lines.append(line)
                    m = PROGRESS.match(line)
                    if m:
                        seen.append(float(m.group(1)))
                    if m and bar is not None:
                        bar.n = min(100.0, float(m.group(1)))
                        bar.set_postfix_str(f"ETA {m.group(2)}", refresh=False)
                        bar.refresh()
                status = p.wait()
            finally:
                if timer:
                    timer.cancel()
                if p.poll() is None:
                    p.kill()
                    p.wait()
        if status == 0 and bar is not None:
            bar.n = 100.0
            bar.set_postfix_str("done", refresh=False)
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - t0
    if status != 0:
        raise _error(status, lines, nml, checkpoint=scene.checkpoint_file(workdir), log=log,
                     scene=scene, output=output, where=scene.name)
    return Result(scene, output, log, cmd, wall, progress=seen)


def study(scenes, ranks=1, jobs=1, workdir=None, restart=False, binary=None, mpirun=None,
          progress=True, errors="keep", **kw):
    """Run a list of scenes (Scenes or files), ``jobs`` at a time (1: in turn), each on
    ``ranks`` ranks, and return their outcomes in the order given: a ``Result`` per
    finished run and, with ``errors="keep"`` (the default), the ``RunError`` of each
    failed one in its place; ``errors="raise"`` raises the first failure after every run
    has ended. ``jobs`` is limited so that jobs * ranks fits the machine's cores."""
    scenes = list(scenes)
    names = [s.name if isinstance(s, Scene) else os.path.basename(os.fspath(s))
             for s in scenes]
    dup = {n for n in names if names.count(n) > 1}
    if dup and all(isinstance(s, Scene) for s in scenes):
        raise ValueError(f"scenes share the names {sorted(dup)}: their outputs would "
                         "collide (set &run name)")
    cores = os.cpu_count() or 1
    jobs = max(1, min(int(jobs), len(scenes) or 1, max(1, cores // max(1, int(ranks)))))

    def one(k):
        try:
            return simulate(scenes[k], ranks=ranks, workdir=workdir, restart=restart,
                            binary=binary, mpirun=mpirun, progress=progress,
                            position=k if jobs > 1 else None, **kw)
        except RunError as e:
            return e

    if jobs == 1:
        outcomes = [one(k) for k in range(len(scenes))]
    else:
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            outcomes = list(pool.map(one, range(len(scenes))))
    if errors == "raise":
        for o in outcomes:
            if isinstance(o, RunError):
                raise o
    return outcomes
