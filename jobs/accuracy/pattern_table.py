#!/usr/bin/python3
"""Pattern observables per fidelity tier (jobs/accuracy/pattern_accuracy.sh writes the input):
wall time per iteration, the rigid bulk's frozen share (mean over the run; reported, not tested),
radial segregation at the end of every iteration, island enrichment,
and the correlation of each replica's c_L map with the reference tier's mean map; mean ± 95% CI
over replicas (Student t; for the bounded ones, the frozen share, enrichment, correlation and
radial segregation, mean [Student's interval cut at the bounds]) and each tier's difference from
the reference with Welch's 95% interval (cut at ±(hi − lo) for a bounded observable).
The first tier present in the order reference, standard, fast, preview is the reference.

usage: jobs/accuracy/pattern_table.py OUT ITERATIONS [--point "theta_z=57;theta_x=57"]
                                      [--split KEY=REF,OTHER,...] [--tier LABEL=DIR ...]
(--point: only the cases whose params hold every given name=value, for campaigns of several
points, jobs/accuracy/campaign_tiers.sh;
--split: OUT is one campaign, and its cases are compared by the value of a swept KEY instead of by
tier folder, the first value being the reference, e.g. --split fidelity.bulk=dynamic,rigid
(jobs/accuracy/rigid_pattern.sh); a value may name more swept keys after '+', e.g.
--split fidelity.bulk=dynamic,rigid,rigid+fidelity.bulk_segment_thaw=off: a column then takes the
cases whose params hold its key=values and lack every other key that some column names (the plain
"rigid" column: the cases without fidelity.bulk_segment_thaw in their params); points that differ
only in such keys share their replicas' beds, so the differences are also given paired by replica
(Student t on the differences);
radial segregation reported at iterations 1..ITERATIONS; each tier's wall per iteration from its
own runs' length, so tiers run for different numbers of iterations can share one table, and from
all of a case's calls when it was stopped and resumed (their steps and wall times summed; logs
from before stopped calls printed theirs hold only the last call's);
--tier: the columns are the campaigns in the DIRs given, in that order, the first the reference,
instead of OUT's tier folders (OUT is then ignored), e.g. the dynamic cases of two rigid_pattern.sh
campaigns at different tiers: --tier standard=results/rigid_pattern/bst_small_standard
--tier fast=results/rigid_pattern/bst_small_fast --point fidelity.bulk=dynamic).

Below the table: the p-values of the differences (Welch's t, and Student's t on the paired
differences with --split), with the Benjamini-Hochberg procedure at q = 0.05 over each column's
family of tested differences, so that one "significant" row among a dozen is not read as a
finding; and a warning when a column has fewer than 5 replicas."""
import glob
import os
import re
import signal
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
from report_stats import (bh_reject, bounded_interval, cut_to_bounds, fmt, fmt_interval,  # noqa: E402
                          mean_ci, welch_half_width)
from scipy import stats  # noqa: E402

TIERS = ["reference", "standard", "fast", "preview"]
# The observables' physical bounds (the others, wall times, have none that matters): their
# intervals are Student's cut at the bounds, their differences' at ±(hi − lo)
# (report_stats.bounded_interval, cut_to_bounds).
FROZEN = "frozen share of the bed (run mean)"


def bounds_of(name):
    if name == FROZEN:
        return 0.0, 1.0
    if name == "island enrichment":
        return 0.0, np.inf
    if name.startswith("c_L pattern correlation") or name.startswith("radial segregation"):
        return -1.0, 1.0
    return None, None


def difference_text(d, half, lo, hi):
    """'+d ± h', or '+d [lower, upper]' where the interval is cut at ±(hi − lo)."""
    if lo is None or hi is None or not np.isfinite(hi):
        return f"{d:+.3g} ± {half:.2g}"
    lower, upper = cut_to_bounds(d - half, d + half, -(hi - lo), hi - lo)
    if lower == d - half and upper == d + half:
        return f"{d:+.3g} ± {half:.2g}"
    return f"{d:+.3g} [{float(lower):+.2g}, {float(upper):+.2g}]"


def text(a):
    return a.decode() if isinstance(a, bytes) else str(a)


def at_point(params, point):
    """Whether a case's params text ("theta_z=57;theta_x=57;f=0.15;...") holds every name=value of
    point (numbers compared as numbers)."""
    have = dict(kv.split("=", 1) for kv in params.split(";") if "=" in kv)
    for kv in filter(None, point.split(";")):
        k, v = kv.split("=", 1)
        if k not in have:
            return False
        try:
            if float(have[k]) != float(v):
                return False
        except ValueError:
            if have[k] != v:
                return False
    return True


def load_tier(d, iterations, point="", absent=()):
    """Per finished case at the point (and without any of the keys in absent): c_L map, radial
    segregation at iterations 1..N, wall per iteration, island enrichment (analysis.h5)."""
    enrich = {}
    an = os.path.join(d, "analysis.h5")
    if os.path.exists(an):
        with h5py.File(an, "r") as f:
            for g in f["points"].values():
                for cid, e in zip(text(g.attrs["cases"]).split("\n"), g["enrichment_map"][:]):
                    enrich[cid] = float(e)
    cases = []
    for path in sorted(glob.glob(os.path.join(d, "cases", "*", "fields.h5"))):
        with h5py.File(path, "r") as f:
            params = text(f.attrs["params"])
            if not at_point(params, point) or any(f";{k}=" in f";{params}" for k in absent):
                continue
            cid = text(f.attrs["case_id"])
            it, rs = f["series/iteration"][:], f["series/radial_segregation"][:]
            c = dict(id=cid, params=params, replica=int(f.attrs.get("replica", -1)),
                     c_L=f["concentration/c_L"][:].ravel(),
                     radial=[float(rs[np.argmin(np.abs(it - k))]) for k in range(1, iterations + 1)],
                     enrichment=enrich.get(cid, np.nan), wall=np.nan, frozen=np.nan)
        # The rigid bulk's frozen share, the mean of the run's series (results.h5, written by
        # every call with the whole run's series; a dynamic bulk has none).
        res = os.path.join(os.path.dirname(path), "results.h5")
        if os.path.exists(res):
            with h5py.File(res, "r") as f:
                if "series/frozen_fraction" in f:
                    c["frozen"] = float(np.mean(f["series/frozen_fraction"][:]))
        log = os.path.join(os.path.dirname(path), "log.txt")
        if os.path.exists(log):
            txt = open(log).read()
            # Every call's steps and wall time (a finished call's done line, a stopped call's
            # "this call ran S steps in W s"), summed: the case's mean rate over all its calls,
            # times the steps of one iteration (the run's own steps and length from its header).
            # Logs from before the stopped calls said it have only the last call's done line.
            m = re.findall(r"(?:\[run\] done:|this call ran) (\d+) steps in ([0-9.e+]+) s", txt)
            n = re.findall(r"s simulated, ([0-9.]+) iterations[,)]", txt)
            total = re.findall(r" s, (\d+) steps \(", txt)
            steps, wall = sum(int(k[0]) for k in m), sum(float(k[1]) for k in m)
            if n and total and steps > 0:
                c["wall"] = wall / steps * int(total[-1]) / float(n[-1])
        cases.append(c)
    return cases


def corr(a, b):
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < 3:
        return np.nan
    return float(np.corrcoef(a[ok], b[ok])[0, 1])


def pattern_correlation(c, k, is_ref, ref_maps, ref_replicas, paired):
    """Correlation of case c's c_L map with the mean map of N - 1 reference replicas, so that
    every column is measured against a reference of the same size: the reference's own replica k
    against the others (leave-one-out: a replica correlates with itself otherwise); with common
    beds (--split) another column's replica against the reference replicas on the other beds (its
    own bed's would share its start); else against each leave-one-out mean in turn, averaged. (A
    mean of all N reference maps is less noisy than one of N - 1 and correlates better with
    anything: compared with the reference's leave-one-out values it favoured the other column,
    by +0.07 to +0.4 on bst_small's maps at N = 3.)"""
    n = len(ref_maps)
    if n < 2:
        return np.nan
    if is_ref:
        return corr(c["c_L"], np.nanmean(np.delete(ref_maps, k, axis=0), axis=0))
    if paired and c["replica"] in ref_replicas:
        j = ref_replicas.index(c["replica"])
        return corr(c["c_L"], np.nanmean(np.delete(ref_maps, j, axis=0), axis=0))
    return float(np.nanmean([corr(c["c_L"], np.nanmean(np.delete(ref_maps, j, axis=0), axis=0))
                             for j in range(n)]))


def take(args, flag):
    """Remove every `flag VALUE` from args; their values in order."""
    values = []
    while flag in args:
        k = args.index(flag)
        if k + 1 >= len(args):
            raise SystemExit(f"{flag} needs a value")
        values.append(args[k + 1])
        del args[k:k + 2]
    return values


def main():
    args = sys.argv[1:]
    point = ";".join(take(args, "--point"))
    split = (take(args, "--split") or [""])[-1]
    tiers = take(args, "--tier")
    if len(args) != 2:
        raise SystemExit(__doc__)
    out, iterations = args[0], int(args[1])
    if split:
        key, values = split.split("=", 1)
        # "rigid+k=v": the column's own conditions; every key some column names must be absent
        # from the cases of a column that does not name it.
        conds = {v: [f"{key}={v.split('+')[0]}"] + v.split("+")[1:] for v in values.split(",")}
        named = {c.split("=", 1)[0] for cs in conds.values() for c in cs}
        data = {v: load_tier(out, iterations, ";".join(filter(None, [point] + cs)),
                             absent=named - {c.split("=", 1)[0] for c in cs})
                for v, cs in conds.items()}
        data = {v: cases for v, cases in data.items() if cases}
        if not data:
            raise SystemExit(f"{out}: no finished case with any value of {key}")
        ref = values.split(",")[0]
        if ref not in data:
            raise SystemExit(f"{out}: no finished case with {key}={ref} (the reference)")
    elif tiers:
        dirs = [t.split("=", 1) for t in tiers]
        if any(len(d) != 2 or not os.path.isdir(d[1]) for d in dirs):
            raise SystemExit("--tier takes LABEL=DIR with DIR a campaign's output folder")
        data = {label: load_tier(d, iterations, point) for label, d in dirs}
        ref = dirs[0][0]
        if not data[ref]:
            raise SystemExit(f"{dirs[0][1]}: no finished case (the reference, {ref})")
        data = {t: cases for t, cases in data.items() if cases}
    else:
        data = {t: load_tier(os.path.join(out, t), iterations, point) for t in TIERS
                if glob.glob(os.path.join(out, t, "cases", "*", "fields.h5"))}
        data = {t: cases for t, cases in data.items() if cases}
        if not data:
            raise SystemExit(f"{out}: no finished case of any tier")
        ref = next(t for t in TIERS if t in data)
    # A column is one point's replicas: cases of two points (another swept key the selection
    # does not name) would be averaged as if they were one, so that is refused.
    for t, cases in data.items():
        points = sorted({c["params"] for c in cases})
        if len(points) > 1:
            raise SystemExit(f"column {t} holds cases of {len(points)} points:\n  " + "\n  ".join(points)
                             + "\nname the one wanted (--point, or with --split a value KEY=V+OTHER=W for"
                             " each, which also keeps the others out of the plain column)")
    ref_maps = np.array([c["c_L"] for c in data[ref]])
    ref_replicas = [c["replica"] for c in data[ref]]
    for t, cases in data.items():
        for k, c in enumerate(cases):
            c["corr"] = pattern_correlation(c, k, t == ref, ref_maps, ref_replicas, bool(split))
    # Costs first, reported but not tested: the wall time (which depends on the machine and its
    # load) and the frozen share (which only a rigid bulk has; it explains the wall time).
    untested = ("wall per iteration [s]", FROZEN)
    metrics = [("wall per iteration [s]", lambda c: c["wall"]),
               (FROZEN, lambda c: c["frozen"]),
               ("island enrichment", lambda c: c["enrichment"]),
               ("c_L pattern correlation with " + ref, lambda c: c["corr"])]
    # "after k iterations", not "N = k": N is the number of replicas everywhere else in the table.
    metrics += [(f"radial segregation after {k + 1} iteration{'s' if k else ''}", lambda c, k=k: c["radial"][k])
                for k in range(iterations)]
    if point:
        print(f"# point: {point}")
    what = split.split("=")[0] if split else "tier"
    print(f"# reference {what}: {ref}; mean ± 95% CI (N replicas); Δ = {what} − {ref} ± Welch 95%")
    print("| observable | " + " | ".join(data) + " |")
    print("|---|" + "---|" * len(data))
    # Per column: (observable, kind, p) of every tested difference, for the multiplicity control.
    tested = {t: [] for t in data if t != ref}
    for name, get in metrics:
        lo, hi = bounds_of(name)
        rv = np.array([get(c) for c in data[ref]], float)
        cells = []
        for t, cases in data.items():
            v = np.array([get(c) for c in cases], float)
            s = fmt(*mean_ci(v)) if lo is None else fmt_interval(bounded_interval(v, lo, hi))
            if t != ref and np.isfinite(v).sum() and name not in untested:
                va, vb = v[np.isfinite(v)], rv[np.isfinite(rv)]
                if len(va) >= 2 and len(vb) >= 2:
                    h = welch_half_width([va.var(ddof=1)], [len(va)], [vb.var(ddof=1)], [len(vb)])[0]
                    s += f"; Δ {difference_text(va.mean() - vb.mean(), h, lo, hi)}"
                    if h > 0:
                        tested[t].append((name, "Welch", stats.ttest_ind(va, vb, equal_var=False).pvalue))
                if split:  # common beds: the same replica's difference, paired by Student t
                    ref_by = {c["replica"]: get(c) for c in data[ref]}
                    d = [get(c) - ref_by[c["replica"]] for c in cases if c["replica"] in ref_by]
                    m, ci, n = mean_ci(d)
                    if n >= 2:
                        s += f"; paired Δ {difference_text(m, ci, lo, hi)}"
                        d = np.asarray(d, float)
                        d = d[np.isfinite(d)]
                        if d.std(ddof=1) > 0:
                            tested[t].append((name, "paired", stats.ttest_1samp(d, 0.0).pvalue))
            cells.append(s)
        print(f"| {name} | " + " | ".join(cells) + " |")
    print_multiplicity(tested, ref, what)
    small = {t: len(c) for t, c in data.items() if len(c) < 5}
    if small:
        # (Said for the smallest N present: it bounds what any column here can resolve.)
        n_min = min(small.values())
        if n_min < 2:
            size = (f"at N = {n_min} there is no interval and no test, only the value, so nothing"
                    " here can show a difference")
        else:
            t_q = stats.t.ppf(0.975, n_min - 1)
            size = (f"a 95% CI at N = {n_min} spans ±{t_q:.2g} standard errors (t(0.975, {n_min - 1});"
                    f" ±{t_q / np.sqrt(n_min):.2g} standard deviations of the replicas), so only"
                    " differences of about that size can show")
        print("# warning: few replicas (" + ", ".join(f"{t}: N = {n}" for t, n in small.items())
              + f"): {size}; 'not significant' here means 'not resolved at this N', not 'equal'.")


def print_multiplicity(tested, ref, what):
    """Each column's p-values with the Benjamini-Hochberg procedure at q = 0.05 over its family
    (every tested observable, Welch and paired counted as separate tests)."""
    for t, rows in tested.items():
        if not rows:
            continue
        p = np.array([r[2] for r in rows], float)
        reject, adjusted = bh_reject(p, 0.05)
        print(f"# {what} {t} − {ref}: {len(rows)} tests; Benjamini-Hochberg at q = 0.05: "
              f"{int(reject.sum())} significant")
        for (name, kind, pv), r, a in zip(rows, reject, adjusted):
            print(f"#   {name} ({kind}): p = {pv:.3g}, BH-adjusted {a:.3g}{' *' if r else ''}")


if __name__ == "__main__":
    # Piped to `head`, the table stops where the reader stopped, without a traceback.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    main()
