"""Running a scene from a script: ``run_scene`` writes the namelist text into a work
directory and runs dpmpm on it with mpirun (the Open MPI settings for root included),
unless its output is there already."""
import os
import subprocess

#: Open MPI refuses to run as root without these (containers, CI).
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}


def run_scene(binary, text, workdir, name, ranks=1, rerun=False):
    """Writes ``text`` to ``workdir/name.nml`` and, when ``workdir/name.h5`` is missing or
    ``rerun`` is set, runs ``binary`` on it on ``ranks`` ranks with its log in
    ``workdir/name.log`` (a failed run raises ``subprocess.CalledProcessError``). The
    scene's &output dir must be ``workdir``. Returns the path of the output file."""
    os.makedirs(workdir, exist_ok=True)
    nml = os.path.join(workdir, name + ".nml")
    h5 = os.path.join(workdir, name + ".h5")
    with open(nml, "w") as f:
        f.write(text)
    if rerun or not os.path.exists(h5):
        cmd = ["mpirun", "--oversubscribe", "-n", str(ranks), binary, nml]
        with open(os.path.join(workdir, name + ".log"), "w") as log:
            subprocess.run(cmd, check=True, stdout=log, stderr=subprocess.STDOUT,
                           env=dict(os.environ, **MPI_ENV))
    return h5


def scene_arguments(ap, end, workdir):
    """The options of a script that runs one scene (``run_scene``): --bin, --ranks,
    --kernel, --t-end (replacing the scene's end time ``end``, in s), --workdir (default
    ``workdir``) and --rerun."""
    ap.add_argument("--bin", default="build/release/dpmpm")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--kernel", default="linear", help="grid functions (linear, quadratic, cubic)")
    ap.add_argument("--t-end", type=float, help=f"end time (s), replacing the scene's {end:g} s")
    ap.add_argument("--workdir", default=workdir)
    ap.add_argument("--rerun", action="store_true")
