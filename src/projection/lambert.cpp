#include "projection/lambert.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tumble::analysis {
namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kQuarterPi = kPi / 4;
}  // namespace

DiscPoint lambert_from_below(double ux, double uy, double uz) {
  // |P - south pole| = sqrt(2 (1 + u_y)) is the standard Lambert radius; dividing by sqrt(2)
  // puts the rim on the unit circle: (u_x, u_z) sqrt(2(1+u_y)) / sqrt(1-u_y^2) / sqrt(2).
  const double s = std::sqrt(std::max(1.0 - uy, 0.0));
  if (s == 0) return {0, 0};  // north pole: no unique image, not on the analysed hemisphere
  return {ux / s, uz / s};
}

std::array<double, 3> lambert_inverse(DiscPoint p) {
  // From X^2 + Z^2 = (1 - u_y^2)/(1 - u_y) = 1 + u_y.
  const double t2 = p.X * p.X + p.Z * p.Z;
  const double uy = t2 - 1.0;
  const double s = std::sqrt(std::max(2.0 - t2, 0.0));  // sqrt(1 - u_y)
  return {p.X * s, uy, p.Z * s};
}

DiscPoint square_to_disc(double a, double b) {
  // Shirley & Chiu (1997): concentric squares map to concentric circles, each wedge linearly
  // in angle, which makes the Jacobian the constant pi/4.
  if (a == 0 && b == 0) return {0, 0};
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = kQuarterPi * (b / a);
  } else {
    r = b;
    phi = 2 * kQuarterPi - kQuarterPi * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

std::array<double, 2> disc_to_square(DiscPoint p) {
  const double r = std::hypot(p.X, p.Z);
  if (r == 0) return {0, 0};
  double phi = std::atan2(p.Z, p.X);
  if (phi < -kQuarterPi) phi += 2 * kPi;  // phi in [-pi/4, 7pi/4)
  if (phi < kQuarterPi) return {r, phi * r / kQuarterPi};
  if (phi < 3 * kQuarterPi) return {-(phi - 2 * kQuarterPi) * r / kQuarterPi, r};
  if (phi < 5 * kQuarterPi) return {-r, -(phi - kPi) * r / kQuarterPi};
  return {(phi - 6 * kQuarterPi) * r / kQuarterPi, -r};
}

LambertGrid::LambertGrid(int n) : n_(n) {
  if (n < 1) throw std::invalid_argument("LambertGrid: N must be >= 1");
}

int LambertGrid::cell_of(DiscPoint p) const {
  if (p.X * p.X + p.Z * p.Z > 1.0) return -1;
  const auto ab = disc_to_square(p);
  auto index = [this](double s) {
    return std::clamp(static_cast<int>(std::floor((s + 1.0) * 0.5 * n_)), 0, n_ - 1);
  };
  return flat(index(ab[0]), index(ab[1]));
}

int LambertGrid::cell_of_direction(double ux, double uy, double uz) const {
  if (uy > 0) return -1;
  return cell_of(lambert_from_below(ux, uy, uz));
}

DiscPoint LambertGrid::cell_center(int i, int j) const {
  const double h = 2.0 / n_;
  return square_to_disc(-1.0 + (i + 0.5) * h, -1.0 + (j + 0.5) * h);
}

double LambertGrid::cell_area_disc() const { return kPi / (static_cast<double>(n_) * n_); }
double LambertGrid::cell_solid_angle() const { return 2 * cell_area_disc(); }

}  // namespace tumble::analysis
