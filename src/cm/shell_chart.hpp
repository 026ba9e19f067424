#pragma once
// "The section": the period map acts in 3D but preserves the shells R(p) = r (shell_radius()),
// so on each shell it is a 2D area-preserving map. A shell is a closed surface: the bulk part,
// the sphere |p| = r below the interface, and the layer part, a cap above it; they meet on the
// circle x^2 + z^2 = q^2, q^2 = (r^2 - eps^2)/(1 - eps^2) (docs/cm.md).
//
// The chart covers both parts and is equal-area for the map's invariant measure, so every
// section map has Jacobian determinant 1 in it:
//   * bulk part -> the disc |v| < rim(): the Lambert projection viewed from below of the
//     direction p/|p| (projection/lambert.hpp), i.e. exactly the picture of Yu 2022 Fig. 1(a);
//   * layer cap -> the ring rim() <= |v| <= outer(): same azimuth atan2(z, x); with
//     u = eta/eps = sqrt(q^2 - x^2 - z^2) in [0, q], |v|^2 = rim^2 + (eps/r) u, so the chart
//     is continuous and keeps its orientation across the interface circle (u = 0).
//     The invariant measure on the cap is r eps du d(azimuth) (flow_field.hpp: density
//     (1 - eps^2) in the layer), which this makes uniform, matching Lambert's scale 1/(2 r^2).
// The cap's apex (x = z = 0) is the one point the chart smears onto the outer circle.
#include <random>
#include <vector>

#include "cm/flow_field.hpp"

namespace tumble::cm {

class ShellChart {
 public:
  ShellChart(double r, double eps);
  double r() const { return r_; }
  double eps() const { return eps_; }
  // Radius of the bulk disc (the interface circle) and of the whole chart.
  double rim() const { return rim_; }
  double outer() const { return outer_; }
  // Footprint radius q of the layer cap and y of the interface circle on this shell.
  double footprint() const { return q_; }
  double interface_y() const { return y_interface_; }
  // Chart areas: bulk disc, whole chart (each = invariant measure / (2 r^2)).
  double bulk_area() const { return kPi * rim_ * rim_; }
  double area() const { return kPi * outer_ * outer_; }
  bool inside(const Vec2& v) const { return v.squaredNorm() <= outer_ * outer_; }
  bool in_bulk(const Vec2& v) const { return v.squaredNorm() < rim_ * rim_; }

  // Chart coordinates of a point of this shell (bulk: Lambert of its direction).
  Vec2 to_chart(const Vec3& p) const;
  // The point of this shell at chart coordinates v (|v| <= outer()).
  Vec3 from_chart(const Vec2& v) const;

  // n seeds equal-area on the bulk part (Fibonacci spiral in the bulk disc).
  std::vector<Vec3> equal_area_seeds(int n) const;
  // n seeds evenly spaced on the interface circle (Yu 2022 Sec. IV C, Fig. 12(a)).
  std::vector<Vec3> interface_seeds(int n) const;
  // n random points on the whole shell, bulk and layer, uniform in the flow's invariant measure
  // (uniform in the chart's disc |v| <= outer()): the MCM's initial condition, "randomly
  // distributed on a hemispherical shell" (Yu 2022 Sec. III B). A distribution the CM keeps: seeds
  // on the bulk part alone spread into the layer, so that the share of the bulk's tracers inside
  // the islands rose from the islands' area share (0.150) to 0.170 without drift or diffusion.
  std::vector<Vec3> random_seeds(int n, std::mt19937_64& rng) const;

 private:
  double r_, eps_, q_, y_interface_, rim_, outer_;
};

}  // namespace tumble::cm
