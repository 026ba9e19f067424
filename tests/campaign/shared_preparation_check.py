"""campaign.mpi2_shared_preparation: cases that share a bed and beta prepare them once.

The campaign of shared_preparation.toml (two points differing only in fidelity.bulk, 2 replicas,
2 ranks in groups of 1, empty bed cache, beta measured) starts its cases replica by replica:
dynamic 0 and rigid 0 first. Before, both settled replica 0's bed and measured its beta side by
side (every bed and beta made twice, hours each on a paper-scale bed). Checks: the case logs show
each replica's bed settled and saved once and its beta measured and saved once (2 of each, not
3 or 4), the campaign log shows a case started ahead of one that waits for another's
preparation, and all four cases end done."""
import glob
import os
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
