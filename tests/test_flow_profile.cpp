// The flowing-layer observables on constructed beds with known answers: particles stacked under a
// plane tilted by a known angle about the x axis, the top row sliding downhill with a known
// profile, the rows below at rest; and a biaxial run's series, measured about each segment's axis.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "analysis/flow_profile.hpp"
#include "analysis/radial_segregation.hpp"
#include "base/vec3.hpp"
#include "bed_fixture.hpp"
#include "h5/hdf5_file.hpp"
#include "io/series_io.hpp"
#include "run/realization.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {
// A lattice of spheres (radius r) below the plane y = tan(angle) * h, h = (e_up x e_axis) . x,
// in the slab |x| < R/2; the top row moves downhill at speed u(h).
Particles tilted_bed(double angle_deg, double R, double r, double (*u)(double)) {
  Particles p;
  const double s = std::tan(angle_deg * kPi / 180);
  const Vec3 eh{0, 0, -1};  // e_up x e_x = -z for rotation about x
  Vec3 t = (1 / std::sqrt(1 + s * s)) * (eh + s * Vec3{0, 1, 0});
  if (s > 0) t = -t;  // downhill
  for (double ax = -0.45 * R; ax <= 0.45 * R; ax += 2 * r)
    for (double h = -0.9 * R; h <= 0.9 * R; h += 2 * r)
      for (int row = 0; row < 4; ++row) {
        const double top = s * h;
        const double y = top - r - 2 * r * row;
        const std::size_t i = p.size();
        p.resize(i + 1);
        p.x[i] = {ax, y, -h};  // z = -h
        p.radius[i] = r;
        p.v[i] = row == 0 ? u(h) * t : Vec3{};
        p.id[i] = static_cast<std::int64_t>(i);
      }
  return p;
}
double uniform(double) { return 0.2; }
double parabolic(double h) { return 0.3 * (1 - h * h / (0.8 * 0.8)); }
}  // namespace

TEST(FlowProfile, FindsTheReposeAngleOfATiltedSurface) {
  for (double angle : {20.0, 27.0, 35.0}) {
    const Particles p = tilted_bed(angle, 1.0, 0.01, uniform);
    analysis::FlowFrame fr;
    fr.radius = 1;
    fr.bin = 0.04;
    fr.depth = 0.015;
    const analysis::FlowProfile f = analysis::flow_profile(p, p.size(), fr);
    EXPECT_NEAR(f.repose_deg, angle, 0.3) << angle;
    EXPECT_NEAR(f.surface_speed, 0.2, 1e-9) << angle;  // only the top row counts
  }
}

TEST(FlowProfile, SurfaceVelocityProfileFollowsTheLayer) {
  const Particles p = tilted_bed(27, 1.0, 0.01, parabolic);
  analysis::FlowFrame fr;
  fr.radius = 1;
  fr.bin = 0.1;
  fr.depth = 0.015;
  const analysis::FlowProfile f = analysis::flow_profile(p, p.size(), fr);
  int checked = 0;
  for (std::size_t b = 0; b < f.h.size(); ++b) {
    if (std::abs(f.h[b]) > 0.7 || std::isnan(f.speed[b])) continue;
    // The bin mean of a parabola over the bin's particles: within the variation across a bin.
    EXPECT_NEAR(f.speed[b], parabolic(f.h[b]), 0.3 * 2 * 0.05 * 0.8 / 0.64 + 1e-3) << f.h[b];
    ++checked;
  }
  EXPECT_GE(checked, 12);
}

TEST(FlowProfile, NoSurfaceNoAngle) {
  Particles empty;
  analysis::FlowFrame fr;
  const analysis::FlowProfile f = analysis::flow_profile(empty, 0, fr);
  EXPECT_TRUE(std::isnan(f.repose_deg));
  EXPECT_TRUE(std::isnan(f.surface_speed));
}

// The profile is kept per sample in results and checkpoints (series/surface_profile, samples x
// bins) and read back as written, NaN bins included; a profile that does not have a row per sample
// (a run resumed from a checkpoint written before profiles were kept) is not written at all.
TEST(FlowProfile, SeriesKeepsTheProfilePerSample) {
  const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/flow_profile";
  std::filesystem::create_directories(dir);
  analysis::Series s;
  for (int k = 0; k < 2; ++k) {
    s.append(0.1 * k, 0, {}, 0);
    s.repose_angle.push_back(25 + k);
    s.surface_speed.push_back(0.01 * k);
  }
  s.profile_h = {-0.5, 0, 0.5};
  s.surface_profile = {0.1, 0.2, std::nan(""), 0.3, 0.4, 0.5};
  {
    io::H5File f(dir + "/series.h5", io::H5File::Mode::Truncate);
    io::write_series(f, s);
  }
  analysis::Series back;
  {
    io::H5File f(dir + "/series.h5", io::H5File::Mode::Read);
    io::read_series(f, back);
  }
  EXPECT_EQ(back.profile_h, s.profile_h);
  ASSERT_EQ(back.surface_profile.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    if (std::isnan(s.surface_profile[i]))
      EXPECT_TRUE(std::isnan(back.surface_profile[i]));
    else
      EXPECT_EQ(back.surface_profile[i], s.surface_profile[i]) << i;
  }
  s.surface_profile.resize(3);  // one row for two samples
  {
    io::H5File f(dir + "/short.h5", io::H5File::Mode::Truncate);
    io::write_series(f, s);
  }
  io::H5File f(dir + "/short.h5", io::H5File::Mode::Read);
  EXPECT_FALSE(f.exists("series/surface_profile"));
  EXPECT_TRUE(f.exists("series/surface_speed"));
}

// A biaxial run measures the flowing layer about the axis it turns about: the bed tilted 27°
// about z, back, then 27° about x and 7.5° on (θz = 0, θx = 10°, three quarters of the period,
// at 30 rpm to keep it short), reads a
// steep surface at the end of each tilt and a low one after the tilt back. Measured about one
// fixed axis, one of the two tilts would read flat. The segment and the turn into it are kept
// per sample, through a restart too.
TEST(FlowProfile, BiaxialRunMeasuresTheLayerAboutEachSegmentsAxis) {
  const std::string base = test_dir("biaxial_layer");
  std::filesystem::remove_all(base);
  auto scene = [&](const std::string& out) {
    return tiny_scene({"protocol.mode=biaxial", "protocol.repose=27", "protocol.theta_z=0",
                       "protocol.theta_x=10", "protocol.rpm=30", "protocol.iterations=0.75",
                       "output.analysis_interval=0.005", "output.checkpoint_interval=0.2",
                       "scene.output_dir=" + base + "/" + out});
  };
  run_realization(scene("full"), {});
  RunOptions first;
  first.max_steps = 10000;
  run_realization(scene("split"), first);
  RunOptions second;
  second.resume = true;
  run_realization(scene("split"), second);
  analysis::Series s, split;
  {
    io::H5File f(base + "/full/results.h5", io::H5File::Mode::Read);
    io::read_series(f, s);
    io::H5File g(base + "/split/results.h5", io::H5File::Mode::Read);
    io::read_series(g, split);
  }
  ASSERT_EQ(s.segment.size(), s.time.size());
  ASSERT_EQ(s.segment_turn.size(), s.time.size());
  ASSERT_EQ(s.repose_angle.size(), s.time.size());
  EXPECT_EQ(split.segment, s.segment);
  EXPECT_EQ(split.segment_turn, s.segment_turn);
  EXPECT_EQ(split.repose_angle.size(), s.repose_angle.size());
  // The last sample of each segment: its turn near 27° (a sample every 0.9°), and its slope.
  double last_slope[4] = {NAN, NAN, NAN, NAN};
  for (std::size_t k = 0; k < s.time.size(); ++k) {
    const int seg = static_cast<int>(s.segment[k]);
    ASSERT_GE(seg, 0);
    ASSERT_LE(seg, 3);
    EXPECT_GE(s.segment_turn[k], 0.0);
    EXPECT_LE(s.segment_turn[k], 27.0 + 1e-9);
    if (s.segment_turn[k] > 25) last_slope[seg] = s.repose_angle[k];
  }
  EXPECT_GT(last_slope[0], 15.0) << "the tilt about z";
  EXPECT_LT(last_slope[1], 10.0) << "after the tilt back about z";
  EXPECT_GT(last_slope[2], 15.0) << "the tilt about x";
}
