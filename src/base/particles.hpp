#pragma once
// Particle state as a structure of arrays: each field is one contiguous array, so the force and
// integration loops stream through exactly the data they use. The fields are declared in one list,
// base/particle_fields.hpp; this file turns it into the struct and the operations on every field.
#include <cstdint>
#include <type_traits>
#include <vector>

#include "base/growth.hpp"
#include "base/particle_fields.hpp"
#include "base/vec3.hpp"

// A build with extra fields has a different Particles: it lives in its own inline namespace, so
// that an object file compiled without the extra fields cannot link against one compiled with them
// (for every function that takes or returns Particles) instead of silently disagreeing on the
// layout.
#ifdef TUMBLE_EXTRA_PARTICLE_FIELDS_HEADER
#define TUMBLE_PARTICLES_NAMESPACE_BEGIN inline namespace with_extra_fields {
#define TUMBLE_PARTICLES_NAMESPACE_END }
#else
#define TUMBLE_PARTICLES_NAMESPACE_BEGIN
#define TUMBLE_PARTICLES_NAMESPACE_END
#endif

namespace tumble {
TUMBLE_PARTICLES_NAMESPACE_BEGIN

struct Particles {
#define TUMBLE_DECLARE_FIELD(type, name, flags) std::vector<type> name;
  TUMBLE_ALL_PARTICLE_FIELDS(TUMBLE_DECLARE_FIELD)
#undef TUMBLE_DECLARE_FIELD

  // false: the columns of the rigid bulk's fields (field::kRigidOnly) are empty and stay empty
  // through resize() and permute() (a dynamic run's engine sets it; every other holder of
  // particles keeps every column).
  bool rigid_columns = true;

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n);
  // Frees every column's capacity beyond its size (a rank's share cut from the whole bed).
  void shrink_to_fit();
  // Applies a permutation: new[k] = old[perm[k]] for every field (the size stays).
  void permute(const std::vector<std::uint32_t>& perm);
  // Sets rigid_columns: sizes the rigid bulk's columns (zeros) or frees them.
  void set_rigid_columns(bool keep);
};

// Calls fn(name, column) for every field of `p` (Particles, const or not) whose flags contain all
// bits of `Mask` (field::kAny: every field), in list order. The flags are tested at compile time:
// the loop a caller writes over one particle's fields unrolls into plain code.
template <unsigned Mask, class P, class Fn>
inline void for_each_field(P& p, Fn&& fn) {
#define TUMBLE_VISIT_FIELD(type, name, flags) \
  if constexpr (((flags)&Mask) == Mask) fn(#name, p.name);
  TUMBLE_ALL_PARTICLE_FIELDS(TUMBLE_VISIT_FIELD)
#undef TUMBLE_VISIT_FIELD
}

// The same with the field's flags as a compile-time constant: fn(name, column, flags), flags a
// std::integral_constant<unsigned, ...>.
template <unsigned Mask, class P, class Fn>
inline void for_each_field_flagged(P& p, Fn&& fn) {
#define TUMBLE_VISIT_FIELD_FLAGGED(type, name, flags) \
  if constexpr (((flags)&Mask) == Mask)               \
    fn(#name, p.name, std::integral_constant<unsigned, flags>{});
  TUMBLE_ALL_PARTICLE_FIELDS(TUMBLE_VISIT_FIELD_FLAGGED)
#undef TUMBLE_VISIT_FIELD_FLAGGED
}

// The same, by type only (for sizes known at compile time): fn(name, FieldType<T>{}).
template <class T>
struct FieldType {
  using type = T;
};
template <unsigned Mask, class Fn>
constexpr void for_each_field_type(Fn&& fn) {
#define TUMBLE_VISIT_FIELD_TYPE(type, name, flags) \
  if constexpr (((flags)&Mask) == Mask) fn(#name, FieldType<type>{});
  TUMBLE_ALL_PARTICLE_FIELDS(TUMBLE_VISIT_FIELD_TYPE)
#undef TUMBLE_VISIT_FIELD_TYPE
}

// The permuted copy keeps the column's capacity: on more than one rank the ghosts are appended
// after the owned particles are sorted, and a column cut to its owned rows would then grow by
// std::vector's doubling (measured: the state's 180 B per particle became 360 on 2 ranks).
template <class T>
inline void apply_permutation(std::vector<T>& a, const std::vector<std::uint32_t>& perm,
                              std::vector<T>& scratch) {
  scratch.reserve(a.capacity());
  scratch.resize(a.size());
  for (std::size_t k = 0; k < perm.size(); ++k) scratch[k] = a[perm[k]];
  a.swap(scratch);
}

// Growing (ghosts and migrants arriving), a column takes 1/8 of headroom, not std::vector's
// doubling (base/growth.hpp); an empty one (a bed or checkpoint being read) takes what it is told.
inline void Particles::resize(std::size_t n) {
  for_each_field_flagged<field::kAny>(*this, [this, n](const char*, auto& column, auto flags) {
    if ((flags & field::kRigidOnly) && !rigid_columns) return;
    if (column.empty())
      column.resize(n);
    else
      resize_with_headroom(column, n);
  });
}

inline void Particles::shrink_to_fit() {
  for_each_field_flagged<field::kAny>(
      *this, [](const char*, auto& column, auto) { column.shrink_to_fit(); });
}

inline void Particles::permute(const std::vector<std::uint32_t>& perm) {
  for_each_field_flagged<field::kAny>(*this, [this, &perm](const char*, auto& column, auto flags) {
    if ((flags & field::kRigidOnly) && !rigid_columns) return;
    std::remove_reference_t<decltype(column)> scratch;
    apply_permutation(column, perm, scratch);
  });
}

inline void Particles::set_rigid_columns(bool keep) {
  rigid_columns = keep;
  const std::size_t n = size();
  for_each_field_flagged<field::kRigidOnly>(*this, [keep, n](const char*, auto& column, auto) {
    if (keep) {
      column.resize(n);
    } else {
      column.clear();
      column.shrink_to_fit();
    }
  });
}

TUMBLE_PARTICLES_NAMESPACE_END
}  // namespace tumble
