// The drift grid: the synthetic field's documented shape and the HDF5 format.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cm/drift_grid.hpp"
#include "cm/flow_field.hpp"
#include "h5/hdf5_file.hpp"

namespace {
using namespace tumble::cm;

TEST(DriftGrid, SyntheticFieldPointsPolewardAndReversesNearPoles) {
  const SyntheticDrift sd;
  const DriftGrid g = synthetic_drift(sd);
  ASSERT_EQ(g.n, 30);
  const double v_max = sd.drift_per_pass / (kPi * sd.eps);
  double largest = 0;
  for (double z = -0.95; z <= 0.95; z += 0.1) {
    const double v = g.v(0.0, z);
    largest = std::max(largest, std::abs(v));
    EXPECT_NEAR(v, -g.v(0.0, -z), 1e-15);  // mirror symmetric about the equator
    if (std::abs(z) < 0.8) {
      EXPECT_GT(v * z, 0) << "towards the pole at z = " << z;
    }
    if (std::abs(z) > 0.9) {
      EXPECT_LT(v * z, 0) << "away from the pole at z = " << z;
    }
    if (std::abs(z) < 0.85) {
      EXPECT_EQ(g.v(0.3, z), v);  // uniform along the stream
    }
  }
  EXPECT_LE(largest, v_max);
  EXPECT_GT(largest, 0.9 * v_max);
  EXPECT_EQ(g.v(0.9, 0.9), 0.0);  // outside the layer's footprint
  EXPECT_NEAR(g.mean_sigma(), sd.sigma, 1e-12);
  // Largest displacement in one transit (pi eps) is the documented drift per pass.
  EXPECT_NEAR(v_max * kPi * sd.eps, 2.0 / 70.0, 1e-15);
}

// Two measured grids merged = one grid of all their samples (the statistics add), through the
// HDF5 file; a synthetic grid (no statistics) or another n is refused.
TEST(DriftGrid, MergedGridsEqualTheGridOfAllTheirSamples) {
  const int n = 4;
  const std::size_t cells = n * n;
  std::vector<double> c1(cells, 0), s1(cells, 0), q1(cells, 0), c2 = c1, s2 = c1, q2 = c1;
  std::vector<double> c12 = c1, s12 = c1, q12 = c1;
  auto add = [](std::vector<double>& c, std::vector<double>& s, std::vector<double>& q,
                std::size_t cell, double v) { c[cell] += 1, s[cell] += v, q[cell] += v * v; };
  for (std::size_t k = 0; k < 40; ++k) {
    const std::size_t cell = (k * 7) % 11;  // cells 0..10 hit, 11..15 never
    const double v = 0.01 * std::sin(1.0 + k);
    if (k % 3 == 0)
      add(c1, s1, q1, cell, v);
    else
      add(c2, s2, q2, cell, v);
    add(c12, s12, q12, cell, v);
  }
  const auto dir = std::filesystem::temp_directory_path();
  const std::string path = (dir / "tumble_test_drift_stats.h5").string();
  write_drift_grid(path, drift_grid_from_statistics(n, {c1, s1, q1}, "first"));
  const DriftGrid a = read_drift_grid(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(a.has_statistics());
  EXPECT_EQ(a.statistics.count, c1);
  const DriftGrid b = drift_grid_from_statistics(n, {c2, s2, q2}, "second");
  const DriftGrid merged = merge_drift_grids({a, b}, "both");
  const DriftGrid all = drift_grid_from_statistics(n, {c12, s12, q12}, "all");
  for (std::size_t c = 0; c < cells; ++c) {
    EXPECT_NEAR(merged.v_ax[c], all.v_ax[c], 1e-16) << c;
    EXPECT_NEAR(merged.sigma_ax[c], all.sigma_ax[c], 1e-15) << c;
    EXPECT_EQ(merged.statistics.count[c], c12[c]);
  }
  // A cell with fewer than 2 samples: no mean, the mean sigma of the sampled cells.
  EXPECT_EQ(all.v_ax[15], 0.0);
  double fill = 0, k = 0;
  for (std::size_t c = 0; c < cells; ++c)
    if (c12[c] >= 2) fill += all.sigma_ax[c], k += 1;
  EXPECT_NEAR(all.sigma_ax[15], fill / k, 1e-15);
  EXPECT_GT(fill, 0.0);
  try {
    (void)merge_drift_grids({a, synthetic_drift({})}, "x");
    FAIL() << "a synthetic grid has no statistics to merge";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("drift grid 'synthetic' holds no per-cell statistics"),
              std::string::npos)
        << e.what();
  }
  DriftGrid other = drift_grid_from_statistics(2, DriftStatistics::zeros(2), "o");
  EXPECT_THROW((void)merge_drift_grids({a, other}, "x"), std::runtime_error);
}

TEST(DriftGrid, Hdf5RoundTripAndShapeCheck) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string path = (dir / "tumble_test_drift.h5").string();
  DriftGrid g = synthetic_drift({});
  g.v_ax[17] = 0.123;  // not symmetric: the layout must survive as is
  write_drift_grid(path, g);
  const DriftGrid r = read_drift_grid(path);
  EXPECT_EQ(r.n, g.n);
  EXPECT_EQ(r.v_ax, g.v_ax);
  EXPECT_EQ(r.sigma_ax, g.sigma_ax);
  EXPECT_EQ(r.source, "synthetic");
  {
    tumble::io::H5File f(path, tumble::io::H5File::Mode::Truncate);
    f.write("/v_ax", std::vector<double>(6, 0.0), {2, 3});
    f.write("/sigma_ax", std::vector<double>(6, 0.0), {2, 3});
  }
  EXPECT_THROW(read_drift_grid(path), std::runtime_error);
  std::filesystem::remove(path);
}

}  // namespace
