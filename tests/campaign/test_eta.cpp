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

}  // namespace
}  // namespace tumble::campaign
