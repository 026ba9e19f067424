// Binary collisions with the Yu 2022 law: the measured normal restitution equals e within 1% and
// the contact lasts t_c within 2%, for small-small, small-large, large-large and particle-wall,
// at the default time step t_c/50. The contact duration is measured between the linearly
// interpolated zero crossings of the overlap (a step count alone resolves only dt = 2% of t_c).
#include <gtest/gtest.h>

#include <cmath>

#include "collision_fixtures.hpp"

using namespace tumble;
using namespace tumble::testing;

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
