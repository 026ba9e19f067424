// The dispatcher's progress line when a group holds its next case: the held case's leader can
// report "preparing" before the dispatcher has the group's previous result (the two travel with
// different tags), and the line must still count only the case that runs (running 1, one share,
// nothing preparing) until that result is in; then the held case runs and is preparing.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <sstream>
#include <thread>

#include "campaign/campaign_spec.hpp"
#include "campaign/dispatcher.hpp"
#include "campaign/expand.hpp"
#include "campaign/manifest.hpp"

namespace tumble::campaign {
namespace {
namespace fs = std::filesystem;

// The last "[campaign] done ..." line written to `out` so far.
std::string last_counts(const std::ostringstream& out) {
  std::istringstream in(out.str());
  std::string line, last;
  while (std::getline(in, line))
    if (line.rfind("[campaign] done ", 0) == 0) last = line;
  return last;
}

TEST(DispatcherLine, HeldCaseReportingEarlyIsNotCountedAsRunning) {
  const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/dispatcher_line";
  fs::remove_all(dir);
  fs::create_directories(dir);
  CampaignSpec spec;
  spec.progress_interval = 1;  // tick() writes a line at most once a second
  Expansion ex;
  for (int k = 0; k < 2; ++k) {
    Case c;
    c.index = static_cast<std::size_t>(k);
    c.id = std::string(15, '0') + std::to_string(k);
    c.point_id = "p";
    c.cost = 1000;
    ex.cases.push_back(c);
  }
  CaseContext ctx;
  ctx.spec = &spec;
  ctx.expansion = &ex;
  ManifestWriter manifest(dir + "/manifest.jsonl");
  std::ostringstream out;
  ScheduleInput in;
  in.tasks = {CaseTask{0, 1, 0, false}, CaseTask{1, 1, 0, false}};
  in.total = 2;
  in.manifest = &manifest;
  in.out = &out;
  in.quiet = false;  // (a quiet campaign writes no line when a case is done)
  Dispatcher d(ctx, in, {"host"}, 1);
  const CaseTask first = in.tasks[0], held = in.tasks[1];
  ASSERT_NE(d.peek(), nullptr);  // (peek() then pop(), as the scheduler hands them out)
  d.pop();
  d.started(first, {0});
  ASSERT_NE(d.peek(), nullptr);
  d.pop();
  d.started(held, {0});  // the same group: held until the first case ends
  d.progress({0, 1, false, 0, 500, 1000, 10.0});
  d.progress({1, 1, true});  // the held case's leader, early
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  d.tick();
  const std::string before = last_counts(out);
  EXPECT_NE(before.find("running 1 (50.0% of its steps) | next 1"), std::string::npos) << before;
  EXPECT_EQ(before.find("preparing"), std::string::npos) << before;

  CaseOutcome done;
  done.ok = true;
  done.wall = 20;
  (void)d.finished(first, done);
  const std::string after = last_counts(out);
  EXPECT_NE(after.find("done 1 | running 1 (1 preparing)"), std::string::npos) << after;
  EXPECT_EQ(after.find("next"), std::string::npos) << after;
}

}  // namespace
}  // namespace tumble::campaign
