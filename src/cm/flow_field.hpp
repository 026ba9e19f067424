#pragma once
// The continuum model (CM) of one rotation about z, in its own frame (Yu 2022 App. A; Christov
// et al. 2014): nondimensional, R = 1, time in units of 1/omega, y up, free surface y = 0, the
// bed the lower half ball. Pure kernels of plain numbers; everything else in cm/ builds on them.
//
//   bulk   (y < -delta):        u_b  = (y, -x, 0)                       (App. A)
//   layer  (-delta <= y <= 0):  u_fl = ((delta + y)/eps^2, x y/delta, 0)  (App. A)
//   delta(x, z) = eps sqrt(1 - x^2 - z^2)
//
// u_b = Omega x p with Omega = -z_hat: viewed from +z the bed turns clockwise, material rises at
// x < 0, enters the layer there and flows downstream towards +x.
//
// Both pieces are divergence free, but the normal flux is not continuous at y = -delta: the
// bulk delivers -x (1 - eps^2) per unit x while the layer takes in -x (docs/cm.md). The exact
// invariant measure is therefore dV in the bulk and (1 - eps^2) dV in the layer; maps that start
// and end in the same region preserve volume exactly, a bulk -> layer passage scales it by
// 1/(1 - eps^2). shell_radius() is the first integral that makes the shells r = const invariant.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace tumble::cm {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// Flowing-layer depth delta(x, z) = eps sqrt(1 - x^2 - z^2), zero outside the unit disc.
inline double layer_depth(double x, double z, double eps) {
  return eps * std::sqrt(std::max(1.0 - x * x - z * z, 0.0));
}

// Height above the layer/bulk interface, eta = y + delta: >= 0 in the layer.
inline double height_above_interface(const Vec3& p, double eps) {
  return p.y() + layer_depth(p.x(), p.z(), eps);
}

inline bool in_layer(const Vec3& p, double eps) { return height_above_interface(p, eps) >= 0.0; }

inline Vec3 bulk_velocity(const Vec3& p) { return {p.y(), -p.x(), 0.0}; }

inline Vec3 layer_velocity(const Vec3& p, double eps) {
  const double d = layer_depth(p.x(), p.z(), eps);
  return {(d + p.y()) / (eps * eps), d > 0 ? p.x() * p.y() / d : 0.0, 0.0};
}

inline Vec3 velocity(const Vec3& p, double eps) {
  return in_layer(p, eps) ? layer_velocity(p, eps) : bulk_velocity(p);
}

// The radius-like first integral R(p): |p| in the bulk; in the layer the cap
//   R^2 = eps^2 + (1 - eps^2)(x^2 + z^2 + eta^2/eps^2),
// which equals |p| on the interface and 1 on the free surface. It is the same expression for
// rotation about x (symmetric in x, z), so it is conserved by every phase of every protocol.
// Derivation: layer streamlines are eta = eps sqrt(a^2 - x^2) (docs/cm.md, Eq. L1), and a layer
// transit joins the bulk circle s^2 = (1 - eps^2) a^2 + eps^2 (1 - z^2) on both ends.
inline double shell_radius(const Vec3& p, double eps) {
  const double eta = height_above_interface(p, eps);
  if (eta < 0) return p.norm();
  const double e2 = eps * eps;
  return std::sqrt(e2 + (1 - e2) * (p.x() * p.x() + p.z() * p.z() + eta * eta / e2));
}

}  // namespace tumble::cm
