#pragma once
// One DEM realization end to end: obtain the settled bed (reuse the cached one, or fill and settle
// and cache it), run the protocol with progress lines, snapshots, checkpoints and the segregation
// time series, and write results.h5. The CLI's `tumble run` and the campaign manager call this.
#include <mpi.h>

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "analysis/radial_segregation.hpp"
#include "base/particles.hpp"
#include "scene/scene.hpp"

namespace tumble {

class Simulation;

// An in-situ analysis: called after every `every_steps` protocol steps (and once at the start of
// a fresh run) with the engine state. Analyses own their data; the engine knows nothing of them.
struct Observer {
  std::int64_t every_steps = 1;
  std::function<void(const Simulation&)> observe;
};

struct RunOptions {
  std::string restart_file;     // continue from this checkpoint
  bool resume = false;          // continue from output_dir/checkpoint.h5 if it exists
  std::int64_t max_steps = -1;  // stop after this many protocol steps (tests); -1 = whole run
  bool write_snapshots = true;
  std::ostream* log = nullptr;      // progress output (nullptr = silent; rank 0 only when parallel)
  std::vector<Observer> observers;  // serial runs only
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

// Settled bed for the scene: fill.bed_file, else the cache, else fill + settle + save to cache.
// With `comm` (collective): settled on all its ranks, the whole bed returned on every rank.
Particles settled_bed(const Scene& scene, std::ostream* log, bool* reused = nullptr,
                      MPI_Comm comm = MPI_COMM_NULL);
// Fills and settles a bed (no caching); the whole bed on every rank of `comm`.
Particles fill_and_settle(const Scene& scene, std::ostream* log, MPI_Comm comm = MPI_COMM_NULL);
// Rank r of `comm` keeps rows [N r / P, N (r+1) / P) of a bed every rank holds in full.
Particles share_of(const Particles& all, MPI_Comm comm);

RunResult run_realization(const Scene& scene, const RunOptions& options);

}  // namespace tumble
