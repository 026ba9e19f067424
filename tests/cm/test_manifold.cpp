// Stable and unstable manifolds by iteration with point re-insertion (Yu 2022 App. B).
#include <gtest/gtest.h>

#include "cm/manifold.hpp"

namespace {
using namespace tumble::cm;

struct Manifold57 : ::testing::Test {
  void SetUp() override {
    PeriodicSearch opt;
    opt.max_period = 1;
    opt.grid = 20;
    const auto pts = find_periodic_points(map, opt);
    for (const auto& p : pts)
      if (p.type == Stability::Hyperbolic) h = p;
    ASSERT_EQ(h.type, Stability::Hyperbolic);
    mopt.iterations = 4;
  }
  const Protocol pr = Protocol::degrees(57, 57);
  const SectionMap map{pr, ShellChart(0.95, pr.eps)};
  PeriodicPoint h;
  ManifoldOptions mopt;
  // Farthest point of the initial segment from h (half the length, up to the shell's curvature).
  double segment_reach(const Manifold& m) const {
    double d = 0;
    for (std::size_t i = 0; i < m.xyz.size(); ++i)
      if (m.iteration[i] == 0) d = std::max(d, (m.xyz[i] - h.p).norm());
    return d;
  }
};

TEST_F(Manifold57, UnstableManifoldIsOnTheShellDenseAndComesFromThePoint) {
  const Manifold m = trace_manifold(map, h, true, mopt);
  ASSERT_EQ(m.iterations_done, mopt.iterations);
  const double reach = segment_reach(m);
  EXPECT_NEAR(reach, 0.5 * mopt.length, 0.01 * mopt.length);
  std::size_t last = 0;
  for (std::size_t i = 0; i < m.xyz.size(); ++i) {
    EXPECT_NEAR(shell_radius(m.xyz[i], pr.eps), 0.95, 1e-12);
    if (m.iteration[i] == mopt.iterations) ++last;
    // Backwards in time every point returns to the initial segment around h.
    if (i % 97 == 0) {
      Vec3 p = m.xyz[i];
      for (int k = 0; k < m.iteration[i]; ++k) p = inverse_period_map(pr, p);
      EXPECT_LT((p - h.p).norm(), reach * (1 + 1e-6));
    }
  }
  // Re-insertion keeps neighbours within the spacing, so the curve grew with the stretching.
  EXPECT_GT(last, 10 * static_cast<std::size_t>(mopt.initial_points));
  for (std::size_t i = 0; i + 1 < m.xyz.size(); ++i)
    if (m.iteration[i] == mopt.iterations && m.iteration[i + 1] == mopt.iterations) {
      EXPECT_LE((m.xyz[i + 1] - m.xyz[i]).norm(), mopt.spacing * (1 + 1e-9));
    }
}

TEST_F(Manifold57, StableManifoldPointsConvergeForwardInTime) {
  const Manifold m = trace_manifold(map, h, false, mopt);
  ASSERT_EQ(m.iterations_done, mopt.iterations);
  const double reach = segment_reach(m);
  for (std::size_t i = 0; i < m.xyz.size(); i += 53) {
    Vec3 p = m.xyz[i];
    for (int k = 0; k < m.iteration[i]; ++k) p = period_map(pr, p);
    EXPECT_LT((p - h.p).norm(), reach * (1 + 1e-6));
  }
}

}  // namespace
