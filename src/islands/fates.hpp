#pragma once
// Yu 2022 Fig. 8 / Sec. III A: where large particles go between two protocol iterations relative
// to the CM's non-mixing islands. Each large particle present at both times is one of
//   persistent  in the same island at the start and at the end (the paper's text: "start and end
//               in the same CM-predicted nonmixing region"),
//   switched    in an island at both times, but not the same one,
//   captured    outside at the start (chaotic region), inside at the end,
//   dispersed   inside at the start, outside at the end,
//   other       outside at both times.
// The islands of a period-p orbit trade places every iteration, so "the same island" is
// meaningful only over a whole number of periods (campaign_analysis checks the window). The paper's
// counts (124 + 241 = 365 inside at the start, 124 + 429 = 544 inside at the end) leave no room for
// `switched`: either none switched there or its "persistent" is "inside at both"; both readings
// are reported (persistent + switched is the second).
#include <cstdint>
#include <vector>

#include "analysis/snapshot_data.hpp"
#include "islands/island_mask.hpp"

namespace tumble::analysis {

enum class Fate : std::int32_t {
  Persistent = 0,
  Captured = 1,
  Dispersed = 2,
  Other = 3,
  Switched = 4
};

// The class of a particle from its island index at the start and at the end (-1: none).
constexpr Fate fate_of(int island_start, int island_end) {
  const bool a = island_start >= 0, b = island_end >= 0;
  if (a && b) return island_start == island_end ? Fate::Persistent : Fate::Switched;
  return a ? Fate::Dispersed : (b ? Fate::Captured : Fate::Other);
}

struct FateCounts {
  std::int64_t persistent = 0, captured = 0, dispersed = 0, other = 0, switched = 0;
  std::int64_t total() const { return persistent + captured + dispersed + other + switched; }
  void add(Fate f);
};

// What chance gives: the expected counts if the particles' end positions were handed out at
// random among the same particles (a random relabelling of the end configuration, every
// permutation equally likely), so that the islands' occupancy at the start and at the end is
// kept and only the link between a particle's start and its end is broken. With a_k and b_k the
// particles in island k at the start and at the end, A = sum a_k, B = sum b_k, of N:
// persistent = sum a_k b_k / N, switched = (A B - sum a_k b_k) / N, captured = (N - A) B / N,
// dispersed = A (N - B) / N, other = (N - A)(N - B) / N (the means of hypergeometric counts).
struct FateExpectation {
  double persistent = 0, captured = 0, dispersed = 0, other = 0, switched = 0;
};

struct FateResult {
  std::vector<std::int64_t> id;  // large particles present in both configurations
  std::vector<std::int32_t> island_start, island_end, fate;
  std::vector<Vec3> x_start, x_end;  // lab positions, for plots
  FateCounts counts;
};

// Particles of `species` (1, the large ones; a density-bidisperse bed's light ones are its mapped
// species, scene/mixture.hpp) are matched by global id; positions are taken in the lab frame,
// where the islands sit at the end of every iteration (docs/architecture.md, "Continuum model
// notes").
FateResult classify_fates(const SnapshotData& start, const SnapshotData& end,
                          const IslandMask& islands, int species = 1);

FateExpectation chance_fates(const FateResult& r);

// Yu 2022 counts Fig. 8 from N = 7, once radial segregation has settled, to the end of the run.
constexpr double kFig8SettledIteration = 7;

// The default Fig. 8 window over snapshots at iterations `iters` (ascending), ending at the last:
// the index of its first snapshot, the earliest at or after `settled` that leaves a whole
// number (>= 1) of the islands' period `period` to the end; failing that (a run too short) the
// earliest anywhere that does; failing that (or period <= 0) the first snapshot. Snapshot times
// sit within a time step of whole iterations: 1e-3 iterations is slack.
std::size_t default_fates_start(const std::vector<double>& iters, int period,
                                double settled = kFig8SettledIteration);

}  // namespace tumble::analysis
