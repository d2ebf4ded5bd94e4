"""Finding dpmpm and mpirun (``dpmpm.simulate`` runs scenes with them), and the command
line of a script that runs one scene."""
import os
import shutil

#: Open MPI refuses to run as root without these (containers, CI).
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}

#: The checkout this package lies in (scripts/python/dpmpm/../../..).
ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))


def find_binary(binary=None, name="dpmpm"):
    """The dpmpm executable: binary when given, else $DPMPM_BIN, else ``dpmpm`` on the
    PATH, else build/release/dpmpm or build/debug/dpmpm of this checkout.
    FileNotFoundError names what was tried."""
    tried = []
    for cand in ([binary] if binary else []) + [os.environ.get("DPMPM_BIN")] + \
            [shutil.which(name)] + [os.path.join(ROOT, "build", b, name)
                                    for b in ("release", "debug")]:
        if cand:
            tried.append(cand)
            if os.path.isfile(cand) and os.access(cand, os.X_OK):
                return os.path.abspath(cand)
            if binary and cand == binary:
                raise FileNotFoundError(f"{binary}: no such executable")
    raise FileNotFoundError(f"no {name} executable found (tried {', '.join(tried) or 'PATH'});"
                            " build it (README.md) or pass binary= or set DPMPM_BIN")


def find_mpirun(mpirun=None):
    """The MPI launcher: mpirun when given, else $DPMPM_MPIEXEC, else mpirun or mpiexec
    on the PATH. FileNotFoundError when there is none."""
    for cand in (mpirun, os.environ.get("DPMPM_MPIEXEC"), "mpirun", "mpiexec"):
        if cand:
            found = shutil.which(cand)
            if found:
                return found
            if cand == mpirun:
                raise FileNotFoundError(f"{mpirun}: no such MPI launcher")
    raise FileNotFoundError("no mpirun or mpiexec on the PATH; pass mpirun= or set "
                            "DPMPM_MPIEXEC")


def scene_arguments(ap, end, workdir):
    """The options of a script that runs one scene (``dpmpm.simulate``): --bin, --ranks,
    --kernel, --t-end (replacing the scene's end time ``end``, in s), --workdir (default
    ``workdir``) and --rerun."""
    ap.add_argument("--bin", default="build/release/dpmpm")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--kernel", default="linear", help="grid functions (linear, quadratic, cubic)")
    ap.add_argument("--t-end", type=float, help=f"end time (s), replacing the scene's {end:g} s")
    ap.add_argument("--workdir", default=workdir)
    ap.add_argument("--rerun", action="store_true")
