#pragma once
// Stops an attempt that has run longer than its wall-clock limit (a campaign's per-case
// time_limit), checked every 16 steps, with TimeLimitError so that the manifest can say "time
// limit" rather than "run". The clock starts when the observer is made (the attempt's start);
// on a decomposed run rank 0's clock decides for every rank (one broadcast per check).
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <string>

#include "base/error.hpp"
#include "run/observer.hpp"
#include "run/run_state.hpp"

namespace tumble {

struct TimeLimitError : RunError {
  using RunError::RunError;
};

// Throws TimeLimitError if more than `limit_seconds` of wall time have passed since t0, as rank 0
// of `comm` measures it (collective over comm; MPI_COMM_NULL: this process); `where` ends the
// message ("at step 1200", "while settling the bed or measuring beta").
void check_time_limit(std::chrono::steady_clock::time_point t0, double limit_seconds, MPI_Comm comm,
                      const std::string& where);

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
