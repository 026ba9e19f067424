#pragma once
// The MCM's drift grid (output.drift_grid = on): large particles at the free surface of the
// flowing layer, every 0.1 s of the protocol's "rotate" segments (or of a constant spin), as
// Yu 2022 App. A; written to drift_grid.h5 when the run ends (run/drift_measure.hpp). The sums
// so far live in RunState::drift, which checkpoints keep: a killed and resumed run ends with the
// grid of an uninterrupted one.
#include <cstdint>

#include "run/drift_measure.hpp"
#include "run/observer.hpp"

namespace tumble {

struct Scene;

class DriftObserver : public Observer {
 public:
  explicit DriftObserver(const Scene& scene);
  void after_step(RunState& s) override;
  void finish(RunState& s) override;

 private:
  analysis::DriftGridMeter meter_;
  std::int64_t every_;
};

}  // namespace tumble
