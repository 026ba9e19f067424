#pragma once
// Poincare sections (Yu 2022 Fig. 1(a), 10(a), 11(a), 12(a)): seeds on the shell r, iterated
// N periods; the state at the start of every period is recorded. Seeds placed at the start of
// the first rotation are iterated directly; seeds placed at the start of the second rotation
// (Fig. 12(a), blue) first finish that rotation, so both sets are recorded at the same section
// times.
#include <string>
#include <vector>

#include "cm/progress.hpp"
#include "cm/protocol.hpp"
#include "cm/shell_chart.hpp"

namespace tumble::cm {

enum class Seeding { Shell, Interface };  // equal-area on the bulk part / on the interface circle

struct PoincareOptions {
  double r = 0.95;
  int seeds = 500;
  int periods = 1000;
  Seeding seeding = Seeding::Shell;
  bool first_rotation = true, second_rotation = false;  // which seed sets
};

struct PoincareSet {
  std::string name;         // "first" or "second"
  std::vector<Vec3> seeds;  // where they were placed (start of that rotation)
  // Iterates in the bulk: chart (Lambert, viewed from below) coordinates, seed index, period.
  std::vector<Vec2> bulk;
  std::vector<std::int64_t> bulk_seed, bulk_period;
  // Iterates in the flowing layer: positions, chart coordinates (the ring), seed index, period.
  std::vector<Vec3> layer;
  std::vector<Vec2> layer_chart;
  std::vector<std::int64_t> layer_seed, layer_period;
};

std::vector<PoincareSet> poincare_section(const Protocol& pr, const PoincareOptions& opt,
                                          const Progress& progress = {});

// Bytes poincare_section and write_poincare hold at their peak, so that a run that cannot fit is
// refused before it starts. Per iterate: 32 B reserved for a bulk iterate (chart point, seed,
// period) and the 16 B copy the writer makes of its chart point; for a layer iterate, 56 B
// (position, chart point, seed, period) doubled for vector growth and 40 B of writer's copies,
// times the layer's share of the shell's invariant measure (the chart's ring: iterates of a long
// orbit visit the layer in that proportion). The writer's copies are counted together: the
// allocator need not give freed blocks back to the system before the next. Seeds: 24 B each.
double poincare_memory_bytes(const Protocol& pr, const PoincareOptions& opt);

}  // namespace tumble::cm
