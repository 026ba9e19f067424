#pragma once
// Island enrichment: the share of the large particles that lie inside the CM islands, divided by
// the share of the view the islands cover. 1 = large particles spread evenly; > 1 = they gather
// in the islands, the segregation pattern of Yu 2022 Figs. 2 and 4; with no islands (e.g.
// (68°, 68°)) it is undefined (NaN), and the pattern's absence is read from the c_L maps instead.
#include <vector>

#include "analysis/snapshot_data.hpp"
#include "islands/island_mask.hpp"

namespace tumble::analysis {

struct Enrichment {
  double inside_share = 0;  // large particles (or their volume) inside islands / all counted
  double area_share = 0;    // islands' share of the counted area
  double value = 0;         // inside_share / area_share (NaN if either is undefined)
  double counted = 0;       // particles (or volume) counted
};

// From particles: particles of `species` (1, the large ones, unless a mixture maps another;
// scene/mixture.hpp) with centres in inner R < r < R on the lower hemisphere, lab frame; area
// share = islands' share of the unit Lambert disc.
Enrichment enrichment_from_particles(const SnapshotData& s, const IslandMask& islands, double inner,
                                     int species = 1);

// Over several configurations (the stroboscopic snapshots of a collection window): the mapped
// particles of all of them pooled, inside share = all inside / all counted (a snapshot with more
// particles in the shell weighs more, as in a map summed over the window).
Enrichment enrichment_pooled(const std::vector<SnapshotData>& snapshots, const IslandMask& islands,
                             double inner, int species = 1);

// From a map of large-particle solid volume per equal-area cell (a case's
// concentration/volume_large) and each cell's island coverage (IslandMask::cell_coverage):
// both shares are taken over the cells the large particles could be seen in (all cells).
Enrichment enrichment_from_map(const std::vector<double>& volume_large,
                               const std::vector<double>& coverage);

}  // namespace tumble::analysis
