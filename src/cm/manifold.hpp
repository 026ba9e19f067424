#pragma once
// Stable and unstable manifolds of hyperbolic periodic points (Yu 2022 App. B): seed a short
// segment (length 0.001 R) along the eigenvector at the point, advect it forward (unstable) or
// backward (stable) one protocol iteration at a time, and after every iteration re-insert points
// between neighbours farther apart than `spacing` (5e-5 R), each inserted point mapped from its
// parameter on the initial segment so that it lies exactly on the manifold.
#include <vector>

#include "cm/periodic.hpp"

namespace tumble::cm {

struct ManifoldOptions {
  double length = 1e-3;   // initial segment, centred on the point (both branches)
  double spacing = 5e-5;  // re-insertion threshold (3D distance)
  int iterations = 14;
  int initial_points = 41;
  std::size_t max_points = 200000;  // per iteration; tracing stops when exceeded
};

struct Manifold {
  int point = -1;  // index of the hyperbolic point in the periodic-point list
  bool unstable = true;
  int iterations_done = 0;
  bool truncated = false;  // stopped at max_points before `iterations`
  // Every recorded point: position, chart coordinates, iteration (0 = initial segment) and its
  // parameter on the initial segment (consecutive parameters are neighbours on the curve).
  std::vector<Vec3> xyz;
  std::vector<Vec2> chart;
  std::vector<int> iteration;
  std::vector<double> param;
};

Manifold trace_manifold(const SectionMap& map, const PeriodicPoint& h, bool unstable,
                        const ManifoldOptions& opt);

}  // namespace tumble::cm
