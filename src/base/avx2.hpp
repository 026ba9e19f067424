#pragma once
// AVX2 building blocks for code that works on four items at once (the lane kernels,
// engine/lanes_avx2.hpp, and the neighbour search's distance filter, neighbor/near_avx2.cpp):
// three-vectors of four lanes, gathers and transposes of Vec3 arrays, left-packing of indices.
//
// Include only after `#pragma GCC target("avx2")`, from a file that uses no standard-library
// template (an inline function instantiated there would be compiled for AVX2, and the linker may
// keep that copy for the whole program, which a CPU without AVX2 could not run). Call that code
// only where base/cpu_lanes.hpp says the CPU has AVX2.
#include <immintrin.h>

#include <cstddef>
#include <cstdint>

namespace tumble::avx2 {

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
inline __m256d abs(__m256d a) {
  return _mm256_and_pd(a, _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL)));
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

// The first three doubles of `v` to `at` with plain stores: a masked store (vmaskmovpd) is
// microcoded on AMD's cores and cost several times as much (docs/performance.md, "Masked stores").
inline void store_first_three(double* at, __m256d v) {
  _mm_storeu_pd(at, _mm256_castpd256_pd128(v));
  _mm_store_sd(at + 2, _mm256_extractf128_pd(v, 1));
}

// The inverse of load3. Lanes are written in order 0..3; padded lanes repeat a contact with the
// same values.
inline void store3(double* base, const std::uint32_t* idx, V a) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d xy02 = _mm256_unpacklo_pd(a.x, a.y), xy13 = _mm256_unpackhi_pd(a.x, a.y);
  const __m256d z02 = _mm256_unpacklo_pd(a.z, zero), z13 = _mm256_unpackhi_pd(a.z, zero);
  store_first_three(base + 3 * std::size_t{idx[0]}, _mm256_permute2f128_pd(xy02, z02, 0x20));
  store_first_three(base + 3 * std::size_t{idx[1]}, _mm256_permute2f128_pd(xy13, z13, 0x20));
  store_first_three(base + 3 * std::size_t{idx[2]}, _mm256_permute2f128_pd(xy02, z02, 0x31));
  store_first_three(base + 3 * std::size_t{idx[3]}, _mm256_permute2f128_pd(xy13, z13, 0x31));
}

// table[idx[l]] for the four lanes (the masked form: GCC 12 warns about the unmasked one's
// undefined source operand).
inline __m256d gather(const double* table, const void* idx) {
  const __m128i index = _mm_loadu_si128(static_cast<const __m128i*>(idx));
  const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  return _mm256_mask_i32gather_pd(_mm256_setzero_pd(), table, index, all, 8);
}

// Left-packing of four 32-bit lanes: kPack[mask] is the byte shuffle (_mm_shuffle_epi8) that moves
// the lanes whose bit is set to the front, in order, and zeroes the rest. A constant table: built
// at compile time, so that no AVX2 code runs at start-up on a CPU without it.
struct PackTable {
  alignas(16) std::uint8_t bytes[16][16];
};
constexpr PackTable make_pack_table() {
  PackTable table{};
  for (int mask = 0; mask < 16; ++mask) {
    int out = 0;
    for (int lane = 0; lane < 4; ++lane)
      if (mask & (1 << lane)) {
        for (int b = 0; b < 4; ++b)
          table.bytes[mask][4 * out + b] = static_cast<std::uint8_t>(4 * lane + b);
        ++out;
      }
    for (int b = 4 * out; b < 16; ++b) table.bytes[mask][b] = 0x80;
  }
  return table;
}
constexpr PackTable kPack = make_pack_table();

inline void pack_store(std::uint32_t* to, __m128i lanes, int mask) {
  const __m128i shuffle = _mm_load_si128(reinterpret_cast<const __m128i*>(kPack.bytes[mask]));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(to), _mm_shuffle_epi8(lanes, shuffle));
}
inline __m128i load_index(const std::uint32_t* p) {
  return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
}

}  // namespace tumble::avx2
