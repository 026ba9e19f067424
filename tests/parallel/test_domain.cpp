// The domain-decomposed engine against the serial one, run by ctest under mpiexec with 2 and 3
// ranks (tests/parallel/CMakeLists.txt). Every rank also runs the serial reference itself, so a
// comparison needs no extra communication.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>

#include "analysis/radial_segregation.hpp"
#include "engine/simulation.hpp"
#include "parallel/domain.hpp"
#include "parallel/wide_bins.hpp"
#include "parallel_helpers.hpp"
#include "run/realization.hpp"
#include "scene/fill.hpp"
#include "scene/fill_cylinder.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {

// Every id 0..n-1 exactly once over the ranks, owned particles only.
void expect_ids_conserved(const Simulation& sim, std::int64_t n) {
  const Particles all = sim.gather_all();
  ASSERT_EQ(static_cast<std::int64_t>(all.size()), n);
  for (std::int64_t k = 0; k < n; ++k) ASSERT_EQ(all.id[k], k);
}

// The settled bed stirred at up to 0.5 m/s per component, the same velocities on every rank
// (`seed`): particles cross the cuts between ranks within a few steps.
Particles stirred_tiny_bed(const Scene& s, unsigned seed) {
  Particles bed = tiny_bed(s);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (Vec3& v : bed.v) v = {u(rng), u(rng), u(rng)};
  return bed;
}

// Positions, velocities and spins of two gathered beds (same size, sorted by id) that differ in
// any bit.
std::size_t motions_differing(const Particles& a, const Particles& b) {
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (const std::vector<Vec3> Particles::*f : {&Particles::x, &Particles::v, &Particles::w}) {
      const Vec3 p = (a.*f)[i], q = (b.*f)[i];
      differ += !(p.x == q.x && p.y == q.y && p.z == q.z);
    }
  return differ;
}

}  // namespace

// Same scene and seed on 1 rank and on every rank of the world: 200 steps of the rotating
// protocol agree to round-off (1e-9 of a diameter), and no particle is lost or duplicated at any
// step (the gathered ids are exactly 0..N-1 after every step). A tiny skin and a threshold of 1
// force a rebuild (migration) every few steps and a re-bisection at each of them. The state's
// memory stays within 1/8 of the serial one's per particle held. With Newton across borders (the
// default: one rank computes a border pair, the ghosts' sums go back, its elastic energy counts
// once) and without (both ranks compute it, half its energy each).
static void matches_serial_trajectory(const char* newton) {
  SCOPED_TRACE(newton);
  const Scene s = tiny({"neighbor.skin=0.02", "parallel.rebalance_threshold=1.0", newton});
  const Particles bed = tiny_bed(s);
  Simulation serial(s, bed, biaxial(s));
  Simulation par(s, share_of(bed, MPI_COMM_WORLD), biaxial(s), 0, 0, MPI_COMM_WORLD);
  EXPECT_EQ(par.neighbors().newton(), s.newton == OnOff::on);
  serial.compute_forces();
  par.compute_forces();
  const auto n = static_cast<std::int64_t>(bed.size());
  std::size_t most_held = 0;  // owned and ghosts, the most this rank held after a step
  for (int k = 0; k < 200; ++k) {
    serial.step();
    par.step();
    ASSERT_EQ(par.global_count(), n) << "step " << k;
    expect_ids_conserved(par, n);
    most_held = std::max(most_held, par.particles().size());
  }
  expect_ids_conserved(par, n);
  EXPECT_GT(par.rebuilds(), 5u);
  ASSERT_NE(par.domain(), nullptr);
  EXPECT_GT(par.domain()->bisections(), 1);
  EXPECT_GT(par.domain()->ghosts(), 0);
  EXPECT_LT(max_deviation(serial.particles(), par.gather_all()), 1e-9 * s.d_small);
  const EnergyBreakdown es = serial.energy(), ep = par.energy();
  EXPECT_NEAR(ep.kinetic, es.kinetic, 1e-9 * es.kinetic);
  EXPECT_NEAR(ep.elastic, es.elastic, 1e-6 * es.elastic);
  // Through all that migration the state holds this rank's particles and ghosts with at most 1/8
  // of headroom over the most it held (the columns grow, they never shrink): the ghosts,
  // appended after the owned particles are sorted, no longer double the columns (they did: 180 B
  // per particle on one rank, 254-416 B per particle held on 2 and 3).
  const double per_row_serial =
      static_cast<double>(serial.memory().particles) / static_cast<double>(bed.size());
  const double per_row =
      static_cast<double>(par.memory().particles) / static_cast<double>(most_held);
  EXPECT_LE(per_row, 1.125 * per_row_serial + 1e-9)
      << per_row << " B per particle held on rank " << par.domain()->rank() << ", serial "
      << per_row_serial;
}

TEST(Domain, MatchesSerialTrajectoryAndConservesIds) {
  matches_serial_trajectory("parallel.newton=on");
  matches_serial_trajectory("parallel.newton=off");
}

// Every spring survives the rebuilds and the migration: a rebuild carries the springs of the
// pairs it held by index and receives only those of the pairs whose particles arrive
// (VerletList::keep_springs). With a tiny skin and a threshold of 1 (a rebuild every few steps,
// a re-bisection at each, many particles changing rank), after every step each live spring of
// the serial run is in the list of every rank that computes its pair, equal to round-off, and no
// rank holds a spring the serial run has not. Newton off: every rank that owns one of the pair's
// particles computes it; on: the owner of the particle computes_border_pair names (a spring that
// changes hands when that particle changes rank, not the other), and only that rank holds it.
static void every_spring_survives_the_migration(const char* newton) {
  const Scene s = tiny({"neighbor.skin=0.02", "parallel.rebalance_threshold=1.0", newton});
  const bool on = s.newton == OnOff::on;
  const Particles bed = stirred_tiny_bed(s, 11);
  Simulation serial(s, bed, biaxial(s));
  Simulation par(s, share_of(bed, MPI_COMM_WORLD), biaxial(s), 0, 0, MPI_COMM_WORLD);
  serial.compute_forces();
  par.compute_forces();
  std::vector<std::uint8_t> was_here(bed.size(), 0);
  std::int64_t compared = 0, arrived = 0, missing = 0, extra = 0;
  double worst = 0;
  for (int k = 0; k < 120; ++k) {
    serial.step();
    par.step();
    neighbor::ContactHistory ref;
    serial.save_contacts(ref);  // sorted by ids, indexed
    const Particles& p = par.particles();
    const neighbor::VerletList& list = par.neighbors();
    const int w = list.history_layout().width;
    std::set<std::pair<std::int64_t, std::int64_t>> held;
    std::vector<std::uint8_t> here(bed.size(), 0);
    for (std::size_t i = 0; i < par.local_count(); ++i) {
      const auto id = static_cast<std::size_t>(p.id[i]);
      arrived += k > 0 && !was_here[id];
      here[id] = 1;
      for (std::uint32_t q = list.start[i]; q < list.start[i + 1]; ++q) {
        const double* h = list.history.data() + w * q;
        neighbor::HistoryValues r{};
        ref.lookup(p.id[i], p.id[list.nbr[q]], r.data());
        const bool live = neighbor::is_live(r.data(), w);
        if (live)
          held.insert({std::min(p.id[i], p.id[list.nbr[q]]), std::max(p.id[i], p.id[list.nbr[q]])});
        extra += !live && neighbor::is_live(h, w);
        if (!live) continue;
        ++compared;
        for (int d = 0; d < w; ++d) worst = std::max(worst, std::abs(h[d] - r[d]));
      }
    }
    // Every serial spring whose pair this rank computes is in its list, and no other.
    std::set<std::int64_t> own(p.id.begin(), p.id.begin() + par.local_count());
    for (const neighbor::SavedSpring& r : ref.records()) {
      const bool both = own.count(r.lo) && own.count(r.hi);
      const bool computes =
          on ? both || own.count(neighbor::computes_border_pair(r.lo, r.hi) ? r.lo : r.hi)
             : own.count(r.lo) || own.count(r.hi);
      missing += computes && !held.count({r.lo, r.hi});
      extra += !computes && held.count({r.lo, r.hi});
    }
    was_here = here;
  }
  std::int64_t totals[2] = {arrived, compared};
  MPI_Allreduce(MPI_IN_PLACE, totals, 2, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_GT(par.rebuilds(), 20u);
  EXPECT_GT(par.domain()->bisections(), 10);
  EXPECT_GT(totals[0], 200) << "too few particles changed rank to test the migration";
  EXPECT_GT(totals[1], 100000);
  if (world_rank() == 0)
    std::printf("[ springs  ] %lld particles changed rank, %lld live springs compared\n",
                static_cast<long long>(totals[0]), static_cast<long long>(totals[1]));
  EXPECT_EQ(missing, 0);
  EXPECT_EQ(extra, 0);
  EXPECT_LT(worst, 1e-9 * s.d_small);
}

TEST(Domain, EverySpringSurvivesTheMigrationNewtonOff) {
  every_spring_survives_the_migration("parallel.newton=off");
}
TEST(Domain, EverySpringSurvivesTheMigrationNewtonOn) {
  every_spring_survives_the_migration("parallel.newton=on");
}

// The ghosts' refresh between ranks of one node goes through a shared window (Domain::
// begin_refresh); with TUMBLE_REFRESH_MESSAGES=1 it goes by messages, and with
// TUMBLE_HALO_NODE_RANKS=2 on 3 ranks both at once (ranks 0 and 1 share a window, rank 2 is a
// node of its own). All give the same run to the last bit: a stirred bed, 150 steps with
// rebuilds and re-bisections (so the window is laid out again and grown while in use).
TEST(Domain, SharedWindowRefreshEqualsMessages) {
  const Scene s = tiny({"neighbor.skin=0.05", "parallel.rebalance_threshold=1.0"});
  const Particles bed = stirred_tiny_bed(s, 5);
  setenv("TUMBLE_REFRESH_MESSAGES", "1", 1);
  Simulation messages(s, share_of(bed, MPI_COMM_WORLD), biaxial(s), 0, 0, MPI_COMM_WORLD);
  unsetenv("TUMBLE_REFRESH_MESSAGES");
  Simulation shared(s, share_of(bed, MPI_COMM_WORLD), biaxial(s), 0, 0, MPI_COMM_WORLD);
  setenv("TUMBLE_HALO_NODE_RANKS", "2", 1);
  Simulation mixed(s, share_of(bed, MPI_COMM_WORLD), biaxial(s), 0, 0, MPI_COMM_WORLD);
  unsetenv("TUMBLE_HALO_NODE_RANKS");
  messages.compute_forces();
  shared.compute_forces();
  mixed.compute_forces();
  for (int k = 0; k < 150; ++k) {
    messages.step();
    shared.step();
    mixed.step();
  }
  EXPECT_EQ(messages.domain()->shared_sources(), 0);
  EXPECT_GT(shared.domain()->shared_sources(), 0);  // (one node: every neighbour)
  if (size_of(MPI_COMM_WORLD) == 3) {               // ranks 0 and 1 share a window, rank 2 has none
    if (world_rank() == 2) {
      EXPECT_EQ(mixed.domain()->shared_sources(), 0);
    } else {
      EXPECT_GT(mixed.domain()->shared_sources(), 0);
    }
  }
  EXPECT_GT(shared.rebuilds(), 10u);
  EXPECT_GT(shared.domain()->bisections(), 5);
  const Particles a = messages.gather_all(), b = shared.gather_all(), c = mixed.gather_all();
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  EXPECT_EQ(motions_differing(a, b), 0u);
  EXPECT_EQ(motions_differing(a, c), 0u);
}

// The thin halo of a size mixture (Domain::thin_halo: a small particle goes to another rank
// only where a particle of that rank may pair with it) against one halo for all
// (TUMBLE_FULL_HALO=1): the same lists, so the same run to the last bit, with fewer ghosts. The
// stirred Yu bed with rebuilds and re-bisections, and the periodic cylinder, whose wide
// particles are found across the periodic ends by their nearest image.
TEST(Domain, SizeSplitHaloEqualsOneHalo) {
  auto compare = [](const Scene& s, const Particles& bed, const geometry::Protocol& proto,
                    int steps) {
    setenv("TUMBLE_FULL_HALO", "1", 1);
    Simulation full(s, share_of(bed, MPI_COMM_WORLD), proto, 0, 0, MPI_COMM_WORLD);
    unsetenv("TUMBLE_FULL_HALO");
    Simulation thin(s, share_of(bed, MPI_COMM_WORLD), proto, 0, 0, MPI_COMM_WORLD);
    full.compute_forces();
    thin.compute_forces();
    long long counts[4] = {0, 0, 0, 0};  // ghosts full, thin; list pairs full, thin (summed)
    for (int k = 0; k < steps; ++k) {
      full.step();
      thin.step();
      counts[0] += full.domain()->ghosts();
      counts[1] += thin.domain()->ghosts();
      counts[2] += static_cast<long long>(full.neighbors().nbr.size());
      counts[3] += static_cast<long long>(thin.neighbors().nbr.size());
    }
    MPI_Allreduce(MPI_IN_PLACE, counts, 4, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_GT(thin.rebuilds(), 10u);
    EXPECT_EQ(counts[2], counts[3]) << "the lists hold other pairs";
    EXPECT_LT(counts[1], 0.9 * counts[0]) << "the thin halo saves under 10% of the ghosts";
    if (world_rank() == 0)
      std::printf("[ halo     ] ghosts per step: full %.0f, thin %.0f\n",
                  static_cast<double>(counts[0]) / steps, static_cast<double>(counts[1]) / steps);
    const Particles a = full.gather_all(), b = thin.gather_all();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(motions_differing(a, b), 0u);
  };
  const Scene yu = tiny({"neighbor.skin=0.05", "parallel.rebalance_threshold=1.0"});
  compare(yu, stirred_tiny_bed(yu, 9), biaxial(yu), 150);

  const Scene cyl =
      load_scene(std::string(TUMBLE_SOURCE_DIR) + "/scenes/rapaport/mini/E.toml",
                 {"tumbler.periodic=on", "neighbor.skin=0.1", "parallel.rebalance_threshold=1.02"});
  CylinderBed cb = make_cylinder_bed(cyl);
  for (double& r : cb.particles.radius) r *= cb.shrink;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  for (Vec3& v : cb.particles.v) v = {u(rng), u(rng), u(rng)};
  compare(cyl, cb.particles, geometry::Protocol::single_axis(name_of(cyl.axis)[0], cyl.omega()),
          300);
}

// The thin halo's binned search of the wide particles (parallel::WideBins) against a scan of all
// of them, with the nearest image across a periodic end: random wide particles of two source
// ranks in a slab (one far away, one not a number), random points around it, reaches up to the
// cell size.
TEST(Domain, WideBinsFindWhatAScanFinds) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  for (const double period : {0.0, 10.0}) {
    std::vector<std::vector<double>> from(3);  // rank 1 sends nothing
    for (int r : {0, 2})
      for (int k = 0; k < 400; ++k)
        from[r].insert(from[r].end(),
                       {8 * u(rng) - 4, 3 * u(rng), period > 0 ? 10 * u(rng) - 5 : 8 * u(rng) - 4,
                        0.2 + 0.3 * u(rng)});
    // An escaped particle far away (the grid coarsens rather than spanning it in small cells)
    // and one with a NaN position (left out) must not change any answer.
    from[2].insert(from[2].end(), {1e12, 0, 0, 0.3, std::nan(""), 0, 0, 0.3});
    const double skin = 0.1;  // r_i <= 0.5, r_w <= 0.5
    parallel::WideBins bins;
    bins.assign(from, 0.5 + skin, period);
    int hits = 0, misses = 0;
    for (int q = 0; q < 4000; ++q) {
      const Vec3 x{10 * u(rng) - 5, 5 * u(rng) - 1, period > 0 ? 10 * u(rng) - 5 : 10 * u(rng) - 5};
      const double ri = 0.5 * u(rng);
      for (int r = 0; r < 3; ++r) {
        bool scan = false;
        for (std::size_t k = 0; k + 4 <= from[r].size(); k += 4) {
          double dz = x.z - from[r][k + 2];
          if (period > 0) dz -= period * std::round(dz / period);
          const double dx = x.x - from[r][k], dy = x.y - from[r][k + 1];
          const double cut = ri + from[r][k + 3] + skin;
          scan = scan || dx * dx + dy * dy + dz * dz <= cut * cut;
        }
        ASSERT_EQ(bins.any_within(r, x, ri + skin, 1.0), scan) << "rank " << r << ", query " << q;
        hits += scan;
        misses += !scan;
      }
    }
    EXPECT_GT(hits, 500);  // both answers are tested often
    EXPECT_GT(misses, 500);
  }
}

// The same on a sub-communicator: the world's ranks split into groups, each group runs the scene
// on its own (a campaign's rank groups). With 3 ranks: a 2-rank group and a 1-rank group.
TEST(Domain, RunsOnASubCommunicator) {
  const int world = size_of(MPI_COMM_WORLD);
  MPI_Comm group;
  MPI_Comm_split(MPI_COMM_WORLD, world_rank() < 2 ? 0 : 1, world_rank(), &group);
  const Scene s = tiny({"neighbor.skin=0.05"});
  const Particles bed = tiny_bed(s);
  Simulation serial(s, bed, biaxial(s));
  Simulation par(s, share_of(bed, group), biaxial(s), 0, 0, group);
  serial.compute_forces();
  par.compute_forces();
  for (int k = 0; k < 100; ++k) {
    serial.step();
    par.step();
  }
  EXPECT_EQ(par.global_count(), static_cast<std::int64_t>(bed.size()));
  EXPECT_LT(max_deviation(serial.particles(), par.gather_all()), 1e-9 * s.d_small);
  EXPECT_EQ(par.domain() != nullptr, size_of(group) > 1) << "world " << world;
  MPI_Comm_free(&group);
}

// The halo is as thin as each particle's size allows (a particle is a ghost where its surface is
// within r_max + skin of a rank's domain; a small one of a size mixture only where a particle of
// that rank may pair with it: Domain::thin_halo) and still thick enough: on a dense random bed,
// half of its particles large (many large-large pairs: the ones the halo must reach farthest for),
// the pairs of every rank's list, by id, are exactly the serial list's pairs that hold one of the
// rank's own particles, and every rank holds
// fewer ghosts than the particles within the uniform reach 2 r_max + skin of its domain (the old
// halo). The list is all the halo decides, so the bed is never stepped (it overlaps freely).
TEST(Domain, ThinHaloHoldsEveryPairOfTheSerialList) {
  const Scene s = tiny({"neighbor.skin=0.1", "protocol.mode=rest"});
  Particles bed;
  std::mt19937_64 rng(20261126);  // the same bed on every rank
  std::uniform_real_distribution<double> u(-1, 1);
  const double R = 0.9 * s.radius;
  while (bed.size() < 6000) {
    const Vec3 x{R * u(rng), R * u(rng), R * u(rng)};
    if (norm2(x) > R * R || x.y > 0) continue;
    const std::size_t k = bed.size();
    bed.resize(k + 1);
    bed.x[k] = x;
    bed.id[k] = static_cast<std::int64_t>(k);
    bed.species[k] = static_cast<std::int32_t>(rng() % 2);
  }
  set_species_properties(s, bed);
  Simulation serial(s, bed, geometry::Protocol::at_rest());
  Simulation par(s, share_of(bed, MPI_COMM_WORLD), geometry::Protocol::at_rest(), 0, 0,
                 MPI_COMM_WORLD);
  serial.compute_forces();
  par.compute_forces();
  const auto pairs_of = [](const Simulation& sim) {
    const Particles& p = sim.particles();
    const neighbor::VerletList& list = sim.neighbors();
    std::vector<std::int64_t> out;
    for (std::size_t i = 0; i < sim.local_count(); ++i)
      for (std::uint32_t k = list.start[i]; k < list.start[i + 1]; ++k) {
        const std::int64_t a = p.id[i], b = p.id[list.nbr[k]];
        out.push_back(std::min(a, b));
        out.push_back(std::max(a, b));
      }
    return out;
  };
  // Each rank computes the force of every pair of two of its own particles, and of a pair with
  // a ghost: with Newton across borders (the default) where computes_border_pair names its own
  // particle, else always. Its list must hold exactly those (the union over the ranks is not
  // enough: a pair found by neither rank, or by both with Newton, moves its particles wrongly).
  std::set<std::int64_t> owned;
  for (std::size_t i = 0; i < par.local_count(); ++i) owned.insert(par.particles().id[i]);
  const bool newton = par.neighbors().newton();
  EXPECT_TRUE(newton);
  std::set<std::pair<std::int64_t, std::int64_t>> here, expected;
  const std::vector<std::int64_t> mine = pairs_of(par), ref = pairs_of(serial);
  for (std::size_t k = 0; k < mine.size(); k += 2) here.insert({mine[k], mine[k + 1]});
  for (std::size_t k = 0; k < ref.size(); k += 2) {
    const std::int64_t a = ref[k], b = ref[k + 1];
    const bool computes = owned.count(a) && owned.count(b)
                              ? true
                              : owned.count(neighbor::computes_border_pair(a, b) ? a : b) ||
                                    (!newton && (owned.count(a) || owned.count(b)));
    if (computes) expected.insert({a, b});
  }
  EXPECT_GT(ref.size() / 2, 10 * bed.size());
  EXPECT_TRUE(here == expected) << here.size() << " pairs in the list of rank "
                                << par.domain()->rank() << ", " << expected.size()
                                << " serial pairs with one of its particles";
  // The rows before interior_rows() look for no ghost partner (the step runs them while the
  // ghosts' refresh travels): the equality above holds only if no pair of theirs has one.
  // Both parts of the list are in use here.
  const neighbor::VerletList& list = par.neighbors();
  const std::size_t inner = list.interior_rows(), n = par.local_count();
  EXPECT_GT(inner, n / 4);
  EXPECT_LT(inner, n);
  std::size_t ghost_pairs = 0;
  std::set<std::uint32_t> partners;  // the ghosts in a pair of the list
  for (std::size_t i = inner; i < n; ++i)
    for (std::uint32_t k = list.start[i]; k < list.start[i + 1]; ++k) {
      ghost_pairs += list.nbr[k] >= n;
      if (list.nbr[k] >= n) partners.insert(list.nbr[k]);
    }
  EXPECT_GT(ghost_pairs, 0u);
  // Only those are refreshed (Domain::keep_used_ghosts), fewer than the halo holds.
  EXPECT_EQ(par.domain()->refreshed_ghosts(), static_cast<std::int64_t>(partners.size()));
  EXPECT_LT(par.domain()->refreshed_ghosts(), par.domain()->ghosts());

  // The old halo: every other rank's particle within 2 r_max + skin of this rank's box.
  const Particles everyone = par.gather_all();
  double r_min = 1e300, r_max = 0;
  for (double r : everyone.radius) r_min = std::min(r_min, r), r_max = std::max(r_max, r);
  ASSERT_LT(r_min, 0.9 * r_max) << "the test needs two sizes";
  const parallel::Domain& dom = *par.domain();
  const double reach = 2 * r_max + par.neighbors().skin();
  std::int64_t uniform = 0;
  for (std::size_t i = 0; i < everyone.size(); ++i)
    if (dom.tree().owner(everyone.x[i]) != dom.rank()) {
      std::vector<int> near;
      dom.tree().ranks_near(everyone.x[i], reach, 0.0, near);
      uniform += std::find(near.begin(), near.end(), dom.rank()) != near.end();
    }
  const auto ghosts = static_cast<std::int64_t>(par.particles().size() - par.local_count());
  EXPECT_GT(ghosts, 0);
  EXPECT_LT(ghosts, uniform);
}

// A sliding contact carried across the rank border keeps its spring: two touching particles
// slide past each other (relative tangential velocity along z) while both move along x through
// the middle of the tumbler, where the first cut lies (the lattice around them is symmetric). The
// spring after the crossing equals the serial run's to round-off.
TEST(Domain, SlidingContactKeepsItsSpringAcrossTheBorder) {
  // Soft contacts (t_c = 4 ms, 50 steps of contact) and no re-bisection: the cut stays put while
  // the pair crosses it.
  const Scene s = parse_scene(
      "",
      {"gravity.g=0", "tumbler.radius=0.02", "protocol.mode=rest", "particles.fill_level=0.05",
       "contact.collision_time=4e-3", "neighbor.skin=0.05", "parallel.rebalance_threshold=100"},
      "slide");
  Particles all;
  std::vector<Vec3> x, v;
  // The pair: just touching, closing at 0.1 m/s, sliding at 0.1 m/s along z, moving at 1 m/s
  // along x. 23 particles lie left of the gap (-0.0005, 0.004), the first cut's share of them
  // right of it, so the cut is at its middle, x = 0.00175: crossed after ~28 steps, while the
  // contact lasts ~50.
  const double d = s.d_small;
  x.push_back({-0.0005, 0, 0});
  v.push_back({1, 0.05, 0.05});
  x.push_back({-0.0005, d, 0});
  v.push_back({1, -0.05, -0.05});
  for (int i = -3; i <= 3; ++i)
    for (int k = -3; k <= 3; ++k)
      if (i != 0) {
        x.push_back({0.004 * i, -0.01, 0.004 * k});
        v.push_back({0, 0, 0});
      }
  // Extra particles on the right make the first cut's share (n/2 of n ranks) exactly the 23 on
  // the left: 2 extra for 2 ranks, 25 for 3.
  const int n = size_of(MPI_COMM_WORLD), lo = n / 2;
  const int extra = 23 * (n - lo) / lo - 21;
  ASSERT_LE(extra, 30) << "laid out for up to 3 ranks";
  for (int e = 0; e < extra; ++e) {
    x.push_back(
        {0.008 + 0.004 * (e % 2), -0.004 + 0.004 * ((e / 2) % 3), -0.008 + 0.004 * (e / 6)});
    v.push_back({0, 0, 0});
  }
  all.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    all.x[i] = x[i];
    all.v[i] = v[i];
    all.id[i] = static_cast<std::int64_t>(i);
  }
  set_species_properties(s, all);
  Simulation serial(s, all, geometry::Protocol::at_rest());
  Simulation par(s, share_of(all, MPI_COMM_WORLD), geometry::Protocol::at_rest(), 0, 0,
                 MPI_COMM_WORLD);
  serial.compute_forces();
  par.compute_forces();
  const int owner_before = par.domain()->tree().owner(x[0]);
  for (int k = 0; k < 40; ++k) {  // 40 δt = 3.2 ms: the pair moves 3.2 mm, across the cut
    serial.step();
    par.step();
  }
  const Particles after = par.gather_all();
  EXPECT_NE(par.domain()->tree().owner(after.x[0]), owner_before) << "the pair did not cross";
  // The spring of pair (0, 1) on every rank that holds it, against the serial one.
  neighbor::ContactHistory hs, hp;
  serial.neighbors().save_history(serial.particles(), hs);
  par.neighbors().save_history(par.particles(), hp);
  const auto vec = [](const neighbor::HistoryValues& h) { return Vec3{h[0], h[1], h[2]}; };
  const Vec3 ref = vec(hs.lookup(0, 1));
  ASSERT_GT(norm(ref), 0.0) << "the serial pair has no spring: the test slides nothing";
  const Vec3 mine = vec(hp.lookup(0, 1));
  const int holds = norm(mine) > 0 ? 1 : 0;
  int holders = 0;
  MPI_Allreduce(&holds, &holders, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  // With Newton across borders (the default) one rank computes the pair, and only it holds the
  // spring: a second holder would compute the pair twice.
  ASSERT_TRUE(par.neighbors().newton());
  EXPECT_EQ(holders, 1);
  if (holds) {
    EXPECT_LT(norm(mine - ref), 1e-9 * norm(ref));
  }
  EXPECT_LT(max_deviation(serial.particles(), after), 1e-9 * d);
}

// Every geometry and law: the periodic Rapaport cylinder (ghosts across the periodic ends) and
// the closed one (end caps), from the lattice fill stirred with random velocities: 400 steps of
// collisions, many across the rank borders, agree with the serial run to round-off.
TEST(Domain, CylinderScenesMatchSerial) {
  for (const char* periodic : {"on", "off"}) {
    const Scene s = load_scene(std::string(TUMBLE_SOURCE_DIR) + "/scenes/rapaport/mini/E.toml",
                               {std::string("tumbler.periodic=") + periodic, "neighbor.skin=0.1",
                                "parallel.rebalance_threshold=1.02"});
    CylinderBed cb = make_cylinder_bed(s);
    for (double& r : cb.particles.radius) r *= cb.shrink;  // as placed (no growing here)
    // A lattice falls plane by plane (no contact across a z cut): stir it so pairs form across
    // every border.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-2, 2);
    for (Vec3& v : cb.particles.v) v = {u(rng), u(rng), u(rng)};
    const auto proto = geometry::Protocol::single_axis(name_of(s.axis)[0], s.omega());
    Simulation serial(s, cb.particles, proto);
    Simulation par(s, share_of(cb.particles, MPI_COMM_WORLD), proto, 0, 0, MPI_COMM_WORLD);
    serial.compute_forces();
    par.compute_forces();
    for (int k = 0; k < 400; ++k) {
      serial.step();
      par.step();
    }
    // The comparison means something only if pairs across the borders were in contact.
    const Particles& q = par.particles();
    int border = 0, all_border = 0;
    for (std::size_t i = 0; i < par.local_count(); ++i)
      for (auto k = par.neighbors().start[i]; k < par.neighbors().start[i + 1]; ++k) {
        const auto j = par.neighbors().nbr[k];
        Vec3 dx = q.x[i] - q.x[j];
        dx.z -= s.length * std::nearbyint(dx.z / s.length);
        if (j >= par.local_count() && norm(dx) < q.radius[i] + q.radius[j]) ++border;
      }
    MPI_Allreduce(&border, &all_border, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_GT(all_border, 10) << "periodic " << periodic;
    EXPECT_EQ(par.global_count(), static_cast<std::int64_t>(cb.particles.size()));
    const double period = s.periodic == OnOff::on ? s.length : 0.0;
    EXPECT_LT(max_deviation(serial.particles(), par.gather_all(), period), 1e-9 * s.d_small)
        << "periodic " << periodic;
  }
}

// The bisection weighted by work: points spread evenly along x, those at x < 0 weighing 0.1 (a
// frozen bulk), the others 1. Cut by count, the ranks' weights differ by far more than the 10%
// a rebalance tolerates; cut by weight, every rank holds the same weight to within a few points
// (the cuts fall between points), and the ranks on the light side hold more points.
TEST(Domain, BisectionWeightedByWorkSharesTheWeight) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const parallel::Box root{{-1, -0.1, -0.1}, {1, 0.1, 0.1}};
  const int n = 6000;  // over all ranks; this rank holds every size-th, so all ranks take part
  std::vector<Vec3> x;
  std::vector<double> w;
  for (int k = rank; k < n; k += size) {
    const double xk = -1 + 2 * (k + 0.5) / n;
    x.push_back({xk, 0.05 * std::sin(7.0 * k), 0.05 * std::cos(5.0 * k)});
    w.push_back(xk < 0 ? 0.1 : 1.0);
  }
  const auto spread = [&](const parallel::RcbTree& t, bool by_weight) {
    std::vector<double> per(size, 0.0);
    for (std::size_t i = 0; i < x.size(); ++i) per[t.owner(x[i])] += by_weight ? w[i] : 1.0;
    MPI_Allreduce(MPI_IN_PLACE, per.data(), size, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    double mx = 0, sum = 0;
    for (double v : per) mx = std::max(mx, v), sum += v;
    return mx / (sum / size);
  };
  const parallel::RcbTree by_count = parallel::RcbTree::build(MPI_COMM_WORLD, root, x, x.size());
  const parallel::RcbTree by_work =
      parallel::RcbTree::build(MPI_COMM_WORLD, root, x, x.size(), w.data());
  EXPECT_LT(spread(by_count, false), 1.01);
  EXPECT_GT(spread(by_count, true), 1.3);
  EXPECT_LT(spread(by_work, true), 1.01);
  EXPECT_GT(spread(by_work, false), 1.3);
}

// A checkpoint keeps the tree as numbers (io/checkpoint.cpp: domain/tree): read back, it sends
// every point to the same rank; numbers that are not a tree of this many ranks are refused (a
// node that is its own child would make the queries loop, a leaf of two ranks leave one out).
TEST(Domain, TreeReadBackFromItsNumbers) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const parallel::Box root{{-1, -1, -1}, {1, 1, 1}};
  std::vector<Vec3> x;
  for (int k = rank; k < 3000; k += size)
    x.push_back({std::sin(1.3 * k), std::cos(0.7 * k), std::sin(0.31 * k)});
  const parallel::RcbTree t = parallel::RcbTree::build(MPI_COMM_WORLD, root, x, x.size());
  const std::vector<double> numbers = t.to_doubles();
  const parallel::RcbTree back = parallel::RcbTree::from_doubles(root, numbers, size);
  ASSERT_EQ(back.to_doubles(), numbers);
  int moved = 0;
  for (const Vec3& p : x) moved += back.owner(p) != t.owner(p);
  EXPECT_EQ(moved, 0);
  EXPECT_THROW(parallel::RcbTree::from_doubles(root, numbers, size + 1), std::invalid_argument);
  std::vector<double> own_child = numbers;
  own_child[4] = 0;  // the root's low child: the root
  EXPECT_THROW(parallel::RcbTree::from_doubles(root, own_child, size), std::invalid_argument);
  std::vector<double> wide_leaf = numbers;
  wide_leaf[parallel::RcbTree::kNodeDoubles + 3] += 1;  // the first child's ranks: one more
  EXPECT_THROW(parallel::RcbTree::from_doubles(root, wide_leaf, size), std::invalid_argument);
  std::vector<double> no_box = numbers;
  no_box[7] = std::nan("");
  EXPECT_THROW(parallel::RcbTree::from_doubles(root, no_box, size), std::invalid_argument);
}

namespace {
// The rigid bulk's springs on P ranks against 1, the dormant ones included: every rank holds (in
// its list or among its dormant springs) each spring of the serial run with one of its own
// particles (Newton off), equal to round-off, and no other. A rank's dormant springs travel only
// when one of their particles leaves it (VerletList::springs_leaving).
struct SpringCheck {
  std::int64_t dormant_compared = 0, missing = 0, extra = 0;
  double worst = 0;

  void compare(const Simulation& serial, const Simulation& par) {
    neighbor::ContactHistory ref, mine;
    serial.save_contacts(ref);
    par.save_contacts(mine);
    const Particles& p = par.particles();
    std::set<std::int64_t> own(p.id.begin(), p.id.begin() + par.local_count());
    for (const neighbor::SavedSpring& r : ref.records()) {
      neighbor::HistoryValues h{};
      const bool held = mine.find(r.lo, r.hi, h.data()) >= 0;
      missing += (own.count(r.lo) || own.count(r.hi)) && !held;
      if (!held) continue;
      for (int d = 0; d < ref.width(); ++d) worst = std::max(worst, std::abs(h[d] - r.history[d]));
    }
    std::set<std::int64_t> frozen;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.bulk_state[i] < 0) frozen.insert(p.id[i]);
    // (save_contacts sorts by ids: a spring held twice by one rank, in its list and among its
    // dormant ones or twice among those, would lie next to itself.)
    for (std::size_t q = 1; q < mine.records().size(); ++q)
      extra += mine.records()[q].lo == mine.records()[q - 1].lo &&
               mine.records()[q].hi == mine.records()[q - 1].hi;
    for (const neighbor::SavedSpring& r : mine.records()) {
      neighbor::HistoryValues scratch{};
      extra += ref.find(r.lo, r.hi, scratch.data()) < 0;
      extra += !own.count(r.lo) && !own.count(r.hi);
      dormant_compared += frozen.count(r.lo) && frozen.count(r.hi);
    }
  }

  // None missing, none extra, all within `tolerance`, and at least `dormant` dormant springs
  // compared on this rank (or the check showed nothing of them).
  void expect(double tolerance, std::int64_t dormant, const char* what) const {
    EXPECT_EQ(missing, 0) << what;
    EXPECT_EQ(extra, 0) << what;
    EXPECT_LT(worst, tolerance) << what;
    EXPECT_GT(dormant_compared, dormant) << what;
    if (world_rank() == 0)
      std::printf("[ springs  ] %s: %lld dormant springs compared on rank 0\n", what,
                  static_cast<long long>(dormant_compared));
  }
};

// Steps the serial and the decomposed run side by side for `steps` steps: the same frozen share
// after every step, the springs compared every `every` steps. Returns the largest frozen share.
double step_side_by_side(Simulation& serial, Simulation& par, int steps, int every,
                         SpringCheck& springs) {
  serial.compute_forces();
  par.compute_forces();
  double most_frozen = 0;
  for (int k = 0; k < steps; ++k) {
    serial.step();
    par.step();
    most_frozen = std::max(most_frozen, serial.frozen_fraction());
    EXPECT_EQ(par.frozen_fraction(), serial.frozen_fraction()) << "step " << k;
    if (par.frozen_fraction() != serial.frozen_fraction()) break;
    if (k % every == every - 1) springs.compare(serial, par);
  }
  return most_frozen;
}
}  // namespace

// fidelity.bulk = "rigid" on P ranks against 1: the frozen state migrates with its particles and
// reaches the ghosts, the free surface is reduced over the ranks, and every freeze/thaw decision
// comes out the same, so the trajectories agree to round-off as the dynamic ones do. A short dwell
// and a generous calm distance make particles freeze (and some thaw) within the 2,000 steps; a thin
// skin moves particles between ranks every few steps; the cuts, made afresh at every rebuild, weigh
// a frozen particle 0.12 of a moving one, so the regions move as the bulk freezes and thaws.
TEST(Domain, RigidBulkMatchesSerial) {
  const Scene s = tiny({"fidelity.bulk=rigid", "fidelity.bulk_dwell=0.004",
                        "fidelity.bulk_calm_distance=0.1", "neighbor.skin=0.05",
                        "parallel.rebalance_threshold=1.0", "parallel.frozen_weight=0.12"});
  const Particles bed = tiny_bed(s);
  Simulation serial(s, bed, biaxial(s));
  Simulation par(s, share_of(bed, MPI_COMM_WORLD), biaxial(s), 0, 0, MPI_COMM_WORLD);
  // The rigid bulk keeps Newton off whatever the key says (its pass reads frozen ghosts beyond
  // the list; a dormant spring is held by each rank that owns one of its particles).
  EXPECT_EQ(s.newton, OnOff::on);
  EXPECT_FALSE(par.neighbors().newton());
  SpringCheck springs;
  EXPECT_GT(step_side_by_side(serial, par, 2000, 20, springs), 0.1);
  EXPECT_GT(serial.frozen_fraction(), 0.05);
  springs.expect(1e-9 * s.d_small, 1000, "sphere");
  const Particles all = par.gather_all();
  std::vector<std::int32_t> state(all.size());
  for (std::size_t i = 0; i < serial.particles().size(); ++i)
    state[serial.particles().id[i]] = serial.particles().bulk_state[i];
  std::size_t differ = 0;
  for (std::size_t i = 0; i < all.size(); ++i) differ += all.bulk_state[i] != state[all.id[i]];
  EXPECT_EQ(differ, 0u);
  EXPECT_LT(max_deviation(serial.particles(), all), 1e-9 * s.d_small);
  EXPECT_EQ(par.global_count(), static_cast<std::int64_t>(bed.size()));
  EXPECT_GT(par.domain()->bisections(), 1);
}

// The same with a still slope (fidelity.bulk_still_slope = 10°, above the tilt's first fraction of
// a degree): the surface layer freezes too, so the whole bed turns frozen across the ranks' borders
// (no moving particle on a rank, dormant springs only), and the slope, fitted to the column tops
// every rank holds alike, decides alike.
TEST(Domain, RigidBulkFrozenWholeMatchesSerial) {
  const Scene s =
      tiny({"fidelity.bulk=rigid", "fidelity.bulk_dwell=0.004", "fidelity.bulk_calm_distance=0.1",
            "fidelity.bulk_still_slope=10", "neighbor.skin=0.05",
            "parallel.rebalance_threshold=1.0", "parallel.frozen_weight=0.12"});
  const Particles bed = tiny_bed(s);
  Simulation serial(s, bed, biaxial(s));
  Simulation par(s, share_of(bed, MPI_COMM_WORLD), biaxial(s), 0, 0, MPI_COMM_WORLD);
  SpringCheck springs;
  EXPECT_GT(step_side_by_side(serial, par, 1000, 20, springs), 0.95);
  springs.expect(1e-9 * s.d_small, 1000, "sphere frozen whole");
  EXPECT_LT(max_deviation(serial.particles(), par.gather_all()), 1e-9 * s.d_small);
}

// The same on the Rapaport cylinder (axis z) from its settled bed (Froude 0.08, beyond the rolling
// regime), with closed ends and axially periodic (pairs across the period, between ranks too; the
// calm test and every pair take the nearest image); a calm
// distance of 0.1 d_large freezes more than 5% of it within the 1,000 steps. The closed bed
// amplifies round-off ~10x per 100 steps (measured: 3e-11 d after 1,000 steps, 3e-9 d after
// 1,300, a first freeze decision of its own at 1,966 with the runs 7e-3 d apart), so it runs
// 1,000 steps.
void rigid_cylinder_matches_serial(const char* periodic) {
  const Scene s =
      load_scene(std::string(TUMBLE_SOURCE_DIR) + "/scenes/rapaport/mini/E.toml",
                 {"fill.bed_cache=" + scratch("beds"), "fidelity.bulk=rigid",
                  "fidelity.bulk_calm_distance=0.1", "parallel.rebalance_threshold=1.02",
                  std::string("tumbler.periodic=") + periodic});
  if (world_rank() == 0) settled_bed(s, nullptr);
  MPI_Barrier(MPI_COMM_WORLD);
  const Particles bed = settled_bed(s, nullptr);
  const auto proto = geometry::Protocol::single_axis('z', s.omega());
  Simulation serial(s, bed, proto);
  Simulation par(s, share_of(bed, MPI_COMM_WORLD), proto, 0, 0, MPI_COMM_WORLD);
  SpringCheck springs;
  EXPECT_GT(step_side_by_side(serial, par, 1000, 50, springs), 0.05);
  springs.expect(1e-9 * s.d_small, 100, periodic[1] == 'n' ? "periodic cylinder" : "cylinder");
  EXPECT_LT(max_deviation(serial.particles(), par.gather_all()), 1e-9 * s.d_small);
}

TEST(Domain, RigidBulkCylinderMatchesSerial) { rigid_cylinder_matches_serial("off"); }
TEST(Domain, RigidBulkPeriodicCylinderMatchesSerial) { rigid_cylinder_matches_serial("on"); }

// Ranks other than 0 report only their failures, prefixed with the rank.
class FailurePrinter : public ::testing::EmptyTestEventListener {
  void OnTestPartResult(const ::testing::TestPartResult& r) override {
    if (r.failed())
      std::fprintf(stderr, "[rank %d] %s:%d: %s\n", world_rank(),
                   r.file_name() ? r.file_name() : "?", r.line_number(), r.summary());
  }
};

namespace {
// Bed-averaged observables of one sample.
struct Observables {
  double kinetic, com_x, com_y, com_z, wall_fraction;
};

Observables observe(const Simulation& sim, double radius) {
  const double ke = sim.energy().kinetic;
  const Particles all = sim.gather_all();
  double m = 0;
  Vec3 c{};
  for (std::size_t i = 0; i < all.size(); ++i) {
    const double mi = 1.0 / all.inv_mass[i];
    m += mi;
    c += mi * all.x[i];
  }
  c = (1.0 / m) * c;
  return {ke, c.x, c.y, c.z, analysis::radial_segregation(all, radius).shell_large_fraction};
}

// Mean and standard error from `blocks` consecutive block means (the samples are correlated).
void block_stats(const std::vector<double>& v, int blocks, double& mean, double& se) {
  const std::size_t per = v.size() / blocks;
  std::vector<double> b(blocks, 0.0);
  for (int k = 0; k < blocks; ++k) {
    for (std::size_t i = 0; i < per; ++i) b[k] += v[k * per + i];
    b[k] /= per;
  }
  mean = 0;
  for (double x : b) mean += x / blocks;
  double var = 0;
  for (double x : b) var += (x - mean) * (x - mean) / (blocks - 1);
  se = std::sqrt(var / blocks);
}
}  // namespace

// Over a long run the two trajectories part (round-off grows), but the bed-averaged observables
// must agree statistically: 1 s of rotation at 15 rpm (50,000 steps), sampled every 0.01 s over
// the last 0.8 s; the means of kinetic energy, centre of mass and large-particle wall fraction on
// 1 rank and on the world's ranks differ by less than 4 combined standard errors (from 8 block
// means each).
TEST(Domain, LongRunObservablesAgreeStatistically) {
  const Scene s = tiny({"neighbor.skin=0.1"});
  const Particles bed = tiny_bed(s);
  Simulation serial(s, bed, biaxial(s));
  Simulation par(s, share_of(bed, MPI_COMM_WORLD), biaxial(s), 0, 0, MPI_COMM_WORLD);
  serial.compute_forces();
  par.compute_forces();
  std::vector<std::vector<double>> a(5), b(5);
  for (int k = 1; k <= 50000; ++k) {
    serial.step();
    par.step();
    if (k % 500 != 0 || k <= 10000) continue;
    const Observables o1 = observe(serial, s.radius), o2 = observe(par, s.radius);
    const double v1[5] = {o1.kinetic, o1.com_x, o1.com_y, o1.com_z, o1.wall_fraction};
    const double v2[5] = {o2.kinetic, o2.com_x, o2.com_y, o2.com_z, o2.wall_fraction};
    for (int q = 0; q < 5; ++q) {
      a[q].push_back(v1[q]);
      b[q].push_back(v2[q]);
    }
  }
  const char* names[5] = {"kinetic energy", "com x", "com y", "com z", "wall fraction"};
  for (int q = 0; q < 5; ++q) {
    double m1, s1, m2, s2;
    block_stats(a[q], 8, m1, s1);
    block_stats(b[q], 8, m2, s2);
    const double tol = 4 * std::sqrt(s1 * s1 + s2 * s2) + 1e-12 * std::abs(m1);
    EXPECT_LT(std::abs(m1 - m2), tol)
        << names[q] << ": " << m1 << " +- " << s1 << " vs " << m2 << " +- " << s2;
    if (world_rank() == 0)
      std::printf("[stats] %-15s 1 rank %.6g +- %.2g   %d ranks %.6g +- %.2g\n", names[q], m1, s1,
                  size_of(MPI_COMM_WORLD), m2, s2);
  }
  const double apart =
      max_deviation(serial.particles(), par.gather_all()) / s.d_small;  // collective
  if (world_rank() == 0)
    std::printf("[stats] largest position difference after 1 s: %.3g d_small\n", apart);
}

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  // Only rank 0 prints; every rank runs every test (the tests are collective).
  if (world_rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new FailurePrinter);
  }
  const int rc = RUN_ALL_TESTS();
  int worst = 0;
  MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return worst;
}
