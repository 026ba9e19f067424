"""jobs/accuracy/accuracy_table.py's rigid-against-dynamic section on constructed flow runs (no
engine run): pairing by seed, the frozen share per phase and the multiplicity control.

  /usr/bin/python3 accuracy_table_check.py SCRATCH_DIR

1. A rigid tier whose runs are copies of the dynamic ones (same seeds, same series): every paired
   and Welch difference is 0 and nothing is significant; the frozen share is read per phase
   (0-35 and 40-80 degrees of rotation) from series/frozen_fraction.
2. The rigid runs shifted in one observable (the surface speed) by an amount smaller than the
   scatter between seeds but the same for every seed (plus a little noise): the paired test
   resolves it, Welch's does not, and Benjamini-Hochberg counts that one test alone.
3. A run stopped part-way (results.h5 `complete` = 0) is left out with a line saying so.
4. The table's wall column names the rank count the runs were made on (results.h5 attribute
   `ranks`).
5. --plot writes a PNG with three panels: the profiles, the paired difference per bin and the
   frozen share.
6. The small-N warning quotes the t quantile of the pairs there are (4.3 at 3 pairs), and with a
   single pair says there is no interval and no test.
7. The profile RMS over the bins filled in nearly every sample, beside the one over all bins:
   edge bins that hold grains in a fifth of the samples decide the latter, not the former.
"""
import math
import os
import re
import shutil
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_run import Checks, script_stdout  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "..", "..", "jobs", "accuracy", "accuracy_table.py")
RPM, RADIUS = 3.0, 0.07
OMEGA = 2 * math.pi * RPM / 60
check = Checks()


def write_run(path, seed, level, speed, frozen=None, ranks=2, h=None, profile=None):
    """A flow run of 81 samples (one per degree) whose observables sit at the seed's level (the
    profile: 3 bins at 3 + level, or h / R and the 81 x bins samples given)."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    t = np.radians(np.arange(81.0)) / OMEGA
    with h5py.File(path, "w") as f:
        f.attrs["scene"] = f"protocol.rpm = {RPM}\ntumbler.radius = {RADIUS}\n"
        f.attrs["particles"] = 1000
        f.attrs["steps"] = 10000
        f.attrs["particle_steps_per_second"] = 1e6
        f.attrs["seed"] = seed
        f.attrs["ranks"] = ranks
        f.attrs["complete"] = 1
        f.create_dataset("series/time", data=t)
        f.create_dataset("series/repose_angle", data=np.full(81, 26.0 + level))
        f.create_dataset("series/surface_speed", data=np.full(81, speed * OMEGA * RADIUS))
        f.create_dataset("series/shell_large_fraction", data=np.full(81, 0.15 + level / 100))
        if profile is None:
            h, profile = np.array([-0.5, 0.0, 0.5]), np.tile((3.0 + level) * np.ones(3), (81, 1))
        f.create_dataset("series/surface_profile_h", data=np.asarray(h) * RADIUS)
        f.create_dataset("series/surface_profile", data=np.asarray(profile) * OMEGA * RADIUS)
        if frozen is not None:
            f.create_dataset("series/frozen_fraction",
                             data=np.where(np.arange(81) <= 35, frozen[0], frozen[1]))


def table(out, *extra):
    return script_stdout(TABLE, out, *extra)


def paired_rows(text):
    """{observable: (paired Δ, p paired, Welch Δ, p Welch)} of the rigid-against-dynamic table."""
    rows = {}
    part = text.split("paired by seed", 1)[-1]
    for line in part.splitlines():
        m = re.match(r"\| ([^|]+?) \| ([-+0-9.e]+)[^|]*\| ([0-9.e]+|nan) \| ([-+0-9.e]+)[^|]*\| ([0-9.e]+|nan) \|",
                     line)
        if m:
            rows[m.group(1)] = tuple(float(m.group(k)) for k in range(2, 6))
    return rows


def significant(text):
    m = re.search(r"Benjamini-Hochberg at q = 0.05 over (\d+) tests: (\d+) significant", text)
    return (int(m.group(1)), int(m.group(2))) if m else (None, None)


work = sys.argv[1]
shutil.rmtree(work, ignore_errors=True)
levels = {1: 0.0, 2: 1.0, 3: -0.8}  # the seeds' beds differ by about a degree and 0.6 omega R
speeds = {1: 3.0, 2: 3.6, 3: 2.5}

# 1. Copies.
out = os.path.join(work, "copies")
for s in levels:
    write_run(os.path.join(out, "standard", f"seed{s}", "results.h5"), s, levels[s], speeds[s])
    write_run(os.path.join(out, "standard-rigid", f"seed{s}", "results.h5"), s, levels[s], speeds[s],
              frozen=(0.7 + s / 100, 0.6 + s / 100))
text = table(out)
rows = paired_rows(text)
check("copies: the paired section lists the 3 observables and 3 profile bins", len(rows) == 6, str(sorted(rows)))
check("copies: every paired and Welch difference is 0",
      rows and all(v[0] == 0 and v[2] == 0 for v in rows.values()), str(rows))
tests, sig = significant(text)
check("copies: nothing significant (paired: no variance to test; Welch p = 1)", sig == 0, f"{sig} of {tests}")
check("copies: frozen share per phase", "0-35 degrees: 0.710, 0.720, 0.730" in text
      and "40-80 degrees: 0.610, 0.620, 0.630" in text)
check("the wall column names the runs' rank count", "wall s per run (2 ranks)" in text)

# 2. A shift of the surface speed by 0.2 omega R in every pair (the seeds scatter by 0.55).
out = os.path.join(work, "shifted")
noise = {1: 0.004, 2: -0.003, 3: 0.001}
for s in levels:
    write_run(os.path.join(out, "standard", f"seed{s}", "results.h5"), s, levels[s], speeds[s])
    write_run(os.path.join(out, "standard-rigid", f"seed{s}", "results.h5"), s, levels[s] + noise[s] / 10,
              speeds[s] + 0.2 + noise[s], frozen=(0.7, 0.6))
# A fourth seed stopped part-way (complete = 0) must be left out, not averaged in.
write_run(os.path.join(out, "standard-rigid", "seed4", "results.h5"), 4, 50.0, 50.0, frozen=(0.7, 0.6))
with h5py.File(os.path.join(out, "standard-rigid", "seed4", "results.h5"), "a") as f:
    f.attrs["complete"] = 0
text = table(out)
check("a run stopped part-way is left out, and said so",
      "left out (stopped before its end" in text and "seed4" in text and "| standard-rigid | 3 |" in text)
rows = paired_rows(text)
speed = rows.get("surface speed / (omega R)")
check("shifted: the paired difference is the planted 0.2", speed and abs(speed[0] - 0.2007) < 1e-3, str(speed))
check("shifted: paired p < 0.01, Welch p > 0.5 (the beds' scatter hides it from Welch)",
      speed and speed[1] < 0.01 and speed[3] > 0.5, str(speed))
tests, sig = significant(text)
check("shifted: Benjamini-Hochberg keeps exactly one test", sig == 1, f"{sig} of {tests}")
check("shifted: the one kept is the surface speed's paired test",
      "significant: surface speed / (omega R) (paired)" in text)
check("a warning at N = 3 with its t quantile", "warning: 3 pairs: at N = 3 a 95% CI spans ±4.3" in text)

# 5. The plot of the shifted runs.
png = os.path.join(work, "shifted.png")
text = table(out, "--plot", png)
ok = os.path.isfile(png)
if ok:
    from PIL import Image
    width, height = Image.open(png).size
check("--plot writes the figure, three panels side by side (3 x 5.5 by 4 inches at 110 dpi)",
      ok and width == 1815 and height == 440, f"{width} x {height}" if ok else "no file")

# 6. One pair: no interval, no test, and the warning says so.
out = os.path.join(work, "one_pair")
write_run(os.path.join(out, "standard", "seed1", "results.h5"), 1, 0.0, 3.0)
write_run(os.path.join(out, "standard-rigid", "seed1", "results.h5"), 1, 0.0, 3.2, frozen=(0.7, 0.6))
text = table(out)
check("one pair: BH over 0 tests", significant(text) == (0, 0), str(significant(text)))
check("one pair: the warning says there is no interval", "warning: 1 pair(s): no interval" in text)

# 7. Edge bins empty in most samples: five bins, the outer two holding grains in 1 sample of 5 (at
# values that scatter between seeds by ±2 omega R), the inner three in all, the rigid runs 0.1
# faster there. The RMS over all bins is the edges' (8.7 times the planted difference); over the
# filled bins it is the planted 0.1.
out = os.path.join(work, "edges")
h5 = [-0.8, -0.4, 0.0, 0.4, 0.8]
for s, edge in ((1, 1.0), (2, 5.0), (3, 3.0)):
    for tier, inner in (("standard", 3.0), ("standard-rigid", 3.1)):
        prof = np.tile([edge, inner, inner, inner, edge], (81, 1))
        prof[np.arange(81) % 5 != 0, 0] = prof[np.arange(81) % 5 != 0, 4] = np.nan
        write_run(os.path.join(out, tier, f"seed{s}", "results.h5"), s, 0.0, 3.0, h=h5, profile=prof,
                  frozen=(0.7, 0.6) if tier != "standard" else None)
text = table(out)
header = next((ln for ln in text.splitlines() if ln.startswith("| h / R |")), "")
col = next((k for k, c in enumerate(header.split("|")) if c.strip().startswith("standard-rigid")), None)


def rms_cell(prefix):
    line = next((ln for ln in text.splitlines() if ln.startswith(prefix)), None)
    if line is None or col is None:
        return None
    m = re.match(r"\s*([0-9.e+-]+)", line.split("|")[col])
    return float(m.group(1)) if m else None


inner = rms_cell("| the same over the 3 bins filled in ≥ 90% of every standard run's samples (h/R -0.40 to +0.40)")
every = rms_cell("| RMS from standard's mean profile, all 5 bins")
check("edge bins: the filled bins' RMS is the planted 0.1", inner is not None and abs(inner - 0.1) < 1e-9,
      str(inner))
# per seed sqrt((2 d_edge^2 + 3 x 0.01) / 5) with d_edge = -2, +2, 0 against the mean edge 3
expect = np.mean([math.sqrt((2 * d * d + 0.03) / 5) for d in (-2.0, 2.0, 0.0)])
check("edge bins: the RMS over all bins is the edges' (0.871)",
      every is not None and abs(every - expect) < 1e-3, f"{every} against {expect:.4f}")
check("no filled-bins row where every bin is filled", "bins filled in" not in table(os.path.join(work, "copies")))

print(f"{check.failures} failure(s)")
sys.exit(1 if check.failures else 0)
