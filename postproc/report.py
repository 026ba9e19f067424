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
    from .report_dpsi import displacement_groups, section_dpsi_contrast
    from .report_fates import section_fates
    from .report_page import CHECK_SCRIPT, CSS, Report
    from .report_scalars import BOUNDS, SCALARS, section_convergence, section_scalars
    from .report_stats import (bounded_interval, bh_reject, cell_tests, cut_to_bounds,
                               welch_half_width)
    from .report_species import named, species_names
else:  # /usr/bin/python3 postproc/report.py: the script's directory is sys.path[0]
    import report_compare as rc
    import report_data as rd
    import report_figs as rf
    import report_findings as fi
    import report_islands as ri
    from report_dpsi import displacement_groups, section_dpsi_contrast
    from report_fates import section_fates
    from report_page import CHECK_SCRIPT, CSS, Report
    from report_scalars import BOUNDS, SCALARS, section_convergence, section_scalars
    from report_stats import (bounded_interval, bh_reject, cell_tests, cut_to_bounds,
                              welch_half_width)
    from report_species import named, species_names

MAP_FIELDS = [  # (field, label, unit factor, colour map, physical bounds in the shown unit)
    ("concentration/c_L", "c_L (species 1, the large particles' share)", 1.0, "viridis", (0.0, 1.0)),
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


def map_fields(pts):
    """MAP_FIELDS with a Δψ pair for every further lag the campaigns collected, each labelled
    with the species' names (report_species)."""
    names = species_names(pts)
    out = [(f, named(label, names), k, cmap, b) for f, label, k, cmap, b in MAP_FIELDS]
    for g, k in displacement_groups(pts):
        if g == "displacement":
            continue
        for sp in ("large", "small"):
            field = f"{g}/dpsi_{sp}"
            EMPTY_COUNT[field] = f"{g}/count_{sp}"
            out.append((field, named(f"Δψ {sp} over {k} iterations [deg]", names), 180 / np.pi,
                        "magma", (0.0, 180.0)))
    return out


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
        "species). Right: the width (upper − lower) of each cell's 95% confidence interval of the "
        "mean (Student's, cut at the quantity's physical range: c_L in [0, 1], Δψ in "
        "[0°, 180°]); a width equal to the range says the replicas "
        "do not constrain the cell at all, a width of 0 that they agree exactly (e.g. no "
        f"{html.escape(species_names(pts)[1])} particle in any replica): with N = 2 that is "
        "not certainty.</p>")
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


def section_differences(R, pts, baseline, map_csv, findings, fields):
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
        f"empty in both points (no particle of the field's species, {species_names(pts)[1]} "
        "for c_L, in any "
        "replica of either), had fewer than 2 replicas on a side, or had no variance on "
        "either side (the test is undefined there, so such a cell is neither significant nor "
        "counted among the tests).</p>")
    summary = []
    for field, label, k, _, _ in fields[:2]:
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
    # analysis.h5 holds Student's half-width h (C++, replica_stats); a share lies in [0, 1], so
    # the interval [m − h, m + h] is cut there (report_stats.cut_to_bounds) and its width shown,
    # as the other maps show theirs.
    cis = []
    for q in have:
        m, h = np.asarray(q["an"]["light_mean"], float), np.asarray(q["an"]["light_ci95"], float)
        lower, upper = cut_to_bounds(m - h, m + h, 0.0, 1.0)
        cis.append(upper - lower)
    rows = [(q["label"] + f" [{q['an']['attrs'].get('light_source', '')}]", q["p"]["grid_n"],
             q["islands"], [m, c], None) for q, m, c in zip(have, means, cis)]
    for q, m, c in zip(have, means, cis):
        map_csv += cell_rows(q["label"], "light_concentration", "mean", m, q["p"]["grid_n"])
        map_csv += cell_rows(q["label"], "light_concentration", "ci95", q["an"]["light_ci95"],
                             q["p"]["grid_n"])
        map_csv += cell_rows(q["label"], "light_concentration", "ci95_width_cut", c,
                             q["p"]["grid_n"])
    rf.map_grid(rows, ["mean", "95% CI width (cut at [0, 1])"],
                os.path.join(R.out, "map_light.png"), "lighter-particle concentration",
                ["cividis", "YlOrBr"], [rf.finite_range(means), rf.finite_range(cis, floor=0.0)],
                ["c_light", "CI width"])
    R.fig("map_light.png", "Lighter species' share of the solid volume near the wall, mean and "
                           "the width of its 95% CI across replicas (Student's, cut at [0, 1]).")


def section_series(R, pts):
    R.h("<h2>5. Time series</h2><p>Ensemble mean with its 95% confidence band across "
        "replicas (Student's interval of the mean, cut at each quantity's physical range).</p>")
    rows = []
    names = species_names(pts)
    for k, (field, label, (lo, hi)) in enumerate(SERIES):
        label = named(label, names)
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
    n0, n1 = species_names(pts)
    R.h("<h2>9. Bottom views</h2><p>The tumbler wall seen from below (Yu 2022 Fig. 2): "
        f"{html.escape(n1)} particles (species 1) blue, {html.escape(n0)} red; first and last "
        "snapshot of one case per point "
        "(postproc/render_bottom.py).</p>")
    for k, (q, cf, files) in enumerate(panels):
        for w, f in zip(("first", "last"), files):
            name = f"bottom_{k}_{w}.png"
            rb.render(f, os.path.join(R.out, name), "lab", "ortho", 420)
            R.fig(name, f"{html.escape(q['label'])}, case {cf['case_id'][:8]}, {w} snapshot.")


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
               "p, Holm-adjusted over the sentences above, &lt; 0.05 with the 95% interval "
               "excluding no difference (1 for a ratio of geometric means, 0 for a "
               "difference); map cells are "
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
    fields = map_fields(pts)
    section_maps(R, pts, map_csv, fields)
    section_dpsi_contrast(R, pts)
    section_light(R, pts, map_csv)
    section_differences(R, pts, baseline, map_csv, findings, fields)
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
                           "compared_as", "estimate", "ci95_lower", "ci95_upper", "welch_p",
                           "welch_p_holm", "verdict"], rows)
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
