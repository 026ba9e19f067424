#!/usr/bin/env python3
"""Table of each fidelity tier's error against the reference tier (docs/accuracy.md).

Reads OUT/<tier>/seed<k>/results.h5 written by jobs/accuracy/flow_accuracy.sh. Per run: the means
of the repose angle, the surface speed (also divided by the tumbler's speed omega R) and the
large-particle fraction of the wall shell over the samples at 40-80 degrees of rotation, and the
wall time of the protocol phase. Per tier: mean and 95% CI over replicas (Student t from scipy;
the wall's large fraction, a share, with the interval cut at [0, 1]); the error against the
reference (or, without reference runs, the standard tier) is the difference of means with its
Welch 95% CI (real degrees of freedom; cut at ±1 for the share); no interval below 2 runs a side.

Then the surface velocity profile (runs that kept series/surface_profile): per run the mean over
the same window of the downhill speed per bin, divided by omega R, against h/R; per tier the mean
± CI per bin on the reference's bins (other grids interpolated linearly: preview coarsens the
bed), and the profile error of each run, the RMS over bins of its difference from the reference
tier's mean profile (the reference's own runs against the mean of the others: the replica
ceiling), mean ± CI, with the Welch difference from the reference's; and the same RMS over the
bins that hold grains in at least 90% of the window's samples in every reference run (the bins at
the layer's two ends, where the surface meets the wall, are empty part of the time, rest on a
few grains and would otherwise dominate the RMS).

--plot FILE.png draws the profiles (mean and 95% CI per bin), the paired difference rigid −
dynamic per bin (mean and 95% CI over the common beds) and the rigid runs' frozen share against
the rotation angle.

Last, for each rigid-bulk tier beside its own dynamic tier (flow_accuracy.sh with BULK=rigid: the
two runs of a seed start from the same settled bed): the frozen share of the bed over 0-35° (the
solid-body phase) and 40-80° (the flow), the paired differences rigid − dynamic by seed (Student
t on the differences) of every observable and profile bin, and the Benjamini-Hochberg procedure
at q = 0.05 over that family (observables and bins, Welch and paired counted as separate tests).
"""
import glob
import math
import os
import signal
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
from postproc.report_stats import (bh_reject, bounded_interval, compare_values,  # noqa: E402
                                   interval_bounds_text, mean_ci, welch_test)
from scipy import stats  # noqa: E402

# The observables' physical bounds (None: none): the wall's large fraction is a share.
BOUNDS = {"wall large fraction": (0.0, 1.0)}


def is_complete(path):
    """Whether a run reached its protocol's end (results.h5 attribute `complete`; files from
    before the attribute existed count as complete)."""
    with h5py.File(path, "r") as f:
        return bool(f.attrs.get("complete", 1))


def run_means(path):
    with h5py.File(path, "r") as f:
        t = f["series/time"][:]
        scene = f.attrs["scene"]
        scene = scene.decode() if isinstance(scene, bytes) else scene
        kv = dict(line.split(" = ", 1) for line in scene.splitlines() if " = " in line)
        rpm = float(kv["protocol.rpm"])
        radius = float(kv["tumbler.radius"])
        omega = 2 * math.pi * rpm / 60
        angle = np.degrees(omega * t)
        win = (angle >= 40) & (angle <= 80)
        rep = f["series/repose_angle"][:][win]
        spd = f["series/surface_speed"][:][win]
        wall = f["series/shell_large_fraction"][:][win]
        profile = fill = None
        if "series/surface_profile" in f:
            prof = f["series/surface_profile"][:][win] / (omega * radius)
            with np.errstate(all="ignore"):
                profile = (f["series/surface_profile_h"][:] / radius, np.nanmean(prof, axis=0))
            fill = np.isfinite(prof).mean(axis=0)  # share of the samples with grains in the bin
        frozen, frozen_series = {}, None
        if "series/frozen_fraction" in f:
            ff = f["series/frozen_fraction"][:]
            frozen = {"0-35": np.nanmean(ff[angle <= 35]), "40-80": np.nanmean(ff[win])}
            frozen_series = (angle, ff)
        wall_s = float(f.attrs["particles"]) * float(f.attrs["steps"]) / float(
            f.attrs["particle_steps_per_second"])
        return {
            "repose angle (deg)": np.nanmean(rep),
            "surface speed (m/s)": np.nanmean(spd),
            "surface speed / (omega R)": np.nanmean(spd) / (omega * radius),
            "wall large fraction": np.nanmean(wall),
            "wall s": wall_s,
            "particles": int(f.attrs["particles"]),
            "rpm": rpm,
            "profile": profile,
            "profile_fill": fill,
            "frozen": frozen,
            "frozen_series": frozen_series,
            "seed": int(f.attrs["seed"]),
            "ranks": int(f.attrs["ranks"]) if "ranks" in f.attrs else None,
        }


def mean_text(values, lo=None, hi=None):
    """'m ± h' of a quantity without bounds, 'm [lower, upper]' (Student's interval cut at the
    bounds) of one with; 'm (N = 1)' without an interval, '—' without a value."""
    b = bounded_interval(values, lo, hi)
    if not b["n"]:
        return "—"
    if not np.isfinite(b["lower"]):
        return f"{b['mean']:.4g} (N = 1)"
    if lo is None and hi is None:
        return f"{b['mean']:.4g} ± {(b['upper'] - b['lower']) / 2:.2g}"
    lower, upper = interval_bounds_text(b)
    return f"{b['mean']:.4g} [{lower}, {upper}]"


def error_text(base, runs, lo=None, hi=None, digits=3):
    """mean(runs) − mean(base) with Welch's 95% interval (real degrees of freedom; cut at
    ±(hi − lo) for a quantity in [lo, hi]): 'd ± h', or 'd [lower, upper]' where cut; no
    interval ('(N < 2)') when either side has fewer than 2 runs."""
    c = compare_values(runs, base, lo, hi)
    if not np.isfinite(c["est"]):
        return "—"
    d = f"{c['est']:+.{digits}g}"
    if not np.isfinite(c["lower"]):
        return d + " (N < 2: no interval)"
    half = (c["upper"] - c["lower"]) / 2
    if abs(c["est"] - half - c["lower"]) < 1e-12 and abs(c["est"] + half - c["upper"]) < 1e-12:
        return f"{d} ± {half:.2g}"
    return f"{d} [{c['lower']:+.2g}, {c['upper']:+.2g}]"


def main():
    args = sys.argv[1:]
    plot = None
    if "--plot" in args:
        k = args.index("--plot")
        if k + 1 >= len(args):
            sys.exit("--plot takes a file name (.png)")
        plot = args[k + 1]
        del args[k:k + 2]
    if len(args) != 1:
        sys.exit("usage: accuracy_table.py OUT [--plot FILE.png]")
    out = args[0]
    # Each tier, then its rigid-bulk runs (flow_accuracy.sh with BULK=rigid).
    tiers = [t + b for t in ["reference", "standard", "fast", "preview"] for b in ["", "-rigid"]]
    data = {}
    for tier in tiers:
        paths = sorted(glob.glob(os.path.join(out, tier, "seed*", "results.h5")))
        done = [p for p in paths if is_complete(p)]
        for p in sorted(set(paths) - set(done)):  # stopped part-way: its window is not whole
            print(f"# left out (stopped before its end; rerun the script to finish it): {p}")
        runs = [run_means(p) for p in done]
        if runs:
            data[tier] = runs
    # The errors are against the most accurate dynamic tier that ran.
    base = next((t for t in tiers if t in data and not t.endswith("-rigid")), None)
    if base is None:
        sys.exit("no dynamic runs in " + out)
    obs = ["repose angle (deg)", "surface speed (m/s)", "surface speed / (omega R)",
           "wall large fraction"]
    ranks = {r["ranks"] for runs in data.values() for r in runs}
    on = (f"{ranks.pop()} rank{'s' if len(ranks) != 1 else ''}" if len(ranks) == 1 and None not in ranks
          else "ranks as run")
    print(f"| tier | N | particles | rpm | wall s per run ({on}) | " +
          " | ".join(f"{o}: mean ± CI | error vs {base} ± CI" for o in obs) + " |")
    print("|---" * (5 + 2 * len(obs)) + "|")
    for tier in tiers:
        if tier not in data:
            continue
        runs = data[tier]
        cells = [tier, str(len(runs)), str(runs[0]["particles"]), f"{runs[0]['rpm']:.3g}",
                 f"{np.mean([r['wall s'] for r in runs]):.0f}"]
        for o in obs:
            lo, hi = BOUNDS.get(o, (None, None))
            cells.append(mean_text([r[o] for r in runs], lo, hi))
            if tier == base:
                cells.append("—")
            else:
                cells.append(error_text([r[o] for r in data[base]], [r[o] for r in runs], lo, hi))
        print("| " + " | ".join(cells) + " |")
    profile_table(data, base)
    for dname, rname in rigid_beside_dynamic(data):
        paired_table(data[dname], data[rname], dname, rname)
    if plot:
        plot_runs(data, plot)


def plot_runs(data, path):
    """The surface velocity profile of each tier (mean and 95% CI per bin, on its own bins); where
    a rigid bulk ran beside its dynamic tier, the paired difference rigid - dynamic per bin (mean
    and 95% CI over the common beds) and the frozen share against the rotation angle (a line a
    seed). The axes are scaled to the means: the edge bins, which few samples reach, have CIs many
    times the profile's height and would flatten it."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    frozen = {t: runs for t, runs in data.items() if any(r["frozen_series"] is not None for r in runs)}
    rigid = rigid_beside_dynamic(data)
    panels = 1 + bool(rigid) + bool(frozen)
    fig, axes = plt.subplots(1, panels, figsize=(5.5 * panels, 4), squeeze=False)
    ax = axes[0][0]
    means = []
    for t, runs in data.items():
        runs = [r for r in runs if r["profile"] is not None]
        if not runs:
            continue
        h = runs[0]["profile"][0]
        m, ci = per_bin(np.array([on_grid(r, h) for r in runs]))
        means.append(m)
        line, = ax.plot(h, m, "o-", label=f"{t} (N = {len(runs)})")
        if np.isfinite(ci).any():
            ax.fill_between(h, m - ci, m + ci, color=line.get_color(), alpha=0.2)
    scale_to(ax, means)
    ax.set_xlabel("h / R (across the surface; the layer flows towards -h)")
    ax.set_ylabel("downhill surface speed / (omega R), 40-80 deg")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    if rigid:
        ax = axes[0][1]
        diffs = []
        for dname, rname in rigid:
            pairs = [(d, r) for d, r in pairs_by_seed(data[dname], data[rname])
                     if d["profile"] is not None and r["profile"] is not None]
            if not pairs:
                continue
            h = pairs[0][0]["profile"][0]
            m, ci = per_bin(np.array([on_grid(r, h) - on_grid(d, h) for d, r in pairs]))
            diffs.append(m)
            ax.errorbar(h, m, yerr=np.where(np.isfinite(ci), ci, 0), fmt="o-", capsize=3,
                        label=f"{rname} - {dname} ({len(pairs)} beds)")
        ax.axhline(0, color="k", lw=0.8)
        scale_to(ax, diffs + [np.zeros(1)])
        ax.set_xlabel("h / R")
        ax.set_ylabel("paired difference / (omega R), mean and 95% CI")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    if frozen:
        ax = axes[0][-1]
        for t, runs in frozen.items():
            for r in runs:
                if r["frozen_series"] is not None:
                    ax.plot(*r["frozen_series"], lw=1, label=f"{t} seed {r['seed']}")
        ax.axvspan(40, 80, color="0.9", zorder=0, label="the averaging window")
        ax.set_xlabel("rotation (deg)")
        ax.set_ylabel("frozen share of the bed")
        ax.set_ylim(0, 1)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"# plot: {path}")


def rigid_beside_dynamic(data):
    """(dynamic tier, rigid tier) for each rigid-bulk tier run beside its own dynamic tier."""
    return [(t[:-len("-rigid")], t) for t in data
            if t.endswith("-rigid") and t[:-len("-rigid")] in data]


def pairs_by_seed(dyn, rig):
    """(dynamic run, rigid run) for each seed both ran: the two runs of one settled bed."""
    by_seed = {r["seed"]: r for r in dyn}
    return [(by_seed[r["seed"]], r) for r in rig if r["seed"] in by_seed]


def per_bin(vals):
    """Mean and 95% CI half-width of each bin (column) of a runs × bins array."""
    s = [mean_ci(vals[:, b]) for b in range(vals.shape[1])]
    return np.array([x[0] for x in s]), np.array([x[1] for x in s])


def scale_to(ax, curves):
    """The y range of the curves' finite values, a quarter of it added either side."""
    v = np.concatenate([np.asarray(c, float).ravel() for c in curves]) if curves else np.array([])
    v = v[np.isfinite(v)]
    if v.size:
        lo, hi = v.min(), v.max()
        pad = 0.25 * (hi - lo) if hi > lo else 0.5
        ax.set_ylim(lo - pad, hi + pad)


def paired_table(dyn, rig, dname, rname):
    """Rigid against dynamic seed by seed (the same bed): frozen share, paired and Welch
    differences of the observables and the profile bins, Benjamini-Hochberg over all of them."""
    obs = ["repose angle (deg)", "surface speed / (omega R)", "wall large fraction"]
    pairs = pairs_by_seed(dyn, rig)
    print()
    print(f"{rname} against {dname}, paired by seed ({len(pairs)} pairs on common beds)")
    fr = [r["frozen"] for r in rig if r["frozen"]]
    if fr:
        for phase in ("0-35", "40-80"):
            print(f"# frozen share of the bed, {phase} degrees: "
                  + ", ".join(f"{x[phase]:.3f}" for x in fr))
    rows = [(o, [d[o] for d, _ in pairs], [r[o] for _, r in pairs]) for o in obs]
    if pairs and all(d["profile"] is not None and r["profile"] is not None for d, r in pairs):
        h = pairs[0][0]["profile"][0]
        for b, hb in enumerate(h):
            rows.append((f"profile h/R {hb:+.2f}", [on_grid(d, h)[b] for d, _ in pairs],
                         [on_grid(r, h)[b] for _, r in pairs]))
    print("| observable | paired Δ (rigid − dynamic) ± 95% CI | p paired | Welch Δ ± 95% CI | p Welch |")
    print("|---|---|---|---|---|")
    tests = []
    for name, dv, rv in rows:
        dv, rv = np.asarray(dv, float), np.asarray(rv, float)
        ok = np.isfinite(dv) & np.isfinite(rv)
        diff = rv[ok] - dv[ok]
        m, ci, n = mean_ci(diff)
        pp = (float(stats.ttest_1samp(diff, 0.0).pvalue) if n >= 2 and diff.std(ddof=1) > 0
              else float("nan"))
        w = welch_test(rv, dv)
        tests += [(name, "paired", pp), (name, "Welch", w["p"])]
        half = f" ± {ci:.2g}" if np.isfinite(ci) else " (N < 2)"
        whalf = f" ± {w['half']:.2g}" if np.isfinite(w["half"]) else " (N < 2)"
        print(f"| {name} | {m:+.3g}{half} | {pp:.3g} | {w['diff']:+.3g}{whalf} | {w['p']:.3g} |")
    p = np.array([t[2] for t in tests], float)
    reject, adjusted = bh_reject(p, 0.05)
    m = int(np.isfinite(p).sum())
    print(f"# Benjamini-Hochberg at q = 0.05 over {m} tests: {int(reject.sum())} significant"
          + (f"; smallest p {np.nanmin(p):.3g} ({tests[int(np.nanargmin(p))][0]},"
             f" {tests[int(np.nanargmin(p))][1]}), adjusted {np.nanmin(adjusted):.3g}" if m else ""))
    for (name, kind, _), r, a in zip(tests, reject, adjusted):
        if r:
            print(f"#   significant: {name} ({kind}), adjusted p {a:.3g}")
    n = len(pairs)
    if n < 2:
        print(f"# warning: {n} pair(s): no interval and no test; the differences above are one"
              " bed's, not an estimate of the mean.")
    elif n < 5:
        print(f"# warning: {n} pairs: at N = {n} a 95% CI spans ±{stats.t.ppf(0.975, n - 1):.2g}"
              f" standard errors (t(0.975, {n - 1})); 'not significant' means 'not resolved at"
              " this N', not 'equal'.")


FILLED = 0.9  # a profile bin counts as filled when it holds grains in this share of the samples


def on_grid(run, h):
    """A run's scaled profile interpolated to the bin centres h/R (NaN outside its own bins)."""
    rh, rv = run["profile"]
    ok = np.isfinite(rv)
    if ok.sum() < 2:
        return np.full(len(h), np.nan)
    return np.interp(h, rh[ok], rv[ok], left=np.nan, right=np.nan)


def profile_table(data, base):
    data = {t: [r for r in runs if r["profile"] is not None] for t, runs in data.items()}
    data = {t: runs for t, runs in data.items() if runs}
    if base not in data or len(data[base]) < 2:  # e.g. runs from before profiles were kept
        base = next((t for t, runs in data.items() if len(runs) >= 2), None)
        if base is None:
            return
    h = data[base][0]["profile"][0]
    ref = np.array([on_grid(r, h) for r in data[base]])
    # The bins that every run of the base has grains in at nearly every sample: those at the
    # layer's ends (where the free surface meets the wall) are empty in part of the samples, their
    # means rest on a few grains, and in an RMS over all bins they outweigh the rest.
    fills = [r["profile_fill"] for r in data[base]]
    filled = (np.all([f >= FILLED for f in fills], axis=0) if all(len(f) == len(h) for f in fills)
              else np.ones(len(h), bool))

    def rms_of(t, bins):
        vals = []
        for k, r in enumerate(data[t]):
            mean = np.nanmean(np.delete(ref, k, axis=0), axis=0) if t == base else np.nanmean(ref, axis=0)
            d = (on_grid(r, h) - mean)[bins]
            vals.append(float(np.sqrt(np.nanmean(d * d))) if np.isfinite(d).any() else np.nan)
        return [v for v in vals if np.isfinite(v)]
    print()
    print(f"Surface velocity profile, downhill speed / (omega R), 40-80 degrees; bins of {base}")
    print("| h / R | " + " | ".join(f"{t} (N = {len(r)})" for t, r in data.items()) + " |")
    print("|---" * (1 + len(data)) + "|")
    for b, hb in enumerate(h):
        cells = []
        vb = [x for x in ref[:, b] if np.isfinite(x)]
        for t, runs in data.items():
            v = [x for x in (on_grid(r, h)[b] for r in runs) if np.isfinite(x)]
            c = mean_text(v)
            if t != base and len(v) >= 2 and len(vb) >= 2:
                c += f"; Δ {error_text(vb, v, digits=2)}"
            cells.append(c)
        print(f"| {hb:+.2f} | " + " | ".join(cells) + " |")
    rows = [(f"RMS from {base}'s mean profile, all {len(h)} bins", np.ones(len(h), bool))]
    if 0 < filled.sum() < len(h):
        rows.append((f"the same over the {int(filled.sum())} bins filled in ≥ {FILLED:.0%} of every"
                     f" {base} run's samples (h/R {h[filled].min():+.2f} to {h[filled].max():+.2f})",
                     filled))
    for label, bins in rows:
        rms = {t: rms_of(t, bins) for t in data}
        cells = []
        for t in data:
            c = mean_text(rms[t], 0.0, np.inf)  # an RMS is >= 0
            if t != base and len(rms[t]) >= 2 and len(rms[base]) >= 2:
                c += f"; Δ {error_text(rms[base], rms[t])}"
            cells.append(c)
        print(f"| {label} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    # Piped to `head`, the table stops where the reader stopped, without a traceback.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    main()
