// protocol.repose = "measured" (issue 17, D7): β is the dynamic repose angle of the scene's own
// bed, measured once, kept beside the cached bed, and carried by a run's checkpoint.
#include <gtest/gtest.h>

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
  const double a = with_repose_resolved(slippery, "", nullptr).repose.deg;
  const double b = with_repose_resolved(rough, "", nullptr).repose.deg;
  // Measured on these beds: 22.9° and 29.9°; a measure that ignored the bed could not order them.
  EXPECT_GT(a, 10.0);
  EXPECT_LT(b, 45.0);
  EXPECT_GT(b - a, 3.0) << "friction 0.1: " << a << " deg, friction 0.9: " << b << " deg";
}

TEST(ReposeMeasure, IsCachedBesideTheBedAndFilledIntoTheSceneText) {
  const Scene s = turning({"contact.friction=0.5"});
  std::filesystem::remove(repose_cache_path(s));
  const Scene first = with_repose_resolved(s, "", nullptr);
  ASSERT_TRUE(std::filesystem::exists(repose_cache_path(s)));
  EXPECT_FALSE(first.repose_pending());
  EXPECT_TRUE(first.repose.measured);
  // The cache gives the same number, bit for bit; the scene text carries it and reads back.
  const Scene again = with_repose_resolved(s, "", nullptr);
  EXPECT_EQ(first.repose.deg, again.repose.deg);
  const Scene back = parse_scene(scene_to_text(first));
  EXPECT_EQ(back.repose.deg, first.repose.deg);
  EXPECT_FALSE(back.repose_pending());
  EXPECT_EQ(first.resolved.at("protocol.repose"), back.resolved.at("protocol.repose"));
  // Another speed is another measurement (its own cache file); a given number is left alone.
  EXPECT_NE(repose_cache_path(turning({"contact.friction=0.5", "protocol.rpm=25"})),
            repose_cache_path(s));
  const Scene given = with_repose_resolved(turning({"protocol.repose=27"}), "", nullptr);
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
  RunOptions full;
  full.max_steps = 400;
  run_realization(scene("full"), full);
  RunOptions first;
  first.max_steps = 200;
  run_realization(scene("split"), first);
  // The cache now says something else: the resumed run must not read it.
  const std::string cache = repose_cache_path(scene("split"));
  {
    io::H5File f(cache, io::H5File::Mode::Read);
    ASSERT_TRUE(f.has_attr("/", "repose_deg"));
  }
  const Scene measured = with_repose_resolved(scene("split"), "", nullptr);
  std::filesystem::remove(cache);
  {
    Scene other = scene("split");
    set_measured_repose(other, 5.0);
    io::AtomicH5Writer out(cache);
    out.file().set_attr("/", "repose_key", repose_key(other));
    out.file().set_attr("/", "repose_deg", 5.0);
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
}
