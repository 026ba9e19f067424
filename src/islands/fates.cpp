#include "islands/fates.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace tumble::analysis {

void FateCounts::add(Fate f) {
  switch (f) {
    case Fate::Persistent:
      ++persistent;
      break;
    case Fate::Switched:
      ++switched;
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
                          const IslandMask& islands, int species) {
  FateResult r;
  for (std::size_t i = 0; i < start.size(); ++i) {
    if (start.species[i] != species) continue;
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
    r.counts.add(f);
  }
  return r;
}

FateExpectation chance_fates(const FateResult& r) {
  FateExpectation e;
  const double n = static_cast<double>(r.id.size());
  if (n == 0) return e;
  std::map<int, double> a, b;  // particles per island at the start and at the end
  double in_a = 0, in_b = 0;
  for (std::size_t i = 0; i < r.id.size(); ++i) {
    if (r.island_start[i] >= 0) a[r.island_start[i]] += 1, in_a += 1;
    if (r.island_end[i] >= 0) b[r.island_end[i]] += 1, in_b += 1;
  }
  double same = 0;
  for (const auto& [k, count] : a)
    if (const auto it = b.find(k); it != b.end()) same += count * it->second;
  e.persistent = same / n;
  e.switched = (in_a * in_b - same) / n;
  e.captured = (n - in_a) * in_b / n;
  e.dispersed = in_a * (n - in_b) / n;
  e.other = (n - in_a) * (n - in_b) / n;
  return e;
}

std::size_t default_fates_start(const std::vector<double>& iters, int period, double settled) {
  if (iters.size() < 2 || period <= 0) return 0;
  const double end = iters.back();
  const auto whole_periods = [&](std::size_t k) {
    const double span = end - iters[k];
    return span > 0.5 && std::fabs(span - period * std::round(span / period)) <= 1e-3;
  };
  for (std::size_t k = 0; k + 1 < iters.size(); ++k)
    if (iters[k] >= settled - 1e-3 && whole_periods(k)) return k;
  for (std::size_t k = 0; k + 1 < iters.size(); ++k)
    if (whole_periods(k)) return k;
  return 0;
}

}  // namespace tumble::analysis
