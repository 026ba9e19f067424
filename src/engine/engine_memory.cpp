// What the engine holds in memory, array by array: the run's last lines report it per particle
// (as LAMMPS reports its memory per rank), so that a change that grows a per-particle array shows.
#include "engine/simulation.hpp"

namespace tumble {
namespace {
template <class T>
std::size_t bytes_of(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
}  // namespace

EngineMemory Simulation::memory() const {
  EngineMemory m;
  for_each_field<field::kAny>(
      p_, [&m](const char*, const auto& column) { m.particles += bytes_of(column); });
  m.neighbors = list_.memory_bytes();
  const engine::TouchingContacts& c = touching_;
  m.scratch = bytes_of(c.i) + bytes_of(c.j) + bytes_of(c.k) + bytes_of(c.miss) +
              bytes_of(wall_candidates_) + bytes_of(cap_candidates_);
  const RigidBulk& b = bulk_;
  m.scratch += bytes_of(b.top) + bytes_of(b.calm) + bytes_of(b.unsettled) + bytes_of(b.touched) +
               b.dormant.memory_bytes() + bytes_of(b.moving) + bytes_of(b.exposed) +
               bytes_of(b.exposed_ghosts) + bytes_of(b.x_build);
  if (dom_) m.scratch += dom_->memory_bytes();
  return m;
}

}  // namespace tumble
