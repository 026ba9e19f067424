// The half Verlet list: every pair within cutoff + skin appears exactly once, rows are sorted, and
// springs survive a rebuild identically whether carried by old index (the fast local path) or by
// global id (the path restarts and migration use).
#include <gtest/gtest.h>

#include <set>

#include "bed_fixture.hpp"
#include "engine/simulation.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {
// A flowing tiny bed with live springs: 0.2 s of the biaxial protocol from the settled bed.
Simulation flowing_bed() {
  const Scene s = tiny_scene({"protocol.mode=biaxial", "protocol.rpm=30"});
  Simulation sim(s, tiny_settled_bed(),
                 geometry::Protocol::biaxial(deg2rad(57), deg2rad(57), deg2rad(27), s.omega()));
  sim.compute_forces();
  for (int k = 0; k < 10000; ++k) sim.step();
  return sim;
}
}  // namespace

TEST(VerletList, HoldsEveryCloseParticlePairOnceInSortedRows) {
  Simulation sim = flowing_bed();
  sim.request_rebuild();
  sim.step();
  const auto& p = sim.particles();
  const auto& l = sim.neighbors();
  std::set<std::pair<std::uint32_t, std::uint32_t>> listed;
  for (std::uint32_t i = 0; i + 1 < l.start.size(); ++i)
    for (std::uint32_t k = l.start[i]; k < l.start[i + 1]; ++k) {
      EXPECT_GT(l.nbr[k], i);
      if (k > l.start[i]) {
        EXPECT_GT(l.nbr[k], l.nbr[k - 1]) << "row " << i << " not sorted";
      }
      EXPECT_TRUE(listed.insert({i, l.nbr[k]}).second) << "pair listed twice";
    }
  std::size_t needed = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (std::uint32_t j = i + 1; j < p.size(); ++j) {
      const double cut = p.radius[i] + p.radius[j] + l.skin();
      if (norm2(p.x[i] - p.x[j]) < cut * cut) {
        ++needed;
        EXPECT_TRUE(listed.count({i, j})) << "missing pair " << i << " " << j;
      }
    }
  EXPECT_EQ(needed, listed.size());
  EXPECT_GT(needed, p.size());  // a dense bed
}

TEST(VerletList, SpringsCarriedByIndexEqualSpringsMatchedById) {
  Simulation sim = flowing_bed();
  neighbor::ContactHistory by_id;
  sim.neighbors().save_history(sim.particles(), by_id);
  ASSERT_GT(by_id.records().size(), 500u);  // many live springs
  // Rebuild a copy through the local path (particles re-sorted, springs carried by old index).
  Particles copy = sim.particles();
  neighbor::VerletList local = sim.neighbors();
  local.rebuild(copy);  // local carry-over
  std::size_t checked = 0;
  for (std::size_t i = 0; i + 1 < local.start.size(); ++i)
    for (std::uint32_t k = local.start[i]; k < local.start[i + 1]; ++k) {
      const Vec3 want = by_id.lookup(copy.id[i], copy.id[local.nbr[k]]);
      const Vec3 got = local.spring[k];
      ASSERT_TRUE(want.x == got.x && want.y == got.y && want.z == got.z) << "pair " << i;
      checked += want.x != 0 || want.y != 0 || want.z != 0;
    }
  EXPECT_EQ(checked, by_id.records().size());
}
