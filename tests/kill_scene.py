"""The scene that tests/check_frame_kill.py and tests/check_flush_kill.py kill and continue:
a saturated column on a fixed floor under gravity (the two-phase part of the scene of
check_stop_signal.py) with a frame at every step and a checkpoint every 25 steps, run on
2 ranks."""
import os
import pathlib
import shutil
import signal
import subprocess
import sys

#: Steps of a run to its end.
MAX_STEPS = 300


def write_scene(work, name, max_steps=MAX_STEPS):
    """<work>/<name>.nml of the scene; returns its file name."""
    text = f"""&run name = '{name}', t_end = 100.0, max_steps = {max_steps}, cfl = 0.4,
  gravity = 0.0, -9.81, drag = 'implicit' /
&grid ndim = 2, ncells = 16, 16, length = 1.0, 1.0 /
&shape kernel = 'quadratic' /
&material id = 1, density = 2650.0, youngs_modulus = 1.0e6, poisson_ratio = 0.3,
  conductivity = 1.0e-3 /
&material id = 2, model = 'fluid', density = 1000.0, bulk_modulus = 2.0e7 /
&region lo = 0.0, 0.0, hi = 0.375, 0.5, material = 1, phase = 'saturated',
  fluid_material = 2, porosity = 0.4, placement = 'random' /
&boundary face = 'x-', condition = 'roller' /
&boundary face = 'x+', condition = 'roller' /
&boundary face = 'y-', condition = 'fixed' /
&output dir = 'out', frame_interval = 1.0e-9, checkpoint_every = 25 /
"""
    (work / f"{name}.nml").write_text(text)
    return f"{name}.nml"


def run_two_ranks(mpiexec, dpmpm, work, args):
    """dpmpm on 2 ranks in work with args: exit code and log."""
    r = subprocess.run([mpiexec, "--oversubscribe", "-n", "2", dpmpm] + args, cwd=work,
                       capture_output=True, text=True, timeout=600)
    return r.returncode, r.stdout + r.stderr


def kill_run(p):
    """SIGKILL to the ranks of the run p (the children of its mpiexec), then to p itself;
    waits for p."""
    ranks = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True,
                           text=True).stdout.split()
    for pid in ranks:
        try:
            os.kill(int(pid), signal.SIGKILL)
        except ProcessLookupError:
            pass
    p.kill()
    p.wait()


class KillCheck:
    """What both kill tests share: a fresh work directory, the scene and the 2-rank run in
    it, scripts/check_output.py, and the checks made so far (expect, finish)."""

    CHECK_OUTPUT = pathlib.Path(__file__).resolve().parent.parent / "scripts" / "check_output.py"

    def __init__(self, mpiexec, dpmpm, work):
        self.mpiexec, self.dpmpm, self.work = mpiexec, dpmpm, pathlib.Path(work)
        shutil.rmtree(self.work, ignore_errors=True)
        self.work.mkdir(parents=True)
        self.failures = []

    def expect(self, cond, what):
        print(("ok:   " if cond else "FAIL: ") + what, flush=True)
        if not cond:
            self.failures.append(what)

    def scene(self, name, max_steps=MAX_STEPS):
        return write_scene(self.work, name, max_steps)

    def run(self, args):
        return run_two_ranks(self.mpiexec, self.dpmpm, self.work, args)

    def check_output(self, path):
        """scripts/check_output.py on path: exit code and output."""
        r = subprocess.run([sys.executable, str(self.CHECK_OUTPUT), str(path)], capture_output=True,
                           text=True)
        return r.returncode, r.stdout + r.stderr

    def finish(self):
        print("PASS" if not self.failures else f"{len(self.failures)} check(s) failed")
        sys.exit(1 if self.failures else 0)
