// protocol.repose = "measured" (issue 17, D7): β is the dynamic repose angle of the scene's own
// bed, measured once, kept beside the cached bed, and carried by a run's checkpoint. The same turn
// gives fidelity.bulk_still_slope = "measured": the slope where the surface starts to creep.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "bed_fixture.hpp"
#include "h5/hdf5_file.hpp"
#include "io/checkpoint.hpp"
#include "run/repose_measure.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {
// The tiny bed turning at 20 rpm (Fr ≈ 0.01: still rolling; 80° take ~5 s of wall time).
Scene turning(std::vector<std::string> o) {
  o.insert(o.begin(), {"protocol.mode=biaxial", "protocol.rpm=20"});
  return tiny_scene(o);
}
}  // namespace

TEST(ReposeMeasure, FollowsTheFrictionOfTheBed) {
  const Scene slippery = turning({"contact.friction=0.1"});
  const Scene rough = turning({"contact.friction=0.9"});
  ASSERT_TRUE(slippery.repose_pending());
  const double a = with_bed_turn_resolved(slippery, "", nullptr).repose.deg;
  const double b = with_bed_turn_resolved(rough, "", nullptr).repose.deg;
  // Measured on these beds: 22.9° and 29.9°; a measure that ignored the bed could not order them.
  EXPECT_GT(a, 10.0);
  EXPECT_LT(b, 45.0);
  EXPECT_GT(b - a, 3.0) << "friction 0.1: " << a << " deg, friction 0.9: " << b << " deg";
}

TEST(ReposeMeasure, IsCachedBesideTheBedAndFilledIntoTheSceneText) {
  const Scene s = turning({"contact.friction=0.5"});
  std::filesystem::remove(repose_cache_path(s));
  const Scene first = with_bed_turn_resolved(s, "", nullptr);
  ASSERT_TRUE(std::filesystem::exists(repose_cache_path(s)));
  EXPECT_FALSE(first.repose_pending());
  EXPECT_TRUE(first.repose.measured);
  // The cache gives the same number, bit for bit; the scene text carries it and reads back.
  const Scene again = with_bed_turn_resolved(s, "", nullptr);
  EXPECT_EQ(first.repose.deg, again.repose.deg);
  const Scene back = parse_scene(scene_to_text(first));
  EXPECT_EQ(back.repose.deg, first.repose.deg);
  EXPECT_FALSE(back.repose_pending());
  EXPECT_EQ(first.resolved.at("protocol.repose"), back.resolved.at("protocol.repose"));
  // Another speed is another measurement (its own cache file); a given number is left alone.
  EXPECT_NE(repose_cache_path(turning({"contact.friction=0.5", "protocol.rpm=25"})),
            repose_cache_path(s));
  const Scene given = with_bed_turn_resolved(turning({"protocol.repose=27"}), "", nullptr);
  EXPECT_EQ(given.repose.deg, 27.0);
  EXPECT_FALSE(given.repose.measured);
}

TEST(ReposeMeasure, AResumedRunKeepsTheTiltOfItsCheckpoint) {
  const std::string base = test_dir("repose_restart");
  std::filesystem::remove_all(base);
  auto scene = [&](const std::string& out) {
    return turning({"contact.friction=0.7", "scene.output_dir=" + base + "/" + out,
                    "output.checkpoint_interval=0.002", "protocol.iterations=0.01"});
  };
  // The cache is shared by every run of this bed (its path does not depend on the output folder):
  // start from none, as the first run of the suite does, not from the other one this test leaves.
  const std::string cache = repose_cache_path(scene("split"));
  std::filesystem::remove(cache);
  RunOptions full;
  full.max_steps = 400;
  run_realization(scene("full"), full);
  RunOptions first;
  first.max_steps = 200;
  run_realization(scene("split"), first);
  // The cache now says something else: the resumed run must not read it.
  {
    io::H5File f(cache, io::H5File::Mode::Read);
    ASSERT_TRUE(f.has_attr("/", "repose_deg"));
  }
  const Scene measured = with_bed_turn_resolved(scene("split"), "", nullptr);
  std::filesystem::remove(cache);
  {
    Scene other = scene("split");
    set_measured_repose(other, 5.0);
    io::AtomicH5Writer out(cache);
    out.file().set_attr("/", "repose_key", repose_key(other));
    out.file().set_attr("/", "repose_deg", 5.0);
    out.file().set_attr("/", "creep_onset_deg", 3.0);
    out.commit();
  }
  RunOptions second;
  second.resume = true;
  second.max_steps = 200;
  run_realization(scene("split"), second);
  const io::CheckpointData a = io::read_checkpoint(base + "/full/checkpoint.h5");
  const io::CheckpointData b = io::read_checkpoint(base + "/split/checkpoint.h5");
  ASSERT_EQ(a.step, 400);
  ASSERT_EQ(b.step, 400);
  EXPECT_EQ(parse_scene(b.scene_text).repose.deg, measured.repose.deg);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.particles.size(); ++i)
    for (int d = 0; d < 3; ++d)
      differ +=
          a.particles.x[i][d] != b.particles.x[i][d] || a.particles.v[i][d] != b.particles.v[i][d];
  EXPECT_EQ(differ, 0u) << "the resumed run did not continue the uninterrupted one";
  std::filesystem::remove(cache);  // the bed's true cache is measured again by the next test
}

TEST(CreepOnset, IsTheSlopeFromWhichTheSurfaceKeepsMovingForThreeDegrees) {
  // Slope = the degree (a bed turning as a solid steepens with the wall); a two-degree burst at
  // 8-9 is no creep, nor are three fast samples with a degree missing (11, 12, 14); the surface
  // creeps from 16 on.
  std::vector<TurnSample> t;
  for (int deg = 1; deg <= 30; ++deg) {
    if (deg == 13) continue;  // no surface found at 13
    const bool fast = deg == 8 || deg == 9 || deg == 11 || deg == 12 || deg == 14 || deg >= 16;
    t.push_back({static_cast<double>(deg), static_cast<double>(deg), fast ? 0.5 : 0.01});
  }
  EXPECT_EQ(creep_onset_slope(t, 0.1), 16.0);
  EXPECT_TRUE(std::isnan(creep_onset_slope(t, 1.0)));  // never above: no onset
  // β averages the samples from kReposeSpinUpDeg; the onset is read with ωR as the unit.
  for (int deg = 31; deg <= 80; ++deg) t.push_back({static_cast<double>(deg), 25.0, 0.5});
  const ReposeMeasurement m = repose_from_samples(t, 1.0);
  EXPECT_DOUBLE_EQ(m.mean_deg, 25.0);
  EXPECT_EQ(m.samples, 41);
  EXPECT_EQ(m.creep_onset_deg, 16.0);
  EXPECT_TRUE(std::isnan(repose_from_samples(t, 10.0).creep_onset_deg));  // 0.5 < 0.1 × 10
}

TEST(StillSlopeMeasured, IsTheBedsCreepOnsetLessTheMarginCachedAndCarriedByTheScene) {
  // A rigid bed turned about x (no β to measure): the turn runs for the still slope alone.
  const Scene s = turning({"contact.friction=0.5", "protocol.mode=single_axis", "protocol.axis=x",
                           "protocol.duration=0.1", "fidelity.bulk=rigid",
                           "fidelity.bulk_still_slope=measured"});
  ASSERT_TRUE(s.still_slope_pending());
  ASSERT_FALSE(s.repose_pending());
  std::filesystem::remove(repose_cache_path(s));
  const Scene first = with_bed_turn_resolved(s, "", nullptr);
  ASSERT_TRUE(std::filesystem::exists(repose_cache_path(s)));
  EXPECT_FALSE(first.bed_turn_pending());
  EXPECT_TRUE(first.bulk_still_slope.measured);
  double onset = 0, beta = 0;
  {
    io::H5File f(repose_cache_path(s), io::H5File::Mode::Read);
    onset = f.attr_double("/", "creep_onset_deg");
    beta = f.attr_double("/", "repose_deg");
  }
  // The surface creeps before the layer flows at its repose angle, and not from the start.
  EXPECT_GT(onset, 5.0);
  EXPECT_LT(onset, beta);
  EXPECT_EQ(first.bulk_still_slope.deg, std::max(0.0, onset - kStillSlopeMargin));
  // The cache gives the same number; the scene text carries it and reads back.
  EXPECT_EQ(with_bed_turn_resolved(s, "", nullptr).bulk_still_slope.deg,
            first.bulk_still_slope.deg);
  EXPECT_EQ(parse_scene(scene_to_text(first)).bulk_still_slope.deg, first.bulk_still_slope.deg);
  // The same bed asking for β too reads both from the one turn; a run takes it as it is.
  Scene biaxial = turning(
      {"contact.friction=0.5", "fidelity.bulk=rigid", "fidelity.bulk_still_slope=measured"});
  EXPECT_EQ(repose_cache_path(biaxial), repose_cache_path(s));
  const Scene both = with_bed_turn_resolved(biaxial, "", nullptr);
  EXPECT_EQ(both.repose.deg, beta);
  EXPECT_EQ(both.bulk_still_slope.deg, first.bulk_still_slope.deg);
  const std::string base = test_dir("still_slope_run");
  std::filesystem::remove_all(base);
  RunOptions o;
  o.max_steps = 50;
  run_realization(turning({"contact.friction=0.5", "protocol.mode=single_axis", "protocol.axis=x",
                           "protocol.duration=0.1", "fidelity.bulk=rigid",
                           "fidelity.bulk_still_slope=measured", "scene.output_dir=" + base}),
                  o);
  const io::CheckpointData c = io::read_checkpoint(base + "/checkpoint.h5");
  EXPECT_EQ(c.step, 50);
  EXPECT_EQ(parse_scene(c.scene_text).bulk_still_slope.deg, first.bulk_still_slope.deg);
}
