"""cli.rigid_restart_ranks: a rigid-bulk run on 2 ranks, stopped and resumed, is the run that was
never stopped, bit for bit; resumed on 3 ranks, it is that run to round-off (issue 20, D2).

bst_tiny, fidelity.bulk = rigid with a short dwell (0.004 s: the bed tilting by beta at the start
of the biaxial protocol turns with the wall and freezes within it), on a cached bed:
  A  2 ranks, STEPS steps without a stop: the reference;
  B  2 ranks, STEPS / 2 steps, then `--resume` for the rest: every dataset of its final
     checkpoint (particles with their bulk state, anchors and frozen gravity; the contact records,
     the dormant springs of frozen pairs among them; the series) must equal A's bit for bit;
  C  B's checkpoint at STEPS / 2 resumed on 3 ranks (another decomposition: every dormant spring
     goes to the ranks that own one of its particles now): the same particles in the same bulk
     states as A, positions and velocities within 1e-9 d_small, the same contact pairs with springs
     within 1e-9 d_small, each pair held by as many ranks as own one of its particles (its
     spring kept by each, Newton off) in A's and C's checkpoints;
  D  C again from a copy of that checkpoint without contacts/anchor, as a file written before
     2026-11-23 reads: every rank gets every record, and the dormant ones must be placed at their
     particles (Simulation::restore), or one that travels with a particle leaving its rank goes
     to the ranks near the origin and is lost; D must pass C's checks.
The checkpoint at the split must hold frozen particles and dormant springs, or the test shows
nothing about them (it fails then).

usage: rigid_restart_check.py TUMBLE SCENE WORK MPIEXEC NP_FLAG"""
import collections
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

tumble, scene, work, mpiexec, np_flag = sys.argv[1:6]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
STEPS = 3000
# The settings of Domain.RigidBulkMatchesSerial (tests/parallel/test_domain.cpp), whose 2- and
# 3-rank runs agree with the serial one step by step on this bed.
KEYS = ["fidelity.bulk=rigid", "fidelity.bulk_dwell=0.004", "fidelity.bulk_calm_distance=0.1",
        "neighbor.skin=0.05", "parallel.rebalance_threshold=1.0", "parallel.frozen_weight=0.12",
        "fill.bed_cache=" + os.path.join(work, "beds"), "output.checkpoint_interval=1000",
        "output.snapshot_interval=1000", "output.analysis_interval=0.01",
        "output.checkpoint_wall=0"]


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def run(name, ranks, steps, resume=False):
    launch = [mpiexec, np_flag, str(ranks)] + (["--oversubscribe"] if ranks > 2 else [])
    cmd = launch + [tumble, "run", scene, "--max-steps", str(steps)] + (["--resume"] if resume else [])
    for k in KEYS + ["scene.output_dir=" + os.path.join(work, name)]:
        cmd += ["--set", k]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        fail("%s: exit %d\n%s%s" % (" ".join(cmd), r.returncode, r.stdout, r.stderr))
    return r.stdout


def datasets(path):
    """Every dataset of a checkpoint by its path, and its step."""
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: out.__setitem__(n, o[()]) if isinstance(o, h5py.Dataset) else None)
        return out, int(f.attrs["step"])


def by_id(d, name):
    order = np.argsort(d["particles/id"])
    return d[name][order]


def copies_missing(d):
    """The contact pairs a checkpoint of several ranks holds a wrong number of copies of: each rank
    that owns one of a pair's particles keeps its spring (Newton off; a dormant spring too), so a
    pair is held once if one rank owns both particles, else twice. A rank that lost its copy of a
    border pair's spring shows here, where the merged springs() would still find the other's."""
    owner = np.empty(int(d["particles/id"].max()) + 1, dtype=int)
    start = 0
    for r, n in enumerate(d["domain/rows"]):
        owner[d["particles/id"][start:start + n]] = r
        start += n
    held = collections.Counter(map(tuple, d["contacts/pair_ids"].tolist()))
    return [p for p, k in held.items() if k != (1 if owner[p[0]] == owner[p[1]] else 2)]


def springs(d):
    """{(lo, hi): spring} of a checkpoint's contact records."""
    return {tuple(p): s for p, s in zip(d["contacts/pair_ids"].tolist(), d["contacts/spring"])}


run("A", 2, STEPS)
run("B", 2, STEPS // 2)
half, at = datasets(os.path.join(work, "B", "checkpoint.h5"))
if at != STEPS // 2:
    fail("B's checkpoint is at step %d, expected %d" % (at, STEPS // 2))
frozen = set(half["particles/id"][half["particles/bulk_state"] < 0].tolist())
dormant = sum(lo in frozen and hi in frozen for lo, hi in half["contacts/pair_ids"].tolist())
if len(frozen) < 100 or dormant < 100:
    fail("at the split %d particles frozen, %d dormant springs: the test would show nothing" % (len(frozen), dormant))
shutil.copytree(os.path.join(work, "B"), os.path.join(work, "C"))
shutil.copytree(os.path.join(work, "B"), os.path.join(work, "D"))
with h5py.File(os.path.join(work, "D", "checkpoint.h5"), "r+") as f:
    del f["contacts/anchor"]
run("B", 2, STEPS - STEPS // 2, resume=True)
run("C", 3, STEPS - STEPS // 2, resume=True)
run("D", 3, STEPS - STEPS // 2, resume=True)

a, a_step = datasets(os.path.join(work, "A", "checkpoint.h5"))
b, b_step = datasets(os.path.join(work, "B", "checkpoint.h5"))
if a_step != STEPS or b_step != STEPS:
    fail("final checkpoints at steps %d and %d, expected %d" % (a_step, b_step, STEPS))
# The domain's rows and tree, and the series, included: the same ranks cut the bed alike.
differ = [n for n in a if n not in b or a[n].shape != b[n].shape or
          not np.array_equal(a[n], b[n], equal_nan=a[n].dtype.kind == "f")]
differ += [n for n in b if n not in a]
if copies_missing(a):
    fail("A (2 ranks): %d contact pairs held by the wrong number of ranks" % len(copies_missing(a)))
if differ:
    fail("2 ranks, stopped at step %d and resumed: datasets differ from the uninterrupted run's: %s"
         % (STEPS // 2, differ))
print("OK: 2 ranks, stopped at step %d (%d frozen, %d dormant springs) and resumed: all %d "
      "checkpoint datasets = the uninterrupted run's bit for bit" % (STEPS // 2, len(frozen), dormant, len(a)),
      flush=True)

with h5py.File(os.path.join(work, "A", "checkpoint.h5"), "r") as f:
    d_small = float(next(l for l in f.attrs["scene"].decode().splitlines()
                         if l.startswith("particles.d_small")).split("=")[1])
tol = 1e-9 * d_small
sa = springs(a)


def check_three_ranks(name, what):
    """A run resumed on 3 ranks against the 2-rank run A, to round-off."""
    c, c_step = datasets(os.path.join(work, name, "checkpoint.h5"))
    if c_step != STEPS or len(c["particles/id"]) != len(a["particles/id"]):
        fail("%s (3 ranks): checkpoint at step %d with %d particles" % (name, c_step, len(c["particles/id"])))
    if not np.array_equal(by_id(a, "particles/bulk_state"), by_id(c, "particles/bulk_state")):
        fail("%s (3 ranks): bulk states differ from the 2-rank run's" % name)
    worst = {n: float(np.max(np.abs(by_id(a, "particles/" + n) - by_id(c, "particles/" + n))))
             for n in ("x", "v")}
    if worst["x"] > tol or worst["v"] * 1e-3 > tol:  # v over 1 ms: a length
        fail("%s (3 ranks): positions %.3g m, velocities %.3g m/s from the 2-rank run's (allowed %.3g, %.3g)"
             % (name, worst["x"], worst["v"], tol, tol * 1e3))
    sc = springs(c)
    if set(sa) != set(sc):
        fail("%s (3 ranks): %d contact pairs only in the 2-rank run, %d only in the 3-rank one"
             % (name, len(set(sa) - set(sc)), len(set(sc) - set(sa))))
    wrong = copies_missing(c)
    if wrong:
        fail("%s (3 ranks): %d contact pairs held by the wrong number of ranks, e.g. %s"
             % (name, len(wrong), wrong[:3]))
    spring = max((float(np.max(np.abs(sa[k] - sc[k]))) for k in sa), default=0.0)
    if spring > tol:
        fail("%s (3 ranks): springs differ by %.3g m from the 2-rank run's (allowed %.3g)" % (name, spring, tol))
    print("OK: %s: the same %d bulk states and %d contact pairs; positions within %.2g m, "
          "springs within %.2g m of the 2-rank run (allowed %.2g)" % (what, len(a["particles/id"]), len(sa),
                                                                    worst["x"], spring, tol), flush=True)


check_three_ranks("C", "resumed on 3 ranks")
check_three_ranks("D", "resumed on 3 ranks from the checkpoint without anchors")
