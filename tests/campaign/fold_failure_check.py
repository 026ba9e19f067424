"""campaign.mpi2_fold_failure: rank 0 fails to write the statistics of a 2-rank campaign.

Rank 0 folds the statistics while the other ranks wait for its verdict. Before, its error (here:
ensemble.h5 cannot be replaced, being a non-empty directory) was thrown on rank 0 alone and rank 1
waited for ever (the job hung until killed). Now:
1. a copy of the finished CI campaign (ci_full), rerun with ensemble.h5 made a directory, exits 1
   within the timeout on every rank, says "cannot rename" once, and leaves no temporary file;
2. the directory removed, the same rerun exits 4 (the CI campaign's failed cases) and its
   ensemble.h5 holds the same tables as ci_full's, and partials/slice_1_of_1.h5 the same bytes as
   its ensemble.h5;
3. the statistics removed, --status exits 10 ("statistics not written"), the rerun writes them and
   --status exits 0."""
import filecmp
import glob
import os
import shutil
import subprocess

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
ap.add_argument("--full", required=True, help="the finished CI campaign's directory")
a = ap.parse_args()

out = "fold_failure"
shutil.rmtree(out, ignore_errors=True)
shutil.copytree(a.full, out)
ensemble = os.path.join(out, "ensemble.h5")
os.remove(ensemble)
os.makedirs(os.path.join(ensemble, "in_the_way"))
cmd = cc.mpiexec_command(a.mpiexec, a.np_flag, 2) + [a.tumble, "campaign", a.campaign, "--output",
                                                      out, "--quiet"]
rc, text = cc.run_or_fail_on_hang(cmd, 60, "the campaign whose statistics cannot be written (a "
                                  "rank waits for rank 0, which has left)")
said = text.count("cannot rename")
if rc != 1 or said != 1:
    cc.fail("statistics that cannot be written: exit %d (want 1), said %d times (want once)"
            % (rc, said))
left = glob.glob(os.path.join(out, "*.tmp.*")) + glob.glob(os.path.join(out, "*", "*.tmp.*"))
if left:
    cc.fail("temporary files left behind: %s" % left)

shutil.rmtree(ensemble)
r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
if r.returncode != 4:
    cc.fail("the rerun exited %d, not 4:\n%s" % (r.returncode, r.stdout + r.stderr))
tables = cc.same_tables(ensemble, os.path.join(a.full, "ensemble.h5"))
if not filecmp.cmp(ensemble, os.path.join(out, "partials", "slice_1_of_1.h5"), shallow=False):
    cc.fail("partials/slice_1_of_1.h5 is not a copy of ensemble.h5")

# 3. Every case finished but no statistics (an invocation stopped or killed after its last case):
# --status says so and exits 10 (the job-array scripts skip a slice whose status is 0, so it was
# never folded); the rerun writes them, and --status is 0 again.
partial = os.path.join(out, "partials", "slice_1_of_1.h5")
os.remove(partial)
os.remove(ensemble)
status = [a.tumble, "campaign", a.campaign, "--output", out, "--status"]
r = subprocess.run(status, capture_output=True, text=True, timeout=60)
if r.returncode != 10 or "statistics not written" not in r.stdout:
    cc.fail("--status of finished cases without statistics: exit %d (want 10):\n%s"
            % (r.returncode, r.stdout + r.stderr))
r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
r2 = subprocess.run(status, capture_output=True, text=True, timeout=60)
if r.returncode != 4 or not os.path.exists(partial) or r2.returncode != 0:
    cc.fail("the rerun: exit %d (want 4), partial %s, then --status exit %d (want 0)"
            % (r.returncode, os.path.exists(partial), r2.returncode))
print("OK: the fold's error ended both ranks in exit 1, said once, no temporary left; the rerun "
      "wrote the same %d tables as the uninterrupted campaign; finished cases without statistics: "
      "--status 10, the rerun writes them" % tables)
