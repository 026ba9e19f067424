// Rapaport 2007's segregation measures on constructed configurations with known answers.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/cylinder_segregation.hpp"

namespace tumble {
namespace {

using analysis::CylinderFrame;

CylinderFrame frame() {
  CylinderFrame c;
  c.radius = 15;
  c.length = 120;
  c.slice = 2.5;
  c.b3 = 1.8 * 1.8 * 1.8;
  return c;
}

void add(Particles& p, const Vec3& x, int species) {
  const std::size_t i = p.size();
  p.resize(i + 1);
  p.x[i] = x;
  p.species[i] = species;
  p.radius[i] = species == 1 ? 0.9 : 0.5;
  p.id[i] = static_cast<std::int64_t>(i);
}

// Per slice k: `nb` big and `ns` small particles at the slice centre.
Particles slices(const CylinderFrame& c, const std::vector<int>& nb, const std::vector<int>& ns) {
  Particles p;
  for (std::size_t k = 0; k < nb.size(); ++k) {
    const double z = -0.5 * c.length + (k + 0.5) * c.slice;
    for (int i = 0; i < nb[k]; ++i) add(p, {0, -5, z}, 1);
    for (int i = 0; i < ns[k]; ++i) add(p, {0, -5, z}, 0);
  }
  return p;
}

TEST(CylinderMeasures, AxialSegregationIsZeroMixedAndOneSeparated) {
  const CylinderFrame c = frame();
  const int n = c.slices();
  ASSERT_EQ(n, 48);
  // Mixed in the mass proportion b^3 n_b = n_s in every slice: 10 big, 58 small (5.83 * 10).
  const Particles mixed = slices(c, std::vector<int>(n, 10), std::vector<int>(n, 58));
  EXPECT_NEAR(analysis::axial_segregation(mixed, c), std::fabs(58.32 - 58) / (58.32 + 58), 1e-9);
  // Separated: big particles in the first half of the slices only.
  std::vector<int> nb(n, 0), ns(n, 0);
  for (int k = 0; k < n; ++k) (k < n / 2 ? nb[k] : ns[k]) = (k < n / 2 ? 10 : 58);
  EXPECT_NEAR(analysis::axial_segregation(slices(c, nb, ns), c), 1.0, 1e-12);
}

TEST(CylinderMeasures, RadialIndexSignFollowsTheCore) {
  // Big particles on a ring of radius 10 around (0, -3), small ones on a ring of radius 4.
  Particles core;
  for (int k = 0; k < 360; ++k) {
    const double a = k * M_PI / 180;
    add(core, {10 * std::cos(a), -3 + 10 * std::sin(a), 0}, 1);
    add(core, {4 * std::cos(a), -3 + 4 * std::sin(a), 0}, 0);
  }
  // Variances 100 and 16 about the common centre; all particles: (100 + 16) / 2.
  EXPECT_NEAR(analysis::radial_segregation_index(core), (100.0 - 16.0) / 58.0, 1e-9);
  for (auto& s : core.species) s = 1 - s;  // inverted: big particles inside
  EXPECT_NEAR(analysis::radial_segregation_index(core), -(100.0 - 16.0) / 58.0, 1e-9);
}

TEST(CylinderMeasures, BandCountCountsAlternatingRuns) {
  std::vector<double> prof;
  for (int band = 0; band < 6; ++band)
    for (int k = 0; k < 8; ++k) prof.push_back(band % 2 ? 0.2 : 0.8);
  EXPECT_EQ(analysis::band_count(prof, 0.5), 6);
  EXPECT_EQ(analysis::band_count(std::vector<double>(48, 0.52), 0.5), 0) << "no departure";
  // A single noisy slice is smoothed away.
  std::vector<double> noisy(48, 0.5);
  noisy[20] = 0.75;
  EXPECT_EQ(analysis::band_count(noisy, 0.5), 0);
}

TEST(CylinderMeasures, SurfaceFitRecoversTheSlopeAndRadialProfileTheLayers) {
  const CylinderFrame c = frame();
  // A bed whose top is the line y = -2 + 0.4 x, filled below it on a grid; big particles in the
  // top 3 units (normal depth), small below.
  const double slope = 0.4, a = -2;
  const double cn = 1 / std::sqrt(1 + slope * slope);
  Particles p;
  for (double z = -59; z < 60; z += 2.5)
    for (double x = -14.5; x <= 14.5; x += 0.5)
      for (double y = -14.5; y <= a + slope * x; y += 0.5) {
        if (x * x + y * y > 14.5 * 14.5) continue;
        const double depth = (a + slope * x - y) * cn;
        add(p, {x, y, z}, depth < 3 ? 1 : 0);
      }
  const auto fit = analysis::fit_surface(p, c);
  ASSERT_TRUE(fit.ok);
  EXPECT_NEAR(fit.slope, slope, 0.03);
  EXPECT_NEAR(fit.intercept, a, 0.3);
  const auto prof = analysis::radial_profile(p, c, fit, 6);
  EXPECT_GT(prof[0], 0.9) << "top slab: big particles";
  EXPECT_LT(prof[2], 0.1) << "deeper: small particles";
  EXPECT_LT(prof[3], 0.1);
}

}  // namespace
}  // namespace tumble
