#pragma once
// One DEM realization end to end: the settled bed (run/settled_bed.hpp) or a checkpoint to continue
// from, then the protocol's time steps with a list of observers around them (run/observer.hpp:
// series, snapshots, checkpoints, drift grid, health, progress, and any the caller adds), and
// results.h5. The CLI's `tumble run` and the campaign manager call this.
#include <mpi.h>

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "analysis/radial_segregation.hpp"
#include "run/observer.hpp"
#include "run/settled_bed.hpp"
#include "scene/scene.hpp"

namespace tumble {

struct RunOptions {
  std::string restart_file;     // continue from this checkpoint
  bool resume = false;          // continue from output_dir/checkpoint.h5 if it exists
  std::int64_t max_steps = -1;  // stop after this many protocol steps (tests); -1 = whole run
  bool write_snapshots = true;
  std::ostream* log = nullptr;  // progress output (nullptr = silent; rank 0 only when parallel)
  // The caller's observers (not owned), called after the run's own series sampling and before
  // its snapshots and checkpoints (so a checkpoint never runs ahead of their saved state).
  // On a decomposed run every rank passes its own instances (run/observer.hpp).
  std::vector<Observer*> observers;
  // Called on the run's rank 0 when the protocol loop begins (its first step not yet taken)
  // and with each progress line (a campaign case's leader reports to the dispatcher from it);
  // empty: nothing beyond the line.
  std::function<void(const RunState&)> on_progress;
  // The ranks that run this realization together (domain decomposition); MPI_COMM_NULL or one
  // rank: serial. Every rank of `comm` calls run_realization with the same scene and options.
  MPI_Comm comm = MPI_COMM_NULL;
};

struct RunResult {
  std::string output_dir, results_file;
  std::int64_t steps = 0;  // protocol steps done in this call
  std::int64_t particles = 0;
  double wall_seconds = 0;  // protocol phase only
  double particle_steps_per_second = 0;
  analysis::Series series;
  bool reused_bed = false;
};

RunResult run_realization(const Scene& scene, const RunOptions& options);

// What a restart from the checkpoint at `path` checks before it begins, on this process alone:
// the file's contents, the scene it was written with against `scene`, its particles against the
// tumbler. Throws as the run would (CorruptInputError, InputError): `tumble run --check`.
void check_restart_from(const Scene& scene, const std::string& path);

}  // namespace tumble
