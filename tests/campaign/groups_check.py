"""campaign.rank_groups: cases run on rank groups (campaign.ranks_per_case = k) give the fields of
the same cases run on one rank each, and a failure seen by one rank of a group is recorded with
that rank's diagnostic while the other groups go on.

1. 2 ranks, k = 1 (the reference), then 2 ranks, k = 2 (one group of two), then 4 ranks, k = 2
   (two groups of two, oversubscribed), then 3 ranks, k = 2 (one group, rank 2 idle: said in the
   start line, no hang). Every case's fields file equals its 1-rank twin to TOL, and every
   ensemble equals a numpy recomputation from its per-case files (1e-12); the positions of each
   case's last snapshot (written collectively by the group) agree to TOL as well.
   TOL = 1e-9 (relative to max(1, |value|)): a decomposed run sums forces in another order, so
   its trajectories agree with the serial run's to round-off (< 1e-9 d_small over these 1,233
   steps, as in parallel.mpi2), and the fields are smooth functions of the positions (volume
   fractions per cell, mean angles) except when a particle sits within that distance of a cell
   boundary, which these runs do not meet (measured: 1e-15).
2. 4 ranks, k = 2, with TUMBLE_TEST_FAULT making one particle of one case leave the tumbler on
   rank 1 of its group only: that case fails (both attempts) with "rank 1 of 2: particle ... left
   the tumbler"; the three others are done and equal their twins; the whole run ends within the
   test's timeout.
3. A case on a group of 2 over its wall-clock limit (groups_time_limit.toml) fails as
   "time_limit" on both ranks at once: the campaign ends (no hang), exit 4.
4. jobs/slurm_array.sh with TUMBLE_RANKS_PER_CASE=2 on a 3-rank task (SLURM_NTASKS=3): the script
   says "1 group(s) of 2, 1 rank(s) idle", passes the group size on, and the slice's cases run on
   ranks 0-1 and equal their twins."""
import os
import shutil
import subprocess

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
ap.add_argument("--jobs", required=True, help="the repository's jobs/ directory")
a = ap.parse_args()
TOL = 1e-9


def run(out, ranks, k, env=None, want_rc=0):
    shutil.rmtree(out, ignore_errors=True)
    cmd = cc.mpiexec_command(a.mpiexec, a.np_flag, ranks) + [
        a.tumble, "campaign", a.campaign, "--output", out, "--ranks-per-case", str(k)]
    print(" ".join(cmd), flush=True)
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=120,
                           env=dict(os.environ, **(env or {})))
    except subprocess.TimeoutExpired:
        cc.fail("%s: no end within 120 s (a hang)" % out)
    with open(out + ".log", "w") as log:
        log.write(r.stdout + r.stderr)
    if r.returncode != want_rc:
        cc.fail("%s: exit %d, expected %d (see %s.log)" % (out, r.returncode, want_rc, out))
    return r.stdout


def fields_equal(case, ref, other):
    """Every dataset of the case's fields file in `other` against `ref`, and the positions of its
    last snapshot (written collectively by the group); returns the worst difference."""
    worst = 0.0
    for name, datasets in (("snap_000001.h5", ("x", "id", "species")),):
        with cc.h5py.File(os.path.join(ref, "cases", case, name), "r") as x, \
                cc.h5py.File(os.path.join(other, "cases", case, name), "r") as y:
            for d in datasets:
                ok, err = cc.close(y[d][()], x[d][()], TOL)
                if not ok:
                    cc.fail("%s: %s/%s in %s differs from the 1-rank run by %g" % (case, name, d, other, err))
                worst = max(worst, err)
    fa = cc.h5py.File(os.path.join(ref, "cases", case, "fields.h5"), "r")
    fb = cc.h5py.File(os.path.join(other, "cases", case, "fields.h5"), "r")
    names = []
    fa.visititems(lambda n, o: names.append(n) if isinstance(o, cc.h5py.Dataset) else None)
    for n in names:
        ok, err = cc.close(fb[n][()], fa[n][()], TOL)
        if not ok:
            cc.fail("%s: %s in %s differs from the 1-rank run by %g (> %g)" % (case, n, other, err, TOL))
        worst = max(worst, err)
    return worst


def groups_of(out):
    _, latest = cc.manifest(out)
    return {c: r.get("ranks", "") for c, r in latest.items()}


ref_out = run("groups_k1", 2, 1)
cc.running_within_groups("groups_k1", ref_out, 2)
done_ref, _, _ = cc.check_against_cases("groups_k1")
if len(done_ref) != 4:
    cc.fail("the 1-rank reference has %d cases done, not 4" % len(done_ref))
if set(groups_of("groups_k1").values()) != {"0", "1"}:
    cc.fail("k = 1 on 2 ranks: groups %s" % groups_of("groups_k1"))

worst = 0.0
for out, ranks, want_groups, layout in (
        ("groups_k2", 2, {"0-1"}, "groups of 2: 1 group)"),
        ("groups_4ranks_k2", 4, {"0-1", "2-3"}, "groups of 2: 2 groups)"),
        ("groups_3ranks_k2", 3, {"0-1"}, "groups of 2: 1 group, rank 2 idle")):
    text = run(out, ranks, 2)
    cc.running_within_groups(out, text, len(want_groups))
    if layout not in text:
        cc.fail("%s: the start line does not say '%s':\n%s" % (out, layout, text))
    done, failed, _ = cc.check_against_cases(out)
    if len(done) != 4 or failed:
        cc.fail("%s: %d done, %d failed" % (out, len(done), len(failed)))
    if set(groups_of(out).values()) != want_groups:
        cc.fail("%s: cases ran on %s, expected %s" % (out, groups_of(out), want_groups))
    for case in done:
        worst = max(worst, fields_equal(case, "groups_k1", out))
    print("%s: 4 cases on groups %s equal their 1-rank twins (worst %.3g)"
          % (out, sorted(want_groups), worst), flush=True)

victim = sorted(done_ref)[0]
text = run("groups_fault", 4, 2, {"TUMBLE_TEST_FAULT": "%s:1:1000" % victim}, want_rc=4)
_, latest = cc.manifest("groups_fault")
r = latest[victim]
if r["status"] != "failed" or r["failure"] != "run":
    cc.fail("the forced failure: %s" % r)
if "rank 1 of 2" not in r["diagnostic"] or "left the tumbler" not in r["diagnostic"]:
    cc.fail("the diagnostic does not come from rank 1: %s" % r["diagnostic"])
others = [c for c in latest if c != victim]
if len(others) != 3 or any(latest[c]["status"] != "done" for c in others):
    cc.fail("the other cases: %s" % {c: latest[c]["status"] for c in others})
for c in others:
    worst = max(worst, fields_equal(c, "groups_k1", "groups_fault"))
with cc.h5py.File(os.path.join("groups_fault", "ensemble.h5"), "r") as e:
    if e.attrs["n_members"] != 3 or e.attrs["n_failed"] != 1:
        cc.fail("fault ensemble: %d members, %d failed" % (e.attrs["n_members"], e.attrs["n_failed"]))
limit_file = os.path.join(os.path.dirname(a.campaign), "groups_time_limit.toml")
shutil.rmtree("groups_limit", ignore_errors=True)
cmd = cc.mpiexec_command(a.mpiexec, a.np_flag, 2) + [
    a.tumble, "campaign", limit_file, "--output", "groups_limit", "--ranks-per-case", "2"]
try:
    lim = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
except subprocess.TimeoutExpired:
    cc.fail("a time limit on a group of 2: no end within 120 s (a hang)")
_, latest = cc.manifest("groups_limit")
rec = list(latest.values())
if lim.returncode != 4 or len(rec) != 1 or rec[0]["failure"] != "time_limit" or rec[0]["ranks"] != "0-1":
    cc.fail("a time limit on a group of 2: exit %d, %s\n%s" % (lim.returncode, rec, lim.stderr))
print("time limit on ranks 0-1: %s" % rec[0]["diagnostic"][:80], flush=True)

shutil.rmtree("groups_slurm", ignore_errors=True)
launch = " ".join(cc.mpiexec_command(a.mpiexec, a.np_flag, 3))
env = dict(os.environ, TUMBLE=a.tumble, TUMBLE_LAUNCH=launch, SLURM_ARRAY_TASK_ID="1",
           SLURM_ARRAY_TASK_MIN="1", SLURM_ARRAY_TASK_MAX="2", SLURM_NTASKS="3",
           TUMBLE_RANKS_PER_CASE="2")
job = subprocess.run(["bash", os.path.join(a.jobs, "slurm_array.sh"), a.campaign, "--output",
                      "groups_slurm", "--quiet"], env=env, capture_output=True, text=True, timeout=120)
if job.returncode != 0 or "1 group(s) of 2, 1 rank(s) idle" not in job.stdout:
    cc.fail("slurm_array.sh with TUMBLE_RANKS_PER_CASE=2:\n%s%s" % (job.stdout, job.stderr))
_, latest = cc.manifest("groups_slurm")
if not latest or any(r["status"] != "done" or r["ranks"] != "0-1" for r in latest.values()):
    cc.fail("slurm slice with groups of 2: %s" % {c: (r["status"], r["ranks"]) for c, r in latest.items()})
for c in latest:
    worst = max(worst, fields_equal(c, "groups_k1", "groups_slurm"))
print("slurm_array.sh: slice 1/2 ran %d cases on ranks 0-1 of a 3-rank task" % len(latest))
print("OK: k = 2 on 2, 3 and 4 ranks equals k = 1 (worst relative difference %.3g, tolerance %g); "
      "a failure on rank 1 of a group was recorded as '%s...' after %d attempts, the other groups "
      "finished" % (worst, TOL, r["diagnostic"][:60], r["attempt"]))
