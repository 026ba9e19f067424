// When a run writes its particle snapshots: the k-th at the step nearest k intervals (no drift
// with k), the protocol's end once, and a resumed run's list the same as an uninterrupted one's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "bed_fixture.hpp"
#include "h5/hdf5_file.hpp"
#include "run/event_steps.hpp"
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

// The simulated time of every snap_*.h5 in dir (its "time" attribute), in file order.
std::vector<double> snapshot_times(const std::string& dir) {
  std::vector<double> times;
  for (std::int64_t k = 0;; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "/snap_%06lld.h5", static_cast<long long>(k));
    if (!std::filesystem::exists(dir + name)) return times;
    times.push_back(io::H5File(dir + name, io::H5File::Mode::Read).attr_double("/", "time"));
  }
}

// The <Time Value="..."/> entries of dir/snapshots.xdmf, in order.
std::vector<double> xdmf_times(const std::string& dir) {
  std::ifstream in(dir + "/snapshots.xdmf");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::vector<double> out;
  const std::string tag = "<Time Value=\"";
  for (auto at = text.find(tag); at != std::string::npos; at = text.find(tag, at + 1))
    out.push_back(std::stod(text.substr(at + tag.size())));
  return out;
}

void expect_xdmf_matches_files(const std::string& dir) {
  const std::vector<double> files = snapshot_times(dir), index = xdmf_times(dir);
  ASSERT_EQ(files.size(), index.size()) << dir;
  for (std::size_t k = 0; k < files.size(); ++k)  // the index prints 6 significant digits
    EXPECT_NEAR(index[k], files[k], 1e-5 * std::max(files[k], 1e-3)) << dir << ", snapshot " << k;
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

// A run resumed with another snapshot interval keeps to the new interval's grid from where it
// resumed (the first rule counted the snapshots written and waited for a step already passed);
// one continued past its end (more iterations) goes on on its grid, and the XDMF index rebuilt
// from the checkpoint gives every file its own time.
TEST(SnapshotSteps, AResumeWithAnotherIntervalOrMoreIterationsKeepsToTheGrid) {
  const std::string base = test_dir("snapshot_steps_resume");
  std::filesystem::remove_all(base);
  auto scene = [&](const std::string& out, const std::string& interval, const char* iterations) {
    return tiny_scene({"protocol.mode=biaxial", "protocol.repose=27",
                       std::string("protocol.iterations=") + iterations,
                       "scene.output_dir=" + base + "/" + out, "output.checkpoint_interval=0.006",
                       "output.snapshot_interval=" + interval});
  };
  // 0.00613 s = 306.5 steps; then 0.00307 s = 153.5 steps from step 500 on.
  const Scene coarse = scene("changed", "0.00613", "0.002");
  const double dt = coarse.time_step();
  RunOptions first;
  first.max_steps = 500;
  run_realization(coarse, first);
  RunOptions rest;
  rest.resume = true;
  const Scene fine = scene("changed", "0.00307", "0.002");
  run_realization(fine, rest);
  const std::int64_t total = std::llround(fine.run_time() / dt);
  std::vector<std::int64_t> want = {0, snapshot_step(1, 0.00613 / dt)};
  for (std::int64_t k = 1; snapshot_step(k, 0.00307 / dt) < total; ++k)
    if (snapshot_step(k, 0.00307 / dt) > 500) want.push_back(snapshot_step(k, 0.00307 / dt));
  want.push_back(total);
  EXPECT_EQ(snapshot_steps(base + "/changed"), want);
  expect_xdmf_matches_files(base + "/changed");

  // To the end of 0.002 iterations (1233 steps: the end between two snapshots, written), then on
  // to 0.004: the snapshots after the first end are those of an uninterrupted 0.004 run.
  run_realization(scene("extended", "0.00613", "0.002"), RunOptions{});
  run_realization(scene("extended", "0.00613", "0.004"), rest);
  run_realization(scene("straight", "0.00613", "0.004"), RunOptions{});
  std::vector<std::int64_t> ext = snapshot_steps(base + "/extended"),
                            straight = snapshot_steps(base + "/straight");
  const std::int64_t first_end = std::llround(coarse.run_time() / dt);
  ASSERT_EQ(std::count(ext.begin(), ext.end(), first_end), 1);
  ext.erase(std::find(ext.begin(), ext.end(), first_end));
  EXPECT_EQ(ext, straight) << "the extended run's grid differs from the uninterrupted run's";
  expect_xdmf_matches_files(base + "/extended");
}

// Checkpoints and segregation samples: steps_between_events. An interval of "never" (1e9 s) at a
// tiny time step is more steps than llround can return; before the clamp it came back LLONG_MIN
// and the max with 1 checkpointed every step.
TEST(EventSteps, AnIntervalPastEveryStepCountStaysNever) {
  EXPECT_EQ(steps_between_events(1e9, 1e-10, 1.0), std::int64_t{1000000000000000000});
  EXPECT_EQ(steps_between_events(1e9, 1e-300, 1.0), std::int64_t{1000000000000000000});
}

TEST(EventSteps, RoundsToTheNearestStepWithAtLeastOneAndZeroMeansTheFallback) {
  EXPECT_EQ(steps_between_events(0.002, 2e-5, 12.3), 100);
  EXPECT_EQ(steps_between_events(0.002012, 2e-5, 12.3), 101);  // 100.6
  EXPECT_EQ(steps_between_events(0, 2e-5, 12.3), 615000);      // once per iteration
  EXPECT_EQ(steps_between_events(1e-6, 2e-5, 12.3), 1);        // (the scene refuses it: w20-w22)
}
