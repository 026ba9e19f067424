"""campaign.mpi2_sigkill_resume: kill a 2-rank campaign with SIGKILL mid-run, rerun the same command.

The whole job (mpiexec and both ranks) is killed at once, as a scheduler or a node failure would,
once at least one case is done and a case begun after it has written a checkpoint. The rerun must
complete, must not recompute any case finished before the kill (no new manifest line for it, its
fields file untouched), must resume the interrupted cases from their checkpoints, and must give
statistics identical, bit for bit, to an uninterrupted run of the same campaign.

With --ranks-per-case K and --rerun-ranks-per-case K2 the reference and the killed run use groups
of K ranks and the rerun groups of K2: the interrupted cases then resume from their checkpoints on
a different decomposition, whose trajectories agree with the first to round-off only, so the
statistics must agree to 1e-9 (relative) instead of bit for bit (groups_check.py says why).

With --signal USR1 (or TERM) the job is not killed but asked to stop: the signal goes to mpiexec
alone, which passes SIGUSR1 on to both ranks (SIGTERM it turns into a kill of its own after a few
seconds, so USR1 is what a batch system should send). The campaign must then end by itself with
exit code 10 (work left), no case left "running" in the manifest and at least one "stopped" with
a checkpoint written at a neighbour rebuild, no statistics; and the rerun must give the
uninterrupted run's statistics bit for bit, as a stop at a rebuild changes nothing in a case's
trajectory (run/checkpoint_observer.hpp)."""
import json
import os
import re
import shutil
import signal
import subprocess
import time

import campaign_checks as cc
import h5py

ap = cc.campaign_arguments(__doc__)
ap.add_argument("--ranks-per-case", type=int, default=1)
ap.add_argument("--rerun-ranks-per-case", type=int, default=None)
ap.add_argument("--signal", default="KILL", choices=["KILL", "USR1", "TERM"])
a = ap.parse_args()
k1 = a.ranks_per_case
k2 = a.rerun_ranks_per_case or k1
tag = ("" if (k1, k2) == (1, 1) else "_k%d_to_%d" % (k1, k2)) + \
    ("" if a.signal == "KILL" else "_" + a.signal.lower())

ref, run = "kill_reference" + tag, "kill_interrupted" + tag
for d in (ref, run):
    shutil.rmtree(d, ignore_errors=True)
launch = cc.mpiexec_command(a.mpiexec, a.np_flag, 2) + [a.tumble, "campaign", a.campaign]
base = launch + ["--ranks-per-case", str(k1), "--output"]
rerun = launch + ["--ranks-per-case", str(k2), "--output"]

t0 = time.time()
if subprocess.run(base + [ref], stdout=subprocess.DEVNULL).returncode != 0:
    cc.fail("the uninterrupted reference run failed")
print("reference run: %.1f s" % (time.time() - t0), flush=True)


def latest_records():
    out = {}
    for f in sorted(os.listdir(os.path.join(run, "manifest"))) if os.path.isdir(os.path.join(run, "manifest")) else []:
        with open(os.path.join(run, "manifest", f)) as fh:
            for line in fh:
                try:
                    r = json.loads(line)
                except ValueError:
                    continue  # a line being written
                out[r["case"]] = r
    return out


def descendants(pid):
    """Every process below `pid`. Open MPI puts each rank in a process group of its own, so
    killing mpiexec's group would leave the ranks running: they are found and killed one by one."""
    children = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % d) as fh:
                stat = fh.read()
        except OSError:
            continue
        ppid = int(stat[stat.rindex(")") + 2:].split()[1])
        children.setdefault(ppid, []).append(int(d))
    out, todo = [], [pid]
    while todo:
        for c in children.get(todo.pop(), []):
            out.append(c)
            todo.append(c)
    return out


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as fh:
            stat = fh.read()
        return stat[stat.rindex(")") + 2] != "Z"
    except OSError:
        return False


def kill_job(proc):
    victims = descendants(proc.pid) + [proc.pid]
    for pid in victims:  # SIGKILL to all of them at once: no rank gets to write another line
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    proc.wait()
    while any(alive(p) for p in victims):
        time.sleep(0.01)
    return len(victims)


log = open(run + ".log", "w")
proc = subprocess.Popen(base + [run], stdout=log, stderr=subprocess.STDOUT)
killed = 0
deadline = time.time() + 300
# The cases of the first round run side by side with equal lengths, so when one is done the other
# is at its last steps and may finish before a stop reaches it (the CI machine once saw exactly
# that: nothing left to stop at a checkpoint). So the job is interrupted in a case that began
# after the first one ended: one not yet seen running while no case was done.
first_round = set()
while time.time() < deadline:
    if proc.poll() is not None:
        break
    recs = latest_records()
    done = [c for c, r in recs.items() if r["status"] == "done"]
    running = [c for c, r in recs.items() if r["status"] == "running"]
    if not done:
        first_round.update(running)
    resumable = [c for c in running if c not in first_round
                 and os.path.exists(os.path.join(run, recs[c]["output"], "checkpoint.h5"))]
    if done and resumable:
        if a.signal == "KILL":
            killed = kill_job(proc)  # mpiexec and every rank, without warning
            break
        proc.send_signal(getattr(signal, "SIG" + a.signal))  # to mpiexec; it passes it on
        try:
            rc = proc.wait(timeout=120)
        except subprocess.TimeoutExpired:
            kill_job(proc)
            cc.fail("SIG%s: the campaign did not end within 120 s" % a.signal)
        if rc != 10:
            cc.fail("SIG%s: exit code %d, expected 10 (work left; see %s.log)" % (a.signal, rc, run))
        killed = 1
        break
    time.sleep(0.02)
if not killed:
    cc.fail("the campaign ended (rc %s) before it could be killed mid-run" % proc.returncode)
if os.path.exists(os.path.join(run, "ensemble.h5")):
    cc.fail("ensemble.h5 exists although the campaign was killed")

lines_before, latest = cc.manifest(run)
done_before = {c: r for c, r in latest.items() if r["status"] == "done"}
running_before = [c for c, r in latest.items() if r["status"] == "running"]
if a.signal != "KILL":
    stopped = [c for c, r in latest.items() if r["status"] == "stopped"
               and os.path.exists(os.path.join(run, r["output"], "checkpoint.h5"))]
    log.flush()
    text = open(run + ".log").read()
    if running_before:
        cc.fail("SIG%s: cases still 'running' in the manifest after the stop: %s" % (a.signal, running_before))
    if not stopped:
        cc.fail("SIG%s: no case recorded as stopped with a checkpoint" % a.signal)
    if "stopped by SIG" + a.signal not in text or "rerun the same command to go on" not in text:
        cc.fail("SIG%s: the campaign did not say why it stopped (see %s.log)" % (a.signal, run))
    print("SIG%s: the campaign stopped by itself, exit 10, %d case(s) stopped at a checkpoint"
          % (a.signal, len(stopped)), flush=True)
    running_before = stopped
stamp = {c: os.stat(os.path.join(run, r["output"], "fields.h5")).st_mtime_ns
         for c, r in done_before.items()}
if a.signal == "KILL":
    print("killed %d processes with %d case(s) done and %d running"
          % (killed, len(done_before), len(running_before)), flush=True)

# `--status` (one process, no mpiexec) lists the cases to run, and each interrupted or stopped
# one with its checkpoint's step, read here from the file itself, of the protocol's steps.
status = subprocess.run([a.tumble, "campaign", a.campaign, "--output", run, "--status"],
                        capture_output=True, text=True)
if status.returncode != 10:
    cc.fail("--status: exit code %d, expected 10 (work left):\n%s%s"
            % (status.returncode, status.stdout, status.stderr))
with_checkpoint = 0
for c in running_before:
    line = [l for l in status.stdout.splitlines() if c in l]
    path = os.path.join(run, latest[c]["output"], "checkpoint.h5")
    if not os.path.exists(path):  # (killed before its first checkpoint)
        if not line or "checkpoint at" in line[0]:
            cc.fail("--status: case %s without a checkpoint: %s" % (c, line))
        continue
    with_checkpoint += 1
    with h5py.File(path, "r") as f:
        step = int(f.attrs["step"])
    m = re.search(r"checkpoint at step (\d+) of (\d+), ([0-9.]+)%", line[0]) if line else None
    if not m or int(m.group(1)) != step or step > int(m.group(2)):  # (= : killed after its last step)
        cc.fail("--status does not give case %s's checkpoint step %d: %s" % (c, step, line))
if not with_checkpoint:
    cc.fail("--status: no interrupted case had a checkpoint to show")
print("--status: %d case(s) with their checkpoint's step" % with_checkpoint, flush=True)

t0 = time.time()
if subprocess.run(rerun + [run], stdout=log, stderr=subprocess.STDOUT).returncode != 0:
    cc.fail("the rerun failed (see %s.log)" % run)
print("rerun: %.1f s" % (time.time() - t0), flush=True)

lines_after, latest = cc.manifest(run)
new_lines = lines_after[len(lines_before):]
for c in done_before:
    again = [l for l in new_lines if l["case"] == c]
    if again:
        cc.fail("case %s, finished before the kill, was run again: %s" % (c, again))
    if os.stat(os.path.join(run, latest[c]["output"], "fields.h5")).st_mtime_ns != stamp[c]:
        cc.fail("case %s: its fields file was rewritten" % c)
resumed = [l for l in new_lines if l["status"] == "done" and l.get("resumed_from_step", 0) > 0]
if not resumed:
    cc.fail("no case resumed from a checkpoint")
for l in resumed:
    if l["case"] not in running_before:
        cc.fail("case %s resumed but was not running (or stopped) at the kill" % l["case"])
if any(r["status"] != "done" for r in latest.values()) or len(latest) != 4:
    cc.fail("not every case is done after the rerun")
for l in new_lines:
    if l["status"] == "done" and len(l.get("ranks", "0").split("-")) != min(k2, 2):
        cc.fail("the rerun ran case %s on ranks %s, not in groups of %d" % (l["case"], l["ranks"], k2))
tol = 0.0 if k1 == k2 else 1e-9
worst = cc.compare_ensembles(os.path.join(run, "ensemble.h5"), os.path.join(ref, "ensemble.h5"), tol)
how = "killed" if a.signal == "KILL" else "stopped by SIG" + a.signal
print("OK: groups of %d, %s, rerun in groups of %d: %d finished case(s) skipped, %d resumed "
      "from checkpoints (at steps %s); ensemble equal to the uninterrupted run's (largest "
      "difference %g, tolerance %g)" % (k1, how, k2, len(done_before), len(resumed),
                                       [l["resumed_from_step"] for l in resumed], worst, tol))
