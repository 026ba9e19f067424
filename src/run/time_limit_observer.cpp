#include "run/time_limit_observer.hpp"

#include <string>

namespace tumble {

void TimeLimitObserver::check(const RunState& s) const {
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  if (el > limit_)
    throw TimeLimitError("time limit: the attempt ran " + std::to_string(el) +
                         " s wall, more than its limit of " + std::to_string(limit_) +
                         " s (at step " + std::to_string(s.sim.step_count()) + ")");
}

}  // namespace tumble
