#pragma once
// Angular displacement over k protocol periods (Yu 2022 Figs. 6-7): for every particle whose
// centre lies in inner <= r/R <= 1 at the start of an interval, the angle between its position
// directions at the start and k periods later, averaged per species over the equal-area Lambert
// cell (lambert.hpp) where it started. Particles caught in a period-k island come back (small
// Δψ); chaotic ones do not. Particles are addressed by slot (a fixed order of their global ids),
// because the engine reorders them in memory.
#include <cstdint>
#include <vector>

#include "base/particles.hpp"
#include "base/vec3.hpp"
#include "projection/lambert.hpp"

namespace tumble::analysis {

// Angle between two directions, accurate at 0 and pi alike: atan2(|a x b|, a . b).
double angle_between(const Vec3& a, const Vec3& b);

struct ShellDirections {
  std::vector<Vec3> u;             // unit direction by slot, in the chosen frame
  std::vector<std::int32_t> cell;  // start cell by slot; -1: outside the shell or the hemisphere
};

// `slot_of[i]` is the slot of particle i (its position in global-id order).
ShellDirections shell_directions(const Particles& p, const std::vector<std::uint32_t>& slot_of,
                                 const Mat3& to_frame, const LambertGrid& grid, double R,
                                 double inner);

class DisplacementMap {
 public:
  explicit DisplacementMap(int cells = 0)
      : sum_large(cells, 0.0),
        sum_small(cells, 0.0),
        count_large(cells, 0.0),
        count_small(cells, 0.0) {}
  // One interval: `start` from its first sample, `end_u` from its last; species by slot.
  void add_interval(const ShellDirections& start, const std::vector<Vec3>& end_u,
                    const std::vector<std::int32_t>& species_by_slot);
  std::vector<double> mean_large() const;  // radians; NaN where no particle started
  std::vector<double> mean_small() const;

  // Running sums (public: they are the persisted state of a case).
  std::vector<double> sum_large, sum_small, count_large, count_small;
  long long intervals = 0;
};

}  // namespace tumble::analysis
