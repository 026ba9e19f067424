// When a run writes its particle snapshots: the k-th at the step nearest k intervals (no drift
// with k), the protocol's end once, and a resumed run's list the same as an uninterrupted one's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "bed_fixture.hpp"
#include "h5/hdf5_file.hpp"
#include "run/realization.hpp"
#include "run/snapshot_observer.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {
// The "step" attribute of every snap_*.h5 in dir, in file order.
std::vector<std::int64_t> snapshot_steps(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("snap_", 0) == 0 && e.path().extension() == ".h5") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<std::int64_t> steps;
  for (const auto& f : files)
    steps.push_back(io::H5File(f, io::H5File::Mode::Read).attr_int64("/", "step"));
  return steps;
}

std::string text_of(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
}  // namespace

TEST(SnapshotSteps, TheKthIsWithinHalfAStepOfKIntervalsForAnyK) {
  // An interval of 1234.567 steps: rounding it once (1235) would put snapshot 100,000 43,300
  // steps late; the nearest step never errs by more than half a step.
  const double x = 1234.567;
  std::int64_t last = -1;
  for (std::int64_t k = 0; k <= 100000; ++k) {
    const std::int64_t s = snapshot_step(k, x);
    ASSERT_LE(std::abs(static_cast<double>(s) - static_cast<double>(k) * x), 0.5) << "k = " << k;
    ASSERT_GT(s, last) << "k = " << k;
    last = s;
  }
  EXPECT_EQ(snapshot_step(7, 0.3), 7);  // an interval below one step: every step
}

TEST(SnapshotSteps, TheEndIsWrittenOnceAndAResumedRunWritesTheSameList) {
  const std::string base = test_dir("snapshot_steps");
  std::filesystem::remove_all(base);
  // A quarter of the run per snapshot (1233 steps in all, 308.x steps each): 4 × round(308.x)
  // = 1232 put the last periodic snapshot one step before the end, which was then written again.
  const Scene probe = tiny_scene({"protocol.mode=biaxial", "protocol.iterations=0.002"});
  std::ostringstream quarter;
  quarter.precision(17);
  quarter << probe.run_time() / 4;
  auto scene = [&](const std::string& out) {
    return tiny_scene({"protocol.mode=biaxial", "protocol.repose=27", "protocol.iterations=0.002",
                       "scene.output_dir=" + base + "/" + out, "output.checkpoint_interval=0.006",
                       "output.snapshot_interval=" + quarter.str()});
  };
  const Scene sc = scene("full");
  const double steps = sc.run_time() / sc.time_step();
  const std::int64_t total = std::llround(steps);
  ASSERT_NE(4 * std::llround(steps / 4), total) << "the case the old rule got wrong";
  run_realization(sc, RunOptions{});
  const std::vector<std::int64_t> full = snapshot_steps(base + "/full");
  ASSERT_EQ(full.size(), 5u) << "step 0, three quarters and the end, once";
  for (std::size_t k = 0; k < full.size(); ++k)
    EXPECT_LE(std::abs(static_cast<double>(full[k]) - static_cast<double>(k) * steps / 4), 0.5);
  EXPECT_EQ(full.back(), total);

  RunOptions first;
  first.max_steps = 500;  // stopped between the second and the third snapshot
  run_realization(scene("split"), first);
  RunOptions second;
  second.resume = true;
  run_realization(scene("split"), second);
  EXPECT_EQ(snapshot_steps(base + "/split"), full);
  // The XDMF index lists the resumed run's snapshots (rebuilt from the checkpoint) at the same
  // times as the uninterrupted run's.
  std::string a = text_of(base + "/full/snapshots.xdmf"),
              b = text_of(base + "/split/snapshots.xdmf");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}
