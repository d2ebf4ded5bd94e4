"""What the Python checks of whole runs share: dpmpm run on an input written into the
work directory (its exit code and output printed), the checks that failed, and the last
line with the exit status that ctest reads."""

import subprocess
import sys


class RunChecks:
    def __init__(self, mpiexec, dpmpm, ranks, work):
        self.mpiexec, self.dpmpm, self.ranks, self.work = mpiexec, dpmpm, str(ranks), work
        self.failures = []

    def run(self, name, text, *flags, tail=None):
        """Write text to work/name and run dpmpm on it (flags before the file name);
        print the exit code, the output (its last `tail` characters where given) and
        stderr."""
        (self.work / name).write_text(text)
        cmd = [self.dpmpm, *flags, name]
        # One rank runs the binary itself, as a plain `dpmpm file.nml` does (MPI as a
        # singleton): mpiexec holds a single process that ends with an error code 2 s.
        if self.ranks != "1":
            cmd = [self.mpiexec, "--oversubscribe", "-n", self.ranks] + cmd
        p = subprocess.run(cmd, cwd=self.work, capture_output=True, text=True, timeout=120)
        out = p.stdout if tail is None else p.stdout[-tail:]
        print(f"--- {' '.join([name, *flags])}: exit code {p.returncode}\n{out}{p.stderr}")
        return p

    def expect(self, cond, what):
        if not cond:
            self.failures.append(what)
            print("FAIL:", what)

    def finish(self):
        print("PASS" if not self.failures else f"{len(self.failures)} check(s) failed")
        sys.exit(1 if self.failures else 0)
