#!/usr/bin/env python3
"""cli.env_one_rank_mpi2: a bad environment variable on one rank only is refused on all.

mpirun passes its environment to every rank, but a wrapper or a batch system may not: here rank 1
alone has TUMBLE_PLAIN_KERNELS=yes (Open MPI's MPMD syntax, `-n 1 A : -n 1 env X=y A`). Before,
rank 1 refused alone and rank 0 waited for it in the run's first collective for ever (a hang with
no message: `tumble campaign` prints rank 0's errors only). Now every rank refuses with rank 1's
message. Checked for `tumble run` and `tumble campaign --status`: exit 2 within 60 s, rank 1's
message on the output.

usage: env_one_rank_check.py TUMBLE MPIEXEC SCENE CAMPAIGN WORKDIR
"""
import os
import subprocess
import sys

tumble, mpiexec, scene, campaign, work = sys.argv[1:6]
os.makedirs(work, exist_ok=True)
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
failures = []
for name, args in (("run", ["run", scene, "--max-steps", "5", "--set",
                            "scene.output_dir=" + os.path.join(work, "run")]),
                   ("campaign", ["campaign", campaign, "-o", os.path.join(work, "campaign"),
                                 "--status"])):
    cmd = [mpiexec, "-n", "1", tumble] + args + [":", "-n", "1", "env",
                                                 "TUMBLE_PLAIN_KERNELS=yes", tumble] + args
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=env,
                           stdin=subprocess.DEVNULL)
        rc, out = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        rc, out = None, "(killed after 60 s: a hang)"
    ok = rc == 2 and "TUMBLE_PLAIN_KERNELS" in out and "environment of rank 1" in out
    print("%-8s rc %s %s" % (name, rc, "ok" if ok else "FAIL"))
    if not ok:
        failures.append("%s: rc %s, output:\n%s" % (" ".join(cmd), rc, out[-1500:]))
if failures:
    print("\n".join(failures))
    sys.exit(1)
