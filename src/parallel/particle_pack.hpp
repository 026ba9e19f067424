#pragma once
// Particles as flat rows of doubles for MPI messages: the whole state (migration, gathers) or
// only what changes every step (ghost refresh: x, v, w). Ids (< 2^53) and species travel as
// doubles exactly. A new per-particle field must be added here, in Particles::permute and in
// io/checkpoint.cpp.
#include <cstdint>
#include <vector>

#include "base/particles.hpp"

namespace tumble::parallel {

constexpr int kStateDoubles = 23;  // every field of Particles
constexpr int kMotionDoubles = 9;  // x, v, w

inline void put(double*& o, const Vec3& a) {
  o[0] = a.x;
  o[1] = a.y;
  o[2] = a.z;
  o += 3;
}
inline Vec3 take(const double*& in) {
  const Vec3 a{in[0], in[1], in[2]};
  in += 3;
  return a;
}

inline void pack_state(const Particles& p, std::size_t i, std::vector<double>& out) {
  const std::size_t at = out.size();
  out.resize(at + kStateDoubles);
  double* o = out.data() + at;
  put(o, p.x[i]);
  put(o, p.v[i]);
  put(o, p.w[i]);
  put(o, p.f[i]);
  put(o, p.t[i]);
  put(o, p.wall_spring[i]);
  o[0] = p.radius[i];
  o[1] = p.inv_mass[i];
  o[2] = p.inv_inertia[i];
  o[3] = p.species[i];
  o[4] = static_cast<double>(p.id[i]);
}

// Appends the particles of `in` (whole rows of kStateDoubles).
inline void unpack_state(const double* in, std::size_t rows, Particles& p) {
  std::size_t k = p.size();
  p.resize(k + rows);
  for (std::size_t r = 0; r < rows; ++r, ++k) {
    p.x[k] = take(in);
    p.v[k] = take(in);
    p.w[k] = take(in);
    p.f[k] = take(in);
    p.t[k] = take(in);
    p.wall_spring[k] = take(in);
    p.radius[k] = in[0];
    p.inv_mass[k] = in[1];
    p.inv_inertia[k] = in[2];
    p.species[k] = static_cast<std::int32_t>(in[3]);
    p.id[k] = static_cast<std::int64_t>(in[4]);
    in += 5;
  }
}

}  // namespace tumble::parallel
