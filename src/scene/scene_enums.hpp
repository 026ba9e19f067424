#pragma once
// The categorical scene keys as enums: parsed once from their names (scene.cpp refuses any other
// name, naming the key and the choices), compared as enums everywhere else. Each enum lists its
// names in EnumNames, in the order of its values; the names are what scene files, provenance text
// and cached-bed keys hold.
#include <array>
#include <cstddef>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

namespace tumble {

enum class Shape { sphere, cylinder };  // cylinder: horizontal, axis along z
enum class OnOff { off, on };
enum class Start { mixed, large_top, large_xneg, large_zneg };
enum class Mode { biaxial, single_axis, rest };
enum class Axis { x, z };
enum class Integrator { velocity_verlet, leapfrog };
enum class Tier { standard, reference, fast, preview };  // scene/fidelity.hpp
// fidelity.bulk: every particle integrated, or the calm bulk carried rigidly with the wall
// (engine/rigid_bulk.cpp).
enum class Bulk { dynamic, rigid };
// fidelity.bulk_segment_thaw: which changes of the protocol's segment thaw the rigid bulk: none,
// every one, or only those where the tumbler's Ω changes (not a tilt becoming its rotation).
enum class SegmentThaw { off, on, omega };

template <class E>
struct EnumNames;  // static constexpr std::array<const char*, N> names: by value
template <>
struct EnumNames<Shape> {
  static constexpr std::array<const char*, 2> names = {"sphere", "cylinder"};
};
template <>
struct EnumNames<OnOff> {
  static constexpr std::array<const char*, 2> names = {"off", "on"};
};
template <>
struct EnumNames<Start> {
  static constexpr std::array<const char*, 4> names = {"mixed", "large_top", "large_xneg",
                                                       "large_zneg"};
};
template <>
struct EnumNames<Mode> {
  static constexpr std::array<const char*, 3> names = {"biaxial", "single_axis", "rest"};
};
template <>
struct EnumNames<Axis> {
  static constexpr std::array<const char*, 2> names = {"x", "z"};
};
template <>
struct EnumNames<Integrator> {
  static constexpr std::array<const char*, 2> names = {"velocity_verlet", "leapfrog"};
};
template <>
struct EnumNames<Tier> {
  static constexpr std::array<const char*, 4> names = {"standard", "reference", "fast", "preview"};
};

template <>
struct EnumNames<Bulk> {
  static constexpr std::array<const char*, 2> names = {"dynamic", "rigid"};
};
template <>
struct EnumNames<SegmentThaw> {
  static constexpr std::array<const char*, 3> names = {"off", "on", "omega"};
};

template <class E, class = void>
struct IsSceneEnum : std::false_type {};
template <class E>
struct IsSceneEnum<E, std::void_t<decltype(EnumNames<E>::names)>> : std::true_type {};

template <class E, std::enable_if_t<IsSceneEnum<E>::value, int> = 0>
const char* name_of(E e) {
  return EnumNames<E>::names[static_cast<std::size_t>(e)];
}
template <class E, std::enable_if_t<IsSceneEnum<E>::value, int> = 0>
std::ostream& operator<<(std::ostream& os, E e) {
  return os << name_of(e);
}
// The value named `name`; false if there is none.
template <class E>
bool enum_from_name(const std::string& name, E& out) {
  for (std::size_t i = 0; i < EnumNames<E>::names.size(); ++i)
    if (name == EnumNames<E>::names[i]) {
      out = static_cast<E>(i);
      return true;
    }
  return false;
}
template <class E>
std::vector<std::string> enum_names() {
  return {EnumNames<E>::names.begin(), EnumNames<E>::names.end()};
}

}  // namespace tumble
