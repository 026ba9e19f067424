"""jobs/accuracy/onset_table.py on constructed runs (no engine run): the onset measures read off
planted series, the paired difference that Benjamini-Hochberg keeps, an incomplete run left out,
and the refusals.

  /usr/bin/python3 onset_table_check.py SCRATCH_DIR

Each run turns 80° at 3 rpm (R chosen so that omega R = 0.01 m/s), sampled once per degree. Base runs: slope = angle + 1 up to 26° then 26°; speed 0 until 16° of
rotation, a creep of 0.3 omega R from there, the flow (3 omega R) from 30°. Rigid runs: the same,
but held at 0 until 20° and a burst of 1.3 + 0.1 k omega R (seed k) at 20° and 21°: their creep
onset slope is 21° (against 17°), their peak before 27° 1.3 + 0.1 k (against 0.3 + 0.01 k), their
flow onset the same 30° (seed 4's burst, 1.7, passes half the flow's 3.0 for two samples only),
and a trough of 2 + 0.05 k omega R at 40° after it (the second family's lowest speed 35-50°:
-1 + 0.05 k against dynamic's 3.0; the slope the same, no test). Rigid runs keep a frozen share,
0.7 + 0.02 k up to 29° and 0.5 from 30°; base runs keep none (the frozen-share table has no row
for them).
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
TABLE = os.path.join(HERE, "..", "..", "jobs", "accuracy", "onset_table.py")
RPM = 3.0
OMEGA = 2 * math.pi * RPM / 60
RADIUS = 0.01 / OMEGA  # omega R = 0.01 m/s
D_SMALL = 0.002
check = Checks()


def series(rigid, seed):
    angle = np.arange(0, 81, 1.0)
    slope = np.minimum(angle + 1, 26.0) + 0.01 * seed
    speed = np.where(angle >= 16, 0.3, 0.0) + 0.01 * seed
    speed[angle >= 30] = 3.0
    if rigid:
        speed[angle < 20] = 0.0
        speed[(angle >= 20) & (angle <= 21)] = 1.3 + 0.1 * seed
        speed[angle == 40] = 2.0 + 0.05 * seed
    return angle, slope, speed


def write_run(path, rigid, seed, complete=1):
    os.makedirs(path, exist_ok=True)
    angle, slope, speed = series(rigid, seed)
    with h5py.File(os.path.join(path, "results.h5"), "w") as f:
        f.attrs["scene"] = (f"protocol.rpm = {RPM}\ntumbler.radius = {RADIUS!r}\n"
                            f"particles.d_small = {D_SMALL}\n")
        f.attrs["seed"] = seed
        f.attrs["complete"] = complete
        f.create_dataset("series/time", data=np.radians(angle) / OMEGA)
        f.create_dataset("series/repose_angle", data=slope)
        f.create_dataset("series/surface_speed", data=speed * OMEGA * RADIUS)
        if rigid:
            f.create_dataset("series/frozen_fraction",
                             data=np.where(angle < 30, 0.7 + 0.02 * seed, 0.5))


def cell(text, row, column):
    """The table cell of the row starting with `row`, column index `column` (0 = the row name)."""
    for line in text.splitlines():
        parts = [p.strip() for p in line.strip().strip("|").split("|")]
        if parts and parts[0] == row:
            return parts[column]
    return None


def main():
    work = sys.argv[1]
    shutil.rmtree(work, ignore_errors=True)
    base, rigid = os.path.join(work, "base"), os.path.join(work, "rigid")
    for k in range(1, 5):
        write_run(os.path.join(base, f"seed{k}"), False, k)
        write_run(os.path.join(rigid, f"seed{k}"), True, k)
    write_run(os.path.join(rigid, "seed5"), True, 5, complete=0)  # cut short: left out
    out = script_stdout(TABLE, base, rigid, "--label", "dynamic", "still")
    check("both sets counted, the incomplete run left out",
          "dynamic (N = 4)" in out and "still (N = 4)" in out, out.splitlines()[0] if out else "")
    # Base creep from 16° of rotation: slope 17 + 0.01 k, mean 17.025; rigid from 20°: 21.025.
    check("creep onset slope of the base", cell(out, "creep onset slope (deg)", 1).startswith("17"),
          cell(out, "creep onset slope (deg)", 1))
    check("creep onset slope of the held run", cell(out, "creep onset slope (deg)", 2).startswith("21"),
          cell(out, "creep onset slope (deg)", 2))
    check("flow onset at 30 degrees for both",
          cell(out, "flow onset angle (deg)", 1).startswith("30 ")
          and cell(out, "flow onset angle (deg)", 2).startswith("30 "),
          f"{cell(out, 'flow onset angle (deg)', 1)}, {cell(out, 'flow onset angle (deg)', 2)}")
    # Slide before 27°: each sample's speed times the 1° interval before it, summed, in d_small.
    # Base seed k: 12 samples (16-27°) of 0.3 + 0.01 k and 15 (1-15°; the first has no interval)
    # of 0.01 k; the mean over k = 1..4.
    dt = math.radians(1) / OMEGA
    slide = np.mean([(12 * 0.3 + 27 * 0.01 * k) * dt * 0.01 / D_SMALL for k in range(1, 5)])
    got = cell(out, "slide before 27 deg (d_small)", 1)
    check("slide of the base", got is not None and abs(float(got.split()[0]) - slide) < 5e-3 * slide,  # 3 digits printed
          f"{got} against {slide:.4g}")
    # Paired peak difference: (1.3 + 0.1 k) - (0.3 + 0.01 k) = 1 + 0.09 k, mean 1.225.
    rows = [line for line in out.splitlines() if line.startswith("| still | peak speed before")]
    check("the burst is the planted difference, kept by BH",
          len(rows) == 1 and "+1.23" in rows[0] and rows[0].rstrip(" |").endswith("yes"),
          rows[0] if rows else "no row")
    rows = [line for line in out.splitlines() if line.startswith("| still | flow onset")]
    check("an equal flow onset is no test (zero spread) and not significant",
          len(rows) == 1 and "no test" in rows[0] and rows[0].rstrip(" |").endswith("no"),
          rows[0] if rows else "no row")
    # The second family (after the first avalanche): its own table and its own BH count (2 tests
    # in the first: the peak before 27° and the slide; the rest have no spread).
    rows = [line for line in out.splitlines() if line.startswith("| still | lowest speed 35-50")]
    check("the trough after the avalanche is the planted difference, kept by its own BH",
          len(rows) == 1 and "-0.875" in rows[0] and rows[0].rstrip(" |").endswith("yes"),
          rows[0] if rows else "no row")
    check("the two families are counted apart",
          "over the 2 tests" in out and "After the first avalanche, paired by seed" in out
          and "over the 1 tests" in out, out)
    # The frozen share: the rigid set's row only, its mean over seeds 1-4 at 10° (0.75), at 32°
    # and over 40-80° (0.50).
    rows = [line for line in out.splitlines() if line.startswith("| still (N = 4) |")]
    check("the frozen share of the set that kept it, none for the base",
          len(rows) == 1 and cell(rows[0], "still (N = 4)", 1) == "0.75"
          and cell(rows[0], "still (N = 4)", 5) == "0.50"
          and cell(rows[0], "still (N = 4)", 11) == "0.50"
          and not any(line.startswith("| dynamic (N = 4) |") for line in out.splitlines()),
          rows[0] if rows else "no row")
    # Fewer than three runs: a warning.
    few = os.path.join(work, "few")
    write_run(os.path.join(few, "seed1"), True, 1)
    out = script_stdout(TABLE, base, few)
    check("a set of one run is warned about", "warning: " in out and "1 run(s)" in out)
    # A directory without runs, or labels that do not match, is refused.
    empty = os.path.join(work, "empty")
    os.makedirs(empty, exist_ok=True)
    r = subprocess.run([sys.executable, TABLE, base, empty], capture_output=True, text=True)
    check("no runs: refused", r.returncode != 0 and "no complete run" in r.stderr, r.stderr.strip())
    r = subprocess.run([sys.executable, TABLE, base, rigid, "--label", "one"], capture_output=True,
                       text=True)
    check("labels must match the directories", r.returncode != 0 and "--label" in r.stderr,
          r.stderr.strip())
    sys.exit(1 if check.failures else 0)


if __name__ == "__main__":
    main()
