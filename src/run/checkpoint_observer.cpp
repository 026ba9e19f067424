#include "run/checkpoint_observer.hpp"

#include "io/checkpoint.hpp"
#include "run/run_state.hpp"

namespace tumble {

bool CheckpointObserver::due(const RunState& s, std::int64_t step) const {
  return step % every_ == 0 || step == s.total_steps || step == s.end_step;
}

void CheckpointObserver::before_step(RunState& s, std::int64_t next) {
  if (due(s, next)) s.sim.request_rebuild();
}

void CheckpointObserver::after_step(RunState& s) {
  if (!due(s, s.sim.step_count())) return;
  s.sim.check_health();
  io::write_checkpoint(path_, s.sim, s.scene, s.series,
                       static_cast<std::int64_t>(s.snapshots.size()));
}

}  // namespace tumble
