"""The report's statistics (postproc/report_stats.py) against closed forms: Student t quantiles
and Welch's half-width of a difference of two ensemble means."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "postproc"))
from report_stats import t_quantile, welch_half_width  # noqa: E402


def check(name, got, want, tol):
    ok = (math.isnan(want) and math.isnan(got)) or abs(got - want) <= tol
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {got!r} (expected {want!r} ± {tol})")
    return ok


t2 = 0.95 / math.sqrt(2 * 0.975 * 0.025)  # t(0.975, 2), closed form
t10 = 2.2281388519862747                  # t(0.975, 10)
good = [
    check("t(0.975, 1) = tan(0.475 pi)", t_quantile(0.975, 1), math.tan(0.475 * math.pi), 1e-9),
    check("t(0.975, 2)", t_quantile(0.975, 2), t2, 1e-9),
    check("t(0.975, 10)", t_quantile(0.975, 10), t10, 1e-9),
]
# Equal variances, two replicas each: Welch's nu = (2 s^2/2)^2 / (2 (s^2/2)^2 / 1) = 2.
h = welch_half_width([0.5], [2], [0.5], [2])[0]
good.append(check("equal variances, n = 2 + 2: t(0.975, 2) sqrt(0.5)", h, t2 * math.sqrt(0.5), 1e-9))
# One side exactly reproducible (variance 0): nu = n_a - 1, half-width = Student's of side a.
h = welch_half_width([0.3], [11], [0.0], [4])[0]
good.append(check("zero variance on one side: t(0.975, 10) sqrt(0.3/11)", h,
                  t10 * math.sqrt(0.3 / 11), 1e-9))
# Unequal: nu = (0.04/5 + 0.01/4)^2 / ((0.04/5)^2/4 + (0.01/4)^2/3), checked against the quantile.
sa, sb = 0.04 / 5, 0.01 / 4
nu = (sa + sb) ** 2 / (sa ** 2 / 4 + sb ** 2 / 3)
h = welch_half_width([0.04], [5], [0.01], [4])[0]
good.append(check(f"unequal (nu = {nu:.4f})", h, t_quantile(0.975, nu) * math.sqrt(sa + sb), 1e-6))
# Undefined with fewer than two replicas on either side; zero when both sides are exact.
good.append(check("one replica: NaN", welch_half_width([0.1], [1], [0.1], [3])[0], math.nan, 0))
good.append(check("both exact: 0", welch_half_width([0.0], [3], [0.0], [3])[0], 0.0, 0))
# Per cell, vectorised.
v = welch_half_width(np.array([0.5, 0.3]), np.array([2, 11]), np.array([0.5, 0.0]), np.array([2, 4]))
good.append(check("vectorised, cell 1", v[1], t10 * math.sqrt(0.3 / 11), 1e-9))
sys.exit(0 if all(good) else 1)
