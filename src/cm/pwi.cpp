#include "cm/pwi.hpp"

#include <cmath>

namespace tumble::cm {

Vec3 flow_z_pwi(const Vec3& p, double t) {
  const double s = std::hypot(p.x(), p.y());
  // Clockwise angle from +x: 0 on the downstream end of the free surface, pi on the upstream end.
  const double phi = std::atan2(-p.y(), p.x());
  double next = std::fmod(std::max(phi, 0.0) + t, kPi);
  if (next < 0) next += kPi;
  return {s * std::cos(next), -s * std::sin(next), p.z()};
}

}  // namespace tumble::cm
