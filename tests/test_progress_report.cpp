// The caller's progress hook (RunOptions::on_progress, a campaign case's reports to its
// dispatcher): called once when the protocol loop begins, at the step where this call begins (0,
// or a resumed run's checkpoint step) with the bed or checkpoint already loaded, before any step
// is taken; and only where the run logs (its rank 0).
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <utility>
#include <vector>

#include "bed_fixture.hpp"
#include "run/realization.hpp"
#include "run/run_state.hpp"

using namespace tumble;
using namespace tumble::testing;

TEST(ProgressReport, FirstWhenTheProtocolBeginsWhereThisCallBegins) {
  const std::string base = test_dir("progress_report");
  std::filesystem::remove_all(base);
  const Scene sc =
      tiny_scene({"protocol.mode=biaxial", "protocol.repose=27", "protocol.iterations=0.002",
                  "scene.output_dir=" + base, "output.checkpoint_interval=0.003"});
  std::vector<std::pair<std::int64_t, std::int64_t>> calls;  // (first_step, step)
  auto record = [&](const RunState& s) { calls.emplace_back(s.first_step, s.sim.step_count()); };
  std::ostringstream log;
  RunOptions first;
  first.max_steps = 500;
  first.log = &log;
  first.on_progress = record;
  run_realization(sc, first);
  ASSERT_FALSE(calls.empty());
  EXPECT_EQ(calls.front(), std::make_pair(std::int64_t{0}, std::int64_t{0}));

  calls.clear();
  RunOptions rest;
  rest.resume = true;
  rest.log = &log;
  rest.on_progress = record;
  run_realization(sc, rest);
  ASSERT_FALSE(calls.empty());
  EXPECT_GT(calls.front().first, 0) << "resumed from a checkpoint";
  EXPECT_EQ(calls.front().second, calls.front().first) << "before its first step";

  calls.clear();
  RunOptions silent;  // no log: not the run's rank 0
  silent.max_steps = 50;
  silent.on_progress = record;
  run_realization(tiny_scene({"protocol.mode=biaxial", "protocol.repose=27",
                              "protocol.iterations=0.002", "scene.output_dir=" + base + "_silent"}),
                  silent);
  EXPECT_TRUE(calls.empty());
}
