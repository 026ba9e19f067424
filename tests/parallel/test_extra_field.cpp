// "Fields declared once": a per-particle field added by one line (tests/parallel/dummy_field.hpp)
// follows its particle - by id - through the cell sorts of the neighbour list, migration between
// ranks, ghost copies, a collective checkpoint and a restart, without any other edit. This binary
// and the copy of the library under it are compiled with the extra field
// (tests/parallel/CMakeLists.txt); run by ctest under mpiexec with 2 ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "geometry/protocol.hpp"
#include "io/checkpoint.hpp"
#include "parallel/particle_pack.hpp"
#include "scene/fill.hpp"
#include "scene/scene.hpp"

using namespace tumble;

// The row width and the checkpoint come from the list: one more double per particle, no edit.
static_assert(parallel::kStateDoubles == 30 + 1, "the dummy field travels in the state rows");
static_assert(parallel::kMotionDoubles == 9, "but not in the ghost refresh");

namespace {

int rank_of(MPI_Comm c) {
  int r = 0;
  MPI_Comm_rank(c, &r);
  return r;
}
int size_of(MPI_Comm c) {
  int n = 1;
  MPI_Comm_size(c, &n);
  return n;
}

// The value particle `id` carries: distinct per particle, never the default 0.
double tag(std::int64_t id) { return 0.5 + 3.0 * static_cast<double>(id); }

// Number of particles 0..size-1 (owned and ghosts) whose dummy is not their tag.
std::int64_t wrong_tags(const Particles& p) {
  std::int64_t bad = 0;
  for (std::size_t i = 0; i < p.size(); ++i) bad += p.dummy[i] != tag(p.id[i]);
  return bad;
}

std::int64_t sum_over_ranks(std::int64_t v) {
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  return v;
}

// A small rotating sphere with an unsettled bed: it falls and flows, so particles cross the
// border between the ranks' domains. A small skin rebuilds (and migrates) often.
Scene scene(const std::string& beds) {
  return parse_scene("",
                     {"tumbler.radius=0.02", "contact.collision_time=1e-3", "protocol.mode=biaxial",
                      "protocol.rpm=15", "neighbor.skin=0.05", "fill.bed_cache=" + beds},
                     "extra_field");
}

geometry::Protocol protocol(const Scene& s) {
  return geometry::Protocol::biaxial(deg2rad(s.theta_z), deg2rad(s.theta_x), deg2rad(s.repose.deg),
                                     s.omega());
}

// This rank's block of ids of the bed, every particle tagged.
Particles tagged_share(const Scene& s) {
  const Particles all = make_bed(s);
  const auto n = static_cast<std::int64_t>(all.size());
  const int r = rank_of(MPI_COMM_WORLD), size = size_of(MPI_COMM_WORLD);
  std::vector<std::uint32_t> mine;
  for (std::int64_t i = n * r / size; i < n * (r + 1) / size; ++i)
    mine.push_back(static_cast<std::uint32_t>(i));
  Particles p = all;
  p.permute(mine);
  p.resize(mine.size());
  for (std::size_t i = 0; i < p.size(); ++i) p.dummy[i] = tag(p.id[i]);
  return p;
}

std::set<std::int64_t> owned_ids(const Simulation& sim) {
  const Particles& p = sim.particles();
  return std::set<std::int64_t>(p.id.begin(), p.id.begin() + sim.local_count());
}

void run(Simulation& sim, int steps) {
  for (int k = 0; k < steps; ++k) {
    if (k == steps - 1) sim.request_rebuild();  // checkpoints follow a rebuild (as the run loop)
    sim.step();
  }
}

}  // namespace

TEST(ExtraField, FollowsItsParticleThroughMigrationAndRestart) {
  const std::string dir = std::string(TUMBLE_TEST_SCRATCH) + "/extra_field";
  if (rank_of(MPI_COMM_WORLD) == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  const Scene s = scene(dir + "/beds");
  Simulation sim(s, tagged_share(s), protocol(s), 0, 0, MPI_COMM_WORLD);
  sim.compute_forces();
  const std::int64_t n = sim.global_count();
  const std::set<std::int64_t> before = owned_ids(sim);
  run(sim, 600);

  // Particles changed rank during the run, and every one (ghosts included) kept its value.
  std::int64_t moved = 0;
  for (std::int64_t id : owned_ids(sim)) moved += before.count(id) == 0;
  moved = sum_over_ranks(moved);
  if (rank_of(MPI_COMM_WORLD) == 0)
    std::printf("[extra field] %lld particles migrated\n", static_cast<long long>(moved));
  EXPECT_GT(moved, 0);
  EXPECT_EQ(sum_over_ranks(wrong_tags(sim.particles())), 0);
  EXPECT_GT(sim.particles().size(), sim.local_count());  // ghosts were checked too

  // The collective checkpoint holds the field (dataset particles/dummy, one row per particle).
  const std::string ckpt = dir + "/ckpt.h5";
  io::write_checkpoint(ckpt, sim, s, {}, {});
  if (rank_of(MPI_COMM_WORLD) == 0) {
    const io::CheckpointData whole = io::read_checkpoint(ckpt);
    EXPECT_EQ(static_cast<std::int64_t>(whole.particles.size()), n);
    EXPECT_EQ(wrong_tags(whole.particles), 0);
  }

  // A restart on the world's ranks reads it back, and both runs go on together (to round-off, as
  // tests/parallel/test_parallel_io.cpp): the extra field changes nothing of the trajectory.
  io::CheckpointData c = io::read_checkpoint(ckpt, MPI_COMM_WORLD);
  Simulation restarted(s, std::move(c.particles), protocol(s), c.time, c.step, MPI_COMM_WORLD);
  restarted.restore(c.history);
  EXPECT_EQ(sum_over_ranks(wrong_tags(restarted.particles())), 0);
  run(sim, 200);
  run(restarted, 200);
  const Particles a = sim.gather_all(), b = restarted.gather_all();  // sorted by id
  ASSERT_EQ(static_cast<std::int64_t>(b.size()), n);
  EXPECT_EQ(wrong_tags(b), 0);
  double apart = 0;
  for (std::size_t i = 0; i < a.size(); ++i) apart = std::max(apart, norm(a.x[i] - b.x[i]));
  EXPECT_LT(apart, 1e-9 * s.d_small);
}

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int rc = RUN_ALL_TESTS();
  int worst = 0;
  MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return worst;
}
