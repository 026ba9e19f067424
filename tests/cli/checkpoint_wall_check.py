"""cli.checkpoint_wall_kill_resume: output.checkpoint_wall bounds what a kill loses, and changes
nothing in the run.

A bst_tiny run of ~14,800 steps (about 6 s here) three ways, on the same cached bed:
  A  output.checkpoint_wall = 0 (off): the reference;
  B  output.checkpoint_wall = 1e-9: a checkpoint after every step that rebuilt the neighbour list
     by itself (hundreds of them): its results.h5 series must equal A's bit for bit, since such a
     checkpoint forces nothing;
  C  output.checkpoint_wall = 0.5 s, SIGKILLed as soon as its first wall-clock checkpoint is on
     disk (the simulated-time checkpoint interval is longer than the run, so only the wall-clock
     checkpoints exist; waiting for the file, not for a fixed time, keeps the test independent of
     the machine's speed and load): the checkpoint is at a step between 0 and the end, and
     `--resume` must end with A's series bit for bit."""
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py

import results_series

tumble, scene, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
beds = os.path.join(work, "beds")


def cmd(name, wall, extra=()):
    return [tumble, "run", scene, "--set", "scene.output_dir=" + os.path.join(work, name),
            "--set", "fill.bed_cache=" + beds, "--set", "protocol.iterations=0.024",
            "--set", "output.checkpoint_interval=1000", "--set", "output.snapshot_interval=1000",
            "--set", "output.checkpoint_wall=%g" % wall] + list(extra)


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def same(a, b, what):  # runs a and b (folders under work) ended with the same series
    diff = results_series.difference(*(results_series.series(os.path.join(work, r)) for r in (a, b)))
    if diff:
        fail("%s: %s" % (what, diff))


for name, wall in (("A", 0), ("B", 1e-9)):
    r = subprocess.run(cmd(name, wall), capture_output=True, text=True)
    if r.returncode != 0:
        fail("run %s: exit %d\n%s" % (name, r.returncode, r.stderr))
same("A", "B", "a checkpoint at every self-made rebuild")
print("B (a checkpoint at every self-made rebuild) = A bit for bit", flush=True)

ckpt = os.path.join(work, "C", "checkpoint.h5")
proc = subprocess.Popen(cmd("C", 0.5), stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
deadline = time.time() + 120
while not os.path.exists(ckpt) and proc.poll() is None and time.time() < deadline:
    time.sleep(0.02)
if proc.poll() is not None:
    fail("run C ended before its first wall-clock checkpoint: make it longer")
proc.send_signal(signal.SIGKILL)
proc.wait()
if not os.path.exists(ckpt):
    fail("no checkpoint within 120 s of a run with output.checkpoint_wall = 0.5 s")
with h5py.File(ckpt, "r") as f:
    step = int(f.attrs["step"])
with h5py.File(os.path.join(work, "A", "results.h5"), "r") as f:
    total = int(f.attrs["steps"])
if not 0 < step < total:
    fail("the checkpoint is at step %d of %d" % (step, total))
r = subprocess.run(cmd("C", 0.5, ["--resume"]), capture_output=True, text=True)
if r.returncode != 0 or "restarting from" not in r.stdout + r.stderr:
    fail("resume: exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
same("A", "C", "killed and resumed from a wall-clock checkpoint")
print("OK: killed after its first wall-clock checkpoint, resumed from the wall-clock checkpoint at step %d of %d; series = A "
      "bit for bit" % (step, total))
