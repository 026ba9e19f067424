#!/usr/bin/env python3
"""cli.env_one_rank_mpi2: a bad environment variable or scene file on one rank only is refused
on all; bad input on every rank is said once.

mpirun passes its environment to every rank, but a wrapper or a batch system may not: here rank 1
alone has TUMBLE_PLAIN_KERNELS=yes (Open MPI's MPMD syntax, `-n 1 A : -n 1 env X=y A`). Before,
rank 1 refused alone and rank 0 waited for it in the run's first collective for ever (a hang with
no message: `tumble campaign` prints rank 0's errors only). Now every rank refuses with rank 1's
message. Checked for `tumble run` and `tumble campaign --status`: exit 2 within 60 s, rank 1's
message on the output, once.

`tumble run` also: a scene file rank 1 alone cannot read (its own arguments, MPMD) is refused on
both ranks, once, naming rank 1 (before: rank 0 went on to make the bed while rank 1 had left);
a bad key (both ranks) is said once, not once per rank. So are CLI11's refusals of the command line
(`--max-steps -5` on both ranks); an option rank 1 alone is given (`--bogus`) is refused on both,
naming rank 1 (before: rank 1 left alone and rank 0 made the bed and waited for ever).

Files read after the checks: a cached bed that rank 1's node lacks (its own bed cache) ends both
ranks, exit 2, naming fill.bed_cache and rank 1 (before: rank 0 waited for ever); a damaged bed file or checkpoint, read on
both ranks, is said once (before: once per rank). `tumble campaign` likewise for a
campaign file rank 1 cannot read (before: rank 1's message was lost, and rank 0 began the
campaign and waited for rank 1 for ever).

Files rank 0 writes for all: a checkpoint it cannot rename into place, a drift grid it cannot
rename end both ranks, exit 1, said once; an output folder under a file is refused before any
work, exit 2, said once (before: each a hang).

usage: env_one_rank_check.py TUMBLE MPIEXEC SCENE CAMPAIGN WORKDIR
"""
import os
import subprocess
import sys

tumble, mpiexec, scene, campaign, work = sys.argv[1:6]
os.makedirs(work, exist_ok=True)
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
failures = []
run = ["run", scene, "--max-steps", "5", "--set", "scene.output_dir=" + os.path.join(work, "run")]
missing = os.path.join(work, "no_such_scene.toml")
# (name, rank 0's command, rank 1's command, a text rank 0 must say once)
checks = (
    ("run env", [tumble] + run, ["env", "TUMBLE_PLAIN_KERNELS=yes", tumble] + run,
     "TUMBLE_PLAIN_KERNELS"),
    ("campaign", [tumble, "campaign", campaign, "-o", os.path.join(work, "campaign"), "--status"],
     ["env", "TUMBLE_PLAIN_KERNELS=yes", tumble, "campaign", campaign, "-o",
      os.path.join(work, "campaign"), "--status"], "TUMBLE_PLAIN_KERNELS"),
    ("run file", [tumble] + run, [tumble, "run", missing, "--max-steps", "5"],
     "cannot read scene file '%s' (on rank 1; 1 of the 2 ranks" % missing),
    ("camp file", [tumble, "campaign", campaign, "-o", os.path.join(work, "campaign"), "--list"],
     [tumble, "campaign", missing, "-o", os.path.join(work, "campaign"), "--list"],
     "cannot read campaign file '%s' (on rank 1; 1 of the 2 ranks" % missing),
    ("run key", [tumble] + run + ["--set", "bogus.key=1"],
     [tumble] + run + ["--set", "bogus.key=1"], "unknown key 'bogus.key'"),
    ("run opt", [tumble, "run", scene, "--max-steps", "-5"], [tumble, "run", scene, "--max-steps", "-5"],
     "--max-steps: must be >= 0"),
    ("opt one", [tumble] + run, [tumble] + run + ["--bogus"],
     "not expected: --bogus (on rank 1; 1 of the 2 ranks"),
    ("camp opt", [tumble, "campaign", campaign, "-o", os.path.join(work, "campaign"), "--list"],
     [tumble, "campaign", campaign, "-o", os.path.join(work, "campaign"), "--list", "--slice"],
     "--slice: 1 required TEXT missing (on rank 1; 1 of the 2 ranks"),
)
checks = [c + (2,) for c in checks]  # (the exit code each must end with: bad input)

# Files read after the checks: a bed cache on a node's own disk that lacks the bed rank 0 has
# (rank 0 decides the bed is cached; rank 1 cannot open it: before, rank 1 left alone and rank 0
# waited for ever), and a damaged bed file or checkpoint, read on both ranks (said twice before).
cached, empty = os.path.join(work, "beds_node0"), os.path.join(work, "beds_node1")
os.makedirs(empty, exist_ok=True)
made = subprocess.run([tumble] + run[:2] + ["--max-steps", "1", "--set", "fill.bed_cache=" + cached,
                                            "--set", "scene.output_dir=" + os.path.join(work, "bed")],
                      capture_output=True, text=True, env=env, stdin=subprocess.DEVNULL,
                      timeout=120)
if made.returncode != 0:
    print("could not make the cached bed: exit %d\n%s%s" % (made.returncode, made.stdout, made.stderr))
    sys.exit(1)
damaged = os.path.join(work, "damaged.h5")
with open(damaged, "w") as f:
    f.write("not an HDF5 file")
checks += [
    ("bed node", [tumble] + run + ["--set", "fill.bed_cache=" + cached],
     [tumble] + run + ["--set", "fill.bed_cache=" + empty],
     "is not the same directory on every rank: rank 0 has the settled bed", 2),
    ("bad bed", [tumble] + run + ["--set", "fill.bed_file=" + damaged],
     [tumble] + run + ["--set", "fill.bed_file=" + damaged], "the file is damaged", 2),
    ("bad ckpt", [tumble] + run + ["--restart", damaged], [tumble] + run + ["--restart", damaged],
     "the file is damaged", 3),
]
# Files rank 0 writes for all: its error is every rank's, said once, exit 1. A checkpoint that
# cannot be renamed into place (a directory in the way; before: rank 1 stepped on while rank 0,
# its error unsaid, waited for it for ever), a drift grid that cannot be renamed (before: a hang
# at the run's end). An output folder under a file is now bad input, refused before any work
# (exit 2; before: rank 1 waited at the barrier after rank 0 failed to make it, for ever).
blocked, blocked_drift = os.path.join(work, "blocked"), os.path.join(work, "blocked_drift")
os.makedirs(os.path.join(blocked, "checkpoint.h5", "in_the_way"), exist_ok=True)
os.makedirs(os.path.join(blocked_drift, "drift_grid.h5", "in_the_way"), exist_ok=True)
a_file = os.path.join(work, "a_file")
open(a_file, "w").close()
own_bed = ["--set", "fill.bed_cache=" + cached]
to = ["--set", "scene.output_dir=" + blocked]
checks += [
    ("ckpt dir", [tumble] + run + own_bed + to, [tumble] + run + own_bed + to, "cannot rename", 1),
    ("out file", [tumble] + run + own_bed + ["--set", "scene.output_dir=" + a_file + "/sub"],
     [tumble] + run + own_bed + ["--set", "scene.output_dir=" + a_file + "/sub"],
     "is a file, not a folder", 2),
    ("drift", [tumble] + run + own_bed + ["--set", "scene.output_dir=" + blocked_drift,
                                           "--set", "output.drift_grid=on"],
     [tumble] + run + own_bed + ["--set", "scene.output_dir=" + blocked_drift,
                                  "--set", "output.drift_grid=on"],
     "drift_grid.h5: Is a directory", 1),
]
for name, first, second, said, want_rc in checks:
    cmd = [mpiexec, "-n", "1"] + first + [":", "-n", "1"] + second
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=env,
                           stdin=subprocess.DEVNULL)
        rc, out = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        rc, out = None, "(killed after 60 s: a hang)"
    ok = rc == want_rc and out.count(said) == 1
    if said == "TUMBLE_PLAIN_KERNELS":
        ok = ok and "environment of rank 1" in out
    if name == "bed node":
        ok = ok and "(on rank 1; 1 of the 2 ranks" in out
    print("%-8s rc %s, said %d time(s): %s" % (name, rc, out.count(said), "ok" if ok else "FAIL"))
    if not ok:
        failures.append("%s: rc %s, expected '%s' once, output:\n%s"
                        % (" ".join(cmd), rc, said, out[-1500:]))
if failures:
    print("\n".join(failures))
    sys.exit(1)
