#pragma once
// The AVX2 toolkit of the lane kernels and their law-independent part: the scan for touching pairs,
// the geometry of four contacts at a time and the sums into the particles in the plain loop's
// order (engine/contact_lanes.hpp). A law's lane file (yu2022_lanes_avx2.cpp,
// rapaport2007_lanes_avx2.cpp) supplies its force on four lanes and instantiates run_lanes.
//
// Include only after `#pragma GCC target("avx2")` (see base/avx2.hpp).
#include "base/avx2.hpp"
#include "engine/contact_lanes.hpp"

namespace tumble::engine::avx2 {

using namespace tumble::avx2;

// A coefficient of the four species pairs (types 0..3) in one register, or, with one species,
// the one value in every lane; looked up per lane with a permutation (a gather from memory costs
// several times more on current CPUs).
template <bool kOneSpecies>
__m256d coefficient_set(const double* per_type, std::int32_t one_type) {
  if constexpr (kOneSpecies) return _mm256_set1_pd(per_type[one_type]);
  return _mm256_loadu_pd(per_type);
}
// The 32-bit lane indices that pick 64-bit element `type` of a register in each lane.
inline __m256i pair_lookup_index(__m128i type) {
  const __m256i twice = _mm256_slli_epi64(_mm256_cvtepu32_epi64(type), 1);
  return _mm256_or_si256(twice,
                         _mm256_slli_epi64(_mm256_add_epi64(twice, _mm256_set1_epi64x(1)), 32));
}
template <bool kOneSpecies>
__m256d lookup(__m256d set, __m256i index) {
  if constexpr (kOneSpecies) return set;
  return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(set), index));
}

// The lane kernel of a law: LawLanes has
//   struct Table (the law's coefficients as registers) and
//     template <bool kOneSpecies> static Table make(const LaneInput&);
//   static void levers(ri, rj, dist, rsum, li, lj);   the lever arms, as Law::lever
//   template <bool kFriction, bool kOneSpecies>
//   static V force(const Table&, __m256i type, V nrm, __m256d overlap, V vrel, V& history,
//                  __m256d dt, V& ft);                  as Law::force, on four lanes
// Each expression mirrors one line of Simulation::pair_forces, with the same association order.
template <class LawLanes, bool kFriction, bool kPeriodic, bool kOneSpecies>
void run_lanes(const LaneInput& in) {
  const std::size_t pairs = in.pairs;
  std::uint32_t* __restrict ci = in.contact_i;
  std::uint32_t* __restrict cj = in.contact_j;
  std::uint32_t* __restrict ck = in.contact_k;
  std::uint32_t* __restrict miss = in.miss;
  const __m256d one = _mm256_set1_pd(1.0), dt = _mm256_set1_pd(in.dt);
  const __m256d period = _mm256_set1_pd(in.period);
  // 1. Scan: a pair touches unless d² >= (r_i + r_j)² (as in pair_forces: a NaN distance counts
  // as touching, so that it reaches the forces and the health check).
  std::size_t m = 0, missed = 0;
  std::size_t k0 = 0;
  for (; k0 + 4 <= pairs; k0 += 4) {
    const std::uint32_t* ii = in.row + k0;
    const std::uint32_t* jj = in.nbr + k0;
    V d = load3(in.x, ii) - load3(in.x, jj);
    if constexpr (kPeriodic)
      d.z = d.z - period * _mm256_round_pd(d.z / period, _MM_FROUND_CUR_DIRECTION);
    const __m256d rsum = gather(in.radius, ii) + gather(in.radius, jj);
    const int apart = _mm256_movemask_pd(_mm256_cmp_pd(dot(d, d), rsum * rsum, _CMP_GE_OQ));
    const int touching = apart ^ 0xF;
    const __m128i kv =
        _mm_add_epi32(_mm_set1_epi32(static_cast<int>(k0)), _mm_setr_epi32(0, 1, 2, 3));
    pack_store(ci + m, load_index(ii), touching);
    pack_store(cj + m, load_index(jj), touching);
    pack_store(ck + m, kv, touching);
    m += static_cast<std::size_t>(__builtin_popcount(touching));
    if constexpr (kFriction) {
      pack_store(miss + missed, kv, apart);
      missed += static_cast<std::size_t>(__builtin_popcount(apart));
    }
  }
  for (; k0 < pairs; ++k0) {  // the last pairs, one at a time
    const std::uint32_t i = in.row[k0], j = in.nbr[k0];
    double d[3];
    for (int q = 0; q < 3; ++q) d[q] = in.x[3 * std::size_t{i} + q] - in.x[3 * std::size_t{j} + q];
    if constexpr (kPeriodic) d[2] -= in.period * __builtin_nearbyint(d[2] / in.period);
    const double rsum = in.radius[i] + in.radius[j];
    const bool apart = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= rsum * rsum;
    ci[m] = i;
    cj[m] = j;
    ck[m] = static_cast<std::uint32_t>(k0);
    m += !apart;
    miss[missed] = static_cast<std::uint32_t>(k0);
    missed += apart;
  }
  // A pair that does not touch starts its spring afresh (plain stores: see store_first_three).
  if constexpr (kFriction) {
    const __m256d zero = _mm256_setzero_pd();
    for (std::size_t q = 0; q < missed; ++q)
      store_first_three(in.history + 3 * std::size_t{miss[q]}, zero);
  }
  if (m == 0) return;
  const std::size_t count = m;
  for (; m % kLaneBlock != 0; ++m) {  // pad the last block with the last contact
    ci[m] = ci[count - 1];
    cj[m] = cj[count - 1];
    ck[m] = ck[count - 1];
  }

  const typename LawLanes::Table table = LawLanes::template make<kOneSpecies>(in);

  // 2 and 3. Forces and torques, four contacts at a time, then added to the particles in list
  // order: the force on the row particle summed over its row first, as pair_forces does.
  double* __restrict f = in.f;
  double* __restrict t = in.t;
  std::uint32_t row = ci[0];
  double f_row[3] = {0, 0, 0}, t_row[3] = {0, 0, 0};
  for (std::size_t b = 0; b < m; b += kLaneBlock) {
    const std::uint32_t* ii = ci + b;
    const std::uint32_t* jj = cj + b;
    // d = x_i - x_j (nearest image along a periodic axis)
    V d = load3(in.x, ii) - load3(in.x, jj);
    if constexpr (kPeriodic)
      d.z = d.z - period * _mm256_round_pd(d.z / period, _MM_FROUND_CUR_DIRECTION);
    const __m256d ri = gather(in.radius, ii), rj = gather(in.radius, jj);
    const __m256d rsum = ri + rj;
    const __m256d dist = _mm256_sqrt_pd(dot(d, d));
    const V nrm = (one / dist) * d;
    __m256d li, lj;
    LawLanes::levers(ri, rj, dist, rsum, li, lj);
    const V vrel = (load3(in.v, ii) - load3(in.v, jj)) -
                   cross(li * load3(in.w, ii) + lj * load3(in.w, jj), nrm);
    const __m256d overlap = rsum - dist;
    __m256i type = _mm256_setzero_si256();
    if constexpr (!kOneSpecies) {
      const __m128i si = _mm_i32gather_epi32(in.species, load_index(ii), 4);
      const __m128i sj = _mm_i32gather_epi32(in.species, load_index(jj), 4);
      type = pair_lookup_index(_mm_add_epi32(_mm_add_epi32(si, si), sj));
    }
    alignas(32) double lanes[9][4];
    V ft{}, spring{};
    if constexpr (kFriction) spring = load3(in.history, ck + b);
    const V force = LawLanes::template force<kFriction, kOneSpecies>(table, type, nrm, overlap,
                                                                     vrel, spring, dt, ft);
    if constexpr (kFriction) {
      store3(in.history, ck + b, spring);
      const V tq = cross(ft, nrm);
      const V tq_i = li * tq, tq_j = lj * tq;
      _mm256_store_pd(lanes[3], tq_i.x);
      _mm256_store_pd(lanes[4], tq_i.y);
      _mm256_store_pd(lanes[5], tq_i.z);
      _mm256_store_pd(lanes[6], tq_j.x);
      _mm256_store_pd(lanes[7], tq_j.y);
      _mm256_store_pd(lanes[8], tq_j.z);
    }
    _mm256_store_pd(lanes[0], force.x);
    _mm256_store_pd(lanes[1], force.y);
    _mm256_store_pd(lanes[2], force.z);
    const std::size_t real = count - b < kLaneBlock ? count - b : kLaneBlock;
    for (std::size_t l = 0; l < real; ++l) {
      const std::uint32_t i = ii[l], j = jj[l];
      if (i != row) {  // the previous row is complete
        for (int q = 0; q < 3; ++q) {
          f[3 * std::size_t{row} + q] += f_row[q];
          t[3 * std::size_t{row} + q] += t_row[q];
          f_row[q] = t_row[q] = 0;
        }
        row = i;
      }
      for (int q = 0; q < 3; ++q) {
        f_row[q] += lanes[q][l];
        f[3 * std::size_t{j} + q] -= lanes[q][l];
      }
      if constexpr (kFriction)
        for (int q = 0; q < 3; ++q) {
          t_row[q] += lanes[3 + q][l];
          t[3 * std::size_t{j} + q] += lanes[6 + q][l];
        }
    }
  }
  for (int q = 0; q < 3; ++q) {
    f[3 * std::size_t{row} + q] += f_row[q];
    t[3 * std::size_t{row} + q] += t_row[q];
  }
}

// The instantiation for a scene's options.
template <class LawLanes>
LaneKernel lanes_for(bool friction, bool periodic, bool one_species) {
  if (friction) {
    if (periodic)
      return one_species ? &run_lanes<LawLanes, true, true, true>
                         : &run_lanes<LawLanes, true, true, false>;
    return one_species ? &run_lanes<LawLanes, true, false, true>
                       : &run_lanes<LawLanes, true, false, false>;
  }
  if (periodic)
    return one_species ? &run_lanes<LawLanes, false, true, true>
                       : &run_lanes<LawLanes, false, true, false>;
  return one_species ? &run_lanes<LawLanes, false, false, true>
                     : &run_lanes<LawLanes, false, false, false>;
}

}  // namespace tumble::engine::avx2
