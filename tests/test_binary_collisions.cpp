// Binary collisions with the Yu 2022 law: the measured normal restitution equals e within 1% and
// the contact lasts t_c within 2%, for small-small, small-large, large-large and particle-wall,
// at the default time step t_c/50. The contact duration is measured between the linearly
// interpolated zero crossings of the overlap (a step count alone resolves only dt = 2% of t_c).
#include <gtest/gtest.h>

#include <cmath>

#include "dem_helpers.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {
struct Outcome {
  double restitution = 0, duration = 0;
};

// Two particles approaching head-on along x with relative speed u.
Outcome pair_collision(int sa, int sb, double u, const Scene& s) {
  const double ra = 0.5 * (sa ? s.d_large : s.d_small), rb = 0.5 * (sb ? s.d_large : s.d_small);
  const double gap = 0.1 * s.d_small;
  Simulation sim(s,
                 make_particles(s, {{{-ra - gap / 2, 0, 0}, {u / 2, 0, 0}, {}, sa},
                                    {{rb + gap / 2, 0, 0}, {-u / 2, 0, 0}, {}, sb}}),
                 geometry::Protocol::at_rest());
  sim.compute_forces();
  auto overlap = [&]() {
    const auto& p = sim.particles();
    return p.radius[0] + p.radius[1] - norm(p.x[0] - p.x[1]);
  };
  double prev = overlap(), t_start = -1, t_end = -1;
  for (int k = 0; k < 100000 && t_end < 0; ++k) {
    sim.step();
    const double ov = overlap();
    if (t_start < 0 && prev <= 0 && ov > 0) t_start = sim.time() - sim.dt() * ov / (ov - prev);
    if (t_start >= 0 && prev > 0 && ov <= 0) t_end = sim.time() - sim.dt() * ov / (ov - prev);
    prev = ov;
  }
  const auto& p = sim.particles();
  const std::size_t a = index_of(sim, 0), b = index_of(sim, 1);
  const double v_after = p.v[b].x - p.v[a].x;  // separating: b moves +x relative to a
  return {v_after / u, t_end - t_start};
}

// A particle moving radially onto the (resting) tumbler wall with speed u.
Outcome wall_collision(int sp, double u, const Scene& s) {
  const double r = 0.5 * (sp ? s.d_large : s.d_small);
  const double y0 = -(s.radius - r - 0.05 * s.d_small);
  Simulation sim(s, make_particles(s, {{{0, y0, 0}, {0, -u, 0}, {}, sp}}),
                 geometry::Protocol::at_rest());
  sim.compute_forces();
  auto overlap = [&]() { return norm(sim.particles().x[0]) + r - s.radius; };
  double prev = overlap(), t_start = -1, t_end = -1;
  for (int k = 0; k < 100000 && t_end < 0; ++k) {
    sim.step();
    const double ov = overlap();
    if (t_start < 0 && prev <= 0 && ov > 0) t_start = sim.time() - sim.dt() * ov / (ov - prev);
    if (t_start >= 0 && prev > 0 && ov <= 0) t_end = sim.time() - sim.dt() * ov / (ov - prev);
    prev = ov;
  }
  return {sim.particles().v[0].y / u, t_end - t_start};
}
}  // namespace

class BinaryCollision : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(BinaryCollision, RestitutionAndDurationMatchTheLaw) {
  const Scene s = test_scene();
  const auto [a, b] = GetParam();
  for (double u : {0.05, 0.5, 2.0}) {
    const Outcome o = pair_collision(a, b, u, s);
    EXPECT_NEAR(o.restitution, s.restitution, 0.01 * s.restitution) << "u = " << u;
    EXPECT_NEAR(o.duration, s.collision_time, 0.02 * s.collision_time) << "u = " << u;
  }
}

std::string pair_name(const ::testing::TestParamInfo<std::pair<int, int>>& info) {
  const char* names[] = {"small", "large"};
  return std::string(names[info.param.first]) + "_" + names[info.param.second];
}

INSTANTIATE_TEST_SUITE_P(SpeciesPairs, BinaryCollision,
                         ::testing::Values(std::make_pair(0, 0), std::make_pair(0, 1),
                                           std::make_pair(1, 1)),
                         pair_name);

TEST(WallCollision, RestitutionAndDurationMatchTheLaw) {
  const Scene s = test_scene();
  for (int sp : {0, 1})
    for (double u : {0.05, 0.5, 2.0}) {
      const Outcome o = wall_collision(sp, u, s);
      EXPECT_NEAR(o.restitution, s.restitution, 0.01 * s.restitution)
          << "species " << sp << " u " << u;
      EXPECT_NEAR(o.duration, s.collision_time, 0.02 * s.collision_time) << "species " << sp;
    }
}

TEST(BinaryCollision, OtherRestitutionsAndStiffnesses) {
  for (const char* e : {"0.3", "0.6", "0.95"})
    for (const char* tc : {"1e-5", "1e-3"}) {
      const Scene s = test_scene(
          {std::string("contact.restitution=") + e, std::string("contact.collision_time=") + tc});
      const Outcome o = pair_collision(0, 1, 0.3, s);
      EXPECT_NEAR(o.restitution, s.restitution, 0.01 * s.restitution) << "e " << e << " tc " << tc;
      EXPECT_NEAR(o.duration, s.collision_time, 0.02 * s.collision_time)
          << "e " << e << " tc " << tc;
    }
}
