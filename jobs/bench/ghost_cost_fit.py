#!/usr/bin/env python3
"""The halo model's per-ghost and per-particle costs fitted to instruction counts.

  /usr/bin/python3 jobs/bench/ghost_cost_fit.py results/bench/ghost_cost/counts.tsv

The TSV (jobs/bench/ghost_cost_callgrind.sh) holds, per rank count P, the engine's instructions
over all ranks for the same steps of the same scene, and the ghosts all ranks held. The halo model
(halo_model.py) charges each rank of a decomposed run c_p (1 + o) per particle-step and c_g per
ghost-step; summed over the ranks, the instructions beyond one rank's are

    I(P) - I(1) = o I(1) + c_g' G(P)            (P >= 2)

with c_g' in instructions per ghost-step, c_g = c_g' / (I(1) / N) in units of one particle-step
(c_p). Least squares over the P >= 2 rows gives o and c_g, with the residual of each row: if one
straight line fits from the fewest to the most ghosts per particle, the model's form holds over
that range (the fit cannot say what waiting costs: that is time, not instructions). Also printed:
each row's c_g with everything charged per ghost (o = 0), the form the model was calibrated with
before, and the halo_model.py command with the fitted constants."""
import argparse
import csv

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("tsv")
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.tsv), delimiter="\t"))
    by_p = {int(r["ranks"]): r for r in rows}
    if 1 not in by_p:
        raise SystemExit("no one-rank row: nothing to compare with")
    one = by_p[1]
    n = float(one["particles"])
    steps = float(one["steps"])
    i1 = float(one["engine_ir"]) / steps  # instructions per step, one rank
    per_particle = i1 / n
    print(f"one rank: {per_particle:.1f} engine instructions per particle-step ({n:.0f} particles)")
    print("| ranks | ghosts (all ranks) | ghosts per particle | instructions per particle-step | "
          "beyond one rank | per ghost-step, all charged per ghost (c_p) |")
    print("|---|---|---|---|---|---|")
    ps = sorted(p for p in by_p if p >= 2)
    extra, ghosts = [], []
    for p in ps:
        r = by_p[p]
        ip = float(r["engine_ir"]) / float(r["steps"])
        g = float(r["ghosts"])
        extra.append(ip - i1)
        ghosts.append(g)
        print(f"| {p} | {g:.0f} | {g / n:.3f} | {ip / n:.1f} | {(ip - i1) / n:+.1f} "
              f"({100 * (ip - i1) / i1:+.1f}%) | {(ip - i1) / g / per_particle:.3f} |")
    if len(ps) < 2:
        print("\n(one decomposed row: no fit of two constants)")
        return
    extra, ghosts = np.array(extra), np.array(ghosts)
    design = np.column_stack([np.full(len(ps), i1), ghosts])
    (o, cg_ir), *_ = np.linalg.lstsq(design, extra, rcond=None)
    cg = cg_ir / per_particle
    fit = design @ np.array([o, cg_ir])
    print(f"\nfit over P = {', '.join(map(str, ps))}: o = {o:.4f} (per particle-step, units of c_p), "
          f"c_g = {cg:.3f} c_p ({cg_ir:.0f} instructions per ghost-step)")
    print("residuals, instructions per particle-step: "
          + ", ".join(f"P = {p}: {(e - f) / n:+.2f}" for p, e, f in zip(ps, extra, fit)))
    print("\nthe halo model with these constants (the rates of the 16-core node, docs/performance.md;"
          " 2,000,000 sampled points: fewer read the largest domain's ghosts high; add --newton"
          " where the runs had parallel.newton = on, the default):")
    print("/usr/bin/python3 jobs/bench/halo_model.py --rate1 1.174e7 --rate2 1.983e7 --ghosts2 7917 "
          f"--imbalance2 1.004 --ranks 64 1024 --overlap --reach 1.1 --sample 2000000 --cg {cg:.2f} "
          f"--overhead {max(o, 0.0):.3f}")


if __name__ == "__main__":
    main()
