// The per-case fields: c_L and Δψ on the Lambert grid from hand-placed particles with known
// answers, and the collector's kill-safety (a collector restored from its state file mid-run
// ends with exactly the fields of one that ran through).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>

#include "analysis/concentration.hpp"
#include "analysis/displacement.hpp"
#include "campaign/field_collector.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::campaign {
namespace {
namespace fs = std::filesystem;
using analysis::LambertGrid;
constexpr double R = 0.02;

Particles place(const std::vector<Vec3>& x, const std::vector<int>& species, double radius) {
  Particles p;
  p.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    p.x[i] = x[i];
    p.species[i] = species[i];
    p.radius[i] = radius * (species[i] == 1 ? 2 : 1);
    p.id[i] = static_cast<std::int64_t>(i);
  }
  return p;
}

Vec3 direction(double polar_from_south, double azimuth) {
  return {std::sin(polar_from_south) * std::cos(azimuth), -std::cos(polar_from_south),
          std::sin(polar_from_south) * std::sin(azimuth)};
}

TEST(Concentration, BinsTheLowerShellByLambertCell) {
  const LambertGrid g(4);
  const Vec3 u = direction(0.7, 0.3);
  const int cell = g.cell_of_direction(u.x, u.y, u.z);
  ASSERT_GE(cell, 0);
  // Two large and one small in the shell on `u`; one too deep, one on the upper hemisphere.
  const Particles p = place(
      {0.95 * R * u, 0.97 * R * u, 0.93 * R * u, 0.8 * R * u, 0.95 * R * Vec3{u.x, -u.y, u.z}},
      {1, 1, 0, 1, 1}, 0.001);
  const analysis::ShellBins b = analysis::bin_shell(p, Mat3::identity(), g, R, 0.9);
  const double vs = 4.0 / 3.0 * kPi * 1e-9, vl = 8 * vs;
  EXPECT_DOUBLE_EQ(b.large[cell], 2 * vl);
  EXPECT_DOUBLE_EQ(b.small[cell], vs);
  EXPECT_DOUBLE_EQ(std::accumulate(b.large.begin(), b.large.end(), 0.0), 2 * vl);
  analysis::ConcentrationMap m(g.cells());
  m.add(b);
  m.add(analysis::bin_shell(place({0.95 * R * u}, {0}, 0.001), Mat3::identity(), g, R, 0.9));
  EXPECT_DOUBLE_EQ(m.c_large()[cell], 2 * vl / (2 * vl + 2 * vs));  // ratio of summed volumes
  EXPECT_DOUBLE_EQ(m.c_small()[cell], 2 * vs / (2 * vl + 2 * vs));
  EXPECT_TRUE(std::isnan(m.c_large()[(cell + 1) % g.cells()]));  // never visited
  EXPECT_DOUBLE_EQ(m.solid_fraction(1.0)[cell], (2 * vl + 2 * vs) / 2);
  // The frame: rotating the analysis frame by pi about z moves the lower shell to the upper one.
  const analysis::ShellBins flipped =
      analysis::bin_shell(p, Mat3::rotation({0, 0, 1}, kPi), g, R, 0.9);
  EXPECT_DOUBLE_EQ(std::accumulate(flipped.large.begin(), flipped.large.end(), 0.0), vl);
}

TEST(Concentration, IntensityOfSegregationIsZeroMixedAndOneSegregated) {
  analysis::ShellBins mixed{{1, 2, 3}, {3, 6, 9}}, segregated{{4, 0, 0}, {0, 5, 7}};
  EXPECT_NEAR(analysis::intensity_of_segregation(mixed), 0, 1e-15);
  EXPECT_NEAR(analysis::intensity_of_segregation(segregated), 1, 1e-15);
  EXPECT_TRUE(std::isnan(analysis::intensity_of_segregation({{0, 0}, {1, 1}})));
}

TEST(Displacement, RigidRotationGivesTheRotationGeometry) {
  // About the vertical axis by alpha, a direction at polar angle t from the south pole moves by
  // psi with cos psi = cos^2 t + sin^2 t cos alpha.
  const LambertGrid g(6);
  const double alpha = 0.4;
  std::vector<Vec3> x;
  std::vector<int> sp;
  for (int k = 0; k < 40; ++k) {
    x.push_back(0.9 * R * direction(0.1 + 0.035 * k, 0.37 * k));
    sp.push_back(k % 3 == 0);
  }
  x.push_back(0.5 * R * direction(0.5, 0.5));  // inside r < 0.8 R: not counted
  sp.push_back(0);
  const Particles p0 = place(x, sp, 0.0005);
  Particles p1 = p0;
  const Mat3 rot = Mat3::rotation({0, 1, 0}, alpha);
  for (auto& xi : p1.x) xi = rot * xi;
  std::vector<std::uint32_t> slot(p0.size());
  std::iota(slot.begin(), slot.end(), 0u);
  const auto start = analysis::shell_directions(p0, slot, Mat3::identity(), g, R, 0.8);
  const auto end = analysis::shell_directions(p1, slot, Mat3::identity(), g, R, 0.8);
  std::vector<std::int32_t> species(sp.begin(), sp.end());
  analysis::DisplacementMap d(g.cells());
  d.add_interval(start, end.u, species);
  std::vector<double> sum[2], n[2];
  for (int s = 0; s < 2; ++s) sum[s].assign(g.cells(), 0.0), n[s].assign(g.cells(), 0.0);
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    const double t = 0.1 + 0.035 * k;
    const double want =
        std::acos(std::cos(t) * std::cos(t) + std::sin(t) * std::sin(t) * std::cos(alpha));
    EXPECT_NEAR(analysis::angle_between(start.u[k], end.u[k]), want, 1e-12);
    sum[sp[k]][start.cell[k]] += want;
    n[sp[k]][start.cell[k]] += 1;
  }
  EXPECT_EQ(start.cell.back(), -1);  // the deep particle
  const auto large = d.mean_large(), small = d.mean_small();
  for (int c = 0; c < g.cells(); ++c) {
    EXPECT_EQ(d.count_large[c], n[1][c]);
    EXPECT_EQ(d.count_small[c], n[0][c]);
    for (int s = 0; s < 2; ++s) {
      const double got = s ? large[c] : small[c];
      if (n[s][c] > 0) {
        EXPECT_NEAR(got, sum[s][c] / n[s][c], 1e-12);
      } else {
        EXPECT_TRUE(std::isnan(got));
      }
    }
  }
}

// A random bed that moves and is reshuffled in memory between samples, as the engine does.
struct FakeRun {
  std::vector<Particles> frames;
  FakeRun(int samples, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Particles p;
    p.resize(600);
    for (std::size_t i = 0; i < p.size(); ++i) {
      Vec3 v;
      do v = {u(rng), -std::fabs(u(rng)), u(rng)};
      while (norm(v) > 0.99 || norm(v) < 0.5);
      p.x[i] = R * v;
      p.species[i] = i % 4 == 0;
      p.radius[i] = p.species[i] ? 0.002 : 0.001;
      p.id[i] = 1000 + static_cast<std::int64_t>(i) * 7;  // ids need not be 0..N-1
    }
    for (int j = 0; j < samples; ++j) {
      frames.push_back(p);
      const Mat3 rot = Mat3::rotation({0.6, 0, 0.8}, 0.05);
      for (auto& x : p.x) x = rot * x + Vec3{u(rng), u(rng), u(rng)} * (1e-4 * R);
      std::vector<std::uint32_t> perm(p.size());
      std::iota(perm.begin(), perm.end(), 0u);
      std::shuffle(perm.begin(), perm.end(), rng);
      p.permute(perm);
    }
  }
};

CollectPlan test_plan() {
  CollectPlan plan;
  plan.spec.samples_per_iteration = 4;
  plan.spec.displacement_periods = {0.75};  // lag of 3 samples
  plan.spec.grid = 6;
  plan.radius = R;
  plan.steps_per_iteration = 400;
  plan.total_steps = 1200;
  plan.last_sample = 12;
  plan.window_first = 3;
  plan.window_last = 12;
  plan.lags = {3};
  return plan;
}

// The same plan with Δψ over 3, 1 and 5 samples (0.75, 0.25, 1.25 periods).
CollectPlan three_lag_plan() {
  CollectPlan plan = test_plan();
  plan.spec.displacement_periods = {0.75, 0.25, 1.25};
  plan.lags = {3, 1, 5};
  return plan;
}

std::vector<double> read(const std::string& f, const std::string& name) {
  return io::H5File(f, io::H5File::Mode::Read).read_double(name);
}

TEST(FieldCollector, ResumedFromItsStateFileMatchesAnUninterruptedRunBitwise) {
  const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/collector";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const CollectPlan plan = test_plan();
  const FakeRun run(13, 5);
  auto drive = [&](FieldCollector& c, int from, int to) {
    for (int j = from; j < to; ++j) c.sample(run.frames[j], j, 0.01 * j, j / 4.0, Mat3::identity());
  };
  FieldCollector through(plan, dir + "/a.h5");
  drive(through, 0, 13);
  EXPECT_TRUE(through.finished());
  through.write_fields(dir + "/through.h5", {});

  for (int kill_at : {1, 4, 7, 11}) {
    FieldCollector before(plan, dir + "/b.h5");
    drive(before, 0, kill_at);
    FieldCollector after(plan, dir + "/b.h5");  // a new process after the kill
    ASSERT_TRUE(after.load());
    EXPECT_EQ(after.next_sample(), kill_at);
    drive(after, kill_at, 13);
    after.write_fields(dir + "/resumed.h5", {});
    for (const auto& name : field_names(plan.spec)) {
      const auto a = read(dir + "/through.h5", name), b = read(dir + "/resumed.h5", name);
      ASSERT_EQ(a.size(), b.size()) << name;
      for (std::size_t i = 0; i < a.size(); ++i)
        EXPECT_TRUE(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))
            << name << "[" << i << "] kill at " << kill_at;
    }
  }
  // The window held 10 samples and 7 displacement intervals (j - 3 >= 3, j <= 12).
  EXPECT_EQ(through.concentration().samples, 10);
  EXPECT_EQ(through.displacement().intervals, 7);
  EXPECT_EQ(through.series().time.size(), 13u);
}

// Several lags share one ring of start directions: each lag's map must be what a collector with
// only that lag gives, bit for bit, and a kill at any sample must not change any of them.
TEST(FieldCollector, EachLagOfSeveralEqualsItsOwnSingleLagCollector) {
  const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/collector_lags";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const FakeRun run(13, 9);
  auto drive = [&](FieldCollector& c, int from, int to) {
    for (int j = from; j < to; ++j) c.sample(run.frames[j], j, 0.01 * j, j / 4.0, Mat3::identity());
  };
  const CollectPlan all = three_lag_plan();
  FieldCollector through(all, dir + "/all.h5");
  drive(through, 0, 13);
  through.write_fields(dir + "/all_fields.h5", {});
  const std::vector<std::string> names = field_names(all.spec);
  ASSERT_EQ(names.size(), 3u + 6u + 3u);  // c_L c_S phi, 3 x (large, small), 3 series
  EXPECT_NE(std::find(names.begin(), names.end(), "displacement_k1.25/dpsi_small"), names.end());
  // Intervals per lag in the window [3, 12]: 12 - 3 - m + 1.
  const std::int64_t expected_intervals[3] = {7, 9, 5};
  for (std::size_t k = 0; k < 3; ++k) {
    CollectPlan one = test_plan();
    one.spec.displacement_periods = {all.spec.displacement_periods[k]};
    one.lags = {all.lags[k]};
    FieldCollector alone(one, dir + "/one.h5");
    drive(alone, 0, 13);
    EXPECT_EQ(through.displacement(k).intervals, expected_intervals[k]);
    EXPECT_EQ(alone.displacement(0).intervals, expected_intervals[k]);
    using D = analysis::DisplacementMap;
    for (const auto v : {&D::sum_large, &D::sum_small, &D::count_large, &D::count_small})
      EXPECT_EQ(through.displacement(k).*v, alone.displacement(0).*v) << "lag " << k;
  }
  // The maps of different lags differ (the bed keeps turning), so a mix-up would be seen.
  EXPECT_NE(through.displacement(0).sum_small, through.displacement(1).sum_small);
  for (int kill_at : {2, 6, 10}) {
    FieldCollector before(all, dir + "/b.h5");
    drive(before, 0, kill_at);
    FieldCollector after(all, dir + "/b.h5");
    ASSERT_TRUE(after.load());
    drive(after, kill_at, 13);
    after.write_fields(dir + "/resumed.h5", {});
    for (const auto& name : names) {
      const auto a = read(dir + "/all_fields.h5", name), b = read(dir + "/resumed.h5", name);
      ASSERT_EQ(a.size(), b.size()) << name;
      for (std::size_t i = 0; i < a.size(); ++i)
        EXPECT_TRUE(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))
            << name << "[" << i << "] kill at " << kill_at;
    }
  }
  // Each lag's group in the fields file says its lag.
  io::H5File f(dir + "/all_fields.h5", io::H5File::Mode::Read);
  EXPECT_EQ(f.attr_double("displacement", "periods"), 0.75);
  EXPECT_EQ(f.attr_double("displacement_k0.25", "periods"), 0.25);
  EXPECT_EQ(f.attr_int64("displacement_k1.25", "intervals"), 5);
}

TEST(FieldCollector, StateOfAnotherPlanIsNotLoaded) {
  const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/collector_plan";
  fs::remove_all(dir);
  fs::create_directories(dir);
  CollectPlan plan = test_plan();
  FieldCollector a(plan, dir + "/s.h5");
  a.sample(FakeRun(1, 1).frames[0], 0, 0, 0, Mat3::identity());
  plan.spec.grid = 8;
  FieldCollector b(plan, dir + "/s.h5");
  EXPECT_FALSE(b.load());
}

}  // namespace
}  // namespace tumble::campaign
