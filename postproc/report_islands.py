"""Report sections that compare points through the CM islands (analysis.h5 of `tumble analyze
campaign`): enrichment of every point against every island set of its campaign, which is how
the absence of a pattern is measured for a protocol without islands, and the Fig. 5 sections."""
import html
import os

import numpy as np

if __package__:
    from . import report_figs as rf
    from . import report_findings as fi
    from .report_findings import ci_span
    from .report_page import Html
    from .report_stats import bounded_interval, compare_values, comparison_text
else:  # loaded by postproc/report.py run as a file
    import report_figs as rf
    import report_findings as fi
    from report_findings import ci_span
    from report_page import Html
    from report_stats import bounded_interval, compare_values, comparison_text


def section_cross_enrichment(R, pts):
    R.h("<h2>6b. Island enrichment against each protocol's islands</h2>")
    cols = []  # (campaign, island point id, label) of every point with islands
    for q in pts:
        if q["an"] is not None and q["islands"]:
            cols.append((id(q["camp"]), q["pid"], q["label"].split()[0]))
    if not cols:
        R.h("<p>No point has CM islands (or <code>tumble analyze campaign</code> has not run): "
            "nothing to measure against.</p>")
        return
    m = html.escape(fi.mapped_name(next(q for q in pts if q["an"] is not None and q["islands"])))
    R.h(f"<p>Each row: the point's time-averaged {m}-particle maps, each column: the islands of "
        "a point of the same campaign (its label). Same definition as the enrichment above "
        "(1 = no preference for the islands). The diagonal is each point's own enrichment; a "
        "protocol without islands, e.g. (68°,68°), has no diagonal entry. 1 is not the null: "
        f"{m} particles gather at the wall unevenly under any protocol (radial segregation, "
        "the free surface), so a mask can collect more than its share without a pattern. The "
        "test of a pattern is the comparison with the islands' own point on the same mask, the "
        "ratio of the geometric means (× r [95%], Welch's t on the logarithms, as in section "
        "6c): a protocol without that pattern has a ratio below 1 beyond its interval. Mean "
        "[95% interval of the mean, Student's, cut at 0] (N replicas).</p>")
    own = {pid: (q["an"] or {}).get("enrichment_vs", {}).get(pid) for q in pts
           for _, pid, _ in cols if q["pid"] == pid}
    rows, csv_rows = [], []
    for q in pts:
        vs = (q["an"] or {}).get("enrichment_vs", {})
        row = [q["label"]]
        for camp, pid, label in cols:
            e = vs.get(pid) if camp == id(q["camp"]) else None
            cell, c = "–", dict(kind="", est=np.nan, lower=np.nan, upper=np.nan)
            if e:
                cell = ci_span(bounded_interval(e["values"], 0.0, np.inf))
                if q["pid"] != pid and own.get(pid):
                    c = compare_values(e["values"], own[pid]["values"], 0.0, np.inf)
                    if np.isfinite(c["est"]):
                        cell += html.escape(f"; vs {label} {comparison_text(c)}")
                cell = Html(cell)
                csv_rows.append([q["label"], label, e["mean"], e["ci95"], e["n"], c["kind"],
                                 c["est"], c["lower"], c["upper"]]
                                + [float(v) for v in e["values"]])
            row.append(cell)
        rows.append(row)
    R.table(["point"] + [f"against the islands of {c[2]}" for c in cols], rows)
    width = max((len(r) for r in csv_rows), default=9) - 9
    R.csv("cross_enrichment.csv", ["point", "islands_of", "mean", "ci95", "n",
                                   "vs_islands_point_as", "vs_islands_point",
                                   "vs_islands_point_lower", "vs_islands_point_upper"]
          + [f"replica_{k}" for k in range(width)], csv_rows)


def section_cross_sections(R, pts):
    R.h("<h2>8b. Cross-section through two islands (Yu 2022 Fig. 5)</h2>")
    have = [q for q in pts if q["an"] is not None and "section" in q["an"]]
    if not have:
        R.h("<p>No section: the cases kept no snapshots, or no point has two CM islands, or "
            "<code>tumble analyze campaign</code> has not run.</p>")
        return
    label_of = {q["pid"]: q["label"].split()[0] for q in pts}
    R.h("<p>c_L of the particles whose centres lie within ± one large diameter of the plane "
        "through the tumbler centre and two CM islands of different orbits (the two farthest "
        "apart); the plane cuts both cone-like KAM tubes along their axes. In-plane coordinates "
        "in units of R; mean over the replicas of each case's average over the snapshots of "
        "its last half. Red dots: where the circles r = 0.55 … 0.95 of the plane cross the "
        "islands of the KAM shells (the tube walls). A point without islands is cut by the "
        "plane of the first point that has them (named below), for comparison. One colour "
        "scale for all (the CI's capped at 1: bins seen by few particles have very wide intervals); "
        "grey: no particle (above the free surface). Up is +y: the free surface at the top.</p>")
    means = [q["an"]["section"]["mean"] for q in have]
    cis = [q["an"]["section"]["ci95"] for q in have]
    rows, csv_rows = [], []
    for q in have:
        s = q["an"]["section"]
        title = (f"{q['label'].split()[0]} {q['label'].split()[1]}, plane of "
                 f"{label_of.get(s['plane_of'], s['plane_of'][:8])}")
        rows.append((title, s["mean"], s["ci95"], s["tubes"]))
        n = s["mean"].shape[0]
        for stat in ("mean", "ci95"):
            v = s[stat].ravel()
            csv_rows += [[q["label"], stat, k // n, k % n, v[k]] for k in range(len(v))]
    name = "section_cL.png"
    lo, hi = rf.finite_range(cis, floor=0.0)
    rf.section_grid(rows, os.path.join(R.out, name), rf.finite_range(means), (lo, min(hi, 1.0)))
    R.fig(name, "Fig. 5: c_L in the plane through two islands, mean (left) and 95% CI half-width "
                "(right) per point; " + html.escape("red dots: KAM-tube boundaries") + ".")
    R.csv("sections.csv", ["point", "stat", "i", "j", "value"], csv_rows)
