#include "islands/replica_stats.hpp"

#include <cmath>
#include <limits>

#include "base/student_t.hpp"

namespace tumble::analysis {

MeanCI mean_ci95(const std::vector<double>& values) {
  MeanCI m;
  double s = 0;
  for (double v : values)
    if (std::isfinite(v)) {
      s += v;
      ++m.n;
    }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (m.n == 0) return {nan, nan, 0};
  m.mean = s / m.n;
  if (m.n < 2) {
    m.ci95 = nan;
    return m;
  }
  double ss = 0;
  for (double v : values)
    if (std::isfinite(v)) ss += (v - m.mean) * (v - m.mean);
  const double var = ss / (m.n - 1);
  m.ci95 = student_t_quantile(0.975, m.n - 1) * std::sqrt(var / m.n);
  return m;
}

}  // namespace tumble::analysis
