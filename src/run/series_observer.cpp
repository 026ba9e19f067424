#include "run/series_observer.hpp"

#include <cmath>

#include "analysis/radial_segregation.hpp"
#include "run/run_state.hpp"

namespace tumble {

SeriesObserver::SeriesObserver(const Scene& scene, std::int64_t every_steps) : every_(every_steps) {
  cylinder_.radius = scene.radius;
  cylinder_.length = scene.length;
  cylinder_.slice =
      scene.slice_width > 0 ? scene.slice_width : 2.5 * (scene.d_small - 0.5 * scene.size_spread);
  cylinder_.b3 = std::pow(scene.d_large / scene.d_small, 3);
  flow_.axis = scene.axis == Axis::x ? Vec3{1, 0, 0} : Vec3{0, 0, 1};  // protocol.axis: x or z
  flow_.radius = scene.radius;
  flow_.bin = 2 * scene.d_large;
  flow_.depth = scene.d_large;
}

void SeriesObserver::after_step(RunState& s) {
  if (s.sim.step_count() % every_ == 0) sample(s);
}

void SeriesObserver::sample(RunState& s) {
  const Scene& scene = s.scene;
  const Simulation& sim = s.sim;
  const double kinetic = sim.energy().kinetic;  // collective: before the gather, on all ranks
  const Particles& all = s.whole_bed();
  analysis::Series& series = s.series;
  // The frozen share: one value per sample of the run, or none (a run never rigid). A run resumed
  // with the other bulk option keeps them aligned: the samples of a dynamic part read 0.
  if (sim.rigid_bulk() || !series.frozen_fraction.empty()) {
    const std::size_t before = scene.cylinder() ? series.cylinder.time.size() : series.time.size();
    series.frozen_fraction.resize(before, 0.0);
    series.frozen_fraction.push_back(sim.rigid_bulk() ? sim.frozen_fraction() : 0.0);
  }
  if (scene.cylinder()) {
    analysis::sample_cylinder(all, cylinder_, sim.time(), scene.omega() * sim.time() / (2 * kPi),
                              kinetic, series.cylinder);
    return;
  }
  const std::size_t before = series.time.size();
  series.append(sim.time(), sim.protocol().iteration(sim.time()),
                analysis::radial_segregation(all, scene.radius), kinetic);
  if (scene.mode == Mode::rest) return;
  // The flowing layer, about the axis the wall turns about now: the repose angle and surface
  // speed, and their profile. A biaxial run measures it about each segment's axis (z, then x), and
  // keeps the segment and the turn into it, so each start of the flow about a new axis can be
  // read as a single-axis run's start is.
  const geometry::Protocol& protocol = sim.protocol();
  analysis::FlowFrame frame = flow_;
  if (scene.mode == Mode::biaxial) frame.axis = protocol.segment_axis(sim.time());
  const analysis::FlowProfile fp = analysis::flow_profile(all, all.size(), frame);
  // A run resumed from a checkpoint written before these were kept has fewer of them than
  // samples: NaN stands for the samples not taken.
  const double nan = std::nan("");
  series.repose_angle.resize(before, nan);
  series.surface_speed.resize(before, nan);
  if (series.profile_h.size() == fp.h.size())
    series.surface_profile.resize(before * fp.h.size(), nan);
  series.repose_angle.push_back(fp.repose_deg);
  series.surface_speed.push_back(fp.surface_speed);
  series.profile_h = fp.h;
  series.surface_profile.insert(series.surface_profile.end(), fp.speed.begin(), fp.speed.end());
  if (scene.mode == Mode::biaxial) {
    series.segment.resize(before, nan);
    series.segment_turn.resize(before, nan);
    series.segment.push_back(static_cast<double>(protocol.segment_count(sim.time())));
    series.segment_turn.push_back(protocol.segment_turn(sim.time()) * 180 / kPi);
  }
}

}  // namespace tumble
