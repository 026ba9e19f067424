// Island boundaries as polygons (the closed invariant curves around elliptic points).
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "cm/island.hpp"
#include "cm/kam.hpp"

namespace {
using namespace tumble::cm;

TEST(Polygon, AreaContainmentAndClipping) {
  const Polygon sq{{{0, 0}, {2, 0}, {2, 1}, {0, 1}}};
  EXPECT_DOUBLE_EQ(sq.area(), 2.0);
  EXPECT_TRUE(sq.contains({1.5, 0.5}));
  EXPECT_FALSE(sq.contains({2.5, 0.5}));
  EXPECT_LT((sq.centroid() - Vec2(1, 0.5)).norm(), 1e-15);
  const Polygon big{{{-3, -3}, {3, -3}, {3, 3}, {-3, 3}}};
  EXPECT_NEAR(clip_to_disc(big, 0.7).area(), kPi * 0.49, 1e-5);
  EXPECT_NEAR(clip_to_disc(sq, 10).area(), 2.0, 1e-12);
}

struct Islands57 : ::testing::Test {
  static void SetUpTestSuite() {
    const Protocol pr = Protocol::degrees(57, 57);
    map = new SectionMap(pr, ShellChart(0.95, pr.eps));
    PeriodicSearch opt;
    opt.max_period = 3;
    opt.grid = 30;
    points = find_periodic_points(*map, opt);
    islands = find_islands(*map, points, IslandOptions{});
  }
  static void TearDownTestSuite() { delete map; }
  static inline SectionMap* map = nullptr;
  static inline std::vector<PeriodicPoint> points;
  static inline std::vector<Island> islands;
};

TEST_F(Islands57, SixCongruentIslandsAroundTheirCentres) {
  ASSERT_EQ(islands.size(), 6u);
  for (const auto& isl : islands) {
    EXPECT_EQ(isl.period, 3);
    EXPECT_TRUE(isl.boundary.contains(isl.center));
    EXPECT_EQ(island_containing(islands, isl.center), &isl - islands.data());  // disjoint
  }
  // P maps an island onto the next one of its orbit and preserves chart area, so the islands of
  // an orbit agree up to the polygon's sampling of the curve.
  for (const auto& a : islands)
    for (const auto& b : islands)
      if (a.orbit == b.orbit) {
        EXPECT_NEAR(a.boundary.area(), b.boundary.area(), 1e-3 * a.boundary.area());
      }
  // The two orbits are mirror images (Sec. II C), so their islands have equal areas; each
  // boundary is found on its own, and the last curve a 10^4-iterate orbit certifies moves
  // within the sticky layer outside the last KAM curve (about 1-2% in area, docs/cm.md).
  EXPECT_NEAR(islands.front().boundary.area(), islands.back().boundary.area(),
              3e-2 * islands.front().boundary.area());
  EXPECT_GT(island_bulk_area_fraction(map->chart(), islands), 0);
}

// Inside a KAM curve points stay inside forever; start well inside (the polygon is a sampled
// curve) and follow P^3 for 300 periods of the island.
TEST_F(Islands57, BoundaryIsABarrierForInnerPoints) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& isl : islands) {
    const auto& vs = isl.boundary.vertices;
    for (int k = 0; k < 10; ++k) {
      const Vec2 edge = vs[static_cast<std::size_t>(u(rng) * vs.size()) % vs.size()];
      Vec2 v = isl.center + 0.9 * u(rng) * (edge - isl.center);
      for (int n = 0; n < 300; ++n) {
        v = (*map)(v, 3);
        ASSERT_TRUE(isl.boundary.contains(v)) << "left island at period " << n;
      }
    }
  }
}

// And it is the outermost one: points launched a little outside it wander off into the chaotic
// sea (most of them, within 1000 periods of the island).
TEST_F(Islands57, PointsJustOutsideEscape) {
  int escaped = 0, launched = 0;
  for (const auto& isl : islands) {
    const Vec2 out = isl.center + 1.25 * (isl.launch - isl.center);
    for (double jitter : {0.0, 0.01, 0.02}) {
      Vec2 v = out + Vec2(jitter, -jitter);
      ++launched;
      for (int n = 0; n < 1000; ++n) {
        v = (*map)(v, 3);
        if ((v - isl.center).norm() > 3 * isl.extent) {
          ++escaped;
          break;
        }
      }
    }
  }
  EXPECT_GE(escaped, launched * 2 / 3);
}

// KAM tubes narrow towards the centre of the tumbler (Yu 2022 Fig. 1(b)).
TEST_F(Islands57, KamTubesNarrowInwards) {
  const auto tubes = kam_tubes(map->protocol(), points, 0.95, {0.85, 0.75}, KamOptions{});
  std::map<int, std::map<double, double>> area;  // point -> r -> area
  for (const auto& isl : tubes) area[isl.point][isl.r] = isl.boundary.area();
  ASSERT_EQ(area.size(), 6u);
  for (const auto& isl : islands) {
    const auto& a = area.at(isl.point);
    ASSERT_EQ(a.size(), 2u);
    EXPECT_LT(a.at(0.75), a.at(0.85));
    EXPECT_LT(a.at(0.85), isl.boundary.area());
  }
}

}  // namespace
