#pragma once
// The horizontal cylinder of Rapaport 2007: axis along z (gravity is -y), radius R, length L,
// centred at the origin. The curved wall is a rough boundary (every force term); the two flat end
// caps at z = ±L/2 are smooth (normal force only) unless the cylinder is axially periodic, in which
// case there are no caps. The surface moves with Ω × r; the cylinder never moves in space.
#include <cmath>

#include "base/vec3.hpp"

namespace tumble::geometry {

struct CylinderWall {
  double radius = 0;
  double half_length = 0;
  bool periodic = false;  // axially periodic: no end caps, z wraps with period 2 half_length

  // Curved wall: overlap (> 0 when touching), unit normal from the wall into the particle and the
  // contact point, as SphereWall::overlap.
  double overlap(const Vec3& x, double r, Vec3& n, Vec3& point) const {
    const double d2 = x.x * x.x + x.y * x.y;
    const double reach = radius - r;
    if (d2 <= reach * reach) return 0.0;
    const double d = std::sqrt(d2);
    const double inv = d > 0 ? 1.0 / d : 0.0;
    const Vec3 u{x.x * inv, x.y * inv, 0.0};
    n = -u;
    point = Vec3{radius * u.x, radius * u.y, x.z};
    return d + r - radius;
  }
  // Is the particle within `reach` of the curved wall (candidate for a wall contact)?
  bool near_curved(const Vec3& x, double r, double skin) const {
    const double reach = radius - r - skin;
    return reach <= 0 || x.x * x.x + x.y * x.y > reach * reach;
  }
  // End caps: overlap with the nearer cap (> 0 when touching); n_z is the normal's z component
  // (+1 at the z = -L/2 cap, -1 at the z = +L/2 cap).
  double cap_overlap(const Vec3& x, double r, double& n_z) const {
    if (x.z < 0) {
      n_z = 1.0;
      return r - (x.z + half_length);
    }
    n_z = -1.0;
    return r - (half_length - x.z);
  }
  bool near_cap(const Vec3& x, double r, double skin) const {
    return !periodic && std::fabs(x.z) > half_length - r - skin;
  }
  // The separation d of two points as its nearest periodic image (z wrapped into one period when
  // periodic; unchanged otherwise). The pair loops keep their own inline copy (kPeriodic).
  Vec3 nearest_image(Vec3 d) const {
    if (periodic) d.z -= 2 * half_length * std::nearbyint(d.z / (2 * half_length));
    return d;
  }
  // A particle whose centre left the cylinder has escaped (periodic: only radially).
  bool escaped(const Vec3& x) const {
    return x.x * x.x + x.y * x.y > radius * radius || (!periodic && std::fabs(x.z) > half_length);
  }
};

}  // namespace tumble::geometry
