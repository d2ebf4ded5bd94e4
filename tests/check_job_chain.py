#!/usr/bin/env python3
"""scripts/job.slurm as a chain of jobs: each link continues the scene from the checkpoint
of the one before until it is done, and the output file equals a run without a break.

    check_job_chain.py <mpiexec> <dpmpm> <work dir>

Slurm is not needed: sbatch, srun and scancel are small stand-ins on PATH (sbatch records
its arguments and answers a job id, srun runs mpiexec on 2 ranks). The scene stops at
max_wall_time at its first look (every 10 steps) in each link, as a job stopped by
SIGTERM before its time limit, so 30 steps take several links. Each link must submit its
successor with afternotok on itself, end with exit code 3 while the scene goes on and 0
when it is done; the final file must hold the frames of the unbroken run, equal to the
last bit.
"""
import os
import pathlib
import shutil
import stat
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from frames_by_id import compare  # noqa: E402

mpiexec, dpmpm, work = sys.argv[1], os.path.abspath(sys.argv[2]), pathlib.Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
(work / "bin").mkdir(parents=True)
(work / "scripts").mkdir()
shutil.copy(HERE.parent / "scripts" / "job.slurm", work / "scripts" / "job.slurm")
failures = []


def expect(cond, what):
    print(("ok:   " if cond else "FAIL: ") + what, flush=True)
    if not cond:
        failures.append(what)


def stub(name, body):
    path = work / "bin" / name
    path.write_text("#!/bin/sh\n" + body)
    path.chmod(path.stat().st_mode | stat.S_IEXEC)


stub("sbatch", 'echo "$@" >> "$STUB_LOG"\nn=$(wc -l < "$STUB_LOG")\necho $((100 + n))\n')
stub("srun", f'exec "{mpiexec}" --oversubscribe -n 2 "$@"\n')
stub("scancel", 'echo "scancel $@" >> "$STUB_LOG"\n')

SCENE = """&run name = 'chain', t_end = 100.0, max_steps = 30, gravity = 0.0, -9.81
  {extra} /
&grid ndim = 2, ncells = 8, 8, length = 1.0, 1.0 /
&shape kernel = 'quadratic' /
&material id = 1, model = 'neo_hookean', youngs_modulus = 1.0e6, poisson_ratio = 0.3,
  density = 1000.0 /
&region lo = 0.25, 0.0, hi = 0.75, 0.5, placement = 'random' /
&boundary face = 'y-', condition = 'fixed' /
&output dir = 'out', frame_interval = 0.004 /
"""
(work / "chain.nml").write_text(SCENE.format(extra=", max_wall_time = 1.0e-3"))
(work / "whole.nml").write_text(SCENE.format(extra="").replace("'chain'", "'whole'"))
r = subprocess.run([mpiexec, "--oversubscribe", "-n", "2", dpmpm, "whole.nml"], cwd=work,
                   capture_output=True, text=True)
expect(r.returncode == 0, "the run without a break ends with exit code 0")

env = dict(os.environ, PATH=f"{work / 'bin'}:{os.environ['PATH']}", DPMPM=dpmpm,
           SLURM_SUBMIT_DIR=str(work), STUB_LOG=str(work / "sbatch.log"))
rc, link = 3, 0
while rc == 3 and link < 8:
    link += 1
    env.update(SLURM_JOB_ID=str(link), DPMPM_LINK=str(link))
    p = subprocess.run(["bash", "scripts/job.slurm", "chain.nml"], cwd=work, env=env,
                       capture_output=True, text=True)
    rc = p.returncode
    print(f"--- link {link}: exit code {rc}\n{p.stdout}{p.stderr}", flush=True)
    log = (work / "sbatch.log").read_text().splitlines()
    expect(len(log) == link and f"--dependency=afternotok:{link}" in log[-1]
           and f"DPMPM_LINK={link + 1}" in log[-1] and log[-1].endswith("chain.nml"),
           f"link {link} submits its successor after itself, with the same scene")
    if link > 1:
        expect("dpmpm: continuing out/chain.h5" in p.stdout,
               f"link {link} continues the output file")
expect(rc == 0, f"the chain ends with exit code 0 (link {link})")
expect(link >= 3, f"the scene took several links ({link})")
bad, worst = compare(str(work / "out" / "whole.h5"), str(work / "out" / "chain.h5"), 0.0)
expect(not bad, f"the chained file equals the unbroken one ({'; '.join(bad[:3])})")
print(f"{1 if not failures else 0} passed, {1 if failures else 0} failed")
sys.exit(1 if failures else 0)
