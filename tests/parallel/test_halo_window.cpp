// The halo's two per-step exchanges (parallel::Domain) under a rank that is late: the ghosts'
// refresh and, with Newton across borders, their force sums going back. Between ranks of one node
// both go through a shared window with two buffers used in turns and a collective or a barrier
// of the node as the only ordering, so a missing barrier shows only when one rank runs behind
// the others. Here one rank at a
// time sleeps at one of the six points of a step, and every value read must be that step's.
// The same under three layouts of the ranks on nodes: one node (the window between all), one
// node per rank (messages only) and, on 3 ranks, nodes of two (TUMBLE_HALO_NODE_RANKS=2: rank 1
// reads rank 0 from the window and rank 2 from messages in the same step).
#include <gtest/gtest.h>
#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "base/error.hpp"
#include "parallel/domain.hpp"
#include "parallel_helpers.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {

// A cubic lattice of n^3 particles of radius 0.05 at spacing 0.16 in [-1, 1]^3, all on rank 0
// (distribute() hands each to its owner).
Particles lattice(int n) {
  Particles p;
  if (world_rank() != 0) return p;
  p.resize(static_cast<std::size_t>(n) * n * n);
  std::size_t k = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      for (int c = 0; c < n; ++c, ++k) {
        p.x[k] = {-0.95 + 0.16 * a, -0.95 + 0.16 * b, -0.95 + 0.16 * c};
        p.radius[k] = 0.05;
        p.inv_mass[k] = p.inv_inertia[k] = 1;
        p.id[k] = static_cast<std::int64_t>(k);
      }
  return p;
}

const parallel::Box kCube{{-1, -1, -1}, {1, 1, 1}};

// The lattice handed to its owners with a halo of reach 0.3 in which every ghost is refreshed
// (and sends its sums back); returns the owned count.
std::size_t lattice_with_halo(parallel::Domain& dom, Particles& p) {
  p = lattice(12);
  std::vector<neighbor::SavedSpring> records;
  dom.distribute(p, records, 0.3, 3);
  const std::size_t n = p.size();
  dom.exchange_ghosts(p, n, 0.3);
  dom.keep_used_ghosts(nullptr);
  return n;
}

// What an owner writes into its particle's motion at step k, and what a rank holding it as a
// ghost adds to its force at step k: no two steps alike, so a row of another step is seen.
Vec3 velocity_at(std::int64_t id, int k) {
  return {static_cast<double>(id), static_cast<double>(k), 1000.0 * id + k};
}
Vec3 spin_at(std::int64_t id, int k) { return {-static_cast<double>(k), 0.5 * id, 1.0}; }
double force_at(std::int64_t id, int k) { return 3.0 * id + 0.25 * k + 1; }

struct Faults {
  long stale_ghosts = 0;  // ghost motion not of this step
  long wrong_sums = 0;    // owned force not the holders' count times this step's value
  long holders_changed = 0;
  long holders = 0;  // ghost copies of this rank's particles (all ranks' ghosts, summed)
};

// `steps` steps on a fixed halo of the refresh and, with `newton`, the sums going back; at step
// k rank k % size sleeps 1-5 ms (long enough for the others to be scheduled on a loaded,
// oversubscribed machine) at one of six points (before the refresh, on either side of
// the collective between its halves, before the reverse, between its halves, after it). Even
// steps call the collective that stands for the engine's rebuild test between the refresh's
// halves; odd steps leave end_refresh its own barrier. Without Newton that collective is the
// step's only meeting of the ranks: what keeps a fast rank's next rows from a late reader is
// the second buffer.
Faults run_late_ranks(int steps, bool newton) {
  parallel::Domain dom(MPI_COMM_WORLD, kCube, 0, 1.1);
  dom.reverse_through_window(newton);
  Particles p;
  const std::size_t n = lattice_with_halo(dom, p);
  const int rank = world_rank(), size = size_of(MPI_COMM_WORLD);
  Faults out;
  std::vector<long> first_holders(n, -1);
  std::mt19937 rng(23);  // the same stream on every rank: all agree on who sleeps where
  std::uniform_int_distribution<int> point(0, newton ? 5 : 2), micros(1000, 5000);
  for (int k = 0; k < steps; ++k) {
    const int late_point = point(rng), late_us = micros(rng);
    auto maybe_late = [&](int here) {
      if (rank == k % size && here == late_point)
        std::this_thread::sleep_for(std::chrono::microseconds(late_us));
    };
    for (std::size_t i = 0; i < n; ++i) {
      p.v[i] = velocity_at(p.id[i], k);
      p.w[i] = spin_at(p.id[i], k);
    }
    maybe_late(0);
    dom.begin_refresh(p, n);
    maybe_late(1);
    if (k % 2 == 0) dom.max_over_ranks(0.0);
    maybe_late(2);
    dom.end_refresh(p, n);
    for (std::size_t q = n; q < p.size(); ++q) {
      const Vec3 v = velocity_at(p.id[q], k), w = spin_at(p.id[q], k);
      out.stale_ghosts += !(p.v[q].x == v.x && p.v[q].y == v.y && p.v[q].z == v.z &&
                            p.w[q].x == w.x && p.w[q].y == w.y && p.w[q].z == w.z);
      p.f[q] = {force_at(p.id[q], k), 0, 0};
      p.t[q] = {1, 0, 0};  // counts the ghost copies
    }
    if (!newton) continue;
    for (std::size_t i = 0; i < n; ++i) p.f[i] = p.t[i] = {0, 0, 0};
    maybe_late(3);
    dom.begin_reverse(p, n);
    maybe_late(4);
    dom.end_reverse(p);
    maybe_late(5);
    for (std::size_t i = 0; i < n; ++i) {
      const long copies = std::lround(p.t[i].x);
      out.wrong_sums += !(p.t[i].x == copies && p.f[i].x == copies * force_at(p.id[i], k) &&
                          p.f[i].y == 0 && p.f[i].z == 0);
      if (first_holders[i] < 0) first_holders[i] = copies;
      out.holders_changed += copies != first_holders[i];
      if (k == 0) out.holders += copies;
    }
  }
  long ghosts = static_cast<long>(p.size() - n);
  MPI_Allreduce(MPI_IN_PLACE, &ghosts, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  long sums[4] = {out.stale_ghosts, out.wrong_sums, out.holders_changed, out.holders};
  MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  out = {sums[0], sums[1], sums[2], sums[3]};
  if (newton) {
    EXPECT_EQ(out.holders, ghosts) << "every ghost's count came home once";
  }
  EXPECT_GT(ghosts, 100) << "too few ghosts to test the halo";
  return out;
}

// The ranks whose ghosts come from the window, summed over the ranks, for a layout.
long shared_sources_with(const char* node_ranks, const char* messages) {
  if (node_ranks) setenv("TUMBLE_HALO_NODE_RANKS", node_ranks, 1);
  if (messages) setenv("TUMBLE_REFRESH_MESSAGES", messages, 1);
  parallel::Domain dom(MPI_COMM_WORLD, kCube, 0, 1.1);
  Particles p;
  (void)lattice_with_halo(dom, p);
  unsetenv("TUMBLE_HALO_NODE_RANKS");
  unsetenv("TUMBLE_REFRESH_MESSAGES");
  long shared = dom.shared_sources();
  MPI_Allreduce(MPI_IN_PLACE, &shared, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  return shared;
}

void expect_no_faults(const Faults& f) {
  EXPECT_EQ(f.stale_ghosts, 0) << "a ghost read a row of another step";
  EXPECT_EQ(f.wrong_sums, 0) << "an owner added sums of another step";
  EXPECT_EQ(f.holders_changed, 0);
}

}  // namespace

// Each layout with Newton across borders (refresh and sums) and without (refresh only).
void late_ranks_in_layout(const char* node_ranks) {
  if (node_ranks) setenv("TUMBLE_HALO_NODE_RANKS", node_ranks, 1);
  const Faults with = run_late_ranks(200, true), without = run_late_ranks(200, false);
  unsetenv("TUMBLE_HALO_NODE_RANKS");
  expect_no_faults(with);
  expect_no_faults(without);
}

TEST(HaloWindow, LateRankOneNode) { late_ranks_in_layout(nullptr); }
TEST(HaloWindow, LateRankNodeOfOneRankEach) { late_ranks_in_layout("1"); }
TEST(HaloWindow, LateRankNodesOfTwoRanks) { late_ranks_in_layout("2"); }

// The layouts are what the tests above take them for: every neighbour through the window on one
// node, none with a node per rank or with messages asked for, and on 3 ranks in nodes of two
// some but not all (rank 2 is alone on its node).
TEST(HaloWindow, NodeLayoutsDecideWhatGoesThroughTheWindow) {
  const int size = size_of(MPI_COMM_WORLD);
  const long one_node = shared_sources_with(nullptr, nullptr);
  if (size <= 4) {  // (RCB's cuts of the cube: more ranks leave some apart)
    EXPECT_EQ(one_node, size * (size - 1)) << "every rank neighbours every other on this lattice";
  }
  EXPECT_GT(one_node, 0);
  EXPECT_EQ(shared_sources_with("1", nullptr), 0);
  EXPECT_EQ(shared_sources_with(nullptr, "1"), 0);
  EXPECT_EQ(shared_sources_with("0", nullptr), one_node);
  const long pairs = shared_sources_with("2", nullptr);
  if (size == 3) {
    EXPECT_EQ(pairs, 2) << "ranks 0 and 1 read each other, rank 2 by messages";
  } else if (size == 2) {
    EXPECT_EQ(pairs, one_node);
  }
}

// A bad value, or ranks that see different values (a split of the node that would hang), is
// refused on every rank, as bad input (a campaign does not retry it).
TEST(HaloWindow, BadNodeRanksRefusedByName) {
  const std::string differ = world_rank() == 0 ? "2" : "1";
  for (const char* bad : {"-1", "two", "2x", "99999999", differ.c_str()}) {
    setenv("TUMBLE_HALO_NODE_RANKS", bad, 1);
    try {
      parallel::Domain dom(MPI_COMM_WORLD, kCube, 0, 1.1);
      ADD_FAILURE() << "accepted TUMBLE_HALO_NODE_RANKS=" << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("TUMBLE_HALO_NODE_RANKS"), std::string::npos);
    }
  }
  unsetenv("TUMBLE_HALO_NODE_RANKS");
}
