#include "cm/exact_map.hpp"

#include <cmath>

namespace tumble::cm {

LayerCoords layer_coords(const Vec3& p, double eps) {
  const double eta = std::max(height_above_interface(p, eps), 0.0);
  const double h = eta / eps;
  return {std::sqrt(p.x() * p.x() + h * h), std::atan2(h, -p.x())};
}

Vec3 layer_point(double a, double s, double z, double eps) {
  const double x = -a * std::cos(s);
  return {x, eps * a * std::sin(s) - layer_depth(x, z, eps), z};
}

BulkEntry bulk_entry(const Vec3& p, double eps) {
  const double e2 = eps * eps;
  const double rho2 = 1.0 - p.z() * p.z();
  const double s2 = p.x() * p.x() + p.y() * p.y();
  const double a = std::sqrt(std::max((s2 - e2 * rho2) / (1.0 - e2), 0.0));
  // Clockwise motion lowers the polar angle from atan2(y, x) in (-pi, 0) to the entry angle.
  const double phi_now = std::atan2(p.y(), p.x());
  const double phi_entry = std::atan2(-layer_depth(a, p.z(), eps), -a);
  return {a, std::max(phi_now - phi_entry, 0.0)};
}

Vec3 rotate_bulk(const Vec3& p, double t) {
  const double c = std::cos(t), s = std::sin(t);
  return {p.x() * c + p.y() * s, -p.x() * s + p.y() * c, p.z()};
}

Vec3 flow_z_exact(const Vec3& p0, double t, double eps, Crossings* crossings) {
  Vec3 p = p0;
  if (1.0 - p.z() * p.z() <= 0.0) return p;  // on the axis: at rest
  bool layer = in_layer(p, eps);
  double left = t;
  // Each bulk+layer cycle takes at least pi eps, so this bound is never reached in practice;
  // it only protects against a degenerate streamline (a = 0) looping forever.
  for (int guard = 0; left > 0 && guard < 100000; ++guard) {
    if (!layer) {
      const BulkEntry e = bulk_entry(p, eps);
      if (left < e.time) return rotate_bulk(p, left);
      left -= e.time;
      if (e.a == 0) return layer_point(0, 0, p.z(), eps);  // the streamline's stagnation point
      p = layer_point(e.a, 0.0, p.z(), eps);
      layer = true;
      if (crossings) ++crossings->entries;
    } else {
      const LayerCoords c = layer_coords(p, eps);
      if (c.a == 0) return p;  // stagnation point of the degenerate streamline
      const double transit_left = eps * (kPi - c.s);
      if (left < transit_left) return layer_point(c.a, c.s + left / eps, p.z(), eps);
      left -= transit_left;
      p = {c.a, -layer_depth(c.a, p.z(), eps), p.z()};
      layer = false;
      if (crossings) ++crossings->exits;
    }
  }
  return p;
}

}  // namespace tumble::cm
