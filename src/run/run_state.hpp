#pragma once
// What the observers of one realization share: the scene and the engine, the run's length, the
// time series and the list of snapshots written (both kept in checkpoints), and a view of the
// whole bed for analyses of a domain-decomposed run.
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "analysis/radial_segregation.hpp"
#include "base/particles.hpp"
#include "cm/drift_grid.hpp"
#include "engine/simulation.hpp"
#include "io/snapshot.hpp"
#include "scene/scene.hpp"

namespace tumble {

struct RunState {
  RunState(const Scene& scene, Simulation& sim, MPI_Comm comm, std::ostream* log)
      : scene(scene), sim(sim), comm(comm), log(log) {}

  const Scene& scene;
  Simulation& sim;
  MPI_Comm comm;                 // MPI_COMM_NULL when serial
  std::ostream* log;             // progress output; nullptr on ranks other than the run's rank 0
  bool lead() const;             // rank 0 of the run: writes the serial files
  std::int64_t total_steps = 0;  // the whole protocol
  std::int64_t end_step = 0;     // where this call stops (--max-steps)
  std::int64_t first_step = 0;   // where this call started (a restart's step)
  std::int64_t particles = 0;    // in the whole realization
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  analysis::Series series;
  cm::DriftStatistics drift;  // output.drift_grid = on: the grid's sums so far (checkpointed)
  std::vector<io::SnapshotEntry> snapshots;

  // Every particle of the realization, sorted by id: the engine's own array when serial, else
  // gathered (collective: every rank calls it at the same steps) once per step however many
  // observers ask.
  const Particles& whole_bed();

 private:
  Particles gathered_;
  std::int64_t gathered_at_ = -1;
};

}  // namespace tumble
