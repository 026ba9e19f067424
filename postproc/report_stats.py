"""Replica statistics for the report: mean and 95% confidence half-width with Student's t, the
same definition as ensemble.h5 (docs/campaign.md): ci95 = t(0.975, n - 1) s / sqrt(n). numpy and
the standard library only (no scipy on a minimal machine)."""
import math

import numpy as np


def _betacf(a, b, x):
    # Continued fraction of the incomplete beta function (Numerical Recipes 6.4).
    tiny = 1e-300
    c, d = 1.0, 1.0 - (a + b) * x / (a + 1)
    d = 1.0 / (d if abs(d) > tiny else tiny)
    h = d
    for m in range(1, 300):
        m2 = 2 * m
        for aa in (m * (b - m) * x / ((a + m2 - 1) * (a + m2)),
                   -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1))):
            d = 1.0 + aa * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + aa / c
            c = c if abs(c) > tiny else tiny
            h *= d * c
        if abs(d * c - 1) < 1e-15:
            break
    return h


def _ibeta(a, b, x):
    if x <= 0:
        return 0.0
    if x >= 1:
        return 1.0
    lbt = math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log1p(-x)
    if x < (a + 1) / (a + b + 2):
        return math.exp(lbt) * _betacf(a, b, x) / a
    return 1.0 - math.exp(lbt) * _betacf(b, a, 1 - x) / b


def t_cdf(t, df):
    p = 0.5 * _ibeta(df / 2, 0.5, df / (df + t * t))
    return 1 - p if t > 0 else p


def t_quantile(p, df):
    lo, hi = -1e3, 1e3
    while hi - lo > 1e-13 * max(1.0, abs(lo)):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if t_cdf(mid, df) < p else (lo, mid)
    return 0.5 * (lo + hi)


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
    """'m ± ci (N = n)' with NaN shown as '–'."""
    if not np.isfinite(m):
        return "–"
    s = f"{m:.{digits}g}"
    if np.isfinite(ci):
        s += f" ± {ci:.2g}"
    if n is not None:
        s += f" (N = {n})"
    return s


_TQ = {}


def _t975(df):
    key = float(df)  # Welch's degrees of freedom are real; cells with equal counts share them
    if key not in _TQ:
        _TQ[key] = t_quantile(0.975, key)
    return _TQ[key]


def welch_half_width(var_a, n_a, var_b, n_b):
    """95% half-width of mean_a − mean_b by Welch's t (unequal variances), per element:
    t(0.975, ν) sqrt(s_a²/n_a + s_b²/n_b), ν by Welch–Satterthwaite. NaN where either side has
    fewer than 2 replicas. When both variances are 0 the half-width is 0: any difference
    is then significant, as it is exactly reproducible."""
    va, vb = np.asarray(var_a, float), np.asarray(var_b, float)
    na, nb = np.asarray(n_a, float), np.asarray(n_b, float)
    out = np.full(np.broadcast(va, vb, na, nb).shape, np.nan)
    ok = (na >= 2) & (nb >= 2) & np.isfinite(va) & np.isfinite(vb)
    with np.errstate(divide="ignore", invalid="ignore"):
        sa, sb = va / na, vb / nb
        se2 = sa + sb
        nu = se2 ** 2 / (sa ** 2 / (na - 1) + sb ** 2 / (nb - 1))
    for idx in zip(*np.nonzero(np.broadcast_to(ok, out.shape))):
        out[idx] = 0.0 if se2[idx] == 0 else _t975(nu[idx]) * np.sqrt(se2[idx])
    return out
