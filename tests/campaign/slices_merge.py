"""campaign.job_array_slices_merge: the CI campaign as a job array of 3 slices, then `tumble merge`.

Slices 1 and 2 run through jobs/slurm_array.sh and slice 3 through jobs/pbs_array.sh, with the
array variables set by hand (SLURM_ARRAY_TASK_ID, PBS_ARRAY_INDEX) and a 1-rank mpiexec as the
launcher. Re-running a finished slice through either script must skip it without touching the
manifest. The merged ensemble.h5 must equal the one of the single 2-rank run (fixture
campaign.mpi2_complete): same points, members, exclusions and counts, statistics to 1e-12 (Chan's
merge of the slices adds round-off only), and every case's fields identical bit for bit."""
import glob
import os
import shutil
import signal
import subprocess
import time

import h5py
import numpy as np

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
ap.add_argument("--jobs", required=True, help="the repository's jobs/ directory")
ap.add_argument("--full", required=True, help="output of the single run (fixture)")
a = ap.parse_args()

out = "ci_sliced"
shutil.rmtree(out, ignore_errors=True)
launch = " ".join(cc.mpiexec_command(a.mpiexec, a.np_flag, 1))
base_env = dict(os.environ, TUMBLE=a.tumble, TUMBLE_LAUNCH=launch)


def slurm(task, low=1, high=3, **extra):
    env = dict(base_env, SLURM_ARRAY_TASK_ID=str(task), SLURM_ARRAY_TASK_MIN=str(low),
               SLURM_ARRAY_TASK_MAX=str(high), SLURM_ARRAY_TASK_COUNT=str(high - low + 1),
               SLURM_ARRAY_JOB_ID="4242", **extra)
    return subprocess.run(["bash", os.path.join(a.jobs, "slurm_array.sh"), a.campaign,
                           "--output", out, "--quiet"], env=env, capture_output=True, text=True)


def pbs(index, **extra):
    env = dict(base_env, PBS_ARRAY_INDEX=str(index), TUMBLE_SLICES="3", CAMPAIGN=a.campaign,
               TUMBLE_ARGS="--output %s --quiet" % out)
    env.update(extra)
    env.pop("PBS_O_WORKDIR", None)
    return subprocess.run(["bash", os.path.join(a.jobs, "pbs_array.sh")], env=env,
                          capture_output=True, text=True)


def manifest_lines():
    return sum(len(open(f).readlines()) for f in glob.glob(os.path.join(out, "manifest", "*.jsonl")))


for name, r in (("slurm task 1", slurm(1)), ("slurm task 2", slurm(2)), ("pbs index 3", pbs(3))):
    print(r.stdout.strip().splitlines()[0])
    failed_here = "failed or have no result" in r.stdout
    if r.returncode != (4 if failed_here else 0):  # 4: the slice finished with failed cases
        cc.fail("%s exited with %d:\n%s%s" % (name, r.returncode, r.stdout, r.stderr))
    if "-> slice" not in r.stdout or "finished slice" not in r.stdout:
        cc.fail("%s did not run its slice:\n%s" % (name, r.stdout))
for i in (1, 2, 3):
    if not os.path.exists(os.path.join(out, "partials", "slice_%d_of_3.h5" % i)):
        cc.fail("no partial result of slice %d" % i)

before = manifest_lines()
for name, r in (("slurm task 1 again", slurm(1)), ("pbs index 2 again", pbs(2))):
    if r.returncode != 0 or "nothing to run; skipping" not in r.stdout:
        cc.fail("%s did not skip its finished slice:\n%s%s" % (name, r.stdout, r.stderr))
if manifest_lines() != before:
    cc.fail("re-running finished slices wrote to the manifest")
print("finished slices skipped by both scripts")

# A resubmitted subset (--array=2): N cannot be read from it (it gave slice 2/2, another slicing).
r = slurm(2, low=2, high=2)
if r.returncode != 2 or "export TUMBLE_SLICES=N" not in r.stderr:
    cc.fail("slurm --array=2 without TUMBLE_SLICES: exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
r = slurm(1, low=1, high=1, TUMBLE_SLICES="3", TUMBLE_FIRST_INDEX="0")  # task 1 of 0-2: slice 2
if r.returncode != 0 or "-> slice 2/3" not in r.stdout or "nothing to run; skipping" not in r.stdout:
    cc.fail("slurm --array=1 of an array 0-2: exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
if manifest_lines() != before:
    cc.fail("the resubmitted subset wrote to the manifest")
print("a resubmitted subset: refused without TUMBLE_SLICES, mapped with TUMBLE_FIRST_INDEX")

# PBS: TUMBLE_FIRST_INDEX=abc went into $((...)) and counted as 0 (slice i+1); TUMBLE_ARGS was
# globbed (a '*' became the names of the files here). TUMBLE=echo shows the options passed.
r = pbs(1, TUMBLE_FIRST_INDEX="abc")
if r.returncode != 2 or "TUMBLE_FIRST_INDEX='abc' must be 0 or 1" not in r.stderr:
    cc.fail("pbs TUMBLE_FIRST_INDEX=abc: exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
open("scene.name=matched", "w").close()  # (what the old script's glob turned the '*' into)
r = pbs(1, TUMBLE="/bin/echo", TUMBLE_ARGS="--set scene.name=* --output %s" % out)
if r.returncode != 0 or "--set scene.name=* --output" not in r.stdout:
    cc.fail("pbs TUMBLE_ARGS with '*': exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
print("pbs: TUMBLE_FIRST_INDEX checked, TUMBLE_ARGS not globbed")

# PBS gives no warning before its walltime: pbs_array.sh reads it from qstat and sends the stop
# request (SIGUSR1) TUMBLE_STOP_MARGIN seconds before it. A fake qstat (walltime 3 s, margin 1 s)
# and a fake tumble that exits 10 on SIGUSR1, as the campaign does: stopped after ~2 s, exit 10.
fake = os.path.abspath("fake_pbs")
os.makedirs(fake, exist_ok=True)
for name, text in (("qstat", "#!/bin/sh\necho '    Resource_List.walltime = 00:00:03'\n"),
                   ("tumble", "#!/bin/bash\nfor x in \"$@\"; do [ \"$x\" = --status ] && exit 10; done\n"
                              "trap 'echo fake: SIGUSR1; kill $s; exit 10' USR1\n"
                              "sleep 60 & s=$!\n"
                              "[ -z \"$FAKE_READY\" ] || : > \"$FAKE_READY\"\n"
                              "wait $s\necho fake: not stopped\n")):
    with open(os.path.join(fake, name), "w") as f:
        f.write(text)
    os.chmod(os.path.join(fake, name), 0o755)
t0 = time.time()
r = pbs(1, TUMBLE=os.path.join(fake, "tumble"), TUMBLE_LAUNCH="env", PBS_JOBID="7.server",
        TUMBLE_STOP_MARGIN="1", PATH=fake + os.pathsep + os.environ["PATH"])
wall = time.time() - t0
if r.returncode != 10 or "fake: SIGUSR1" not in r.stdout or not 1.5 < wall < 30:
    cc.fail("pbs stop before the walltime: exit %d after %.1f s\n%s%s"
            % (r.returncode, wall, r.stdout, r.stderr))
print("pbs: the stop request %.1f s into a 3 s walltime (margin 1 s), exit 10" % wall)

# With the timer on, the script is the job's top process: a stop request sent to it (Torque's
# qsig signals that process) reaches the campaign. Before, it ended the script alone and left the
# campaign and the timer running. The request is sent once the fake campaign says it has set its
# trap (FAKE_READY): a fixed wait raced with the start of the script and the fake on a busy machine.
# FAKE_READY comes after the fake's sleep has started: written before it, a request in between
# left the sleep (and the pipe it holds) running for 60 s after the fake had exited 10.
ready = os.path.abspath("fake_ready")
if os.path.exists(ready):
    os.remove(ready)
env = dict(base_env, PBS_ARRAY_INDEX="1", TUMBLE_SLICES="3", CAMPAIGN=a.campaign,
           TUMBLE=os.path.join(fake, "tumble"), TUMBLE_LAUNCH="env", TUMBLE_STOP_AFTER="100",
           FAKE_READY=ready)
p = subprocess.Popen(["bash", os.path.join(a.jobs, "pbs_array.sh")], env=env,
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
t0 = time.time()
while not os.path.exists(ready) and p.poll() is None and time.time() - t0 < 30:
    time.sleep(0.05)
if not os.path.exists(ready):
    p.kill()
    cc.fail("pbs: the fake campaign did not start within 30 s: exit %s\n%s%s"
            % (p.returncode, *p.communicate()))
p.send_signal(signal.SIGUSR1)
try:
    stdout, stderr = p.communicate(timeout=30)
except subprocess.TimeoutExpired:
    p.kill()
    cc.fail("pbs: SIGUSR1 to the script did not end the campaign")
if p.returncode != 10 or "fake: SIGUSR1" not in stdout:
    cc.fail("pbs: SIGUSR1 to the script: exit %d\n%s%s" % (p.returncode, stdout, stderr))
print("pbs: a stop request sent to the script reaches the campaign (exit 10)")

# A spooled copy of the script (what Slurm runs), submitted from outside the repository: it finds
# its helper through TUMBLE_JOBS, and without it says so (before: "No such file", exit 1).
spool = os.path.abspath("spool")
os.makedirs(spool, exist_ok=True)
shutil.copy(os.path.join(a.jobs, "slurm_array.sh"), os.path.join(spool, "slurm_script"))
for jobs_var, want in ((None, 2), (os.path.abspath(a.jobs), 0)):
    env = dict(base_env, SLURM_ARRAY_TASK_ID="1", SLURM_ARRAY_TASK_MIN="1",
               SLURM_ARRAY_TASK_MAX="3", SLURM_SUBMIT_DIR=spool)
    if jobs_var:
        env["TUMBLE_JOBS"] = jobs_var
    r = subprocess.run(["bash", os.path.join(spool, "slurm_script"), a.campaign, "--output", out,
                        "--quiet"], env=env, capture_output=True, text=True)
    said = "nothing to run; skipping" in r.stdout if want == 0 else "TUMBLE_JOBS" in r.stderr
    if r.returncode != want or not said:
        cc.fail("spooled script, TUMBLE_JOBS=%s: exit %d\n%s%s" % (jobs_var, r.returncode, r.stdout,
                                                                  r.stderr))
print("a spooled copy finds its helper through TUMBLE_JOBS")

r = subprocess.run([a.tumble, "merge", out], capture_output=True, text=True)
print(r.stdout.strip())
# (the CI campaign's two failing cases are excluded: exit 4, as the campaign's own run)
if r.returncode != 4 or "exit code 4" not in r.stdout:
    cc.fail("tumble merge exited with %d (want 4: two cases failed): %s" % (r.returncode, r.stderr))
worst = cc.compare_ensembles(os.path.join(out, "ensemble.h5"), os.path.join(a.full, "ensemble.h5"),
                             1e-12)
_, latest = cc.manifest(out)
for c, rec in latest.items():
    if rec["status"] != "done":
        continue
    with h5py.File(os.path.join(out, rec["output"], "fields.h5"), "r") as x, \
            h5py.File(os.path.join(a.full, rec["output"], "fields.h5"), "r") as y:
        def same(name, obj):
            if isinstance(obj, h5py.Dataset) and not np.array_equal(obj[()], y[name][()], equal_nan=True):
                cc.fail("case %s: %s differs from the single run" % (c, name))
        x.visititems(same)
print("OK: 3 slices merged = single run (largest relative difference %.3g; case fields bitwise "
      "equal)" % worst)

# --- the merged statistics as the job scripts and `--status` read them -------------------------
def campaign(*args, out_dir=out):
    return subprocess.run([a.tumble, "campaign", a.campaign, "--output", out_dir] + list(args),
                          capture_output=True, text=True)


def copy_of_out(suffix):
    """A fresh copy of the merged campaign directory, to damage."""
    d = out + suffix
    shutil.rmtree(d, ignore_errors=True)
    shutil.copytree(out, d)
    return d


def cases_in(path):
    """Case ids a statistics file accounts for: members, excluded (failed) and without result."""
    ids = set()
    with h5py.File(path, "r") as f:
        for g in f["points"].values():
            for key in ("members", "missing"):
                ids.update(x for x in cc.text(g.attrs[key]).split(",") if x)
            ids.update(x.split(":")[0] for x in cc.text(g.attrs["failed"]).split("\n") if x)
    return ids


# The whole campaign's status after a sliced run and its merge: done, its statistics (the merged
# ensemble.h5) current. Before, it said "statistics not written", and following that advice wrote
# a 1/1 partial beside the 3 slices', which `tumble merge` then refused.
r = campaign("--status")
if r.returncode != 0 or "statistics" in r.stdout:
    cc.fail("--status of the whole campaign after the merge: exit %d\n%s%s"
            % (r.returncode, r.stdout, r.stderr))
print("whole-campaign --status after the merge: 0")

# A stale partial (here slice 1's file in slice 2's place, as a partial written before the
# campaign grew and dealt its cases anew would be): --status must not call slice 2 done (the job
# scripts would skip it for ever), and the merge must name both files holding a case.
stale = copy_of_out("_stale")
shutil.copy(os.path.join(stale, "partials", "slice_1_of_3.h5"),
            os.path.join(stale, "partials", "slice_2_of_3.h5"))
r = campaign("--slice", "2/3", "--status", out_dir=stale)
if r.returncode != 10 or "not this slice's current result" not in r.stdout:
    cc.fail("--status of a slice whose partial is another's: exit %d\n%s%s"
            % (r.returncode, r.stdout, r.stderr))
r = subprocess.run([a.tumble, "merge", stale], capture_output=True, text=True)
if r.returncode != 2 or "slice_1_of_3.h5" not in r.stderr or "slice_2_of_3.h5" not in r.stderr:
    cc.fail("merge of a stale partial: exit %d, want 2 naming both files\n%s%s"
            % (r.returncode, r.stdout, r.stderr))
# A damaged partial is no result either.
with open(os.path.join(stale, "partials", "slice_2_of_3.h5"), "r+b") as f:
    f.truncate(5000)
r = campaign("--slice", "2/3", "--status", out_dir=stale)
if r.returncode != 10 or "does not read" not in r.stdout:
    cc.fail("--status of a slice whose partial is truncated: exit %d\n%s%s"
            % (r.returncode, r.stdout, r.stderr))
print("a stale or damaged partial: --status 10, merge names both files")

# A slice with no partial: its cases are counted without result, in their points (before, the
# merged file had n_missing = 0 and a point only that slice held had no row at all).
gone = copy_of_out("_missing")
third = cases_in(os.path.join(gone, "partials", "slice_3_of_3.h5"))
os.remove(os.path.join(gone, "partials", "slice_3_of_3.h5"))
r = subprocess.run([a.tumble, "merge", gone], capture_output=True, text=True)
print(r.stdout.strip())
if r.returncode != 10:
    cc.fail("merge without slice 3: exit %d, want 10\n%s%s" % (r.returncode, r.stdout, r.stderr))
with h5py.File(os.path.join(gone, "ensemble.h5"), "r") as f, \
        h5py.File(os.path.join(out, "ensemble.h5"), "r") as full:
    if sorted(f["points"]) != sorted(full["points"]):
        cc.fail("merge without slice 3: points %s, want %s" % (sorted(f["points"]),
                                                              sorted(full["points"])))
    missing = set()
    for g in f["points"].values():
        ids = [x for x in cc.text(g.attrs["missing"]).split(",") if x]
        if len(ids) != int(g.attrs["n_missing"]):
            cc.fail("n_missing disagrees with the missing list")
        missing.update(ids)
if missing != third:
    cc.fail("merge without slice 3: without result %s, want slice 3's cases %s"
            % (sorted(missing), sorted(third)))
print("OK: a slice not merged counts its %d cases without result, in their points" % len(third))
