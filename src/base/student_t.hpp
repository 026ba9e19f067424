#pragma once
// Quantiles of Student's t distribution, for confidence half-widths of ensemble means: with n
// replicas the 95% half-width is t(0.975, n - 1) s / sqrt(n), which for small n is much wider than
// the normal 1.96 s / sqrt(n) (t = 12.71 for n = 2, 2.26 for n = 10).

namespace tumble {

// Regularised incomplete beta function I_x(a, b) (continued fraction, Numerical Recipes 6.4).
double incomplete_beta(double a, double b, double x);
// P(T <= t) for T ~ Student t with `df` degrees of freedom.
double student_t_cdf(double t, double df);
// The p-quantile (0 < p < 1), by bisection of the CDF to round-off.
double student_t_quantile(double p, double df);

}  // namespace tumble
