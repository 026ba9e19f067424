#pragma once
// Dynamic scheduling of cases over rank groups (docs/architecture.md, "Campaigns"). The world is
// split with MPI_Comm_split into groups of ranks_per_case; world rank 0 hands out cases, largest
// first, to whichever group asks, and records every assignment and result in the manifest.
//
// Rank 0 also computes: its own group's cases run in a second thread while the main thread keeps
// dispatching, so no core idles for the dispatcher. That thread makes no MPI calls (the engine is
// serial), which MPI_THREAD_FUNNELED allows; with a lower thread level rank 0 only dispatches.
// Every wait (rank 0 for messages, workers for work, everyone at the end) sleeps between polls,
// so an idle rank costs no CPU and ranks may oversubscribe cores.
#include <mpi.h>

#include <iosfwd>
#include <vector>

#include "campaign/case_runner.hpp"
#include "campaign/manifest.hpp"

namespace tumble::campaign {

struct ScheduleStats {
  int workers = 0;          // groups that ran cases
  int cases_run = 0;        // attempts finished in this invocation
  double loop_wall = 0;     // seconds from the first assignment to the last result
  double case_wall = 0;     // sum of the attempts' own wall times
  double overhead() const;  // 1 - case_wall / (workers * loop_wall): time not spent in cases
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
