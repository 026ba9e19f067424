#!/usr/bin/env python3
"""Each start of the flow inside a biaxial run, rigid bulk against dynamic (issue 20; the runs of
jobs/accuracy/segment_start.sh; docs/accuracy.md, "The start at a segment change").

A biaxial iteration turns the wall about z (tilt by beta, rotate theta_z, tilt back), then about
x the same way. Each tilt-and-rotate is a start of the flow about a new axis, 80-odd degrees of
turn in one sense, like the single run of flow_accuracy.sh that onset_table.py reads: the surface
steepens as the bed turns with the wall, creeps, lets go in a first avalanche and settles to a
steady layer. The first start (z of iteration 1) is from the settled bed; every later one is from
the bed the last tilt back left, and with the rigid bulk also from a bed that
fidelity.bulk_segment_thaw thawed at the segment change (and thaws again where the tilt becomes
the rotation, at beta). The series of a biaxial run (series/segment, series/segment_turn and the
layer about the segment's axis, sampled every output.analysis_interval) give each start's curves
against the wall's turn since its tilt began, and onset_table.py's measures of them.

Per start (z1, x1, z2, ...; the letter the axis, the number the iteration) and set of runs: mean ±
Student 95% interval over the seeds. Each other set against the first, start by start (runs of
the same seed start from the same settled bed): the paired difference per seed, Student's t on the
differences, and the Benjamini-Hochberg procedure at q = 0.05 over every test of the table (all
starts, measures and sets: one family, fixed before the runs). Fewer than 3 pairs: the difference
is printed, no test.

A second look, its own family: the speed step at the tilt's end (the mean speed over the 2° of turn
after beta less that over the 2° before), where the tilt becomes the rotation: the wall turns on
alike, but the new segment thaws a rigid bulk. It was defined after the curves of the first job's
first bed, so the later beds of that job are its check. With three sets or more, a third family:
the step of each set after the second paired against the second's (a variant of the rigid bulk,
e.g. fidelity.bulk_segment_thaw = omega, against the rigid run it changes).

usage: segment_start_table.py DIR [DIR ...]   (each DIR holds seed<k>/results.h5; the first is
       the base, e.g. OUT/dynamic, then OUT/rigid of segment_start.sh)
       [--label NAME ...] one name per DIR (default: the DIR's last part)
       [--plot FILE.png]  slope and speed against the turn, mean per set, one column per start
"""
import glob
import math
import os
import signal
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from accuracy_table import is_complete  # noqa: E402  (the runs' own completeness rule)
from onset_table import (AFTER, BETA_ANGLE, CREEP, MEASURES, mean_table,  # noqa: E402
                         measures, paired_tests, parse_sets, print_tests, scene_value)

SEGMENTS = 6  # per period: (tilt, rotate, tilt back) about z, then about x
# A second look, its own BH family: defined after the curves of bed 1 of the first job
# (2026-12-06) showed the rigid runs' speed stepping up where the tilt becomes the rotation;
# beds 2-5 of that job, run after it was fixed, are its check.
STEP = "speed step at the tilt's end (omega R)"


def starts(path):
    """{start name: onset measures} of one complete biaxial run; None if it is not complete."""
    if not is_complete(path):
        return None
    with h5py.File(path, "r") as f:
        if "series/segment" not in f:
            sys.exit(f"{path}: no series/segment (not a biaxial run, or one written before the"
                     " layer was kept per segment): rerun it with this build")
        value = {k: scene_value(f, k) for k in ("protocol.rpm", "tumbler.radius",
                                                "particles.d_small", "protocol.repose",
                                                "protocol.theta_z", "protocol.theta_x")}
        t = f["series/time"][:]
        segment = f["series/segment"][:]
        turn = f["series/segment_turn"][:]
        slope = f["series/repose_angle"][:]
        speed_ms = f["series/surface_speed"][:]
        seed = int(f.attrs["seed"])
    beta = float(value["protocol.repose"])
    if beta <= 0 or float(value["protocol.theta_z"]) <= 0 or float(value["protocol.theta_x"]) <= 0:
        sys.exit(f"{path}: a start needs the tilt and both rotations (protocol.repose,"
                 " theta_z and theta_x > 0)")
    omega = 2 * math.pi * float(value["protocol.rpm"]) / 60
    radius = float(value["tumbler.radius"])
    speed = speed_ms / (omega * radius)
    out = {}
    periods = int(np.nanmax(segment) // SEGMENTS) + 1 if np.isfinite(segment).any() else 0
    for period in range(periods):
        for half, axis in enumerate("zx"):
            tilt = period * SEGMENTS + 3 * half
            pick = (segment == tilt) | (segment == tilt + 1)  # the tilt, then the rotation
            if not pick.any():
                continue
            # The turn since the tilt began: the tilt's own, then beta plus the rotation's.
            angle = np.where(segment[pick] == tilt, turn[pick], beta + turn[pick])
            r = measures(t[pick], angle, slope[pick], speed[pick], omega * radius / float(
                value["particles.d_small"]))
            # The step at the tilt's end: the mean speed over the 2° after beta less that over
            # the 2° before. The tilt and the rotation turn alike, but a new segment thaws a
            # rigid bulk there (fidelity.bulk_segment_thaw).
            v = speed[pick]
            after, before = (angle > beta) & (angle <= beta + 2), (angle >= beta - 2) & (angle < beta)
            r[STEP] = (np.nanmean(v[after]) - np.nanmean(v[before])
                       if after.any() and before.any() else math.nan)
            r["seed"] = seed
            out[f"{axis}{period + 1}"] = r
    return out


def load(directory):
    """{start name: {seed: measures}} over the complete runs of DIR/seed<k>/results.h5."""
    by_start = {}
    for path in sorted(glob.glob(os.path.join(directory, "seed*", "results.h5"))):
        found = starts(path)
        for name, r in (found or {}).items():
            by_start.setdefault(name, {})[r["seed"]] = r
    return by_start


def order(name):
    return (int(name[1:]), name[0] != "z")  # z1, x1, z2, x2, ...


def main():
    a, labels, sets = parse_sets(__doc__, load, os.path.basename)
    names = sorted(set().union(*sets), key=order)
    every = MEASURES + AFTER
    tests = []
    for name in names:
        runs = [s.get(name, {}) for s in sets]
        first = "the settled bed" if name == "z1" else "a segment change"
        print(f"\n## Start {name} (from {first})\n")
        for label, r in zip(labels, runs):
            if 0 < len(r) < 3:
                print(f"# warning: {label} has {len(r)} run(s) of this start; intervals need more")
        mean_table(labels, runs, every)
        for label, r in zip(labels[1:], runs[1:]):
            tests += paired_tests(f"{label}, {name}", runs[0], r, every)
    print_tests(tests, f"Paired by seed against {labels[0]}, every start")
    print("\nReading: a difference is a change in how the bed starts to flow about a new axis that"
          " these seeds resolve; 'no' everywhere means none resolved at this N, not that there is"
          " none.")
    print("\nAt the tilt's end (a second look, defined after the first bed's curves; its own"
          " family):\n")
    steps = []
    for name in names:
        runs = [s.get(name, {}) for s in sets]
        mean_table([f"{label}, {name}" for label in labels], runs, [STEP])
        for label, r in zip(labels[1:], runs[1:]):
            steps += paired_tests(f"{label}, {name}", runs[0], r, [STEP])
    print_tests(steps, f"At the tilt's end, paired by seed against {labels[0]}")
    if len(sets) > 2:
        # A variant of the rigid bulk against the rigid run it changes (the segment thaw's rule):
        # what the variant does to the step itself, free of dynamic's scatter.
        versus = []
        for name in names:
            runs = [s.get(name, {}) for s in sets]
            for label, r in zip(labels[2:], runs[2:]):
                versus += paired_tests(f"{label} - {labels[1]}, {name}", runs[1], r, [STEP])
        print_tests(versus, f"At the tilt's end, each later set paired by seed against {labels[1]}"
                    " (its own family)")
    if a.plot:
        plot(a.plot, labels, sets, names)


def plot(path, labels, sets, names):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, len(names), figsize=(3.6 * len(names), 5.5), sharex=True,
                             sharey="row", squeeze=False)
    grid = np.arange(0, 84.5, 1.0)
    for col, name in enumerate(names):
        for label, by_start in zip(labels, sets):
            runs = by_start.get(name, {})
            if not runs:
                continue
            for row, k in ((0, 1), (1, 2)):
                mean = np.mean([np.interp(grid, r["series"][0], r["series"][k], right=np.nan)
                                for r in runs.values()], 0)
                axes[row][col].plot(grid, mean, label=f"{label} (N = {len(runs)})")
        axes[0][col].set_title(f"start {name}")
        axes[1][col].set_xlabel("turn since the tilt began (deg)")
        axes[1][col].axhline(CREEP, color="grey", lw=0.5, ls=":")
        for row in (0, 1):
            axes[row][col].axvline(BETA_ANGLE, color="grey", lw=0.5, ls="--")
    axes[0][0].set_ylabel("surface slope (deg)")
    axes[1][0].set_ylabel("surface speed / (omega R)")
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"\nplot: {path}")


if __name__ == "__main__":
    # Piped to `head`, the table stops where the reader stopped, without a traceback.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    main()
