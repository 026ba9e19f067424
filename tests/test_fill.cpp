// Filling: reproducible in the seed, the requested composition, and the presegregated starts.
#include <gtest/gtest.h>

#include <cmath>

#include "base/error.hpp"
#include "io/bed_io.hpp"
#include "scene/fill.hpp"
#include "scene/scene.hpp"

using namespace tumble;

namespace {
Scene tiny(const std::vector<std::string>& o = {}) {
  std::vector<std::string> all = {"tumbler.radius=0.02"};
  all.insert(all.end(), o.begin(), o.end());
  return parse_scene("", all, "test");
}
double mean_coord(const Particles& p, int species, int axis) {
  double s = 0, n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] == species) s += p.x[i][axis], n += 1;
  return s / n;
}
}  // namespace

TEST(Fill, SameSeedSameBedOtherSeedOtherBed) {
  const Particles a = make_bed(tiny({"fill.seed=7"}));
  const Particles b = make_bed(tiny({"fill.seed=7"}));
  const Particles c = make_bed(tiny({"fill.seed=8"}));
  ASSERT_EQ(a.size(), b.size());
  bool same = true, differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    same = same && a.x[i].x == b.x[i].x && a.x[i].y == b.x[i].y && a.x[i].z == b.x[i].z &&
           a.species[i] == b.species[i];
    differs = differs || a.x[i].x != c.x[i].x;
  }
  EXPECT_TRUE(same);
  EXPECT_TRUE(differs);
}

// Validation plans without storing positions: the same walk, so the same counts and the same fit.
TEST(Fill, CountOnlyPlanMatchesTheBed) {
  for (const char* start : {"fill.start=mixed", "fill.start=large_top", "fill.start=large_xneg"}) {
    const Scene s = tiny({start, "particles.large_fraction=0.3"});
    const BedPlan full = plan_bed(s), counts = plan_bed(s, false);
    EXPECT_EQ(counts.n_large, full.n_large);
    EXPECT_EQ(counts.n_small, full.n_small);
    EXPECT_TRUE(counts.position.empty());
    EXPECT_EQ(static_cast<std::int64_t>(full.position.size()), full.n_large + full.n_small);
  }
}

TEST(Fill, CompositionMatchesLargeFraction) {
  for (double f : {0.0, 0.15, 0.5, 1.0}) {
    const Scene s = tiny({"particles.large_fraction=" + std::to_string(f)});
    const Particles p = make_bed(s);
    double vl = 0, vall = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double v = std::pow(p.radius[i], 3);
      vall += v;
      if (p.species[i] == 1) vl += v;
    }
    EXPECT_NEAR(vl / vall, f, 0.01) << "f = " << f;
    // Every particle inside the tumbler, none overlapping the wall.
    for (std::size_t i = 0; i < p.size(); ++i) EXPECT_LT(norm(p.x[i]) + p.radius[i], s.radius);
  }
}

TEST(Fill, NoTwoParticlesOverlapAtStart) {
  const Particles p = make_bed(tiny());
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      ASSERT_GE(norm(p.x[i] - p.x[j]), p.radius[i] + p.radius[j]) << i << " " << j;
}

TEST(Fill, PresegregatedStarts) {
  const Particles top = make_bed(tiny({"fill.start=large_top", "particles.large_fraction=0.3"}));
  EXPECT_GT(mean_coord(top, 1, 1), mean_coord(top, 0, 1) + 0.004);  // large above small
  const Particles half = make_bed(tiny({"fill.start=large_xneg", "particles.large_fraction=0.3"}));
  EXPECT_LT(mean_coord(half, 1, 0), -0.004);  // large in the x < 0 half
  EXPECT_GT(mean_coord(half, 0, 0), 0.0);
  const Particles mixed = make_bed(tiny({"particles.large_fraction=0.3"}));
  EXPECT_NEAR(mean_coord(mixed, 1, 0), 0.0, 0.003);
}

TEST(Fill, DensityBidisperseAndSizeRatioFour) {
  const Particles d = make_bed(tiny({"particles.d_large=0.002", "particles.density_ratio=3"}));
  ASSERT_GT(d.size(), 0u);
  for (std::size_t i = 0; i < d.size(); ++i) EXPECT_EQ(d.radius[i], 0.001);
  const Particles r4 =
      make_bed(parse_scene("", {"tumbler.radius=0.04", "particles.d_large=0.008"}, "test"));
  EXPECT_GT(r4.size(), 1000u);
}

// The bed cache key: the settle-relevant keys change it, output keys do not, and a new version of
// the fill/settle code names another file (version 1 keeps the names of existing caches).
TEST(Fill, BedCacheKeyNamesWhatDeterminesTheBed) {
  const Scene s = tiny({"fill.seed=7"});
  EXPECT_EQ(io::bed_key(s), io::bed_key(s, 1));
  EXPECT_EQ(io::bed_key(s).find(";code="), std::string::npos);
  EXPECT_NE(io::bed_key(s, 2), io::bed_key(s, 1));
  EXPECT_NE(io::bed_key(s), io::bed_key(tiny({"fill.seed=8"})));
  EXPECT_NE(io::bed_key(s), io::bed_key(tiny({"fill.seed=7", "contact.collision_time=0.001"})));
  EXPECT_EQ(io::bed_key(s), io::bed_key(tiny({"fill.seed=7", "output.snapshot_interval=0.5"})));
}
