// Collective checkpoints and snapshots (parallel HDF5) and restarts on another rank count: a
// checkpoint written on the world's ranks restarts on 1 rank, and one written on 1 rank restarts
// on the world's ranks; both continue the same trajectory as an uninterrupted serial run (to
// round-off over a short horizon).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>

#include "engine/simulation.hpp"
#include "h5/hdf5_file.hpp"
#include "io/checkpoint.hpp"
#include "io/snapshot.hpp"
#include "parallel_helpers.hpp"
#include "run/realization.hpp"
#include "scene/fill.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {

Scene scene() { return tiny({"neighbor.skin=0.05"}); }

// The settled bed, read once per test binary (collective over the world: call it on every rank
// before any rank-0-only section).
const Particles& bed(const Scene& s) {
  static Particles b;
  static bool done = false;
  if (!done) {
    b = tiny_bed(s);
    done = true;
  }
  return b;
}

// `steps` steps, the last with a neighbour rebuild (checkpoints follow one, as in the run loop).
void advance(Simulation& sim, int steps) {
  for (int k = 0; k < steps; ++k) {
    if (k == steps - 1) sim.request_rebuild();
    sim.step();
  }
}

// Runs `steps` steps on `comm` from a checkpoint (or the bed), and writes a checkpoint at the end.
std::unique_ptr<Simulation> continue_run(const Scene& s, MPI_Comm comm, const std::string& from,
                                         int steps, const std::string& to) {
  std::unique_ptr<Simulation> sim;
  if (from.empty()) {
    sim = std::make_unique<Simulation>(s, share_of(bed(s), comm), biaxial(s), 0, 0, comm);
    sim->compute_forces();
  } else {
    io::CheckpointData c = io::read_checkpoint(from, comm);
    sim = io::engine_from_checkpoint(c, s, biaxial(s), from, comm);
  }
  advance(*sim, steps);
  if (!to.empty()) io::write_checkpoint(to, *sim, s, {}, {});
  return sim;
}

}  // namespace

TEST(ParallelIO, CheckpointRestartsOnAnotherRankCount) {
  const Scene s = scene();
  const std::string d = scratch("restart");
  const int me = rank_of(MPI_COMM_WORLD);
  bed(s);
  // Reference: 300 uninterrupted serial steps (every rank runs it).
  auto ref = continue_run(s, MPI_COMM_NULL, "", 300, "");
  const Particles reference = ref->gather_all();

  // Written on all ranks, restarted on one (rank 0 alone; the others wait).
  continue_run(s, MPI_COMM_WORLD, "", 150, d + "/world.h5");
  if (me == 0) {
    auto one = continue_run(s, MPI_COMM_NULL, d + "/world.h5", 150, "");
    EXPECT_EQ(one->particles().size(), reference.size());
    EXPECT_LT(max_deviation(reference, one->particles()), 1e-9 * s.d_small);
  }
  MPI_Barrier(MPI_COMM_WORLD);

  // Written on one rank, restarted on all.
  if (me == 0) continue_run(s, MPI_COMM_NULL, "", 150, d + "/one.h5");
  MPI_Barrier(MPI_COMM_WORLD);
  auto all = continue_run(s, MPI_COMM_WORLD, d + "/one.h5", 150, "");
  const Particles gathered = all->gather_all();
  EXPECT_EQ(gathered.size(), reference.size());
  EXPECT_LT(max_deviation(reference, gathered), 1e-9 * s.d_small);

  // Written on all, restarted on all: the same again.
  auto again = continue_run(s, MPI_COMM_WORLD, d + "/world.h5", 150, "");
  EXPECT_LT(max_deviation(reference, again->gather_all()), 1e-9 * s.d_small);
}

// On as many ranks as wrote it, a checkpoint goes on bit for bit: the ranks keep the rows they
// wrote and the boxes they had (a bisection made afresh where the bed is at the restart cut
// elsewhere: 7.6e-16 m after 9,000 steps of bst_tiny at 20 rpm on 2 ranks, 0.03 m after 110,000).
// The bed turns at 30 rpm here so that the boxes move between the start and the checkpoint.
TEST(ParallelIO, RestartOnAsManyRanksIsBitwise) {
  const Scene s =
      tiny({"neighbor.skin=0.05", "protocol.rpm=30", "parallel.rebalance_threshold=1.02"});
  const std::string d = scratch("restart_bitwise");
  bed(s);
  // Uninterrupted, with the rebuild the checkpoint's step has: 3 x 1,500 steps.
  auto ref = continue_run(s, MPI_COMM_WORLD, "", 1500, "");
  advance(*ref, 1500);
  advance(*ref, 1500);
  const Particles reference = ref->gather_all();
  const std::vector<double> boxes = ref->decomposition();
  continue_run(s, MPI_COMM_WORLD, "", 1500, d + "/a.h5");
  continue_run(s, MPI_COMM_WORLD, d + "/a.h5", 1500, d + "/b.h5");
  auto split = continue_run(s, MPI_COMM_WORLD, d + "/b.h5", 1500, "");
  const Particles resumed = split->gather_all();
  ASSERT_EQ(resumed.size(), reference.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < reference.size(); ++i)
    for (int k = 0; k < 3; ++k)
      differ += reference.x[i][k] != resumed.x[i][k] || reference.v[i][k] != resumed.v[i][k] ||
                reference.w[i][k] != resumed.w[i][k];
  EXPECT_EQ(differ, 0u) << "coordinates that differ after two restarts on as many ranks";
  EXPECT_EQ(split->decomposition(), boxes);
}

// A checkpoint's contact records survive a rank-count change: the springs after a restart on all
// ranks equal those the serial run holds at the same step.
TEST(ParallelIO, SpringsSurviveTheRestart) {
  const Scene s = scene();
  const std::string d = scratch("springs");
  bed(s);
  if (rank_of(MPI_COMM_WORLD) == 0) continue_run(s, MPI_COMM_NULL, "", 100, d + "/one.h5");
  MPI_Barrier(MPI_COMM_WORLD);
  io::CheckpointData c = io::read_checkpoint(d + "/one.h5", MPI_COMM_WORLD);
  Simulation par(s, std::move(c.particles), biaxial(s), c.time, c.step, MPI_COMM_WORLD);
  par.restore(c.history);
  const io::CheckpointData whole = io::read_checkpoint(d + "/one.h5");
  neighbor::ContactHistory mine;
  par.neighbors().save_history(par.particles(), mine);
  ASSERT_EQ(whole.history.width(), 3);  // the law's one Vec3: three columns in the file
  const auto vec = [](const neighbor::HistoryValues& h) { return Vec3{h[0], h[1], h[2]}; };
  int found = 0, checked = 0;
  for (const auto& r : mine.records()) {
    const Vec3 ref = vec(whole.history.lookup(r.lo, r.hi));
    EXPECT_EQ(norm(ref - vec(r.history)), 0.0) << r.lo << "-" << r.hi;
    ++checked;
  }
  // Every record of the file is held by exactly one rank: with Newton across borders (the
  // default) only the rank that computes a pair holds its spring.
  ASSERT_TRUE(par.neighbors().newton());
  int live = 0;
  for (const auto& r : whole.history.records()) {
    live += norm(vec(r.history)) > 0;
    if (norm(vec(mine.lookup(r.lo, r.hi))) > 0) ++found;
  }
  int all_found = 0;
  MPI_Allreduce(&found, &all_found, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(all_found, live);
  EXPECT_GT(live, 0);
  EXPECT_GT(checked, 0);
}

// A snapshot written collectively holds every particle once, sorted by id, with the positions
// the ranks hold.
TEST(ParallelIO, CollectiveSnapshotHasEveryParticleOnce) {
  const Scene s = scene();
  const std::string d = scratch("snap");
  auto sim = continue_run(s, MPI_COMM_WORLD, "", 20, "");
  io::write_snapshot(d + "/snap.h5", *sim, s);
  const Particles all = sim->gather_all();
  io::H5File f(d + "/snap.h5", io::H5File::Mode::Read);
  const auto id = f.read_int64("id");
  const auto x = f.read_double("x");
  ASSERT_EQ(id.size(), all.size());
  for (std::size_t k = 0; k < id.size(); ++k) {
    ASSERT_EQ(id[k], static_cast<std::int64_t>(k));
    for (int c = 0; c < 3; ++c) ASSERT_EQ(x[3 * k + c], all.x[k][c]);
  }
  EXPECT_EQ(f.attr_string("/", "tumble_version").empty(), false);
}

// Ranks with nothing to write still take part: one particle on every rank of the world (all but
// one rank own nothing). The checkpoint and the snapshot hold it once; a restart on the world
// finds it again.
TEST(ParallelIO, RanksWithoutParticlesTakePart) {
  const Scene s = parse_scene("",
                              {"gravity.g=0", "tumbler.radius=0.02", "protocol.mode=rest",
                               "particles.fill_level=0.05", "contact.collision_time=1e-3"},
                              "single");
  const std::string d = scratch("single");
  Particles one;
  one.resize(1);
  one.x[0] = {0.001, -0.002, 0.003};
  one.v[0] = {0.01, 0, 0};
  one.id[0] = 0;
  set_species_properties(s, one);
  Simulation sim(s, share_of(one, MPI_COMM_WORLD), geometry::Protocol::at_rest(), 0, 0,
                 MPI_COMM_WORLD);
  sim.compute_forces();
  for (int k = 0; k < 10; ++k) sim.step();
  sim.request_rebuild();
  sim.step();
  io::write_checkpoint(d + "/ckpt.h5", sim, s, {}, {});
  io::write_snapshot(d + "/snap.h5", sim, s);
  io::H5File f(d + "/snap.h5", io::H5File::Mode::Read);
  ASSERT_EQ(f.read_int64("id").size(), 1u);
  EXPECT_NEAR(f.read_double("x")[0], 0.001 + 11 * s.time_step() * 0.01, 1e-12);
  io::CheckpointData c = io::read_checkpoint(d + "/ckpt.h5", MPI_COMM_WORLD);
  Simulation again(s, std::move(c.particles), geometry::Protocol::at_rest(), c.time, c.step,
                   MPI_COMM_WORLD);
  again.restore(c.history);
  EXPECT_EQ(again.global_count(), 1);
  EXPECT_EQ(again.gather_all().x[0].x, sim.gather_all().x[0].x);
}
