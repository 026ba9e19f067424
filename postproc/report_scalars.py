"""Report sections 6 and 7: the scalar metrics of every case (island enrichment, shell share
ratio, shell c_L, Δψ, mixing index and its random-bed baseline, radial segregation, repose tilt,
Fig. 8 counts) with intervals within their physical bounds, and their convergence with the
number of replicas."""
import os
import re

import numpy as np

if __package__:
    from . import report_figs as rf
    from . import report_findings as fi
    from . import report_mixing as rm
    from .report_fates import FATES, fate_bound
    from .report_page import Html
    from .report_species import named, species_names
    from .report_stats import bounded_interval, fmt, mean_ci
else:  # loaded by postproc/report.py run as a file
    import report_figs as rf
    import report_findings as fi
    import report_mixing as rm
    from report_fates import FATES, fate_bound
    from report_page import Html
    from report_species import named, species_names
    from report_stats import bounded_interval, fmt, mean_ci


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
        "interval is Student's interval of the mean, cut at the quantity's physical bounds "
        "(which loses no coverage: the mean lies inside them): 0 for the enrichment, [0, 1] for "
        "shares and indices, [0°, 180°] for Δψ, [−1, 1] for the radial segregation. Island enrichment = share of the large particles (the light ones in a "
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
    # The metrics are keyed by their size-bed names; shown with the species' own names.
    names = species_names(pts)
    shown = [named(k, names) for k in SCALARS]
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
    R.table(["point"] + shown + ["mixing index of a random bed, same particles",
                                   "mixing index − random (last snapshot)",
                                   "islands' area share"], rows, "scalar_table.csv")
    R.csv("case_scalars.csv", ["point", "case", "replica"] + shown + FATES, per_case)
    summ = []
    for q in pts:
        for k in SCALARS + FATES:
            m, ci, n = mean_ci([s[k] for s in q["scalars"]])
            lo, hi = BOUNDS.get(k, (0.0, fate_bound(q)))
            b = bounded_interval([s[k] for s in q["scalars"]], lo, hi)
            summ.append([q["label"], named(k, names), m, ci, b["lower"], b["upper"], n])
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
