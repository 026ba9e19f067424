// The integrator's passes on AVX2 lanes (engine/integrator_lanes.hpp): compiled for AVX2 by the
// pragma and called only after a run-time check. No FMA: every value rounds exactly as in
// Simulation::kick_drift_rows and half_kick_rows. No standard-library template either (see
// base/avx2.hpp).
#pragma GCC target("avx2")
#include <immintrin.h>

#include "engine/integrator_lanes.hpp"

namespace tumble::engine {
namespace {

// Four particles' Vec3 rows are twelve consecutive doubles, three registers:
// [0x 0y 0z 1x] [1y 1z 2x 2y] [2z 3x 3y 3z]. The passes are per component, so they run on these
// registers as they are; a per-particle scalar (1/m, 1/I) is spread to match them, and so is g.
struct Rows3 {
  __m256d a, b, c;
};
inline Rows3 load_rows(const double* p) {
  return {_mm256_loadu_pd(p), _mm256_loadu_pd(p + 4), _mm256_loadu_pd(p + 8)};
}
inline void store_rows(double* p, Rows3 r) {
  _mm256_storeu_pd(p, r.a);
  _mm256_storeu_pd(p + 4, r.b);
  _mm256_storeu_pd(p + 8, r.c);
}
// s = [s0 s1 s2 s3] as [s0 s0 s0 s1] [s1 s1 s2 s2] [s2 s3 s3 s3].
inline Rows3 spread(__m256d s) {
  return {_mm256_permute4x64_pd(s, 0x40), _mm256_permute4x64_pd(s, 0xA5),
          _mm256_permute4x64_pd(s, 0xFE)};
}
// g as the rows hold it: [gx gy gz gx] [gy gz gx gy] [gz gx gy gz].
inline Rows3 gravity_rows(const double* g) {
  return {_mm256_setr_pd(g[0], g[1], g[2], g[0]), _mm256_setr_pd(g[1], g[2], g[0], g[1]),
          _mm256_setr_pd(g[2], g[0], g[1], g[2])};
}
// v += s (m f + g), component by component, in the scalar loop's order: s * ((m * f) + g).
inline Rows3 kick(Rows3 v, __m256d s, Rows3 m, Rows3 f, Rows3 g) {
  return {v.a + s * (m.a * f.a + g.a), v.b + s * (m.b * f.b + g.b), v.c + s * (m.c * f.c + g.c)};
}
// v += s t, s spread per particle.
inline Rows3 add_scaled(Rows3 v, Rows3 s, Rows3 t) {
  return {v.a + s.a * t.a, v.b + s.b * t.b, v.c + s.c * t.c};
}
// |x - r|² of the four particles, as norm2 sums it: (dx² + dy²) + dz². The squares are moved
// from the rows into one register per component (three 128-bit swaps, three shuffles).
inline __m256d distance2(Rows3 x, Rows3 r) {
  const __m256d a = (x.a - r.a) * (x.a - r.a), b = (x.b - r.b) * (x.b - r.b),
                c = (x.c - r.c) * (x.c - r.c);
  const __m256d t0 = _mm256_permute2f128_pd(a, b, 0x30);  // 0x 0y 2x 2y
  const __m256d t1 = _mm256_permute2f128_pd(a, c, 0x21);  // 0z 1x 2z 3x
  const __m256d t2 = _mm256_permute2f128_pd(b, c, 0x30);  // 1y 1z 3y 3z
  const __m256d dx = _mm256_shuffle_pd(t0, t1, 0xA);      // 0x 1x 2x 3x
  const __m256d dy = _mm256_shuffle_pd(t0, t2, 0x5);      // 0y 1y 2y 3y
  const __m256d dz = _mm256_shuffle_pd(t1, t2, 0xA);      // 0z 1z 2z 3z
  return dx + dy + dz;
}
// The larger, as std::max(acc, d2) keeps it: acc unless acc < d2 (a NaN d2 leaves acc).
inline double larger(double acc, double d2) { return acc < d2 ? d2 : acc; }

template <bool kRotation>
double kick_drift_lanes(const IntegratorInput& in) {
  const std::size_t n = in.n;
  const Rows3 g = gravity_rows(in.gravity);
  const __m256d k = _mm256_set1_pd(in.kick), dt = _mm256_set1_pd(in.dt);
  const __m256d zero = _mm256_setzero_pd();
  const Rows3 zeros = {zero, zero, zero};
  const bool have_ref = in.has_ref;
  __m256d acc = zero;
  for (std::size_t i = 0; i < n; i += 4) {
    const std::size_t e = 3 * i;
    const Rows3 v = kick(load_rows(in.v + e), k, spread(_mm256_loadu_pd(in.inv_mass + i)),
                         load_rows(in.f + e), g);
    store_rows(in.v + e, v);
    if constexpr (kRotation) {
      const Rows3 s = spread(k * _mm256_loadu_pd(in.inv_inertia + i));
      store_rows(in.w + e, add_scaled(load_rows(in.w + e), s, load_rows(in.t + e)));
      store_rows(in.t + e, zeros);
    }
    const Rows3 x0 = load_rows(in.x + e);
    const Rows3 x = {x0.a + dt * v.a, x0.b + dt * v.b, x0.c + dt * v.c};
    store_rows(in.x + e, x);
    store_rows(in.f + e, zeros);
    // max(d2, acc): a NaN d2 leaves acc, as std::max(acc, d2) does.
    if (have_ref) acc = _mm256_max_pd(distance2(x, load_rows(in.x_ref + e)), acc);
  }
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, acc);
  double max_d2 = 0;
  for (int l = 0; l < 4; ++l) max_d2 = larger(max_d2, lanes[l]);
  return have_ref ? max_d2 : 1e300;
}

template <bool kRotation>
void half_kick_lanes(const IntegratorInput& in) {
  const std::size_t n = in.n;
  const Rows3 g = gravity_rows(in.gravity);
  const __m256d k = _mm256_set1_pd(in.kick);
  for (std::size_t i = 0; i < n; i += 4) {
    const std::size_t e = 3 * i;
    store_rows(in.v + e, kick(load_rows(in.v + e), k, spread(_mm256_loadu_pd(in.inv_mass + i)),
                              load_rows(in.f + e), g));
    if constexpr (kRotation) {
      const Rows3 s = spread(k * _mm256_loadu_pd(in.inv_inertia + i));
      store_rows(in.w + e, add_scaled(load_rows(in.w + e), s, load_rows(in.t + e)));
    }
  }
}

}  // namespace

double kick_drift_avx2(const IntegratorInput& in, bool rotation) {
  return rotation ? kick_drift_lanes<true>(in) : kick_drift_lanes<false>(in);
}

void half_kick_avx2(const IntegratorInput& in, bool rotation) {
  if (rotation)
    half_kick_lanes<true>(in);
  else
    half_kick_lanes<false>(in);
}

}  // namespace tumble::engine
