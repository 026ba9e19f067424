// The campaign's ETA against campaigns whose end is known: equal cases on two workers (the
// estimate equals the true remainder at every moment and falls while cases run), the tail with
// fewer cases than workers, a case running longer than its cost predicts, groups of two ranks,
// nothing finished yet.
#include <gtest/gtest.h>

#include <cmath>

#include "campaign/eta.hpp"

namespace tumble::campaign {
namespace {

// Six cases of cost 1 that take 1800 s each, two workers: at 1800 + a seconds two are done, two
// run (age a) and two wait; the campaign ends at 5400 s.
EtaInput six_equal_cases(double a) {
  EtaInput in;
  in.done_cost = 2;
  in.done_rank_seconds = 2 * 1800;
  in.running = {{1, a}, {1, a}};
  in.queued_cost = 2;
  in.ranks = 2;
  return in;
}

TEST(Eta, EqualCasesOnTwoWorkersGiveTheTrueRemainder) {
  double previous = INFINITY;
  for (double a : {0.0, 300.0, 900.0, 1500.0, 1799.0}) {
    const double eta = estimate_eta(six_equal_cases(a));
    EXPECT_NEAR(eta, 5400 - (1800 + a), 1e-9) << "a = " << a;
    EXPECT_LT(eta, previous) << "the estimate must fall while the cases run";
    previous = eta;
  }
}

TEST(Eta, TheTailIsTheLongestRunningCase) {
  EtaInput in;  // one case done in 1800 s; the last one running for 600 s; a worker idle
  in.done_cost = 1;
  in.done_rank_seconds = 1800;
  in.running = {{1, 600}};
  in.ranks = 2;
  EXPECT_NEAR(estimate_eta(in), 1200, 1e-9);
  in.running = {{3, 600}};  // three times the cost: three times as long
  EXPECT_NEAR(estimate_eta(in), 3 * 1800 - 600, 1e-9);
}

TEST(Eta, OverrunningCaseCountsZeroNotNegative) {
  EtaInput in;
  in.done_cost = 1;
  in.done_rank_seconds = 1800;
  in.running = {{1, 4000}};  // longer than its cost predicts
  in.queued_cost = 1;
  in.ranks = 1;
  EXPECT_NEAR(estimate_eta(in), 1800, 1e-9);
}

// Four ranks in two groups of two: each case of cost 1 takes 900 s on its group (1800
// rank-seconds, as on one rank); six cases end at 2700 s. At 900 + a: two done, two running, two
// queued.
TEST(Eta, GroupsOfTwoRanksCountInRankSeconds) {
  for (double a : {0.0, 450.0, 899.0}) {
    EtaInput in;
    in.done_cost = 2;
    in.done_rank_seconds = 2 * 900 * 2;
    in.running = {{1, a, 2}, {1, a, 2}};
    in.queued_cost = 2;
    in.ranks = 4;
    EXPECT_NEAR(estimate_eta(in), 2700 - (900 + a), 1e-9) << "a = " << a;
  }
}

TEST(Eta, UnknownBeforeAnyCaseFinished) {
  EtaInput in;
  in.running = {{1, 100}};
  in.queued_cost = 3;
  EXPECT_TRUE(std::isnan(estimate_eta(in)));
}

// Cases that take days: before any has finished, the running cases' progress reports give the
// rate. Two cases of cost 1 on two workers, each 25% through after 100 s (400 s per case), two
// queued cases of cost 1: the running ones end in 300 s, the queued ones 400 s later: 700 s.
TEST(Eta, ReportsGiveTheRateBeforeAnyCaseFinished) {
  EtaInput in;
  in.ranks = 2;
  in.queued_cost = 2;
  EtaInput::Running fresh{1, 100};
  fresh.reported = true;
  fresh.done_share = 0.25;
  fresh.call_share = 0.25;
  fresh.call_seconds = 100;
  in.running = {fresh, fresh};
  EXPECT_NEAR(estimate_eta(in), 700, 1e-9);
  // A resumed case, 25% done: 10% before this call, 15% in its 100 s: 75% left at its own
  // 0.15% per second, 500 s.
  EtaInput::Running resumed = fresh;
  resumed.call_share = 0.15;
  in.running = {resumed};
  in.queued_cost = 0;
  EXPECT_NEAR(estimate_eta(in), 0.75 / 0.0015, 1e-9);
  // 60 s after its report it is 9% further.
  in.running[0].since_report = 60;
  EXPECT_NEAR(estimate_eta(in), 0.75 / 0.0015 - 60, 1e-9);
  // Without a report (a case still settling its bed) there is no rate yet.
  in.running[0].reported = false;
  EXPECT_TRUE(std::isnan(estimate_eta(in)));
}

// A finished case and a running one that reported share one rate (cost per rank-second) for the
// queue; the running case is left with what its own rate leaves of it.
TEST(Eta, ReportsAndFinishedCasesShareTheRate) {
  EtaInput in;
  in.ranks = 1;
  in.done_cost = 1;
  in.done_rank_seconds = 1000;  // one case of cost 1 in 1000 s
  EtaInput::Running r{1, 300};
  r.reported = true;
  r.done_share = 0.2;
  r.call_share = 0.2;
  r.call_seconds = 300;  // this one runs slower: 0.2 of its cost in 300 s
  in.running = {r};
  in.queued_cost = 1;
  // The running case: 0.8 / (0.2 / 300) = 1200 s; the queued one at (1 + 0.2) / (1000 + 300).
  EXPECT_NEAR(estimate_eta(in), 1200 + 1300 / 1.2, 1e-9);
}

// Points whose cases run at different speeds for the same cost (a rigid bulk against a dynamic
// one): each point's queued cases are charged at its own rate once it has one. Cost 1 each, one
// rank. Rigid: one case done in 100 s. Dynamic: one running, 10% after 100 s (1000 s a case).
// Queued: one rigid, one dynamic; a third point not measured yet takes the rate of all.
TEST(Eta, EachPointAtItsOwnRate) {
  EtaInput in;
  in.ranks = 1;
  in.done_cost = 1;
  in.done_rank_seconds = 100;
  in.done_by_point["rigid"] = {1, 100};
  EtaInput::Running dynamic{1, 100};
  dynamic.reported = true;
  dynamic.done_share = dynamic.call_share = 0.1;
  dynamic.call_seconds = 100;
  dynamic.point = "dynamic";
  in.running = {dynamic};
  in.queued_by_point = {{"rigid", 1}, {"dynamic", 1}};
  EXPECT_NEAR(estimate_eta(in), 900 + 100 + 1000, 1e-9);
  // With one rate for all ((1 + 0.1) / 200 per second) the queue would cost 2 x 181.8 s: the
  // dynamic case's 1000 s would be missed.
  in.queued_by_point["other"] = 1;
  EXPECT_NEAR(estimate_eta(in), 900 + 100 + 1000 + 200 / 1.1, 1e-9);
  // Before its own report a running case of a measured point is credited at that point's rate.
  in.queued_by_point = {};
  EtaInput::Running rigid{1, 40};
  rigid.point = "rigid";
  in.running = {dynamic, rigid};
  EXPECT_NEAR(estimate_eta(in), 900 + 60, 1e-9);
}

// A case that says it is preparing (settling its bed, measuring β: hours on a paper-scale bed,
// outside the cost model) has done none of its protocol, whatever its age; once its protocol
// begins (one report at its first step, no rate of its own yet) it is credited from its share
// at that report. One case done in 1000 s (cost 1), one rank.
TEST(Eta, PreparingCaseHasDoneNoneOfItsCost) {
  EtaInput in;
  in.ranks = 1;
  in.done_cost = 1;
  in.done_rank_seconds = 1000;
  EtaInput::Running case_{1, 600};  // without a word: credited with 600 s of its 1000
  in.running = {case_};
  EXPECT_NEAR(estimate_eta(in), 400, 1e-9);
  in.running[0].preparing = true;  // preparing for 600 s: all of it left
  EXPECT_NEAR(estimate_eta(in), 1000, 1e-9);
  // Its protocol began 100 s ago at step 0 (a fresh case): 900 s left, its 600 s of
  // preparation not counted as protocol.
  in.running[0].preparing = false;
  in.running[0].reported = true;
  in.running[0].since_report = 100;
  EXPECT_NEAR(estimate_eta(in), 900, 1e-9);
  // A resumed case whose protocol began at 40% 100 s ago: 600 - 100 s left.
  in.running[0].done_share = 0.4;
  EXPECT_NEAR(estimate_eta(in), 500, 1e-9);
}

// Preparations (settled beds, measured βs) once one has been measured: 1800 rank-seconds per
// file (one case made its bed and β in 1800 s on a group of 2). One case done in 1000 s (cost 1)
// on one rank; 2 ranks run cases; one case of cost 1 queued, whose bed and β are 2 files still
// to make: 1000 + 2 x 1800 rank-seconds over 2 ranks.
TEST(Eta, PreparationsToComeAreChargedTheirMeasuredCost) {
  EtaInput in;
  in.ranks = 2;
  in.done_cost = 1;
  in.done_rank_seconds = 1000;
  in.queued_cost = 1;
  EXPECT_NEAR(estimate_eta(in), 500, 1e-9);  // none measured yet: left out, as before
  in.rank_seconds_per_file = 3600.0 / 2;
  in.queued_files = 2;
  EXPECT_NEAR(estimate_eta(in), (1000 + 2 * 1800) / 2.0, 1e-9);
  // A case of cost 1 preparing 2 files on one rank for 1000 s so far: 3600 - 1000 rank-seconds
  // of preparation left, then its whole protocol; it is the longest, so it sets the estimate.
  in.queued_files = 0;
  in.queued_cost = 0;
  in.running = {{1, 1000}};
  in.running[0].preparing = true;
  in.running[0].files = 2;
  in.running[0].preparing_for = 1000;
  EXPECT_NEAR(estimate_eta(in), 2600 + 1000, 1e-9);
  // A preparation past its measure is taken to end now: only the protocol is left.
  in.running[0].preparing_for = 5000;
  EXPECT_NEAR(estimate_eta(in), 1000, 1e-9);
  // On a group of 2 ranks it has 3600 - 2 x 1000 rank-seconds left, 800 s of the group's.
  in.running[0].preparing_for = 1000;
  in.running[0].ranks = 2;
  EXPECT_NEAR(estimate_eta(in), (1600 + 1000) / 2.0, 1e-9);
}

}  // namespace
}  // namespace tumble::campaign
