#pragma once
// The MCM's headline numbers (Yu 2022 Fig. 9): how many tracers sit inside the CM islands
// compared with the islands' share of the area, and the Peclet number. Lambert is equal-area, so
// a uniform tracer distribution puts the area fraction of tracers inside.
#include <cstdint>
#include <vector>

#include "cm/island.hpp"
#include "cm/mcm.hpp"

namespace tumble::cm {

struct McmSummary {
  double peclet = 0, island_length = 0;
  // Islands' share of the bulk disc (what a view from below sees) and of the whole shell chart.
  double bulk_area_fraction = 0, area_fraction = 0;
  // Tracers inside islands at the snapshot: among tracers in the bulk, and among all.
  double bulk_inside_fraction = 0, inside_fraction = 0;
  std::int64_t bulk_tracers = 0;
  // The same for the cumulative positions (Fig. 9 bottom row), bulk only.
  double cumulative_bulk_inside_fraction = 0;
  // Initial condition, as a check of the estimate (should match bulk_area_fraction).
  double initial_bulk_inside_fraction = 0;
};

McmSummary summarize_mcm(const ShellChart& chart, const std::vector<Island>& islands,
                         const DriftGrid& grid, const McmOptions& opt, const McmResult& res,
                         double island_length);

}  // namespace tumble::cm
