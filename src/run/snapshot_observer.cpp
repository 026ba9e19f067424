#include "run/snapshot_observer.hpp"

#include <cstdio>

#include "run/run_state.hpp"

namespace tumble {

void SnapshotObserver::after_step(RunState& s) {
  const std::int64_t step = s.sim.step_count();
  const auto k = static_cast<std::int64_t>(s.snapshots.size());  // step 0's is snapshot 0
  if (step == snapshot_step(k, interval_steps_) || step == s.total_steps) write(s);
}

void SnapshotObserver::write(RunState& s) {
  char name[64];
  std::snprintf(name, sizeof name, "snap_%06zu.h5", s.snapshots.size());
  io::write_snapshot(s.scene.output_dir + "/" + name, s.sim, s.scene);
  s.snapshots.push_back({name, s.sim.time(), static_cast<std::size_t>(s.particles)});
  if (s.lead()) io::write_xdmf(s.scene.output_dir, s.snapshots);
}

}  // namespace tumble
