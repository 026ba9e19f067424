// The modified continuum model (Yu 2022 Sec. III B, App. A).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cm/exact_map.hpp"
#include "cm/mcm_summary.hpp"
#include "cm/shell_chart.hpp"
#include "cm_test_util.hpp"

namespace {
using namespace tumble::cm;

DriftGrid uniform_grid(double v, double sigma) {
  DriftGrid g;
  g.v_ax.assign(g.n * g.n, v);
  g.sigma_ax.assign(g.n * g.n, sigma);
  return g;
}

TEST(Mcm, WithoutDriftOrDiffusionItIsTheCm) {
  const ShellChart chart(0.95, 0.15);
  McmOptions opt;
  opt.drift = false;
  opt.c = 0;
  const DriftGrid g = uniform_grid(0.05, 1.0);
  std::mt19937_64 rng(51), seeds(52);
  for (const Vec3& p : chart.random_seeds(200, seeds)) {
    const Vec3 a = mcm_flow_z(p, 2.5, 0.15, chart.footprint(), g, opt, rng);
    EXPECT_LT((a - flow_z_exact(p, 2.5, 0.15)).norm(), 1e-12);
  }
}

// Iteration 0 is the seeds: --snapshot 0 gave an empty snapshot, --cumulative 0,N began at 1.
TEST(Mcm, IterationZeroIsTheSeeds) {
  const Protocol pr = Protocol::degrees(57, 57);
  McmOptions opt;
  opt.tracers = 50;
  opt.snapshot = 0;
  opt.cumulative_from = 0;
  opt.cumulative_to = 1;
  opt.cumulative_stride = 1;
  const McmResult res = run_mcm(pr, synthetic_drift({}), opt);
  ASSERT_EQ(res.snapshot.size(), 50u);
  ASSERT_EQ(res.cumulative.size(), 100u);
  for (std::size_t k = 0; k < 50; ++k) {
    EXPECT_EQ(res.snapshot[k], res.initial[k]);
    EXPECT_EQ(res.cumulative[k], res.initial[k]);
    EXPECT_EQ(res.cumulative_iteration[k], 0);
    EXPECT_EQ(res.cumulative_iteration[50 + k], 1);
  }
  EXPECT_NE(res.cumulative[50], res.initial[0]);  // (one iteration moves it)
}

// A uniform drift moves a tracer by v pi eps per transit, and it stays on its shell.
TEST(Mcm, DriftDisplacesAxiallyByVTimesTransitTime) {
  const double eps = 0.15, v = 0.01;
  const ShellChart chart(0.95, eps);
  McmOptions opt;
  opt.c = 0;
  const DriftGrid g = uniform_grid(v, 0.0);
  std::mt19937_64 rng(53);
  for (double z : {-0.4, 0.0, 0.3}) {
    const double a = std::sqrt(chart.footprint() * chart.footprint() - z * z);
    const Vec3 entry = layer_point(a, 0, z, eps);
    const Vec3 out = mcm_flow_z(entry, kPi * eps, eps, chart.footprint(), g, opt, rng);
    EXPECT_NEAR(out.z() - z, v * kPi * eps, 1e-12);
    EXPECT_NEAR(shell_radius(out, eps), 0.95, 1e-12);
    EXPECT_FALSE(in_layer(out + Vec3(0, -1e-9, 0), eps));  // arrived at the interface
  }
}

// The random walk has the diffusivity of the paper's scheme, (c sigma)^2 dt_ref, whatever dt.
TEST(Mcm, KickVarianceMatchesPaperDiffusivity) {
  const double eps = 0.15, sigma = 1.0;
  const ShellChart chart(0.95, eps);
  const DriftGrid g = uniform_grid(0.0, sigma);
  for (double dt : {0.002, 0.01}) {
    McmOptions opt;
    opt.c = 3;
    opt.dt = dt;
    std::mt19937_64 rng(54);
    const double a = std::sqrt(chart.footprint() * chart.footprint() - 0.01);
    const Vec3 entry = layer_point(a, 0, 0.1, eps);
    double s2 = 0;
    const int n = 4000;
    for (int k = 0; k < n; ++k) {
      const double dz = mcm_flow_z(entry, kPi * eps, eps, chart.footprint(), g, opt, rng).z() - 0.1;
      s2 += dz * dz;
    }
    const double expected = std::pow(opt.c * sigma, 2) * opt.dt_ref * kPi * eps;
    // Sample variance of n values: relative sd sqrt(2/n) = 2.2%; allow 4.5 sd.
    EXPECT_NEAR(s2 / n / expected, 1.0, 0.1) << "dt = " << dt;
  }
}

// Yu 2022 Fig. 9 with the synthetic drift field: drift makes the islands sinks; diffusion alone
// does not. Numbers of this run are reported in docs/cm.md.
TEST(Mcm, Protocol57DriftFillsTheIslands) {
  const Protocol pr = Protocol::degrees(57, 57);
  const ShellChart chart(0.95, pr.eps);
  const SectionMap map(pr, chart);
  PeriodicSearch ps;
  ps.max_period = 3;
  ps.grid = 30;
  const auto islands = find_islands(map, find_periodic_points(map, ps), IslandOptions{});
  // Six period-3 islands, with the period-6 chains around them (found as 1/2 resonances).
  ASSERT_EQ(std::count_if(islands.begin(), islands.end(),
                          [](const Island& i) { return i.parent_orbit < 0; }),
            6);
  const DriftGrid grid = synthetic_drift({});
  auto fraction = [&](bool drift, double c) {
    McmOptions opt;
    opt.drift = drift;
    opt.c = c;
    opt.cumulative_from = opt.cumulative_to = opt.snapshot;
    const auto s = summarize_mcm(chart, islands, grid, opt, run_mcm(pr, grid, opt), 10.0 / 70);
    return s;
  };
  const auto cm = fraction(false, 0), diff = fraction(false, 1), d1 = fraction(true, 1),
             d20 = fraction(true, 20);
  const double area = d1.bulk_area_fraction;
  EXPECT_GT(d1.bulk_inside_fraction, 2.0 * area);
  EXPECT_LT(cm.bulk_inside_fraction, 1.3 * area);
  EXPECT_LT(diff.bulk_inside_fraction, 1.3 * area);
  EXPECT_LT(d20.bulk_inside_fraction, 0.7 * d1.bulk_inside_fraction);
  EXPECT_GT(d1.peclet, 50);
  EXPECT_LT(d20.peclet, 1);
  EXPECT_NEAR(d1.peclet / d20.peclet, 400, 1e-9);  // Pe ~ 1/c^2

  // Without drift or diffusion the tracers keep the CM's invariant distribution: the share of the
  // bulk's tracers inside the islands is their area share, at the start and at N = 30, to 4
  // binomial standard deviations at 20,000 tracers (0.011). Seeded on the bulk part alone, they
  // spread into the layer and the share rose by ~14% (0.150 -> 0.170 for other islands).
  McmOptions still;
  still.drift = false;
  still.c = 0;
  still.tracers = 20000;
  still.cumulative_from = still.cumulative_to = still.snapshot;
  const auto s = summarize_mcm(chart, islands, grid, still, run_mcm(pr, grid, still), 10.0 / 70);
  const double sd = std::sqrt(area * (1 - area) / static_cast<double>(s.bulk_tracers));
  EXPECT_NEAR(s.initial_bulk_inside_fraction, area, 4 * sd);
  EXPECT_NEAR(s.bulk_inside_fraction, area, 4 * sd);
  EXPECT_NEAR(s.bulk_inside_fraction, s.initial_bulk_inside_fraction, 4 * sd);
}

}  // namespace

namespace {
using namespace tumble::cm;

// Pe with neither drift nor diffusion is 0/0: "none", never "nan"; drift alone is infinite;
// diffusion alone is 0 (docs/cm.md, Sec. 5).
TEST(Mcm, PecletWithoutTransportIsNoneNotNan) {
  const DriftGrid grid = synthetic_drift({});
  McmOptions opt;
  opt.drift = false;
  opt.c = 0;
  const double none = mcm_peclet(grid, opt, 0.143);
  EXPECT_TRUE(std::isnan(none));
  EXPECT_EQ(peclet_text(none), "none");
  opt.drift = true;
  const double drift_only = mcm_peclet(grid, opt, 0.143);
  EXPECT_TRUE(std::isinf(drift_only));
  EXPECT_EQ(peclet_text(drift_only), "infinite");
  opt.drift = false;
  opt.c = 1;
  EXPECT_EQ(mcm_peclet(grid, opt, 0.143), 0.0);
  EXPECT_EQ(peclet_text(0.0), "0");
  EXPECT_EQ(peclet_text(106.1234), "106.1");
}

// The cumulative records are reserved whole, and the memory estimate covers what a run keeps.
TEST(Mcm, MemoryEstimateCoversTheRecordedPositions) {
  const Protocol pr = Protocol::degrees(57, 57);
  McmOptions opt;
  opt.tracers = 300;
  opt.snapshot = 4;
  opt.cumulative_from = 1;
  opt.cumulative_to = 7;
  opt.cumulative_stride = 2;  // iterations 1, 3, 5, 7
  ASSERT_EQ(mcm_cumulative_records(opt), 4);
  const auto res = run_mcm(pr, synthetic_drift({}), opt);
  ASSERT_EQ(res.cumulative.size(), 4u * 300u);
  EXPECT_EQ(res.cumulative.capacity(), res.cumulative.size());  // no growth slack
  const double kept = sizeof(Vec3) * (res.initial.capacity() + res.snapshot.capacity() +
                                      res.cumulative.capacity() + opt.tracers) +
                      sizeof(int) * res.cumulative_iteration.capacity();
  EXPECT_GE(mcm_memory_bytes(opt), kept);
  EXPECT_LE(mcm_memory_bytes(opt), 3 * kept);  // an estimate, not a blanket refusal
}

}  // namespace
