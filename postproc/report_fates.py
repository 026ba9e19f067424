"""Report section 8: the Fig. 8 counts of Yu 2022 (persistent, switched, captured, dispersed,
other) per point against chance and the paper's counts."""
import html
import os

import numpy as np

if __package__:
    from . import report_figs as rf
    from . import report_findings as fi
    from .report_page import Html
    from .report_stats import bounded_interval, interval_bounds_text
else:  # loaded by postproc/report.py run as a file
    import report_figs as rf
    import report_findings as fi
    from report_page import Html
    from report_stats import bounded_interval, interval_bounds_text


FATES = ["persistent", "switched", "captured", "dispersed", "other"]


# Yu 2022 Fig. 8 (f = 0.15, N = 7 -> 34, 1980 large particles); "switched" is not one of its classes
PAPER_FATES = {"persistent": 124, "captured": 429, "dispersed": 241, "other": 1186}


PAPER_LARGE = 1980


def fate_bound(q):
    """The most large particles a Fig. 8 class can hold in a case of q (the four classes sum
    to the large particles present at both times)."""
    an = q["an"]
    if an is None:
        return np.inf
    tot = sum(np.asarray(an["fates"][f], float) for f in FATES)
    tot = tot[tot >= 0]
    return float(tot.max()) if tot.size else np.inf


def section_fates(R, pts):
    R.h("<h2>8. Fig. 8 counts: persistent / captured / dispersed / other</h2>")
    have = [q for q in pts if q["an"] is not None and any(
        np.asarray(q["an"]["fates"]["persistent"]) >= 0)]
    if not have:
        R.h("<p>No case kept particle snapshots at two iterations (campaign.snapshots = true), "
            "or <code>tumble analyze campaign</code> has not run: no Fig. 8 counts.</p>")
        return
    m = html.escape(fi.mapped_name(have[0]))  # the species the maps show: large, or light
    R.h(f"<p>{m.capitalize()} particles, classified by whether the Lambert image of their "
        "direction lies in a CM island (r = 0.95) at the start and at the end of the interval (lab frame): "
        "<b>persistent</b> in the <i>same</i> island at both times (the paper's definition), "
        "<b>switched</b> in an island at both times but not the same one (not a class of the "
        "paper's figure), <b>captured</b> outside → inside, <b>dispersed</b> inside → outside, "
        "<b>other</b> outside at both. Mean [95% interval of the mean, Student's, cut at 0 and the "
        f"{m} particles of a case] (N), and "
        f"the share of the {m} particles. <b>Chance</b>: the expected count if each particle's end "
        "position were that of a particle drawn at random (the islands' occupancy at both "
        "times kept, the link between a particle's start and end broken); <b>excess</b> = "
        "observed − chance, per replica, mean [Student's 95% interval of the mean] (N): a persistent excess "
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
            b = bounded_interval(obs, 0.0, top)
            share = obs / tot
            row = [q["label"], f"{np.nanmin(frm):.3g} → {np.nanmax(to):.3g}", f,
                   Html(fi.ci_span(b)), f"{100 * np.nanmean(share):.1f}%"]
            if chance is not None and f in chance:
                c = np.asarray(chance[f], float)
                # The excess over chance, a difference of two counts of 0 … top particles.
                e = bounded_interval(obs - c, -top, top)
                ex_text = "—"
                if e["n"]:
                    ex_text = f"{e['mean']:+.1f}"
                    if np.isfinite(e["lower"]):
                        lower, upper = interval_bounds_text(e)  # (rounded outwards)
                        ex_text += f" [{lower}, {upper}]"
                    ex_text += f" (N = {e['n']})"
                row += [f"{np.nanmean(c):.1f}", f"{100 * np.nanmean(c / tot):.1f}%", ex_text]
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
