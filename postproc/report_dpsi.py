"""Report section 3c: the angular displacement Δψ of the particles that started inside the CM
islands against those outside, per collected lag (Yu 2022 Figs. 6-7), from the maps the runs
collected and from the snapshots; and which Δψ groups the campaign's fields hold."""
import html
import re

import numpy as np

if __package__:
    from .report_species import named, species_names
    from .report_stats import bounded_interval, interval_bounds_text
else:  # loaded by postproc/report.py run as a file
    from report_species import named, species_names
    from report_stats import bounded_interval, interval_bounds_text


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


# Δψ lies in [0°, 180°], so the contrast outside − inside in [−180°, 180°].
DPSI_BOUNDS = {"inside": (0.0, 180.0), "outside": (0.0, 180.0), "contrast": (-180.0, 180.0)}


def dpsi_cell(values, which):
    """'m [lower, upper] (N = n)' of the finite per-replica values [deg] of `which` (inside,
    outside, contrast): Student's interval of the mean cut at DPSI_BOUNDS, its ends rounded
    outwards; no interval at N = 1, '—' without any value (tables 3c)."""
    b = bounded_interval(np.asarray(values, float), *DPSI_BOUNDS[which])
    if not b["n"]:
        return "—"
    text = f"{b['mean']:.2f}"  # (two decimals, as the table always had: degrees)
    if np.isfinite(b["lower"]):
        lower, upper = interval_bounds_text(b)
        text += f" [{lower}, {upper}]"
    return text + f" (N = {b['n']})"


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
        "replica; <b>contrast</b> = outside − inside; mean [Student's 95% interval of the mean, cut at "
        "0°-180°, the contrast at ±180°] (N). A "
        "positive contrast over a whole number of island periods is the paper's Figs. 6-7: "
        "particles in period-3 islands return after 3, 6, 18 iterations, the chaotic ones do "
        "not. Over a lag that is not a whole number of periods the islands' particles are "
        "elsewhere and the contrast says little.</p>")
    rows, stale = [], []
    for q in have:
        names = species_names([q])  # per row: a report may hold size and density beds
        if "dpsi_fields" not in q["an"]:
            stale.append(q["label"])
            continue
        for d in q["an"]["dpsi_fields"]:
            for sp in ("large", "small"):
                rows.append([q["label"], f"{d['lag']:g}", named(sp, names)]
                            + [dpsi_cell(d[f"{w}_{sp}"], w) for w in ("inside", "outside", "contrast")])
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
        names = species_names([q])
        for d in q["an"].get("dpsi_snapshots", []):
            ok = np.asarray(d["starts"]) > 0
            if not ok.any():
                continue
            starts = np.asarray(d["starts"])[ok]
            first, last = np.nanmin(d["first"]), np.nanmax(d["last"])
            for sp in ("large", "small"):
                cells = [dpsi_cell(np.asarray(d[f"{w}_{sp}"], float)[ok], w)
                         for w in ("inside", "outside", "contrast")]
                rows.append([q["label"], f"{d['lag']:g}", f"{starts.min()}-{starts.max()}",
                             f"{first:.3g}-{last:.3g}", named(sp, names)] + cells)
    if not rows:
        return
    R.h("<p>From the snapshots (<code>tumble analyze campaign --dpsi-lags</code>): the same "
        "contrast for the lags asked for, summed over every start N of the Fig. 8 window with a "
        "snapshot at N + lag in it, per replica; mean [95% interval] (N) as above.</p>")
    R.table(["point", "lag [iterations]", "starts per case", "start iterations", "species",
             "Δψ inside [deg]", "Δψ outside [deg]", "contrast outside − inside [deg]"], rows,
            "dpsi_snapshots.csv")
