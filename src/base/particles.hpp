#pragma once
// Particle state as a structure of arrays: each field is one contiguous array, so the force and
// integration loops stream through exactly the data they use.
#include <cstdint>
#include <vector>

#include "base/vec3.hpp"

namespace tumble {

struct Particles {
  std::vector<Vec3> x;  // position (lab frame)
  std::vector<Vec3> v;  // velocity
  std::vector<Vec3> w;  // angular velocity
  std::vector<Vec3> f;  // force accumulator
  std::vector<Vec3> t;  // torque accumulator
  std::vector<double> radius;
  std::vector<double> inv_mass;
  std::vector<double> inv_inertia;  // 1 / (2/5 m r^2)
  std::vector<std::int32_t> species;
  std::vector<std::int64_t> id;  // global id, stable for the whole run
  // Tangential spring of the (single) wall contact of each particle; zero when not touching.
  std::vector<Vec3> wall_spring;

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n) {
    x.resize(n);
    v.resize(n);
    w.resize(n);
    f.resize(n);
    t.resize(n);
    radius.resize(n);
    inv_mass.resize(n);
    inv_inertia.resize(n);
    species.resize(n);
    id.resize(n);
    wall_spring.resize(n);
  }
  // Applies a permutation: new[k] = old[perm[k]] for every per-particle field. New per-particle
  // fields must be added here (and in io/checkpoint.cpp) - that is the one place to touch.
  void permute(const std::vector<std::uint32_t>& perm);
};

template <class T>
inline void apply_permutation(std::vector<T>& a, const std::vector<std::uint32_t>& perm,
                              std::vector<T>& scratch) {
  scratch.resize(a.size());
  for (std::size_t k = 0; k < perm.size(); ++k) scratch[k] = a[perm[k]];
  a.swap(scratch);
}

inline void Particles::permute(const std::vector<std::uint32_t>& perm) {
  std::vector<Vec3> s3;
  std::vector<double> sd;
  std::vector<std::int32_t> si;
  std::vector<std::int64_t> sl;
  apply_permutation(x, perm, s3);
  apply_permutation(v, perm, s3);
  apply_permutation(w, perm, s3);
  apply_permutation(f, perm, s3);
  apply_permutation(t, perm, s3);
  apply_permutation(wall_spring, perm, s3);
  apply_permutation(radius, perm, sd);
  apply_permutation(inv_mass, perm, sd);
  apply_permutation(inv_inertia, perm, sd);
  apply_permutation(species, perm, si);
  apply_permutation(id, perm, sl);
}

}  // namespace tumble
