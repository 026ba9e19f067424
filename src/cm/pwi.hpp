#pragma once
// The eps -> 0 limit of the CM: the cutting-and-shuffling piecewise isometry (PWI) of the
// hemispherical shell (Juarez et al. 2010; Park et al. 2016; docs/architecture.md, "Continuum model
// notes"). In every slice z = const a phase of duration t rotates the lower half-disc clockwise (as
// the CM bulk does) by t modulo pi: a point reaching the free surface at x = -s reappears at x =
// +s, which is the CM layer transit taking zero time.
#include "cm/flow_field.hpp"

namespace tumble::cm {

// Rotation about z for time t in its own frame, eps = 0. Points must have y <= 0.
Vec3 flow_z_pwi(const Vec3& p, double t);

}  // namespace tumble::cm
