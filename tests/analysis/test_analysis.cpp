// Analyses of issue 7 on constructed inputs with known answers: particles placed in and out of a
// polygon island, classified trajectories, a rigid rotation's Δψ (from maps and from a series of
// snapshots), a plane through two islands,
// the lighter species of a density-bidisperse bed, and replica confidence intervals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "analysis/displacement.hpp"
#include "analysis/light_concentration.hpp"
#include "analysis/radial_segregation.hpp"
#include "base/error.hpp"
#include "islands/cross_section.hpp"
#include "islands/dpsi_snapshots.hpp"
#include "islands/enrichment.hpp"
#include "islands/fates.hpp"
#include "islands/island_mask.hpp"
#include "islands/replica_stats.hpp"
#include "scene/mixture.hpp"

namespace ta = tumble::analysis;
using tumble::Vec3;
using tumble::cm::Polygon;
using tumble::cm::Vec2;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A square island [x0, x1] x [z0, z1] in the Lambert disc.
Polygon square(double x0, double z0, double x1, double z1) {
  Polygon p;
  p.vertices = {Vec2(x0, z0), Vec2(x1, z0), Vec2(x1, z1), Vec2(x0, z1)};
  return p;
}

// The lab position at radius r (m) whose direction projects to disc point (X, Z).
Vec3 at_disc(double X, double Z, double r) {
  const auto u = ta::lambert_inverse({X, Z});
  return Vec3{u[0], u[1], u[2]} * r;
}

ta::SnapshotData empty_snapshot(double R) {
  ta::SnapshotData s;
  s.R = R;
  return s;
}

void add(ta::SnapshotData& s, std::int64_t id, int species, const Vec3& x, double radius = 1e-3) {
  s.id.push_back(id);
  s.species.push_back(species);
  s.radius.push_back(radius);
  s.x.push_back(x);
  s.x_tumbler.push_back(x);
}

}  // namespace

TEST(IslandMask, PointsInsideAndOutsideAPolygonIsland) {
  const ta::IslandMask mask({square(0.1, 0.1, 0.3, 0.3), square(-0.5, -0.5, -0.4, -0.2)});
  EXPECT_EQ(mask.island_of({0.2, 0.2}), 0);
  EXPECT_EQ(mask.island_of({-0.45, -0.3}), 1);
  EXPECT_EQ(mask.island_of({0.0, 0.0}), -1);
  EXPECT_EQ(mask.island_of({0.35, 0.2}), -1);
  // Directions: the lower hemisphere is seen from below; the upper one is never in an island.
  EXPECT_EQ(mask.island_of_direction(at_disc(0.2, 0.25, 0.02)), 0);
  EXPECT_EQ(mask.island_of_direction(at_disc(0.2, 0.25, 0.02) * 7.0), 0);  // any length
  Vec3 up = at_disc(0.2, 0.25, 1.0);
  up.y = -up.y;
  EXPECT_EQ(mask.island_of_direction(up), -1);
}

TEST(IslandMask, AreaFractionAndCellCoverageAgree) {
  const ta::IslandMask mask({square(0.1, 0.1, 0.3, 0.3), square(-0.5, -0.5, -0.4, -0.2)});
  const double area = 0.04 + 0.03;
  EXPECT_NEAR(mask.area_fraction(), area / kPi, 1e-12);
  const ta::LambertGrid grid(24);
  const auto cover = mask.cell_coverage(grid, 16);
  double sum = 0;
  for (double c : cover) {
    EXPECT_GE(c, 0.0);
    EXPECT_LE(c, 1.0);
    sum += c;
  }
  // Equal-area cells: mean coverage = the islands' share of the disc, up to the edge sampling.
  EXPECT_NEAR(sum / grid.cells(), area / kPi, 0.02 * area / kPi);
  EXPECT_EQ(ta::IslandMask().area_fraction(), 0.0);
}

TEST(Enrichment, ParticlesPlacedInAndOutOfAnIsland) {
  const double R = 0.02;
  const ta::IslandMask mask({square(-0.2, -0.2, 0.2, 0.2)});  // area 0.16 of pi
  ta::SnapshotData s = empty_snapshot(R);
  std::int64_t id = 0;
  // 30 large particles in the shell: 12 inside the island, 18 outside; small ones and large ones
  // off the shell or on the upper hemisphere do not count.
  for (int k = 0; k < 12; ++k) add(s, id++, 1, at_disc(-0.15 + 0.02 * k, 0.05, 0.95 * R));
  for (int k = 0; k < 18; ++k) add(s, id++, 1, at_disc(0.5, -0.4 + 0.04 * k, 0.95 * R));
  for (int k = 0; k < 50; ++k) add(s, id++, 0, at_disc(0.0, 0.0, 0.95 * R));
  add(s, id++, 1, at_disc(0.0, 0.0, 0.5 * R));  // deep: outside the shell
  Vec3 up = at_disc(0.0, 0.0, 0.95 * R);
  up.y = -up.y;
  add(s, id++, 1, up);
  const ta::Enrichment e = ta::enrichment_from_particles(s, mask, 0.9);
  EXPECT_EQ(e.counted, 30);
  EXPECT_NEAR(e.inside_share, 12.0 / 30.0, 1e-15);
  EXPECT_NEAR(e.area_share, 0.16 / kPi, 1e-12);
  EXPECT_NEAR(e.value, (12.0 / 30.0) / (0.16 / kPi), 1e-9);
  // No islands: undefined, not 0 or infinity.
  EXPECT_TRUE(std::isnan(ta::enrichment_from_particles(s, ta::IslandMask(), 0.9).value));
}

// Radial segregation by species: the share of a species' centres in the outer shell.
TEST(Radial, ShellShareOfASpecies) {
  const double R = 0.02;
  // Species 0: 3 of 4 in 0.9 R < r <= R; species 1: 1 of 5 (r = R exactly counts, 0.9 R not).
  const std::vector<tumble::Vec3> x{{0.95 * R, 0, 0}, {0, -0.99 * R, 0}, {0, 0, R},
                                    {0.5 * R, 0, 0},  {0, 0.95 * R, 0},  {0.9 * R, 0, 0},
                                    {0.1 * R, 0, 0},  {0, 0.2 * R, 0},   {0, 0, -0.3 * R}};
  const std::vector<std::int32_t> species{0, 0, 0, 0, 1, 1, 1, 1, 1};
  EXPECT_DOUBLE_EQ(ta::shell_share(x, species, 0, R, 0.9), 0.75);
  EXPECT_DOUBLE_EQ(ta::shell_share(x, species, 1, R, 0.9), 0.2);
  EXPECT_TRUE(std::isnan(ta::shell_share(x, species, 2, R, 0.9)));  // no such particle
}

// Snapshots lie within a time step of whole iterations, on either side: the window 25 <= N <= 35
// holds the ones written at 24.99995 and 35.0000015 (the yu2022_density_fast cases had 10 or 11
// of the 11 configurations by that round-off while the test used 1e-9), not 24.998 or 35.002.
TEST(Snapshots, IterationWindowHoldsBothEndsWithinAStep) {
  EXPECT_TRUE(ta::in_iteration_window(24.99995, 25, 35));
  EXPECT_TRUE(ta::in_iteration_window(35.0000014687252, 25, 35));
  EXPECT_TRUE(ta::in_iteration_window(30, 25, 35));
  EXPECT_FALSE(ta::in_iteration_window(24.998, 25, 35));
  EXPECT_FALSE(ta::in_iteration_window(35.002, 25, 35));
}

// A run's end written a few steps after its last periodic snapshot repeats it; snapshots a tenth
// of the spacing apart (the CI campaign's end, 211 steps after its last periodic one) do not.
TEST(Snapshots, RepeatedSnapshotsAreTheRunsEndAStepLater) {
  const std::vector<bool> r = ta::repeated_snapshots({33.99994, 34.99994, 35.0, 36.0});
  EXPECT_EQ(r, (std::vector<bool>{false, false, true, false}));
  const std::vector<bool> ci = ta::repeated_snapshots({0.0, 0.00184, 0.00369, 0.0040});
  EXPECT_EQ(ci, (std::vector<bool>{false, false, false, false}));
  EXPECT_TRUE(ta::repeated_snapshots({}).empty());
  EXPECT_EQ(ta::repeated_snapshots({1.0}), std::vector<bool>{false});
}

// The window's snapshots are pooled particle by particle, not averaged snapshot by snapshot.
TEST(Enrichment, WindowSnapshotsArePooled) {
  const double R = 0.02;
  const ta::IslandMask mask({square(-0.2, -0.2, 0.2, 0.2)});
  ta::SnapshotData a = empty_snapshot(R), b = empty_snapshot(R), none = empty_snapshot(R);
  std::int64_t id = 0;
  // a: 10 large particles in the shell, 5 inside; b: 30, 3 inside; none: no large one.
  for (int k = 0; k < 5; ++k) add(a, id++, 1, at_disc(-0.15 + 0.05 * k, 0.05, 0.95 * R));
  for (int k = 0; k < 5; ++k) add(a, id++, 1, at_disc(0.5, -0.4 + 0.04 * k, 0.95 * R));
  for (int k = 0; k < 3; ++k) add(b, id++, 1, at_disc(-0.1 + 0.05 * k, 0.0, 0.95 * R));
  for (int k = 0; k < 27; ++k) add(b, id++, 1, at_disc(0.5, -0.5 + 0.03 * k, 0.95 * R));
  add(none, id++, 0, at_disc(0.0, 0.0, 0.95 * R));
  const ta::Enrichment e = ta::enrichment_pooled({a, b, none}, mask, 0.9);
  EXPECT_EQ(e.counted, 40);
  EXPECT_NEAR(e.inside_share, 8.0 / 40.0, 1e-15);  // averaging the snapshots would give 0.3
  EXPECT_NEAR(e.value, (8.0 / 40.0) / (0.16 / kPi), 1e-9);
  // Nothing counted in any snapshot: undefined.
  EXPECT_TRUE(std::isnan(ta::enrichment_pooled({none}, mask, 0.9).value));
}

TEST(Enrichment, FromAVolumeMapWithCoverage) {
  // Four cells, one fully inside an island and one half inside: area share 1.5/4.
  const std::vector<double> cover{1.0, 0.5, 0.0, 0.0};
  const std::vector<double> vol{3.0, 2.0, 1.0, std::numeric_limits<double>::quiet_NaN()};
  const ta::Enrichment e = ta::enrichment_from_map(vol, cover);
  EXPECT_NEAR(e.inside_share, (3.0 + 1.0) / 6.0, 1e-15);
  EXPECT_NEAR(e.area_share, 1.5 / 4.0, 1e-15);
  EXPECT_NEAR(e.value, (4.0 / 6.0) / (1.5 / 4.0), 1e-12);
  // Evenly spread large particles give exactly 1.
  EXPECT_NEAR(ta::enrichment_from_map({1, 1, 1, 1}, cover).value, 1.0, 1e-15);
}

// The default Fig. 8 window: from N >= 7 (radial segregation settled) over whole island periods.
TEST(Fates, DefaultWindowStartsSettledOverWholePeriods) {
  std::vector<double> to34;
  for (int n = 0; n <= 34; ++n) to34.push_back(n + 1e-4);  // snapshots a step after each end
  EXPECT_EQ(ta::default_fates_start(to34, 3), 7u);         // the paper's 7 -> 34: 9 periods of 3
  EXPECT_EQ(ta::default_fates_start(to34, 6), 10u);        // 10 -> 34: 4 periods of 6
  const std::vector<double> to12{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  EXPECT_EQ(ta::default_fates_start(to12, 3), 9u);  // 7 and 8 leave 5 and 4 iterations
  // Too short to start at 7: the longest whole-period window; none at all: the first snapshot.
  const std::vector<double> to8{0, 1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_EQ(ta::default_fates_start(to8, 6), 2u);
  EXPECT_EQ(ta::default_fates_start({0, 1, 2}, 6), 0u);
  EXPECT_EQ(ta::default_fates_start(to8, 0), 0u);  // no islands
}

TEST(Fates, ConstructedTrajectoriesOfFig8) {
  const double R = 0.02;
  const ta::IslandMask mask({square(0.1, 0.1, 0.3, 0.3), square(-0.3, -0.3, -0.1, -0.1)});
  const Vec3 in_a = at_disc(0.2, 0.2, 0.95 * R), in_b = at_disc(-0.2, -0.2, 0.95 * R);
  const Vec3 out1 = at_disc(0.6, -0.5, 0.95 * R), out2 = at_disc(-0.6, 0.5, 0.95 * R);
  ta::SnapshotData s0 = empty_snapshot(R), s1 = empty_snapshot(R);
  // id: start -> end                         expected
  add(s0, 1, 1, in_a), add(s1, 1, 1, in_a);  // persistent: the same island
  add(s0, 2, 1, in_a), add(s1, 2, 1, in_b);  // switched: another island
  add(s0, 3, 1, out1), add(s1, 3, 1, in_b);  // captured
  add(s0, 4, 1, out2), add(s1, 4, 1, in_a);  // captured
  add(s0, 5, 1, in_b), add(s1, 5, 1, out1);  // dispersed
  add(s0, 6, 1, out1), add(s1, 6, 1, out2);  // other
  add(s0, 7, 0, out1), add(s1, 7, 0, in_a);  // small: not classified
  add(s0, 8, 1, in_a);                       // absent at the end: not classified
  add(s0, 9, 1, out2), add(s1, 9, 1, out2);  // other
  const ta::FateResult r = ta::classify_fates(s0, s1, mask);
  EXPECT_EQ(r.counts.persistent, 1);
  EXPECT_EQ(r.counts.switched, 1);
  EXPECT_EQ(r.counts.captured, 2);
  EXPECT_EQ(r.counts.dispersed, 1);
  EXPECT_EQ(r.counts.other, 2);
  EXPECT_EQ(r.counts.total(), 7);
  ASSERT_EQ(r.id.size(), 7u);
  EXPECT_EQ(r.id[2], 3);
  EXPECT_EQ(r.fate[2], static_cast<int>(ta::Fate::Captured));
  EXPECT_EQ(r.island_start[1], 0);
  EXPECT_EQ(r.island_end[1], 1);
  EXPECT_EQ(r.fate[1], static_cast<int>(ta::Fate::Switched));
  static_assert(ta::fate_of(-1, -1) == ta::Fate::Other);
  static_assert(ta::fate_of(2, -1) == ta::Fate::Dispersed);
  static_assert(ta::fate_of(1, 1) == ta::Fate::Persistent);
  static_assert(ta::fate_of(1, 0) == ta::Fate::Switched);

  // What chance gives for these 7: island A holds ids 1, 2 at the start (a_A = 2), B holds 5
  // (a_B = 1); at the end A holds 1, 4 (b_A = 2), B holds 2, 3 (b_B = 2). A = 3, B = 4, N = 7.
  const ta::FateExpectation e = ta::chance_fates(r);
  EXPECT_NEAR(e.persistent, (2.0 * 2 + 1.0 * 2) / 7, 1e-15);
  EXPECT_NEAR(e.switched, (3.0 * 4 - 6) / 7, 1e-15);
  EXPECT_NEAR(e.captured, 4.0 * 4 / 7, 1e-15);
  EXPECT_NEAR(e.dispersed, 3.0 * 3 / 7, 1e-15);
  EXPECT_NEAR(e.other, 4.0 * 3 / 7, 1e-15);
  EXPECT_NEAR(e.persistent + e.switched + e.captured + e.dispersed + e.other, 7.0, 1e-12);
}

// The chance expectation is the mean over random relabellings: check it against 20,000 random
// permutations of the end islands of 40 particles in three islands (Monte Carlo, 5 sigma).
TEST(Fates, ChanceExpectationIsTheMeanOverRandomRelabellings) {
  ta::FateResult r;
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> pick(-1, 2);  // -1: outside, 0..2: islands
  for (int i = 0; i < 40; ++i) {
    r.id.push_back(i);
    r.island_start.push_back(pick(rng));
    r.island_end.push_back(pick(rng));
  }
  const ta::FateExpectation e = ta::chance_fates(r);
  std::vector<int> end = r.island_end;
  double sum[5] = {0, 0, 0, 0, 0}, sum2[5] = {0, 0, 0, 0, 0};
  const int trials = 20000;
  for (int t = 0; t < trials; ++t) {
    std::shuffle(end.begin(), end.end(), rng);
    ta::FateCounts c;
    for (int i = 0; i < 40; ++i) c.add(ta::fate_of(r.island_start[i], end[i]));
    const double v[5] = {double(c.persistent), double(c.captured), double(c.dispersed),
                         double(c.other), double(c.switched)};
    for (int k = 0; k < 5; ++k) sum[k] += v[k], sum2[k] += v[k] * v[k];
  }
  const double expect[5] = {e.persistent, e.captured, e.dispersed, e.other, e.switched};
  for (int k = 0; k < 5; ++k) {
    const double mean = sum[k] / trials, var = sum2[k] / trials - mean * mean;
    EXPECT_NEAR(mean, expect[k], 5 * std::sqrt(var / trials) + 1e-12) << "class " << k;
  }
}

// Δψ of a rigid rotation by theta about the x axis: a direction at angle beta from the axis
// turns through cos Δψ = cos^2 beta + sin^2 beta cos theta; on the great circle beta = 90° it is
// theta itself. Checked through the campaign's displacement module on particles in the shell.
TEST(Displacement, RigidRotationGivesTheRotationAngle) {
  const double R = 0.02, theta = 0.7;
  const tumble::Mat3 rot = tumble::Mat3::rotation({1, 0, 0}, theta);
  const ta::LambertGrid grid(8);
  tumble::Particles p;
  const int n = 40;
  p.resize(2 * n);
  std::vector<std::uint32_t> slot(2 * n);
  std::vector<std::int32_t> species(2 * n, 1);
  for (int k = 0; k < n; ++k) {
    const double phi = kPi + kPi * (k + 0.5) / n;  // y = R sin(phi) < 0: lower hemisphere
    p.x[k] = Vec3{0, std::sin(phi), std::cos(phi)} * (0.95 * R);  // on the great circle
    const double beta = 0.3 + 1.2 * k / n;  // off the great circle, angle beta from the axis
    p.x[n + k] =
        Vec3{std::cos(beta), std::sin(beta) * std::sin(phi), std::sin(beta) * std::cos(phi)} *
        (0.95 * R);
  }
  for (int i = 0; i < 2 * n; ++i) slot[i] = i, p.radius[i] = 1e-3, p.species[i] = 1;
  const tumble::Mat3 id = tumble::Mat3::identity();
  const auto start = ta::shell_directions(p, slot, id, grid, R, 0.8);
  std::vector<Vec3> end(2 * n);
  for (int i = 0; i < 2 * n; ++i) end[i] = rot * start.u[i];
  for (int k = 0; k < n; ++k) EXPECT_NEAR(ta::angle_between(start.u[k], end[k]), theta, 1e-14);
  for (int k = 0; k < n; ++k) {
    const double beta = 0.3 + 1.2 * k / n;
    const double c =
        std::cos(beta) * std::cos(beta) + std::sin(beta) * std::sin(beta) * std::cos(theta);
    EXPECT_NEAR(ta::angle_between(start.u[n + k], end[n + k]), std::acos(c), 1e-12);
  }
  // The cell means of the great-circle particles alone are theta in every visited cell.
  ta::DisplacementMap m(grid.cells());
  auto great = start;
  for (int i = n; i < 2 * n; ++i) great.cell[i] = -1;
  m.add_interval(great, end, species);
  int visited = 0;
  for (double v : m.mean_large())
    if (!std::isnan(v)) {
      ++visited;
      EXPECT_NEAR(v, theta, 1e-13);
    }
  EXPECT_GE(visited, 4);
}

// Snapshots at iterations 0 ... 7 (6 written twice, as a run's last snapshot is by the next
// call): the large particles on a great circle turn by alpha about x each iteration, the small
// ones stay. Over a lag of L iterations every start cell's large particles moved alpha L, the
// small ones 0; the starts are those of the window whose end is in it, the repeat counted once.
TEST(DpsiSnapshots, StartsInTheWindowAndTheRotationAngle) {
  const double R = 0.02, alpha = 0.1;
  const ta::LambertGrid grid(8);
  std::vector<ta::SnapshotData> snaps;
  for (int k = 0; k <= 7; ++k) {
    ta::SnapshotData s = empty_snapshot(R);
    s.iteration = k + 1e-7 * (k % 2 ? 1 : -1);  // within a step of the whole iteration
    s.path = "snap_" + std::to_string(k);
    const tumble::Mat3 turn = tumble::Mat3::rotation({1, 0, 0}, alpha * k);
    for (int i = 0; i < 40; ++i) {
      const double phi = kPi + kPi * (i + 0.5) / 40;  // the lower half of the circle at k = 0
      add(s, i, 1, turn * (Vec3{0, std::sin(phi), std::cos(phi)} * (0.95 * R)));
      add(s, 40 + i, 0, Vec3{0.3, std::sin(phi), std::cos(phi)} * (0.9 * R));
    }
    snaps.push_back(s);
    if (k == 6) snaps.push_back(s), snaps.back().iteration += 4e-7;
  }
  const ta::SnapshotDisplacement two = ta::displacement_from_snapshots(snaps, 2, 1, 5, grid, 0.8);
  EXPECT_EQ(two.starts, 3);  // 1 -> 3, 2 -> 4, 3 -> 5
  EXPECT_NEAR(two.first, 1, 1e-6);
  EXPECT_NEAR(two.last, 3, 1e-6);
  int large = 0, small = 0;
  for (double v : two.map.mean_large())
    if (!std::isnan(v)) {
      ++large;
      EXPECT_NEAR(v, 2 * alpha, 1e-12);
    }
  for (double v : two.map.mean_small())
    if (!std::isnan(v)) {
      ++small;
      EXPECT_NEAR(v, 0, 1e-12);
    }
  EXPECT_GE(large, 3);
  EXPECT_GE(small, 3);
  // Lag 1 over 0 ... 7: starts 0 ... 6, the repeated 6 once.
  EXPECT_EQ(ta::displacement_from_snapshots(snaps, 1, 0, 7, grid, 0.8).starts, 7);
  // A lag longer than the window: none.
  EXPECT_EQ(ta::displacement_from_snapshots(snaps, 8, 0, 7, grid, 0.8).starts, 0);
  // No partner for the starts whose end is missing: without snapshot 4, lag 2 over 0 ... 7
  // keeps 0 -> 2, 1 -> 3, 3 -> 5, 5 -> 7 (and 6 -> 8 is past the window).
  auto gap = snaps;
  gap.erase(gap.begin() + 4);
  EXPECT_EQ(ta::displacement_from_snapshots(gap, 2, 0, 7, grid, 0.8).starts, 4);
  // Snapshots of different particles are refused, not compared.
  auto other = snaps;
  other[3].id[0] = 1000;
  EXPECT_THROW(ta::displacement_from_snapshots(other, 2, 0, 7, grid, 0.8),
               tumble::CorruptInputError);
}

// The inside / outside means weight each cell's particles by its area share: cell 0 (mean 1,
// inside), cell 1 (mean 3, outside), cell 2 (mean 2, half inside), cell 3 (no particle).
TEST(DpsiSnapshots, ContrastWeightsCellsByTheirIslandShare) {
  const std::vector<double> sum = {2, 9, 4, 0}, count = {2, 3, 2, 0}, cover = {1, 0, 0.5, 1};
  const ta::DpsiContrast c = ta::dpsi_contrast(sum, count, cover);
  EXPECT_NEAR(c.inside, (2 + 0.5 * 4) / (2 + 0.5 * 2), 1e-15);
  EXPECT_NEAR(c.outside, (9 + 0.5 * 4) / (3 + 0.5 * 2), 1e-15);
  EXPECT_NEAR(c.contrast(), 11.0 / 4 - 4.0 / 3, 1e-15);
  // No cell inside: the inside mean is undefined, not 0.
  EXPECT_TRUE(std::isnan(ta::dpsi_contrast(sum, count, {0, 0, 0, 0}).inside));
}

TEST(CrossSection, PlaneThroughTwoDirectionsBinsTheSlab) {
  const double R = 0.02;
  const Vec3 a{0.3, -0.9, 0.1}, b{-0.5, -0.6, 0.4};
  const ta::SectionPlane pl = ta::plane_through(a, b);
  EXPECT_NEAR(tumble::dot(pl.e1, pl.e2), 0.0, 1e-15);
  EXPECT_NEAR(tumble::dot(pl.normal, a), 0.0, 1e-15);
  EXPECT_NEAR(tumble::dot(pl.normal, b), 0.0, 1e-15);
  EXPECT_GT(tumble::dot(pl.e2, b), 0.0);
  ta::SnapshotData s = empty_snapshot(R);
  // Large at in-plane (0.7, -0.3) R, small at (-0.3, -0.3) R, one large just off the slab.
  add(s, 1, 1, (0.7 * pl.e1 - 0.3 * pl.e2) * R);
  add(s, 2, 0, (-0.3 * pl.e1 - 0.3 * pl.e2) * R);
  add(s, 3, 0, (-0.3 * pl.e1 - 0.3 * pl.e2) * R + 0.9e-3 * pl.normal);
  add(s, 4, 1, (-0.3 * pl.e1 - 0.3 * pl.e2) * R + 1.1e-3 * pl.normal);
  ta::SectionMap m(4);
  m.add(s, pl, 1e-3);
  const auto c = m.c_large();
  EXPECT_DOUBLE_EQ(c[3 * 4 + 1], 1.0);  // s1 in [0.5, 1), s2 in [-0.5, 0)
  EXPECT_DOUBLE_EQ(c[1 * 4 + 1], 0.0);  // s1 in [-0.5, 0): two small, the large is off the slab
  EXPECT_TRUE(std::isnan(c[0]));
}

TEST(CrossSection, UprightPlaneKeepsThePlaneAndPointsE2Up) {
  const ta::SectionPlane pl = ta::plane_through({0.3, -0.9, 0.1}, {-0.5, -0.6, 0.4});
  const ta::SectionPlane up = ta::upright(pl);
  EXPECT_NEAR(tumble::norm(up.normal - pl.normal), 0.0, 1e-15);  // the same plane
  EXPECT_NEAR(tumble::dot(up.e1, up.e2), 0.0, 1e-15);
  EXPECT_NEAR(tumble::norm(up.e1), 1.0, 1e-15);
  EXPECT_NEAR(tumble::norm(up.e2), 1.0, 1e-15);
  EXPECT_NEAR(tumble::norm(tumble::cross(up.e1, up.e2) - up.normal), 0.0, 1e-15);
  EXPECT_NEAR(up.e1.y, 0.0, 1e-15);  // horizontal: "up" is all in e2
  EXPECT_GT(up.e2.y, 0.9);           // the plane is steep: e2 nearly +y
  // Both island directions point down into the bed: negative s2.
  EXPECT_LT(tumble::dot(Vec3{0.3, -0.9, 0.1}, up.e2), 0.0);
  // A horizontal plane has no up: unchanged.
  const ta::SectionPlane flat = ta::plane_through({1, 0, 0}, {0, 0, 1});
  EXPECT_EQ(ta::upright(flat).e1.x, flat.e1.x);
}

TEST(CrossSection, FarthestPairOfDifferentOrbits) {
  std::vector<tumble::cm::Island> is(4);
  const double c[4][2] = {{-0.8, 0}, {0.8, 0}, {0.7, 0.1}, {-0.1, 0.5}};
  const int orbit[4] = {0, 0, 1, 1};  // 0-1 farthest, but one orbit: 0-2 is the pair
  for (int k = 0; k < 4; ++k) {
    is[k].center = tumble::cm::Vec2(c[k][0], c[k][1]);
    is[k].orbit = orbit[k];
  }
  EXPECT_EQ(ta::farthest_island_pair(is), std::make_pair(0, 2));
  is[2].orbit = is[3].orbit = 0;
  EXPECT_EQ(ta::farthest_island_pair(is), std::make_pair(-1, -1));
}

TEST(CrossSection, TubeCrossingsOfAnIslandAroundThePole) {
  // A square island of half-width h around the pole of the disc on two shells: the plane
  // through the pole (x = 0) meets its boundary where the direction's Lambert image leaves it.
  const double h = 0.2;
  std::vector<tumble::cm::Island> islands(2);
  islands[0].r = 0.95;
  islands[1].r = 0.6;
  for (auto& is : islands) is.boundary = square(-h, -h, h, h);
  const ta::SectionPlane pl = ta::plane_through({0, -1, 0}, {0, -1, 1});  // e1 = -y, e2 = z
  const auto t = ta::tube_crossings(islands, pl, 20000);
  ASSERT_EQ(t.size(), 4u);  // two per shell
  for (const auto& c : t) {
    // Lambert radius |Z| = sin(psi)/sqrt(1 + cos psi) = h at the crossing: angle psi from -y.
    const double psi = std::atan2(std::abs(c.s2), c.s1);
    EXPECT_NEAR(std::sin(psi) / std::sqrt(1 + std::cos(psi)), h, 1e-3);
    EXPECT_NEAR(std::hypot(c.s1, c.s2), c.r, 1e-12);
  }
}

// A density-bidisperse bed counts its light particles: the enrichment of the mapped species.
TEST(Enrichment, TheMappedSpeciesOfADensityBedIsTheLightOne) {
  const double R = 0.02;
  const ta::IslandMask mask({square(-0.2, -0.2, 0.2, 0.2)});
  ta::SnapshotData s = empty_snapshot(R);
  // Light (species 0): 4 inside the island, 4 outside; heavy (species 1): 1 inside, 15 outside.
  std::int64_t id = 0;
  for (int k = 0; k < 4; ++k) add(s, id++, 0, at_disc(-0.15 + 0.05 * k, 0.0, 0.95 * R));
  for (int k = 0; k < 4; ++k) add(s, id++, 0, at_disc(0.5, -0.3 + 0.1 * k, 0.95 * R));
  add(s, id++, 1, at_disc(0.1, 0.1, 0.95 * R));
  for (int k = 0; k < 15; ++k) add(s, id++, 1, at_disc(-0.5, -0.4 + 0.05 * k, 0.95 * R));
  const double area = 0.16 / kPi;
  EXPECT_NEAR(ta::enrichment_from_particles(s, mask, 0.9, 0).value, 0.5 / area, 1e-9);
  EXPECT_NEAR(ta::enrichment_from_particles(s, mask, 0.9, 1).value, (1.0 / 16) / area, 1e-9);
}

// The roles of the species (scene/mixture.hpp) for the beds of Yu 2022.
TEST(Mixture, SizeDensityAndOneKindBeds) {
  const std::string base = "[tumbler]\nradius = 0.07\n[particles]\nd_small = 0.002\n";
  const tumble::Mixture size = tumble::mixture_of(
      tumble::parse_scene(base + "d_large = 0.004\nlarge_fraction = 0.15\n", {}, "size"));
  EXPECT_EQ(size.kind, tumble::MixtureKind::size);
  EXPECT_EQ(size.name[size.mapped], "large");
  EXPECT_EQ(size.mapped, 1);
  EXPECT_EQ(size.minority, 1);
  const tumble::Mixture dense = tumble::mixture_of(tumble::parse_scene(
      base + "d_large = 0.002\nlarge_fraction = 0.98\ndensity = 2000\ndensity_ratio = 3\n", {},
      "density"));
  EXPECT_EQ(dense.kind, tumble::MixtureKind::density);
  EXPECT_EQ(dense.name[0], "light");
  EXPECT_EQ(dense.mapped, 0);
  EXPECT_EQ(dense.minority, 0);
  EXPECT_NE(dense.describe().find("light (species 0, 2 vol %, minority, mapped)"),
            std::string::npos)
      << dense.describe();
  // Species 1 lighter (R_rho < 1): the light one is species 1, still the one mapped.
  const tumble::Mixture inverse = tumble::mixture_of(tumble::parse_scene(
      base + "d_large = 0.002\nlarge_fraction = 0.02\ndensity_ratio = 0.5\n", {}, "inverse"));
  EXPECT_EQ(inverse.name[1], "light");
  EXPECT_EQ(inverse.mapped, 1);
  EXPECT_EQ(inverse.minority, 1);
  const tumble::Mixture mono =
      tumble::mixture_of(tumble::parse_scene(base + "d_large = 0.002\n", {}, "mono"));
  EXPECT_EQ(mono.kind, tumble::MixtureKind::mono);
}

TEST(LightConcentration, LighterSpeciesShareInTheWallLayer) {
  EXPECT_EQ(ta::lighter_species(3.0), 0);
  EXPECT_EQ(ta::lighter_species(0.5), 1);
  EXPECT_EQ(ta::lighter_species(1.0), -1);
  const double R = 0.02;
  ta::SnapshotData s = empty_snapshot(R);
  s.density_ratio = 3;  // species 1 heavy: species 0 is the lighter one
  // In one cell: 3 light and 1 heavy particle of equal size in the wall layer, and a light one
  // deeper than 0.97 R that must not count.
  for (int k = 0; k < 3; ++k) add(s, k, 0, at_disc(0.01 * k, 0.0, 0.985 * R));
  add(s, 3, 1, at_disc(0.0, 0.01, 0.985 * R));
  add(s, 4, 1, at_disc(0.0, 0.01, 0.9 * R));
  const ta::LambertGrid grid(4);
  const auto c = ta::light_concentration({s, s}, grid, 0.97);
  const int cell = grid.cell_of(ta::lambert_from_below(0, -1, 0));
  EXPECT_NEAR(c[cell], 0.75, 1e-12);
  s.density_ratio = 1;
  EXPECT_THROW(ta::light_concentration({s}, grid, 0.97), std::invalid_argument);
}

TEST(ReplicaStats, MeanAndStudentTHalfWidth) {
  const ta::MeanCI m = ta::mean_ci95({1.0, 2.0, 3.0, std::numeric_limits<double>::quiet_NaN()});
  EXPECT_EQ(m.n, 3);
  EXPECT_DOUBLE_EQ(m.mean, 2.0);
  EXPECT_NEAR(m.ci95, 4.302652729749464 / std::sqrt(3.0), 1e-9);  // t(0.975, 2) s / sqrt(3)
  EXPECT_TRUE(std::isnan(ta::mean_ci95({5.0}).ci95));
  EXPECT_EQ(ta::mean_ci95({}).n, 0);
}
