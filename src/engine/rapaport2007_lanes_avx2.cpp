// The Rapaport 2007 contact kernel (contact/rapaport2007.hpp) on four contacts at once, AVX2:
// compiled for AVX2 by the pragma (every target that builds this file does so) and called only
// after a run-time check (engine/contact_lanes.cpp). No FMA: every lane rounds exactly as
// rapaport2007_force does; its branches become selects that keep the same values.
#pragma GCC target("avx2")
#include "engine/lanes_avx2.hpp"

namespace tumble::engine {
namespace {

using namespace avx2;

struct Rapaport2007Lanes {
  // The coefficients of Rapaport2007Pair (LaneInput::coefficient 0..5: kn, gn, gs, mu, kg,
  // ratchet).
  struct Table {
    __m256d kn, gn, gs, mu, kg, ratchet;
  };
  template <bool kOneSpecies>
  static Table make(const LaneInput& in) {
    Table t;
    t.kn = coefficient_set<kOneSpecies>(in.coefficient[0], in.one_type);
    t.gn = coefficient_set<kOneSpecies>(in.coefficient[1], in.one_type);
    t.gs = coefficient_set<kOneSpecies>(in.coefficient[2], in.one_type);
    t.mu = coefficient_set<kOneSpecies>(in.coefficient[3], in.one_type);
    t.kg = coefficient_set<kOneSpecies>(in.coefficient[4], in.one_type);
    t.ratchet = coefficient_set<kOneSpecies>(in.coefficient[5], in.one_type);
    return t;
  }
  // Rapaport2007Law::lever: r dist / rsum (the contact point divides the centre line in the
  // ratio of the diameters).
  static void levers(__m256d ri, __m256d rj, __m256d dist, __m256d rsum, __m256d& li, __m256d& lj) {
    li = ri * dist / rsum;
    lj = rj * dist / rsum;
  }
  // rapaport2007_force, line by line.
  template <bool kFriction, bool kOneSpecies>
  static V force(const Table& t, __m256i type, V nrm, __m256d overlap, V vrel, V& u, __m256d dt,
                 V& ft) {
    const __m256d kn = lookup<kOneSpecies>(t.kn, type), gn = lookup<kOneSpecies>(t.gn, type);
    const __m256d vn = dot(vrel, nrm);
    const __m256d fn_mag = kn * overlap - gn * vn;
    V force = fn_mag * nrm;
    if constexpr (kFriction) {
      const __m256d gs = lookup<kOneSpecies>(t.gs, type), mu = lookup<kOneSpecies>(t.mu, type);
      const __m256d kg = lookup<kOneSpecies>(t.kg, type);
      const __m256d ratchet = lookup<kOneSpecies>(t.ratchet, type);
      const __m256d zero = _mm256_setzero_pd();
      const V vs = vrel - vn * nrm;
      const __m256d cap = mu * abs(fn_mag);
      // Frictional damping, capped: -min(γ_s |v_s|, cap) v_s / |v_s| where v_s != 0. Both
      // arguments of the min are >= +0, where _mm256_min_pd and std::fmin agree.
      const __m256d vs2 = dot(vs, vs);
      const __m256d vs_mag = _mm256_sqrt_pd(vs2);
      const __m256d fs_mag = _mm256_min_pd(gs * vs_mag, cap);
      const V damping = (-fs_mag / vs_mag) * vs;
      ft = select(_mm256_cmp_pd(vs2, zero, _CMP_GT_OQ), damping, V{zero, zero, zero});
      // The accumulated displacement u and its ratchet.
      u = u + dt * vs;
      u = select(_mm256_cmp_pd(dot(u, u), ratchet * ratchet, _CMP_GT_OQ), V{zero, zero, zero}, u);
      // The restoring force -k_g u, capped.
      const __m256d fg2 = kg * kg * dot(u, u);
      const __m256d scale = _mm256_blendv_pd(_mm256_set1_pd(1.0), cap / _mm256_sqrt_pd(fg2),
                                             _mm256_cmp_pd(fg2, cap * cap, _CMP_GT_OQ));
      ft = select(_mm256_cmp_pd(fg2, zero, _CMP_GT_OQ), ft - (scale * kg) * u, ft);
      force = force + ft;
    }
    return force;
  }
};

}  // namespace

LaneKernel rapaport2007_lanes_avx2(bool friction, bool periodic, bool one_species) {
  return lanes_for<Rapaport2007Lanes>(friction, periodic, one_species);
}

}  // namespace tumble::engine
