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

namespace {

// --max-points bounds the whole manifold (all iterations together), so its memory is known before
// a run: a strongly stretching manifold stops before the iteration that would exceed it, even
// when one gap alone would (|lambda|^k growth).
TEST_F(Manifold57, MaxPointsBoundsTheWholeManifold) {
  mopt.iterations = 14;
  mopt.max_points = 3000;
  const Manifold m = trace_manifold(map, h, true, mopt);
  EXPECT_TRUE(m.truncated);
  EXPECT_LE(m.xyz.size(), mopt.max_points);
  EXPECT_EQ(m.chart.size(), m.xyz.size());
  EXPECT_GE(m.iterations_done, 2);
  EXPECT_LT(m.iterations_done, mopt.iterations);
  EXPECT_EQ(m.iteration.back(), m.iterations_done);
  // One more iteration would not have fit.
  mopt.iterations = m.iterations_done + 1;
  mopt.max_points = 100000000;
  const Manifold more = trace_manifold(map, h, true, mopt);
  EXPECT_GT(more.xyz.size(), 3000u);
  // The estimate covers what the manifold holds (vectors grow by doubling).
  const double held = m.xyz.capacity() * sizeof(Vec3) + m.chart.capacity() * sizeof(Vec2) +
                      m.iteration.capacity() * sizeof(int) + m.param.capacity() * sizeof(double);
  mopt.max_points = 3000;
  EXPECT_GE(manifold_memory_bytes(mopt), held);
}

// Progress goes from 0 to 1 without going back.
TEST_F(Manifold57, ProgressIsMonotoneAndEndsAtOne) {
  std::vector<double> seen;
  mopt.iterations = 5;
  trace_manifold(map, h, false, mopt, [&](double d) { seen.push_back(d); });
  ASSERT_FALSE(seen.empty());
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]);
  EXPECT_GE(seen.front(), 0.0);
  EXPECT_EQ(seen.back(), 1.0);
}

}  // namespace
