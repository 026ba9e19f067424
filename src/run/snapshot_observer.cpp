#include "run/snapshot_observer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "run/run_state.hpp"

namespace tumble {

void SnapshotObserver::after_step(RunState& s) {
  const std::int64_t step = s.sim.step_count();
  // Whether this step is a snapshot step, from the step alone (not from how many were written:
  // a run resumed with another interval, or continued past an end that was written between two
  // snapshots, keeps to its own grid).
  const std::int64_t k = std::llround(static_cast<double>(step) / std::max(1.0, interval_steps_));
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
