#pragma once
// Yu 2022 Fig. 8 / Sec. III A: where large particles go between two protocol iterations relative
// to the CM's non-mixing islands. Each large particle present at both times is one of
//   persistent  in an island at the start and at the end,
//   captured    outside at the start (chaotic region), inside at the end,
//   dispersed   inside at the start, outside at the end,
//   other       outside at both times.
// The paper's text counts as persistent the particles that "start and end in the same
// CM-predicted nonmixing region"; `same_island` counts those among the persistent ones, so both
// readings are available (for period-3 islands compare iterations a multiple of 3 apart, where
// every island is back in place).
#include <cstdint>
#include <vector>

#include "analysis/snapshot_data.hpp"
#include "islands/island_mask.hpp"

namespace tumble::analysis {

enum class Fate : std::int32_t { Persistent = 0, Captured = 1, Dispersed = 2, Other = 3 };

// The class of a particle from its island index at the start and at the end (-1: none).
constexpr Fate fate_of(int island_start, int island_end) {
  const bool a = island_start >= 0, b = island_end >= 0;
  return a ? (b ? Fate::Persistent : Fate::Dispersed) : (b ? Fate::Captured : Fate::Other);
}

struct FateCounts {
  std::int64_t persistent = 0, captured = 0, dispersed = 0, other = 0;
  std::int64_t same_island = 0;  // persistent particles in the same island at both times
  std::int64_t total() const { return persistent + captured + dispersed + other; }
  void add(Fate f, bool same);
};

struct FateResult {
  std::vector<std::int64_t> id;  // large particles present in both configurations
  std::vector<std::int32_t> island_start, island_end, fate;
  std::vector<Vec3> x_start, x_end;  // lab positions, for plots
  FateCounts counts;
};

// Large particles (species 1) are matched by global id; positions are taken in the lab frame,
// where the islands sit at the end of every iteration (docs/architecture.md, "Continuum model
// notes").
FateResult classify_fates(const SnapshotData& start, const SnapshotData& end,
                          const IslandMask& islands);

}  // namespace tumble::analysis
