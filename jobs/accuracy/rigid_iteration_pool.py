#!/usr/bin/python3
"""The chunks of several jobs/accuracy/rigid_iteration_ab.sh jobs over one bst_paper (57°, 57°)
iteration at beta = 27° (1,233,333 steps; the six segments' edges below), pooled: dynamic / rigid
over all their paired chunks, a 95% bootstrap over the pairs within each segment (a chunk counts
for the segment its middle falls in), and per segment the steps, wall seconds and ratio.

usage: rigid_iteration_pool.py OUT[:FIRST-END] [OUT[:FIRST-END] ...]
FIRST-END keeps a job's chunks whose first step lies in [FIRST, END) (a job whose later chunks
ran another binary, or overlap another job's)."""
import csv
import sys

import numpy as np

N = 1233333
EDGES = [0.122, 0.378, 0.5, 0.622, 0.878, 1.01]  # tilt, rotate z, tilt back, tilt, rotate x, tilt back


def main():
    pairs = []
    for arg in sys.argv[1:]:
        out, _, span = arg.partition(":")
        first, end = (int(v) for v in span.split("-")) if span else (0, N)
        by = {}
        for r in csv.DictReader(open(out + "/chunks.tsv"), delimiter="\t"):
            by.setdefault(r["variant"], {})[int(r["first_step"])] = (int(r["steps"]), float(r["wall_s"]))
        for k, (n, r) in by.get("rigid", {}).items():
            if first <= k < end and k in by.get("dynamic", {}) and by["dynamic"][k][0] == n:
                pairs.append((k, n, by["dynamic"][k][1], r))
    if not pairs:
        raise SystemExit("no paired chunks")
    k, n, d, r = map(np.array, zip(*pairs))
    seg = np.searchsorted(EDGES, (k + n / 2) / N, side="right")
    print(f"{len(k)} paired chunks, {n.sum()} steps: dynamic {d.sum():.0f} s, rigid {r.sum():.0f} s,"
          f" dynamic / rigid {d.sum() / r.sum():.2f}")
    rng = np.random.default_rng(1)
    idx = [np.flatnonzero(seg == s) for s in range(6) if (seg == s).any()]
    boot = [d[p].sum() / r[p].sum()
            for p in (np.concatenate([rng.choice(i, len(i)) for i in idx]) for _ in range(10000))]
    print("95%% bootstrap over the pairs within segments: %.2f-%.2f" % tuple(np.percentile(boot, [2.5, 97.5])))
    for s in range(6):
        m = seg == s
        if m.any():
            print(f"segment {s + 1}: {n[m].sum()} steps, dynamic {d[m].sum():.0f} s, rigid {r[m].sum():.0f} s,"
                  f" {d[m].sum() / r[m].sum():.2f}")


if __name__ == "__main__":
    main()
