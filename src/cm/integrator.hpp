#pragma once
// Reference integrator of the single-axis CM velocity field, used only to check the exact map.
// The streamwise velocity jumps at the interface y = -delta (bulk -delta vs layer 0), so a
// fixed-step scheme across it is first order (docs/architecture.md, "Continuum model notes"). This
// one integrates each region with its own smooth field (adaptive Dormand-Prince 5(4)) and locates
// the crossing of g = y + delta(x, z) = 0 as an event before switching fields.
#include "cm/flow_field.hpp"

namespace tumble::cm {

struct IntegratorOptions {
  double tol = 1e-12;       // per-step error bound (mixed absolute/relative)
  double h_initial = 1e-3;  // first trial step
  long max_steps = 10'000'000;
};

struct IntegratorStats {
  long steps = 0, rejected = 0, events = 0;
};

// Flow of the rotation about z for time t >= 0, in its own frame.
Vec3 flow_z_integrated(const Vec3& p, double t, double eps, const IntegratorOptions& opt = {},
                       IntegratorStats* stats = nullptr);

}  // namespace tumble::cm
