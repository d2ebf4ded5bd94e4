#!/usr/bin/env python3
"""The command line says what it is doing: --help, --version, a bad option, the start banner,
a warning when an earlier output file is overwritten, and an ETA that follows max_steps.

    check_command_line.py <mpiexec> <dpmpm> <work dir> <project version>
"""
import pathlib
import re
import shutil
import subprocess
import sys
import time

mpiexec, dpmpm, work, version = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3]), sys.argv[4]
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
failures = []


def expect(cond, what):
    print(("ok:   " if cond else "FAIL: ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(*args, ranks=1):
    """dpmpm with args on ranks ranks in work: one rank runs the binary itself, as a plain
    `dpmpm file.nml` does (MPI as a singleton, without the start of mpiexec, which holds a
    single process that ends with an error code 2 s)."""
    t0 = time.time()
    cmd = [dpmpm, *args]
    if ranks > 1:
        cmd = [mpiexec, "--oversubscribe", "-n", str(ranks)] + cmd
    p = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=120)
    wall = time.time() - t0
    print(f"--- dpmpm {' '.join(args)} on {ranks}: exit code {p.returncode}\n{p.stdout}{p.stderr}")
    return p, wall


p, _ = run("--help", ranks=2)
expect(p.returncode == 0, "--help: exit code 0")
expect(p.stdout.count("usage: dpmpm") == 1, "--help: the usage, printed once on 2 ranks")
for word in ["--check", "--version", "Exit codes", "doc/input.md"]:
    expect(word in p.stdout, f"--help mentions {word}")

p, _ = run("--version")
expect(p.returncode == 0, "--version: exit code 0")
expect(re.fullmatch(rf"dpmpm {re.escape(version)} \(commit \S+\)\n", p.stdout) is not None,
       f"--version prints 'dpmpm {version} (commit ...)'")

p, _ = run("--bogus", "scene.nml")
expect(p.returncode == 2, "an unknown option: exit code 2")
expect("unexpected argument '--bogus'" in p.stderr and "usage: dpmpm" in p.stderr,
       "an unknown option is named, with the usage")

# A short scene whose end is max_steps (t_end lies far beyond it), long enough (about
# 0.4 s on a quiet 2-core machine) for several progress lines at progress_seconds = 0.02.
MAX_STEPS = 4000
(work / "scene.nml").write_text(f"""&run name = 'cli', t_end = 100.0, max_steps = {MAX_STEPS},
  progress_seconds = 0.02, gravity = 0.0, -9.81 /
&grid ndim = 2, ncells = 8, 8, length = 1.0, 1.0 /
&material id = 1, youngs_modulus = 1.0e6, poisson_ratio = 0.3, density = 1000.0 /
&region lo = 0.25, 0.0, hi = 0.75, 0.5 /
&boundary face = 'y-', condition = 'fixed' /
&output dir = 'out' /
""")
p, wall = run("scene.nml", ranks=2)
expect(p.returncode == 0, "the scene runs")
first = p.stdout.splitlines()[0] if p.stdout else ""
expect(first.startswith(f"dpmpm {version} (commit ") and first.endswith(": scene.nml on 2 ranks"),
       "the banner: version, commit, input file and ranks on the first line")
expect("dpmpm: writing out/cli.h5" in p.stdout, "the banner names the output file")
expect("overwritten" not in p.stderr, "no overwrite warning for a new file")

progress = re.findall(r"^step (\d+)  t = .*?\s([\d.]+)%  ETA ([\d.]+) s$", p.stdout, re.M)
expect(len(progress) >= 2, f"progress lines printed ({len(progress)})")
for step, pct, eta in progress:
    expect(abs(float(pct) - 100.0 * int(step) / MAX_STEPS) <= 0.1,
           f"step {step}: {pct} % done counts the steps of max_steps")
    # The first lines extrapolate from a step or two, which a busy machine can stretch
    # a hundredfold; from a fifth of the run on the estimate has enough steps behind it.
    if float(pct) >= 20.0:
        expect(float(eta) <= 5.0 * wall + 2.0,
               f"step {step}: ETA {eta} s is of the order of the run ({wall:.1f} s)")

p, _ = run("scene.nml", ranks=2)
expect(p.returncode == 0, "the scene runs again")
expect(p.stderr.count("dpmpm: warning: out/cli.h5 exists and is overwritten") == 1,
       "the second run warns once that it overwrites out/cli.h5")

# The time step falls tenfold: a soft block (wave speed 1 m/s) falls under g = 100 m/s^2
# until its speed is 10 m/s (0.1 s, 0.5 m), so that c + |v| grows elevenfold. The run
# warns once, names the point of the fastest signal and its volume against its initial
# one; max_dilation is named only for a plastic soil point dilated more than twice, so
# not here.
for model in ["linear_elastic", "mohr_coulomb"]:
    (work / "fall.nml").write_text(f"""&run name = 'fall', t_end = 0.1, gravity = -100.0 /
&grid ndim = 1, ncells = 100, length = 1.0 /
&material id = 1, model = '{model}', youngs_modulus = 1000.0, poisson_ratio = 0.0,
  density = 1000.0 /
&region lo = 0.9, hi = 1.0 /
&output dir = 'out' /
""")
    p, _ = run("fall.nml", ranks=2)
    expect(p.returncode == 0, f"{model}: the falling block runs")
    falls = re.findall(r"dpmpm: warning: step \d+: time step .* s, below 10\^-1 of the first \(.*\); "
                       r"the fastest signal is at solid point id \d+ at x = .*: wave speed +(\S+) m/s, "
                       r"speed +(\S+) m/s, volume +(\S+) times its initial one", p.stderr)
    expect(len(falls) == 1, f"{model}: one warning when the step falls below a tenth of the first")
    if falls:
        c, v, vol = (float(s) for s in falls[0])
        expect(abs(c - 1.0) < 1e-3 and 9.0 <= v <= 10.0 and abs(vol - 1.0) < 1e-3,
               f"{model}: the warning gives wave speed 1 m/s, a speed of 9-10 m/s and volume 1")
    expect("10^-2" not in p.stderr, f"{model}: no second warning (the step fell by less than 100)")
    expect("max_dilation" not in p.stderr, f"{model}: max_dilation is not named (volume 1)")

# Rough walls of friction 0.45 or more under pore water warn that the wall holds the
# skeleton (doc/verification.md, "Larger friction: frictional flutter"); 0.44 does not,
# nor does a dry scene, whose wall lets go of nodes moving away from it.
for mu, water, warns in [(0.44, True, False), (0.45, True, True), (0.9, False, False)]:
    soil = ("&material id = 1, model = 'linear_elastic', youngs_modulus = 1.0e6, poisson_ratio = 0.3,\n"
            "  density = 2650.0, conductivity = 1.0e-4 /\n"
            "&material id = 2, model = 'fluid', density = 1000.0, bulk_modulus = 1.0e7 /\n"
            "&region lo = 0.2, 0.0, hi = 0.6, 0.2, phase = 'saturated', fluid_material = 2,\n"
            "  porosity = 0.4 /\n") if water else (
            "&material id = 1, model = 'linear_elastic', youngs_modulus = 1.0e6, poisson_ratio = 0.3,\n"
            "  density = 1000.0 /\n&region lo = 0.2, 0.0, hi = 0.6, 0.2 /\n")
    (work / "rough.nml").write_text(f"""&run name = 'rough', t_end = 1.0, max_steps = 2, gravity = 4.9, -8.5 /
&grid ndim = 2, ncells = 10, 5, length = 1.0, 0.5 /
&shape kernel = 'linear' /
{soil}&boundary face = 'y-', condition = 'roller', friction = {mu} /
&output dir = 'out' /
""")
    p, _ = run("rough.nml")
    named = "Larger friction: frictional flutter" in p.stderr
    what = f"friction {mu}, {'saturated' if water else 'dry'}: "
    expect(p.returncode == 0 and named == warns,
           what + ("warns of frictional flutter" if warns else "no flutter warning"))

# Gauss quadrature with a field weight that does not reach every place of a cell from the
# cell's Gauss points warns (one Gauss point in 2D: the corners lie 0.707 cells from it, and
# 0.5 cells along each axis for a box); a radius beyond that, and the tensor-product weight
# of natural support (radius 0), do not.
for radius, support, warns, far in [(0.65, "ball", True, "0.707"), (0.75, "ball", False, "0.707"),
                                    (0.0, "ball", False, "0.707"), (0.5, "box", True, "0.500"),
                                    (0.55, "box", False, "0.500")]:
    (work / "reach.nml").write_text(f"""&run name = 'reach', t_end = 1.0, max_steps = 2 /
&grid ndim = 2, ncells = 8, 8, length = 1.0, 1.0 /
&shape kernel = 'linear', quadrature = 'gauss', gauss_points = 1, field_kernel = 'linear',
  field_radius = {radius}, field_support = '{support}' /
&material id = 1, youngs_modulus = 1.0e6, poisson_ratio = 0.3, density = 1000.0 /
&region lo = 0.25, 0.25, hi = 0.75, 0.75 /
&output dir = 'out' /
""")
    p, _ = run("reach.nml")
    named = "does not reach every place of a cell" in p.stderr and far in p.stderr
    expect(p.returncode == 0 and named == warns,
           f"field_radius {radius} ({support}): " + ("warns that the weight misses the cell's corners"
                                                    if warns else "no reach warning"))

# --check prints every parameter as input that reads back to the same parameters, for
# every scene that ships with dpmpm.
inputs = pathlib.Path(__file__).resolve().parent.parent / "inputs"
for scene in sorted(inputs.glob("*.nml")):
    p, _ = run("--check", str(scene))
    echo = work / f"echo_{scene.stem}.nml"
    echo.write_text(p.stdout)
    expect(p.returncode == 0 and "&run" in p.stdout and "&benchmark" in p.stdout,
           f"--check {scene.name}: every group printed")
    again, _ = run("--check", str(echo))
    expect(again.returncode == 0 and again.stdout.splitlines()[1:] == p.stdout.splitlines()[1:],
           f"--check {scene.name}: the printed parameters read back to the same parameters")

print("PASS" if not failures else f"{len(failures)} check(s) failed")
sys.exit(1 if failures else 0)
