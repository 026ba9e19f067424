#pragma once
// The campaign's time-to-finish estimate, from the cost model (particles x steps) and the wall
// time of the cases finished so far, counted in rank-seconds so that cases run on groups of
// different sizes share one rate.
#include <vector>

namespace tumble::campaign {

struct EtaInput {
  double done_cost = 0;          // cost of the cases finished successfully in this invocation
  double done_rank_seconds = 0;  // the sum of their wall times x the ranks of their groups
  struct Running {
    double cost = 0;  // the case's cost
    double age = 0;   // seconds since it started
    int ranks = 1;    // its group's ranks
  };
  std::vector<Running> running;
  double queued_cost = 0;  // cost of the cases not started yet
  int ranks = 1;           // ranks that run cases (the world less any left idle)
};

// Seconds until the last case ends, NaN before any case has finished. The rate is done_cost /
// done_rank_seconds (cost per rank-second: a group of k ranks is taken to run a case k times as
// fast as one rank, which domain decomposition approaches at the group sizes a campaign uses,
// docs/performance.md); a running case is credited with the work its age implies at that rate,
// so the estimate falls while cases run. The queue is shared by all ranks; the result is at least
// the longest running case's remainder.
double estimate_eta(const EtaInput& in);

}  // namespace tumble::campaign
