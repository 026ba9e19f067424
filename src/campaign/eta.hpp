#pragma once
// The campaign's time-to-finish estimate, from the cost model (particles x steps) and the wall
// time of the cases finished so far and of the running cases' progress reports, counted in
// rank-seconds so that cases run on groups of different sizes share one rate, and by point, so
// that points whose cases run at different speeds for their cost (a rigid bulk against a dynamic
// one, tiers, laws) are each charged at their own rate once one of their cases has measured it.
#include <map>
#include <string>
#include <vector>

namespace tumble::campaign {

struct EtaInput {
  struct Rate {
    double cost = 0;          // cost done
    double rank_seconds = 0;  // the wall seconds it took x the ranks of the groups
  };
  double done_cost = 0;          // cost of the cases finished successfully in this invocation
  double done_rank_seconds = 0;  // the sum of their wall times x the ranks of their groups
  std::map<std::string, Rate> done_by_point;  // the same, by point (empty: one rate for all)
  struct Running {
    double cost = 0;  // the case's cost
    double age = 0;   // seconds since it started
    int ranks = 1;    // its group's ranks
    // Its group leader's reports (CaseProgress), if any: the share of the protocol done at the
    // last one, the share done over a recent stretch of the run and the wall seconds it took (the
    // case's own rate), and the seconds since the last report.
    bool reported = false;
    double done_share = 0, call_share = 0, call_seconds = 0, since_report = 0;
    std::string point = {};  // its point's id ("": charged at the common rate)
    // It said it is preparing (settling its bed, measuring β) and its protocol has not begun:
    // none of its cost is done, whatever its age (the preparation is not in the cost model);
    // `files` it makes, for `preparing_for` seconds so far.
    bool preparing = false;
    int files = 0;
    double preparing_for = 0;
  };
  std::vector<Running> running;
  double queued_cost = 0;                         // cost of the cases not started yet, no point
  std::map<std::string, double> queued_by_point;  // the same, by point
  int ranks = 1;  // ranks that run cases (the world less any left idle)
  // The preparations (a settled bed, a measured β: files of the bed cache) are outside the cost
  // model: each costs the rank-seconds per file measured on the preparations that ended in this
  // invocation (0: none yet, and the preparations are left out), for the files the queued cases
  // will make (each once, whichever case makes it) and what a preparing case has left of its own.
  double rank_seconds_per_file = 0;
  int queued_files = 0;
};

// Seconds until the last case ends, NaN before any case has finished or reported. A rate is cost
// per rank-second (a group of k ranks is taken to run a case k times as fast as one rank, which
// domain decomposition approaches at the group sizes a campaign uses, docs/performance.md), over
// the cases done and the running cases' reported calls: a point's own where it has one, else all
// points' together; so a campaign of cases that take days has an estimate from the first
// progress reports. A running case that reported is left with what its own rate leaves of it;
// one that did not is credited with the work its age implies at its point's rate. So the
// estimate falls while cases run. The work left, in rank-seconds, is shared by all ranks; the
// result is at least the longest running case's remainder. Preparations are added as above.
double estimate_eta(const EtaInput& in);

}  // namespace tumble::campaign
