// The shared Lambert projection and equal-area grid (projection/lambert.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "projection/lambert.hpp"

namespace {
using namespace tumble::analysis;
constexpr double kPi = 3.14159265358979323846;

std::array<double, 3> random_lower_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  double x = n(rng), y = -std::abs(n(rng)), z = n(rng);
  const double s = std::sqrt(x * x + y * y + z * z);
  return {x / s, y / s, z / s};
}

TEST(Lambert, PoleToOriginRimToUnitCircle) {
  const auto pole = lambert_from_below(0, -1, 0);
  EXPECT_DOUBLE_EQ(pole.X, 0);
  EXPECT_DOUBLE_EQ(pole.Z, 0);
  for (double a = 0; a < 2 * kPi; a += 0.3) {
    const auto d = lambert_from_below(std::cos(a), 0, std::sin(a));
    EXPECT_NEAR(std::hypot(d.X, d.Z), 1.0, 1e-15);
    EXPECT_NEAR(std::atan2(d.Z, d.X), std::atan2(std::sin(a), std::cos(a)), 1e-12);
  }
}

TEST(Lambert, InverseRoundTrip) {
  std::mt19937_64 rng(1);
  for (int k = 0; k < 1000; ++k) {
    const auto u = random_lower_direction(rng);
    const auto back = lambert_inverse(lambert_from_below(u[0], u[1], u[2]));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[i], u[i], 1e-14);
  }
}

TEST(Lambert, ConcentricMapRoundTrip) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 1000; ++k) {
    const double a = u(rng), b = u(rng);
    const auto d = square_to_disc(a, b);
    EXPECT_LE(std::hypot(d.X, d.Z), 1 + 1e-15);
    const auto ab = disc_to_square(d);
    EXPECT_NEAR(ab[0], a, 1e-13);
    EXPECT_NEAR(ab[1], b, 1e-13);
  }
}

// Equal area at every point, not only per cell: the composite square -> disc -> hemisphere has
// the constant Jacobian (2 pi) / 4 = pi / 2 (hemisphere area over square area).
TEST(Lambert, SquareToHemisphereIsEqualArea) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.999, 0.999);
  const double h = 1e-6;
  auto sphere = [](double a, double b) {
    const auto u3 = lambert_inverse(square_to_disc(a, b));
    return std::array<double, 3>{u3[0], u3[1], u3[2]};
  };
  for (int k = 0; k < 500; ++k) {
    const double a = u(rng), b = u(rng);
    if (std::abs(std::abs(a) - std::abs(b)) < 1e-4) continue;  // the map's wedge seams
    const auto pa = sphere(a + h, b), ma = sphere(a - h, b);
    const auto pb = sphere(a, b + h), mb = sphere(a, b - h);
    double da[3], db[3];
    for (int i = 0; i < 3; ++i) {
      da[i] = (pa[i] - ma[i]) / (2 * h);
      db[i] = (pb[i] - mb[i]) / (2 * h);
    }
    const double cx = da[1] * db[2] - da[2] * db[1], cy = da[2] * db[0] - da[0] * db[2],
                 cz = da[0] * db[1] - da[1] * db[0];
    EXPECT_NEAR(std::sqrt(cx * cx + cy * cy + cz * cz), kPi / 2, 1e-6);
  }
}

TEST(LambertGrid, CellsRoundTripAndEqualCounts) {
  const LambertGrid g(30);
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) EXPECT_EQ(g.cell_of(g.cell_center(i, j)), g.flat(i, j));
  EXPECT_NEAR(g.cell_solid_angle() * g.cells(), 2 * kPi, 1e-12);
  EXPECT_EQ(g.cell_of_direction(0, 0.5, std::sqrt(0.75)), -1);
  // Uniform directions fill the 900 cells evenly: counts are Poisson with mean 200.
  std::mt19937_64 rng(4);
  std::vector<int> count(g.cells(), 0);
  const int n = 180000;
  for (int k = 0; k < n; ++k) {
    const auto u = random_lower_direction(rng);
    ++count[g.cell_of_direction(u[0], u[1], u[2])];
  }
  double chi2 = 0;
  const double mean = static_cast<double>(n) / g.cells();
  for (int c : count) chi2 += (c - mean) * (c - mean) / mean;
  // chi^2 with 899 degrees of freedom: mean 899, sd 42.4; 6 sd is a clear failure only.
  EXPECT_LT(chi2, 899 + 6 * 42.4);
}

}  // namespace
