#!/usr/bin/python3
"""The island enrichment and the radial segregation of every point of a campaign's analysis.h5
(`tumble analyze campaign`), as docs/validation.md tabulates them for the density beds of
Yu 2022 Fig. 13 (issue 17, D1).

usage: jobs/accuracy/enrichment_table.py CAMPAIGN_DIR [--reference LABEL]

Per point (labelled by the parameters that differ between the points), mean ± Student 95% over
the replicas of: the repose tilt β, the mapped species' share in the collection shell and the
other species', their ratio per replica; and the island enrichment from the window snapshots and
from the fields map as the geometric mean with the 95% interval of the log values (the scatter
of a ratio is multiplicative; the interval stays in (0, ∞)), tested against 1 (no pattern) by
Student's t on the logarithms, Holm-adjusted over every point's two enrichment tests.

Then each point against the reference point (the first, or --reference): the shell ratio as a
difference of means (Welch), the enrichments as ratios of geometric means (Welch on the
logarithms), Holm-adjusted over the comparisons shown; the points pooled; and the log standard
deviation of each enrichment with the replicas per point that a two-sided 5% test needs to see a
10% difference with 80% power, n = 2 (z_0.975 + z_0.8)² s² / ln(1.1)²."""
import argparse
import math
import os
import re
import signal
import sys

import h5py
import numpy as np
from scipy import stats

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
from postproc.report_stats import holm_adjust, mean_ci, welch_log_ratio, welch_test  # noqa: E402


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def load(path):
    """Per point: its parameters and the per-case arrays this table reads."""
    pts = []
    with h5py.File(path, "r") as f:
        for pid, g in f["points"].items():
            need = ("enrichment_window", "enrichment_map", "shell_share_mapped",
                    "shell_share_other", "repose_deg")
            missing = [k for k in need if k not in g]
            if missing:
                raise SystemExit(f"{path}: point {pid} lacks {', '.join(missing)}: rerun "
                                 "`tumble analyze campaign` with this binary")
            params = dict(kv.split("=", 1) for kv in text(g.attrs["params"]).split(";") if kv)
            p = dict(pid=pid, params=params)
            m = int(np.ravel(g.attrs.get("mapped_species", [1]))[0])
            p["mapped"] = text(g.attrs.get(f"species_{m}", "mapped"))
            p["other"] = text(g.attrs.get(f"species_{1 - m}", "other"))
            for k in need:
                p[k] = np.asarray(g[k][:], float)
            with np.errstate(divide="ignore", invalid="ignore"):  # no other species there: NaN
                p["shell_ratio"] = np.where(p["shell_share_other"] > 0, p["shell_share_mapped"]
                                            / p["shell_share_other"], np.nan)
            pts.append(p)
    # Label each point by the parameters in which the points differ.
    keys = sorted({k for p in pts for k in p["params"]})
    varying = [k for k in keys if len({p["params"].get(k) for p in pts}) > 1]
    for p in pts:
        p["label"] = ";".join(f"{k}={p['params'].get(k)}" for k in varying) or p["pid"]
    return sorted(pts, key=lambda p: natural_key(p["label"]))


def natural_key(label):
    """Numbers compared as numbers: R_rho=3 before R_rho=10."""
    return [(0, float(t), "") if re.fullmatch(r"\d+(\.\d*)?", t) else (1, 0.0, t)
            for t in re.split(r"(\d+(?:\.\d*)?)", label) if t]


def geo(v):
    """Geometric mean and the 95% interval of the mean of log v; p of Student's t of log v = 0."""
    lv = np.log(v[np.isfinite(v)])
    m, h, n = mean_ci(lv)
    p = float(stats.ttest_1samp(lv, 0.0).pvalue) if n >= 2 else math.nan
    return math.exp(m), math.exp(m - h), math.exp(m + h), p, n


def pm(v, digits=3):
    m, h, n = mean_ci(v)
    return f"{m:.{digits}g} ± {h:.2g}"


def pfmt(p):
    return "–" if not np.isfinite(p) else (f"{p:.2g}" if p >= 1e-4 else f"{p:.1e}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("campaign", help="campaign directory holding analysis.h5")
    ap.add_argument("--reference", help="the point the others are compared with: its label or "
                    "a part of it that names one point (e.g. R_rho=8); default the first")
    a = ap.parse_args()
    path = os.path.join(a.campaign, "analysis.h5")
    if not os.path.exists(path):
        raise SystemExit(f"{path}: not found (run `tumble analyze campaign {a.campaign}`)")
    pts = load(path)
    if any(np.any(p[k] <= 0) for p in pts for k in ("enrichment_window", "enrichment_map")):
        raise SystemExit("an enrichment of 0 in some replica: the log-scale table does not "
                         "apply; use the report's section 6c (differences of means)")
    ref = 0
    if a.reference:
        labels = [p["label"] for p in pts]
        hits = [i for i, l in enumerate(labels) if a.reference in l.split(";") or a.reference == l]
        if len(hits) != 1:
            raise SystemExit(f"--reference {a.reference}: names {len(hits)} points, not one; "
                             f"points: {labels}")
        ref = hits[0]

    print(f"{path}: {len(pts)} points; mean ± Student 95% over replicas; enrichment: geometric "
          "mean [95%], p of log enrichment = 0, Holm over all enrichment tests")
    one = []  # (point, key, p)
    for p in pts:
        for k in ("enrichment_window", "enrichment_map"):
            one.append((p["label"], k, geo(p[k])[3]))
    holm = dict(zip([(l, k) for l, k, _ in one], holm_adjust([x[2] for x in one])))
    for p in pts:
        print(f"\n{p['label']}  (N = {len(p['repose_deg'])})")
        print(f"  repose tilt beta [deg]            {pm(p['repose_deg'], 4)} "
              f"({p['repose_deg'].min():.2f}-{p['repose_deg'].max():.2f})")
        print(f"  {p['mapped']} in the shell                {pm(p['shell_share_mapped'])}")
        print(f"  {p['other']} in the shell                 {pm(p['shell_share_other'])}")
        print(f"  shell ratio {p['mapped']}/{p['other']}            {pm(p['shell_ratio'])}")
        for k in ("enrichment_window", "enrichment_map"):
            g, lo, hi, pv, n = geo(p[k])
            print(f"  {k:<32s}  {g:.3f} [{lo:.3f}, {hi:.3f}]  p {pfmt(pv)}  Holm "
                  f"{pfmt(holm[(p['label'], k)])}   per replica "
                  + " ".join(f"{x:.2f}" for x in p[k]))

    if len(pts) > 1:
        base = pts[ref]
        print(f"\nagainst {base['label']} (Welch; enrichment as a ratio of geometric means; "
              "Holm over the rows)")
        rows = []
        for p in pts:
            if p is base:
                continue
            w = welch_test(p["shell_ratio"], base["shell_ratio"])
            rows.append((p["label"], "shell ratio, difference", w["diff"], w["diff"] - w["half"],
                         w["diff"] + w["half"], w["p"]))
            for k in ("enrichment_window", "enrichment_map"):
                r = welch_log_ratio(p[k], base[k])
                rows.append((p["label"], f"{k}, ratio", r["ratio"], r["lower"], r["upper"],
                             r["p"]))
        adj = holm_adjust([r[5] for r in rows])
        for r, h in zip(rows, adj):
            print(f"  {r[0]}: {r[1]:<28s} {r[2]:.3g} [{r[3]:.3g}, {r[4]:.3g}]  p {pfmt(r[5])}  "
                  f"Holm {pfmt(h)}")
        print("\nall points pooled, and the replicas a 10% difference needs (80% power, 5%)")
        z = stats.norm.ppf(0.975) + stats.norm.ppf(0.8)
        for k in ("enrichment_window", "enrichment_map"):
            allv = np.concatenate([p[k] for p in pts])
            g, lo, hi, pv, n = geo(allv)
            # Pooled within-point variance of the log enrichment, weighted by n - 1.
            logs = [np.log(p[k][np.isfinite(p[k])]) for p in pts]
            dof = sum(max(len(l) - 1, 0) for l in logs)
            sd = (math.sqrt(sum(((l - l.mean()) ** 2).sum() for l in logs if len(l) > 1) / dof)
                  if dof > 0 else math.nan)
            need = 2 * (z * sd / math.log(1.1)) ** 2 if np.isfinite(sd) else math.nan
            print(f"  {k:<20s} pooled {g:.3f} [{lo:.3f}, {hi:.3f}] p {pfmt(pv)} (N = {n}); "
                  f"log SD {sd:.3f}: {need:.0f} replicas per point")


if __name__ == "__main__":
    # Piped to `head`, the table stops where the reader stopped, without a traceback.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    main()
