"""Replica statistics for the report (docs/report.md, "Statistics"), with scipy.stats:

* mean_ci: mean and Student half-width t(0.975, n − 1) s / sqrt(n), the definition of
  ensemble.h5 (docs/campaign.md);
* bounded_interval: the mean of a quantity with physical bounds and Student's 95% interval of
  it, cut at the bounds (cut_to_bounds: the same coverage, never outside, always around the mean);
* welch_half_width / welch_test / cell_tests: the difference of two ensemble means, per value or
  per map cell, by Welch's t (unequal variances, ν by Welch–Satterthwaite);
* bh_reject: Benjamini–Hochberg control of the false discovery rate over the cells of a map;
* welch_log_ratio: the ratio of two geometric means (a positive quantity such as the island
  enrichment), Welch's t on the logarithms;
* compare_values / comparison_text: one comparison of two points' replicas, as a ratio of
  geometric means for a positive unbounded quantity, else as a difference of means (cut at
  ±(hi − lo) for a quantity in [lo, hi]), and its printed form;
* holm_adjust: Holm's step-down adjustment of a family of p-values (family-wise error).

This module imports nothing from the rest of postproc, so scripts outside the package
(jobs/accuracy/pattern_table.py) can load it on its own."""
import math
import warnings

import numpy as np
from scipy import stats

LEVEL = 0.95


def t_quantile(p, df):
    """Student t quantile (scipy.stats.t.ppf); real degrees of freedom allowed (Welch)."""
    return float(stats.t.ppf(p, df))


def mean_ci(values):
    """(mean, ci95, n) of the finite values; ci95 NaN for n < 2."""
    v = np.asarray([x for x in values if x is not None and np.isfinite(x)], dtype=float)
    n = len(v)
    if n == 0:
        return math.nan, math.nan, 0
    if n == 1:
        return float(v[0]), math.nan, 1
    return float(v.mean()), t_quantile(0.975, n - 1) * float(v.std(ddof=1)) / math.sqrt(n), n


def fmt(m, ci, n=None, digits=3):
    """'m ± ci (N = n)' with NaN shown as '–'. For quantities without physical bounds
    (differences); bounded ones use bounded_interval and fmt_interval."""
    if not np.isfinite(m):
        return "–"
    s = f"{m:.{digits}g}"
    if np.isfinite(ci):
        s += f" ± {ci:.2g}"
    if n is not None:
        s += f" (N = {n})"
    return s


# --- intervals that respect physical bounds --------------------------------------------------

def cut_to_bounds(lower, upper, lo=None, hi=None):
    """An interval cut at the bounds [lo, hi] a parameter cannot leave (lo None: no lower bound;
    hi None or inf: no upper one). Cutting never loses coverage: the parameter is inside the
    bounds, so the cut interval holds it whenever the whole one does. NaN stays NaN."""
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    with np.errstate(invalid="ignore"):
        if lo is not None:
            lower = np.where(np.isfinite(lower), np.maximum(lower, lo), lower)
        if hi is not None and np.isfinite(hi):
            upper = np.where(np.isfinite(upper), np.minimum(upper, hi), upper)
    return lower, upper


def bounded_interval(values, lo=None, hi=None, level=LEVEL, axis=0):
    """Mean and a `level` confidence interval of the replicas' mean of a quantity in [lo, hi]
    (hi None or inf: [lo, ∞); lo None: no lower bound).

    Student's interval of the mean, x̄ ± t(½(1 + level), n − 1) s/√n, cut at the bounds
    (cut_to_bounds): it covers the ensemble mean as often as Student's does, it never leaves the
    bounds, and it always holds the printed mean, the arithmetic mean of the replicas (the number
    ensemble.h5 holds). (An interval computed on a logit or log scale and mapped back, as this
    function did before, is an interval for another centre, the back-transformed mean of the
    logits: with skewed replicas it could exclude the arithmetic mean printed beside it, and a
    replica on a bound had to be moved an arbitrary eps inside it.) With few replicas the
    interval is wide (N = 2: t = 12.7) and often the whole range: that is what two replicas say.
    Identical replicas give [value, value]. Works element-wise along `axis` (replicas) for maps;
    NaN values are left out. Returns dict(mean, lower, upper, n, lo, hi) (arrays for arrays);
    lower/upper NaN where n < 2."""
    v = np.asarray(values, float)
    if v.ndim == 0:
        v = v[None]
    v = np.moveaxis(v, axis, 0)
    ok = np.isfinite(v)
    n = ok.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(n > 0, np.where(ok, v, 0).sum(axis=0) / np.maximum(n, 1), np.nan)
        sd = np.sqrt(np.where(ok, (v - mean) ** 2, 0).sum(axis=0) / np.maximum(n - 1, 1))
        tq = stats.t.ppf(0.5 * (1 + level), np.maximum(n - 1, 1))
        half = tq * sd / np.sqrt(np.maximum(n, 1))
        lower = np.where(n >= 2, mean - half, np.nan)
        upper = np.where(n >= 2, mean + half, np.nan)
    lower, upper = cut_to_bounds(lower, upper, lo, hi)
    out = dict(mean=mean, lower=lower, upper=upper, n=n)
    if np.ndim(mean) == 0:
        out = {k: (int(x) if k == "n" else float(x)) for k, x in out.items()}
    out.update(lo=lo, hi=hi)
    return out


def fmt_num(x, digits=3):
    return f"{x:.{digits}g}" if np.isfinite(x) else "–"


def interval_bounds_text(b, digits=2):
    """(lower, upper) as printed: rounded outwards at the `digits`-th significant figure of the
    interval's width (so that [122.5, 124.5] prints as such, not as [120, 130]: a rounding at
    the values' own figures widened a narrow interval of large numbers five times), then kept
    within the quantity's bounds (the rounding must neither narrow the interval nor leave them).
    An interval of width 0 prints its value."""
    lo, hi = b.get("lo"), b.get("hi")
    lower, upper = float(b["lower"]), float(b["upper"])
    width = upper - lower
    decimals = None
    if np.isfinite(width) and width > 0:
        e = math.floor(math.log10(width)) - (digits - 1)
        step = 10.0 ** e
        lower, upper = math.floor(lower / step) * step, math.ceil(upper / step) * step
        decimals = max(0, -e)
    if lo is not None:
        lower = max(lower, lo)
    if hi is not None and np.isfinite(hi):
        upper = min(upper, hi)
    if decimals is None:
        return f"{lower:.{digits + 1}g}", f"{upper:.{digits + 1}g}"
    return f"{lower:.{decimals}f}", f"{upper:.{decimals}f}"


def fmt_interval(b, digits=3, n=True):
    """'m [lower, upper] (N = n)' for a bounded_interval result; '–' without a mean."""
    if not np.isfinite(b["mean"]):
        return "–"
    s = fmt_num(b["mean"], digits)
    if np.isfinite(b["lower"]):
        lower, upper = interval_bounds_text(b)
        s += f" [{lower}, {upper}]"
    if n:
        s += f" (N = {b['n']})"
    return s


# --- differences of two ensemble means --------------------------------------------------------

def _welch_se_nu(var_a, n_a, var_b, n_b):
    va, vb = np.asarray(var_a, float), np.asarray(var_b, float)
    na, nb = np.asarray(n_a, float), np.asarray(n_b, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        sa, sb = va / na, vb / nb
        se2 = sa + sb
        nu = se2 ** 2 / (sa ** 2 / (na - 1) + sb ** 2 / (nb - 1))
    ok = (na >= 2) & (nb >= 2) & np.isfinite(va) & np.isfinite(vb)
    return se2, nu, ok


def welch_half_width(var_a, n_a, var_b, n_b, level=LEVEL):
    """Half-width of the `level` interval of mean_a − mean_b by Welch's t, per element:
    t(½(1 + level), ν) sqrt(s_a²/n_a + s_b²/n_b), ν by Welch–Satterthwaite. NaN where either
    side has fewer than 2 replicas; 0 when both variances are 0."""
    se2, nu, ok = _welch_se_nu(var_a, n_a, var_b, n_b)
    with np.errstate(invalid="ignore"):
        t = stats.t.ppf(0.5 * (1 + level), np.where(ok & (se2 > 0), nu, 1.0))
        out = np.where(se2 > 0, t * np.sqrt(se2), 0.0)
    return np.where(ok, out, np.nan)


def welch_test(a, b, level=LEVEL):
    """mean(a) − mean(b) of the finite values, Welch's half-width and two-sided p-value
    (scipy.stats.ttest_ind, equal_var=False). Half-width and p NaN below 2 values each."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    if len(a) == 0 or len(b) == 0:
        return dict(diff=math.nan, half=math.nan, p=math.nan, na=len(a), nb=len(b))
    d = float(a.mean() - b.mean())
    if len(a) < 2 or len(b) < 2:
        return dict(diff=d, half=math.nan, p=math.nan, na=len(a), nb=len(b))
    half = float(welch_half_width([a.var(ddof=1)], [len(a)], [b.var(ddof=1)], [len(b)],
                                  level)[0])
    with warnings.catch_warnings():  # one side's replicas all equal (e.g. a tilt set by hand):
        # scipy warns of "precision loss" in a variance that is 0; the test is still Welch's
        # with that side exact (ν = n_other − 1), as welch_half_width computes it.
        warnings.simplefilter("ignore", RuntimeWarning)
        p = float(stats.ttest_ind(a, b, equal_var=False).pvalue) if half > 0 else math.nan
    return dict(diff=d, half=half, p=p, na=len(a), nb=len(b))


def cell_tests(mean_a, var_a, n_a, mean_b, var_b, n_b, empty_a=None, empty_b=None):
    """Welch's two-sided p-value of mean_a − mean_b per map cell, and why a cell is not tested.

    Returns (p, status): p NaN where untested; status per cell
      0 tested;
      1 empty in both (empty_a & empty_b: no particle of the species in any replica of either
        point; their "difference" is 0 − 0 or NaN − NaN and means nothing);
      2 fewer than 2 replicas with data on either side;
      3 no variance on either side (s² = 0 in both: with few replicas a discrete quantity can
        repeat exactly; Welch's statistic is then undefined, not infinite).
    Excluded cells count neither as significant nor towards the number of tests."""
    ma, mb = np.asarray(mean_a, float), np.asarray(mean_b, float)
    se2, nu, ok = _welch_se_nu(var_a, n_a, var_b, n_b)
    status = np.zeros(ma.shape, int)
    empty = np.zeros(ma.shape, bool)
    if empty_a is not None and empty_b is not None:
        empty = np.asarray(empty_a, bool) & np.asarray(empty_b, bool)
    status[~(ok & np.isfinite(ma) & np.isfinite(mb))] = 2
    status[(status == 0) & ~(se2 > 0)] = 3
    status[empty] = 1
    p = np.full(ma.shape, np.nan)
    t = status == 0
    with np.errstate(invalid="ignore", divide="ignore"):
        p[t] = 2 * stats.t.sf(np.abs(ma[t] - mb[t]) / np.sqrt(se2[t]), nu[t])
    return p, status


def bh_reject(p, q=0.05):
    """Benjamini–Hochberg step-up procedure at false discovery rate q over the finite p-values
    (NaN: not tested, never rejected, not counted in m). Returns (reject, p_adjusted) of p's
    shape; p_adjusted = min over j ≥ rank of m p_(j) / j, capped at 1 (NaN where untested), the
    same numbers as scipy.stats.false_discovery_control (scipy ≥ 1.11)."""
    p = np.asarray(p, float)
    flat = p.ravel()
    idx = np.flatnonzero(np.isfinite(flat))
    adj = np.full(flat.shape, np.nan)
    rej = np.zeros(flat.shape, bool)
    m = len(idx)
    if m:
        order = idx[np.argsort(flat[idx], kind="stable")]
        ranked = flat[order] * m / np.arange(1, m + 1)
        ranked = np.minimum.accumulate(ranked[::-1])[::-1]
        adj[order] = np.minimum(ranked, 1.0)
        rej[order] = adj[order] <= q
    return rej.reshape(p.shape), adj.reshape(p.shape)


def welch_log_ratio(a, b, level=LEVEL):
    """Ratio of the geometric means of a and b (finite values), with the `level` interval and
    two-sided p-value of Welch's t on log a − log b: for a positive quantity whose replicas
    scatter multiplicatively (an enrichment of 0.8-1.8), the comparison "a is r times b", with an
    interval that cannot leave (0, ∞). None when a value is ≤ 0 (no logarithm: compare on the
    natural scale instead, welch_test); ratio/interval/p NaN below 2 values each."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    if (a <= 0).any() or (b <= 0).any():
        return None
    if len(a) == 0 or len(b) == 0:
        return dict(ratio=math.nan, lower=math.nan, upper=math.nan, p=math.nan, na=len(a),
                    nb=len(b))
    w = welch_test(np.log(a), np.log(b), level)
    return dict(ratio=math.exp(w["diff"]), lower=math.exp(w["diff"] - w["half"]),
                upper=math.exp(w["diff"] + w["half"]), p=w["p"], na=w["na"], nb=w["nb"])


def compare_values(a, b, lo, hi, level=LEVEL):
    """Replicas a against b of one metric with physical bounds [lo, hi]: dict(kind, est, lower,
    upper, p, na, nb). A quantity in (0, ∞) with every value positive (the island enrichment, a
    ratio of shares) is compared as the ratio of geometric means (kind "ratio", Welch's t on the
    logarithms: its replicas scatter multiplicatively and the interval stays in (0, ∞), 1 = no
    difference); anything else, or such a quantity with a replica at 0, as the difference of the
    means (kind "difference", Welch's t, 0 = no difference)."""
    if lo == 0.0 and hi is not None and not np.isfinite(hi):
        r = welch_log_ratio(a, b, level)
        if r is not None:
            return dict(kind="ratio", est=r["ratio"], lower=r["lower"], upper=r["upper"],
                        p=r["p"], na=r["na"], nb=r["nb"])
    w = welch_test(a, b, level)
    # A difference of two means in [lo, hi] lies in [−(hi − lo), hi − lo]: the interval is cut
    # there (cut_to_bounds; Welch's at N = 2 of two shares reached ±6).
    span = hi - lo if lo is not None and hi is not None and np.isfinite(hi) else None
    lower, upper = cut_to_bounds(w["diff"] - w["half"], w["diff"] + w["half"],
                                 -span if span is not None else None, span)
    return dict(kind="difference", est=w["diff"], lower=float(lower), upper=float(upper),
                p=w["p"], na=w["na"], nb=w["nb"])


def excludes_none(c):
    """Whether the interval of a compare_values result excludes "no difference" (1 for a ratio,
    0 for a difference); False where there is no interval."""
    none = 1.0 if c["kind"] == "ratio" else 0.0
    return bool(np.isfinite(c["lower"]) and np.isfinite(c["upper"])
                and (c["lower"] > none or c["upper"] < none))


def comparison_text(c):
    """A compare_values result as "× 1.23 [1.01, 1.49]" (ratio) or "+0.28 [+0.03, +0.53]"
    (difference); the interval left out where there is none (N < 2, or nothing varies)."""
    if not np.isfinite(c["est"]):
        return "–"
    s = f"× {fmt_num(c['est'])}" if c["kind"] == "ratio" else f"{c['est']:+.3g}"
    if np.isfinite(c["lower"]) and np.isfinite(c["p"]):
        s += (f" [{fmt_num(c['lower'])}, {fmt_num(c['upper'])}]" if c["kind"] == "ratio" else
              f" [{c['lower']:+.3g}, {c['upper']:+.3g}]")
    return s


def holm_adjust(p):
    """Holm's step-down adjusted p-values of a family (NaN: not tested, not counted): the k-th
    smallest of m becomes max over j ≤ k of min(1, (m − j + 1) p_(j)). Rejecting where the
    adjusted value is below α keeps the chance of any false rejection in the family below α,
    whatever the dependence between the tests (Holm 1979)."""
    p = np.asarray(p, float)
    flat = p.ravel()
    idx = np.flatnonzero(np.isfinite(flat))
    adj = np.full(flat.shape, np.nan)
    m = len(idx)
    if m:
        order = idx[np.argsort(flat[idx], kind="stable")]
        stepped = np.minimum(flat[order] * (m - np.arange(m)), 1.0)
        adj[order] = np.maximum.accumulate(stepped)
    return adj.reshape(p.shape)
