"""jobs/accuracy/segment_start_table.py on constructed biaxial runs (no engine run): each start of
the flow cut out of the series by segment and turned into the turn since its tilt began, the
paired difference that Benjamini-Hochberg keeps in the start where it was planted and not in the
other, an incomplete run left out, and the refusals.

  /usr/bin/python3 segment_start_table_check.py SCRATCH_DIR

Each run is one (57°, 57°) iteration with beta = 27° at 3 rpm (R chosen so that omega R =
0.01 m/s), sampled once per degree of turn: per half, the tilt (27 samples, turn 0-26°), the
rotation (57, turn 0-56°, so 27-83° since the tilt began) and the tilt back (27). Within a start
(tilt and rotation): slope = turn + 1 up to 26° then 26°, speed 0.01 k (seed k) until the flow at
30°, 3 omega R from there; the tilt back reads speed 5 (which no measure of a start may see).
Rigid runs: the same, but in the x start a burst of 1.3 + 0.1 k omega R at 20° and 21° (its peak
before 27°: 1.3 + 0.09 k above the base's 0.01 k, mean +1.525); in the z start a step to
1 + 0.05 k omega R at 28° and 29°, after the tilt's end and before the flow (the second family's
step at the tilt's end, the 2° after beta less the 2° before: 1 + 0.04 k above the base's 0, mean
+1.1), which no measure of the first family sees.
"""
import math
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_run import Checks, script_stdout  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "..", "..", "jobs", "accuracy", "segment_start_table.py")
RPM = 3.0
OMEGA = 2 * math.pi * RPM / 60
RADIUS = 0.01 / OMEGA  # omega R = 0.01 m/s
D_SMALL = 0.002
BETA, THETA = 27, 57
check = Checks()


def start_speed(since_tilt, rigid, seed, axis):
    speed = np.where(since_tilt >= 30, 3.0, 0.01 * seed)
    if rigid and axis == "x":
        speed[(since_tilt >= 20) & (since_tilt <= 21)] = 1.3 + 0.1 * seed
    if rigid and axis == "z":  # a step where the tilt becomes the rotation, before the flow
        speed[(since_tilt >= 28) & (since_tilt < 30)] = 1 + 0.05 * seed
    return speed


def series(rigid, seed):
    segment, turn, slope, speed = [], [], [], []
    for half, axis in enumerate("zx"):
        for part, length in enumerate((BETA, THETA, BETA)):
            k = np.arange(length, dtype=float)
            segment.append(np.full(length, 3 * half + part, dtype=float))
            turn.append(k)
            if part == 2:  # tilt back: not part of a start
                slope.append(np.full(length, 5.0))
                speed.append(np.full(length, 5.0))
                continue
            since = k + (BETA if part == 1 else 0)
            slope.append(np.minimum(since + 1, 26.0) + 0.01 * seed)
            speed.append(start_speed(since, rigid, seed, axis))
    segment, turn = np.concatenate(segment), np.concatenate(turn)
    time = np.radians(np.arange(segment.size, dtype=float)) / OMEGA
    return time, segment, turn, np.concatenate(slope), np.concatenate(speed)


def write_run(path, rigid, seed, complete=1, with_segment=True):
    os.makedirs(path, exist_ok=True)
    time, segment, turn, slope, speed = series(rigid, seed)
    with h5py.File(os.path.join(path, "results.h5"), "w") as f:
        f.attrs["scene"] = (f"protocol.rpm = {RPM}\ntumbler.radius = {RADIUS!r}\n"
                            f"particles.d_small = {D_SMALL}\nprotocol.repose = {BETA}\n"
                            f"protocol.theta_z = {THETA}\nprotocol.theta_x = {THETA}\n")
        f.attrs["seed"] = seed
        f.attrs["complete"] = complete
        f.create_dataset("series/time", data=time)
        if with_segment:
            f.create_dataset("series/segment", data=segment)
            f.create_dataset("series/segment_turn", data=turn)
        f.create_dataset("series/repose_angle", data=slope)
        f.create_dataset("series/surface_speed", data=speed * OMEGA * RADIUS)


def rows(out, start):
    """The paired table's row of the peak before 27° for `start`."""
    return [line for line in out.splitlines()
            if line.startswith(f"| rigid, {start} | peak speed before 27 deg")]


def main():
    work = sys.argv[1]
    shutil.rmtree(work, ignore_errors=True)
    base, rigid = os.path.join(work, "dynamic"), os.path.join(work, "rigid")
    for k in range(1, 5):
        write_run(os.path.join(base, f"seed{k}"), False, k)
        write_run(os.path.join(rigid, f"seed{k}"), True, k)
    write_run(os.path.join(rigid, "seed5"), True, 5, complete=0)  # cut short: left out
    out = script_stdout(TABLE, base, rigid)
    check("both starts found", "## Start z1 (from the settled bed)" in out
          and "## Start x1 (from a segment change)" in out)
    check("both sets counted, the incomplete run left out",
          "dynamic (N = 4)" in out and "rigid (N = 4)" in out and "N = 5" not in out)
    # The flow from 30° since the tilt began: 3° into the rotation, so the rotation's turn has
    # had beta added (without it the flow would read 57°) and the tilt back's speed 5 is not seen.
    check("the flow onset counts from the tilt's start",
          out.count("| flow onset angle (deg) | 30 ± 0 | 30 ± 0 |") == 2)
    check("the tilt back is no part of a start",
          out.count("| peak speed before 27 deg (omega R) | 0.025 ± 0.021 | 0.025 ± 0.021 |") == 1)
    z, x = rows(out, "z1"), rows(out, "x1")
    check("the burst in x1 is the planted difference, kept by BH",
          len(x) == 1 and "+1.53" in x[0] and x[0].rstrip(" |").endswith("yes"), x[0] if x else "no row")
    check("z1, the same in both, is no difference",
          len(z) == 1 and "+0 " in z[0] and z[0].rstrip(" |").endswith("no"), z[0] if z else "no row")
    # One family over both starts: 2 tests each in x1 (the peak, the slide), none in z1.
    check("one BH family over every start", "over the 2 tests" in out)
    steps = [line for line in out.splitlines()
             if line.startswith("| rigid, z1 | speed step at the tilt's end")]
    check("the step at the tilt's end in z1, kept by its own family",
          len(steps) == 1 and "+1.1 " in steps[0] and steps[0].rstrip(" |").endswith("yes")
          and "At the tilt's end, paired by seed against dynamic (Student t on the differences;"
          " BH at q = 0.05 over the 1 tests)" in out, steps[0] if steps else "no row")
    # A run written before the series kept the segment is refused with what to do.
    old = os.path.join(work, "old")
    write_run(os.path.join(old, "seed1"), False, 1, with_segment=False)
    r = subprocess.run([sys.executable, TABLE, base, old], capture_output=True, text=True)
    check("a run without series/segment: refused", r.returncode != 0
          and "no series/segment" in r.stderr and "rerun" in r.stderr, r.stderr.strip())
    empty = os.path.join(work, "empty")
    os.makedirs(empty, exist_ok=True)
    r = subprocess.run([sys.executable, TABLE, base, empty], capture_output=True, text=True)
    check("no runs: refused", r.returncode != 0 and "no complete run" in r.stderr, r.stderr.strip())
    sys.exit(1 if check.failures else 0)


if __name__ == "__main__":
    main()
