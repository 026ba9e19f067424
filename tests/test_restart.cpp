// A run restarted from a checkpoint continues bitwise identically to an uninterrupted run.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>

#include "base/error.hpp"
#include "bed_fixture.hpp"
#include "h5/hdf5_file.hpp"
#include "io/checkpoint.hpp"
#include "run/realization.hpp"

using namespace tumble;
using namespace tumble::testing;

TEST(Restart, ContinuesBitwiseIdentically) {
  const std::string base = test_dir("restart");
  std::filesystem::remove_all(base);
  auto scene = [&](const std::string& out) {
    // The biaxial protocol (1233 steps), a checkpoint every 300 steps; 900 steps are run.
    // β given: the measured tilt's own restart test is in test_repose_measure.cpp.
    return tiny_scene({"protocol.mode=biaxial", "protocol.repose=27",
                       "scene.output_dir=" + base + "/" + out, "output.checkpoint_interval=0.006",
                       "output.snapshot_interval=0.006", "protocol.iterations=0.002"});
  };
  RunOptions full;
  full.max_steps = 900;
  run_realization(scene("full"), full);

  RunOptions first;
  first.max_steps = 300;
  run_realization(scene("split"), first);
  RunOptions second;
  second.resume = true;
  second.max_steps = 600;
  run_realization(scene("split"), second);

  const io::CheckpointData a = io::read_checkpoint(base + "/full/checkpoint.h5");
  const io::CheckpointData b = io::read_checkpoint(base + "/split/checkpoint.h5");
  ASSERT_EQ(a.step, 900);
  ASSERT_EQ(b.step, 900);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  EXPECT_EQ(state_differences(a.particles, b.particles), 0u)
      << "values differ between the restarted and the uninterrupted run";
  ASSERT_EQ(a.history.records().size(), b.history.records().size());
  for (std::size_t k = 0; k < a.history.records().size(); ++k) {
    const auto& r = a.history.records()[k];
    const auto& t = b.history.records()[k];
    EXPECT_TRUE(r.lo == t.lo && r.hi == t.hi && r.history == t.history);
  }
  // The run actually moved (a restart of a frozen state would pass trivially).
  EXPECT_GT(a.history.records().size(), 100u);
}

// The drift grid's sums are part of the checkpoint: a run killed after one drift sample (every
// 0.1 s = 5,000 steps) and resumed writes the grid of the uninterrupted run, bit for bit.
// A checkpoint written before the rigid bulk's `bulk_state` column existed restarts (the column is
// read as 0: every particle dynamic) and continues bitwise like the uninterrupted run.
TEST(Restart, ACheckpointWithoutTheBulkStateColumnRestarts) {
  const std::string base = test_dir("restart_no_bulk_state");
  std::filesystem::remove_all(base);
  auto scene = [&](const std::string& out) {
    return tiny_scene({"protocol.mode=biaxial", "protocol.repose=27",
                       "scene.output_dir=" + base + "/" + out, "output.checkpoint_interval=0.006",
                       "protocol.iterations=0.002"});
  };
  RunOptions full;
  full.max_steps = 600;
  run_realization(scene("full"), full);
  RunOptions first;
  first.max_steps = 300;
  run_realization(scene("old"), first);
  {  // make it an older checkpoint
    const std::string path = base + "/old/checkpoint.h5";
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    ASSERT_GE(H5Ldelete(file, "particles/bulk_state", H5P_DEFAULT), 0);
    H5Fclose(file);
  }
  RunOptions second;
  second.resume = true;
  second.max_steps = 300;
  run_realization(scene("old"), second);
  const io::CheckpointData a = io::read_checkpoint(base + "/full/checkpoint.h5");
  const io::CheckpointData b = io::read_checkpoint(base + "/old/checkpoint.h5");
  ASSERT_EQ(a.step, 600);
  ASSERT_EQ(b.step, 600);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  EXPECT_EQ(state_differences(a.particles, b.particles), 0u);
  for (std::int32_t state : b.particles.bulk_state) EXPECT_EQ(state, 0);
}

TEST(Restart, DriftGridSumsSurviveAResume) {
  const std::string base = test_dir("restart_drift");
  std::filesystem::remove_all(base);
  auto scene = [&](const std::string& out) {
    return tiny_scene({"protocol.mode=single_axis", "protocol.rpm=30", "protocol.duration=0.31",
                       "output.drift_grid=on", "scene.output_dir=" + base + "/" + out,
                       "output.checkpoint_interval=0.152", "output.snapshot_interval=0.31"});
  };
  run_realization(scene("full"), RunOptions{});
  RunOptions first;
  first.max_steps = 7600;  // the first checkpoint; one drift sample (step 5,000) taken before it
  run_realization(scene("split"), first);
  const io::CheckpointData mid = io::read_checkpoint(base + "/split/checkpoint.h5");
  ASSERT_EQ(mid.step, 7600);
  ASSERT_FALSE(mid.drift.empty());
  EXPECT_GT(mid.drift.samples(), 0);
  RunOptions second;
  second.resume = true;
  run_realization(scene("split"), second);
  io::H5File a(base + "/full/drift_grid.h5", io::H5File::Mode::Read);
  io::H5File b(base + "/split/drift_grid.h5", io::H5File::Mode::Read);
  double total = 0;
  for (const char* name : {"/count", "/sum", "/sum2", "/v_ax", "/sigma_ax"}) {
    const auto x = a.read_double(name), y = b.read_double(name);
    ASSERT_EQ(x.size(), y.size()) << name;
    for (std::size_t c = 0; c < x.size(); ++c) EXPECT_EQ(x[c], y[c]) << name << "[" << c << "]";
    if (std::string(name) == "/count")
      for (const double v : x) total += v;
  }
  // More samples at the end than at the kill: the resumed run added to the restored sums.
  EXPECT_GT(total, mid.drift.samples());
}

TEST(Restart, RefusesACheckpointOfAnotherScene) {
  const std::string base = test_dir("restart_mismatch");
  std::filesystem::remove_all(base);
  RunOptions o;
  o.max_steps = 10;
  run_realization(tiny_scene({"scene.output_dir=" + base, "protocol.duration=0.001"}), o);
  RunOptions r;
  r.resume = true;
  EXPECT_THROW(run_realization(tiny_scene({"scene.output_dir=" + base, "protocol.duration=0.001",
                                           "contact.restitution=0.5"}),
                               r),
               InputError);
  // Another seed is another realization: the checkpoint's bed would be recorded under it.
  try {
    run_realization(
        tiny_scene({"scene.output_dir=" + base, "protocol.duration=0.001", "fill.seed=5"}), r);
    ADD_FAILURE() << "a restart under another fill.seed went on";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fill.seed (checkpoint 1, scene 5)"), std::string::npos)
        << e.what();
  }
}
