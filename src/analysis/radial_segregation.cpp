#include "analysis/radial_segregation.hpp"

#include <limits>

namespace tumble::analysis {

SegregationSample radial_segregation(const Particles& p, double R, double inner) {
  double vol_all = 0, vol_large = 0, shell_all = 0, shell_large = 0, count = 0;
  const double r_in2 = inner * inner * R * R;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i];
    const double vol = r * r * r;  // the 4π/3 cancels in the fractions
    const bool large = p.species[i] == 1;
    vol_all += vol;
    if (large) vol_large += vol;
    if (norm2(p.x[i]) > r_in2) {
      shell_all += vol;
      count += 1;
      if (large) shell_large += vol;
    }
  }
  SegregationSample s;
  s.bed_large_fraction = vol_all > 0 ? vol_large / vol_all : 0;
  s.shell_large_fraction = shell_all > 0 ? shell_large / shell_all : 0;
  s.shell_count = count;
  return s;
}

double shell_share(const std::vector<Vec3>& x, const std::vector<std::int32_t>& species, int which,
                   double R, double inner) {
  const double lo2 = inner * inner * R * R, hi2 = R * R;
  double in = 0, all = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (species[i] != which) continue;
    const double r2 = norm2(x[i]);
    all += 1;
    in += r2 > lo2 && r2 <= hi2;
  }
  return all > 0 ? in / all : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace tumble::analysis
