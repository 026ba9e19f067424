#pragma once
// Stable and unstable manifolds of hyperbolic periodic points (Yu 2022 App. B): seed a short
// segment (length 0.001 R) along the eigenvector at the point, advect it forward (unstable) or
// backward (stable) one protocol iteration at a time, and after every iteration re-insert points
// between neighbours farther apart than `spacing` (5e-5 R), each inserted point mapped from its
// parameter on the initial segment so that it lies exactly on the manifold.
//
// A manifold stretches by |lambda| per period of its point, so the points needed grow
// geometrically ((57 deg, 57 deg), period 1, lambda = -5.2: ~10^12 for 14 iterations).
// `max_points` bounds what one manifold records over all its iterations together: tracing stops
// before an iteration whose curve would not fit, so the memory of a run is known before it starts
// (manifold_memory_bytes).
#include <vector>

#include "cm/periodic.hpp"
#include "cm/progress.hpp"

namespace tumble::cm {

struct ManifoldOptions {
  double length = 1e-3;   // initial segment, centred on the point (both branches)
  double spacing = 5e-5;  // re-insertion threshold (3D distance)
  int iterations = 14;
  int initial_points = 41;
  std::size_t max_points = 200000;  // recorded per manifold, all iterations together
};

struct Manifold {
  int point = -1;  // index of the hyperbolic point in the periodic-point list
  bool unstable = true;
  int iterations_done = 0;
  bool truncated = false;  // stopped before `iterations`: the next one exceeded max_points
  // Every recorded point: position, chart coordinates, iteration (0 = initial segment) and its
  // parameter on the initial segment (consecutive parameters are neighbours on the curve).
  std::vector<Vec3> xyz;
  std::vector<Vec2> chart;
  std::vector<int> iteration;
  std::vector<double> param;
};

// Progress: the larger of the iterations done and the share of max_points used.
Manifold trace_manifold(const SectionMap& map, const PeriodicPoint& h, bool unstable,
                        const ManifoldOptions& opt, const Progress& progress = {});

// Bytes trace_manifold and the writer hold at their peak for one manifold: per point of
// max_points, 52 B recorded (position, chart point, iteration, parameter), doubled for vector
// growth; 32 B for the current curve and twice that for the next one being built; 44 B of the
// writer's copies (flat positions, chart points, iterations; counted together, as the allocator
// need not give one back to the system before the next).
double manifold_memory_bytes(const ManifoldOptions& opt);

}  // namespace tumble::cm
