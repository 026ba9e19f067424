#pragma once
// Helpers for engine tests: a scene from a few TOML lines, and hand-placed particles.
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "scene/fill.hpp"
#include "scene/scene.hpp"

namespace tumble::testing {

// A scene with gravity off, a large tumbler (R = 0.1 m) and the paper's contact parameters,
// modified by `extra` TOML lines or overrides.
inline Scene test_scene(const std::vector<std::string>& overrides = {}) {
  std::vector<std::string> o = {"gravity.g=0", "tumbler.radius=0.1", "protocol.mode=rest",
                                "particles.fill_level=0.05"};
  o.insert(o.end(), overrides.begin(), overrides.end());
  return parse_scene("", o, "test");
}

// A small bidisperse bed (1 and 2 mm) in a 12 mm sphere turning at 30 rpm about z, filled to
// `fill_level` as a loose lattice (make_bed): the kernel-equivalence tests run it.
inline Scene rotating_bed_scene(const std::vector<std::string>& extra, double fill_level = 0.3) {
  std::vector<std::string> o = {"tumbler.radius=0.012",
                                "particles.d_small=0.001",
                                "particles.d_large=0.002",
                                "particles.fill_level=" + std::to_string(fill_level),
                                "contact.collision_time=1e-3",
                                "protocol.mode=single_axis",
                                "protocol.axis=z",
                                "protocol.rpm=30"};
  o.insert(o.end(), extra.begin(), extra.end());
  return parse_scene("", o, "bed");
}

struct Placed {
  Vec3 x, v, w;
  int species = 0;
};

inline Particles make_particles(const Scene& s, const std::vector<Placed>& list) {
  Particles p;
  p.resize(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    p.x[i] = list[i].x;
    p.v[i] = list[i].v;
    p.w[i] = list[i].w;
    p.species[i] = list[i].species;
    p.id[i] = static_cast<std::int64_t>(i);
  }
  set_species_properties(s, p);
  return p;
}

// The particle with global id `id` (order changes at every neighbour rebuild).
inline std::size_t index_of(const Simulation& sim, std::int64_t id) {
  const auto& ids = sim.particles().id;
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (ids[i] == id) return i;
  return ids.size();
}

}  // namespace tumble::testing
