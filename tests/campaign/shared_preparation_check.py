"""campaign.mpi2_shared_preparation: cases that share a bed and beta prepare them once.

The campaign of shared_preparation.toml (two points differing only in fidelity.bulk, 2 replicas,
2 ranks in groups of 1, empty bed cache, beta measured) starts its cases replica by replica:
dynamic 0 and rigid 0 first. Before, both settled replica 0's bed and measured its beta side by
side (every bed and beta made twice, hours each on a paper-scale bed). Checks: the case logs show
each replica's bed settled and saved once and its beta measured and saved once (2 of each, not
3 or 4), the campaign log shows a case started ahead of one that waits for another's
preparation, and all four cases end done.

Then the same campaign in groups of 2 ranks from a copy of that bed cache whose cached betas are
damaged (cut to 100 bytes): the group's leader reads the cache for the group and fails each case
("cannot be opened"); every case ends failed and the campaign exits 4 within 60 s. Before, the
leader's error was its own: the other rank of the group waited for its beta for ever (a hang).

Last, from an empty bed cache with a time limit of 2 s per attempt: every case fails on its time
limit "while settling the bed or measuring beta", each attempt within 6 s. Before, the limit was
checked from the protocol's first step only: each attempt prepared for ~15 s and then failed."""
import glob
import os
import re
import shutil

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
a = ap.parse_args()

out = "ci_shared_preparation"
shutil.rmtree(out, ignore_errors=True)
shutil.rmtree("beds_shared_preparation", ignore_errors=True)
run = cc.run_campaign_or_fail(a.mpiexec, a.np_flag, 2, a.tumble, a.campaign)
if run.stdout.count("[campaign] done: ") != 4:
    cc.fail("expected all four cases done")

logs = sorted(glob.glob(os.path.join(out, "cases", "*", "log.txt")))
if len(logs) != 4:
    cc.fail("expected 4 case logs, found %d" % len(logs))
beds = betas = 0
for path in logs:
    with open(path) as f:
        text = f.read()
    n_bed, n_beta = text.count("[fill] saved settled bed"), text.count("[repose] saved in")
    print("%s: bed settled %d, beta measured %d" % (path, n_bed, n_beta))
    beds += n_bed
    betas += n_beta
if beds != 2 or betas != 2:
    cc.fail("each replica's bed and beta should be made once: beds settled %d, betas measured %d "
            "(of 2 replicas)" % (beds, betas))
ahead = [l for l in run.stdout.splitlines() if "which waits for the settled bed or measured beta" in l]
if not ahead:
    cc.fail("no start line says a case went ahead of one waiting for another's preparation")
print("OK: 2 beds and 2 betas for 4 cases; %s" % ahead[0])


def variant(name, beds, out, extra=""):
    """shared_preparation.toml with its own bed cache and output (and `extra` campaign keys),
    written here as NAME.toml; run on 2 ranks in groups of 2, within 60 s (else the test fails:
    a hang). Returns (exit code, output)."""
    with open(a.campaign) as fh:
        toml = fh.read()
    scene = os.path.abspath(os.path.join(os.path.dirname(a.campaign), "../../scenes/bst_tiny.toml"))
    toml = re.sub(r'(?m)^scene = .*$', 'scene = "%s"' % scene, toml)
    toml = re.sub(r'(?m)^bed_cache = .*$', 'bed_cache = "%s"\n%s' % (beds, extra), toml)
    toml = re.sub(r'(?m)^output_dir = .*$', 'output_dir = "%s"' % out, toml)
    with open(name + ".toml", "w") as fh:
        fh.write(toml)
    shutil.rmtree(out, ignore_errors=True)
    cmd = cc.mpiexec_command(a.mpiexec, a.np_flag, 2) + [a.tumble, "campaign", name + ".toml",
                                                          "--ranks-per-case", "2", "--quiet"]
    return cc.run_or_fail_on_hang(cmd, 60, "%s in groups of 2 (the group's other rank waits "
                                  "for its leader)" % name)


# A damaged beta cache under groups of 2 ranks.
damaged, out2 = "beds_damaged_beta", "ci_damaged_beta"
shutil.rmtree(damaged, ignore_errors=True)
shutil.copytree("beds_shared_preparation", damaged)
cut = glob.glob(os.path.join(damaged, "repose_*.h5"))
if len(cut) != 2:
    cc.fail("want the 2 cached betas to damage, found %s" % cut)
for f in cut:
    os.truncate(f, 100)
rc, text = variant("damaged_beta", damaged, out2)
_, latest = cc.manifest(out2)
failed = [r for r in latest.values() if r["status"] == "failed" and "cannot be opened" in
          r.get("diagnostic", "")]
if rc != 4 or len(failed) != 4:
    cc.fail("damaged cached betas: exit %d (want 4), %d of 4 cases failed naming the file"
            % (rc, len(failed)))
print("OK: damaged cached betas in groups of 2: every case failed naming the file, exit 4, no hang")

# The time limit holds while a case prepares: an empty bed cache (about 15 s to settle the bed and
# measure beta) and a limit of 2 s per attempt.
empty, out3 = "beds_time_limit", "ci_time_limit_preparation"
shutil.rmtree(empty, ignore_errors=True)
rc, text = variant("time_limit_preparation", empty, out3, "time_limit = 2\nmax_attempts = 1")
_, latest = cc.manifest(out3)
over = [r for r in latest.values() if r["status"] == "failed" and r["failure"] == "time_limit"
        and "while settling the bed or measuring beta" in r.get("diagnostic", "")]
slow = [r["wall"] for r in latest.values() if r.get("wall", 0) > 6]
if rc != 4 or len(over) != 4 or slow:
    cc.fail("a 2 s limit while preparing: exit %d (want 4), %d of 4 cases failed on it while "
            "preparing, attempts longer than 6 s: %s" % (rc, len(over), slow))
print("OK: a 2 s time limit ends each attempt while it prepares (walls %s s)"
      % ", ".join("%.1f" % r["wall"] for r in latest.values()))
