#pragma once
// Which contact laws have a lane kernel (engine/contact_lanes.hpp), and the coefficients each
// reads, in the order its lane file (engine/*_lanes_avx2.cpp) expects them. A law without an entry
// runs the plain loop.
#include "contact/rapaport2007.hpp"
#include "contact/yu2022.hpp"
#include "engine/contact_lanes.hpp"

namespace tumble::engine {

template <class Law>
struct LawLanes {
  static constexpr bool kHas = false;
};

template <>
struct LawLanes<contact::Yu2022Law> {
  static constexpr bool kHas = true;
  static LaneKernel kernel(bool friction, bool periodic, bool one_species) {
    return yu2022_lanes_avx2(friction, periodic, one_species);
  }
  static constexpr int kCoefficients = 5;
  static void coefficients(const contact::Yu2022Pair& p, double* out) {
    const double c[kCoefficients] = {p.kn, p.dn, p.kt, p.dt, p.mu};
    for (int q = 0; q < kCoefficients; ++q) out[q] = c[q];
  }
};

template <>
struct LawLanes<contact::Rapaport2007Law> {
  static constexpr bool kHas = true;
  static LaneKernel kernel(bool friction, bool periodic, bool one_species) {
    return rapaport2007_lanes_avx2(friction, periodic, one_species);
  }
  static constexpr int kCoefficients = 6;
  static void coefficients(const contact::Rapaport2007Pair& p, double* out) {
    const double c[kCoefficients] = {p.kn, p.gn, p.gs, p.mu, p.kg, p.ratchet};
    for (int q = 0; q < kCoefficients; ++q) out[q] = c[q];
  }
};

}  // namespace tumble::engine
