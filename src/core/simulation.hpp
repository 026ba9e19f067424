#pragma once
// The DEM engine for one realization: particle state, neighbour list with contact history, the
// contact law, the tumbler wall and its rotation protocol, and the velocity-Verlet integrator.
// Physics options are resolved once at construction into a member-function pointer to a kernel
// instantiated for exactly those options: the per-contact loop has no option branches.
#include <cstdint>
#include <string>

#include "contact/yu2022.hpp"
#include "core/particles.hpp"
#include "core/scene.hpp"
#include "geometry/protocol.hpp"
#include "geometry/sphere_wall.hpp"
#include "neighbor/verlet_list.hpp"

namespace tumble {

struct EnergyBreakdown {
  double kinetic = 0;    // translational + rotational
  double potential = 0;  // gravity, relative to y = 0
  double elastic = 0;    // normal springs (pairs + wall); tangential springs
  double total() const { return kinetic + potential + elastic; }
};

class Simulation {
 public:
  // `time` and `step` let a restart continue the clock.
  Simulation(const Scene& scene, Particles particles, geometry::Protocol protocol, double time = 0,
             std::int64_t step = 0);

  // Advances one time step.
  void step();
  // Forces a neighbour rebuild during the next step (checkpoints: see io/checkpoint.cpp).
  void request_rebuild() { force_rebuild_ = true; }
  // Restores contact history and forces from a checkpoint; rebuilds the list from the current
  // (already sorted) particle order without recomputing forces.
  void restore(const neighbor::ContactHistory& history);
  // Computes forces for the current state (initial call of a fresh run).
  void compute_forces();

  // Throws RunError if a particle has a non-finite state or left the tumbler.
  void check_health() const;

  EnergyBreakdown energy() const;
  double rms_speed() const;

  const Particles& particles() const { return p_; }
  Particles& particles() { return p_; }
  const neighbor::VerletList& neighbors() const { return list_; }
  const geometry::Protocol& protocol() const { return protocol_; }
  const geometry::SphereWall& wall() const { return wall_; }
  double time() const { return time_; }
  std::int64_t step_count() const { return step_; }
  double dt() const { return dt_; }
  std::uint64_t rebuilds() const { return list_.builds; }
  // Number of rebuilds that came fewer than 10 steps after the previous one (skin too thin).
  std::uint64_t fast_rebuilds() const { return fast_rebuilds_; }
  const contact::Yu2022Pair& pair(int a, int b) const { return pair_[a][b]; }
  const contact::Yu2022Pair& wall_pair(int a) const { return wall_pair_[a]; }

 private:
  template <bool kFriction>
  void pair_forces();
  template <bool kFriction>
  void wall_forces();
  void maybe_rebuild(double max_displacement2);
  void rebuild_lists(const neighbor::ContactHistory* history);

  Particles p_;
  geometry::Protocol protocol_;
  geometry::SphereWall wall_;
  neighbor::VerletList list_;
  std::vector<std::uint32_t>
      wall_candidates_;  // particles that may touch the wall before the next rebuild
  contact::Yu2022Pair pair_[2][2];
  contact::Yu2022Pair wall_pair_[2];
  Vec3 gravity_;
  double dt_;
  double time_;
  std::int64_t step_;
  std::int64_t last_build_step_ = -1000;
  std::uint64_t fast_rebuilds_ = 0;
  bool force_rebuild_ = false;
  void (Simulation::*pair_kernel_)() = nullptr;
  void (Simulation::*wall_kernel_)() = nullptr;
};

}  // namespace tumble
