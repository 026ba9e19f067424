#pragma once
// How a long CM computation says how far it is: the fraction done, in [0, 1], non-decreasing,
// reported often (after each Newton start, seed, tracer block or manifold gap). The library never
// prints; the caller decides whether and how often to show it (app/progress_line.hpp). An empty
// Progress costs one branch per report.
#include <functional>

namespace tumble::cm {

using Progress = std::function<void(double done)>;

inline void report(const Progress& progress, double done) {
  if (progress) progress(done);
}

// The part [from, from + width] of a parent's progress, for a step inside a longer computation.
inline Progress sub_progress(const Progress& parent, double from, double width) {
  if (!parent) return {};
  return [parent, from, width](double done) { parent(from + width * done); };
}

}  // namespace tumble::cm
