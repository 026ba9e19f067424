#pragma once
// Yu 2022 Figs. 6-7 from stored snapshots: the angular displacement Δψ over a lag of L protocol
// iterations, summed over every start in a window whose end is in it too (the paper averages its
// maps over the starts in 13 <= N <= 35), and its contrast between the particles that started
// outside the CM islands and those that started inside.
//
// A campaign's fields hold Δψ maps that the run collected for the lags its [collect] table named
// (campaign/field_collector.cpp); this computes any lag afterwards from the snapshots (one per
// iteration, stroboscopic), so a run continued past the campaign's end adds starts to a long lag.
// Same definition as the collector: lab-frame position directions, particles with
// inner <= r/R <= 1 at the start, binned by their start cell (analysis/displacement.hpp).
#include <vector>

#include "analysis/displacement.hpp"
#include "analysis/snapshot_data.hpp"
#include "projection/lambert.hpp"

namespace tumble::analysis {

struct SnapshotDisplacement {
  DisplacementMap map;
  int starts = 0;              // intervals summed into the map
  double first = 0, last = 0;  // their first and last start iteration
};

// `snaps` in iteration order (as list_snapshots gives them), every one of the same particles.
// A start is a snapshot with from <= N <= to - lag whose partner at N + lag exists (within 1e-3
// iterations: snapshot times lie near whole iterations); a snapshot that repeats its
// predecessor's configuration (snapshot_data.hpp: repeated_snapshots) counts once.
SnapshotDisplacement displacement_from_snapshots(const std::vector<SnapshotData>& snaps, double lag,
                                                 double from, double to, const LambertGrid& grid,
                                                 double inner);

// Mean Δψ [rad] of the particles that started inside the islands and of those outside: each cell's
// particles weighted by the share of its area inside (`coverage`) or outside (1 - coverage). NaN
// for a side without particles. The one definition: the collected maps' contrast (analysis.h5
// dpsi_fields, the report's table 3c) uses it too (campaign_analysis.cpp).
struct DpsiContrast {
  double inside = 0, outside = 0;
  double contrast() const { return outside - inside; }
};
DpsiContrast dpsi_contrast(const std::vector<double>& sum, const std::vector<double>& count,
                           const std::vector<double>& coverage);

}  // namespace tumble::analysis
