#pragma once
// Shared helpers for the continuum-model tests.
#include <random>

#include "cm/flow_field.hpp"

namespace tumble::cm::test {

// Uniform random point of the bed (lower half ball) with rmin < |p| < rmax.
inline Vec3 random_bed_point(std::mt19937_64& rng, double rmin = 0.2, double rmax = 0.98) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  while (true) {
    const Vec3 p(u(rng), -std::abs(u(rng)), u(rng));
    if (p.norm() > rmin && p.norm() < rmax) return p;
  }
}

}  // namespace tumble::cm::test
