// Ensemble statistics: Welford equals the two-pass formulas, Chan's merge of partial results
// equals one pass over everything, NaN components are missing per case, Student t quantiles
// match closed forms, and ensemble files round-trip through PetscViewerHDF5.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "base/error.hpp"
#include "base/student_t.hpp"
#include "campaign/ensemble.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::campaign {
namespace {
namespace fs = std::filesystem;
const double kNaN = std::nan("");

std::vector<std::vector<double>> random_cases(int cases, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.3, 0.05);  // c_L-like: small spread around a large mean
  std::vector<std::vector<double>> x(cases, std::vector<double>(n));
  for (auto& c : x)
    for (auto& v : c) v = g(rng);
  return x;
}

void expect_close(double a, double b, double rel, const char* what, int i) {
  EXPECT_LE(std::fabs(a - b), rel * std::max(1.0, std::fabs(b))) << what << "[" << i << "]";
}

TEST(FieldStats, WelfordEqualsTwoPass) {
  const auto x = random_cases(40, 25, 1);
  FieldStats s(25);
  for (const auto& c : x) s.add(c);
  const auto mean = s.mean(), var = s.variance(), count = s.count();
  for (int i = 0; i < 25; ++i) {
    double m = 0, v = 0;
    for (const auto& c : x) m += c[i];
    m /= x.size();
    for (const auto& c : x) v += (c[i] - m) * (c[i] - m);
    v /= x.size() - 1;
    EXPECT_EQ(count[i], 40);
    expect_close(mean[i], m, 1e-14, "mean", i);
    expect_close(var[i], v, 1e-12, "variance", i);
  }
}

TEST(FieldStats, ChanMergeOfPartsEqualsOnePass) {
  const auto x = random_cases(31, 12, 2);
  FieldStats all(12), a(12), b(12), c(12), empty(12);
  for (std::size_t k = 0; k < x.size(); ++k) {
    all.add(x[k]);
    (k < 5 ? a : k < 20 ? b : c).add(x[k]);
  }
  FieldStats merged(12);
  merged.merge(empty);  // merging nothing changes nothing
  merged.merge(a);      // into an empty accumulator: an exact copy
  EXPECT_EQ(merged.mean(), a.mean());
  merged.merge(b);
  merged.merge(c);
  const auto m1 = all.mean(), m2 = merged.mean(), v1 = all.m2(), v2 = merged.m2();
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ(merged.count()[i], 31);
    expect_close(m2[i], m1[i], 1e-14, "mean", i);
    expect_close(v2[i], v1[i], 1e-12, "m2", i);
  }
}

TEST(FieldStats, NanComponentsAreMissingForThatCaseOnly) {
  FieldStats s(3);
  s.add({1.0, kNaN, 5.0});
  s.add({3.0, 7.0, kNaN});
  s.add({5.0, kNaN, kNaN});
  EXPECT_EQ(s.count(), (std::vector<double>{3, 1, 1}));
  EXPECT_EQ(s.mean(), (std::vector<double>{3, 7, 5}));
  EXPECT_EQ(s.variance()[0], 4.0);
  EXPECT_TRUE(std::isnan(s.variance()[1]));  // one value: no variance
  EXPECT_TRUE(std::isnan(s.ci95()[2]));
  // Half-width with three values: t(0.975, 2) sqrt(4 / 3), t(0.975, 2) = 0.95 / sqrt(0.04875).
  EXPECT_NEAR(s.ci95()[0], 0.95 / std::sqrt(0.04875) * std::sqrt(4.0 / 3.0), 1e-12);
}

TEST(StudentT, QuantilesMatchClosedFormsAndTables) {
  EXPECT_NEAR(student_t_quantile(0.975, 1), std::tan(0.475 * M_PI), 1e-11);  // Cauchy
  EXPECT_NEAR(student_t_quantile(0.975, 2), 0.95 / std::sqrt(2 * 0.975 * 0.025), 1e-12);
  // Roots of the CDF to 40 digits (mpmath); scipy 1.10's t.ppf(0.975, 10) is 2e-11 lower.
  EXPECT_NEAR(student_t_quantile(0.975, 10), 2.2281388519862747, 1e-13);
  EXPECT_NEAR(student_t_quantile(0.975, 30), 2.0422724563012383, 1e-13);
  EXPECT_NEAR(student_t_quantile(0.975, 1e7), 1.959963984540054, 1e-6);  // the normal limit
  EXPECT_NEAR(student_t_quantile(0.025, 5), -student_t_quantile(0.975, 5), 1e-14);
  EXPECT_NEAR(student_t_cdf(student_t_quantile(0.9, 3.5), 3.5), 0.9, 1e-14);
}

TEST(Ensemble, FileRoundTripAndDisjointMerge) {
  const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/ensemble";
  fs::remove_all(dir);
  fs::create_directories(dir);
  Ensemble e;
  e.notes["campaign"] = "t";
  PointStats& p = e.points["p1"];
  p.id = "p1";
  p.params_text = "theta_z=57;R_rho=3";
  p.params_canonical = "theta_z=57;R_rho=3;time.dt=2e-05;fill.start=mixed";
  p.tier = "standard";
  p.frame = "lab";
  p.grid_n = 2;
  p.members = {"c1", "c2"};
  p.failed = {"c3: [run, attempt 2] particle 7 left the tumbler"};
  p.series_time = {0, 1, 2};
  p.series_iteration = {0, 0.5, 1};
  FieldStats f(4), s(3);
  f.add({0.1, 0.2, kNaN, 0.4});
  f.add({0.3, 0.1, kNaN, 0.5});
  s.add({1, 2, 3});
  p.fields.emplace("concentration/c_L", std::move(f));
  p.fields.emplace("series/mixing_index", std::move(s));
  PointStats& p2 = e.points["p2"];
  p2.id = "p2";
  p2.params_canonical = "theta_z=90";
  p2.members = {"c4"};
  p2.series_time = {0, 2};
  p2.series_iteration = {0, 1};
  FieldStats s2(2);
  s2.add({5, 6});
  p2.fields.emplace("series/mixing_index", std::move(s2));
  e.write(dir + "/e.h5");

  io::H5File h(dir + "/e.h5", io::H5File::Mode::Read);
  EXPECT_EQ(h.attr_string("/", "kind"), "tumble ensemble");
  EXPECT_EQ(h.attr_int64("/", "n_failed"), 1);
  EXPECT_EQ(h.attr_double("/points/p1", "theta_z"), 57);
  EXPECT_EQ(h.attr_string("/points/p1", "fill.start"), "mixed");
  EXPECT_EQ(h.attr_string("/points/p1", "members"), "c1,c2");
  EXPECT_EQ(h.attr_int64("/points/p1", "row"), 0);
  EXPECT_EQ(h.shape("/fields/concentration/c_L/mean"), (std::vector<hsize_t>{2, 4}));
  EXPECT_DOUBLE_EQ(h.read_double("/fields/concentration/c_L/variance")[0], 0.02);
  EXPECT_TRUE(std::isnan(h.read_double("/fields/concentration/c_L/mean")[2]));  // count 0

  const Ensemble back = Ensemble::read(dir + "/e.h5");
  const PointStats& q = back.points.at("p1");
  EXPECT_EQ(q.members, p.members);
  EXPECT_EQ(q.failed, p.failed);
  EXPECT_EQ(q.series_iteration, p.series_iteration);
  EXPECT_EQ(q.fields.at("concentration/c_L").m2(), p.fields.at("concentration/c_L").m2());
  EXPECT_EQ(q.fields.at("concentration/c_L").count(), (std::vector<double>{2, 2, 0, 2}));

  const PointStats& q2 = back.points.at("p2");
  EXPECT_EQ(q2.series_time, p2.series_time);  // unpadded again
  EXPECT_EQ(q2.fields.count("concentration/c_L"), 0u);
  EXPECT_EQ(q2.fields.at("series/mixing_index").mean(), (std::vector<double>{5, 6}));
  EXPECT_EQ(h.shape("/fields/series/mixing_index/mean"), (std::vector<hsize_t>{2, 3}));

  Ensemble twice = Ensemble::read(dir + "/e.h5");
  EXPECT_THROW(twice.merge(back), InputError);  // c1 and c2 would be counted twice
}

}  // namespace
}  // namespace tumble::campaign
