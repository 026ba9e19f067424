#include "cm/shell_chart.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "projection/lambert.hpp"

namespace tumble::cm {

ShellChart::ShellChart(double r, double eps) : r_(r), eps_(eps) {
  if (!(r > eps && r < 1 && eps >= 0))
    throw std::invalid_argument("ShellChart: need 0 <= eps < r < 1");
  const double e2 = eps * eps;
  q_ = std::sqrt((r * r - e2) / (1 - e2));
  // On the interface |p| = r and y = -delta(q): r^2 - q^2 = eps^2 (1 - r^2)/(1 - eps^2).
  y_interface_ = -eps * std::sqrt((1 - r * r) / (1 - e2));
  // Lambert radius^2 = 1 + u_y for a unit direction u.
  rim_ = std::sqrt(1 + y_interface_ / r);
  outer_ = std::sqrt(rim_ * rim_ + eps * q_ / r);
}

Vec2 ShellChart::to_chart(const Vec3& p) const {
  if (!in_layer(p, eps_)) {
    const Vec3 u = p.normalized();
    const auto d = analysis::lambert_from_below(u.x(), u.y(), u.z());
    return {d.X, d.Z};
  }
  const double rho2 = p.x() * p.x() + p.z() * p.z();
  const double u = std::sqrt(std::max(q_ * q_ - rho2, 0.0));
  const double rc = std::sqrt(rim_ * rim_ + eps_ / r_ * std::min(u, q_));
  const double az = std::atan2(p.z(), p.x());
  return {rc * std::cos(az), rc * std::sin(az)};
}

Vec3 ShellChart::from_chart(const Vec2& v) const {
  const double rc2 = v.squaredNorm();
  if (rc2 < rim_ * rim_ || eps_ == 0) {  // eps = 0 (PWI): no layer, the shell is a hemisphere
    const auto u = analysis::lambert_inverse({v.x(), v.y()});
    return r_ * Vec3(u[0], u[1], u[2]);
  }
  const double u = std::clamp((rc2 - rim_ * rim_) * r_ / eps_, 0.0, q_);
  const double rho = std::sqrt(std::max(q_ * q_ - u * u, 0.0));
  const double az = std::atan2(v.y(), v.x());
  const double x = rho * std::cos(az), z = rho * std::sin(az);
  return {x, eps_ * u - layer_depth(x, z, eps_), z};
}

std::vector<Vec3> ShellChart::equal_area_seeds(int n) const {
  // Vogel's spiral: radius^2 proportional to k gives equal area per point in the disc, and the
  // golden angle avoids radial alignments; Lambert carries equal area back to the shell.
  const double golden = kPi * (3 - std::sqrt(5.0));
  std::vector<Vec3> out;
  out.reserve(n);
  for (int k = 0; k < n; ++k) {
    const double rad = rim_ * std::sqrt((k + 0.5) / n);
    out.push_back(from_chart({rad * std::cos(k * golden), rad * std::sin(k * golden)}));
  }
  return out;
}

std::vector<Vec3> ShellChart::interface_seeds(int n) const {
  std::vector<Vec3> out;
  out.reserve(n);
  for (int k = 0; k < n; ++k) {
    const double a = 2 * kPi * (k + 0.5) / n;
    out.emplace_back(q_ * std::cos(a), y_interface_, q_ * std::sin(a));
  }
  return out;
}

std::vector<Vec3> ShellChart::random_seeds(int n, std::mt19937_64& rng) const {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> out;
  out.reserve(n);
  for (int k = 0; k < n; ++k) {
    const double rad = outer_ * std::sqrt(u(rng)), a = 2 * kPi * u(rng);
    out.push_back(from_chart({rad * std::cos(a), rad * std::sin(a)}));
  }
  return out;
}

}  // namespace tumble::cm
