// Progress reports of the long CM computations (cm/progress.hpp): what `tumble cm` turns into
// progress lines. Each must start at or above 0, never go back, and end at 1.
#include <gtest/gtest.h>

#include <vector>

#include "cm/kam.hpp"
#include "cm/mcm.hpp"
#include "cm/poincare.hpp"

namespace {
using namespace tumble::cm;

struct Recorder {
  std::vector<double> seen;
  Progress fn() {
    return [this](double d) { seen.push_back(d); };
  }
  void expect_monotone_to_one(const char* what) const {
    SCOPED_TRACE(what);
    ASSERT_FALSE(seen.empty());
    EXPECT_GE(seen.front(), 0.0);
    for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]);
    EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  }
};

TEST(Progress, EveryLongComputationReportsFromZeroToOne) {
  const Protocol pr = Protocol::degrees(57, 57);
  const SectionMap map(pr, ShellChart(0.95, pr.eps));

  Recorder search;
  PeriodicSearch ps;
  ps.max_period = 3;
  ps.grid = 12;
  const auto points = find_periodic_points(map, ps, search.fn());
  search.expect_monotone_to_one("find_periodic_points");

  Recorder islands;
  IslandOptions io;
  io.iterations = 200;
  io.final_iterations = 400;
  find_islands(map, points, io, islands.fn());
  islands.expect_monotone_to_one("find_islands");

  Recorder kam;
  kam_tubes(pr, points, 0.95, {0.85, 0.9}, {ps, io}, kam.fn());
  kam.expect_monotone_to_one("kam_tubes");

  Recorder section;
  PoincareOptions po;
  po.seeds = 10;
  po.periods = 20;
  po.second_rotation = true;
  poincare_section(pr, po, section.fn());
  section.expect_monotone_to_one("poincare_section");

  Recorder mcm;
  McmOptions mo;
  mo.tracers = 600;
  mo.snapshot = 2;
  mo.cumulative_from = mo.cumulative_to = 2;
  run_mcm(pr, synthetic_drift({}), mo, mcm.fn());
  mcm.expect_monotone_to_one("run_mcm");
  EXPECT_GT(mcm.seen.size(), 4u);  // within an iteration too, not only at its end
}

// Without a reporter nothing changes: the same points with and without one.
TEST(Progress, ReportingDoesNotChangeResults) {
  const Protocol pr = Protocol::degrees(57, 57);
  const SectionMap map(pr, ShellChart(0.95, pr.eps));
  PeriodicSearch ps;
  ps.max_period = 2;
  ps.grid = 10;
  const auto a = find_periodic_points(map, ps);
  const auto b = find_periodic_points(map, ps, [](double) {});
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].v, b[i].v);
}

}  // namespace
