"""The report's statistics (postproc/report_stats.py) against closed forms and hand-computed
examples.

  PYTHONPATH=SOURCE_ROOT /usr/bin/python3 report_stats_check.py [stats|bounded|fdr|cells|tilt|
                                                                  compare|enrichment|species]

  stats    Student t quantiles (scipy) and Welch's half-width of a difference of two means;
  bounded  intervals of bounded quantities (Student's, cut at the bounds): closed forms, never
           outside the bounds where the Student interval is, always around the mean, the same
           coverage as Student's, per-cell form, differences of shares, printing;
  fdr      Benjamini-Hochberg: a hand-computed example (with the step-up case), NaN not
           counted, scipy.stats.false_discovery_control where this scipy has it (>= 1.11), and
           the rate of any false discovery over 144 null cells;
  cells    the difference maps' per-cell test: Welch's p equal to scipy's ttest_ind on the
           replicas, and the cells excluded from testing (empty in both, < 2 replicas, no
           variance) neither significant nor counted in the number of tests;
  tilt     the Findings' warning when points were tilted to repose angles more than 0.3 deg
           apart (postproc/report_findings.py), on constructed points;
  compare  section 6c (postproc/report_compare.py): Holm's adjustment (a hand-computed example,
           NaN not counted, the family-wise error over 10 null tests), the ratio of geometric
           means against scipy's Welch test on the logarithms, and the tests of constructed
           points (a ratio, a difference where a replica is 0, a metric missing at a point);
  enrichment  the Findings' enrichment sentences (postproc/report_findings.py) on constructed
           points: the same ratio of geometric means and p as section 6c (scipy's Welch on the
           logarithms), the verdict from that test (a pair the arithmetic Welch test would call
           inconclusive), a replica at 0 compared as a difference, N = 2 called inconclusive;
  species  the species' names in the report's labels (postproc/report_species.py): from the
           files' attributes, "large" relabelled only where the bed is not a size mixture.
No argument: all groups. ctest runs each group as its own test (tests/analysis/CMakeLists.txt).
"""
import math
import sys
import warnings

import numpy as np
from scipy import stats

from postproc.report_stats import (bh_reject, bounded_interval, cell_tests, compare_values,
                                   holm_adjust,
                                   interval_bounds_text, mean_ci, t_quantile, welch_half_width,
                                   welch_log_ratio)


def check(name, got, want, tol):
    ok = (math.isnan(want) and math.isnan(got)) or abs(got - want) <= tol
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {got!r} (expected {want!r} ± {tol})")
    return ok


def truth(name, cond, detail=""):
    print(f"{'ok  ' if cond else 'FAIL'} {name}{': ' + detail if detail else ''}")
    return bool(cond)


T1 = math.tan(0.475 * math.pi)              # t(0.975, 1), closed form
T2 = 0.95 / math.sqrt(2 * 0.975 * 0.025)    # t(0.975, 2), closed form
T10 = 2.2281388519862747                    # t(0.975, 10)


def group_stats():
    good = [
        check("t(0.975, 1) = tan(0.475 pi)", t_quantile(0.975, 1), T1, 1e-9),
        check("t(0.975, 2)", t_quantile(0.975, 2), T2, 1e-9),
        check("t(0.975, 10)", t_quantile(0.975, 10), T10, 1e-9),
    ]
    m, ci, n = mean_ci([1.0, 2.0, 3.0])
    good.append(check("mean_ci of 1, 2, 3: t(0.975, 2) / sqrt(3)", ci, T2 / math.sqrt(3), 1e-9))
    # Equal variances, two replicas each: Welch's nu = (2 s^2/2)^2 / (2 (s^2/2)^2 / 1) = 2.
    h = welch_half_width([0.5], [2], [0.5], [2])[0]
    good.append(check("equal variances, n = 2 + 2: t(0.975, 2) sqrt(0.5)", h,
                      T2 * math.sqrt(0.5), 1e-9))
    # One side exactly reproducible (variance 0): nu = n_a - 1, half-width = Student's of side a.
    h = welch_half_width([0.3], [11], [0.0], [4])[0]
    good.append(check("zero variance on one side: t(0.975, 10) sqrt(0.3/11)", h,
                      T10 * math.sqrt(0.3 / 11), 1e-9))
    # Unequal: nu = (0.04/5 + 0.01/4)^2 / ((0.04/5)^2/4 + (0.01/4)^2/3).
    sa, sb = 0.04 / 5, 0.01 / 4
    nu = (sa + sb) ** 2 / (sa ** 2 / 4 + sb ** 2 / 3)
    h = welch_half_width([0.04], [5], [0.01], [4])[0]
    good.append(check(f"unequal (nu = {nu:.4f})", h,
                      stats.t.ppf(0.975, nu) * math.sqrt(sa + sb), 1e-9))
    good.append(check("one replica: NaN", welch_half_width([0.1], [1], [0.1], [3])[0], math.nan,
                      0))
    good.append(check("both exact: 0", welch_half_width([0.0], [3], [0.0], [3])[0], 0.0, 0))
    v = welch_half_width(np.array([0.5, 0.3]), np.array([2, 11]), np.array([0.5, 0.0]),
                         np.array([2, 4]))
    good.append(check("vectorised, cell 1", v[1], T10 * math.sqrt(0.3 / 11), 1e-9))
    return good


def group_bounded():
    # Tolerances: scipy's t quantile is accurate to ~1e-10 relative (t(0.975, 1) = 12.7 and
    # t(0.975, 2) = 4.30 against their closed forms above).
    good = []

    def student(v):
        m, sd, n = float(np.mean(v)), float(np.std(v, ddof=1)), len(v)
        return m, stats.t.ppf(0.975, n - 1) * sd / math.sqrt(n)

    # Inside the bounds: Student's interval of the mean itself (N = 5, c_L-like).
    v = [0.40, 0.42, 0.44, 0.41, 0.43]
    m, h = student(v)
    b = bounded_interval(v, 0.0, 1.0)
    good.append(check("N = 5 inside [0, 1]: lower = Student's", b["lower"], m - h, 1e-12))
    good.append(check("N = 5 inside [0, 1]: upper = Student's", b["upper"], m + h, 1e-12))
    good.append(check("the mean is the arithmetic mean", b["mean"], 0.42, 1e-15))
    # Cut at a bound: Δψ in [0, 180], N = 3: 60 ± 74.5 -> [0, 134.5].
    m, h = student([30.0, 90.0, 60.0])
    b = bounded_interval([30.0, 90.0, 60.0], 0.0, 180.0)
    good.append(check("[0, 180], N = 3: lower cut at 0", b["lower"], 0.0, 0))
    good.append(check("[0, 180], N = 3: upper = Student's", b["upper"], m + h, 1e-9))
    # [lo, inf): the enrichment, cut at 0 only.
    m, h = student([1.0, 1.3])
    b = bounded_interval([1.0, 1.3], 0.0, np.inf)
    good.append(truth("[0, inf), N = 2: 1.15 - 1.91 cut at 0, the upper end Student's",
                      b["lower"] == 0.0 and abs(b["upper"] - (m + h)) < 1e-9,
                      f"{b['lower']} .. {b['upper']}"))
    # Where Student's interval leaves the bounds, this one does not (the c_L ± 5.6 of issue 18).
    v = [0.05, 0.95]
    m, ci, _ = mean_ci(v)
    b = bounded_interval(v, 0.0, 1.0)
    good.append(truth("Student's interval of {0.05, 0.95} leaves [0, 1]", m - ci < 0 < 1 < m + ci,
                      f"{m - ci:.3g} .. {m + ci:.3g}"))
    good.append(truth("the cut interval is [0, 1]: two replicas that far apart say nothing",
                      b["lower"] == 0.0 and b["upper"] == 1.0,
                      f"{b['lower']:.3g} .. {b['upper']:.3g}"))
    # Skewed replicas: the interval holds the printed mean (a logit-scale interval mapped back
    # printed 0.0388 [0.00054, 0.017] for these, the mean outside its own interval).
    for v, lo, hi in (([0.001, 0.002, 0.0015, 0.3, 0.002, 0.001, 0.0012, 0.002], 0.0, 1.0),
                      ([0.05] * 20 + [3.0] * 20, 0.0, np.inf)):
        b = bounded_interval(v, lo, hi)
        good.append(truth(f"skewed replicas (mean {b['mean']:.3g}): lower <= mean <= upper",
                          b["lower"] <= b["mean"] <= b["upper"],
                          f"{b['lower']:.3g} .. {b['upper']:.3g}"))
    # Cutting loses no coverage: over 4,000 samples of 5 from Beta(0.5, 4.5) (mean 0.1, skewed
    # against the bound 0), the cut interval covers the mean exactly as often as Student's.
    rng = np.random.default_rng(7)
    draws = rng.beta(0.5, 4.5, size=(4000, 5))
    b = bounded_interval(draws, 0.0, 1.0, axis=1)
    m, sd = draws.mean(axis=1), draws.std(axis=1, ddof=1)
    h = stats.t.ppf(0.975, 4) * sd / math.sqrt(5)
    cut = int(np.sum((b["lower"] <= 0.1) & (0.1 <= b["upper"])))
    whole = int(np.sum((m - h <= 0.1) & (0.1 <= m + h)))
    good.append(truth(f"coverage of the mean 0.1: cut {cut} of 4000 = Student's {whole}, "
                      f"{int(np.sum(m - h < 0))} intervals cut", cut == whole
                      and np.all(b["lower"] >= 0) and np.sum(m - h < 0) > 0))
    # Values on a bound need no shift any more: Student's interval cut.
    b = bounded_interval([0.0, 0.02], 0.0, 1.0)
    good.append(truth("a value on the bound: [0, 0.01 + 12.7 x 0.01]",
                      b["lower"] == 0 and abs(b["upper"] - (0.01 + T1 * 0.01)) < 1e-9,
                      f"{b['lower']:.3g} .. {b['upper']:.3g}"))
    b = bounded_interval([2.0, 0.0], 0.0, 45.0)  # a Fig. 8 count of 45 large
    good.append(truth("counts 2 and 0 of 45: within [0, 45] (Student: 1 ± 12.7)",
                      b["lower"] == 0 and abs(b["upper"] - (1 + T1)) < 1e-9,
                      f"{b['lower']:.3g} .. {b['upper']:.3g}"))
    # No spread: the interval is the value; one replica: none.
    b = bounded_interval([0.4, 0.4, 0.4], 0.0, 1.0)
    good.append(check("equal replicas: lower = value", b["lower"], 0.4, 1e-12))
    good.append(check("equal replicas: upper = value", b["upper"], 0.4, 1e-12))
    b = bounded_interval([0.0, 0.0], 0.0, 45.0)
    good.append(truth("identical replicas on a bound (two counts of 0): [0, 0]",
                      b["lower"] == 0 and b["upper"] == 0 and b["mean"] == 0,
                      f"{b['lower']} .. {b['upper']}"))
    b = bounded_interval([0.4, np.nan], 0.0, 1.0)
    good.append(check("one finite replica: no interval", b["lower"], math.nan, 0))
    # Per cell (replicas along axis 0), NaN cells left out: the same as cell by cell.
    maps = np.array([[0.1, 0.5, np.nan, 0.0], [0.3, 0.6, 0.2, 0.0], [0.2, 0.9, 0.4, 0.1]])
    b = bounded_interval(maps, 0.0, 1.0)
    same = True
    for c in range(maps.shape[1]):
        col = maps[:, c]
        s = bounded_interval(col[np.isfinite(col)], 0.0, 1.0)
        same &= all(abs(s[k] - b[k][c]) <= 1e-12 for k in ("mean", "lower", "upper"))
        same &= int(b["n"][c]) == int(np.isfinite(col).sum())
    good.append(truth("per-cell form = cell by cell", same))
    good.append(truth("every cell's interval within [0, 1]",
                      np.all((b["lower"] >= 0) & (b["upper"] <= 1))))
    # A difference of two shares is cut at ±1 (Welch's at N = 2 reached ±6).
    c = compare_values([0.05, 0.95], [0.9, 0.95], 0.0, 1.0)
    good.append(truth("a difference of shares in [-1, 1]: " + f"{c['lower']:.3g} .. {c['upper']:.3g}",
                      c["kind"] == "difference" and c["lower"] == -1.0 and c["upper"] == 1.0))
    # Printing: rounded outwards, never past a bound.
    lo_s, hi_s = interval_bounds_text(dict(lower=0.0123, upper=0.99996, lo=0.0, hi=1.0))
    good.append(truth("printed upper of 0.99996 in [0, 1] is at most 1", float(hi_s) <= 1.0,
                      hi_s))
    lo_s, hi_s = interval_bounds_text(dict(lower=3.14, upper=145.8, lo=0.0, hi=146.0))
    good.append(truth("printed upper of 145.8 in [0, 146] is at most 146 and covers it",
                      145.8 <= float(hi_s) <= 146.0, hi_s))
    good.append(truth("printed lower rounded down", float(lo_s) <= 3.14, lo_s))
    # Rounded at the width's second figure, not the values': a narrow interval of large numbers
    # keeps its width (Δψ 122.5-124.5 printed [120, 130] before).
    lo_s, hi_s = interval_bounds_text(dict(lower=122.53, upper=124.47, lo=0.0, hi=180.0))
    good.append(truth("[122.53, 124.47] prints as [122.5, 124.5]", (lo_s, hi_s) == ("122.5", "124.5"),
                      f"{lo_s}, {hi_s}"))
    return good


def group_fdr():
    good = []
    # Hand-computed: sorted 0.005 0.01 0.03 0.04 0.2 0.5, thresholds i 0.05/6 = .0083 .0167 .025
    # .0333 .0417 .05: the largest i with p_(i) <= i q/m is 2.
    p = np.array([0.01, 0.04, 0.03, 0.005, 0.20, 0.50])
    rej, adj = bh_reject(p, 0.05)
    good.append(truth("example 1: rejects 0.005 and 0.01 only",
                      list(rej) == [True, False, False, True, False, False], str(rej)))
    want = [0.03, 0.06, 0.06, 0.03, 0.24, 0.5]  # m p / rank, then min over larger ranks
    good.append(truth("example 1: adjusted p", np.allclose(adj, want, rtol=0, atol=1e-15),
                      str(adj)))
    # Step-up: p_(3) = 0.039 > 3 q/4 = 0.0375, yet rejected because p_(4) = 0.045 <= 0.05.
    p = np.array([0.045, 0.012, 0.039, 0.02])
    rej, adj = bh_reject(p, 0.05)
    good.append(truth("example 2 (step-up): all four rejected", rej.all(), str(rej)))
    good.append(truth("example 2: adjusted p = 0.045 0.04 0.045 0.04",
                      np.allclose(adj, [0.045, 0.04, 0.045, 0.04], rtol=0, atol=1e-15), str(adj)))
    # NaN (untested cells) are not counted in m: the same answer with NaN mixed in.
    p2 = np.array([np.nan, 0.045, 0.012, np.nan, 0.039, 0.02])
    rej2, adj2 = bh_reject(p2, 0.05)
    good.append(truth("NaN neither rejected nor counted",
                      list(rej2) == [False, True, True, False, True, True]
                      and np.isnan(adj2[[0, 3]]).all()
                      and np.allclose(adj2[[1, 2, 4, 5]], adj), str(adj2)))
    rng = np.random.default_rng(18)
    if hasattr(stats, "false_discovery_control"):
        q = rng.uniform(size=500) ** 3
        good.append(truth("= scipy.stats.false_discovery_control (500 p-values)",
                          np.allclose(bh_reject(q)[1], stats.false_discovery_control(q),
                                      rtol=1e-12, atol=0)))
    else:
        print(f"     (scipy {__import__('scipy').__version__} has no false_discovery_control: "
              "checked against the hand-computed examples above)")
    # Under the global null (144 independent uniform p, as a 12 x 12 map with no effect) BH at
    # q = 0.05 makes any rejection with probability exactly q; uncorrected 5% tests flag 7.2
    # cells on average and almost always some.
    trials = 4000
    any_bh = sum(bh_reject(rng.uniform(size=144), 0.05)[0].any() for _ in range(trials)) / trials
    se = math.sqrt(0.05 * 0.95 / trials)
    good.append(truth("null map: P(any BH rejection) = 0.05 within 4 standard errors",
                      abs(any_bh - 0.05) <= 4 * se, f"{any_bh:.4f} (se {se:.4f})"))
    return good


def group_cells():
    good = []
    # Six cells; the replicas behind each are given, the function gets mean, variance, count.
    a = [np.array([0.50, 0.55, 0.52]),   # 0: a clear difference, variance on both sides
         np.array([0.0, 0.0]),           # 1: empty in both points (no particle in any replica)
         np.array([0.4]),                # 2: one replica on a side
         np.array([0.2, 0.2]),           # 3: no variance on either side, different means
         np.array([0.25, 0.25, 0.25]),   # 4: no variance on one side only: Welch is defined
         np.array([0.1, 0.2, 0.15])]     # 5: empty only in the baseline point
    b = [np.array([0.30, 0.28, 0.33]), np.array([0.0, 0.0]), np.array([0.1, 0.2, 0.3]),
         np.array([0.5, 0.5]), np.array([0.1, 0.2, 0.15]), np.array([0.0, 0.0, 0.0])]
    stat = lambda xs, f: np.array([f(x) for x in xs], float)  # noqa: E731
    var = lambda x: x.var(ddof=1) if len(x) > 1 else np.nan   # noqa: E731
    ea = np.array([False, True, False, False, False, False])
    eb = np.array([False, True, False, False, False, True])
    p, status = cell_tests(stat(a, np.mean), stat(a, var), stat(a, len), stat(b, np.mean),
                           stat(b, var), stat(b, len), ea, eb)
    good.append(truth("status: tested, empty in both, < 2 replicas, no variance, tested, tested",
                      list(status) == [0, 1, 2, 3, 0, 0], str(list(status))))
    for c in (0, 4, 5):
        with warnings.catch_warnings():  # scipy warns that one side is constant (cells 4, 5)
            warnings.simplefilter("ignore", RuntimeWarning)
            want = float(stats.ttest_ind(a[c], b[c], equal_var=False).pvalue)
        good.append(check(f"cell {c}: p = scipy ttest_ind(equal_var=False)", p[c], want, 1e-12))
    good.append(truth("excluded cells have no p-value", np.isnan(p[[1, 2, 3]]).all()))
    # The old rule flagged cell 3: half-width 0, |difference| 0.3 > 0. It is excluded now.
    h = welch_half_width(stat(a, var), stat(a, len), stat(b, var), stat(b, len))
    good.append(truth("old rule would flag the zero-variance cell 3 (half-width 0)",
                      h[3] == 0 and abs(a[3].mean() - b[3].mean()) > h[3]))
    rej, adj = bh_reject(p, 0.05)
    good.append(truth("BH over the map: excluded cells never rejected",
                      not rej[[1, 2, 3]].any(), str(rej)))
    m = int(np.isfinite(p).sum())
    alone = bh_reject(p[[0, 4, 5]], 0.05)[1]
    good.append(truth("BH counts only the tested cells: m = 3, adjusted p as for those alone",
                      m == 3 and np.allclose(adj[[0, 4, 5]], alone, rtol=0, atol=1e-15),
                      f"m = {m}, {adj[[0, 4, 5]]} vs {alone}"))
    return good


def group_tilt():
    """The Findings' tilt warning (report_findings.tilt_spread_warning) on constructed points:
    each case's scene records the resolved protocol.repose."""
    from postproc import report_findings as fi

    def point(name, betas):
        members = [dict(scene=(f"[protocol]\nrepose = {b!r}\n" if b is not None else
                               "[protocol]\nrpm = 3.0\n")) for b in betas]
        return dict(short=name, members=members)

    good = []
    a, b = point("A1 (57,57)", [26.4, 26.6]), point("A2 (57,57) beta27", [27.0, 27.0])
    good.append(check("case_repose reads the scene's protocol.repose",
                      fi.case_repose(a["members"][0]), 26.4, 0.0))
    good.append(check("case_repose is NaN without one", fi.case_repose(
        point("x", [None])["members"][0]), math.nan, 0.0))
    w = fi.tilt_spread_warning([a, b])
    good.append(truth("0.50 deg apart (> 0.3): a warning naming both points and the spread",
                      w is not None and "0.50° apart" in w and "A1 (57,57) 26.50°" in w
                      and "(26.40–26.60)" in w and "A2 (57,57) beta27 27.00°" in w, str(w)))
    near = point("A3", [26.75, 26.85])
    good.append(truth("0.20 deg apart: no warning", fi.tilt_spread_warning([near, b]) is None))
    good.append(truth("the widest pair counts: 0.20 and 0.30 apart from the middle, 0.50 in all",
                      fi.tilt_spread_warning([a, near, b]) is not None))
    old = point("B1", [None, None])
    good.append(truth("a point whose files predate the resolved tilt is left out (no warning "
                      "from one known point)", fi.tilt_spread_warning([old, b]) is None))
    good.append(truth("a string (\"measured\", unresolved) is not read as a tilt",
                      math.isnan(fi.case_repose(dict(scene='[protocol]\nrepose = "measured"\n')))))
    return good


def group_compare():
    from postproc import report_compare as rc

    good = []
    # Hand-computed Holm: sorted 0.005 0.01 0.03 0.04 (m = 4) -> 4 x 0.005 = 0.02, 3 x 0.01 =
    # 0.03, 2 x 0.03 = 0.06, 1 x 0.04 = 0.04 raised to 0.06 (adjusted values never decrease).
    adj = holm_adjust([0.01, 0.04, 0.03, np.nan, 0.005])
    good.append(truth("Holm example: 0.03 0.06 0.06 NaN 0.02",
                      np.allclose(adj, [0.03, 0.06, 0.06, np.nan, 0.02], rtol=0, atol=1e-15,
                                  equal_nan=True), str(adj)))
    good.append(truth("Holm caps at 1", holm_adjust([0.6, 0.7])[1] == 1.0))
    rng = np.random.default_rng(6)
    trials = 4000
    any_holm = sum((holm_adjust(rng.uniform(size=10)) < 0.05).any()
                   for _ in range(trials)) / trials
    any_raw = sum((rng.uniform(size=10) < 0.05).any() for _ in range(trials)) / trials
    se = math.sqrt(0.05 * 0.95 / trials)
    good.append(truth("10 null tests: P(any Holm rejection) <= 0.05 + 3 se, uncorrected ~0.40",
                      any_holm <= 0.05 + 3 * se and abs(any_raw - (1 - 0.95 ** 10)) < 0.03,
                      f"{any_holm:.4f}, uncorrected {any_raw:.3f}"))
    a = np.array([1.22, 0.89, 1.45, 0.91, 1.51, 1.35])
    b = np.array([1.35, 1.44, 0.76, 1.39, 0.95, 1.78, 1.56])
    r = welch_log_ratio(a, b)
    t = stats.ttest_ind(np.log(a), np.log(b), equal_var=False)
    good.append(check("log ratio = exp(mean log a - mean log b)", r["ratio"],
                      math.exp(np.log(a).mean() - np.log(b).mean()), 1e-12))
    good.append(check("log ratio p = scipy's Welch on the logs", r["p"], float(t.pvalue), 1e-12))
    sa, sb = np.log(a).var(ddof=1) / 6, np.log(b).var(ddof=1) / 7
    nu = (sa + sb) ** 2 / (sa ** 2 / 5 + sb ** 2 / 6)
    half = stats.t.ppf(0.975, nu) * math.sqrt(sa + sb)
    good.append(check("log ratio interval: exp(log ratio + Welch half-width)", r["upper"],
                      r["ratio"] * math.exp(half), 1e-12))
    good.append(truth("a replica at 0: no log ratio", welch_log_ratio([0.0, 1.0], b) is None))

    def pt(label, **metrics):
        n = len(next(iter(metrics.values())))
        return dict(label=label, short=label,
                    scalars=[{k: v[j] for k, v in metrics.items()} for j in range(n)])

    bounds = {"e": (0.0, np.inf), "beta": (0.0, 90.0)}
    base = pt("A1", e=list(b), beta=[30.0, 30.2, 29.8, 30.1, 29.9, 30.0, 30.0])
    same = pt("A2", e=list(a), beta=[30.0, 30.1, 29.9, 30.2, 29.8, 30.0])
    zero = pt("A3", e=[0.0, 1.2, 1.1], beta=[np.nan] * 3)
    rows = rc.scalar_tests([base, same, zero], 0, ["e", "beta"], bounds)
    kinds = [(r["point"]["label"], r["metric"], r["kind"]) for r in rows]
    good.append(truth("enrichment as a ratio, beta and a replica at 0 as differences, a metric "
                      "missing at a point not tested",
                      kinds == [("A2", "e", "ratio"), ("A2", "beta", "difference"),
                                ("A3", "e", "difference")], str(kinds)))
    good.append(check("the ratio row is welch_log_ratio", rows[0]["est"], r["ratio"], 1e-12))
    w = stats.ttest_ind([0.0, 1.2, 1.1], b, equal_var=False)
    good.append(check("the difference row's p is scipy's Welch", rows[2]["p"], float(w.pvalue),
                      1e-12))
    good.append(truth("Holm over the table's 3 tests",
                      np.allclose([r["p_holm"] for r in rows],
                                  holm_adjust([r["p"] for r in rows]), rtol=0, atol=0)
                      and rows[0]["p_holm"] >= rows[0]["p"]))
    return good


def group_enrichment():
    """report_findings.enrichment_sentences: P's enrichment on its own islands against Q's on the
    same mask, compared as section 6c compares every enrichment."""
    from postproc import report_findings as fi

    camp = object()

    def point(pid, label, own_values, on_mask_of=None):
        vs = {(on_mask_of or pid): dict(values=np.asarray(own_values, float))}
        return dict(pid=pid, label=label, short=label.split()[0], camp=camp,
                    islands=on_mask_of is None, an=dict(enrichment_vs=vs, attrs={}))

    good = []
    # Log-scale Welch p = 0.033, arithmetic Welch p = 0.072 on these replicas.
    a, b = [1.36, 1.88, 1.08], [0.65, 0.59, 0.61]
    P, Q = point("p1", "A1 (57,57)", a), point("q1", "A2 (68,68)", b, on_mask_of="p1")
    sentences, rows = fi.enrichment_sentences([P, Q])
    t_log = stats.ttest_ind(np.log(a), np.log(b), equal_var=False)
    t_lin = stats.ttest_ind(a, b, equal_var=False)
    good.append(truth("one sentence and one row for the pair", len(sentences) == 1
                      and len(rows) == 1, f"{len(sentences)} sentences, {len(rows)} rows"))
    row = rows[0]
    good.append(truth("compared as a ratio", row[8] == "ratio", str(row[8])))
    good.append(check("the ratio = the ratio of the geometric means", row[9],
                      math.exp(np.log(a).mean() - np.log(b).mean()), 1e-12))
    good.append(check("its p = scipy's Welch on the logarithms", row[12], float(t_log.pvalue),
                      1e-12))
    good.append(truth("significant by the log test (p = 0.033) where the arithmetic one says "
                      f"p = {t_lin.pvalue:.3f}",
                      row[14] == "significant" and t_lin.pvalue > 0.05 and row[10] > 1,
                      f"{row[14]}, lower {row[10]}"))
    good.append(truth("the sentence names the ratio and the verdict",
                      "ratio of the geometric means × " in sentences[0]
                      and "significantly more" in sentences[0], sentences[0]))
    # A replica at 0: no logarithm, the difference of the means.
    Z = point("q2", "A3 (45,45)", [0.0, 0.7, 0.6], on_mask_of="p1")
    _, rows = fi.enrichment_sentences([P, Z])
    t0 = stats.ttest_ind(a, [0.0, 0.7, 0.6], equal_var=False)
    good.append(truth("a replica at 0: compared as a difference, scipy's Welch p",
                      rows[0][8] == "difference" and abs(rows[0][12] - t0.pvalue) < 1e-12,
                      f"{rows[0][8]}, p {rows[0][12]} vs {t0.pvalue}"))
    # Two replicas of Q: whatever the numbers, the verdict says N = 2 when not significant.
    S = point("q3", "A4 (30,30)", [1.3, 1.1], on_mask_of="p1")
    sentences, rows = fi.enrichment_sentences([P, S])
    good.append(truth("N = 2 and an interval including 1: inconclusive, with both reasons",
                      rows[0][14] == "inconclusive" and "N = 2" in sentences[0]
                      and "the interval of the ratio includes 1" in sentences[0], sentences[0]))
    # Three points with the same replicas as Q: three tests at p = 0.033 each, Holm-adjusted
    # 3 × 0.033 = 0.099: none significant, each sentence says why.
    Qs = [point(f"q{k}", f"A{k} (68,68)", b, on_mask_of="p1") for k in (5, 6, 7)]
    sentences, rows = fi.enrichment_sentences([P] + Qs)
    good.append(check("Holm over the page's 3 comparisons", rows[0][13],
                      min(1.0, 3 * float(t_log.pvalue)), 1e-12))
    good.append(truth("p = 0.033 three times: inconclusive once adjusted (Holm)",
                      all(r[14] == "inconclusive" for r in rows)
                      and all("once adjusted for the 3 comparisons (Holm)" in x
                              for x in sentences), sentences[0]))
    return good


def group_species():
    """report_species: the names every point's files agree on, and the labels they give."""
    from postproc.report_species import named, species_names

    def point(names=None, in_analysis=True):
        a = dict(species_0=names[0], species_1=names[1]) if names else {}
        return dict(an=dict(attrs=a) if in_analysis else None,
                    members=[] if in_analysis else [dict(a)])

    good = []
    dens = ("light", "heavy")
    good.append(truth("a density bed: its names, from analysis.h5 or from the fields",
                      species_names([point(dens), point(dens, in_analysis=False)]) == dens))
    good.append(truth("files without names: small / large",
                      species_names([point(), point(None, False)]) == ("small", "large")))
    good.append(truth("a size and a density bed in one report: species 0 / species 1",
                      species_names([point(dens), point(("small", "large"))])
                      == ("species 0", "species 1")))
    good.append(truth("labels: species 1 (\"large\") and species 0 (\"small\") renamed",
                      named("mean Δψ large [deg]", dens) == "mean Δψ heavy [deg]"
                      and named("Δψ small over 3 iterations [deg]", dens)
                      == "Δψ light over 3 iterations [deg]"
                      and named("large share of the shell", ("species 0", "species 1"))
                      == "species 1 share of the shell"))
    good.append(truth("a size bed's labels and words inside others are left alone",
                      named("mean Δψ large [deg]", ("small", "large")) == "mean Δψ large [deg]"
                      and named("enlarged smallest", dens) == "enlarged smallest"))
    return good


GROUPS = dict(stats=group_stats, bounded=group_bounded, fdr=group_fdr, cells=group_cells,
              tilt=group_tilt, compare=group_compare, enrichment=group_enrichment,
              species=group_species)
which = sys.argv[1:] or list(GROUPS)
results = []
for g in which:
    print(f"--- {g}")
    results += GROUPS[g]()
print(f"{sum(results)} of {len(results)} checks passed")
sys.exit(0 if all(results) else 1)
