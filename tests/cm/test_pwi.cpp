// The eps -> 0 limit: the piecewise isometry of the hemispherical shell.
#include <gtest/gtest.h>

#include <random>

#include "cm/protocol.hpp"
#include "cm_test_util.hpp"

namespace {
using namespace tumble::cm;
using tumble::cm::test::random_bed_point;

// For (90, 90) the PWI period map M satisfies M^6 = identity (docs/architecture.md, "Continuum
// model notes").
TEST(Pwi, NinetyNinetyHasOrderSix) {
  const Protocol pr = Protocol::degrees(90, 90, 0.15, FlowModel::Pwi);
  std::mt19937_64 rng(31);
  int moved = 0;
  for (int k = 0; k < 1000; ++k) {
    const Vec3 p = random_bed_point(rng, 0.01, 1.0);
    EXPECT_LT((iterate(pr, p, 6) - p).norm(), 1e-12);
    moved += (iterate(pr, p, 3) - p).norm() > 1e-3;  // and M^3 is not the identity
  }
  EXPECT_GT(moved, 500);
}

TEST(Pwi, IsAnIsometryOfShells) {
  const Protocol pr = Protocol::degrees(57, 57, 0.15, FlowModel::Pwi);
  std::mt19937_64 rng(32);
  for (int k = 0; k < 200; ++k) {
    const Vec3 p = random_bed_point(rng);
    EXPECT_NEAR(period_map(pr, p).norm(), p.norm(), 1e-14);
  }
}

// Mean distance between the CM and the PWI images of the same points, over a fixed sample.
double mean_gap(double eps, bool whole_period) {
  const Protocol cm = Protocol::degrees(57, 57, eps);
  const Protocol pwi = Protocol::degrees(57, 57, eps, FlowModel::Pwi);
  std::mt19937_64 rng(33);
  double s = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    const Vec3 p = random_bed_point(rng, 0.3, 0.95);
    s += whole_period ? (period_map(cm, p) - period_map(pwi, p)).norm()
                      : (phase_map(cm, Axis::Z, p) - phase_map(pwi, Axis::Z, p)).norm();
  }
  return s / n;
}

// The CM converges to the PWI at first order in eps: halving eps halves the gap.
TEST(Pwi, CmConvergesAtFirstOrderInEps) {
  for (bool whole : {false, true}) {
    const double g1 = mean_gap(0.02, whole), g2 = mean_gap(0.01, whole),
                 g3 = mean_gap(0.005, whole);
    EXPECT_GT(g1 / g2, 1.7) << (whole ? "period" : "phase");
    EXPECT_LT(g1 / g2, 2.3) << (whole ? "period" : "phase");
    EXPECT_GT(g2 / g3, 1.7) << (whole ? "period" : "phase");
    EXPECT_LT(g2 / g3, 2.3) << (whole ? "period" : "phase");
  }
}

}  // namespace
