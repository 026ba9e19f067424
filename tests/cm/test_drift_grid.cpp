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
