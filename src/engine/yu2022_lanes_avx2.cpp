// The Yu 2022 contact kernel (contact/yu2022.hpp) on four contacts at once, AVX2: compiled for
// AVX2 by the pragma (every target that builds this file does so) and called only after a
// run-time check (engine/contact_lanes.cpp). No FMA: every lane rounds exactly as yu2022_force
// does.
#pragma GCC target("avx2")
#include "engine/lanes_avx2.hpp"

namespace tumble::engine {
namespace {

using namespace avx2;

struct Yu2022Lanes {
  // The coefficients of Yu2022Pair (LaneInput::coefficient 0..4: kn, dn, kt, dt, mu), and -1/k_t,
  // which yu2022_force computes for a sliding contact: the same value, divided once.
  struct Table {
    __m256d kn, dn, kt, dt_tangential, mu, neg_inv_kt;
  };
  template <bool kOneSpecies>
  static Table make(const LaneInput& in) {
    Table t;
    t.kn = coefficient_set<kOneSpecies>(in.coefficient[0], in.one_type);
    t.dn = coefficient_set<kOneSpecies>(in.coefficient[1], in.one_type);
    t.kt = coefficient_set<kOneSpecies>(in.coefficient[2], in.one_type);
    t.dt_tangential = coefficient_set<kOneSpecies>(in.coefficient[3], in.one_type);
    t.mu = coefficient_set<kOneSpecies>(in.coefficient[4], in.one_type);
    t.neg_inv_kt = (-_mm256_set1_pd(1.0)) / t.kt;
    return t;
  }
  // Yu2022Law::lever: the radii.
  static void levers(__m256d ri, __m256d rj, __m256d, __m256d, __m256d& li, __m256d& lj) {
    li = ri;
    lj = rj;
  }
  // yu2022_force, line by line.
  template <bool kFriction, bool kOneSpecies>
  static V force(const Table& t, __m256i type, V nrm, __m256d overlap, V vrel, V& spring,
                 __m256d dt, V& ft) {
    const __m256d kn = lookup<kOneSpecies>(t.kn, type), dn = lookup<kOneSpecies>(t.dn, type);
    const __m256d vn = dot(vrel, nrm);
    const __m256d fn_mag = kn * overlap - dn * vn;
    V force = fn_mag * nrm;
    if constexpr (kFriction) {
      const __m256d kt = lookup<kOneSpecies>(t.kt, type);
      const __m256d dtt = lookup<kOneSpecies>(t.dt_tangential, type);
      const __m256d mu = lookup<kOneSpecies>(t.mu, type);
      const V vt = vrel - vn * nrm;
      spring = spring - dot(spring, nrm) * nrm;
      spring = spring + dt * vt;
      ft = neg(kt * spring + dtt * vt);
      const __m256d ft2 = dot(ft, ft);
      const __m256d cap = mu * abs(fn_mag);
      const __m256d sliding = _mm256_cmp_pd(ft2, cap * cap, _CMP_GT_OQ);
      if (_mm256_movemask_pd(sliding) != 0) {  // the Coulomb cap on some lane
        const V capped = (cap / _mm256_sqrt_pd(ft2)) * ft;
        const V capped_spring = lookup<kOneSpecies>(t.neg_inv_kt, type) * (capped + dtt * vt);
        ft = select(sliding, capped, ft);
        spring = select(sliding, capped_spring, spring);
      }
      force = force + ft;
    }
    return force;
  }
};

}  // namespace

LaneKernel yu2022_lanes_avx2(bool friction, bool periodic, bool one_species) {
  return lanes_for<Yu2022Lanes>(friction, periodic, one_species);
}

}  // namespace tumble::engine
