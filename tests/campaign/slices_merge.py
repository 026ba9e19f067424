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
import subprocess

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


def slurm(task):
    env = dict(base_env, SLURM_ARRAY_TASK_ID=str(task), SLURM_ARRAY_TASK_MIN="1",
               SLURM_ARRAY_TASK_MAX="3", SLURM_ARRAY_TASK_COUNT="3", SLURM_ARRAY_JOB_ID="4242")
    return subprocess.run(["bash", os.path.join(a.jobs, "slurm_array.sh"), a.campaign,
                           "--output", out, "--quiet"], env=env, capture_output=True, text=True)


def pbs(index):
    env = dict(base_env, PBS_ARRAY_INDEX=str(index), TUMBLE_SLICES="3", CAMPAIGN=a.campaign,
               TUMBLE_ARGS="--output %s --quiet" % out)
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

r = subprocess.run([a.tumble, "merge", out], capture_output=True, text=True)
print(r.stdout.strip())
if r.returncode != 0:
    cc.fail("tumble merge exited with %d: %s" % (r.returncode, r.stderr))
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
