// The Yu 2022 contact kernel (contact/yu2022.hpp) on four contacts at once, AVX2. This file alone
// is compiled with -mavx2 (src/engine/CMakeLists.txt) and is called only after a run-time check
// (engine/contact_lanes.cpp). No -mfma: every lane rounds exactly as the plain kernel does, so the
// two paths agree bitwise (tests/test_lane_kernels.cpp). Each expression below mirrors one line of
// Simulation::pair_forces and yu2022_force, with the same association order.
#include <immintrin.h>

#include "engine/contact_lanes.hpp"

namespace tumble::engine {
namespace {

// Three packed coordinates of four contacts.
struct V {
  __m256d x, y, z;
};
inline V operator+(V a, V b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V operator-(V a, V b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V operator*(__m256d s, V a) { return {s * a.x, s * a.y, s * a.z}; }
inline V neg(V a) {
  const __m256d sign = _mm256_set1_pd(-0.0);
  return {_mm256_xor_pd(a.x, sign), _mm256_xor_pd(a.y, sign), _mm256_xor_pd(a.z, sign)};
}
inline __m256d dot(V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V cross(V a, V b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline V select(__m256d mask, V if_set, V if_clear) {
  return {_mm256_blendv_pd(if_clear.x, if_set.x, mask),
          _mm256_blendv_pd(if_clear.y, if_set.y, mask),
          _mm256_blendv_pd(if_clear.z, if_set.z, mask)};
}

// The first three doubles of each row: a masked load never touches the memory after the last
// particle of an array.
inline __m256i first_three() { return _mm256_setr_epi64x(-1, -1, -1, 0); }

// Gathers base[3 idx[l] + 0..2] for the four lanes and transposes them into x, y, z.
inline V load3(const double* base, const std::uint32_t* idx) {
  const __m256i m = first_three();
  const __m256d r0 = _mm256_maskload_pd(base + 3 * std::size_t{idx[0]}, m);
  const __m256d r1 = _mm256_maskload_pd(base + 3 * std::size_t{idx[1]}, m);
  const __m256d r2 = _mm256_maskload_pd(base + 3 * std::size_t{idx[2]}, m);
  const __m256d r3 = _mm256_maskload_pd(base + 3 * std::size_t{idx[3]}, m);
  const __m256d xz01 = _mm256_unpacklo_pd(r0, r1), y01 = _mm256_unpackhi_pd(r0, r1);
  const __m256d xz23 = _mm256_unpacklo_pd(r2, r3), y23 = _mm256_unpackhi_pd(r2, r3);
  return {_mm256_permute2f128_pd(xz01, xz23, 0x20), _mm256_permute2f128_pd(y01, y23, 0x20),
          _mm256_permute2f128_pd(xz01, xz23, 0x31)};
}

// The inverse of load3. Lanes are written in order 0..3; padded lanes repeat a contact with the
// same values.
inline void store3(double* base, const std::uint32_t* idx, V a) {
  const __m256i m = first_three();
  const __m256d zero = _mm256_setzero_pd();
  const __m256d xy02 = _mm256_unpacklo_pd(a.x, a.y), xy13 = _mm256_unpackhi_pd(a.x, a.y);
  const __m256d z02 = _mm256_unpacklo_pd(a.z, zero), z13 = _mm256_unpackhi_pd(a.z, zero);
  _mm256_maskstore_pd(base + 3 * std::size_t{idx[0]}, m, _mm256_permute2f128_pd(xy02, z02, 0x20));
  _mm256_maskstore_pd(base + 3 * std::size_t{idx[1]}, m, _mm256_permute2f128_pd(xy13, z13, 0x20));
  _mm256_maskstore_pd(base + 3 * std::size_t{idx[2]}, m, _mm256_permute2f128_pd(xy02, z02, 0x31));
  _mm256_maskstore_pd(base + 3 * std::size_t{idx[3]}, m, _mm256_permute2f128_pd(xy13, z13, 0x31));
}

// table[idx[l]] for the four lanes (the masked form: GCC 12 warns about the unmasked one's
// undefined source operand).
inline __m256d gather(const double* table, const void* idx) {
  const __m128i index = _mm_loadu_si128(static_cast<const __m128i*>(idx));
  const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  return _mm256_mask_i32gather_pd(_mm256_setzero_pd(), table, index, all, 8);
}

template <bool kFriction, bool kPeriodic>
void yu2022_lanes(const LaneInput& in) {
  TouchingContacts& c = *in.contacts;
  const std::size_t n = c.padded();
  double* out = c.out.data();
  const __m256d one = _mm256_set1_pd(1.0), dt = _mm256_set1_pd(in.dt);
  const __m256d period = _mm256_set1_pd(in.period);
  const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
  for (std::size_t b = 0; b < n; b += kLaneBlock) {
    const std::uint32_t* ii = c.i.data() + b;
    const std::uint32_t* jj = c.j.data() + b;
    // d = x_i - x_j (nearest image along a periodic axis)
    V d = load3(in.x, ii) - load3(in.x, jj);
    if constexpr (kPeriodic)
      d.z = d.z - period * _mm256_round_pd(d.z / period, _MM_FROUND_CUR_DIRECTION);
    const __m256d ri = gather(in.radius, ii), rj = gather(in.radius, jj);
    const __m256d rsum = ri + rj;
    const __m256d dist = _mm256_sqrt_pd(dot(d, d));
    const V nrm = (one / dist) * d;
    // Lever arms are the radii (Yu2022Law::lever).
    const V vrel = (load3(in.v, ii) - load3(in.v, jj)) -
                   cross(ri * load3(in.w, ii) + rj * load3(in.w, jj), nrm);
    const __m256d overlap = rsum - dist;
    const std::int32_t* type = c.type.data() + b;
    const __m256d kn = gather(in.kn, type), dn = gather(in.dn, type);
    // yu2022_force
    const __m256d vn = dot(vrel, nrm);
    const __m256d fn_mag = kn * overlap - dn * vn;
    V force = fn_mag * nrm;
    V tq_i{}, tq_j{};
    if constexpr (kFriction) {
      const __m256d kt = gather(in.kt, type), dtt = gather(in.dt_tangential, type);
      const __m256d mu = gather(in.mu, type);
      const std::uint32_t* kk = c.k.data() + b;
      const V vt = vrel - vn * nrm;
      V spring = load3(in.history, kk);
      spring = spring - dot(spring, nrm) * nrm;
      spring = spring + dt * vt;
      V ft = neg(kt * spring + dtt * vt);
      const __m256d ft2 = dot(ft, ft);
      const __m256d cap = mu * _mm256_and_pd(fn_mag, abs_mask);
      const __m256d sliding = _mm256_cmp_pd(ft2, cap * cap, _CMP_GT_OQ);
      if (_mm256_movemask_pd(sliding) != 0) {  // Coulomb cap on some lane
        const V capped = (cap / _mm256_sqrt_pd(ft2)) * ft;
        const V capped_spring = ((-one) / kt) * (capped + dtt * vt);
        ft = select(sliding, capped, ft);
        spring = select(sliding, capped_spring, spring);
      }
      store3(in.history, kk, spring);
      force = force + ft;
      const V tq = cross(ft, nrm);
      tq_i = ri * tq;
      tq_j = rj * tq;
    }
    _mm256_storeu_pd(out + 0 * n + b, force.x);
    _mm256_storeu_pd(out + 1 * n + b, force.y);
    _mm256_storeu_pd(out + 2 * n + b, force.z);
    if constexpr (kFriction) {
      _mm256_storeu_pd(out + 3 * n + b, tq_i.x);
      _mm256_storeu_pd(out + 4 * n + b, tq_i.y);
      _mm256_storeu_pd(out + 5 * n + b, tq_i.z);
      _mm256_storeu_pd(out + 6 * n + b, tq_j.x);
      _mm256_storeu_pd(out + 7 * n + b, tq_j.y);
      _mm256_storeu_pd(out + 8 * n + b, tq_j.z);
    }
  }
}

}  // namespace

LaneKernel yu2022_lanes_avx2(bool friction, bool periodic) {
  if (friction) return periodic ? &yu2022_lanes<true, true> : &yu2022_lanes<true, false>;
  return periodic ? &yu2022_lanes<false, true> : &yu2022_lanes<false, false>;
}

}  // namespace tumble::engine
