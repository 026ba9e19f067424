// The dispatcher's lines when a group holds its next case. The held case's leader can report
// "preparing" before the dispatcher has the group's previous result (the two travel with
// different tags): the line must still count only the case that runs (running 1, one share,
// nothing preparing) until that result is in; then the held case runs and is preparing. A stop
// then says one running case ends (the held one ends "not begun").
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
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

// A case's outcome when a stop ended it (`diagnostic`: where, as its group reports it).
CaseOutcome stopped_outcome(const std::string& diagnostic) {
  CaseOutcome o;
  o.failure = "stopped";
  o.diagnostic = diagnostic;
  return o;
}

// A finished case's outcome: `wall` seconds in all, `protocol_wall` of them its protocol loop's.
CaseOutcome done_outcome(double wall, double protocol_wall = 0, long long resumed_from_step = 0) {
  CaseOutcome o;
  o.ok = true;
  o.wall = wall;
  o.protocol_wall = protocol_wall;
  o.resumed_from_step = resumed_from_step;
  return o;
}

// Two cases of one point (cost 1000 each) and a dispatcher for one rank, nothing handed out.
struct TwoCases : ::testing::Test {
  CampaignSpec spec;
  Expansion ex;
  CaseContext ctx;
  std::unique_ptr<ManifestWriter> manifest;
  std::ostringstream out;
  ScheduleInput in;
  std::unique_ptr<Dispatcher> d;
  const CaseTask first{0, 1, 0, false}, second{1, 1, 0, false};

  void SetUp() override {
    // A folder per test: ctest runs this fixture's tests side by side, and one test's SetUp
    // must not remove (or lock) another's manifest.
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/dispatcher_line/" +
                            test->test_suite_name() + "." + test->name();
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
    in.tasks = {first, second};
    in.total = 2;
    in.manifest = manifest.get();
    in.out = &out;
    in.quiet = false;  // (a quiet campaign writes no line when a case is done)
    d = std::make_unique<Dispatcher>(ctx, in, std::vector<std::string>{"host"}, 1);
  }

  // The queue's next case to `ranks`, as the scheduler hands one out (peek, pop, started);
  // `group`: the ranks it is held on, next in line, when they run a case.
  void hand_out(const CaseTask& t, const std::vector<int>& ranks,
                const std::vector<int>& group = {}) {
    const CaseTask* next = d->peek(group);
    ASSERT_NE(next, nullptr);
    ASSERT_EQ(next->case_index, t.case_index);
    d->pop();
    d->started(t, ranks);
  }
};

// The first runs (half its steps done), the second is held next in line on the same rank and
// its leader has already said it is preparing.
struct HeldCase : TwoCases {
  const CaseTask& held = second;
  void SetUp() override {
    TwoCases::SetUp();
    hand_out(first, {0});
    hand_out(held, {0}, {0});  // the same group: held until the first case ends (and not
                               // waiting for the first's preparation, which ends before it)
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

// A case resumed from step 900 of 1000 that ends 10 s later did a tenth of its cost in those
// 10 s: the queued case (cost 1000) is then 100 s away, not 10 (its whole cost was credited).
TEST_F(TwoCases, ResumedCaseIsCreditedOnlyWithTheStepsItRan) {
  hand_out(first, {0});
  d->progress({0, 1, false, 900, 900, 1000, 0.0});  // its protocol begins at its checkpoint
  (void)d->finished(first, done_outcome(10, 0, 900));
  const std::string line = last_counts(out);
  EXPECT_NE(line.find("ETA 0:01:40"), std::string::npos) << line;
}

// A finished case's rate is its protocol's: the hours it spent settling its bed and measuring β
// (60 of its 100 s here) are not steps, and a running case's reports do not count them either.
TEST_F(TwoCases, FinishedCaseRateLeavesItsPreparationOut) {
  hand_out(first, {0});
  d->progress({0, 1, false, 0, 0, 1000, 0.0});
  (void)d->finished(first, done_outcome(100, 40));
  const std::string line = last_counts(out);
  EXPECT_NE(line.find("ETA 0:00:40"), std::string::npos) << line;
}

// A retryable failure that comes in after a stop is not retried in this invocation; its record
// must leave the retry to the rerun (final: false), not end the case as failed for good.
TEST_F(TwoCases, RetryableFailureDuringAStopIsLeftToTheRerun) {
  spec.max_attempts = 2;
  hand_out(first, {0});
  d->stop(SIGUSR1);
  CaseOutcome failed;
  failed.failure = "run";
  failed.diagnostic = "particle 1 left the tumbler";
  failed.retryable = true;
  (void)d->finished(first, failed);
  manifest->sync();
  std::ifstream in(manifest->path());
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  CaseRecord r;
  ASSERT_TRUE(from_json(last, r)) << last;
  EXPECT_EQ(r.status, "failed");
  EXPECT_FALSE(r.final_failure) << last;
  EXPECT_NE(out.str().find("the rerun retries it (attempt 2)"), std::string::npos) << out.str();
}

// The stop's counts: a case stopped before its protocol's first report kept no checkpoint, and
// a held case that ends "not begun" is not started, neither "stopped at a checkpoint".
TEST_F(HeldCase, StopCountsPreparingAndNotBegunApart) {
  d->stop(SIGUSR1);
  (void)d->finished(first, stopped_outcome("stopped by SIGUSR1 at step 600"));  // (reported 500)
  (void)d->finished(held, stopped_outcome("not begun: SIGUSR1 came first"));
  EXPECT_EQ(d->stats().stopped, 1);
  EXPECT_EQ(d->stats().stopped_preparing, 0);
  EXPECT_EQ(d->stats().not_started, 1);
}

TEST_F(TwoCases, StopWhilePreparingIsCountedApart) {
  hand_out(first, {0});
  d->progress({0, 1, true});  // preparing: no protocol report yet
  d->stop(SIGUSR1);
  (void)d->finished(first, stopped_outcome("stopped by SIGUSR1 while measuring the repose angle"));
  EXPECT_EQ(d->stats().stopped, 0);
  EXPECT_EQ(d->stats().stopped_preparing, 1);
  EXPECT_EQ(d->stats().not_started, 1);  // (the second case, still queued)
}

// Three ranks and cases of two: rank 2 stays idle, so the work left is shared by two ranks. A
// case done in 10 s on its 2 ranks (20 rank-seconds) leaves its twin 10 s away, not 6.7.
TEST_F(TwoCases, IdleRanksDoNotShareTheWorkLeft) {
  for (Case& c : ex.cases) c.ranks = 2;
  d = std::make_unique<Dispatcher>(ctx, in, std::vector<std::string>(3, "host"), 3);
  hand_out(first, {0, 1});
  CaseOutcome done;
  done.ok = true;
  done.wall = 10;
  (void)d->finished(first, done);
  const std::string line = last_counts(out);
  EXPECT_NE(line.find("ETA 0:00:10"), std::string::npos) << line;
}

// A stop that reaches rank 0 before its group's result: the held case may still have begun
// (its group went on to it before the stop reached it). Its start line then comes with its
// result; one that ends "not begun" gets none.
TEST_F(HeldCase, HeldCaseThatBeganDuringAStopHasItsStartLine) {
  d->stop(SIGUSR1);
  (void)d->finished(first, stopped_outcome("stopped by SIGUSR1 at step 600"));
  const std::string start = "start " + ex.cases[1].id;
  EXPECT_EQ(out.str().find(start), std::string::npos) << out.str();  // (not yet: it may not begin)
  (void)d->finished(held, stopped_outcome("stopped by SIGUSR1 while settling the bed"));
  EXPECT_NE(out.str().find(start), std::string::npos) << out.str();
}

TEST_F(HeldCase, HeldCaseNotBegunDuringAStopHasNoStartLine) {
  d->stop(SIGUSR1);
  (void)d->finished(first, stopped_outcome("stopped by SIGUSR1 at step 600"));
  (void)d->finished(held, stopped_outcome("not begun: SIGUSR1 came first"));
  EXPECT_EQ(out.str().find("start " + ex.cases[1].id), std::string::npos) << out.str();
}

}  // namespace
}  // namespace tumble::campaign
