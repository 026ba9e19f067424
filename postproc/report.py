#!/usr/bin/python3
"""Ensemble comparison report: one self-contained HTML page (figures embedded), the PNG figures
and a CSV of every number, for one or more campaign directories (docs/report.md).

usage: postproc/report.py RESULTS_A [RESULTS_B ...] [-o OUTDIR] [--baseline K]

RESULTS_* are campaign directories (or their ensemble.h5). Run `tumble analyze campaign DIR`
first for the CM islands, island enrichment, Fig. 8 counts and lighter-particle maps; without
analysis.h5 those parts say so and the rest is reported. Every parameter point of every
campaign is one row; difference maps compare each point with the baseline point (the first).
"""
import argparse
import base64
import csv
import datetime
import html
import os
import platform
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report_data as rd  # noqa: E402
import report_figs as rf  # noqa: E402
import report_islands as ri  # noqa: E402
from report_stats import fmt, mean_ci, welch_half_width  # noqa: E402

MAP_FIELDS = [  # (field, label, unit factor, colour map)
    ("concentration/c_L", "c_L (large-particle concentration)", 1.0, "viridis"),
    ("displacement/dpsi_large", "Δψ large [deg]", 180 / np.pi, "magma"),
    ("displacement/dpsi_small", "Δψ small [deg]", 180 / np.pi, "magma"),
]
SERIES = [("series/shell_large_fraction", "large share of the shell 0.9 < r/R < 1"),
          ("series/radial_segregation", "radial segregation (shell share − bed share)"),
          ("series/mixing_index", "intensity of segregation of the shell map")]
FATES = ["persistent", "captured", "dispersed", "other", "same_island"]


class Report:
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
            self.h("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>")
        self.h("</table>")
        if csv_name:
            self.csv(csv_name, header, rows)

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


def short(params):
    p = rd.parse_params(params)
    keys = ["theta_z", "theta_x", "f", "R_rho", "size_ratio"]
    s = f"({p.get('theta_z', '?')}°,{p.get('theta_x', '?')}°) f={p.get('f', '?')}"
    if p.get("R_rho", "1") != "1":
        s += f" Rρ={p['R_rho']}"
    if p.get("size_ratio", "2") != "2":
        s += f" d_L/d_S={p['size_ratio']}"
    extra = [f"{k}={v}" for k, v in p.items() if k not in keys]
    return s + ("; " + ", ".join(extra) if extra else "")


def gather_points(camps):
    """Every (campaign, point) as one row, labelled A1, A2, B1, ..."""
    rows = []
    for ci, c in enumerate(camps):
        for k, (pid, p) in enumerate(sorted(c["points"].items(), key=lambda kv: kv[1]["row"])):
            label = f"{chr(65 + ci)}{k + 1} {short(p['params'])}"
            members = [cf for cf in c["case_fields"].values() if cf.get("point_id") == pid]
            members.sort(key=lambda cf: int(cf.get("replica", 0)))
            an = (c["analysis"] or {}).get(pid)
            rows.append(dict(label=label, camp=c, pid=pid, p=p, members=members, an=an,
                             islands=an["islands"] if an else []))
    return rows


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


def section_maps(R, pts, map_csv):
    R.h("<h2>3. Maps per parameter point</h2><p>Lambert equal-area projection of the lower "
        "hemisphere viewed from below (X right, Z up; docs/campaign.md). Red curves: CM island "
        "boundaries on r = 0.95 from <code>tumble analyze campaign</code>. One colour scale per "
        "field for all points; grey cells were never visited (or hold no particle of the "
        "species).</p>")
    for field, label, k, cmap in MAP_FIELDS:
        have = [q for q in pts if field in q["p"]["fields"]]
        if not have:
            continue
        means = [q["p"]["fields"][field]["mean"] * k for q in have]
        cis = [q["p"]["fields"][field]["ci95"] * k for q in have]
        rng_m = rf.finite_range(means)
        rng_c = rf.finite_range(cis, floor=0.0)
        rows = []
        for q, m, c in zip(have, means, cis):
            rows.append((q["label"], q["p"]["grid_n"], q["islands"], [m, c], None))
            n = q["p"]["grid_n"]
            map_csv += cell_rows(q["label"], field, "mean", m, n)
            map_csv += cell_rows(q["label"], field, "ci95", c, n)
            map_csv += cell_rows(q["label"], field, "count", q["p"]["fields"][field]["count"], n)
        name = "map_" + field.replace("/", "_") + ".png"
        rf.map_grid(rows, ["mean", "95% CI half-width"], os.path.join(R.out, name), label,
                    [cmap, "YlOrBr"], [rng_m, rng_c], [label, "± " + label])
        R.fig(name, f"{html.escape(label)}: ensemble mean (left) and its 95% confidence "
                    f"half-width (right) per parameter point.")


def difference_half_width(qf, bf):
    """95% half-width of mean(q) − mean(b) per cell: Welch from the variances and counts; a
    file without variances (older ensemble.h5) falls back to the quadrature sum of the two
    Student half-widths (wider than Welch's, so fewer cells pass)."""
    if "variance" in qf and "variance" in bf:
        return welch_half_width(qf["variance"], qf["count"], bf["variance"], bf["count"])
    return np.sqrt(qf["ci95"] ** 2 + bf["ci95"] ** 2)


def section_differences(R, pts, baseline, map_csv):
    R.h("<h2>4. Differences from the baseline point</h2>")
    if len(pts) < 2:
        R.h("<p>One parameter point only: nothing to compare.</p>")
        return
    base = pts[baseline]
    R.h(f"<p>Baseline: <b>{html.escape(base['label'])}</b>. Each map shows mean(point) − "
        "mean(baseline); cells where |difference| ≤ the 95% half-width of the difference are "
        "masked grey (not significant at the 5% level). The half-width is Welch's: "
        "t(0.975, ν) sqrt(s²_point/N_point + s²_baseline/N_baseline), ν by Welch–Satterthwaite, "
        "per cell from the replicas that visited it (ensemble.h5 variance and count); with "
        "fewer than 2 replicas on either side it is undefined and the cell is masked.</p>")
    for field, label, k, _ in MAP_FIELDS[:2]:
        if field not in base["p"]["fields"]:
            continue
        others = [q for i, q in enumerate(pts) if i != baseline and field in q["p"]["fields"]
                  and q["p"]["grid_n"] == base["p"]["grid_n"]]
        if not others:
            continue
        bf = base["p"]["fields"][field]
        bm = bf["mean"] * k
        diffs, masks = [], []
        for q in others:
            qf = q["p"]["fields"][field]
            d = qf["mean"] * k - bm
            half = difference_half_width(qf, bf) * k
            mask = ~(np.abs(d) > half)
            diffs.append(d)
            masks.append(mask)
            n = q["p"]["grid_n"]
            map_csv += cell_rows(q["label"], field, "diff_vs_" + base["label"].split()[0], d, n)
            map_csv += cell_rows(q["label"], field, "diff_half_width", half, n)
        rng = rf.finite_range(diffs, symmetric=True)
        rows = [(f"{q['label']} − {base['label'].split()[0]}", q["p"]["grid_n"], q["islands"],
                 [d, d], [None, m]) for q, d, m in zip(others, diffs, masks)]
        name = "diff_" + field.replace("/", "_") + ".png"
        rf.map_grid(rows, ["difference", "difference, masked within the CI"],
                    os.path.join(R.out, name), f"{label}: difference from the baseline",
                    ["RdBu_r", "RdBu_r"], [rng, rng], ["Δ " + label] * 2)
        R.fig(name, f"{html.escape(label)}: difference from the baseline, unmasked (left) and "
                    f"masked where it is within the 95% CI (right).")


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
    R.h("<h2>5. Time series</h2><p>Ensemble mean with its 95% confidence band (Student t "
        "across replicas).</p>")
    rows = []
    for k, (field, label) in enumerate(SERIES):
        curves = []
        for q in pts:
            st = q["p"]["fields"].get(field)
            if st is None or "series_iteration" not in q["p"]:
                continue
            x = q["p"]["series_iteration"]
            n = len(x)
            m, ci, cnt = st["mean"][:n], st["ci95"][:n], st["count"][:n]
            curves.append((q["label"], x, m, ci))
            rows += [[q["label"], field, j, x[j], q["p"]["series_time"][j], m[j], ci[j], cnt[j]]
                     for j in range(n)]
        if curves:
            name = f"series_{k}.png"
            rf.series_fig(curves, label, os.path.join(R.out, name), label)
            R.fig(name, f"{html.escape(label)} against the protocol iteration.")
    R.csv("series.csv", ["point", "field", "sample", "iteration", "time_s", "mean", "ci95",
                         "count"], rows)


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
        for f in FATES:
            v = an["fates"][f][j] if j is not None else -1
            s[f] = float(v) if v >= 0 else np.nan
        out.append(s)
    return out


SCALARS = ["enrichment (map)", "enrichment (last snapshot)", "shell c_L", "mean Δψ large [deg]",
           "mean Δψ small [deg]", "final mixing index", "final radial segregation"]


def section_scalars(R, pts):
    R.h("<h2>6. Scalar metrics</h2><p>Mean ± 95% CI half-width (N replicas). Island "
        "enrichment = share of the large particles inside the CM islands ÷ the islands' share "
        "of the view from below: 1 = no preference, &gt; 1 = the segregation pattern of Yu 2022 "
        "Fig. 4; undefined (–) for a protocol without islands, e.g. (68°,68°). 'map': from "
        "the case's time-averaged c_L window (0.9 &lt; r/R &lt; 1); 'last snapshot': from the "
        "particles of its last snapshot.</p>")
    per_case, rows = [], []
    for q in pts:
        sc = case_scalars(q)
        q["scalars"] = sc
        for s in sc:
            per_case.append([q["label"], s["case"], s["replica"]] + [s[k] for k in SCALARS + FATES])
        row = [q["label"]]
        for k in SCALARS:
            row.append(fmt(*mean_ci([s[k] for s in sc])))
        row.append(f"{q['an']['attrs'].get('island_area_fraction', np.nan):.3f}"
                   if q["an"] else "–")
        rows.append(row)
    R.table(["point"] + SCALARS + ["islands' area share"], rows)
    R.csv("case_scalars.csv", ["point", "case", "replica"] + SCALARS + FATES, per_case)
    summ = []
    for q in pts:
        for k in SCALARS + FATES:
            m, ci, n = mean_ci([s[k] for s in q["scalars"]])
            summ.append([q["label"], k, m, ci, n])
    R.csv("scalar_summary.csv", ["point", "metric", "mean", "ci95", "n"], summ)


def section_convergence(R, pts):
    R.h("<h2>7. Convergence with the number of replicas</h2><p>Mean over the first k replicas "
        "(in replica order) with its 95% CI, and the RMS over cells of the difference between "
        "the k-replica mean c_L map and the all-replica mean: where the curves flatten, more "
        "replicas change little.</p>")
    panels, rows = [], []
    for metric in ("enrichment (map)", "final mixing index"):
        curves = []
        for q in pts:
            v = [s[metric] for s in q["scalars"]]
            ks, ms, cs = [], [], []
            for k in range(1, len(v) + 1):
                m, ci, n = mean_ci(v[:k])
                ks.append(k), ms.append(m), cs.append(ci)
                rows.append([q["label"], metric, k, m, ci, n])
            if np.isfinite(ms).any():
                curves.append((q["label"], np.array(ks), np.array(ms), np.array(cs)))
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
            rows.append([q["label"], "rms(c_L mean_k - mean_all)", k, r, np.nan, k])
        curves.append((q["label"], np.array(ks), np.array(rms), np.full(len(ks), np.nan)))
    if curves:
        panels.append(("c_L map: RMS(mean of k − mean of all)", "RMS over cells", curves))
    if panels:
        rf.convergence_fig(panels, os.path.join(R.out, "convergence.png"))
        R.fig("convergence.png", "Convergence of the ensemble mean with the number of replicas.")
    R.csv("convergence.csv", ["point", "metric", "k", "mean", "ci95", "n"], rows)


def section_fates(R, pts):
    R.h("<h2>8. Fig. 8 counts: persistent / captured / dispersed / other</h2>")
    have = [q for q in pts if q["an"] is not None and any(
        np.asarray(q["an"]["fates"]["persistent"]) >= 0)]
    if not have:
        R.h("<p>No case kept particle snapshots at two iterations (campaign.snapshots = true), "
            "or <code>tumble analyze campaign</code> has not run: no Fig. 8 counts.</p>")
        return
    R.h("<p>Large particles, classified by whether the Lambert image of their direction lies in "
        "a CM island (r = 0.95) at the start and at the end of the interval (lab frame). "
        "'same island' counts the persistent ones in the same island at both times (the "
        "paper's text). Yu 2022, f = 0.15, N = 7 → 34, 1980 large: persistent 124, captured "
        "429, dispersed 241, other 1186.</p>")
    rows, panels = [], []
    for q in have:
        a = q["an"]
        frm, to = a["fates_from"], a["fates_to"]
        row = [q["label"], f"{np.nanmin(frm):.3g} → {np.nanmax(to):.3g}"]
        for f in FATES:
            row.append(fmt(*mean_ci([v if v >= 0 else np.nan for v in a["fates"][f]])))
        rows.append(row)
        ex = a.get("fate_example")
        if ex is not None:
            panels.append((f"{q['label']} case {ex['case'][:8]} N = {ex['frm']:.3g} → "
                           f"{ex['to']:.3g}", q["islands"], ex["fate"], ex["x_start"], ex["x_end"]))
    R.table(["point", "iterations"] + FATES, rows, "fates.csv")
    if panels:
        rf.fates_fig(panels, os.path.join(R.out, "fates.png"))
        R.fig("fates.png", "Large particles at the start (left) and end (right) of the interval, "
                           "coloured by fate, with the CM islands (black), one case per point.")


def section_renders(R, pts):
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", nargs="+", help="campaign directories (or their ensemble.h5)")
    ap.add_argument("-o", "--output", help="output directory (default RESULTS_A/report)")
    ap.add_argument("--baseline", type=int, default=0, help="row of the baseline point")
    ap.add_argument("--title", default="Tumble ensemble report")
    a = ap.parse_args()
    started = time.time()
    camps = [rd.load_campaign(d) for d in a.results]
    out = a.output or os.path.join(camps[0]["dir"], "report")
    R = Report(out)
    pts = gather_points(camps)
    if not pts:
        raise SystemExit("no parameter point in " + ", ".join(a.results))
    if not 0 <= a.baseline < len(pts):
        raise SystemExit(f"--baseline {a.baseline}: must be in [0, {len(pts) - 1}]")
    R.h(f"<h1>{html.escape(a.title)}</h1><p>{len(camps)} campaign(s): "
        + ", ".join(html.escape(c["name"]) for c in camps) + f"; {len(pts)} parameter points. "
        "Every number is also in the CSV files next to this page.</p>")
    map_csv = []
    section_provenance(R, camps, pts)
    section_cases(R, camps)
    section_maps(R, pts, map_csv)
    section_light(R, pts, map_csv)
    section_differences(R, pts, a.baseline, map_csv)
    section_series(R, pts)
    section_scalars(R, pts)
    ri.section_cross_enrichment(R, pts)
    section_convergence(R, pts)
    section_fates(R, pts)
    ri.section_cross_sections(R, pts)
    section_renders(R, pts)
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
