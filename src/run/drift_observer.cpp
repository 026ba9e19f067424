#include "run/drift_observer.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>

#include "base/agreed_input.hpp"
#include "cm/drift_grid.hpp"
#include "run/run_state.hpp"

namespace tumble {

DriftObserver::DriftObserver(const Scene& scene)
    : meter_(30, scene.radius, deg2rad(scene.repose.deg), scene.omega(), scene.d_large),
      every_(std::max<std::int64_t>(1, std::llround(0.1 / scene.time_step()))) {}

void DriftObserver::after_step(RunState& s) {
  const Simulation& sim = s.sim;
  if (sim.step_count() % every_ != 0) return;
  const char* flowing = sim.protocol().periodic() ? "rotate" : "spin";
  if (std::string(sim.protocol().phase(sim.time())) == flowing) {
    // Into the run state, which the checkpoints keep (a restart brings its sums back there).
    if (s.drift.empty()) s.drift = meter_.zeros();
    meter_.sample(s.whole_bed(), sim.protocol().omega(sim.time()), s.drift);
  }
}

void DriftObserver::finish(RunState& s) {
  // Rank 0 writes the grid; its error (a full disk) is every rank's: thrown on rank 0 alone, the
  // others waited for it in the run's last collective call.
  on_rank_0_agreed(s.comm, [&] {
    const Scene& scene = s.scene;
    const std::string path = scene.output_dir + "/drift_grid.h5";
    const cm::DriftStatistics sums = s.drift.empty() ? meter_.zeros() : s.drift;
    const auto samples = static_cast<long long>(sums.samples());
    cm::write_drift_grid(
        path, meter_.grid(sums, "DEM scene " + scene.name + ", seed " + std::to_string(scene.seed) +
                                    ", " + std::to_string(samples) + " samples"));
    if (s.log) *s.log << "[run] drift grid (" << samples << " samples) in " << path << "\n";
  });
}

}  // namespace tumble
