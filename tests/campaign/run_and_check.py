"""campaign.mpi2_complete: the CI campaign on 2 ranks (1 rank per case), from scratch.

Checks: every case is done except the two made to fail; each failure is recorded with its kind
and diagnostic (a run-time failure and a time limit are retried once, same seed); the campaign
exits 4 (finished with failed cases) and says how to retry them; the ensemble excludes them and says so; the density-bidisperse point is there;
ensemble mean/variance/ci95 equal a recomputation from the per-case files to 1e-12."""
import os
import shutil
import subprocess

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
ap.add_argument("--out", required=True)
a = ap.parse_args()

shutil.rmtree(a.out, ignore_errors=True)
cmd = cc.mpiexec_command(a.mpiexec, a.np_flag, 2) + [a.tumble, "campaign", a.campaign, "--output", a.out]
print(" ".join(cmd), flush=True)
r = subprocess.run(cmd, capture_output=True, text=True)
print(r.stdout + r.stderr)
cc.running_within_groups(a.out, r.stdout, 2, expect_held=True)  # 8 cases on 2 groups: some held
if r.returncode != 4:
    cc.fail("campaign exited with %d, not 4 (finished with failed cases)" % r.returncode)
if "--retry-failed" not in r.stdout + r.stderr:
    cc.fail("the campaign does not say how to retry its failed cases")

done, failed, worst = cc.check_against_cases(a.out)
if len(done) != 6 or len(failed) != 2:
    cc.fail("expected 6 done and 2 failed cases, got %d and %d" % (len(done), len(failed)))
kinds = {r["failure"]: r for r in failed.values()}
if sorted(kinds) != ["run", "time_limit"]:
    cc.fail("failure kinds %s" % sorted(kinds))
if kinds["run"]["attempt"] != 2 or "did not settle" not in kinds["run"]["diagnostic"]:
    cc.fail("the run-time failure: %s" % kinds["run"])
if kinds["time_limit"]["attempt"] != 2 or "time limit" not in kinds["time_limit"]["diagnostic"]:
    cc.fail("the time limit: %s" % kinds["time_limit"])
lines, _ = cc.manifest(a.out)
for c, r in failed.items():
    seeds = {l["seed"] for l in lines if l["case"] == c}
    if len(seeds) != 1:
        cc.fail("case %s was retried with another seed: %s" % (c, seeds))
with cc.h5py.File(os.path.join(a.out, "ensemble.h5"), "r") as e:
    if e.attrs["n_failed"] != 2 or e.attrs["n_members"] != 6:
        cc.fail("ensemble root says %d members, %d failed" % (e.attrs["n_members"], e.attrs["n_failed"]))
    density = [p for p in e["points"].values() if p.attrs["size_ratio"] == 1 and p.attrs["R_rho"] == 3]
    if len(density) != 1 or density[0].attrs["n_members"] != 2:
        cc.fail("the density-bidisperse point (size_ratio 1, R_rho 3) is missing or incomplete")
    for p in e["points"].values():
        for line in cc.text(p.attrs["failed"]).split("\n"):
            if line and line.split(":")[0] not in failed:
                cc.fail("point lists %s as failed" % line)
print("OK: 6 cases done, 2 failed and excluded with diagnostics, exit 4; ensemble = recomputation "
      "(largest relative difference %.3g)" % worst)
