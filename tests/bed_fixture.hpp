#pragma once
// A settled CI-size bed (bst_tiny-like, ~2,000 particles), settled once per test binary run and
// cached in a temporary directory.
#include <filesystem>
#include <type_traits>

#include "run/realization.hpp"
#include "scene/scene.hpp"

namespace tumble::testing {

// Scratch space inside the build tree (TUMBLE_TEST_SCRATCH), so a new build never reuses beds
// settled by an older one.
inline std::string test_dir(const std::string& name) {
  const auto d = std::filesystem::path(TUMBLE_TEST_SCRATCH) / name;
  std::filesystem::create_directories(d);
  return d.string();
}

// The tiny scene with extra overrides; its bed cache is shared by all tests.
inline Scene tiny_scene(std::vector<std::string> o = {}) {
  std::vector<std::string> all = {"tumbler.radius=0.02", "contact.collision_time=1e-3",
                                  "fill.bed_cache=" + test_dir("beds"), "protocol.mode=rest"};
  all.insert(all.end(), o.begin(), o.end());
  return parse_scene("", all, "tiny");
}

inline Particles tiny_settled_bed() { return settled_bed(tiny_scene(), nullptr); }

// How many state values of two runs' particles differ (positions, velocities, spins, wall springs,
// ids, the rigid bulk's states, anchors and gravity directions, compared bitwise): 0 for a restart
// that continued exactly. (A dynamic run's engine keeps the rigid bulk's columns empty,
// field::kRigidOnly: they count as zeros.)
inline std::size_t state_differences(const Particles& p, const Particles& q) {
  auto at = [](const auto& column, std::size_t i) {
    return column.empty() ? typename std::decay_t<decltype(column)>::value_type{} : column[i];
  };
  std::size_t differ = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 anchor_p = at(p.bulk_anchor, i), anchor_q = at(q.bulk_anchor, i);
    const Vec3 gravity_p = at(p.bulk_gravity, i), gravity_q = at(q.bulk_gravity, i);
    for (int d = 0; d < 3; ++d)
      differ += p.x[i][d] != q.x[i][d] || p.v[i][d] != q.v[i][d] || p.w[i][d] != q.w[i][d] ||
                p.wall_spring[i][d] != q.wall_spring[i][d] || anchor_p[d] != anchor_q[d] ||
                gravity_p[d] != gravity_q[d];
    differ += p.id[i] != q.id[i] || at(p.bulk_state, i) != at(q.bulk_state, i);
  }
  return differ;
}

}  // namespace tumble::testing
