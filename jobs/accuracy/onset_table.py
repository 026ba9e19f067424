#!/usr/bin/env python3
"""The onset of flow in flow_accuracy.sh's runs: how a bed rotated from rest starts to flow, and
whether a rigid-bulk setting changes it (docs/accuracy.md, "The still surface at `standard`").

Each run of jobs/accuracy/flow_accuracy.sh turns a settled bed 80° about x at the tier's speed.
For the first ~30° the bed turns with the wall and its surface steepens; then the surface layer
starts to move and a flowing layer forms. fidelity.bulk_still_slope freezes the whole bed while
the surface is below the key and thaws the surface layer when it passes it, so this is where it
can err. Per run, from the series sampled once per degree (angle = the wall's rotation, slope =
series/repose_angle, speed = series/surface_speed / (omega R), downhill along the surface):

* creep onset slope: the surface slope at the first sample from which the speed stays above
  CREEP (0.1 omega R) for three samples: where the surface stops turning with the wall;
* flow onset angle: the first sample from which the speed stays above half the run's mean over
  40-80° (the established layer's speed) for three samples (a burst of two is not the flow);
* largest slope before the flow onset (the bed's angle of maximum stability, over the samples);
* peak speed before 27° of rotation (a held layer let go shows here as a burst);
* slide before 27°: the surface's downhill travel up to 27° of rotation, the sum over the samples
  of the speed times the time since the sample before, in d_small (how far the top grains moved
  before the flow began);
* peak speed 27-40°: the first avalanche, where the layer forms over the bed (a frozen bed under
  it can make it run faster than over a dynamic one).

After the first avalanche (a second table, its own BH family: these two were added once the mean
curves of bst_paper's runs showed the rigid arms' avalanche overshooting, so they are a second
look at the same runs, not part of the first family's plan):

* lowest speed 35-50°: the trough that follows the first avalanche, before the layer settles to
  its steady speed (a harder avalanche can run the surface out past its steady slope);
* lowest slope 30-45°: how flat the surface runs out past the avalanche.

Where the runs kept series/frozen_fraction (the rigid bulk's runs), a third table shows the
frozen share through the start: each set's mean over its seeds at chosen turns of the wall, and
its mean over 40-80°. It is descriptive (no tests): it shows where the bed thaws and refreezes
beside the speed, the reading a change of a freezing rule is judged by.

Per set of runs: mean ± Student 95% interval over the seeds. Each other set against the first
(runs of the same seed start from the same settled bed): the paired difference per seed, Student's
t on the differences, and the Benjamini-Hochberg procedure at q = 0.05 over every difference in
its table (each family apart). Fewer than 3 pairs: the difference is printed, no test.

usage: onset_table.py DIR [DIR ...]   (each DIR holds seed<k>/results.h5; the first is the base,
       e.g. OUT/standard, then OUT/standard-rigid of each flow_accuracy.sh job)
       [--label NAME ...] one name per DIR (default: the DIR's last two parts)
       [--plot FILE.png]  slope, speed (and the frozen share, where kept) against the
                          rotation angle, mean per set
"""
import argparse
import glob
import math
import os
import signal
import sys

import h5py
import numpy as np
from scipy import stats

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
from postproc.report_stats import bh_reject, mean_ci  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from accuracy_table import is_complete  # noqa: E402  (the flow runs' own completeness rule)

CREEP = 0.1      # omega R: above the reading of a bed turning as a solid (within ±0.06 but for
                 # single samples; a grain's depth times omega is ~0.1 omega R at R/d = 8.75)
BETA_ANGLE = 27  # degrees of rotation: the protocol's tilt (beta = 27 deg) ends here


def scene_value(f, key):
    scene = f.attrs["scene"]
    scene = scene.decode() if isinstance(scene, bytes) else scene
    kv = dict(line.split(" = ", 1) for line in scene.splitlines() if " = " in line)
    return kv[key]


def first_lasting(above, samples=3):
    """The first sample from which `above` holds for `samples` samples (None: never)."""
    return next((k for k in range(len(above) - samples + 1) if above[k:k + samples].all()), None)


def onset(path):
    """The onset measures of one run (NaN where the run never reaches them)."""
    if not is_complete(path):
        return None
    with h5py.File(path, "r") as f:
        omega = 2 * math.pi * float(scene_value(f, "protocol.rpm")) / 60
        radius = float(scene_value(f, "tumbler.radius"))
        d_small = float(scene_value(f, "particles.d_small"))
        t = f["series/time"][:]
        slope = f["series/repose_angle"][:]
        speed = f["series/surface_speed"][:] / (omega * radius)
        seed = int(f.attrs["seed"])
        frozen = f["series/frozen_fraction"][:] if "series/frozen_fraction" in f else None
    return dict(measures(t, np.degrees(omega * t), slope, speed, omega * radius / d_small),
                seed=seed, frozen=frozen)


def measures(t, angle, slope, speed, omega_r_over_d_small):
    """The onset measures of one start of the flow: the samples' times t (s), the wall's turn since
    the start (degrees), the surface slope (degrees) and speed (omega R); the last argument,
    omega R / d_small, turns a travel in omega R seconds into d_small. Also used for each start of a biaxial run
    (segment_start_table.py)."""
    nan = math.nan
    creep = first_lasting(speed > CREEP)
    flowing = speed[(angle >= 40) & (angle <= 80)]
    half = 0.5 * np.nanmean(flowing) if flowing.size else nan
    flow = first_lasting(speed > half)  # lasting: a held layer's burst at its thaw is no flow
    early = angle <= BETA_ANGLE
    dt = np.diff(t, prepend=t[0])
    return {
        "creep onset slope (deg)": slope[creep] if creep is not None else nan,
        "flow onset angle (deg)": angle[flow] if flow is not None else nan,
        "largest slope before the flow (deg)": np.nanmax(slope[:flow + 1]) if flow is not None else nan,
        "peak speed before 27 deg (omega R)": np.nanmax(speed[early]),
        "slide before 27 deg (d_small)": np.nansum((speed * dt)[early]) * omega_r_over_d_small,
        "peak speed 27-40 deg (omega R)": np.nanmax(speed[(angle > BETA_ANGLE) & (angle <= 40)]),
        "lowest speed 35-50 deg (omega R)": np.nanmin(speed[(angle >= 35) & (angle <= 50)]),
        "lowest slope 30-45 deg (deg)": np.nanmin(slope[(angle >= 30) & (angle <= 45)]),
        "series": (angle, slope, speed),
    }


MEASURES = ["creep onset slope (deg)", "flow onset angle (deg)",
            "largest slope before the flow (deg)", "peak speed before 27 deg (omega R)",
            "slide before 27 deg (d_small)", "peak speed 27-40 deg (omega R)"]
AFTER = ["lowest speed 35-50 deg (omega R)", "lowest slope 30-45 deg (deg)"]


def load(directory):
    runs = {}
    for path in sorted(glob.glob(os.path.join(directory, "seed*", "results.h5"))):
        r = onset(path)
        if r is not None:
            runs[r["seed"]] = r
    return runs


FROZEN_AT = [10, 20, 24, 28, 32, 36, 40, 45, 50, 60]  # degrees of the wall's turn


def mean_frozen(runs, angles):
    """The frozen share over the runs that kept it, mean per angle (degrees of the wall's turn),
    and how many kept it; (None, 0) where none did."""
    kept = [r for r in runs.values() if r["frozen"] is not None]
    if not kept:
        return None, 0
    return np.mean([np.interp(angles, r["series"][0], r["frozen"]) for r in kept], 0), len(kept)


def frozen_table(labels, sets):
    """The mean frozen share of each set that kept it, at FROZEN_AT and over 40-80° (no set kept
    it: no table)."""
    rows = []
    for label, runs in zip(labels, sets):
        at, n = mean_frozen(runs, FROZEN_AT)
        if at is None:
            continue
        steady = np.mean([np.mean(r["frozen"][(r["series"][0] >= 40) & (r["series"][0] <= 80)])
                          for r in runs.values() if r["frozen"] is not None])
        rows.append(f"| {label} (N = {n}) | " + " | ".join(f"{v:.2f}" for v in at)
                    + f" | {steady:.2f} |")
    if not rows:
        return
    print("\nThe frozen share through the start (series/frozen_fraction; mean over the seeds, no"
          " tests):\n")
    print("| set | " + " | ".join(f"{a}°" for a in FROZEN_AT) + " | mean 40-80° |")
    print("|---" * (len(FROZEN_AT) + 2) + "|")
    print("\n".join(rows))


def mean_table(labels, sets, measure_names):
    """Mean ± Student 95% interval of each measure over each set's seeds."""
    print("| measure | " + " | ".join(f"{lab} (N = {len(r)})" for lab, r in zip(labels, sets)) + " |")
    print("|---" * (len(sets) + 1) + "|")
    for m in measure_names:
        cells = []
        for runs in sets:
            mean, ci, n = mean_ci([r[m] for r in runs.values()])
            cells.append(f"{mean:.3g} ± {ci:.2g}" if np.isfinite(ci) else f"{mean:.3g}")
        print(f"| {m} | " + " | ".join(cells) + " |")


def paired_tests(label, base, runs, measure_names):
    """The paired differences runs - base over the keys (seeds) both hold, one test per measure:
    (label, measure, mean, 95% half width, p, pairs); fewer than 3 pairs: no test (NaN)."""
    tests = []
    common = sorted(set(base) & set(runs))
    for m in measure_names:
        d = np.array([runs[s][m] - base[s][m] for s in common])
        d = d[np.isfinite(d)]
        mean = float(d.mean()) if d.size else math.nan
        if d.size >= 3 and d.std(ddof=1) > 0:
            p = float(stats.ttest_1samp(d, 0).pvalue)
            half = float(stats.t.ppf(0.975, d.size - 1) * d.std(ddof=1) / math.sqrt(d.size))
        else:
            p, half = math.nan, math.nan
        tests.append((label, m, mean, half, p, d.size))
    return tests


def paired_table(labels, sets, measure_names, family):
    """Each set's paired differences from the first set over `measure_names`: one BH family,
    under the heading `family`."""
    tests = []
    for label, runs in zip(labels[1:], sets[1:]):
        tests += paired_tests(label, sets[0], runs, measure_names)
    print_tests(tests, f"{family} by seed against {labels[0]}")


def print_tests(tests, heading):
    """The tests as one Benjamini-Hochberg family at q = 0.05, as a table under `heading`."""
    ps = np.array([t[4] for t in tests])
    tested = np.isfinite(ps)
    reject, adjusted = bh_reject(ps)  # untested (NaN) entries are neither counted nor rejected
    print(f"\n{heading} (Student t on the differences; BH at"
          f" q = 0.05 over the {int(tested.sum())} tests):\n")
    print("| set | measure | difference (95% CI) | pairs | p | p adjusted (BH) | significant |")
    print("|---|---|---|---|---|---|---|")
    for (label, m, mean, half, p, n), rej, adj in zip(tests, reject, adjusted):
        diff = f"{mean:+.3g} ± {half:.2g}" if np.isfinite(half) else f"{mean:+.3g} (no test)"
        print(f"| {label} | {m} | {diff} | {n} | {p:.3g} | {adj:.3g} | {'yes' if rej else 'no'} |")


def parse_sets(doc, load_dir, default_label):
    """The command line shared with segment_start_table.py: DIR ... [--label ...] [--plot FILE];
    returns the arguments, a label per DIR and load_dir(DIR) of each, refusing an empty one."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--label", nargs="*")
    ap.add_argument("--plot")
    a = ap.parse_args()
    labels = a.label or [default_label(os.path.normpath(d)) for d in a.dirs]
    if len(labels) != len(a.dirs):
        sys.exit("--label: one name per DIR")
    sets = [load_dir(d) for d in a.dirs]
    for runs, d in zip(sets, a.dirs):
        if not runs:
            sys.exit(f"{d}: no complete run (seed<k>/results.h5)")
    return a, labels, sets


def main():
    a, labels, sets = parse_sets(__doc__, load, lambda d: "/".join(d.split(os.sep)[-2:]))
    for label, runs in zip(labels, sets):
        if len(runs) < 3:
            print(f"# warning: {label} has {len(runs)} run(s); intervals need more")
    mean_table(labels, sets, MEASURES)
    # Paired differences against the first set: the planned measures one BH family, the second
    # look after the first avalanche another.
    paired_table(labels, sets, MEASURES, "Paired")
    print("\nReading: a difference is a change in how the bed starts to flow that these seeds"
          " resolve; 'no' everywhere means none resolved at this N, not that there is none.")
    print("\nAfter the first avalanche (a second look, added once the mean curves showed an"
          " overshoot; its own family):\n")
    mean_table(labels, sets, AFTER)
    paired_table(labels, sets, AFTER, "After the first avalanche, paired")
    frozen_table(labels, sets)
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        any_frozen = any(r["frozen"] is not None for runs in sets for r in runs.values())
        fig, axes = plt.subplots(3 if any_frozen else 2, 1, figsize=(7, 8.5 if any_frozen else 6),
                                 sharex=True)
        ax1, ax2 = axes[0], axes[1]
        grid = np.arange(0, 50.5, 1.0)
        for label, runs in zip(labels, sets):
            def mean_curve(column):
                return np.mean([np.interp(grid, r["series"][0], r["series"][column])
                                for r in runs.values()], 0)
            sl, sp = mean_curve(1), mean_curve(2)
            line, = ax1.plot(grid, sl, label=f"{label} (N = {len(runs)})")
            ax2.plot(grid, sp, label=label, color=line.get_color())
            fr, _ = mean_frozen(runs, grid)
            if fr is not None:
                axes[2].plot(grid, fr, color=line.get_color())
        ax1.set_ylabel("surface slope (deg)")
        ax2.set_ylabel("surface speed / (omega R)")
        axes[-1].set_xlabel("rotation of the wall from the settled bed (deg)")
        ax2.axhline(CREEP, color="grey", lw=0.5, ls=":")
        if any_frozen:
            axes[2].set_ylabel("frozen share")
        for ax in axes:
            ax.axvline(BETA_ANGLE, color="grey", lw=0.5, ls="--")
        ax1.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=110)
        print(f"\nplot: {a.plot}")


if __name__ == "__main__":
    # Piped to `head`, the table stops where the reader stopped, without a traceback.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    main()
