"""Exceptions of runs and scenes, one per exit code of dpmpm (dpmpm --help):
2 InputError, 3 StoppedEarly, 4 MonitorStop, anything else RunError."""


class RunError(Exception):
    """A dpmpm run that did not finish. ``status``: its exit code; ``lines``: what the log
    says about it; ``log``: the log file; ``scene``: the Scene; ``output``: its file."""

    def __init__(self, lines, status=1, log=None, scene=None, output=None, where=""):
        self.lines = list(lines)
        self.status = status
        self.log = log
        self.scene = scene
        self.output = output
        head = f"{where}: " if where else ""
        tail = f" (log {log})" if log else ""
        super().__init__(f"{head}exit code {status}: " + " / ".join(self.lines) + tail
                         if status is not None else head + "; ".join(self.lines))


class InputError(RunError):
    """dpmpm refused the scene or the command line (exit code 2); ``problems`` lists the
    messages, without their ``dpmpm: input error: FILE:`` prefix."""

    def __init__(self, problems, status=2, **kw):
        self.problems = list(problems)
        super().__init__(self.problems or ["bad input"], status, **kw)


class StoppedEarly(RunError):
    """The run stopped early with a checkpoint (exit code 3: a stop signal or &run
    max_wall_time); ``checkpoint`` is its file. Continue with ``restart=True``."""

    def __init__(self, lines, status=3, checkpoint=None, **kw):
        self.checkpoint = checkpoint
        super().__init__(lines, status, **kw)


class MonitorStop(RunError):
    """The run monitor stopped the run (exit code 4): it grew or a value became
    non-finite. The last frame before is in the output; do not continue it as it is."""
