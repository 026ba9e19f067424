#include "islands/fates.hpp"

#include <algorithm>

namespace tumble::analysis {

void FateCounts::add(Fate f, bool same) {
  switch (f) {
    case Fate::Persistent:
      ++persistent;
      if (same) ++same_island;
      break;
    case Fate::Captured:
      ++captured;
      break;
    case Fate::Dispersed:
      ++dispersed;
      break;
    case Fate::Other:
      ++other;
      break;
  }
}

FateResult classify_fates(const SnapshotData& start, const SnapshotData& end,
                          const IslandMask& islands) {
  FateResult r;
  for (std::size_t i = 0; i < start.size(); ++i) {
    if (start.species[i] != 1) continue;
    // Snapshots hold particles in ascending id order (io/snapshot.cpp).
    const auto it = std::lower_bound(end.id.begin(), end.id.end(), start.id[i]);
    if (it == end.id.end() || *it != start.id[i]) continue;
    const std::size_t k = static_cast<std::size_t>(it - end.id.begin());
    const int a = islands.island_of_direction(start.x[i]);
    const int b = islands.island_of_direction(end.x[k]);
    const Fate f = fate_of(a, b);
    r.id.push_back(start.id[i]);
    r.island_start.push_back(a);
    r.island_end.push_back(b);
    r.fate.push_back(static_cast<std::int32_t>(f));
    r.x_start.push_back(start.x[i]);
    r.x_end.push_back(end.x[k]);
    r.counts.add(f, a >= 0 && a == b);
  }
  return r;
}

}  // namespace tumble::analysis
