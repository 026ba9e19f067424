#pragma once
// The campaign's time-to-finish estimate, from the cost model (particles x steps) and the wall
// time of the cases finished so far.
#include <vector>

namespace tumble::campaign {

struct EtaInput {
  double done_cost = 0;  // cost of the cases finished successfully in this invocation
  double done_wall = 0;  // the sum of their wall times (seconds, one worker each)
  struct Running {
    double cost = 0;  // the case's cost
    double age = 0;   // seconds since it started
  };
  std::vector<Running> running;
  double queued_cost = 0;  // cost of the cases not started yet
  int workers = 1;         // rank groups running cases at once
};

// Seconds until the last case ends, NaN before any case has finished. A worker's rate is
// done_cost / done_wall (cost per worker-second); a running case is credited with the work its
// age implies at that rate, so the estimate falls while cases run (an estimate from finished
// cases alone grew while long cases ran, and counted nothing for them until they ended). The
// queue is shared by all workers; the result is at least the longest running case's remainder.
double estimate_eta(const EtaInput& in);

}  // namespace tumble::campaign
