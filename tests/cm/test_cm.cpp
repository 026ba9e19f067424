// End to end: library results written to and read back from the HDF5 files of docs/cm.md.
#include <gtest/gtest.h>

#include <filesystem>

#include "cm/cm_io.hpp"
#include "h5/hdf5_file.hpp"

namespace {
using namespace tumble::cm;

TEST(CmIo, OrbitsFileRoundTripsPointsAndIslands) {
  const Protocol pr = Protocol::degrees(90, 90);
  const SectionMap map(pr, ShellChart(0.95, pr.eps));
  PeriodicSearch ps;
  ps.max_period = 2;
  ps.grid = 20;
  const auto pts = find_periodic_points(map, ps);
  IslandOptions io;
  io.iterations = 300;
  io.final_iterations = 600;
  const auto isl = find_islands(map, pts, io);
  ASSERT_EQ(isl.size(), 4u);
  const std::string path =
      (std::filesystem::temp_directory_path() / "tumble_test_orbits.h5").string();
  write_orbits(path, pr, 0.95, pts, isl);
  const auto pts2 = read_periodic_points(path);
  const auto isl2 = islands_on_shell(read_islands(path), 0.95);
  ASSERT_EQ(pts2.size(), pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(pts2[i].v, pts[i].v);
    EXPECT_EQ(pts2[i].type, pts[i].type);
    EXPECT_EQ(pts2[i].jacobian, pts[i].jacobian);
  }
  ASSERT_EQ(isl2.size(), isl.size());
  for (std::size_t k = 0; k < isl.size(); ++k) {
    EXPECT_EQ(isl2[k].boundary.vertices, isl[k].boundary.vertices);
    EXPECT_EQ(isl2[k].period, 2);
  }
  tumble::io::H5File f(path, tumble::io::H5File::Mode::Read);
  EXPECT_DOUBLE_EQ(f.attr_double("/", "theta_z_deg"), 90.0);
  std::filesystem::remove(path);
}

TEST(CmIo, PoincareFileSeparatesBulkAndLayer) {
  const Protocol pr = Protocol::degrees(57, 57);
  PoincareOptions opt;
  opt.seeds = 20;
  opt.periods = 50;
  opt.second_rotation = true;
  const auto sets = poincare_section(pr, opt);
  ASSERT_EQ(sets.size(), 2u);
  const std::string path =
      (std::filesystem::temp_directory_path() / "tumble_test_poinc.h5").string();
  write_poincare(path, pr, opt, sets);
  tumble::io::H5File f(path, tumble::io::H5File::Mode::Read);
  for (const auto& s : sets) {
    const auto n_bulk = f.shape("/" + s.name + "/bulk")[0];
    const auto n_layer = f.shape("/" + s.name + "/layer")[0];
    EXPECT_EQ(n_bulk + n_layer, 20u * 50u);
    EXPECT_GT(n_layer, 0u);
    const auto chart = f.read_double("/" + s.name + "/bulk");
    const double rim = f.attr_double("/", "chart_rim");
    for (std::size_t i = 0; i < chart.size(); i += 2)
      EXPECT_LT(std::hypot(chart[i], chart[i + 1]), rim);
  }
  std::filesystem::remove(path);
}

}  // namespace

namespace {
using namespace tumble::cm;

// The estimate a Poincaré run is refused by covers what the section holds (bulk reserved, layer
// grown by doubling) for a shell whose layer share is large (r near eps) and a usual one.
TEST(CmIo, PoincareMemoryEstimateCoversTheSection) {
  const Protocol pr = Protocol::degrees(57, 57);
  for (double r : {0.95, 0.3}) {
    PoincareOptions opt;
    opt.r = r;
    opt.seeds = 40;
    opt.periods = 300;
    double held = 0;
    for (const auto& s : poincare_section(pr, opt))
      held += s.seeds.capacity() * sizeof(Vec3) + s.bulk.capacity() * sizeof(Vec2) +
              (s.bulk_seed.capacity() + s.bulk_period.capacity()) * 8 +
              s.layer.capacity() * sizeof(Vec3) + s.layer_chart.capacity() * sizeof(Vec2) +
              (s.layer_seed.capacity() + s.layer_period.capacity()) * 8;
    EXPECT_GE(poincare_memory_bytes(pr, opt), held) << "r = " << r;
    EXPECT_LE(poincare_memory_bytes(pr, opt), 4 * held) << "r = " << r;
  }
}

}  // namespace
