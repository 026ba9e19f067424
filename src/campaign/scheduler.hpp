#pragma once
// Dynamic scheduling of cases over rank groups (docs/campaign.md, "Rank groups"). World rank 0
// hands out cases, largest first: each case goes to a group of the ranks its point asks for
// (campaign.ranks_per_case, or its sweep's), placed by RankPool on consecutive free ranks; every
// rank of the group receives the assignment, the group makes its communicator with
// MPI_Comm_create_group (collective over the group only, so other groups compute undisturbed),
// runs the case decomposed exactly as `mpirun -n k tumble run` does, and its leader reports the
// outcome. Rank 0 records every assignment and result in the manifest. A remote group holds its
// next case too while the queue is longer than there are groups, so it never waits for rank 0's
// next poll between cases.
//
// Rank 0 also computes, without threads: while its own group runs a case, the run calls the
// dispatcher's poll after every time step (and every 200 settling steps): one MPI_Iprobe when
// there is nothing to do. The time spent there is measured (ScheduleStats::poll_seconds). Every
// other wait (idle ranks for work, everyone at the end) sleeps between polls, so an idle rank
// costs no CPU and ranks may oversubscribe cores.
#include <mpi.h>

#include <iosfwd>
#include <string>
#include <vector>

#include "campaign/case_runner.hpp"
#include "campaign/manifest.hpp"

namespace tumble::campaign {

struct ScheduleStats {
  int ranks = 0;              // world ranks that could run cases
  int cases_run = 0;          // attempts finished in this invocation
  double loop_wall = 0;       // seconds from the first assignment to the last result
  double rank_seconds = 0;    // sum over attempts of wall time x the ranks of their group
  double local_seconds = 0;   // rank 0's time inside its own group's cases
  double poll_seconds = 0;    // ... of which spent dispatching (polls between steps)
  long long polls = 0;        // polls made from inside those cases
  int stop_signal = 0;        // a stop request ended the invocation early (0: it did not)
  int stopped = 0;            // cases that stopped at a checkpoint on that request
  int stopped_preparing = 0;  // cases stopped before their protocol began (no run checkpoint)
  int not_started = 0;        // cases still queued when it came
  // A manifest line could not be written (Dispatcher::halted): the error, how many cases were
  // still queued, and the lines (JSON) that could not be written even at the end.
  std::string manifest_error;
  int halted_not_started = 0;
  std::vector<std::string> unwritten;
  double overhead() const;        // 1 - rank_seconds / (ranks * loop_wall): rank time not in cases
  double dispatch_share() const;  // poll_seconds / local_seconds
};

struct ScheduleInput {
  std::vector<CaseTask> tasks;  // rank 0: what to run, in order (largest first)
  int total = 0, done_before = 0, failed_before = 0;  // progress counts of the slice
  ManifestWriter* manifest = nullptr;                 // rank 0
  std::string slice;                                  // "i/n"
  std::ostream* out = nullptr;                        // rank 0: progress lines
  bool quiet = false;                                 // progress lines only every progress_interval
};

// Collective over `world`. Returns statistics on rank 0 (zeros elsewhere).
ScheduleStats schedule(const CaseContext& ctx, MPI_Comm world, const ScheduleInput& in);

// A barrier that sleeps while it waits (a plain MPI_Barrier spins on a core).
void sleeping_barrier(MPI_Comm comm);

}  // namespace tumble::campaign
