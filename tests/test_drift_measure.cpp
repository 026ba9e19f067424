// The DEM measurement of the MCM drift grid (Yu 2022 App. A) on constructed particles: frames of
// both rotation phases, selection (large, at the surface, flowing downstream) and per-cell
// statistics.
#include <gtest/gtest.h>

#include <cmath>

#include "run/drift_measure.hpp"
#include "scene/fill.hpp"

using namespace tumble;

namespace {
const double R = 0.035, beta = deg2rad(27), omega = 0.1 * kPi, dL = 0.004;

void expect_vec(const Vec3& a, const Vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-12);
  EXPECT_NEAR(a.y, b.y, 1e-12);
  EXPECT_NEAR(a.z, b.z, 1e-12);
}
}  // namespace

TEST(DriftMeasure, LayerFramesOfBothPhases) {
  analysis::DriftGridMeter m(30, R, beta, omega, dL);
  // z phase, Ω = −ω ẑ: the wall's bottom moves along −x (Ω × r), so material rises at x < 0 and
  // the tilted surface runs downhill along R_z(−β) x̂: that is the streamwise +x of the frame.
  const Vec3 wz{0, 0, -omega};
  expect_vec(m.to_layer_frame({std::cos(beta), -std::sin(beta), 0}, wz), {1, 0, 0});
  expect_vec(m.to_layer_frame({0, 0, 1}, wz), {0, 0, 1});  // axial = +z
  // x phase, Ω = +ω x̂: the bottom moves along −z, material rises at z < 0, downhill is
  // R_x(β) ẑ; the continuum model's frame is (z, y, −x), so the axial direction is −x.
  const Vec3 wx{omega, 0, 0};
  expect_vec(m.to_layer_frame({0, -std::sin(beta), std::cos(beta)}, wx), {1, 0, 0});
  expect_vec(m.to_layer_frame({-1, 0, 0}, wx), {0, 0, 1});
}

TEST(DriftMeasure, CellStatisticsOfSelectedParticles) {
  analysis::DriftGridMeter m(30, R, 0.0, omega, dL);  // no tilt: frame = lab for the z phase
  const Vec3 wz{0, 0, -omega};
  const double u = omega * R;  // velocity unit
  Particles p;
  auto add = [&](Vec3 x, Vec3 v, int species) {
    const std::size_t i = p.size();
    p.resize(i + 1);
    p.x[i] = x;
    p.v[i] = v;
    p.species[i] = species;
  };
  // Cell of (x, z) = (0.1 R, 0.5 R): four flowing large particles at the surface with axial
  // velocities 0.1, 0.3 (twice) and 0.5 ω R.
  for (double va : {0.1, 0.3, 0.3, 0.5}) add({0.1 * R, -0.001, 0.5 * R}, {0.2 * u, 0, va * u}, 1);
  // Excluded: a small particle, a large one deep in the bed, one flowing upstream.
  add({0.1 * R, -0.001, 0.5 * R}, {0.2 * u, 0, 5 * u}, 0);
  add({0.1 * R, -3 * dL, 0.5 * R}, {0.2 * u, 0, 5 * u}, 1);
  add({0.1 * R, 0.0, 0.5 * R}, {-0.2 * u, 0, 5 * u}, 1);
  // Another cell: (−0.5 R, −0.2 R), axial −0.2 ω R twice.
  add({-0.5 * R, 0.001, -0.2 * R}, {0.1 * u, 0, -0.2 * u}, 1);
  add({-0.5 * R, 0.001, -0.2 * R}, {0.1 * u, 0, -0.2 * u}, 1);
  cm::DriftStatistics sums = m.zeros();
  EXPECT_EQ(m.sample(p, wz, sums), 6);
  const cm::DriftGrid g = m.grid(sums, "test");
  const int c1 = g.cell(0.1, 0.5), c2 = g.cell(-0.5, -0.2);
  ASSERT_GE(c1, 0);
  ASSERT_GE(c2, 0);
  EXPECT_NEAR(g.v_ax[c1], 0.3, 1e-12);
  EXPECT_NEAR(g.sigma_ax[c1], std::sqrt(0.08 / 3), 1e-12);  // sample standard deviation
  EXPECT_NEAR(g.v_ax[c2], -0.2, 1e-12);
  EXPECT_NEAR(g.sigma_ax[c2], 0.0, 1e-12);
  // Unsampled cells: no drift, the mean σ of the sampled cells.
  EXPECT_EQ(g.v_ax[g.cell(0.9, -0.9)], 0.0);
  EXPECT_NEAR(g.sigma_ax[g.cell(0.9, -0.9)], 0.5 * std::sqrt(0.08 / 3), 1e-12);
  EXPECT_NEAR(g.v(0.1, 0.5), 0.3, 1e-12);  // the continuum model reads the same cell
}
