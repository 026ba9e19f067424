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
    // Its group leader's last report (CaseProgress), if any: the share of the protocol done at
    // the report, the share this call of the run did and the wall seconds it took, and the
    // seconds since the report.
    bool reported = false;
    double done_share = 0, call_share = 0, call_seconds = 0, since_report = 0;
  };
  std::vector<Running> running;
  double queued_cost = 0;  // cost of the cases not started yet
  int ranks = 1;           // ranks that run cases (the world less any left idle)
};

// Seconds until the last case ends, NaN before any case has finished or reported. The rate is
// cost per rank-second (a group of k ranks is taken to run a case k times as fast as one rank,
// which domain decomposition approaches at the group sizes a campaign uses, docs/performance.md)
// over the cases done and the running cases' reported calls together, so a campaign of cases
// that take days has an estimate from the first progress reports. A running case that reported
// is left with what its own rate leaves of it; one that did not is credited with the work its
// age implies at the common rate. So the estimate falls while cases run. The queue is shared by
// all ranks; the result is at least the longest running case's remainder.
double estimate_eta(const EtaInput& in);

}  // namespace tumble::campaign
