// Invariants of the CM map: the shells R(p) = r and the invariant measure.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "cm/protocol.hpp"
#include "cm/section_map.hpp"
#include "cm_test_util.hpp"

namespace {
using namespace tumble::cm;
using tumble::cm::test::random_bed_point;

TEST(Invariants, ShellRadiusPreservedOver100Periods) {
  const Protocol pr = Protocol::degrees(57, 57);
  std::mt19937_64 rng(21);
  int layer_starts = 0;
  for (int k = 0; k < 200; ++k) {
    const Vec3 p0 = random_bed_point(rng, 0.2, 0.999);
    layer_starts += in_layer(p0, pr.eps);
    const double r0 = shell_radius(p0, pr.eps);
    Vec3 p = p0;
    for (int n = 0; n < 100; ++n) {
      p = period_map(pr, p);
      ASSERT_NEAR(shell_radius(p, pr.eps), r0, 1e-12) << "start " << p0.transpose();
    }
  }
  EXPECT_GT(layer_starts, 5);  // caps in the layer were tested too
}

// The region a point is in at the start and end, and the interface crossings of each phase:
// finite differences are only meaningful on one smooth branch of the map.
struct Branch {
  Crossings z, x;
  bool operator==(const Branch& o) const {
    return z.entries == o.z.entries && z.exits == o.z.exits && x.entries == o.x.entries &&
           x.exits == o.x.exits;
  }
};

Vec3 map_on_branch(const Protocol& pr, const Vec3& p, Branch& b) {
  return phase_map(pr, Axis::X, phase_map(pr, Axis::Z, p, &b.z), &b.x);
}

// Richardson-extrapolated central differences (error O(h^4)), so that truncation stays well
// below the 1e-8 asserted; false if a stencil point takes another branch.
bool jacobian3(const Protocol& pr, const Vec3& p, Eigen::Matrix3d& J) {
  Branch base;
  map_on_branch(pr, p, base);
  Eigen::Matrix3d Jh[2];
  const double hs[2] = {1e-6, 5e-7};
  for (int s = 0; s < 2; ++s)
    for (int c = 0; c < 3; ++c) {
      Vec3 d = Vec3::Zero();
      d[c] = hs[s];
      Branch a, b;
      const Vec3 fa = map_on_branch(pr, p + d, a), fb = map_on_branch(pr, p - d, b);
      if (!(a == base) || !(b == base)) return false;
      Jh[s].col(c) = (fa - fb) / (2 * hs[s]);
    }
  J = (4 * Jh[1] - Jh[0]) / 3;
  return true;
}

// The exact invariant measure is dV in the bulk and (1 - eps^2) dV in the layer (flow_field.hpp):
// det DF = 1 when a point starts and ends in the same region, 1/(1 - eps^2) bulk -> layer,
// (1 - eps^2) layer -> bulk.
TEST(Invariants, VolumeJacobianIsOneOnSameRegionBranches) {
  const Protocol pr = Protocol::degrees(57, 57);
  const double e2 = pr.eps * pr.eps;
  std::mt19937_64 rng(22);
  int tested[3] = {0, 0, 0};
  for (int k = 0; k < 1500; ++k) {
    const Vec3 p = random_bed_point(rng);
    Eigen::Matrix3d J;
    if (!jacobian3(pr, p, J)) continue;
    const bool from_layer = in_layer(p, pr.eps), to_layer = in_layer(period_map(pr, p), pr.eps);
    const int kind = from_layer == to_layer ? 0 : from_layer ? 1 : 2;
    const double expected = kind == 0 ? 1.0 : kind == 1 ? 1 - e2 : 1 / (1 - e2);
    EXPECT_NEAR(J.determinant(), expected, 1e-8) << "p = " << p.transpose() << " kind " << kind;
    ++tested[kind];
  }
  EXPECT_GT(tested[0], 500);
  EXPECT_GT(tested[1], 50);
  EXPECT_GT(tested[2], 50);
}

// In the shell chart (equal-area for the invariant measure) the section map is area preserving
// everywhere, region changes included.
TEST(Invariants, SectionMapPreservesChartArea) {
  const Protocol pr = Protocol::degrees(57, 57);
  const SectionMap map(pr, ShellChart(0.95, pr.eps));
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.05, 1.05);
  int tested = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec2 v(u(rng), u(rng));
    if (!map.chart().inside(v) || v.norm() > 0.98 * map.chart().outer()) continue;
    // Richardson differences; skip stencils straddling a kink of the map (the rim, a phase end).
    Eigen::Matrix2d Jh[2];
    const double hs[2] = {2e-6, 1e-6};
    for (int s = 0; s < 2; ++s)
      for (int c = 0; c < 2; ++c) {
        Vec2 d = Vec2::Zero();
        d[c] = hs[s];
        Jh[s].col(c) = (map(v + d) - map(v - d)) / (2 * hs[s]);
      }
    const Eigen::Matrix2d J = (4 * Jh[1] - Jh[0]) / 3;
    if ((Jh[1] - Jh[0]).norm() > 1e-3 * (1 + J.norm())) continue;  // kink inside the stencil
    EXPECT_NEAR(J.determinant(), 1.0, 1e-8) << "v = " << v.transpose();
    ++tested;
  }
  EXPECT_GT(tested, 250);
}

}  // namespace
