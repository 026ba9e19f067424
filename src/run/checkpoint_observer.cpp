#include "run/checkpoint_observer.hpp"

#include <mpi.h>

#include "io/checkpoint.hpp"
#include "run/run_state.hpp"

namespace tumble {

bool CheckpointObserver::due(const RunState& s, std::int64_t step) const {
  return step % every_ == 0 || step == s.total_steps || step == s.end_step;
}

void CheckpointObserver::start(RunState& s) { rebuilds_seen_ = s.sim.rebuilds(); }

void CheckpointObserver::before_step(RunState& s, std::int64_t next) {
  if (due(s, next)) s.sim.request_rebuild();
}

bool CheckpointObserver::wall_due(const RunState& s) {
  if (wall_ <= 0) return false;
  const std::uint64_t rebuilds = s.sim.rebuilds();
  if (rebuilds == rebuilds_seen_) return false;  // not a step that rebuilt the list
  rebuilds_seen_ = rebuilds;
  int late = std::chrono::duration<double>(Clock::now() - last_).count() >= wall_ ? 1 : 0;
  if (s.comm != MPI_COMM_NULL) MPI_Bcast(&late, 1, MPI_INT, 0, s.comm);
  return late != 0;
}

void CheckpointObserver::after_step(RunState& s) {
  if (due(s, s.sim.step_count()) || wall_due(s)) write(s);
  rebuilds_seen_ = s.sim.rebuilds();
}

void CheckpointObserver::write(RunState& s) {
  s.sim.check_health();
  io::write_checkpoint(path_, s.sim, s.scene, s.series,
                       static_cast<std::int64_t>(s.snapshots.size()), s.drift);
  last_ = Clock::now();
}

}  // namespace tumble
