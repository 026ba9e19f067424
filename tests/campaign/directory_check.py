"""campaign.one_directory_one_campaign: a campaign directory is run by one slicing at a time and
holds one campaign.

1. While the whole campaign (kill_campaign.toml, 1 rank, frozen by SIGSTOP once its manifest
   records a case running) runs, `--slice 1/2` of it into the same directory is refused at once
   (exit 2, "another slicing"), as is a second whole run (exit 2, "already running"), and
   `--status` names the running process (not after it is killed); the first run is then killed.
2. Another campaign (groups_campaign.toml) into that directory is refused (exit 2, "holds another
   campaign") without touching its campaign.toml; with --force it runs (exit 0) and removes the
   other campaign's statistics (a partial result put there; before, `tumble merge` folded it in).
3. `tumble merge` refuses a partial holding cases that cases.tsv does not list (exit 2, named)."""
import argparse
import os
import shutil
import signal
import subprocess
import time

import campaign_checks as cc

ap = argparse.ArgumentParser()
ap.add_argument("--tumble", required=True)
ap.add_argument("--kill-campaign", required=True)
ap.add_argument("--other-campaign", required=True)
a = ap.parse_args()
out = "one_directory"
shutil.rmtree(out, ignore_errors=True)

whole = subprocess.Popen([a.tumble, "campaign", a.kill_campaign, "--output", out],
                         stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
deadline = time.time() + 60
manifest = os.path.join(out, "manifest", "slice_1_of_1.jsonl")


def a_case_runs():
    # The file is made before its first case is recorded: --status names the running process
    # beside a case recorded as running, so the freeze waits for that record.
    try:
        return '"running"' in open(manifest).read()
    except OSError:
        return False


while not a_case_runs():
    if time.time() > deadline or whole.poll() is not None:
        cc.fail("the whole campaign did not start a case")
    time.sleep(0.05)
# Frozen while the checks run (it keeps its lock and its process): on a fast machine its few
# seconds of cases could end between two checks, which would then prove nothing.
os.kill(whole.pid, signal.SIGSTOP)
try:
    for extra, word in ((["--slice", "1/2"], "another slicing"), ([], "already running")):
        r = subprocess.run([a.tumble, "campaign", a.kill_campaign, "--output", out] + extra,
                           capture_output=True, text=True, timeout=30)
        if r.returncode != 2 or word not in r.stderr:
            cc.fail("%s while the whole campaign runs: exit %d, %s" % (extra or "a second run",
                                                                     r.returncode, r.stderr))
        print("refused while running (%s): %s" % (" ".join(extra) or "same slicing",
                                                   r.stderr.strip().splitlines()[0][:100]))
    # --status names the running process (DirectoryLock::running_process) beside the case it
    # runs; once the process is gone, it does not.
    r = subprocess.run([a.tumble, "campaign", a.kill_campaign, "--output", out, "--status"],
                       capture_output=True, text=True, timeout=30)
    want = "process %d runs this campaign" % whole.pid
    if r.returncode != 10 or want not in r.stdout:
        cc.fail("--status while the campaign runs: exit %d, no '%s' in:\n%s%s"
                % (r.returncode, want, r.stdout, r.stderr))
    print("--status while running: " + [l for l in r.stdout.splitlines() if want in l][0][:120])
    if whole.poll() is not None:
        cc.fail("the whole campaign ended before the checks: they proved nothing")
finally:
    whole.kill()
    whole.wait()
r = subprocess.run([a.tumble, "campaign", a.kill_campaign, "--output", out, "--status"],
                   capture_output=True, text=True, timeout=30)
if "runs this campaign" in r.stdout:
    cc.fail("--status after the campaign was killed still names a running process:\n" + r.stdout)

before = open(os.path.join(out, "campaign.toml")).read()
r = subprocess.run([a.tumble, "campaign", a.other_campaign, "--output", out],
                   capture_output=True, text=True, timeout=60)
if r.returncode != 2 or "holds another campaign" not in r.stderr:
    cc.fail("another campaign into the directory: exit %d, %s" % (r.returncode, r.stderr))
if open(os.path.join(out, "campaign.toml")).read() != before:
    cc.fail("the refused campaign replaced campaign.toml")
# Its --status says so too (before: exit 10, "to run", for cases the run would refuse).
r = subprocess.run([a.tumble, "campaign", a.other_campaign, "--output", out, "--status"],
                   capture_output=True, text=True, timeout=60)
if r.returncode != 2 or "holds another campaign" not in r.stderr:
    cc.fail("--status of another campaign's directory: exit %d, %s" % (r.returncode, r.stderr))
# The first campaign's statistics (here: the CI campaign's, standing in for them) must not
# survive --force: `tumble merge` folded them into the new campaign's ensemble.
ci_partial = os.path.join("ci_full", "partials", "slice_1_of_1.h5")
stale = os.path.join(out, "partials", "slice_1_of_3.h5")
os.makedirs(os.path.dirname(stale), exist_ok=True)
shutil.copyfile(ci_partial, stale)
r = subprocess.run([a.tumble, "campaign", a.other_campaign, "--output", out, "--force"],
                   capture_output=True, text=True, timeout=120)
if r.returncode != 0:
    cc.fail("with --force: exit %d, %s" % (r.returncode, r.stderr))
if os.path.exists(stale) or "removed the other campaign's statistics" not in r.stdout:
    cc.fail("--force left the other campaign's partial result, or did not say it removed it")
# A partial of another campaign copied in is refused by merge, named.
foreign = os.path.join(out, "partials", "slice_1_of_2.h5")
shutil.copyfile(ci_partial, foreign)
r = subprocess.run([a.tumble, "merge", out, "--slices", "2"], capture_output=True, text=True,
                   timeout=60)
if r.returncode != 2 or "does not list" not in r.stderr or "slice_1_of_2.h5" not in r.stderr:
    cc.fail("merge of another campaign's partial: exit %d (want 2), %s" % (r.returncode, r.stderr))
print("OK: another slicing and a second run refused while the campaign ran; another campaign "
      "refused without --force, run with it, the other's statistics removed; merge refuses "
      "another campaign's partial")

# 4. Two campaigns started at once into one empty directory, as slices of one slicing (which the
# slicing lock lets run together): before, both found no case table and both ran; now the table
# is checked and written under a lock, and the second finds the first's table and is refused.
race = "one_directory_race"
shutil.rmtree(race, ignore_errors=True)
procs = [subprocess.Popen([a.tumble, "campaign", c, "--output", race, "--slice", s],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
         for c, s in ((a.other_campaign, "1/2"), (a.kill_campaign, "2/2"))]
refused = None
deadline = time.time() + 120
while refused is None and time.time() < deadline:
    for k, p in enumerate(procs):
        if p.poll() == 2:
            refused = k
    if all(p.poll() is not None for p in procs):
        break
    time.sleep(0.05)
outputs = []
for p in procs:
    if p.poll() is None:
        p.kill()
    outputs.append(p.communicate()[0])
if refused is None or "holds another campaign" not in outputs[refused]:
    cc.fail("two campaigns started at once into one directory: neither refused (exit codes %s)\n%s"
            % ([p.returncode for p in procs], "\n".join(outputs)))
print("OK: of two campaigns started at once into one directory, the second is refused")
