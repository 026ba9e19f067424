"""campaign.mpi2_cylinder: a 2-rank campaign of two replicas of a scaled-down Rapaport cylinder.

Checks: both cases done with different seeds; each case's fields.h5 holds exactly the S_a, S_r and
band-count series of its own run (results.h5, written by the engine) against revolutions; the
ensemble's mean/variance/CI equal a recomputation from the per-case files to 1e-12. Then the same
campaign with groups of 2 ranks (--ranks-per-case 2): each case's fields again hold its own run's
series, and the samples of the first 1,256 steps (0, 628, 1256) equal the 1-rank run's to 1e-9
(relative to max(1, |x|); band counts exactly). Later samples are not compared: this flow is
chaotic, and the round-off difference between a decomposed and a serial run (another order of
force sums) grows from 4e-14 d at step 200 to 7e-13 at 800, 2e-9 at 1,600 and 0.16 d at 3,200
(measured with `tumble run scenes/rapaport/mini/E.toml --max-steps N` on 1 and 2 ranks), so by
the last samples the two runs are different realizations of the same flow."""
import os
import shutil
import subprocess

import campaign_checks as cc
import numpy as np

ap = cc.campaign_arguments(__doc__)
ap.add_argument("--out", required=True)
a = ap.parse_args()

shutil.rmtree(a.out, ignore_errors=True)
cmd = cc.mpiexec_command(a.mpiexec, a.np_flag, 2) + [a.tumble, "campaign", a.campaign, "--output", a.out]
print(" ".join(cmd), flush=True)
if subprocess.run(cmd).returncode != 0:
    cc.fail("campaign failed")

done, failed, worst = cc.check_against_cases(a.out)
if len(done) != 2 or failed:
    cc.fail("expected 2 done cases and no failure, got %d and %d" % (len(done), len(failed)))
lines, _ = cc.manifest(a.out)
seeds = {l["seed"] for l in lines}
if len(seeds) != 2:
    cc.fail("the replicas ran with seeds %s (want two different ones)" % seeds)
for c, r in done.items():
    case = os.path.join(a.out, r["output"])
    with cc.h5py.File(os.path.join(case, "fields.h5"), "r") as f, \
            cc.h5py.File(os.path.join(case, "results.h5"), "r") as res:
        for mine, theirs in (("series/Sa", "cylinder/Sa"), ("series/Sr", "cylinder/Sr"),
                             ("series/bands", "cylinder/bands"),
                             ("series/iteration", "cylinder/revolutions")):
            x, y = f[mine][()], res[theirs][()]
            if not np.array_equal(x, y):
                cc.fail("case %s: %s differs from the run's %s" % (c, mine, theirs))
        # A sample every round(pi / 0.005) = 628 steps of 0.005 at Omega = 0.2, from step 0.
        rev = f["series/iteration"][()]
        want = np.arange(6) * 628 * 0.005 * 0.2 / (2 * np.pi)
        if len(rev) != 6 or np.max(np.abs(rev - want)) > 1e-12:
            cc.fail("case %s: samples at revolutions %s (want %s)" % (c, rev, want))
with cc.h5py.File(os.path.join(a.out, "ensemble.h5"), "r") as e:
    names = {n for p in e["points"].values() for n in cc.text(p.attrs["fields"]).split(",") if n}
    if names != {"series/Sa", "series/Sr", "series/bands"}:
        cc.fail("ensemble fields %s" % sorted(names))
grouped = a.out + "_k2"
shutil.rmtree(grouped, ignore_errors=True)
if subprocess.run(cmd[:-1] + [grouped, "--ranks-per-case", "2"]).returncode != 0:
    cc.fail("campaign with groups of 2 failed")
done2, failed2, _ = cc.check_against_cases(grouped)
if sorted(done2) != sorted(done) or failed2:
    cc.fail("groups of 2: done %s, failed %s" % (sorted(done2), sorted(failed2)))
group_worst = 0.0
EARLY = 3  # samples at steps 0, 628 and 1256
for c, r in done2.items():
    if r["ranks"] != "0-1":
        cc.fail("case %s ran on ranks %s" % (c, r["ranks"]))
    case = os.path.join(grouped, r["output"])
    with cc.h5py.File(os.path.join(case, "fields.h5"), "r") as f, \
            cc.h5py.File(os.path.join(case, "results.h5"), "r") as res, \
            cc.h5py.File(os.path.join(a.out, r["output"], "fields.h5"), "r") as g:
        for mine, theirs in (("series/Sa", "cylinder/Sa"), ("series/Sr", "cylinder/Sr"),
                             ("series/bands", "cylinder/bands")):
            if not np.array_equal(f[mine][()], res[theirs][()]):
                cc.fail("case %s on 2 ranks: %s differs from its run's %s" % (c, mine, theirs))
        if not np.array_equal(f["series/iteration"][()], g["series/iteration"][()]):
            cc.fail("case %s: samples at other revolutions on 2 ranks" % c)
        for name in ("series/Sa", "series/Sr"):
            ok, err = cc.close(f[name][:EARLY], g[name][:EARLY], 1e-9)
            group_worst = max(group_worst, err)
            if not ok:
                cc.fail("case %s: %s on 2 ranks differs from 1 rank by %g" % (c, name, err))
        if not np.array_equal(f["series/bands"][:EARLY], g["series/bands"][:EARLY]):
            cc.fail("case %s: band counts differ on 2 ranks" % c)
print("OK: 2 cylinder cases; fields = the runs' series; ensemble = recomputation "
      "(largest relative difference %.3g); on groups of 2 ranks the first %d samples agree to %.3g"
      % (worst, EARLY, group_worst))

# `tumble analyze campaign` maps the spherical tumbler's cases: a cylinder campaign is refused by
# name (exit 2), not read as a damaged file (it has no Lambert grid).
r = subprocess.run([a.tumble, "analyze", "campaign", a.out], capture_output=True, text=True)
if r.returncode != 2 or "tumbler.shape = cylinder" not in r.stderr:
    cc.fail("analyze campaign on the cylinder campaign: exit %d, expected 2 naming tumbler.shape:\n%s%s"
            % (r.returncode, r.stdout, r.stderr))
print("OK: analyze campaign refuses the cylinder campaign by name")
