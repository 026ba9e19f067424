"""cli.repose_stop_resume: the repose angle's turn (protocol.repose = "measured") is kept, not lost,
when the run is stopped or killed in it, and going on from it gives the uninterrupted number bit for
bit (run/repose_measure.hpp).

bst_tiny turned at 20 rpm (80 degrees in seconds), its bed settled once and copied into each
run's own bed cache, so that every run below measures beta on the same bed:
  R1, R2  uninterrupted, on 1 and 2 ranks: the reference betas (the cached value's repose_deg);
      the caches keep the rank count they were made on (the bed's settled_on_ranks 1, the betas'
      turned_on_ranks 1 and 2) and R2's line reusing R1's bed says it settled on 1 rank;
  K   serial, output.checkpoint_wall = 1 s, SIGKILL once it says it kept its turn: the turn file
      holds the engine and the samples so far, and the rerun goes on from it to R1's beta;
  S   2 ranks under mpiexec, SIGUSR1 to mpiexec past 45 degrees (samples taken): exit code 10, one
      line saying where the turn is kept, no value cached yet; the rerun goes on to R2's beta,
      bit for bit, and removes the turn file;
  D   a damaged turn file: the rerun says it does not go on from it, turns from the start and
      still gives R1's beta;
  C   a one-case campaign sent SIGUSR1 while its case measures beta: exit 10, `--status` says how
      far the kept turn is, and the rerun's case goes on from it.
The signals go when the run's own lines say so, not after a fixed time.

usage: repose_stop_check.py TUMBLE SCENE WORK MPIEXEC NP_FLAG"""
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py

from signalled_run import fail, signalled

tumble, scene, work, mpiexec, np_flag = sys.argv[1:6]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def cmd(name, ranks, extra=()):
    launch = [mpiexec, np_flag, str(ranks)] if ranks > 1 else []
    return launch + [tumble, "run", scene, "--set", "protocol.repose=measured",
                     "--set", "protocol.rpm=20", "--set", "protocol.iterations=0.002",
                     "--set", "output.progress_interval=0.2", "--set", "output.checkpoint_wall=0",
                     "--set", "output.snapshot_interval=1000",
                     "--set", "output.checkpoint_interval=1000",
                     "--set", "scene.output_dir=" + os.path.join(work, name),
                     "--set", "fill.bed_cache=" + os.path.join(work, "beds_" + name)] + list(extra)


def run(name, ranks, extra=()):
    r = subprocess.run(cmd(name, ranks, extra), capture_output=True, text=True)
    if r.returncode != 0:
        fail("%s: exit %d\n%s%s" % (name, r.returncode, r.stdout, r.stderr))
    return r.stdout + r.stderr


def files(name, pattern):
    return sorted(glob.glob(os.path.join(work, "beds_" + name, pattern)))


def beta(name):
    values = [f for f in files(name, "repose_*.h5") if not f.endswith(".turn.h5")]
    if len(values) != 1:
        fail("%s: expected one cached repose value, found %s" % (name, values))
    with h5py.File(values[0], "r") as f:
        return float(f.attrs["repose_deg"])


def with_bed(name):  # the reference's settled bed, without its repose value
    os.makedirs(os.path.join(work, "beds_" + name))
    for f in files("R1", "bed_*.h5"):
        shutil.copy(f, os.path.join(work, "beds_" + name))


def interrupted(name, ranks, sig, when, extra=()):
    return signalled(name, cmd(name, ranks, extra), sig, when)


def past(degrees):
    def when(line):
        m = re.match(r"\[repose\] ([0-9.]+) of 80 degrees", line)
        return m is not None and float(m.group(1)) >= degrees
    return when


def resumed_to(name, ranks, reference, what):
    text = run(name, ranks)
    if "[repose] going on from " not in text:
        fail("%s: the rerun did not go on from the kept turn\n%s" % (name, text))
    got = beta(name)
    if got != reference:
        fail("%s: beta %r after %s, %r uninterrupted" % (name, got, what, reference))
    if files(name, "*.turn.h5"):
        fail("%s: the turn file is still there once the value is cached" % name)
    line = [l for l in text.splitlines() if "[repose] going on from " in l][0]
    print("OK: %s: %s; the rerun %s; beta %.10g = the uninterrupted turn's, bit for bit"
          % (name, what, line.split("] ")[1], got), flush=True)


def attr(name, pattern, key):
    got = [f for f in files(name, pattern) if not f.endswith(".turn.h5")]
    with h5py.File(got[0], "r") as f:
        return int(f.attrs[key]) if key in f.attrs else None


run("R1", 1)
beta1 = beta("R1")
with_bed("R2")
text2 = run("R2", 2)
beta2 = beta("R2")
print("references: beta %.10g (1 rank), %.10g (2 ranks)" % (beta1, beta2), flush=True)
# The caches keep the rank count their bed settled and their beta turned on, and a run that reuses
# a bed settled on another count says so (a bed settles in round-off differently on another).
kept = (attr("R1", "bed_*.h5", "settled_on_ranks"), attr("R1", "repose_*.h5", "turned_on_ranks"),
        attr("R2", "repose_*.h5", "turned_on_ranks"))
if kept != (1, 1, 2):
    fail("settled_on_ranks of R1's bed, turned_on_ranks of R1's and R2's beta: %s, expected "
         "(1, 1, 2)" % (kept,))
reuse = [l for l in text2.splitlines() if l.startswith("[fill] reusing settled bed ")]
# (The turn reads the bed, then the run: one line each.)
if not reuse or any(", settled on 1 rank (this run has 2: " not in l for l in reuse):
    fail("R2 (2 ranks, R1's bed settled on 1): expected a line saying the bed settled on 1 rank "
         "and this run has 2, got %s" % reuse)
print("OK: the caches say they were made on %s ranks; R2: %s" % (kept, reuse[0]), flush=True)

# K: killed after a wall-clock keep (nothing warns it).
with_bed("K")
rc, text = interrupted("K", 1, signal.SIGKILL, lambda l: l.startswith("[repose] turn kept at "),
                       ["--set", "output.checkpoint_wall=1"])
turn = files("K", "*.turn.h5")
if len(turn) != 1:
    fail("K: expected one turn file after the kill, found %s\n%s" % (turn, text))
with h5py.File(turn[0], "r") as f:
    kept_at = int(f.attrs["step"])
if kept_at <= 0:
    fail("K: the turn file is at step %d" % kept_at)
shutil.copy(turn[0], os.path.join(work, "turn_K.h5"))
resumed_to("K", 1, beta1, "SIGKILL after a keep by output.checkpoint_wall (step %d)" % kept_at)

# S: a stop signal on 2 ranks, once samples are being taken (from 40 degrees).
with_bed("S")
rc, text = interrupted("S", 2, signal.SIGUSR1, past(45))
said = [l for l in text.splitlines() if "stopped by SIGUSR1 while measuring the repose angle, at " in l]
if rc != 10 or len(said) != 1 or "the turn so far is kept in " not in said[0]:
    fail("S: exit %d, expected 10 and one line 'stopped by SIGUSR1 while measuring the repose "
         "angle, at ...: the turn so far is kept in ...'\n%s" % (rc, text))
turn = files("S", "*.turn.h5")
if len(turn) != 1 or turn[0] not in said[0]:
    fail("S: the line names no turn file there is: %s, %s" % (turn, said[0]))
with h5py.File(turn[0], "r") as f:
    samples = len(f["measure/samples"][...]) if "measure/samples" in f else 0
if samples < 1:
    fail("S: the turn past 45 degrees kept no samples")
if [f for f in files("S", "repose_*.h5") if not f.endswith(".turn.h5")]:
    fail("S: a repose value was cached although the turn was stopped")
resumed_to("S", 2, beta2, "SIGUSR1 on 2 ranks, exit 10, turn kept with %d samples" % samples)

# D: a damaged turn file is not gone on from; the turn starts again.
with_bed("D")
damaged = os.path.join(work, "beds_D", os.path.basename(files("K", "repose_*.h5")[0])[:-3] + ".turn.h5")
with open(os.path.join(work, "turn_K.h5"), "rb") as f:
    data = bytearray(f.read())
with open(damaged, "wb") as f:
    f.write(data[: len(data) // 2])
text = run("D", 1)
if "[repose] not going on from " not in text or "turning from the start" not in text:
    fail("D: no line that the damaged turn is not gone on from\n%s" % text)
if beta("D") != beta1 or files("D", "*.turn.h5"):
    fail("D: beta %r (uninterrupted %r), turn files %s" % (beta("D"), beta1, files("D", "*.turn.h5")))
print("OK: D: a damaged turn file: not gone on from, the turn started again, beta = the "
      "uninterrupted one's", flush=True)

# C: a campaign stopped while its case measures beta.
camp = os.path.join(work, "C.toml")
with open(camp, "w") as f:
    f.write('[campaign]\nname = "c"\nscene = "%s"\noutput_dir = "%s"\nbed_cache = "%s"\n'
            'replicas = 1\nprogress_interval = 0.2\n[overrides]\n"protocol.repose" = "measured"\n"protocol.rpm" = 20\n'
            '"protocol.iterations" = 0.01\n"output.progress_interval" = 0.2\n'
            '"output.checkpoint_wall" = 0\n"fill.settle_rms_speed" = 0.005\n'
            '[[sweep]]\ntheta_z = 57\ntheta_x = 57\n[collect]\niterations = [0, 0.01]\n'
            'samples_per_iteration = 1000\ndisplacement_periods = 0.003\ngrid = 8\n'
            % (scene, os.path.join(work, "C"), os.path.join(work, "beds_C")))
with open(os.path.join(work, "C.log"), "w") as log:
    proc = subprocess.Popen([tumble, "campaign", camp], stdout=log, stderr=subprocess.STDOUT)
    deadline, turned = time.time() + 120, None
    while time.time() < deadline and proc.poll() is None and turned is None:
        for case_log in glob.glob(os.path.join(work, "C", "cases", "*", "log.txt")):
            with open(case_log) as f:
                at = [float(m.group(1)) for m in re.finditer(r"\[repose\] ([0-9.]+) of 80", f.read())]
            if at and at[-1] >= 45:
                turned = case_log
        time.sleep(0.05)
    if turned is None:
        proc.kill()
        fail("C: the campaign's case said nothing past 45 degrees of its turn within 120 s")
    proc.send_signal(signal.SIGUSR1)
    rc = proc.wait(timeout=120)
with open(os.path.join(work, "C.log")) as f:
    text = f.read()
with open(turned) as f:
    case_text = f.read()
kept = [f for f in glob.glob(os.path.join(work, "beds_C", "*.turn.h5"))]
if rc != 10 or "the turn so far is kept in " not in case_text or len(kept) != 1:
    fail("C: exit %d after SIGUSR1 (expected 10, the case's line that its turn is kept, and the "
         "turn file: %s)\n%s\n%s" % (rc, kept, text, case_text))
status = subprocess.run([tumble, "campaign", camp, "--status"], capture_output=True, text=True)
m = re.search(r"beta turn kept at ([0-9.]+) of 80 degrees", status.stdout)
if status.returncode != 10 or not m or float(m.group(1)) < 45:
    fail("C: --status (exit %d) does not say how far the kept turn is:\n%s%s"
         % (status.returncode, status.stdout, status.stderr))
# The one turn reads beta and the still slope's creep onset: a rigid campaign of the same bed
# finds the same kept turn, and its status names what its case waits on.
with open(camp) as f:
    c_text = f.read()
for name, repose, what in (("C2", '"measured"', "beta and still-slope"), ("C3", "27", "still-slope")):
    other = os.path.join(work, name + ".toml")
    with open(other, "w") as f:
        f.write(c_text.replace(os.path.join(work, "C") + '"', os.path.join(work, name) + '"')
                .replace('"protocol.repose" = "measured"', '"protocol.repose" = ' + repose)
                .replace("[overrides]\n", '[overrides]\n"fidelity.bulk" = "rigid"\n'
                         '"fidelity.bulk_still_slope" = "measured"\n'))
    st = subprocess.run([tumble, "campaign", other, "--status"], capture_output=True, text=True)
    m2 = re.search(r"([a-z -]+) turn kept at ([0-9.]+) of 80 degrees", st.stdout)
    if st.returncode != 10 or not m2 or m2.group(1).strip() != what or \
            m2.group(2) != m.group(1):
        fail("%s: --status (exit %d) of a rigid campaign on the same bed does not say '%s turn "
             "kept at %s':\n%s%s" % (name, st.returncode, what, m.group(1), st.stdout, st.stderr))
print("OK: C: the same bed's rigid campaigns read the kept turn: 'beta and still-slope turn' "
      "(beta measured too), 'still-slope turn' (beta given)", flush=True)
r = subprocess.run([tumble, "campaign", camp], capture_output=True, text=True)
with open(turned) as f:
    case_text = f.read()
if r.returncode != 0 or "[repose] going on from " not in case_text:
    fail("C: the rerun (exit %d) did not go on from the kept turn\n%s%s%s"
         % (r.returncode, r.stdout, r.stderr, case_text))
print("OK: C: a campaign stopped in its case's turn: exit 10, --status '%s', the rerun went on "
      "from it and finished" % m.group(0), flush=True)
