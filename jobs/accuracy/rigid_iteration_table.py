#!/usr/bin/python3
"""The rigid bulk's speed-up over a whole iteration, from jobs/accuracy/rigid_iteration_ab.sh.

usage: jobs/accuracy/rigid_iteration_table.py OUT [-o plot.png] [--boot 10000] [--rigid NAME]
                                               [--base NAME] [--drop FIRST_STEP ...]
                                               [--label BASE_TEXT RIGID_TEXT]

Reads OUT/chunks.tsv (one line per chunk: variant, first step, steps, wall s) and the rigid run's
OUT/rigid/results.h5 (--rigid rigid_before: the run of the script's OTHER binary instead) (its
frozen share per analysis sample and the resolved scene, whose protocol gives the six segments of
a biaxial iteration). --base rigid_before --rigid rigid compares two rigid runs (a job with
VARIANTS="rigid rigid_before": a setting against the defaults) instead of dynamic and rigid.
Pairs each rigid chunk with the dynamic chunk over the same steps (run minutes apart, so the
machine's load falls on both alike) and prints, per segment of the protocol, the steps covered,
the two wall times, their ratio and the mean frozen share; then the iteration's ratio dynamic /
rigid as the ratio of the summed wall times, with a 95% interval from a bootstrap over the paired chunks (resampled within each segment, so that every
segment keeps its weight). The interval says how much the chunks' scatter (the machine's noise)
moves the ratio; it does not cover a change of machine. --drop leaves out the pairs that start at
the given steps (a pair one of whose chunks shared the cores with other work, e.g. a build: the
pairing evens out the machine's load only when both chunks see it); the dropped pairs are listed.
--label names the two runs in the table and the plot by what they are ("margin 3" "margin 5")
rather than by the script's variant names.

While one half of the iteration is not run (the job unfinished, or started from a checkpoint of the
other half: OUT holding only the x half), its segments are estimated from their twins in the half
that is, by the protocol's symmetry (the same angles about the other axis): printed as an estimate,
labelled so.
"""
import argparse
import csv
import os
import signal
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
from plot_frozen import load as load_frozen  # noqa: E402
from plot_frozen import segment_edges  # noqa: E402

NAMES = ["tilt by beta", "rotate about z", "tilt back", "tilt by beta (2)", "rotate about x",
         "tilt back (2)"]


def read_chunks(path):
    by = {}
    with open(path) as f:
        for r in csv.DictReader(f, delimiter="\t"):
            by.setdefault(r["variant"], {})[int(r["first_step"])] = (int(r["steps"]),
                                                                     float(r["wall_s"]))
    return by


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("-o", "--output", help="plot of the chunks' wall times and the frozen share")
    ap.add_argument("--boot", type=int, default=10000)
    ap.add_argument("--rigid", default="rigid", help="the rigid run to compare with dynamic")
    ap.add_argument("--base", default="dynamic", help="the run it is compared with")
    ap.add_argument("--drop", type=int, nargs="*", default=[],
                    help="first steps of pairs to leave out (a chunk run beside other work)")
    ap.add_argument("--label", nargs=2, metavar=("BASE_TEXT", "RIGID_TEXT"),
                    help="what the two runs are, for the table and the plot (default: their names)")
    args = ap.parse_args()
    rv, bv = args.rigid, args.base
    bl, rl = args.label if args.label else (bv, rv)
    by = read_chunks(os.path.join(args.out, "chunks.tsv"))
    if rv not in by or bv not in by:
        raise SystemExit(f"no paired chunks of {bv} and {rv} yet (both need at least one)")
    frozen, iteration, text = load_frozen(os.path.join(args.out, rv))
    edges = segment_edges(text)
    if len(edges) != 6:
        raise SystemExit("not a biaxial protocol: no segments to report")
    first = sorted(k for k in by[rv] if k in by[bv] and by[rv][k][0] == by[bv][k][0])
    for k in args.drop:
        if k in first:
            print(f"# left out: the pair at step {k} ({bv} {by[bv][k][1]:.0f} s, "
                  f"{rv} {by[rv][k][1]:.0f} s)")
        else:
            print(f"# --drop {k}: no such pair")
    first = [k for k in first if k not in set(args.drop)]
    if not first:
        raise SystemExit("no chunk of the same steps in both variants yet")
    steps = np.array([by[rv][k][0] for k in first], float)
    mid = np.array(first, float) + steps / 2
    d = np.array([by[bv][k][1] for k in first])
    r = np.array([by[rv][k][1] for k in first])
    n_iter = estimate_steps(args.out)
    frac = mid / n_iter
    seg = np.searchsorted(np.array(edges), frac, side="right")
    seg = np.minimum(seg, 5)
    print(f"# {args.out}: {len(first)} paired chunks, {int(steps.sum())} of {n_iter} steps"
          f" ({steps.sum() / n_iter:.1%} of the iteration)")
    print(f"| segment (share of the iteration) | steps run | {bl} wall s | {rl} wall s |"
          f" {bl} / {rl} | per-chunk ratio, median (range) | mean frozen share ({rl}) |")
    print("|---|---|---|---|---|---|---|")
    lo = 0.0
    rng = np.random.default_rng(1)
    for s in range(6):
        hi = edges[s]
        m = seg == s
        fm = (iteration % 1 >= lo) & (iteration % 1 < hi) & (iteration < 1)
        fz = f"{frozen[fm].mean():.3f}" if fm.any() else "-"
        if m.any():
            q = d[m] / r[m]
            print(f"| {NAMES[s]} ({lo:.3f}-{hi:.3f}) | {int(steps[m].sum())} | {d[m].sum():.0f} |"
                  f" {r[m].sum():.0f} | **{d[m].sum() / r[m].sum():.2f}** | {np.median(q):.2f}"
                  f" ({q.min():.2f}-{q.max():.2f}) | {fz} |")
        else:
            print(f"| {NAMES[s]} ({lo:.3f}-{hi:.3f}) | 0 | - | - | - | - | {fz} |")
        lo = hi

    def boot_ratio(mask_segments):
        idx = [np.flatnonzero(seg == s) for s in mask_segments if (seg == s).any()]
        out = np.empty(args.boot)
        for b in range(args.boot):
            pick = np.concatenate([rng.choice(i, len(i)) for i in idx])
            out[b] = d[pick].sum() / r[pick].sum()
        return np.percentile(out, [2.5, 97.5])

    ratio = d.sum() / r.sum()
    lo95, hi95 = boot_ratio(range(6))
    print(f"\nRun so far ({steps.sum() / n_iter:.1%} of the iteration): {bl} {d.sum():.0f} s,"
          f" {rl} {r.sum():.0f} s, **{bl} / {rl} = {ratio:.2f}** (95% bootstrap interval over"
          f" the paired chunks {lo95:.2f}-{hi95:.2f}).")
    # By the protocol's symmetry (the same angles about the other axis) a segment not fully run
    # takes the seconds per step of its twin in the other half, where that one is fully run.
    starts = np.array(first, float)

    def fully_run(s):
        """The paired chunks cover the segment's steps (a chunk counts for the segment its
        middle falls in, so one that straddles a change of segment covers its neighbour's start)."""
        lo_step, hi_step = (edges[s - 1] if s else 0.0) * n_iter, edges[s] * n_iter
        reach = lo_step
        for a, b in sorted(zip(starts, starts + steps)):
            if a <= reach < b:
                reach = b
        return reach >= hi_step - 1

    full = [fully_run(s) for s in range(6)]
    if any(full) and not all(full):
        dd, rr, borrowed = 0.0, 0.0, []
        for s in range(6):
            seg_steps = (edges[s] - (edges[s - 1] if s else 0.0)) * n_iter
            if full[s]:
                src = seg == s
            elif full[(s + 3) % 6]:
                src = seg == (s + 3) % 6
                borrowed.append(NAMES[s])
            else:
                print(f"Whole iteration: no estimate, neither '{NAMES[s]}' nor its twin is fully run.")
                break
            dd += d[src].sum() / steps[src].sum() * seg_steps
            rr += r[src].sum() / steps[src].sum() * seg_steps
        else:
            print(f"Whole iteration, {', '.join(borrowed)} taken from their twins in the other half"
                  f" (an estimate by the protocol's symmetry): {bl} {dd:.0f} s, {rl} {rr:.0f} s,"
                  f" **{dd / rr:.2f}x**.")
    if args.output:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 3.4))
        ax.plot(frac, d / steps * 1000, "o-", ms=3, lw=1, label=bl)
        ax.plot(frac, r / steps * 1000, "s-", ms=3, lw=1, label=rl)
        ax.set_xlabel("protocol iteration")
        ax.set_ylabel("wall s per 1,000 steps")
        for e in edges[:-1]:
            ax.axvline(e, color="0.6", lw=0.6, ls=":")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, None)
        ax2 = ax.twinx()
        ax2.plot(iteration, frozen, color="0.5", lw=0.8, label=f"frozen share ({rl})")
        ax2.set_ylim(0, 1)
        ax2.set_ylabel("share of the bed frozen")
        h1, l1 = ax.get_legend_handles_labels()
        h2, l2 = ax2.get_legend_handles_labels()
        ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper right")
        fig.tight_layout()
        fig.savefig(args.output, dpi=130)
        print(f"wrote {args.output}")


def estimate_steps(out):
    """Steps per iteration from the runs' own first line ("... N steps (T s simulated, 1
    iterations"): the job runs one iteration."""
    for v in ("rigid", "dynamic", "rigid_before"):
        path = os.path.join(out, f"{v}.log")
        if os.path.exists(path):
            with open(path) as f:
                for line in f:
                    if " particles, dt = " in line and " steps (" in line:
                        return int(line.split(" steps (")[0].split()[-1])
    raise SystemExit("cannot tell the iteration's steps: no run log in " + out)


if __name__ == "__main__":
    # Piped to `head`, the table stops where the reader stopped, without a traceback.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    main()
