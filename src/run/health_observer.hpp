#pragma once
// Stops a run whose state went bad (a non-finite value, a particle outside the tumbler) within
// 1000 steps of it happening, with the engine's diagnostic (Simulation::check_health).
#include "run/observer.hpp"
#include "run/run_state.hpp"

namespace tumble {

class HealthObserver : public Observer {
 public:
  void after_step(RunState& s) override {
    if (s.sim.step_count() % 1000 == 0) s.sim.check_health();
  }
};

}  // namespace tumble
