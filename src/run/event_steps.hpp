#pragma once
// The steps between two of a run's periodic events (checkpoints, segregation samples), from their
// interval in simulated seconds.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace tumble {

// Steps between two events `interval` simulated seconds apart at time step dt (interval 0: once
// per `fallback` seconds, an iteration), at least 1. Clamped before rounding: an interval of 1e9 s
// ("never") at dt = 1e-10 s is 1e19 steps, past what llround can return; it gave LLONG_MIN, and
// the max with 1 made it every step.
inline std::int64_t steps_between_events(double interval, double dt, double fallback) {
  const double t = interval > 0 ? interval : fallback;
  return std::max<std::int64_t>(1, std::llround(std::min(t / dt, 1e18)));
}

}  // namespace tumble
