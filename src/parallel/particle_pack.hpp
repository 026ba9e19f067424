#pragma once
// Particles as flat rows of doubles for MPI messages, generated from the field list
// (base/particle_fields.hpp): the whole state (fields with field::kMigrate: migration, ghost
// copies, gathers) or only what changes every step (field::kGhostRefresh: x, v, w). Ids (< 2^53)
// and species travel as doubles exactly.
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "base/particles.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace tumble::parallel {

// Doubles one value of a field type takes in a row (a type without one cannot be in the list).
template <class T>
constexpr int kDoublesOf = 0;
template <>
constexpr int kDoublesOf<Vec3> = 3;
template <>
constexpr int kDoublesOf<double> = 1;
template <>
constexpr int kDoublesOf<std::int32_t> = 1;
template <>
constexpr int kDoublesOf<std::int64_t> = 1;

// Width of a row of the fields with all bits of `Mask`, from the list at compile time.
template <unsigned Mask>
constexpr int row_doubles() {
  int n = 0;
  for_each_field_type<Mask>([&n](const char*, auto type) {
    using T = typename decltype(type)::type;
    static_assert(kDoublesOf<T> > 0, "a per-particle field type parallel/ cannot carry yet");
    n += kDoublesOf<T>;
  });
  return n;
}

constexpr int kStateDoubles = row_doubles<field::kMigrate>();
constexpr int kMotionDoubles = row_doubles<field::kGhostRefresh>();

inline void put(double*& o, const Vec3& a) {
  o[0] = a.x;
  o[1] = a.y;
  o[2] = a.z;
  o += 3;
}
inline void put(double*& o, double a) { *o++ = a; }
inline void put(double*& o, std::int32_t a) { *o++ = a; }
inline void put(double*& o, std::int64_t a) { *o++ = static_cast<double>(a); }

inline void take(const double*& in, Vec3& a) {
  a = {in[0], in[1], in[2]};
  in += 3;
}
inline void take(const double*& in, double& a) { a = *in++; }
inline void take(const double*& in, std::int32_t& a) { a = static_cast<std::int32_t>(*in++); }
inline void take(const double*& in, std::int64_t& a) { a = static_cast<std::int64_t>(*in++); }

// Appends row i of the fields with all bits of `Mask` to `o` (which has room for it). An empty
// column (the rigid bulk's, in a dynamic run: field::kRigidOnly) sends zeros.
template <unsigned Mask>
inline void put_row(double*& o, const Particles& p, std::size_t i) {
  for_each_field_flagged<Mask>(p, [&o, i](const char*, const auto& column, auto flags) {
    using T = typename std::decay_t<decltype(column)>::value_type;
    if constexpr ((flags & field::kRigidOnly) != 0) {
      put(o, column.empty() ? T{} : column[i]);
    } else {
      put(o, column[i]);
    }
  });
}
// Reads one row of the fields with all bits of `Mask` into particle k (an empty column skips its
// values).
template <unsigned Mask>
inline void take_row(const double*& in, Particles& p, std::size_t k) {
  for_each_field_flagged<Mask>(p, [&in, k](const char*, auto& column, auto flags) {
    using T = typename std::decay_t<decltype(column)>::value_type;
    if constexpr ((flags & field::kRigidOnly) != 0) {
      T value{};
      take(in, value);
      if (!column.empty()) column[k] = value;
    } else {
      take(in, column[k]);
    }
  });
}

// put_row() for rows that another core reads next (the ghost refresh's shared window,
// parallel/domain.cpp): non-temporal stores, which take the line from the reader's cache without
// first fetching it for ownership (the reader read these lines two steps before). Measured on the
// R35 bed at 2 ranks, ~730 rows a step: 9.5 µs with plain stores, 2.6-3.4 µs with these.
// stream_fence() once after the rows, before they are published.
template <unsigned Mask>
inline void put_row_streaming(double*& o, const Particles& p, std::size_t i) {
  double row[row_doubles<Mask>()];
  double* at = row;
  put_row<Mask>(at, p, i);
#if defined(__x86_64__)
  for (int d = 0; d < row_doubles<Mask>(); ++d) {
    long long bits;
    std::memcpy(&bits, &row[d], sizeof bits);
    _mm_stream_si64(reinterpret_cast<long long*>(o + d), bits);
  }
#else
  std::memcpy(o, row, sizeof row);
#endif
  o += row_doubles<Mask>();
}
inline void stream_fence() {
#if defined(__x86_64__)
  _mm_sfence();
#endif
}

inline void pack_state(const Particles& p, std::size_t i, std::vector<double>& out) {
  const std::size_t at = out.size();
  out.resize(at + kStateDoubles);
  double* o = out.data() + at;
  put_row<field::kMigrate>(o, p, i);
}

// Appends the particles of `in` (whole rows of kStateDoubles).
inline void unpack_state(const double* in, std::size_t rows, Particles& p) {
  std::size_t k = p.size();
  p.resize(k + rows);
  for (std::size_t r = 0; r < rows; ++r, ++k) take_row<field::kMigrate>(in, p, k);
}

}  // namespace tumble::parallel
