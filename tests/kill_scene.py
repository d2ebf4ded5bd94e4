"""The scene that tests/check_frame_kill.py and tests/check_flush_kill.py kill and continue:
a saturated column on a fixed floor under gravity (the two-phase part of the scene of
check_stop_signal.py) with a frame at every step and a checkpoint every 25 steps, run on
2 ranks."""
import subprocess

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
