#pragma once
// Stops an attempt that has run longer than its wall-clock limit (a campaign's per-case
// time_limit), checked every 16 steps, with TimeLimitError so that the manifest can say "time
// limit" rather than "run". The clock starts when the observer is made (the attempt's start);
// on a decomposed run rank 0's clock decides for every rank (one broadcast per check).
#include <chrono>
#include <cstdint>

#include "base/error.hpp"
#include "run/observer.hpp"
#include "run/run_state.hpp"

namespace tumble {

struct TimeLimitError : RunError {
  using RunError::RunError;
};

class TimeLimitObserver : public Observer {
 public:
  TimeLimitObserver(std::chrono::steady_clock::time_point t0, double limit_seconds)
      : t0_(t0), limit_(limit_seconds) {}
  void start(RunState& s) override { check(s); }
  void after_step(RunState& s) override {
    if (s.sim.step_count() % 16 == 0) check(s);
  }

 private:
  void check(const RunState& s) const;
  std::chrono::steady_clock::time_point t0_;
  double limit_;
};

}  // namespace tumble
