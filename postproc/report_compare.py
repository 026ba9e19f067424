"""Report section 6c: every scalar metric of section 6 compared between each point and the
baseline point, one family of tests with Holm's correction, so that "does point A give more of X
than point B" has a single answer per metric that accounts for the number of questions asked.

A positive quantity without an upper bound (the island enrichment, the shell ratio) is compared as
a ratio of geometric means, Welch's t on the logarithms (its replicas scatter multiplicatively);
every other metric as a difference of means, Welch's t on the values."""
import html

import numpy as np

if __package__:
    from .report_findings import ALPHA, p_text
    from .report_species import named, species_names
    from .report_stats import comparison_text, compare_values, holm_adjust
else:  # loaded by postproc/report.py run as a file
    from report_findings import ALPHA, p_text
    from report_species import named, species_names
    from report_stats import comparison_text, compare_values, holm_adjust


def _p(p):  # a table cell: the number alone
    return "–" if not np.isfinite(p) else (f"{p:.2g}" if p >= 1e-4 else "< 0.0001")


def scalar_tests(pts, baseline, scalars, bounds):
    """Every (point, metric) test against the baseline, Holm-adjusted over all of them. Each
    point's q["scalars"] (report_scalars.case_scalars) must be filled. Rows: dict(point, metric, kind,
    est, lower, upper, p, p_holm, na, nb)."""
    base = pts[baseline]
    rows = []
    for i, q in enumerate(pts):
        if i == baseline:
            continue
        for k in scalars:
            a = [s[k] for s in q["scalars"]]
            b = [s[k] for s in base["scalars"]]
            c = compare_values(a, b, *bounds[k])
            if c["na"] == 0 or c["nb"] == 0:
                continue  # the metric does not exist at one of the two points
            rows.append(dict(point=q, metric=k, **c))
    adj = holm_adjust([r["p"] for r in rows])
    for r, pa in zip(rows, adj):
        r["p_holm"] = float(pa)
    return rows


def section_scalar_differences(R, pts, baseline, scalars, bounds, findings):
    R.h("<h2>6c. Scalar metrics against the baseline point</h2>")
    if len(pts) < 2:
        R.h("<p>One parameter point only: nothing to compare.</p>")
        return
    btag = pts[baseline]["label"].split()[0]
    names = species_names(pts)
    rows = scalar_tests(pts, baseline, scalars, bounds)
    m = int(np.sum(np.isfinite([r["p"] for r in rows])))
    R.h(f"<p>Each metric of section 6 at each point against the baseline <b>{html.escape(btag)}"
        "</b>. The island enrichment and other positive ratios: the ratio of the geometric "
        "means (point ÷ baseline, 1 = no difference) with its 95% interval, Welch's t on the "
        "logarithms of the replicas; a metric with a replica at 0 and all others: the "
        "difference of the means (point − baseline, 0 = none), Welch's t. The p-values are "
        f"then adjusted by <b>Holm's method over all {m} tests of this table</b>: a metric "
        f"'differs' when its adjusted p is below {ALPHA:g}, which keeps the chance of any "
        f"false 'differs' in the table below {ALPHA:.0%}. A metric chosen before the run as the one "
        "question to ask can be read at its unadjusted p; every other reading should use "
        "Holm's.</p>")
    # The table names each point by its tag (A2): a full label (every parameter and the
    # campaign's note) repeated on each metric's row made the table wider than the page.
    listed = [q for q in pts if any(r["point"] is q for r in rows)] + [pts[baseline]]
    R.h("<p>" + "; ".join(f"<b>{html.escape(q['label'].split()[0])}</b> = "
                          f"{html.escape(q['label'].split(' ', 1)[1] if ' ' in q['label'] else '')}"
                          for q in listed) + ".</p>")
    trows = []
    for r in rows:
        verdict = ("differs" if np.isfinite(r["p_holm"]) and r["p_holm"] < ALPHA else
                   "no difference shown" if np.isfinite(r["p_holm"]) else "not tested")
        trows.append([r["point"]["label"].split()[0], named(r["metric"], names), f"{r['kind']} vs {btag}",
                      comparison_text(r), _p(r["p"]), _p(r["p_holm"]), f"{r['na']} / {r['nb']}",
                      verdict])
    R.table(["point", "metric", "compared as", "estimate [95%]", "p (Welch)", "p (Holm)",
             "N point / baseline", "verdict"], trows)
    R.csv("scalar_differences.csv",
          ["point", "metric", "kind", "estimate", "ci95_lower", "ci95_upper", "p_welch",
           "p_holm", "n_point", "n_baseline"],
          [[r["point"]["label"], named(r["metric"], names), r["kind"], r["est"], r["lower"], r["upper"],
            r["p"], r["p_holm"], r["na"], r["nb"]] for r in rows])
    for q in pts:
        mine = [r for r in rows if r["point"] is q and np.isfinite(r["p"])]  # tested ones
        if not mine:
            continue
        hits = [r for r in mine if np.isfinite(r["p_holm"]) and r["p_holm"] < ALPHA]
        said = "; ".join(f"{html.escape(named(r['metric'], names))} {html.escape(comparison_text(r))} "
                         f"(Holm {html.escape(p_text(r['p_holm']))})" for r in hits)
        findings.append(
            f"Scalars, <b>{html.escape(q['short'])}</b> against {html.escape(btag)}: "
            + (f"{len(hits)} of the {len(mine)} metrics tested differ after Holm over the {m} "
               f"tests of section 6c: {said}." if hits else
               f"none of the {len(mine)} metrics tested differs after Holm over the {m} tests "
               "of section 6c."))
