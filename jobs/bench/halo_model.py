#!/usr/bin/env python3
"""Halo cost model of the domain-decomposed engine (issue 3; docs/performance.md).

Per step, the slowest rank of P costs

    T(P) = c_p * (1 + o) * n(P) + c_g * G(P) + lat(P) + bytes(P) / B_net

  n(P)   particles on the busiest rank (N/P times the measured imbalance)
  G(P)   ghosts held by the busiest rank: counted here by laying N particles at the measured number
         density into a half-full sphere, bisecting it as src/parallel/rcb.cpp does (longest side of
         the particles' bounding box, count-weighted cut) and counting, for every domain, the
         particles of other domains within their halo reach of it (r_i + r_max + skin: 1.6 d_small
         for a small particle, 2.1 for a large one)
  c_p    seconds per particle-step on one core (measured, 1-rank run)
  o      the work a decomposed rank adds per particle whatever its ghosts (--overhead, default 0:
         all of the second rank's extra work charged per ghost, as calibrated): the per-step
         synchronisation and the decomposed rebuild's spring and id bookkeeping, which instruction
         counts of 1 and 2 ranks separate from the per-ghost work (docs/performance.md)
  c_g    seconds per ghost per step: the border pairs computed twice (Newton off; once with
         Newton across borders, which adds the packing and adding of the ghosts' force sums), the
         refresh packing/unpacking and the amortised rebuild exchange; calibrated from the 2-rank
         run: c_g = (T_2 - c_p n(2) - lat(2)) / G(2), or counted (ghost_cost_fit.py)
  lat(P) per-step latency: one message to each neighbour domain + one allreduce (the rebuild test)
  bytes  72 bytes per ghost per step (x, v, w), over a network of B_net bytes/s

With --overlap (the engine since 2026-11-26: the ghosts' refresh travels while the rank computes
the pairs of its interior rows, those with no ghost partner) the messages' latency and transfer
are hidden up to the interior rows' share of the compute, 1 - B(P)/n(P), with B(P) the particles
of the busiest rank that may pair with a ghost (taken equal to its ghost count: the halo is
symmetric); the allreduce of the rebuild test is not hidden:

    T(P) = c_p n + c_g G + lat_allreduce + max(0, lat_messages + bytes / B_net - c_p (n - G))

With --newton (Newton across borders, parallel.newton = on) the ghosts' force sums travel back
after the border rows, one more message per neighbour and 48 bytes per ghost; the engine splits
the interior rows in halves, the first behind the refresh and the second behind the sums:

    T(P) = c_p n + c_g G + lat_allreduce + max(0, lat_messages + bytes / B_net - c_p (n - G) / 2)
                                         + max(0, lat_messages + bytes_back / B_net - c_p (n - G) / 2)

(without --overlap both rounds of messages are added whole).

Efficiency E(P) = c_p N / P / T(P). Run with the measured numbers (defaults: bst_paper, this
machine, 2026-11-22) to reproduce the table in docs/performance.md.
"""
import argparse

import numpy as np


def rcb(points, ranks, lo, hi):
    """Leaf boxes of the count-weighted bisection of `points` into `ranks` parts."""
    if ranks == 1:
        return [(lo.copy(), hi.copy(), len(points))]
    d = int(np.argmax(points.max(axis=0) - points.min(axis=0))) if len(points) else int(np.argmax(hi - lo))
    n_lo = ranks // 2
    k = len(points) * n_lo // ranks
    order = np.argpartition(points[:, d], k) if 0 < k < len(points) else np.arange(len(points))
    below, above = points[order[:k]], points[order[k:]]
    cut = 0.5 * (below[:, d].max() + above[:, d].min()) if len(below) and len(above) else lo[d]
    hi_lo, lo_hi = hi.copy(), lo.copy()
    hi_lo[d] = cut
    lo_hi[d] = cut
    return rcb(below, n_lo, lo, hi_lo) + rcb(above, ranks - n_lo, lo_hi, hi)


def half_sphere(n_points, rng):
    """Uniform points in the lower half ball of radius 1 (the bed of a half-full tumbler)."""
    out = []
    while sum(len(o) for o in out) < n_points:
        p = rng.uniform(-1, 1, size=(2 * n_points, 3))
        p = p[(np.einsum("ij,ij->i", p, p) < 1) & (p[:, 1] < 0)]
        out.append(p)
    return np.concatenate(out)[:n_points]


def ghosts_per_domain(n_total, ranks, reach_d, sample, rng, reach_large_d=None, large_share=0.0):
    """Largest ghost count and the mean over domains, for n_total particles at one per d^3.

    reach_d: how far from a domain (centre to box, in d_small) a particle is a ghost there. With
    reach_large_d and large_share (their share of the particles by number), that share of the
    sampled points reaches reach_large_d instead: the engine's halo is r_i + r_max + skin, so a
    small particle's is thinner than a large one's."""
    radius_d = (3 * n_total / (2 * np.pi)) ** (1 / 3)  # half ball of n_total d^3
    pts = half_sphere(sample, rng)
    boxes = rcb(pts, ranks, np.array([-1.0, -1, -1]), np.array([1.0, 1, 1]))
    h = np.full(len(pts), reach_d / radius_d)
    if reach_large_d is not None and large_share > 0:
        h[rng.random(len(pts)) < large_share] = reach_large_d / radius_d
    h_max = h.max()
    scale = n_total / sample
    counts = []
    for lo, hi, _ in boxes:
        inside_big = np.all((pts >= lo - h_max) & (pts <= hi + h_max), axis=1)
        inside = np.all((pts >= lo) & (pts < hi), axis=1)
        # Within the expanded box and not in the domain; corners of the shell are rounded in
        # reality (distance to a box), so subtract the points beyond the reach at the corners.
        pick = inside_big & ~inside
        cand, hc = pts[pick], h[pick]
        dx = np.maximum(np.maximum(lo - cand, 0), cand - hi)
        counts.append(np.count_nonzero(np.einsum("ij,ij->i", dx, dx) <= hc * hc) * scale)
    counts = np.array(counts)
    return counts.max(), counts.mean(), radius_d


def add_model_arguments(ap, rate1=6.765e6, rate2=1.219e7, imbalance2=1.0):
    """The measured and assumed constants of the model (shared with campaign_wall_model.py)."""
    ap.add_argument("--rate1", type=float, default=rate1, help="1-rank particle-steps/s")
    ap.add_argument("--rate2", type=float, default=rate2, help="2-rank particle-steps/s")
    ap.add_argument("--particles", type=float, default=89394, help="particles of the measured scene")
    ap.add_argument("--ghosts2", type=float, default=7852, help="ghosts (both ranks) at 2 ranks")
    ap.add_argument("--imbalance2", type=float, default=imbalance2, help="max/mean at 2 ranks")
    ap.add_argument("--lat-local", type=float, default=2e-6, help="per-step latency at 2 ranks (s)")
    ap.add_argument("--alpha", type=float, default=2e-6, help="network latency per message (s)")
    ap.add_argument("--alpha-allreduce", type=float, default=3e-6,
                    help="allreduce latency per tree level (s)")
    ap.add_argument("--bandwidth", type=float, default=10e9, help="network bytes/s per rank")
    ap.add_argument("--imbalance", type=float, default=1.05, help="max/mean assumed at P ranks")
    ap.add_argument("--neighbours", type=float, default=26, help="messages per step at large P")
    ap.add_argument("--reach", type=float, default=1.6,
                    help="a small particle's ghost reach in d_small (r_small + r_max + skin)")
    ap.add_argument("--reach-large", type=float, default=2.1,
                    help="a large particle's ghost reach in d_small (2 r_max + skin)")
    ap.add_argument("--large-share", type=float, default=0.0216,
                    help="large particles' share by number (f = 0.15, size ratio 2: 0.0216); "
                         "0 with --reach 2.1: the uniform halo before the thin one")
    ap.add_argument("--sample", type=int, default=400000, help="points sampled for ghost counts")
    ap.add_argument("--newton", action="store_true",
                    help="Newton across borders: the ghosts' force sums go back each step")
    ap.add_argument("--overhead", type=float, default=0.0,
                    help="per-particle work of a decomposed rank, whatever its ghosts, in units of "
                         "c_p (0: all extra work per ghost)")


def calibrate(a):
    """c_p (seconds per particle-step, 1 rank) and c_g (per ghost-step) from the 2-rank run."""
    c_p = 1 / a.rate1
    t2 = 2 / a.rate2 * a.particles / 2  # seconds per step at 2 ranks
    n2 = a.particles / 2 * a.imbalance2 * (1 + a.overhead)
    return c_p, (t2 - c_p * n2 - a.lat_local) / (a.ghosts2 / 2)


def step_parts(a, c_p, c_g, n_total, p, gmax, measured_two=False, overlap=False):
    """The slowest rank's compute, ghost, latency and network seconds per step at P ranks;
    measured_two: P = 2 with the measured imbalance and latency of the calibration run;
    overlap: the messages' latency and transfer hidden behind the interior rows' compute (what
    is left of them is returned as latency, the network part then 0)."""
    n = n_total / p * (a.imbalance2 if measured_two else a.imbalance) * (1 + a.overhead)
    if measured_two:
        return c_p * n, c_g * gmax, a.lat_local, 72 * gmax / a.bandwidth
    messages = min(a.neighbours, p - 1) * a.alpha
    allreduce = np.log2(p) * a.alpha_allreduce
    net = 72 * gmax / a.bandwidth
    newton = getattr(a, "newton", False)
    back = 48 * gmax / a.bandwidth if newton else 0.0  # the ghosts' force and torque
    if not overlap:
        return c_p * n, c_g * gmax, messages * (2 if newton else 1) + allreduce, net + back
    interior = c_p * max(0.0, n / (1 + a.overhead) - gmax)
    if not newton:
        return c_p * n, c_g * gmax, allreduce + max(0.0, messages + net - interior), 0.0
    hidden = max(0.0, messages + net - interior / 2) + max(0.0, messages + back - interior / 2)
    return c_p * n, c_g * gmax, allreduce + hidden, 0.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_model_arguments(ap)
    ap.add_argument("--target", type=float, default=10e6, help="particles of the predicted tumbler")
    ap.add_argument("--cg", type=float, default=0,
                    help="cost per ghost-step in units of c_p (0: calibrate from the 2-rank run)")
    ap.add_argument("--ranks", type=int, nargs="+", default=[2, 64, 1024])
    ap.add_argument("--overlap", action="store_true",
                    help="the refresh travels while the interior rows are computed")
    ap.add_argument("--seeds", type=int, default=1,
                    help="samplings per rank count (seeds 1..K); K > 1 prints the median and range")
    a = ap.parse_args()
    if a.seeds < 1:
        ap.error("--seeds must be at least 1")

    def rng_for(ranks, seed=1):
        # One stream per (seed, rank count): a row does not depend on which other rows ran.
        return np.random.default_rng([seed, ranks])

    c_p, c_g = calibrate(a)
    t2 = 2 / a.rate2 * a.particles / 2  # seconds per step at 2 ranks
    g2 = a.ghosts2 / 2
    if a.cg > 0:
        print(f"(calibrated c_g would be {c_g / c_p:.2f} c_p; using {a.cg} c_p)")
        c_g = a.cg * c_p
    gmax2, gmean2, _ = ghosts_per_domain(a.particles, 2, a.reach, a.sample, rng_for(2),
                                         a.reach_large, a.large_share)
    print(f"calibration (2 ranks, {a.particles:.0f} particles): T_2 = {t2 * 1e3:.3f} ms/step, "
          f"c_p = {c_p * 1e9:.1f} ns, c_g = {c_g * 1e9:.1f} ns per ghost-step "
          f"({c_g / c_p:.2f} c_p); ghosts per rank measured {g2:.0f}, model {gmean2:.0f}")
    print(f"\n{a.target:.3g} particles (half-full sphere of radius "
          f"{(3 * a.target / (2 * np.pi)) ** (1 / 3):.0f} d_small), reach {a.reach} d_small "
          f"({a.reach_large} for the {100 * a.large_share:.2f}% large):")
    spread = f" (median of {a.seeds} samplings; efficiency range)" if a.seeds > 1 else ""
    print(f"| ranks | particles/rank | ghosts/rank (max){spread} | ghosts/particle | compute ms | "
          "ghost ms | latency ms | network ms | efficiency |")
    print("|---|---|---|---|---|---|---|---|---|")
    for p in a.ranks:
        rows = []
        for seed in range(1, a.seeds + 1):
            gmax, _, _ = ghosts_per_domain(a.target, p, a.reach, a.sample, rng_for(p, seed),
                                           a.reach_large, a.large_share)
            parts = step_parts(a, c_p, c_g, a.target, p, gmax, overlap=a.overlap)
            eff = c_p * a.target / p / sum(parts)  # against one rank, no overhead
            rows.append((eff, gmax, parts))
        rows.sort(key=lambda r: r[0])
        eff, gmax, (compute, ghost, lat, net) = rows[len(rows) // 2]
        effs = f" ({100 * rows[0][0]:.1f}-{100 * rows[-1][0]:.1f}%)" if a.seeds > 1 else ""
        print(f"| {p} | {a.target / p:.0f} | {gmax:.0f} | {gmax / (a.target / p):.2f} | "
              f"{compute * 1e3:.3f} | {ghost * 1e3:.3f} | {lat * 1e3:.3f} | {net * 1e3:.3f} | "
              f"{100 * eff:.1f}%{effs} |")


if __name__ == "__main__":
    main()
