// Only what a scene needs (issue 8): the kernels chosen for one species and for frictionless
// scenes skip work, never change a result. Each is compared bitwise with the general path
// (TUMBLE_GENERAL_KERNELS=1 forces it).
#include <gtest/gtest.h>

#include <cstdlib>

#include "dem_helpers.hpp"
#include "scene/fill.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {

Scene bed_scene(const std::vector<std::string>& extra) { return rotating_bed_scene(extra); }

// Runs 1,500 steps from the loose lattice; `general` forces the general kernels.
Particles run(const Scene& s, bool general, bool& one_species, bool& rotation) {
  if (general)
    setenv("TUMBLE_GENERAL_KERNELS", "1", 1);
  else
    unsetenv("TUMBLE_GENERAL_KERNELS");
  Simulation sim(s, make_bed(s), geometry::Protocol::single_axis('z', s.omega()));
  unsetenv("TUMBLE_GENERAL_KERNELS");
  one_species = sim.one_species();
  rotation = sim.rotation();
  sim.compute_forces();
  for (int k = 0; k < 1500; ++k) sim.step();
  return sim.particles();
}

void expect_identical(const Particles& a, const Particles& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.id[i], b.id[i]);
    for (int d = 0; d < 3; ++d) {
      ASSERT_EQ(a.x[i][d], b.x[i][d]) << "particle " << a.id[i];
      ASSERT_EQ(a.v[i][d], b.v[i][d]) << "particle " << a.id[i];
      ASSERT_EQ(a.w[i][d], b.w[i][d]) << "particle " << a.id[i];
    }
  }
}

}  // namespace

TEST(Specialisations, OneSpeciesSkipsLookupsWithTheSameResult) {
  const Scene s = bed_scene({"particles.large_fraction=0"});
  bool one, rot, one_g, rot_g;
  const Particles fast = run(s, false, one, rot);
  const Particles general = run(s, true, one_g, rot_g);
  EXPECT_TRUE(one);
  EXPECT_FALSE(one_g);
  expect_identical(fast, general);
  // A bidisperse bed keeps the lookups.
  bool one_bi, rot_bi;
  (void)run(bed_scene({}), false, one_bi, rot_bi);
  EXPECT_FALSE(one_bi);
  EXPECT_TRUE(rot_bi);
}

TEST(Specialisations, FrictionlessScenesDoNotRotate) {
  const Scene s = bed_scene({"contact.friction=0", "contact.wall_friction=0"});
  bool one, rot, one_g, rot_g;
  const Particles fast = run(s, false, one, rot);
  const Particles general = run(s, true, one_g, rot_g);
  EXPECT_FALSE(rot);
  EXPECT_TRUE(rot_g);
  expect_identical(fast, general);
  for (const Vec3& w : fast.w) ASSERT_EQ(norm2(w), 0.0);
  // Wall friction alone makes torques: rotation stays on.
  bool one_w, rot_w;
  (void)run(bed_scene({"contact.friction=0"}), false, one_w, rot_w);
  EXPECT_TRUE(rot_w);
}
