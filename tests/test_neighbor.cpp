// The half Verlet list: every pair within cutoff + skin appears exactly once, rows are sorted, and
// springs survive a rebuild identically whether carried by old index (the fast local path) or by
// global id (the path restarts and migration use).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "bed_fixture.hpp"
#include "engine/simulation.hpp"
#include "neighbor/id_set.hpp"
#include "neighbor/near_filter.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {
// A flowing tiny bed with live springs: 0.2 s of the biaxial protocol from the settled bed.
Simulation flowing_bed() {
  const Scene s = tiny_scene({"protocol.mode=biaxial", "protocol.rpm=30"});
  Simulation sim(s, tiny_settled_bed(),
                 geometry::Protocol::biaxial(deg2rad(57), deg2rad(57), deg2rad(27), s.omega()));
  sim.compute_forces();
  for (int k = 0; k < 10000; ++k) sim.step();
  return sim;
}
}  // namespace

TEST(VerletList, HoldsEveryCloseParticlePairOnceInSortedRows) {
  Simulation sim = flowing_bed();
  sim.request_rebuild();
  sim.step();
  const auto& p = sim.particles();
  const auto& l = sim.neighbors();
  std::set<std::pair<std::uint32_t, std::uint32_t>> listed;
  for (std::uint32_t i = 0; i + 1 < l.start.size(); ++i)
    for (std::uint32_t k = l.start[i]; k < l.start[i + 1]; ++k) {
      EXPECT_GT(l.nbr[k], i);
      if (k > l.start[i]) {
        EXPECT_GT(l.nbr[k], l.nbr[k - 1]) << "row " << i << " not sorted";
      }
      EXPECT_TRUE(listed.insert({i, l.nbr[k]}).second) << "pair listed twice";
    }
  std::size_t needed = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (std::uint32_t j = i + 1; j < p.size(); ++j) {
      const double cut = p.radius[i] + p.radius[j] + l.skin();
      if (norm2(p.x[i] - p.x[j]) < cut * cut) {
        ++needed;
        EXPECT_TRUE(listed.count({i, j})) << "missing pair " << i << " " << j;
      }
    }
  EXPECT_EQ(needed, listed.size());
  EXPECT_GT(needed, p.size());  // a dense bed
}

TEST(VerletList, SpringsCarriedByIndexEqualSpringsMatchedById) {
  Simulation sim = flowing_bed();
  neighbor::ContactHistory by_id;
  sim.neighbors().save_history(sim.particles(), by_id);
  ASSERT_GT(by_id.records().size(), 500u);  // many live springs
  // Rebuild a copy through the local path (particles re-sorted, springs carried by old index).
  Particles copy = sim.particles();
  neighbor::VerletList local = sim.neighbors();
  local.rebuild(copy);  // local carry-over
  std::size_t checked = 0;
  for (std::size_t i = 0; i + 1 < local.start.size(); ++i)
    for (std::uint32_t k = local.start[i]; k < local.start[i + 1]; ++k) {
      const neighbor::HistoryValues want = by_id.lookup(copy.id[i], copy.id[local.nbr[k]]);
      const double* got = local.history.data() + 3 * k;
      ASSERT_TRUE(want[0] == got[0] && want[1] == got[1] && want[2] == got[2]) << "pair " << i;
      checked += want[0] != 0 || want[1] != 0 || want[2] != 0;
    }
  EXPECT_EQ(checked, by_id.records().size());
}

// The store is as wide as the law says, with the law's sign pattern: a history of 6 doubles of
// which components 0, 2 and 4 change sign seen from the other particle (a test layout, no law)
// survives a rebuild that re-sorts the particles and turns pairs around (carried by old index),
// the saved records, their packing into migration rows, and a rebuild matched by global id.
TEST(VerletList, HistoryOfAnotherWidthAndSignPatternSurvivesRebuildsAndRecords) {
  const neighbor::HistoryLayout layout{6, 0x15};
  const int w = layout.width;
  Particles p;
  p.resize(27);
  for (int i = 0; i < 27; ++i) {  // a 3 x 3 x 3 lattice of touching spheres
    p.x[i] = {0.9 * (i % 3 - 1), 0.9 * (i / 3 % 3 - 1), 0.9 * (i / 9 - 1)};
    p.radius[i] = 0.5;
    p.id[i] = i;
  }
  const neighbor::CellGrid grid({-3, -3, -3}, {3, 3, 3}, 1.2);
  neighbor::VerletList list(grid, 0.1, layout);
  list.rebuild(p);
  // The history of pair (a, b) as seen from a: distinct for every pair and component, nonzero.
  const auto value = [&](std::int64_t a, std::int64_t b, int d) {
    const double seen_from_lo = 1000.0 * std::min(a, b) + 10.0 * std::max(a, b) + d + 1;
    return a < b ? seen_from_lo : layout.other_side(d, seen_from_lo);
  };
  const auto check = [&](const neighbor::VerletList& l, const Particles& q) {
    std::size_t pairs = 0, turned = 0;
    for (std::size_t i = 0; i + 1 < l.start.size(); ++i)
      for (std::uint32_t k = l.start[i]; k < l.start[i + 1]; ++k) {
        const std::int64_t a = q.id[i], b = q.id[l.nbr[k]];
        for (int d = 0; d < w; ++d)
          EXPECT_EQ(l.history[static_cast<std::size_t>(w) * k + d], value(a, b, d))
              << a << "-" << b << " component " << d;
        ++pairs;
        turned += a > b;
      }
    EXPECT_GT(turned, 0u);  // some rows hold their pair from the other side
    return pairs;
  };
  ASSERT_EQ(list.history.size(), static_cast<std::size_t>(w) * list.nbr.size());
  for (std::size_t i = 0; i + 1 < list.start.size(); ++i)
    for (std::uint32_t k = list.start[i]; k < list.start[i + 1]; ++k)
      for (int d = 0; d < w; ++d)
        list.history[static_cast<std::size_t>(w) * k + d] = value(p.id[i], p.id[list.nbr[k]], d);
  // Mirror the lattice: the same pairs, in another cell order (ids change places).
  for (auto& x : p.x) x = -x;
  list.rebuild(p);  // carried by old index
  const std::size_t pairs = check(list, p);
  EXPECT_GE(pairs, 54u);  // at least the 54 lattice edges

  neighbor::ContactHistory saved;
  list.save_history(p, saved);
  ASSERT_EQ(saved.width(), w);
  ASSERT_EQ(saved.records().size(), pairs);
  // Migration rows: 2 ids, 6 doubles of history, the anchor; read back unchanged.
  std::vector<double> rows;
  for (const auto& r : saved.records()) neighbor::append_record(r, w, rows);
  ASSERT_EQ(rows.size(), pairs * static_cast<std::size_t>(neighbor::record_doubles(w)));
  std::vector<neighbor::SavedSpring> back;
  for (std::size_t k = 0; k < rows.size();
       k += static_cast<std::size_t>(neighbor::record_doubles(w)))
    back.push_back(neighbor::record_from(rows.data() + k, w));
  for (std::size_t k = 0; k < back.size(); ++k) {
    const auto& r = saved.records()[k];
    EXPECT_TRUE(back[k].lo == r.lo && back[k].hi == r.hi && back[k].history == r.history &&
                back[k].anchor.x == r.anchor.x && back[k].anchor.y == r.anchor.y &&
                back[k].anchor.z == r.anchor.z);
  }
  neighbor::ContactHistory received(layout);
  received.set_records(std::move(back));
  // A fresh list on rotated particles (another order again), histories matched by global id.
  Particles q = p;
  for (auto& x : q.x) x = Vec3{x.y, x.z, x.x};
  neighbor::VerletList fresh(grid, 0.1, layout);
  fresh.rebuild(q, &received);
  EXPECT_EQ(check(fresh, q), pairs);
}

// The list build's distance filter on AVX2 lanes returns exactly the plain filter's indices: runs
// of every length 0..40 (whole blocks of four and tails), candidates at, inside and outside the
// reach, with and without a z period.
namespace {
// The list and the dormant springs of the rigid bulk against the bed's pairs found by brute
// force: a pair within the cutoff is dormant if both of its particles are frozen and listed once
// otherwise, and every spring, listed or dormant, is the one `springs` holds for its pair.
void expect_split(const Particles& p, const neighbor::VerletList& l,
                  const neighbor::ContactHistory& dormant,
                  const neighbor::ContactHistory& springs) {
  auto frozen = [&](std::size_t i) { return p.bulk_state[i] < 0; };
  std::set<std::pair<std::int64_t, std::int64_t>> listed, kept;
  for (std::size_t i = 0; i + 1 < l.start.size(); ++i)
    for (std::uint32_t k = l.start[i]; k < l.start[i + 1]; ++k) {
      const std::size_t j = l.nbr[k];
      ASSERT_FALSE(frozen(i) && frozen(j)) << "a pair of two frozen particles is listed";
      ASSERT_TRUE(listed.insert(std::minmax(p.id[i], p.id[j])).second) << "pair listed twice";
      const neighbor::HistoryValues want = springs.lookup(p.id[i], p.id[j]);
      for (int d = 0; d < 3; ++d) ASSERT_EQ(l.history[3 * k + d], want[d]) << "pair " << i;
    }
  for (const auto& r : dormant.records()) {
    ASSERT_TRUE(kept.insert({r.lo, r.hi}).second) << "dormant pair kept twice";
    const neighbor::HistoryValues want = springs.lookup(r.lo, r.hi);
    for (int d = 0; d < 3; ++d) ASSERT_EQ(r.history[d], want[d]);
  }
  std::size_t pairs = 0, frozen_pairs = 0, frozen_springs = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double cut = p.radius[i] + p.radius[j] + l.skin();
      if (norm2(p.x[i] - p.x[j]) >= cut * cut) continue;
      const auto ids = std::minmax(p.id[i], p.id[j]);
      const bool live = springs.lookup(p.id[i], p.id[j])[0] != 0;
      if (frozen(i) && frozen(j)) {
        ++frozen_pairs;
        frozen_springs += live;
        EXPECT_EQ(kept.count(ids), live ? 1u : 0u) << "dormant spring of " << i << ", " << j;
      } else {
        ++pairs;
        EXPECT_EQ(listed.count(ids), 1u) << "missing pair " << i << ", " << j;
      }
    }
  EXPECT_EQ(listed.size(), pairs);
  EXPECT_EQ(kept.size(), frozen_springs);
  EXPECT_GT(frozen_springs, p.size() / 4);  // the case is not empty
  EXPECT_GT(pairs, p.size() / 2);
  // One rank, one border class: the sort puts the frozen after every moving particle, so the
  // moving rows are one run (the integrator's lanes take it) and a frozen row lists nothing (its
  // moving partners lie below it, in their rows).
  std::size_t first_frozen = p.size();
  for (std::size_t i = 0; i < p.size() && first_frozen == p.size(); ++i)
    if (frozen(i)) first_frozen = i;
  std::size_t out_of_place = 0, frozen_rows_listing = 0;
  for (std::size_t i = first_frozen; i < p.size(); ++i) {
    out_of_place += !frozen(i);
    frozen_rows_listing += l.start[i + 1] != l.start[i];
  }
  EXPECT_EQ(out_of_place, 0u);
  EXPECT_EQ(frozen_rows_listing, 0u);
  EXPECT_LT(first_frozen, p.size());
}
}  // namespace

// The rigid bulk's list: a pair of two frozen particles leaves the list, its spring kept by ids
// (dormant), and comes back with it when one of the two thaws; freezing and thawing at the same
// rebuild, a rebuild matched by ids (a restart) and one carried by old index split the pairs alike.
TEST(VerletList, FrozenPairsLeaveTheListWithTheirSpringsAndComeBackWithThem) {
  Simulation sim = flowing_bed();
  neighbor::ContactHistory springs;  // every live spring of the bed: positions do not change here
  sim.neighbors().save_history(sim.particles(), springs);
  Particles p = sim.particles();
  neighbor::VerletList list = sim.neighbors();
  neighbor::ContactHistory dormant(list.history_layout());
  // Freeze half of the bed (x < 0).
  p.set_rigid_columns(true);  // (a dynamic run's particles leave them out)
  for (std::size_t i = 0; i < p.size(); ++i) p.bulk_state[i] = p.x[i].x < 0 ? -1 : 0;
  list.rebuild(p, nullptr, &dormant);
  {
    SCOPED_TRACE("half of the bed frozen");
    expect_split(p, list, dormant, springs);
  }
  // Thaw the upper half of the frozen ones and freeze a band of the moving ones, at one rebuild.
  const double r = sim.wall().radius;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.x[i].x < 0 && p.x[i].y > -0.5 * r) p.bulk_state[i] = 0;
    if (p.x[i].x >= 0 && p.x[i].x < 0.3 * r) p.bulk_state[i] = -1;
  }
  list.rebuild(p, nullptr, &dormant);
  {
    SCOPED_TRACE("thawed and frozen at one rebuild");
    expect_split(p, list, dormant, springs);
  }
  // A restart: the list's and the dormant springs saved by ids, matched into a new list.
  neighbor::ContactHistory saved;
  list.save_history(p, saved, false);
  std::vector<neighbor::SavedSpring> all = saved.records();
  all.insert(all.end(), dormant.records().begin(), dormant.records().end());
  saved.set_records(std::move(all));
  Particles q = p;
  neighbor::VerletList again = list;
  neighbor::ContactHistory dormant_again(list.history_layout());
  again.rebuild(q, &saved, &dormant_again);
  {
    SCOPED_TRACE("a restart");
    expect_split(q, again, dormant_again, springs);
  }
  EXPECT_EQ(dormant_again.records().size(), dormant.records().size());
}

// The rigid bulk's id sets answer as a std::set of the same ids, whether a byte per id or a table,
// and a rank's few ids among a large realization's take memory by their count, not by the largest
// id (a byte per id up to 10^12 would not fit).
TEST(IdSet, AnswersAsASetDenseOrHashedAndTakesMemoryByItsCount) {
  std::mt19937_64 rng(7);
  for (const std::int64_t range : {std::int64_t{1000}, std::int64_t{1000000000000}}) {
    std::vector<std::int64_t> ids;
    std::uniform_int_distribution<std::int64_t> pick(0, range - 1);
    for (int k = 0; k < 3000; ++k) ids.push_back(pick(rng));
    for (int k = 0; k < 500; ++k) ids.push_back(ids[static_cast<std::size_t>(k)]);  // repeats
    const std::set<std::int64_t> expected(ids.begin(), ids.end());
    const tumble::neighbor::IdSet set([&](auto mark) {
      for (const std::int64_t id : ids) mark(id);
    });
    EXPECT_EQ(set.dense(), range == 1000) << range;
    std::size_t wrong = 0;
    for (const std::int64_t id : ids) wrong += !set(id);
    for (int k = 0; k < 20000; ++k) {
      const std::int64_t id = pick(rng);
      wrong += set(id) != (expected.count(id) == 1);
    }
    for (const std::int64_t id : {std::int64_t{-1}, range, range + 12345})
      wrong += set(id) != (expected.count(id) == 1);
    EXPECT_EQ(wrong, 0u) << range;
    EXPECT_LE(set.memory_bytes(), 64 * ids.size()) << range;
  }
  const tumble::neighbor::IdSet none([](auto) {});
  EXPECT_TRUE(none.empty());
  EXPECT_FALSE(none(0));
  const tumble::neighbor::IdSet one([](auto mark) { mark(std::int64_t{5000000}); });
  EXPECT_FALSE(one.dense());
  EXPECT_TRUE(one(5000000));
  EXPECT_FALSE(one(4999999));
  EXPECT_FALSE(one(0));
}

TEST(NearFilter, LanesReturnThePlainIndices) {
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2")) {
    EXPECT_EQ(tumble::neighbor::near_filter(), &tumble::neighbor::near_filter_plain);
    return;
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::size_t n = 48;
  std::vector<double> x(3 * n), radius(n);
  for (std::size_t j = 0; j < n; ++j) {
    for (int q = 0; q < 3; ++q) x[3 * j + q] = 2.0 * u(rng);
    radius[j] = 0.5 + 0.25 * u(rng);
  }
  const double xi[3] = {0.1, -0.2, 1.9};
  x[3] = xi[0] + 1.0;  // candidate 1 at the reach of (0.3 + 0.6) + 0.1
  x[4] = xi[1];
  x[5] = xi[2];
  radius[1] = 0.6;
  std::size_t found = 0, tried = 0;
  for (double period : {0.0, 4.0}) {
    for (std::uint32_t lo = 0; lo < 8; ++lo)
      for (std::uint32_t hi = lo; hi <= lo + 40; ++hi) {
        std::vector<std::uint32_t> a(hi - lo + 4), b(hi - lo + 4);
        const std::size_t na = tumble::neighbor::near_filter_plain(x.data(), radius.data(), lo, hi,
                                                                   xi, 0.3, 0.1, period, a.data());
        const std::size_t nb = tumble::neighbor::near_filter_avx2(x.data(), radius.data(), lo, hi,
                                                                  xi, 0.3, 0.1, period, b.data());
        ASSERT_EQ(na, nb) << "lo " << lo << " hi " << hi << " period " << period;
        for (std::size_t k = 0; k < na; ++k) ASSERT_EQ(a[k], b[k]);
        found += na;
        tried += hi - lo;
      }
  }
  EXPECT_GT(found, tried / 10);  // both outcomes occur often
  EXPECT_LT(found, tried * 9 / 10);
}

// A pair is listed from both of its sides alike (two ranks each decide a border pair from their
// own particle, possibly in different paths of the filter): pairs placed within a few ulps of
// the cutoff, random radii and skins, j asked about from i and i from j in every path (plain,
// AVX2's four lanes, AVX2's one-at-a-time remainder): all answers agree. The cutoff summed as
// (r_i + skin) + r_j, the order before, disagrees on some of the same pairs (counted here, so
// the test can fail).
TEST(NearFilter, PairListedFromBothSidesAlike) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<tumble::neighbor::NearFilter> filters = {&tumble::neighbor::near_filter_plain};
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) filters.push_back(&tumble::neighbor::near_filter_avx2);
  long asymmetric = 0, listed = 0, asked = 0, old_asymmetric = 0;
  const int pairs = 20000;
  for (int k = 0; k < pairs; ++k) {
    const double r[2] = {1e-3 * (0.5 + u(rng)), 1e-3 * (0.5 + u(rng))};
    const double skin = 1e-3 * (0.01 + 0.5 * u(rng));
    // j along a random direction at the cutoff, nudged by a few ulps either way
    const double cut = (r[0] + r[1]) + skin;
    double dir[3] = {u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
    const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    double dist = cut;
    for (int n = static_cast<int>(u(rng) * 7) - 3; n != 0; n += n > 0 ? -1 : 1)
      dist = std::nextafter(dist, n > 0 ? 1.0 : 0.0);
    std::vector<double> x(24, 0.0), radius(8, 1e-3);  // two particles, room for a 4-lane load
    for (int q = 0; q < 3; ++q) {
      x[q] = 0.01 * (u(rng) - 0.5);
      x[3 + q] = x[q] + dist * dir[q] / len;
    }
    radius[0] = r[0];
    radius[1] = r[1];
    for (int q = 6; q < 24; ++q) x[q] = 10.0 + q;  // particles 2-7 far away
    // Every answer, each way: ranges of four candidates (AVX2: its lanes) and of one (its
    // remainder); j's index is 1 (from i), i's is 0 (from j).
    std::vector<bool> answers;
    for (const auto filter : filters) {
      std::uint32_t out[8];
      const std::size_t four_from_i =
          filter(x.data(), radius.data(), 1, 5, x.data(), r[0], skin, 0.0, out);
      answers.push_back(four_from_i > 0 && out[0] == 1);
      answers.push_back(filter(x.data(), radius.data(), 1, 2, x.data(), r[0], skin, 0.0, out) > 0);
      const std::size_t four_from_j =
          filter(x.data(), radius.data(), 0, 4, x.data() + 3, r[1], skin, 0.0, out);
      answers.push_back(four_from_j > 0 && out[0] == 0);
      answers.push_back(filter(x.data(), radius.data(), 0, 1, x.data() + 3, r[1], skin, 0.0, out) >
                        0);
    }
    for (const bool a : answers) asymmetric += a != answers[0];
    listed += answers[0];
    asked += 1;
    double d2 = 0;
    for (int q = 0; q < 3; ++q) d2 += (x[q] - x[3 + q]) * (x[q] - x[3 + q]);
    const double old_ij = (r[0] + skin) + r[1], old_ji = (r[1] + skin) + r[0];
    old_asymmetric += (d2 < old_ij * old_ij) != (d2 < old_ji * old_ji);
  }
  EXPECT_EQ(asymmetric, 0);
  EXPECT_GT(listed, asked / 10);  // both outcomes occur
  EXPECT_LT(listed, asked * 9 / 10);
  EXPECT_GT(old_asymmetric, 0) << "no pair near enough the cutoff to tell the orders apart";
  std::printf(
      "[ symmetry ] %ld of %d pairs at the cutoff listed from one side only with "
      "(r_i + skin) + r_j\n",
      old_asymmetric, pairs);
}
