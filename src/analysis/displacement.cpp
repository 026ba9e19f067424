#include "analysis/displacement.hpp"

#include <cmath>
#include <limits>

namespace tumble::analysis {

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

ShellDirections shell_directions(const Particles& p, const std::vector<std::uint32_t>& slot_of,
                                 const Mat3& to_frame, const LambertGrid& grid, double R,
                                 double inner) {
  ShellDirections d;
  d.u.assign(p.size(), Vec3{});
  d.cell.assign(p.size(), -1);
  const double lo2 = inner * inner * R * R, hi2 = R * R;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r2 = norm2(p.x[i]);
    const std::uint32_t s = slot_of[i];
    if (r2 == 0) continue;  // no direction; cannot happen in a tumbler, but never divide by 0
    d.u[s] = to_frame * p.x[i] * (1.0 / std::sqrt(r2));
    if (r2 >= lo2 && r2 <= hi2) d.cell[s] = grid.cell_of_direction(d.u[s].x, d.u[s].y, d.u[s].z);
  }
  return d;
}

void DisplacementMap::add_interval(const ShellDirections& start, const std::vector<Vec3>& end_u,
                                   const std::vector<std::int32_t>& species) {
  for (std::size_t s = 0; s < start.cell.size(); ++s) {
    const int c = start.cell[s];
    if (c < 0) continue;
    const double a = angle_between(start.u[s], end_u[s]);
    if (species[s] == 1) {
      sum_large[c] += a;
      count_large[c] += 1;
    } else {
      sum_small[c] += a;
      count_small[c] += 1;
    }
  }
  ++intervals;
}

namespace {
std::vector<double> ratio(const std::vector<double>& sum, const std::vector<double>& count) {
  std::vector<double> out(sum.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t c = 0; c < out.size(); ++c)
    if (count[c] > 0) out[c] = sum[c] / count[c];
  return out;
}
}  // namespace

std::vector<double> DisplacementMap::mean_large() const { return ratio(sum_large, count_large); }
std::vector<double> DisplacementMap::mean_small() const { return ratio(sum_small, count_small); }

}  // namespace tumble::analysis
