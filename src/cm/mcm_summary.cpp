#include "cm/mcm_summary.hpp"

namespace tumble::cm {
namespace {

struct Count {
  std::int64_t bulk = 0, bulk_in = 0, all_in = 0, all = 0;
};

Count count_inside(const ShellChart& chart, const std::vector<Island>& islands,
                   const std::vector<Vec3>& pts) {
  Count c;
  for (const Vec3& p : pts) {
    const Vec2 v = chart.to_chart(p);
    const bool in = island_containing(islands, v) >= 0;
    ++c.all;
    c.all_in += in;
    if (chart.in_bulk(v)) {
      ++c.bulk;
      c.bulk_in += in;
    }
  }
  return c;
}

double ratio(std::int64_t a, std::int64_t b) { return b ? static_cast<double>(a) / b : 0.0; }

}  // namespace

McmSummary summarize_mcm(const ShellChart& chart, const std::vector<Island>& islands,
                         const DriftGrid& grid, const McmOptions& opt, const McmResult& res,
                         double island_length) {
  McmSummary s;
  s.island_length = island_length;
  s.peclet = mcm_peclet(grid, opt, island_length);
  s.bulk_area_fraction = island_bulk_area_fraction(chart, islands);
  s.area_fraction = island_area_fraction(chart, islands);
  const Count snap = count_inside(chart, islands, res.snapshot);
  s.bulk_inside_fraction = ratio(snap.bulk_in, snap.bulk);
  s.inside_fraction = ratio(snap.all_in, snap.all);
  s.bulk_tracers = snap.bulk;
  const Count cum = count_inside(chart, islands, res.cumulative);
  s.cumulative_bulk_inside_fraction = ratio(cum.bulk_in, cum.bulk);
  const Count init = count_inside(chart, islands, res.initial);
  s.initial_bulk_inside_fraction = ratio(init.bulk_in, init.bulk);
  return s;
}

}  // namespace tumble::cm
