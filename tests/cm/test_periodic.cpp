// Periodic points and their classification (Yu 2022 Secs. I, II A, IV; App. B).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "cm/periodic.hpp"

namespace {
using namespace tumble::cm;

std::vector<PeriodicPoint> search(double tz, double tx, int max_period) {
  const Protocol pr = Protocol::degrees(tz, tx);
  const SectionMap map(pr, ShellChart(0.95, pr.eps));
  PeriodicSearch opt;
  opt.max_period = max_period;
  opt.grid = 30;
  return find_periodic_points(map, opt);
}

int count(const std::vector<PeriodicPoint>& pts, int period, Stability type) {
  int n = 0;
  for (const auto& p : pts) n += p.period == period && p.type == type;
  return n;
}

TEST(PeriodicPoints, Protocol57HasTwoOrbitsOfEllipticPeriod3Points) {
  const auto pts = search(57, 57, 3);
  EXPECT_EQ(count(pts, 1, Stability::Elliptic), 0);
  EXPECT_EQ(count(pts, 2, Stability::Elliptic), 0);
  EXPECT_EQ(count(pts, 3, Stability::Elliptic), 6);
  std::map<int, int> orbit_size;
  for (const auto& p : pts) {
    if (p.type != Stability::Elliptic) continue;
    ++orbit_size[p.orbit];
    EXPECT_NEAR(p.det, 1.0, 1e-6);
    EXPECT_LT(std::abs(p.trace), 2.0);
    EXPECT_NEAR(std::cos(p.rotation), p.trace / 2, 1e-12);
  }
  ASSERT_EQ(orbit_size.size(), 2u);
  for (const auto& [orbit, size] : orbit_size) EXPECT_EQ(size, 3) << "orbit " << orbit;
  int hyperbolic = 0;
  for (const auto& p : pts)
    if (p.type == Stability::Hyperbolic) {
      ++hyperbolic;
      EXPECT_GT(std::abs(p.trace), 2.0);
      EXPECT_GT(std::abs(p.lambda), 1.0);
      // The eigenvectors are eigenvectors: J e_u = lambda e_u.
      EXPECT_LT((p.jacobian * p.unstable - p.lambda * p.unstable).norm(),
                1e-5 * std::abs(p.lambda));
    }
  EXPECT_GE(hyperbolic, 3);
}

// Every orbit is listed whole, each member the image of the one before (P maps it, to Newton's
// tolerance), of one kind. On grid 20 the (45°, 45°) search found an elliptic period-3 orbit with
// 2 members and a hyperbolic one with 1, and (57°, 57°) a period-2 orbit of 1.
TEST(PeriodicPoints, EveryOrbitIsComplete) {
  for (const double theta : {45.0, 57.0}) {
    const Protocol pr = Protocol::degrees(theta, theta);
    const SectionMap map(pr, ShellChart(0.95, pr.eps));
    PeriodicSearch opt;
    opt.max_period = 3;
    opt.grid = 20;
    const auto pts = find_periodic_points(map, opt);
    std::map<int, std::vector<const PeriodicPoint*>> orbits;
    for (const auto& p : pts) orbits[p.orbit].push_back(&p);
    for (const auto& [orbit, members] : orbits) {
      ASSERT_EQ(static_cast<int>(members.size()), members.front()->period)
          << "(" << theta << ", " << theta << ") orbit " << orbit;
      for (const PeriodicPoint* m : members) {
        EXPECT_EQ(m->type, members.front()->type);
        const Vec2 image = map.chart().to_chart(period_map(pr, m->p));
        double nearest = 1e9;
        for (const PeriodicPoint* o : members) nearest = std::min(nearest, (o->v - image).norm());
        EXPECT_LT(nearest, 1e-7) << "(" << theta << ", " << theta << ") orbit " << orbit;
      }
    }
    if (theta == 45.0) {
      EXPECT_EQ(count(pts, 3, Stability::Elliptic), 6);
    }
  }
}

TEST(PeriodicPoints, Protocol90HasFourPeriod2Islands) {
  const auto pts = search(90, 90, 3);
  EXPECT_EQ(count(pts, 1, Stability::Elliptic), 0);
  EXPECT_EQ(count(pts, 2, Stability::Elliptic), 4);
  EXPECT_EQ(count(pts, 3, Stability::Elliptic), 0);
}

// No islands for (68, 68); the hyperbolic points show the search itself did work.
TEST(PeriodicPoints, Protocol68HasNoEllipticPointsUpToPeriod3) {
  const auto pts = search(68, 68, 3);
  for (int n = 1; n <= 3; ++n) EXPECT_EQ(count(pts, n, Stability::Elliptic), 0) << "period " << n;
  int hyperbolic = 0;
  for (const auto& p : pts) hyperbolic += p.type == Stability::Hyperbolic;
  EXPECT_GE(hyperbolic, 2);
}

// Yu 2022 Sec. II A (Fig. 3): during one iteration one A island crosses the flowing layer in
// both rotations, one B island in the first rotation only, another B island in the second only,
// and A1, A2, B2 stay in the bed. Checks the island dynamics independently of chirality.
TEST(PeriodicPoints, Protocol57LayerPassagesMatchFig3) {
  const Protocol pr = Protocol::degrees(57, 57);
  const auto pts = search(57, 57, 3);
  std::map<int, std::multiset<std::pair<int, int>>> passes;  // orbit -> {(z entries, x entries)}
  for (const auto& p : pts) {
    if (p.type != Stability::Elliptic) continue;
    Crossings cz, cx;
    phase_map(pr, Axis::X, phase_map(pr, Axis::Z, p.p, &cz), &cx);
    passes[p.orbit].insert({cz.entries, cx.entries});
  }
  const std::multiset<std::pair<int, int>> a{{1, 1}, {0, 0}, {0, 0}};
  const std::multiset<std::pair<int, int>> b{{1, 0}, {0, 1}, {0, 0}};
  ASSERT_EQ(passes.size(), 2u);
  const auto& o1 = passes.begin()->second;
  const auto& o2 = std::next(passes.begin())->second;
  EXPECT_TRUE((o1 == a && o2 == b) || (o1 == b && o2 == a));
}

// The A and B groups are mirror images half an iteration apart (Sec. II C): with S the mirror
// x <-> z, F = (S F_z)^2, so G = S F_z maps every period-3 point to one of the other orbit.
TEST(PeriodicPoints, Protocol57OrbitsAreMirrorImagesHalfAnIterationApart) {
  const Protocol pr = Protocol::degrees(57, 57);
  const ShellChart chart(0.95, pr.eps);
  const auto pts = search(57, 57, 3);
  for (const auto& p : pts) {
    if (p.type != Stability::Elliptic) continue;
    const Vec3 h = phase_map(pr, Axis::Z, p.p);
    const Vec2 g = chart.to_chart(Vec3(h.z(), h.y(), h.x()));
    int match = -1;
    for (const auto& q : pts)
      if (q.type == Stability::Elliptic && (q.v - g).norm() < 1e-7) match = q.orbit;
    EXPECT_GE(match, 0);
    EXPECT_NE(match, p.orbit);
  }
}

}  // namespace
