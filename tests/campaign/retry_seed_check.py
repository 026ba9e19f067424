"""campaign.retry_seed_new_after_stop: a retry with a new seed never goes on from the failed
attempt's checkpoint.

With retry_seed = "new", attempt 2 of a case runs under another seed, from its own bed. A retry
handed out and then stopped (SIGUSR1) or killed before it began is recorded "stopped" ("not
begun") or left "running", and the rerun continues that same attempt from the case's checkpoint;
the only checkpoint there was attempt 1's. Before, the rerun went on from it (attempt 1's bed and
steps) and recorded the result as attempt 2's, with attempt 2's seed. Here: attempt 1 fails at
step 1000 (test hook) with a checkpoint at step 900; a "stopped, not begun" line of attempt 2 is
appended to the manifest (what such a stop writes); the rerun must start afresh: its log says the
checkpoint was another seed's, it does not resume, and the manifest's "done" line is attempt 2's,
not resumed, and its fields' seed is attempt 2's."""
import json
import os
import shutil
import subprocess

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
a = ap.parse_args()
out = "retry_seed_campaign"
shutil.rmtree(out, ignore_errors=True)
listing = subprocess.run([a.tumble, "campaign", a.campaign, "--list"], capture_output=True,
                         text=True, check=True).stdout
case = [l.split("\t") for l in listing.splitlines() if not l.startswith("#")][0]
cid, seed1 = case[0], int(case[3])
env = dict(os.environ, TUMBLE_TEST_FAULT="%s:0:1000" % cid)
r = subprocess.run([a.tumble, "campaign", a.campaign, "--quiet"], capture_output=True, text=True,
                   env=env, timeout=120)
print(r.stdout + r.stderr)
lines, latest = cc.manifest(out)
if r.returncode != 4 or latest[cid]["status"] != "failed":
    cc.fail("attempt 1 should fail (test hook): exit %d, %s" % (r.returncode, latest[cid]))
ckpt = os.path.join(out, "cases", cid, "checkpoint.h5")
if not os.path.exists(ckpt):
    cc.fail("attempt 1 left no checkpoint: the test proves nothing")
# The line a stop writes for a retry handed out that had not begun.
stopped = dict(lines[-1])
stopped.update(status="stopped", attempt=2, diagnostic="not begun: SIGUSR1 came first",
               t=lines[-1]["t"] + 1e-3)  # (just after it: the rerun's lines come later)
for k in ("failure", "final", "end", "wall", "checksum"):
    stopped.pop(k, None)
with open(os.path.join(out, "manifest", "slice_1_of_1.jsonl"), "a") as fh:
    fh.write(json.dumps(stopped) + "\n")
r = subprocess.run([a.tumble, "campaign", a.campaign, "--quiet"], capture_output=True, text=True,
                   timeout=120)
print(r.stdout + r.stderr)
_, latest = cc.manifest(out)
done = latest[cid]
log = open(os.path.join(out, "cases", cid, "log.txt")).read()
second = log[log.rfind("attempt 2"):]
if r.returncode != 0 or done["status"] != "done" or done["attempt"] != 2:
    cc.fail("the rerun should finish attempt 2: exit %d, %s" % (r.returncode, done))
if done.get("resumed_from_step", 0) != 0 or "resuming from" in second:
    cc.fail("attempt 2 went on from attempt 1's checkpoint: %s" % done)
if "an earlier attempt's" not in second:
    cc.fail("the log does not say the checkpoint was an earlier attempt's:\n" + second)
with cc.h5py.File(os.path.join(out, "cases", cid, "fields.h5"), "r") as f:
    kept_seed = int(f.attrs["seed"])
if done["seed"] == seed1 or kept_seed != done["seed"]:
    cc.fail("seeds: attempt 1 %d, attempt 2 %d, fields %d" % (seed1, done["seed"], kept_seed))
print("OK: attempt 2 (seed %d) started afresh, not from attempt 1's checkpoint (seed %d)"
      % (done["seed"], seed1))
