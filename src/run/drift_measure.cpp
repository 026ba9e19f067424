#include "run/drift_measure.hpp"

#include <cmath>
#include <string>

#include "base/error.hpp"

namespace tumble::analysis {

DriftGridMeter::DriftGridMeter(int n, double R, double repose, double omega, double d_large)
    : n_(n), R_(R), repose_(repose), omega_(omega), d_large_(d_large) {}

Vec3 DriftGridMeter::to_layer_frame(const Vec3& lab, const Vec3& omega_vec) const {
  const double w = norm(omega_vec);
  const Vec3 axis = (1.0 / w) * omega_vec;
  // Undo the repose tilt: the tumbler turned by β about Ω̂ before the layer formed.
  const Vec3 p = Mat3::rotation(axis, -repose_) * lab;
  const bool x_phase = std::fabs(omega_vec.x) > std::fabs(omega_vec.z);
  return x_phase ? Vec3{p.z, p.y, -p.x} : p;  // cm::to_frame
}

std::int64_t DriftGridMeter::sample(const Particles& p, const Vec3& omega_vec,
                                    cm::DriftStatistics& into) const {
  const std::size_t cells = static_cast<std::size_t>(n_) * n_;
  if (into.count.size() != cells || into.sum.size() != cells || into.sum2.size() != cells)
    throw CorruptInputError("drift statistics of " + std::to_string(into.count.size()) +
                            " cells where the drift grid has " + std::to_string(cells));
  if (norm(omega_vec) == 0.0) return 0;
  std::int64_t taken = 0;
  const double vscale = 1.0 / (omega_ * R_);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.species[i] != 1) continue;
    const Vec3 q = to_layer_frame(p.x[i], omega_vec);
    if (q.y < -d_large_ || q.y > d_large_) continue;  // not at the free surface
    const Vec3 u = to_layer_frame(p.v[i], omega_vec);
    if (u.x <= 0.0) continue;  // not flowing downstream
    const int ci = static_cast<int>(std::floor((q.x / R_ + 1.0) * 0.5 * n_));
    const int cj = static_cast<int>(std::floor((q.z / R_ + 1.0) * 0.5 * n_));
    if (ci < 0 || ci >= n_ || cj < 0 || cj >= n_) continue;
    const std::size_t c = static_cast<std::size_t>(ci) * n_ + cj;
    const double va = u.z * vscale;
    into.count[c] += 1;
    into.sum[c] += va;
    into.sum2[c] += va * va;
    ++taken;
  }
  return taken;
}

cm::DriftGrid DriftGridMeter::grid(const cm::DriftStatistics& statistics,
                                   const std::string& source) const {
  return cm::drift_grid_from_statistics(n_, statistics, source);
}

}  // namespace tumble::analysis
