#pragma once
// The run's time series (results.h5 /series, kept in checkpoints): for a sphere scene the
// large-particle fraction in the wall shell against the bed's (Yu 2022's radial segregation) and,
// when it turns, the flowing layer's repose angle, surface speed and speed profile about the axis
// of the protocol's segment (a biaxial run also keeps the segment and the turn into it); for a
// cylinder scene Rapaport's S_a, S_r, space-time profiles and bands. Sampled every
// output.analysis_interval (and at step 0); none when that interval is 0.
#include <cstdint>

#include "analysis/cylinder_segregation.hpp"
#include "analysis/flow_profile.hpp"
#include "run/observer.hpp"

namespace tumble {

struct Scene;

class SeriesObserver : public Observer {
 public:
  SeriesObserver(const Scene& scene, std::int64_t every_steps);
  void start(RunState& s) override { sample(s); }
  void after_step(RunState& s) override;

 private:
  void sample(RunState& s);
  std::int64_t every_;
  analysis::CylinderFrame cylinder_;
  analysis::FlowFrame flow_;
};

}  // namespace tumble
