#pragma once
// Exact solution of the single-axis CM flow (flow_field.hpp) in its own frame. In each slice
// z = const the motion is along closed streamlines and integrable in closed form (docs/cm.md):
//
//   bulk:  solid-body rotation, (x, y) -> R(-t)(x, y), on circles s^2 = x^2 + y^2.
//   layer: streamline eta = eps sqrt(a^2 - x^2), eta = y + delta, parametrised by the phase
//          s = t/eps in [0, pi]:  x = -a cos s,  eta = eps a sin s.                  (Eq. L1)
//          Every transit lasts pi eps, whatever a (Christov et al. 2014; docs/architecture.md,
//          "Continuum model notes").
//   joins: a bulk circle s enters the layer at (-a, -delta(a)) and leaves it at (+a, -delta(a))
//          with a^2 = (s^2 - eps^2 (1 - z^2)) / (1 - eps^2): the same circle on both ends.
//
// The pieces are exposed for the MCM, which perturbs the layer part.
#include "cm/flow_field.hpp"

namespace tumble::cm {

// Position of a layer point on its streamline: half-length a and transit phase s in [0, pi].
struct LayerCoords {
  double a = 0, s = 0;
};
LayerCoords layer_coords(const Vec3& p, double eps);
// Inverse of layer_coords at axial position z.
Vec3 layer_point(double a, double s, double z, double eps);
// Where the bulk circle through p enters the layer, as the streamline half-length a, and how
// long the point takes to get there.
struct BulkEntry {
  double a = 0, time = 0;
};
BulkEntry bulk_entry(const Vec3& p, double eps);
// Solid-body rotation by time t: (x, y) -> R(-t)(x, y).
Vec3 rotate_bulk(const Vec3& p, double t);

// Interface crossings during a flow map, so that callers can tell which smooth branch of the
// piecewise-smooth map a point took (used by the Jacobian tests and volume bookkeeping).
struct Crossings {
  int entries = 0, exits = 0;
};

// Flow of the rotation about z for time t >= 0, eps > 0.
Vec3 flow_z_exact(const Vec3& p, double t, double eps, Crossings* crossings = nullptr);

}  // namespace tumble::cm
