#!/usr/bin/python3
"""Ensemble comparison report: one self-contained HTML page (figures embedded), the PNG figures
and a CSV of every number, for one or more campaign directories (docs/report.md).

usage: postproc/report.py RESULTS_A [RESULTS_B ...] [-o OUTDIR] [--baseline K]
       python3 -m postproc.report ... (the same, as a module of the postproc package)

RESULTS_* are campaign directories (or their ensemble.h5). Run `tumble analyze campaign DIR`
first for the CM islands, island enrichment, Fig. 8 counts and lighter-particle maps; without
analysis.h5 those parts say so and the rest is reported. Every parameter point of every
campaign is one row; difference maps compare each point with the baseline point (the first
in the campaign file unless --baseline names one). The page opens with its Findings: one
sentence per comparison, generated from the numbers (postproc/report_findings.py).
"""
import argparse
import base64
import csv
import datetime
import html
import os
import platform
import re
import subprocess
import time

import numpy as np

if __package__:  # python3 -m postproc.report
    from . import report_compare as rc
    from . import report_data as rd
    from . import report_figs as rf
    from . import report_findings as fi
    from . import report_islands as ri
    from . import report_mixing as rm
    from .report_stats import (bounded_interval, bh_reject, cell_tests, fmt, mean_ci,
                               welch_half_width)
else:  # /usr/bin/python3 postproc/report.py: the script's directory is sys.path[0]
    import report_compare as rc
    import report_data as rd
    import report_figs as rf
    import report_findings as fi
    import report_islands as ri
    import report_mixing as rm
    from report_stats import (bounded_interval, bh_reject, cell_tests, fmt, mean_ci,
                              welch_half_width)

MAP_FIELDS = [  # (field, label, unit factor, colour map, physical bounds in the shown unit)
    ("concentration/c_L", "c_L (species 1: the large, or in a density bed the heavy particles)",
     1.0, "viridis", (0.0, 1.0)),
    ("displacement/dpsi_large", "Δψ large [deg]", 180 / np.pi, "magma", (0.0, 180.0)),
    ("displacement/dpsi_small", "Δψ small [deg]", 180 / np.pi, "magma", (0.0, 180.0)),
]
# A cell is empty for a field when no replica had a particle of the species the field follows
# there: large for c_L (the large share: 0 without a large particle, whatever the small ones do)
# and Δψ large, small for Δψ small.
EMPTY_COUNT = {"concentration/c_L": "concentration/volume_large",
               "displacement/dpsi_large": "displacement/count_large",
               "displacement/dpsi_small": "displacement/count_small"}
FDR_Q = 0.05
SERIES = [("series/shell_large_fraction", "large share of the shell 0.9 < r/R < 1", (0.0, 1.0)),
          ("series/radial_segregation", "radial segregation (shell share − bed share)",
           (-1.0, 1.0)),
          ("series/mixing_index", "intensity of segregation of the shell map", (0.0, 1.0))]
FATES = ["persistent", "switched", "captured", "dispersed", "other"]
# Yu 2022 Fig. 8 (f = 0.15, N = 7 -> 34, 1980 large particles); "switched" is not one of its classes
PAPER_FATES = {"persistent": 124, "captured": 429, "dispersed": 241, "other": 1186}
PAPER_LARGE = 1980


def displacement_groups(pts):
    """The Δψ groups of the campaigns' fields (displacement, displacement_k6, ...) with their lag
    in protocol periods, i.e. iterations (collect.displacement_periods), from the per-case collect
    text (';k=1,6,18;'): [(group, iterations)]. Labels say "iterations": "periods" would read as
    the islands' period (3 iterations for (57°, 57°)), which is the paper's unit."""
    groups = {}
    for q in pts:
        for cf in q["members"]:
            m = re.search(r"(?:^|;)k=([^;]+)", str(cf.get("collect", "")))
            if not m:
                continue
            lags = m.group(1).split(",")
            for i, k in enumerate(lags):
                groups.setdefault("displacement" if i == 0 else f"displacement_k{k}", k)
    return sorted(groups.items(), key=lambda gk: float(gk[1]))


def map_fields(pts):
    """MAP_FIELDS with a Δψ pair for every further lag the campaigns collected."""
    out = list(MAP_FIELDS)
    for g, k in displacement_groups(pts):
        if g == "displacement":
            continue
        for sp in ("large", "small"):
            field = f"{g}/dpsi_{sp}"
            EMPTY_COUNT[field] = f"{g}/count_{sp}"
            out.append((field, f"Δψ {sp} over {k} iterations [deg]", 180 / np.pi, "magma",
                        (0.0, 180.0)))
    return out


class Html(str):
    """A table cell that is HTML already (e.g. an interval in its checkable span)."""


def plain(cell):
    """A cell as CSV text: the HTML's text."""
    if isinstance(cell, Html):
        return html.unescape(re.sub(r"<[^>]+>", "", cell))
    return cell


def cell_html(c):
    return c if isinstance(c, Html) else html.escape(str(c))


class Report:
    html_cell = staticmethod(Html)  # for the sections in other modules

    def __init__(self, out):
        self.out = out
        self.parts = []
        self.figures = 0
        self.csvs = []
        os.makedirs(out, exist_ok=True)

    def h(self, s):
        self.parts.append(s)

    def fig(self, name, caption):
        """Embeds OUT/name (written already) as a data URI, so the page stands alone."""
        with open(os.path.join(self.out, name), "rb") as fh:
            data = base64.b64encode(fh.read()).decode()
        self.figures += 1
        self.h(f'<figure><img alt="{html.escape(name)}" src="data:image/png;base64,{data}">'
               f'<figcaption>Fig. {self.figures}. {caption} <a href="{html.escape(name)}">'
               f'{html.escape(name)}</a></figcaption></figure>')

    def table(self, header, rows, csv_name=None):
        self.h("<table><tr>" + "".join(f"<th>{html.escape(str(c))}</th>" for c in header) + "</tr>")
        for r in rows:
            self.h("<tr>" + "".join(f"<td>{cell_html(c)}</td>" for c in r) + "</tr>")
        self.h("</table>")
        if csv_name:
            self.csv(csv_name, header, [[plain(c) for c in r] for r in rows])

    def csv(self, name, header, rows):
        with open(os.path.join(self.out, name), "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            w.writerows(rows)
        if name not in self.csvs:
            self.csvs.append(name)


def git_commit():
    here = os.path.dirname(os.path.abspath(__file__))
    try:
        c = subprocess.run(["git", "-C", here, "rev-parse", "HEAD"], capture_output=True,
                           text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", here, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10).stdout.strip()
        return c + (" (with uncommitted changes)" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def mixture_note(p):
    """A density-bidisperse point (equal sizes, R_rho != 1) says which species is the light one
    and that its maps and enrichment are the light particles' (src/scene/mixture.hpp)."""
    try:
        ratio, rho, f = float(p.get("size_ratio", 2)), float(p.get("R_rho", 1)), float(p.get("f", 0.15))
    except ValueError:
        return ""
    if abs(ratio - 1) > 1e-9 or rho == 1:
        return ""
    light = 1 - f if rho > 1 else f
    return f" [equal sizes: light {100 * light:g} vol %, enrichment and Fig. 13 of the light]"


def short(params):
    p = rd.parse_params(params)
    keys = ["theta_z", "theta_x", "f", "R_rho", "size_ratio"]
    s = f"({p.get('theta_z', '?')}°,{p.get('theta_x', '?')}°) f={p.get('f', '?')}"
    if p.get("R_rho", "1") != "1":
        s += f" Rρ={p['R_rho']}"
    if p.get("size_ratio", "2") != "2":
        s += f" d_L/d_S={p['size_ratio']}"
    s += mixture_note(p)
    extra = [f"{k}={v}" for k, v in p.items() if k not in keys]
    return s + ("; " + ", ".join(extra) if extra else "")


def file_order(c):
    """Position of each point in the campaign file: the expansion index of its first case
    (cases.tsv); points absent from cases.tsv follow, in ensemble.h5's row order."""
    first = {}
    for r in c["cases_tsv"].values():
        try:
            k = int(r.get("index", ""))
        except ValueError:
            continue
        pid = r.get("point", "")
        first[pid] = min(k, first.get(pid, k))
    big = len(c["cases_tsv"]) + 1
    return lambda kv: (first.get(kv[0], big), kv[1]["row"])


def gather_points(camps):
    """Every (campaign, point) as one row, labelled A1, A2, B1, ... in campaign-file order."""
    rows = []
    for ci, c in enumerate(camps):
        for k, (pid, p) in enumerate(sorted(c["points"].items(), key=file_order(c))):
            label = f"{chr(65 + ci)}{k + 1} {short(p['params'])}"
            members = [cf for cf in c["case_fields"].values() if cf.get("point_id") == pid]
            members.sort(key=lambda cf: int(cf.get("replica", 0)))
            an = (c["analysis"] or {}).get(pid)
            rows.append(dict(label=label, short=label, camp=c, pid=pid, p=p, members=members,
                             an=an, islands=an["islands"] if an else []))
    return rows


def resolve_baseline(arg, pts):
    """--baseline: a row number (0 = first), a label (A2) or a point id (or its start);
    default the first point in campaign-file order."""
    if arg is None:
        return 0
    if re.fullmatch(r"\d+", arg):
        k = int(arg)
        if 0 <= k < len(pts):
            return k
    hits = [k for k, q in enumerate(pts) if q["label"].split()[0] == arg
            or q["pid"].startswith(arg)]
    if len(hits) == 1:
        return hits[0]
    raise SystemExit(f"--baseline {arg}: not one of the points: "
                     + "; ".join(f"{k} = {q['label']} ({q['pid'][:8]})"
                                 for k, q in enumerate(pts)))


def section_provenance(R, camps, pts):
    R.h("<h2>1. Provenance</h2>")
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    prov = [("report written", now), ("report generator commit", git_commit()),
            ("machine", f"{platform.node()} ({platform.platform()}, {os.cpu_count()} CPUs)"),
            ("python / numpy", f"{platform.python_version()} / {np.__version__}")]
    for c in camps:
        tag = c["name"]
        cf = next(iter(c["case_fields"].values()), {})
        man = c["manifest"].values()
        starts = sorted(r["start"] for r in man if r.get("start"))
        ends = sorted(r["end"] for r in man if r.get("end"))
        prov += [(f"{tag}: directory", os.path.abspath(c["dir"])),
                 (f"{tag}: Tumble version (git)",
                  f"{cf.get('tumble_version', '?')} ({cf.get('git_hash', '?')})"),
                 (f"{tag}: hosts", ", ".join(sorted({r.get('host', '?') for r in man}))),
                 (f"{tag}: cases ran", f"{starts[0] if starts else '?'} to "
                                       f"{ends[-1] if ends else '?'}"),
                 (f"{tag}: ensemble", f"{c['root'].get('n_points', '?')} points, "
                                      f"{c['root'].get('n_members', '?')} members, "
                                      f"{c['root'].get('n_failed', '?')} failed"),
                 (f"{tag}: CM analysis", "analysis.h5 present" if c["analysis"] is not None
                  else "absent: run `tumble analyze campaign DIR` for islands, enrichment and "
                       "Fig. 8")]
    R.table(["item", "value"], prov, "provenance.csv")
    for c in camps:
        R.h(f"<details><summary>campaign file of {html.escape(c['name'])}</summary><pre>"
            f"{html.escape(c['toml'])}</pre></details>")
    R.h("<h3>Parameter points</h3>")
    rows = []
    for q in pts:
        a = q["p"]["attrs"]
        params = rd.parse_params(q["p"]["params"])
        rows.append([q["label"].split()[0], q["camp"]["name"], q["pid"],
                     params.get("theta_z", ""), params.get("theta_x", ""), params.get("f", ""),
                     params.get("R_rho", ""), params.get("size_ratio", ""),
                     int(np.ravel(a.get("n_members", [0]))[0]),
                     int(np.ravel(a.get("n_failed", [0]))[0]), q["p"]["params"]])
    R.table(["row", "campaign", "point", "θz", "θx", "f", "R_ρ", "size ratio", "members",
             "failed", "all parameters"], rows, "points.csv")


def section_cases(R, camps):
    R.h("<h2>2. Cases done and failed</h2>")
    all_rows, fail_rows, summary = [], [], []
    for c in camps:
        counts = {}
        seen = set()
        for cid, r in c["manifest"].items():
            seen.add(cid)
            st = r.get("status", "?")
            counts[st] = counts.get(st, 0) + 1
            all_rows.append([c["name"], cid, r.get("point", ""), r.get("replica", ""), st,
                             r.get("attempt", ""), r.get("failure", ""), r.get("wall", ""),
                             r.get("host", ""), r.get("params", ""),
                             r.get("diagnostic", "")])
            if st == "failed":
                # Joined to its parameters: the manifest line carries them; cases.tsv too.
                params = r.get("params") or c["cases_tsv"].get(cid, {}).get("params", "")
                fail_rows.append([c["name"], cid, params, r.get("failure", ""),
                                  r.get("attempt", ""), "yes" if r.get("final") else "no",
                                  r.get("diagnostic", "")])
        never = [cid for cid in c["cases_tsv"] if cid not in seen]
        summary.append([c["name"], len(c["cases_tsv"]) or len(c["manifest"]),
                        counts.get("done", 0), counts.get("failed", 0),
                        counts.get("running", 0), len(never)])
    R.table(["campaign", "cases", "done", "failed", "running or interrupted", "never started"],
            summary, "cases_summary.csv")
    R.csv("cases.csv", ["campaign", "case", "point", "replica", "status", "attempt", "failure",
                        "wall_s", "host", "params", "diagnostic"], all_rows)
    if fail_rows:
        R.h("<h3>Failed cases, with their parameters</h3>")
        R.table(["campaign", "case", "parameters", "failure", "attempts", "out of attempts",
                 "diagnostic"], fail_rows, "failed_cases.csv")
    else:
        R.h("<p>No case failed.</p>")


def cell_rows(label, field, stat, values, n):
    v = np.asarray(values, float).ravel()
    return [[label, field, stat, k, k // n, k % n, v[k]] for k in range(len(v))]


def member_maps(q, field, k=1.0):
    """The per-replica maps of a point [replicas][cells] (NaN: the cell was empty), or None."""
    maps = [cf["data"].get(field) for cf in q["members"]]
    maps = [np.asarray(m, float).ravel() * k for m in maps if m is not None]
    return np.array(maps) if maps else None


def section_maps(R, pts, map_csv, fields):
    R.h("<h2>3. Maps per parameter point</h2><p>Lambert equal-area projection of the lower "
        "hemisphere viewed from below (X right, Z up; docs/campaign.md). Red curves: CM island "
        "boundaries on r = 0.95 from <code>tumble analyze campaign</code>. One colour scale per "
        "field for all points; grey cells were never visited (or hold no particle of the "
        "species). Right: the width (upper − lower) of each cell's 95% confidence interval, "
        "computed on the logit scale of the quantity's physical range (c_L in [0, 1], Δψ in "
        "[0°, 180°]) so that it stays inside it; a width equal to the range says the replicas "
        "do not constrain the cell at all, a width of 0 that they agree exactly (e.g. no large "
        "particle in any replica): with N = 2 that is not certainty.</p>")
    for field, label, k, cmap, (lo, hi) in fields:
        have = [q for q in pts if field in q["p"]["fields"]]
        if not have:
            continue
        means = [q["p"]["fields"][field]["mean"] * k for q in have]
        widths = []
        rows = []
        for q, m in zip(have, means):
            reps = member_maps(q, field, k)
            n = q["p"]["grid_n"]
            if reps is not None and reps.shape[1] == np.size(m):
                b = bounded_interval(reps, lo, hi)
                w = (b["upper"] - b["lower"]).reshape(np.shape(m))
                map_csv += cell_rows(q["label"], field, "ci95_lower", b["lower"], n)
                map_csv += cell_rows(q["label"], field, "ci95_upper", b["upper"], n)
            else:  # no per-case fields: the ensemble's Student interval, width 2 × half-width
                w = 2 * q["p"]["fields"][field]["ci95"] * k
            widths.append(w)
            rows.append((q["label"], n, q["islands"], [m, w], None))
            map_csv += cell_rows(q["label"], field, "mean", m, n)
            map_csv += cell_rows(q["label"], field, "ci95", q["p"]["fields"][field]["ci95"] * k, n)
            map_csv += cell_rows(q["label"], field, "count", q["p"]["fields"][field]["count"], n)
        rng_m = rf.finite_range(means)
        rng_c = (0.0, hi - lo)
        name = "map_" + field.replace("/", "_") + ".png"
        rf.map_grid(rows, ["mean", "95% CI width (upper − lower)"], os.path.join(R.out, name),
                    label, [cmap, "YlOrBr"], [rng_m, rng_c], [label, "CI width"])
        R.fig(name, f"{html.escape(label)}: ensemble mean (left) and the width of its 95% "
                    f"confidence interval (right, 0 to the full range {lo:g}–{hi:g}) per "
                    f"parameter point.")


def empty_cells(q, field):
    """Cells of point q where no replica had a particle of the field's species (EMPTY_COUNT),
    from the per-case fields; without them, where the ensemble's count is 0."""
    c = member_maps(q, EMPTY_COUNT[field])
    if c is None or c.shape[1] != np.size(q["p"]["fields"][field]["mean"]):
        return np.asarray(q["p"]["fields"][field]["count"]).ravel() == 0
    return ~(np.nansum(c, axis=0) > 0)


def section_differences(R, pts, baseline, map_csv, findings):
    R.h("<h2>4. Differences from the baseline point</h2>")
    if len(pts) < 2:
        R.h("<p>One parameter point only: nothing to compare.</p>")
        return
    base = pts[baseline]
    btag = base["label"].split()[0]
    R.h(f"<p>Baseline: <b>{html.escape(base['label'])}</b> (the first point in the campaign "
        "file, or <code>--baseline</code>). Each map shows mean(point) − mean(baseline); red "
        "curves: the point's CM islands, black dashed: the baseline's. Right: only the cells "
        "whose difference is significant after controlling the <b>false discovery rate at "
        f"{FDR_Q:.0%} (Benjamini–Hochberg)</b> over the cells tested in that map: each cell's "
        "two-sided p-value is Welch's t, (difference) / sqrt(s²_point/N_point + "
        "s²_baseline/N_baseline) with ν by Welch–Satterthwaite, from the replicas that "
        "visited it (ensemble.h5 variance and count), and the cells are then rejected by the "
        "BH step-up rule, so that on average at most 5% of the flagged cells are false. Light "
        "grey: tested, not significant; dark grey: <b>not tested</b>, because the cell was "
        "empty in both points (no particle of the field's species, large for c_L, in any "
        "replica of either), had fewer than 2 replicas on a side, or had no variance on "
        "either side (the test is undefined there, so such a cell is neither significant nor "
        "counted among the tests).</p>")
    summary = []
    for field, label, k, _, _ in MAP_FIELDS[:2]:
        if field not in base["p"]["fields"]:
            continue
        others = [q for i, q in enumerate(pts) if i != baseline and field in q["p"]["fields"]
                  and q["p"]["grid_n"] == base["p"]["grid_n"]]
        if not others:
            continue
        bf = base["p"]["fields"][field]
        bm = bf["mean"] * k
        b_empty = empty_cells(base, field)
        rows = []
        diffs = []
        for q in others:
            qf = q["p"]["fields"][field]
            d = qf["mean"] * k - bm
            if "variance" in qf and "variance" in bf:
                pval, status = cell_tests(qf["mean"], qf["variance"], qf["count"], bf["mean"],
                                          bf["variance"], bf["count"],
                                          empty_cells(q, field), b_empty)
                pval, status = pval.ravel(), status.ravel()
                rej, padj = bh_reject(pval, FDR_Q)
                half = welch_half_width(qf["variance"], qf["count"], bf["variance"],
                                        bf["count"]) * k
            else:  # an older ensemble.h5 without variances: no test, every cell grey
                status = np.full(np.size(d), 2)
                pval = padj = np.full(np.size(d), np.nan)
                rej = np.zeros(np.size(d), bool)
                half = np.sqrt(qf["ci95"] ** 2 + bf["ci95"] ** 2) * k
            tested = status == 0
            m = int(tested.sum())
            raw = int(np.sum(tested & (pval < 0.05)))
            nsig = int(rej.sum())
            # The old per-cell rule, for comparison: |d| > Welch's 95% half-width, every cell
            # with a half-width (also those with no variance, where it is 0).
            old = int(np.sum(np.abs(d.ravel()) > half.ravel()))
            why = {s: int(np.sum(status == s)) for s in (1, 2, 3)}
            summary.append((label, q, base, m, nsig, raw, old, why))
            diffs.append(d)
            n = q["p"]["grid_n"]
            tag = "diff_vs_" + btag
            map_csv += cell_rows(q["label"], field, tag, d, n)
            map_csv += cell_rows(q["label"], field, "diff_welch_half_width", half, n)
            map_csv += cell_rows(q["label"], field, "diff_p_welch", pval, n)
            map_csv += cell_rows(q["label"], field, "diff_p_bh_adjusted", padj, n)
            map_csv += cell_rows(q["label"], field, "diff_test_status", status, n)
            map_csv += cell_rows(q["label"], field, "diff_bh_significant", rej.astype(int), n)
            rows.append((f"{q['label']} − {btag}", n, q["islands"], [d, d],
                         [None, ~rej.reshape(np.shape(d))],
                         [None, (status != 0).reshape(np.shape(d))], base["islands"]))
        rng = rf.finite_range(diffs, symmetric=True)
        name = "diff_" + field.replace("/", "_") + ".png"
        rf.map_grid(rows, ["difference", f"significant at FDR {FDR_Q:.0%} (BH)"],
                    os.path.join(R.out, name), f"{label}: difference from the baseline",
                    ["RdBu_r", "RdBu_r"], [rng, rng], ["Δ " + label] * 2)
        R.fig(name, f"{html.escape(label)}: difference from the baseline, all cells (left) and "
                    f"only those significant at a false discovery rate of {FDR_Q:.0%} "
                    f"(Benjamini–Hochberg; right).")
    if summary:
        trows = []
        for label, q, base, m, nsig, raw, old, why in summary:
            trows.append([label, f"{q['label']} − {btag}", m, nsig, raw, f"{0.05 * m:.1f}", old,
                          why[1], why[2], why[3]])
            findings.append(
                f"{html.escape(label.split(' [')[0].split(' (')[0])} map, "
                f"{html.escape(q['short'])} − {html.escape(btag)}: <b>{nsig} of {m}</b> tested "
                f"cells differ at a false discovery rate of {FDR_Q:.0%} (Benjamini–Hochberg); "
                f"{raw} pass an uncorrected 5% test, where {0.05 * m:.1f} are expected by chance; "
                f"not tested: {why[1]} cells empty in both, {why[2]} with fewer than 2 replicas "
                f"on a side, {why[3]} without variance on either side.")
        R.table(["field", "difference", "cells tested", f"significant, FDR {FDR_Q:.0%} (BH)",
                 "p < 0.05 uncorrected", "expected by chance at 5%",
                 "old rule: |Δ| > Welch half-width", "not tested: empty in both",
                 "not tested: < 2 replicas", "not tested: no variance"], trows,
                "difference_tests.csv")


def section_light(R, pts, map_csv):
    have = [q for q in pts if q["an"] is not None and "light_mean" in q["an"]]
    if not have:
        return
    R.h("<h3>Lighter-particle concentration (density-bidisperse points, Yu 2022 Fig. 13)</h3>")
    means = [q["an"]["light_mean"] for q in have]
    cis = [q["an"]["light_ci95"] for q in have]
    rows = [(q["label"] + f" [{q['an']['attrs'].get('light_source', '')}]", q["p"]["grid_n"],
             q["islands"], [m, c], None) for q, m, c in zip(have, means, cis)]
    for q, m, c in zip(have, means, cis):
        map_csv += cell_rows(q["label"], "light_concentration", "mean", m, q["p"]["grid_n"])
        map_csv += cell_rows(q["label"], "light_concentration", "ci95", c, q["p"]["grid_n"])
    rf.map_grid(rows, ["mean", "95% CI half-width"], os.path.join(R.out, "map_light.png"),
                "lighter-particle concentration", ["cividis", "YlOrBr"],
                [rf.finite_range(means), rf.finite_range(cis, floor=0.0)],
                ["c_light", "± c_light"])
    R.fig("map_light.png", "Lighter species' share of the solid volume near the wall, mean and "
                           "95% CI across replicas.")


def section_series(R, pts):
    R.h("<h2>5. Time series</h2><p>Ensemble mean with its 95% confidence band across "
        "replicas, computed on the logit scale of each quantity's range (so that the band stays "
        "inside it).</p>")
    rows = []
    for k, (field, label, (lo, hi)) in enumerate(SERIES):
        curves = []
        for q in pts:
            st = q["p"]["fields"].get(field)
            if st is None or "series_iteration" not in q["p"]:
                continue
            x = q["p"]["series_iteration"]
            n = len(x)
            m, cnt = st["mean"][:n], st["count"][:n]
            reps = [np.asarray(cf["data"][field], float) for cf in q["members"]
                    if field in cf["data"]]
            lower = upper = np.full(n, np.nan)
            if reps:
                stack = np.full((len(reps), n), np.nan)
                for j, v in enumerate(reps):
                    stack[j, :min(n, len(v))] = v[:n]
                b = bounded_interval(stack, lo, hi)
                lower, upper = b["lower"], b["upper"]
            curves.append((q["label"], x, m, lower, upper))
            rows += [[q["label"], field, j, x[j], q["p"]["series_time"][j], m[j], st["ci95"][j],
                      lower[j], upper[j], cnt[j]] for j in range(n)]
        if curves:
            name = f"series_{k}.png"
            rf.series_fig(curves, label, os.path.join(R.out, name), label)
            R.fig(name, f"{html.escape(label)} against the protocol iteration.")
    R.csv("series.csv", ["point", "field", "sample", "iteration", "time_s", "mean", "ci95",
                         "ci95_lower", "ci95_upper", "count"], rows)


def case_scalars(q):
    """Scalar metrics of every member case of a point, by replica."""
    an = q["an"]
    by_case = {}
    if an is not None:
        for j, cid in enumerate(an["cases"]):
            by_case[cid] = j
    out = []
    for cf in q["members"]:
        d = cf["data"]
        s = dict(case=cf["case_id"], replica=int(cf.get("replica", 0)))
        vl, vs = d.get("concentration/volume_large"), d.get("concentration/volume_small")
        s["shell c_L"] = float(np.nansum(vl) / np.nansum(vl + vs)) if vl is not None else np.nan
        for f in ("large", "small"):
            m, c = d.get(f"displacement/dpsi_{f}"), d.get(f"displacement/count_{f}")
            ok = np.isfinite(m) & (c > 0) if m is not None else None
            s[f"mean Δψ {f} [deg]"] = (float(np.sum(m[ok] * c[ok]) / np.sum(c[ok])) * 180 / np.pi
                                      if ok is not None and ok.any() else np.nan)
        for key, name in (("series/mixing_index", "final mixing index"),
                          ("series/radial_segregation", "final radial segregation")):
            v = d.get(key)
            s[name] = float(v[-1]) if v is not None and len(v) else np.nan
        j = by_case.get(cf["case_id"])
        s["enrichment (map)"] = float(an["enrichment_map"][j]) if j is not None else np.nan
        s["enrichment (last snapshot)"] = float(an["enrichment_snap"][j]) if j is not None else np.nan
        ew = an.get("enrichment_window") if an is not None else None
        s["enrichment (window snapshots)"] = (float(ew[j]) if j is not None and ew is not None
                                              else np.nan)
        sm, so = (an.get("shell_share_mapped"), an.get("shell_share_other")) if an else (None,
                                                                                        None)
        s[SHELL_RATIO] = (float(sm[j] / so[j]) if j is not None and sm is not None and so[j] > 0
                          else np.nan)
        for f in FATES:
            v = an["fates"][f][j] if j is not None else -1
            s[f] = float(v) if v >= 0 else np.nan
        s["repose tilt β [deg]"] = fi.case_repose(cf)
        out.append(s)
    return out


# The mapped species' share in the collection shell over the other species' (analysis.h5
# shell_share_*: the light over the heavy in a density bed, the large over the small otherwise;
# window snapshots): radial segregation as in Yu 2022 Fig. 13, 1 = none.
SHELL_RATIO = "shell share ratio, mapped / other species (window snapshots)"
SCALARS = ["enrichment (map)", "enrichment (last snapshot)", "enrichment (window snapshots)",
           SHELL_RATIO, "shell c_L", "mean Δψ large [deg]", "mean Δψ small [deg]", "final mixing index",
           "final radial segregation", "repose tilt β [deg]"]
BOUNDS = {"enrichment (map)": (0.0, np.inf), "enrichment (last snapshot)": (0.0, np.inf),
          "enrichment (window snapshots)": (0.0, np.inf), SHELL_RATIO: (0.0, np.inf),
          "shell c_L": (0.0, 1.0), "mean Δψ large [deg]": (0.0, 180.0),
          "mean Δψ small [deg]": (0.0, 180.0), "final mixing index": (0.0, 1.0),
          "final radial segregation": (-1.0, 1.0), "repose tilt β [deg]": (0.0, 90.0)}


def shell_inner(cf):
    """Inner radius r/R of the shell a case's c_L maps collect (0.9 unless its collect plan
    says otherwise, e.g. 0.97 for the density beds of Fig. 13)."""
    m = re.search(r"(?:^|;)shell=([0-9.eE+-]+)", str(cf.get("collect", "")))
    return float(m.group(1)) if m else 0.9


def mixing_baseline(q):
    """Per case: the mixing index of its last snapshot, and of the same particles shuffled
    (report_mixing.random_bed_index); lab-frame maps only."""
    out = dict(observed=[], random=[], random_sd=[], excess=[], series=[])
    for cf in q["members"]:
        snaps = cf.get("snapshots") or []
        if not snaps or str(cf.get("frame", "lab")) != "lab":
            continue
        shell = shell_inner(cf)
        obs, rnd, sd = rm.random_bed_index(snaps[-1], q["p"]["grid_n"], shell,
                                           seed=int(np.ravel(cf.get("seed", [0]))[0]) % 2**32)
        series = cf["data"].get("series/mixing_index")
        out["observed"].append(obs)
        out["random"].append(rnd)
        out["random_sd"].append(sd)
        out["excess"].append(obs - rnd)
        out["series"].append(float(series[-1]) if series is not None and len(series) else np.nan)
    return out


def section_scalars(R, pts, findings):
    shells = sorted({shell_inner(cf) for q in pts for cf in q["members"]}) or [0.9]
    shell_text = " or ".join(f"{r:g} &lt; r/R &lt; 1" for r in shells)
    R.h("<h2>6. Scalar metrics</h2><p>Mean [95% confidence interval] (N replicas). Every "
        "interval is computed on a scale on which the quantity is unbounded and mapped back, "
        "so it stays within the physical bounds: log for the enrichment (&gt; 0), logit for "
        "shares and indices in [0, 1], for Δψ in [0°, 180°] and for the radial segregation in "
        "[−1, 1]. Island enrichment = share of the large particles (the light ones in a "
        "density-bidisperse point) inside the CM islands ÷ the "
        "islands' share of the view from below: 1 = no preference, &gt; 1 = the segregation "
        "pattern of Yu 2022 Fig. 4; undefined (–) for a protocol without islands, e.g. "
        "(68°,68°). 'map': from the case's time-averaged c_L window (" + shell_text + "); "
        "'last snapshot': from the particles of its last snapshot; 'window snapshots': the "
        "particles of every stroboscopic snapshot of the collection window pooled (a map "
        "sampled within the iteration averages islands that move during it). The shell share "
        "ratio: the share of the mapped species' particles (light, or large) whose centres lie "
        "in the collection shell over the other species' share, over the window snapshots "
        "(Yu 2022 Fig. 13's radial segregation; 1 = none). The mixing index (intensity "
        "of segregation of the shell map, 0 = even, 1 = segregated) is compared with its value "
        "for a <b>randomly mixed bed of the same particles</b> (species shuffled among the "
        "positions of the last snapshot's shell, 200 shuffles; postproc/report_mixing.py): "
        "with a few particles per cell a random bed is far from 0. The repose tilt β is the "
        "one each case's bed was tilted to (measured on the bed unless the campaign set it); "
        "the Findings warn when points differ in it by more than "
        f"{fi.TILT_TOL_DEG:g}°.</p>")
    per_case, rows = [], []
    for q in pts:
        sc = case_scalars(q)
        q["scalars"] = sc
        q["mixing"] = mixing_baseline(q)
        for s in sc:
            per_case.append([q["label"], s["case"], s["replica"]] + [s[k] for k in SCALARS + FATES])
        row = [q["label"]]
        for k in SCALARS:
            lo, hi = BOUNDS[k]
            row.append(Html(fi.ci_span(bounded_interval([s[k] for s in sc], lo, hi))))
        mx = q["mixing"]
        if mx["random"]:
            row.append(f"{np.mean(mx['random']):.3g} (SD {np.mean(mx['random_sd']):.2g})")
            row.append(fmt(*mean_ci(mx["excess"])))
        else:
            row += ["–", "–"]
        row.append(f"{q['an']['attrs'].get('island_area_fraction', np.nan):.3f}"
                   if q["an"] else "–")
        rows.append(row)
        sent = fi.mixing_sentence(q)
        if sent:
            findings.append(sent)
    R.table(["point"] + SCALARS + ["mixing index of a random bed, same particles",
                                   "mixing index − random (last snapshot)",
                                   "islands' area share"], rows, "scalar_table.csv")
    R.csv("case_scalars.csv", ["point", "case", "replica"] + SCALARS + FATES, per_case)
    summ = []
    for q in pts:
        for k in SCALARS + FATES:
            m, ci, n = mean_ci([s[k] for s in q["scalars"]])
            lo, hi = BOUNDS.get(k, (0.0, fate_bound(q)))
            b = bounded_interval([s[k] for s in q["scalars"]], lo, hi,
                                 eps=0.5 if k in FATES else None)
            summ.append([q["label"], k, m, ci, b["lower"], b["upper"], n])
    R.csv("scalar_summary.csv", ["point", "metric", "mean", "ci95_student", "ci95_lower",
                                 "ci95_upper", "n"], summ)
    mrows = []
    for q in pts:
        mx = q["mixing"]
        for j in range(len(mx["observed"])):
            mrows.append([q["label"], j, mx["observed"][j], mx["series"][j], mx["random"][j],
                          mx["random_sd"][j], mx["excess"][j]])
    R.csv("mixing_random.csv", ["point", "member", "index_last_snapshot",
                                "index_series_last_sample", "random_bed_mean", "random_bed_sd",
                                "excess"], mrows)


def fate_bound(q):
    """The most large particles a Fig. 8 class can hold in a case of q (the four classes sum
    to the large particles present at both times)."""
    an = q["an"]
    if an is None:
        return np.inf
    tot = sum(np.asarray(an["fates"][f], float) for f in FATES)
    tot = tot[tot >= 0]
    return float(tot.max()) if tot.size else np.inf


def section_convergence(R, pts):
    R.h("<h2>7. Convergence with the number of replicas</h2>")
    panels, rows = [], []
    for metric in ("enrichment (map)", "final mixing index"):
        curves = []
        for q in pts:
            v = [s[metric] for s in q["scalars"]]
            ks, ms, los, his = [], [], [], []
            for k in range(1, len(v) + 1):
                b = bounded_interval(v[:k], *BOUNDS[metric])
                ks.append(k), ms.append(b["mean"]), los.append(b["lower"]), his.append(b["upper"])
                rows.append([q["label"], metric, k, b["mean"], b["lower"], b["upper"], b["n"]])
            if np.isfinite(ms).any():
                curves.append((q["label"], np.array(ks), np.array(ms), np.array(los),
                               np.array(his)))
        if curves:
            panels.append((metric, metric, curves))
    curves = []
    for q in pts:
        maps = [cf["data"].get("concentration/c_L") for cf in q["members"]]
        maps = [np.asarray(m, float).ravel() for m in maps if m is not None]
        if len(maps) < 1:
            continue
        full = np.nanmean(np.array(maps), axis=0)
        ks, rms = [], []
        for k in range(1, len(maps) + 1):
            part = np.nanmean(np.array(maps[:k]), axis=0)
            r = float(np.sqrt(np.nanmean((part - full) ** 2)))
            ks.append(k), rms.append(r)
            rows.append([q["label"], "rms(c_L mean_k - mean_all)", k, r, np.nan, np.nan, k])
        nan = np.full(len(ks), np.nan)
        curves.append((q["label"], np.array(ks), np.array(rms), nan, nan))
    if curves:
        panels.append(("c_L map: RMS(mean of k − mean of all)", "RMS over cells", curves))
    kmax = max((len(q["members"]) for q in pts), default=0)
    if kmax < 3:
        R.h(f"<p>Not shown: with at most {kmax} replica(s) per point the curves would have "
            f"{kmax} point(s), the last of which is the all-replica mean by definition, and no "
            "interval before k = 2: they say nothing about convergence. Run 3 or more replicas "
            "per point to see it (the numbers are in convergence.csv).</p>")
    elif panels:
        R.h("<p>Mean over the first k replicas (in replica order) with its 95% CI (bounded as "
            "in Sec. 6), and the RMS over cells of the difference between the k-replica mean "
            "c_L map and the all-replica mean: where the curves flatten, more replicas change "
            "little.</p>")
        rf.convergence_fig(panels, os.path.join(R.out, "convergence.png"))
        R.fig("convergence.png", "Convergence of the ensemble mean with the number of replicas.")
    R.csv("convergence.csv", ["point", "metric", "k", "mean", "ci95_lower", "ci95_upper", "n"],
          rows)


def section_fates(R, pts):
    R.h("<h2>8. Fig. 8 counts: persistent / captured / dispersed / other</h2>")
    have = [q for q in pts if q["an"] is not None and any(
        np.asarray(q["an"]["fates"]["persistent"]) >= 0)]
    if not have:
        R.h("<p>No case kept particle snapshots at two iterations (campaign.snapshots = true), "
            "or <code>tumble analyze campaign</code> has not run: no Fig. 8 counts.</p>")
        return
    R.h("<p>Large particles, classified by whether the Lambert image of their direction lies in "
        "a CM island (r = 0.95) at the start and at the end of the interval (lab frame): "
        "<b>persistent</b> in the <i>same</i> island at both times (the paper's definition), "
        "<b>switched</b> in an island at both times but not the same one (not a class of the "
        "paper's figure), <b>captured</b> outside → inside, <b>dispersed</b> inside → outside, "
        "<b>other</b> outside at both. Mean [95% interval, on the logit scale of 0 … the large "
        "particles of a case, a count on a bound moved half a particle inside it] (N), and the "
        "share of the large particles. <b>Chance</b>: the expected count if each particle's end "
        "position were that of a particle drawn at random (the islands' occupancy at both "
        "times kept, the link between a particle's start and end broken); <b>excess</b> = "
        "observed − chance, per replica, mean ± Student 95% half-width: a persistent excess "
        "above 0 is memory of the island, beyond what the end pattern alone gives. Yu 2022 "
        "(f = 0.15, N = 7 → 34, 1980 large): persistent 124 (6.3%), captured 429 (21.7%), "
        "dispersed 241 (12.2%), other 1186 (59.9%).</p>")
    rows, panels, warn = [], [], []
    for q in have:
        a = q["an"]
        frm, to = a["fates_from"], a["fates_to"]
        period = a.get("island_period", 0)
        span = np.nanmax(to) - np.nanmin(frm)
        if period and abs(span - period * round(span / period)) > 1e-3:  # snapshots: ± 1 step
            warn.append(f"{q['label']}: the window {np.nanmin(frm):.3g} → {np.nanmax(to):.3g} "
                        f"is not a whole number of the islands' period ({period} iterations); "
                        "islands trade places within a period, so 'persistent' and 'switched' "
                        "are mixed up")
        top = fate_bound(q)
        tot = sum(np.asarray(a["fates"][f], float) for f in FATES)
        tot = np.where(tot > 0, tot, np.nan)
        chance = a.get("fates_by_chance")
        for f in FATES:
            obs = np.array([v if v >= 0 else np.nan for v in a["fates"][f]], float)
            b = bounded_interval(obs, 0.0, top, eps=0.5)
            share = obs / tot
            row = [q["label"], f"{np.nanmin(frm):.3g} → {np.nanmax(to):.3g}", f,
                   Html(fi.ci_span(b)), f"{100 * np.nanmean(share):.1f}%"]
            if chance is not None and f in chance:
                c = np.asarray(chance[f], float)
                ex = obs - c
                m, h, n = mean_ci(ex[np.isfinite(ex)])
                row += [f"{np.nanmean(c):.1f}", f"{100 * np.nanmean(c / tot):.1f}%",
                        f"{m:+.1f} ± {h:.1f} ({n})"]
            else:
                row += ["", "", ""]
            pf = PAPER_FATES.get(f)
            row.append(f"{pf} ({100 * pf / PAPER_LARGE:.1f}%)" if pf is not None else "—")
            rows.append(row)
        ex = a.get("fate_example")
        if ex is not None:
            panels.append((f"{q['label']}, case {ex['case'][:8]}, N = {ex['frm']:.3g} → "
                           f"{ex['to']:.3g}", q["islands"], ex["fate"], ex["x_start"], ex["x_end"]))
    for w in warn:
        R.h(f"<p class='warn'>{html.escape(w)}</p>")
    R.table(["point", "iterations", "class", "count", "share", "chance", "chance share",
             "excess (observed − chance)", "Yu 2022"], rows, "fates.csv")
    if panels:
        rf.fates_fig(panels, os.path.join(R.out, "fates.png"))
        R.fig("fates.png", "Large particles at the start (left) and end (right) of the interval, "
                           "coloured by fate, with the CM islands (black), one case per point.")


def dpsi_cell(values):
    """'m ± h (N)' of the finite per-replica values [deg], '—' without any (tables 3c)."""
    m, h, n = mean_ci(np.asarray(values, float))
    return f"{m:.2f} ± {h:.2f} ({n})" if n else "—"


def section_dpsi_contrast(R, pts):
    """Yu 2022 Figs. 6-7: particles caught in period-p islands come back after p iterations, so
    their Δψ over whole periods is small; the contrast outside − inside says how much. The
    numbers are `tumble analyze campaign`'s (analysis.h5 dpsi_fields, from each case's
    collected Δψ maps), the weighting defined once there (dpsi_snapshots.hpp)."""
    have = [q for q in pts if q["an"] is not None and len(q["islands"]) > 0]
    if not displacement_groups(pts) or not have:
        return
    R.h("<h2>3c. Δψ inside and outside the CM islands, per lag</h2><p>Mean angular "
        "displacement over each collected lag of the particles that started inside the CM "
        "islands and of those that started outside (0.8 ≤ r/R ≤ 1, cells weighted by their "
        "particle count and the share of their area inside or outside the islands), per "
        "replica; <b>contrast</b> = outside − inside, mean ± Student 95% half-width (N). A "
        "positive contrast over a whole number of island periods is the paper's Figs. 6-7: "
        "particles in period-3 islands return after 3, 6, 18 iterations, the chaotic ones do "
        "not. Over a lag that is not a whole number of periods the islands' particles are "
        "elsewhere and the contrast says little.</p>")
    rows, stale = [], []
    for q in have:
        if "dpsi_fields" not in q["an"]:
            stale.append(q["label"])
            continue
        for d in q["an"]["dpsi_fields"]:
            for sp in ("large", "small"):
                rows.append([q["label"], f"{d['lag']:g}", sp]
                            + [dpsi_cell(d[f"{w}_{sp}"]) for w in ("inside", "outside", "contrast")])
    if stale:
        R.h("<p class='warn'>No contrast for " + html.escape(", ".join(stale)) + ": the "
            "campaign's analysis.h5 predates it; run <code>tumble analyze campaign DIR</code> again.</p>")
    R.table(["point", "lag [iterations]", "species", "Δψ inside [deg]", "Δψ outside [deg]",
             "contrast outside − inside [deg]"], rows, "dpsi_contrast.csv")
    section_dpsi_snapshots(R, have)


def section_dpsi_snapshots(R, pts):
    """The same contrast from the snapshots (`tumble analyze campaign --dpsi-lags`): any lag,
    every start of the Fig. 8 window, including starts past the fields' window."""
    rows = []
    for q in pts:
        for d in q["an"].get("dpsi_snapshots", []):
            ok = np.asarray(d["starts"]) > 0
            if not ok.any():
                continue
            starts = np.asarray(d["starts"])[ok]
            first, last = np.nanmin(d["first"]), np.nanmax(d["last"])
            for sp in ("large", "small"):
                cells = [dpsi_cell(np.asarray(d[f"{w}_{sp}"], float)[ok])
                         for w in ("inside", "outside", "contrast")]
                rows.append([q["label"], f"{d['lag']:g}", f"{starts.min()}-{starts.max()}",
                             f"{first:.3g}-{last:.3g}", sp] + cells)
    if not rows:
        return
    R.h("<p>From the snapshots (<code>tumble analyze campaign --dpsi-lags</code>): the same "
        "contrast for the lags asked for, summed over every start N of the Fig. 8 window with a "
        "snapshot at N + lag in it, per replica; mean ± Student 95% half-width (N).</p>")
    R.table(["point", "lag [iterations]", "starts per case", "start iterations", "species",
             "Δψ inside [deg]", "Δψ outside [deg]", "contrast outside − inside [deg]"], rows,
            "dpsi_snapshots.csv")


def section_renders(R, pts):
    if __package__:
        from . import render_bottom as rb
    else:
        import render_bottom as rb
    panels = []
    for q in pts:
        for cf in q["members"]:
            snaps = sorted(f for f in os.listdir(cf["dir"]) if f.startswith("snap_")
                           and f.endswith(".h5"))
            if snaps:
                panels.append((q, cf, [os.path.join(cf["dir"], s) for s in (snaps[0], snaps[-1])]))
                break
    if not panels:
        return
    R.h("<h2>9. Bottom views</h2><p>The tumbler wall seen from below (Yu 2022 Fig. 2): large "
        "particles blue, small red; first and last snapshot of one case per point "
        "(postproc/render_bottom.py).</p>")
    for k, (q, cf, files) in enumerate(panels):
        for w, f in zip(("first", "last"), files):
            name = f"bottom_{k}_{w}.png"
            rb.render(f, os.path.join(R.out, name), "lab", "ortho", 420)
            R.fig(name, f"{html.escape(q['label'])}, case {cf['case_id'][:8]}, {w} snapshot.")


CSS = """body{font-family:sans-serif;max-width:1200px;margin:1em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;margin:0.5em 0;font-size:0.85em}
td,th{border:1px solid #bbb;padding:2px 6px;text-align:left;vertical-align:top}
th{background:#eee} figure{margin:1em 0} img{max-width:100%} figcaption{font-size:0.85em}
#findings{border:2px solid #4a6fa5;background:#f4f8ff;padding:0.3em 1em;margin:1em 0}
#findings li{margin:0.35em 0} .context{font-size:0.9em;color:#333}
.warn{border-left:5px solid #d68910;background:#fef5e7;padding:0.4em 0.8em;margin:0.6em 0}
pre{background:#f6f6f6;padding:0.5em;font-size:0.8em;overflow-x:auto}"""

# Sets data attributes on <body> once everything has loaded: how many images the page holds and
# how many decoded (naturalWidth > 0). tests/analysis/check_report_chromium.py reads them back from
# headless Chromium's DOM.
CHECK_SCRIPT = """<script>
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0, bad = [];
  for (var i = 0; i < imgs.length; i++) {
    if (imgs[i].complete && imgs[i].naturalWidth > 0) ok++; else bad.push(imgs[i].alt);
  }
  document.body.setAttribute('data-images-total', String(imgs.length));
  document.body.setAttribute('data-images-ok', String(ok));
  document.body.setAttribute('data-images-broken', bad.join('|'));
});
</script>"""


def section_findings(camps, pts, findings):
    """The first section: the run's context, warnings, then one sentence per comparison."""
    out = ['<section id="findings"><h2>Findings</h2>']
    for c in camps:
        ctx = fi.campaign_context(c, pts)
        out.append(f'<p class="context">{html.escape(fi.context_line(ctx))}.</p>')
        nmin = min((len(q["members"]) for q in pts if q["camp"] is c), default=0)
        if nmin < 3:
            tq = f"{fi.t_quantile(0.975, nmin - 1):.3g}" if nmin >= 2 else "undefined"
            out.append(f'<p class="warn"><b>Warning: N = {nmin} replica(s)</b> at a point of '
                       f"{html.escape(c['name'])}. With N = {nmin} the 95% t quantile is {tq}: "
                       "intervals are very wide, only a very large difference can be detected, "
                       "and a variance estimated from so few replicas is itself unreliable. "
                       "Use 3 or more (5 for a referee) before drawing a conclusion.</p>")
        pc = fi.pipeline_check(ctx)
        if pc:
            out.append(f'<p class="warn">{pc}</p>')
    tilt = fi.tilt_spread_warning(pts)
    if tilt:
        out.append(f'<p class="warn">{tilt}</p>')
    sentences, csv_rows = fi.enrichment_sentences(pts)
    items = sentences + findings
    if not items:
        items = ["No comparison available: no point has CM islands (run <code>tumble analyze "
                 "campaign DIR</code>) and there is one point only."]
    out.append("<ul>" + "".join(f"<li>{s}</li>" for s in items) + "</ul>")
    out.append("<p class='context'>Intervals are 95%; 'significant' means Welch's two-sided "
               "p &lt; 0.05 with the difference's 95% interval excluding 0; map cells are "
               f"tested at a false discovery rate of {FDR_Q:.0%} (Benjamini–Hochberg). How "
               "each number is computed: the sections below and docs/report.md.</p></section>")
    return "\n".join(out), csv_rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", nargs="+", help="campaign directories (or their ensemble.h5)")
    ap.add_argument("-o", "--output", help="output directory (default RESULTS_A/report)")
    ap.add_argument("--baseline", help="the point differences are taken from: a row number "
                    "(0 = first), a label (A2) or a point id; default the first point in the "
                    "campaign file")
    ap.add_argument("--title", default="Tumble ensemble report")
    a = ap.parse_args()
    started = time.time()
    camps = [rd.load_campaign(d) for d in a.results]
    out = a.output or os.path.join(camps[0]["dir"], "report")
    R = Report(out)
    pts = gather_points(camps)
    if not pts:
        raise SystemExit("no parameter point in " + ", ".join(a.results))
    baseline = resolve_baseline(a.baseline, pts)
    R.h(f"<h1>{html.escape(a.title)}</h1><p>{len(camps)} campaign(s): "
        + ", ".join(html.escape(c["name"]) for c in camps) + f"; {len(pts)} parameter points. "
        "Every number is also in the CSV files next to this page.</p>")
    for c in camps:
        R.h(f'<p class="context">{html.escape(fi.context_line(fi.campaign_context(c, pts)))}'
            "</p>")
    findings_at = len(R.parts)
    findings = []
    map_csv = []
    section_provenance(R, camps, pts)
    section_cases(R, camps)
    section_maps(R, pts, map_csv, map_fields(pts))
    section_dpsi_contrast(R, pts)
    section_light(R, pts, map_csv)
    section_differences(R, pts, baseline, map_csv, findings)
    section_series(R, pts)
    section_scalars(R, pts, findings)
    ri.section_cross_enrichment(R, pts)
    rc.section_scalar_differences(R, pts, baseline, SCALARS, BOUNDS, findings)
    section_convergence(R, pts)
    section_fates(R, pts)
    ri.section_cross_sections(R, pts)
    section_renders(R, pts)
    text, rows = section_findings(camps, pts, findings)
    R.parts.insert(findings_at, text)
    R.csv("findings.csv", ["islands_of", "compared", "enrichment_own", "own_lower", "own_upper",
                           "enrichment_other_same_mask", "other_lower", "other_upper",
                           "difference", "welch_ci95", "welch_p", "verdict"], rows)
    R.csv("maps.csv", ["point", "field", "stat", "cell", "i", "j", "value"], map_csv)
    elapsed = time.time() - started
    R.h("<h2>Files</h2><p>" + ", ".join(f'<a href="{c}">{c}</a>' for c in R.csvs)
        + f". Report generated in {elapsed:.1f} s.</p>")
    page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(a.title)}"
            f"</title><style>{CSS}</style>{CHECK_SCRIPT}</head><body>" + "\n".join(R.parts)
            + "</body></html>")
    path = os.path.join(out, "report.html")
    with open(path, "w") as fh:
        fh.write(page)
    print(f"wrote {path} ({R.figures} figures, {len(R.csvs)} CSV files) in {elapsed:.1f} s")


if __name__ == "__main__":
    main()
