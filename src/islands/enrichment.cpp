#include "islands/enrichment.hpp"

#include <cmath>
#include <limits>

namespace tumble::analysis {

namespace {
Enrichment finish(double inside, double counted, double area_share) {
  Enrichment e;
  e.counted = counted;
  e.area_share = area_share;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  e.inside_share = counted > 0 ? inside / counted : nan;
  e.value = (counted > 0 && area_share > 0) ? e.inside_share / area_share : nan;
  return e;
}
}  // namespace

Enrichment enrichment_from_particles(const SnapshotData& s, const IslandMask& islands, double inner,
                                     int species) {
  const double lo2 = inner * inner * s.R * s.R, hi2 = s.R * s.R;
  double inside = 0, counted = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.species[i] != species) continue;
    const double r2 = norm2(s.x[i]);
    if (r2 <= lo2 || r2 >= hi2 || s.x[i].y > 0) continue;
    counted += 1;
    if (islands.island_of_direction(s.x[i]) >= 0) inside += 1;
  }
  return finish(inside, counted, islands.area_fraction());
}

Enrichment enrichment_pooled(const std::vector<SnapshotData>& snapshots, const IslandMask& islands,
                             double inner, int species) {
  double inside = 0, counted = 0;
  for (const auto& s : snapshots) {
    const Enrichment e = enrichment_from_particles(s, islands, inner, species);
    if (e.counted == 0) continue;  // its inside share is undefined (NaN)
    inside += e.inside_share * e.counted;
    counted += e.counted;
  }
  return finish(inside, counted, islands.area_fraction());
}

Enrichment enrichment_from_map(const std::vector<double>& volume_large,
                               const std::vector<double>& coverage) {
  double inside = 0, counted = 0, area = 0;
  for (std::size_t c = 0; c < volume_large.size(); ++c) {
    if (!std::isfinite(volume_large[c])) continue;
    inside += coverage[c] * volume_large[c];
    counted += volume_large[c];
    area += coverage[c];
  }
  return finish(inside, counted, volume_large.empty() ? 0 : area / volume_large.size());
}

}  // namespace tumble::analysis
