"""cli.stop_signal_resume: a signal stops `tumble run` cleanly, and the continuation is the run
that was never stopped, bit for bit (base/stop_request.hpp, run/checkpoint_observer.hpp).

A bst_tiny run of ~14,800 steps on a cached bed, serially and on 2 ranks under mpiexec:
  A  uninterrupted: the reference;
  S  the same, sent a signal once it is stepping (SIGTERM to the serial run; SIGUSR1 to mpiexec,
     which passes it on to both ranks): it must end by itself with exit code 10, say at which
     step it stopped and how to go on, leave its checkpoint at that step (between 0 and the
     end), and `--resume` must end with A's results.h5 series bit for bit.
Signalled when its first line after the set-up is out, not after a fixed time, so the test does
not depend on the machine's speed (a run that ends before the signal arrives fails the test).
And a run whose bed is not cached yet, sent SIGINT once it is settling: it must stop within the
settling (exit 10, "while settling the bed") and cache no half-settled bed.

usage: stop_signal_check.py TUMBLE SCENE WORK MPIEXEC NP_FLAG"""
import os
import shutil
import signal
import subprocess
import sys

import h5py

import results_series
from signalled_run import fail, signalled

tumble, scene, work, mpiexec, np_flag = sys.argv[1:6]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
beds = os.path.join(work, "beds")


def cmd(name, ranks, extra=()):
    launch = [mpiexec, np_flag, str(ranks)] if ranks > 1 else []
    return launch + [tumble, "run", scene, "--set", "scene.output_dir=" + os.path.join(work, name),
                     "--set", "fill.bed_cache=" + beds, "--set", "protocol.iterations=0.024",
                     "--set", "output.checkpoint_interval=1000", "--set", "output.snapshot_interval=1000",
                     "--set", "output.checkpoint_wall=0"] + list(extra)


def same(a, b, what):  # runs a and b (folders under work) ended with the same series
    diff = results_series.difference(*(results_series.series(os.path.join(work, r)) for r in (a, b)))
    if diff:
        fail("%s: %s" % (what, diff))


def stopped_run(name, ranks, sig, extra=(), when=lambda line: line.startswith("[run] ") and " particles, dt = " in line):
    """Signals the run once a line for which `when` holds is out (by default the header printed
    after the set-up, when the stop handlers are in place) and 0.2 s more (into the step loop);
    returns (exit code, its output)."""
    return signalled(name, cmd(name, ranks, extra), sig, when, settle=0.2)


for ranks, sig in ((1, signal.SIGTERM), (2, signal.SIGUSR1)):
    ref, name = "A%d" % ranks, "S%d" % ranks
    r = subprocess.run(cmd(ref, ranks), capture_output=True, text=True)
    if r.returncode != 0:
        fail("reference %s: exit %d\n%s%s" % (ref, r.returncode, r.stdout, r.stderr))
    with h5py.File(os.path.join(work, ref, "results.h5"), "r") as f:
        total = int(f.attrs["steps"])
    rc, text = stopped_run(name, ranks, sig)
    if rc != 10:
        fail("%s: exit code %d after %s, expected 10 (work left)\n%s" % (name, rc, sig.name, text))
    said = [l for l in text.splitlines() if "stopped by " + sig.name + " at step " in l]
    if len(said) != 1 or "--resume" not in said[0]:
        fail("%s: expected one line 'stopped by %s at step ... --resume', got\n%s" % (name, sig.name, text))
    step = int(said[0].split(" at step ")[1].split()[0])
    with h5py.File(os.path.join(work, name, "checkpoint.h5"), "r") as f:
        at = int(f.attrs["step"])
    if at != step or not 0 < step < total:
        fail("%s: stopped at step %d, checkpoint at step %d, run of %d steps" % (name, step, at, total))
    # The call's own cost, as a finished call's done line gives it (a fresh start: all its steps).
    ran = said[0].split("this call ran ")[1].split() if "this call ran " in said[0] else []
    if len(ran) < 4 or int(ran[0]) != step or ran[1:3] != ["steps", "in"] or not float(ran[3]) > 0:
        fail("%s: expected 'this call ran %d steps in W s' with W > 0, got\n%s" % (name, step, said[0]))
    r = subprocess.run(cmd(name, ranks, ["--resume"]), capture_output=True, text=True)
    if r.returncode != 0 or "restarting from" not in r.stdout + r.stderr:
        fail("%s --resume: exit %d\n%s%s" % (name, r.returncode, r.stdout, r.stderr))
    same(ref, name, "%s, stopped by %s and resumed" % (name, sig.name))
    print("OK: %d rank(s), %s: stopped at step %d of %d with exit code 10, resumed; series = the "
          "uninterrupted run's bit for bit" % (ranks, sig.name, step, total), flush=True)

fresh = os.path.join(work, "beds_fresh")
rc, text = stopped_run("F1", 1, signal.SIGINT, ["--set", "fill.bed_cache=" + fresh],
                       when=lambda line: line.startswith("[fill] "))
if rc != 10 or "stopped by SIGINT while settling the bed" not in text:
    fail("F1: exit code %d after SIGINT while settling, expected 10 and 'stopped by SIGINT while "
         "settling the bed'\n%s" % (rc, text))
if os.path.isdir(fresh) and os.listdir(fresh):
    fail("F1: a bed was cached although the settling was stopped: %s" % os.listdir(fresh))
print("OK: SIGINT while settling: exit code 10, nothing cached", flush=True)
