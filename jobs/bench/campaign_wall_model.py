#!/usr/bin/env python3
"""Wall time of a bst_paper study on C cores against the campaign's group size k (issue 15).

The study: 2 protocols x 3 replicas = 6 cases of 20 iterations at the standard tier. A case costs
T1 core-hours on one core; docs/accuracy.md, tier cost table, standard row ("| standard | 89,394 |
17.5 | 5e-4 | 1e-5 | ... | 20 | 1,233,333 | 6.15e6 | 5.0 h | 99.6 h |", line 44 at commit f70ed4b;
also line 278: "`standard` on bst_paper (5 core-hours per iteration)"): 5.0 h per iteration,
99.6 h for the 20 iterations, the default of --t1.

`tumble campaign` under C ranks with campaign.ranks_per_case = k makes g = floor(C / k) groups of
k consecutive ranks (C - g k ranks never get a case) and runs the 6 cases in waves of g:

    waves      = ceil(6 / g)
    case wall  = T1 / (k E(k))
    study wall = waves x case wall            (all cases cost the same; dispatch cost ignored:
                                               jobs/bench/bench_campaign_groups.sh measures it)

E(k), the efficiency of one bst_paper realization decomposed over k ranks, is the halo cost model
of jobs/bench/halo_model.py (its functions, unchanged) with the 89,394-particle bst_paper bed as
the target and the measured 1- and 2-rank rates as calibration (docs/performance.md:
--rate1 6.483e6 --rate2 1.165e7 --ghosts2 7852 --imbalance2 1.003). c_g, the cost per ghost-step,
is either calibrated from the 2-rank run (1.25 c_p, pessimistic: it holds the 2-rank work
imbalance) or 0.5 c_p (optimistic: the duplicated border pairs alone). At k = 2 the measured
imbalance (1.003) is used, above it the model's assumed --imbalance (1.05). k = 1 is today's
one-rank-per-case layout: E = 1, wall = T1 since 6 cases <= C.

Candidate k per C: powers of two, floor(C / g) for g = 1..6 (the largest k that gives g groups)
and 10, 21, 42, 85, 170, 341, all capped at C. Ghost counts depend on k only, so each k's count is
computed once and used for both c_g (about a minute on one core, mostly the counts at k >= 256).

    /usr/bin/python3 jobs/bench/campaign_wall_model.py
    /usr/bin/python3 jobs/bench/campaign_wall_model.py --cores 64 256 1024 --t1 99.6 --cases 6
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from halo_model import add_model_arguments, calibrate, ghosts_per_domain, step_parts  # noqa: E402


def candidates(cores, cases):
    ks = {1 << i for i in range(int(math.log2(cores)) + 1)}
    ks |= {cores // g for g in range(1, cases + 1) if cores // g >= 1}
    ks |= {10, 21, 42, 85, 170, 341}
    return sorted(k for k in ks if k <= cores)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t1", type=float, default=99.6, help="core-hours of one case on one core")
    ap.add_argument("--cases", type=int, default=6, help="cases of the study (2 protocols x 3 replicas)")
    ap.add_argument("--cores", type=int, nargs="+", default=[64, 256, 1024])
    ap.add_argument("--cg", type=float, nargs="+", default=[0, 0.5],
                    help="cost per ghost-step in c_p; 0 = calibrated from the 2-rank run")
    # halo_model.py's constants, with the bst_paper calibration of docs/performance.md
    add_model_arguments(ap, rate1=6.483e6, rate2=1.165e7, imbalance2=1.003)
    a = ap.parse_args()

    n = a.particles
    c_p, c_g_cal = calibrate(a)

    all_k = sorted(set(k for c in a.cores for k in candidates(c, a.cases)))
    gmax = {1: 0.0}
    for k in all_k:
        if k > 1:
            gmax[k] = ghosts_per_domain(n, k, a.reach, a.sample, np.random.default_rng(1),
                                        a.reach_large, a.large_share)[0]

    def efficiency(k, c_g):
        if k == 1:
            return 1.0
        return c_p * n / k / sum(step_parts(a, c_p, c_g, n, k, gmax[k], measured_two=k == 2))

    print(f"study: {a.cases} cases x {a.t1:g} core-hours (bst_paper, standard tier, 20 iterations); "
          f"{n:.0f} particles; c_p = {c_p * 1e9:.1f} ns, calibrated c_g = {c_g_cal * 1e9:.1f} ns "
          f"({c_g_cal / c_p:.2f} c_p)")
    for cg in a.cg:
        c_g = c_g_cal if cg == 0 else cg * c_p
        label = f"c_g = {c_g / c_p:.2f} c_p ({'calibrated, pessimistic' if cg == 0 else 'optimistic'})"
        for cores in a.cores:
            rows = []
            for k in candidates(cores, a.cases):
                g = cores // k
                used = min(g, a.cases)
                waves = math.ceil(a.cases / g)
                e = efficiency(k, c_g)
                case_wall = a.t1 / (k * e)
                wall = waves * case_wall
                rows.append(dict(k=k, g=g, idle=cores - used * k, waves=waves, e=e, ghosts=gmax[k],
                                 case=case_wall, wall=wall, alloc=cores * wall,
                                 busy=a.cases * k * case_wall))
            best = min(rows, key=lambda r: (r["wall"], r["k"]))
            print(f"\n### C = {cores} cores, {label}\n")
            print("| k | groups | idle cores | waves | ghosts/rank (max) | particles/rank | E(k) | "
                  "case wall (h) | **study wall (h)** | core-hours allocated (C x wall) | "
                  "core-hours in cases |")
            print("|---|---|---|---|---|---|---|---|---|---|---|")
            for r in rows:
                mark = " (best)" if r is best else (" (k = 1: today)" if r["k"] == 1 else "")
                print(f"| {r['k']}{mark} | {r['g']} | {r['idle']} | {r['waves']} | {r['ghosts']:.0f} | "
                      f"{n / r['k']:.0f} | {100 * r['e']:.1f}% | {r['case']:.2f} | **{r['wall']:.2f}** | "
                      f"{r['alloc']:.0f} | {r['busy']:.0f} |")
            one = rows[0]
            print(f"\nbest k = {best['k']}: {best['g']} groups, {best['idle']} idle cores, "
                  f"{best['waves']} wave(s), E = {100 * best['e']:.1f}%, wall {best['wall']:.2f} h "
                  f"({one['wall'] / best['wall']:.1f}x faster than k = 1's {one['wall']:.1f} h), "
                  f"{best['alloc']:.0f} core-hours allocated ({best['busy']:.0f} in cases; k = 1: "
                  f"{one['busy']:.0f} in cases, {one['alloc']:.0f} allocated if C cores are held)")


if __name__ == "__main__":
    main()
