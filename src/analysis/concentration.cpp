#include "analysis/concentration.hpp"

#include <cmath>
#include <limits>

namespace tumble::analysis {

ShellBins bin_shell(const Particles& p, const Mat3& to_frame, const LambertGrid& grid, double R,
                    double inner) {
  ShellBins b;
  b.large.assign(grid.cells(), 0.0);
  b.small.assign(grid.cells(), 0.0);
  const double lo2 = inner * inner * R * R, hi2 = R * R;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r2 = norm2(p.x[i]);
    if (r2 <= lo2 || r2 >= hi2) continue;
    const Vec3 u = to_frame * p.x[i] * (1.0 / std::sqrt(r2));
    const int cell = grid.cell_of_direction(u.x, u.y, u.z);
    if (cell < 0) continue;
    const double a = p.radius[i];
    const double vol = 4.0 / 3.0 * kPi * a * a * a;
    (p.species[i] == 1 ? b.large : b.small)[cell] += vol;
  }
  return b;
}

double intensity_of_segregation(const ShellBins& b) {
  double vl = 0, vt = 0;
  for (std::size_t c = 0; c < b.large.size(); ++c) {
    vl += b.large[c];
    vt += b.large[c] + b.small[c];
  }
  if (vt <= 0) return std::numeric_limits<double>::quiet_NaN();
  const double mean = vl / vt;
  if (mean <= 0 || mean >= 1) return std::numeric_limits<double>::quiet_NaN();
  double s = 0;
  for (std::size_t c = 0; c < b.large.size(); ++c) {
    const double v = b.large[c] + b.small[c];
    if (v <= 0) continue;
    const double d = b.large[c] / v - mean;
    s += v * d * d;
  }
  return std::sqrt(s / vt) / std::sqrt(mean * (1 - mean));
}

double shell_cell_volume(const LambertGrid& grid, double R, double inner) {
  const double ri = inner * R;
  return 2.0 / 3.0 * kPi * (R * R * R - ri * ri * ri) / grid.cells();
}

void ConcentrationMap::add(const ShellBins& b) {
  for (std::size_t c = 0; c < volume_large.size(); ++c) {
    volume_large[c] += b.large[c];
    volume_small[c] += b.small[c];
  }
  ++samples;
}

std::vector<double> ConcentrationMap::c_large() const {
  std::vector<double> out(volume_large.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t c = 0; c < out.size(); ++c) {
    const double v = volume_large[c] + volume_small[c];
    if (v > 0) out[c] = volume_large[c] / v;
  }
  return out;
}

std::vector<double> ConcentrationMap::c_small() const {
  std::vector<double> out(volume_large.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t c = 0; c < out.size(); ++c) {
    const double v = volume_large[c] + volume_small[c];
    if (v > 0) out[c] = volume_small[c] / v;
  }
  return out;
}

std::vector<double> ConcentrationMap::solid_fraction(double cell_volume) const {
  std::vector<double> out(volume_large.size(), 0.0);
  if (samples == 0) return out;
  for (std::size_t c = 0; c < out.size(); ++c)
    out[c] = (volume_large[c] + volume_small[c]) / (static_cast<double>(samples) * cell_volume);
  return out;
}

}  // namespace tumble::analysis
