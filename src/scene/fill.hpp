#pragma once
// Filling the tumbler: a reproducible random bidisperse bed, placed on a loose lattice in the
// bottom of the tumbler (so it settles in a fraction of a second rather than falling from the top),
// then settled under gravity by the engine.
#include <cstdint>
#include <string>
#include <vector>

#include "base/particles.hpp"
#include "scene/scene.hpp"

namespace tumble {

struct BedPlan {
  std::int64_t n_large = 0, n_small = 0;
  double site = 0;             // lattice site side; one large or up to k^3 small per site
  int small_per_side = 1;      // k
  std::vector<Vec3> position;  // particle centres before jitter, large first
  std::vector<std::int32_t> species;
};

// Particle counts and their lattice positions for the scene, deterministic in the seed; throws
// InputError if the bed does not fit in the tumbler. With positions = false only the counts and
// the fit are computed (validation: the same walk of the lattice, nothing stored).
BedPlan plan_bed(const Scene& s, bool positions = true);
// Number of particles the scene's bed will hold (a cylinder: particles.count; a sphere: the plan).
std::int64_t planned_particle_count(const Scene& s);

// What a scene will need before anything is allocated: particles (a sphere: the plan's counts,
// computed without the lattice), cells of the neighbour grid, and bytes in all.
struct ResourceEstimate {
  double particles = 0, cells = 0, bytes = 0;
};
// The engine's measured share per particle (docs/performance.md, "Memory": 0.94 kB: state,
// neighbour list with springs, reference positions, checkpoint buffers) and per grid cell (the
// cell starts and their fill copy, two uint32).
inline constexpr double kBytesPerParticle = 940;
inline constexpr double kBytesPerCell = 8;
ResourceEstimate estimate_resources(const Scene& s);
// The memory a scene may need, checked by validate_scene before the bed is planned. 0 (the
// default) checks only what the code can index (uint32 particle and cell indices): a scene read
// back from a snapshot or checkpoint is not refused for the reading machine. `tumble run` and
// `tumble campaign` set it (--max-memory, else the machine's available memory); `origin` says
// where the limit came from, for the message.
void set_memory_limit(double bytes, const std::string& origin);
// Throws InputError with the estimate when the scene needs more than the limit or the indices hold.
void check_resources(const Scene& s);

// Builds the (unsettled) bed: species 0 = small, 1 = large; ids 0..N-1. Deterministic in the seed.
Particles make_bed(const Scene& s);
// Sets mass/inertia/radius-derived fields from species (used by every bed source).
void set_species_properties(const Scene& s, Particles& p);

// A small, portable random generator (splitmix64): the same seed gives the same bed everywhere,
// unlike std::uniform_real_distribution whose algorithm differs between standard libraries.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 0x1234567ull) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  std::uint64_t below(std::uint64_t n) { return next() % n; }
  template <class T>
  void shuffle(std::vector<T>& v) {
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[below(i)]);
  }

 private:
  std::uint64_t state_;
};

}  // namespace tumble
