#pragma once
// The spherical tumbler: an analytic shell of radius R centred at the origin, particles inside.
// Its surface moves with Ω × r (the shell itself never moves in space).
#include "base/vec3.hpp"

namespace tumble::geometry {

struct SphereWall {
  double radius = 0;

  // Contact of a particle at x with radius r. Returns the overlap (> 0 when touching) and sets n,
  // the unit normal pointing from the wall into the particle, and the contact point.
  double overlap(const Vec3& x, double r, Vec3& n, Vec3& point) const {
    const double d2 = norm2(x);
    const double reach = radius - r;
    if (d2 <= reach * reach) return 0.0;
    const double d = std::sqrt(d2);
    const Vec3 u = (d > 0 ? 1.0 / d : 0.0) * x;
    n = -u;
    point = radius * u;
    return d + r - radius;
  }
  // Outside test for diagnostics: a particle whose centre left the shell has escaped.
  bool escaped(const Vec3& x) const { return norm2(x) > radius * radius; }
};

}  // namespace tumble::geometry
