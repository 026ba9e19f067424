// The dispatcher's lines when a group holds its next case. The held case's leader can report
// "preparing" before the dispatcher has the group's previous result (the two travel with
// different tags): the line must still count only the case that runs (running 1, one share,
// nothing preparing) until that result is in; then the held case runs and is preparing. A stop
// then says one running case ends (the held one ends "not begun").
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <memory>
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

// Two cases of one point handed to rank 0 alike: the first runs (half its steps done), the
// second is held next in line and its leader has already said it is preparing.
struct HeldCase : ::testing::Test {
  CampaignSpec spec;
  Expansion ex;
  CaseContext ctx;
  std::unique_ptr<ManifestWriter> manifest;
  std::ostringstream out;
  ScheduleInput in;
  std::unique_ptr<Dispatcher> d;
  const CaseTask first{0, 1, 0, false}, held{1, 1, 0, false};

  void SetUp() override {
    const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/dispatcher_line";
    fs::remove_all(dir);
    fs::create_directories(dir);
    spec.progress_interval = 1;  // tick() writes a line at most once a second
    for (int k = 0; k < 2; ++k) {
      Case c;
      c.index = static_cast<std::size_t>(k);
      c.id = std::string(15, '0') + std::to_string(k);
      c.point_id = "p";
      c.cost = 1000;
      ex.cases.push_back(c);
    }
    ctx.spec = &spec;
    ctx.expansion = &ex;
    manifest = std::make_unique<ManifestWriter>(dir + "/manifest.jsonl");
    in.tasks = {first, held};
    in.total = 2;
    in.manifest = manifest.get();
    in.out = &out;
    in.quiet = false;  // (a quiet campaign writes no line when a case is done)
    d = std::make_unique<Dispatcher>(ctx, in, std::vector<std::string>{"host"}, 1);
    ASSERT_NE(d->peek(), nullptr);  // (peek() then pop(), as the scheduler hands them out)
    d->pop();
    d->started(first, {0});
    ASSERT_NE(d->peek({0}), nullptr);  // (for the same group: nothing waits on its preparation)
    d->pop();
    d->started(held, {0});  // the same group: held until the first case ends
    d->progress({0, 1, false, 0, 500, 1000, 10.0});
    d->progress({1, 1, true});  // the held case's leader, early
  }
};

TEST_F(HeldCase, ReportingEarlyIsNotCountedAsRunning) {
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  d->tick();
  const std::string before = last_counts(out);
  EXPECT_NE(before.find("running 1 (50.0% of its steps) | next 1"), std::string::npos) << before;
  EXPECT_EQ(before.find("preparing"), std::string::npos) << before;

  CaseOutcome done;
  done.ok = true;
  done.wall = 20;
  (void)d->finished(first, done);
  const std::string after = last_counts(out);
  EXPECT_NE(after.find("done 1 | running 1 (1 preparing)"), std::string::npos) << after;
  EXPECT_EQ(after.find("next"), std::string::npos) << after;
}

TEST_F(HeldCase, StopCountsTheGroupNotTheHeldCase) {
  d->stop(SIGUSR1);
  EXPECT_NE(out.str().find("the running case ends"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace tumble::campaign
