#include "run/settled_bed.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "base/agreed_input.hpp"
#include "base/comm.hpp"
#include "base/error.hpp"
#include "base/stop_request.hpp"
#include "base/text_util.hpp"
#include "engine/simulation.hpp"
#include "io/bed_io.hpp"
#include "run/made_on_ranks.hpp"
#include "scene/fill.hpp"
#include "scene/fill_cylinder.hpp"

namespace tumble {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
}  // namespace

Particles share_of(const Particles& all, MPI_Comm comm) {
  const int p = size_of(comm), r = rank_in(comm);
  if (p == 1) return all;
  const auto n = static_cast<std::int64_t>(all.size());
  std::vector<std::uint32_t> rows;
  for (std::int64_t i = n * r / p; i < n * (r + 1) / p; ++i)
    rows.push_back(static_cast<std::uint32_t>(i));
  Particles mine = all;
  mine.permute(rows);
  mine.resize(rows.size());
  mine.shrink_to_fit();  // else every rank would keep room for the whole bed for the whole run
  return mine;
}

std::string settling_needs_gravity() {
  return "scene error: key 'gravity.g' = 0: a bed Tumble fills settles under gravity (to "
         "fill.settle_rms_speed), which never ends without it; give gravity.g > 0, or "
         "fill.bed_file for a bed made elsewhere";
}

Particles fill_and_settle(const Scene& scene, std::ostream* log, MPI_Comm comm,
                          const std::function<void()>& between_blocks) {
  // (A scene without gravity is valid for an engine given its particles; settling one never ends:
  // it ran to fill.settle_max_time and said "did not settle ... rms speed 0 m/s".)
  if (scene.g <= 0) throw InputError(settling_needs_gravity());
  double shrink = 1;
  Particles bed;
  if (scene.cylinder()) {
    CylinderBed cb = make_cylinder_bed(scene);
    bed = std::move(cb.particles);
    shrink = cb.shrink;
  } else {
    bed = make_bed(scene);
  }
  if (log) {
    *log << "[fill] " << bed.size() << " particles placed (seed " << scene.seed << ", start '"
         << scene.start << "'";
    if (shrink < 1) *log << ", at " << shrink << " of their size, grown back while settling";
    *log << "); settling until rms speed < " << scene.settle_rms_speed << "\n";
  }
  // The engine is built with the full radii (they size its cells); a shrunk placement starts
  // with every radius scaled by `shrink` and grows back linearly over kGrowBlocks blocks of 200
  // steps, rebuilding the neighbour list after each change.
  std::vector<double> full_radius(bed.size());
  for (std::size_t i = 0; i < bed.size(); ++i) full_radius[bed.id[i]] = bed.radius[i];
  // Settling integrates every particle: the rigid bulk needs a turning wall, and the cached bed
  // must not depend on fidelity.bulk (it is not part of the bed's key).
  Scene dynamic = scene;
  dynamic.bulk = Bulk::dynamic;
  Simulation sim(dynamic, share_of(bed, comm), geometry::Protocol::at_rest(), 0, 0, comm);
  constexpr int kGrowBlocks = 50;
  auto set_scale = [&](double scale) {
    Particles& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) p.radius[i] = scale * full_radius[p.id[i]];
  };
  if (shrink < 1) set_scale(shrink);
  sim.compute_forces();
  const auto t0 = Clock::now();
  auto last = t0;
  const double min_time =
      20 * scene.collision_time + std::sqrt(2 * scene.d_large / std::max(scene.g, 1e-12));
  for (int block = 1;; ++block) {
    if (shrink < 1 && block <= kGrowBlocks) {
      set_scale(shrink + (1 - shrink) * block / kGrowBlocks);
      sim.request_rebuild();
    }
    for (int k = 0; k < 200; ++k) sim.step();
    if (between_blocks) between_blocks();
    stop_if_requested(comm, "settling the bed");
    const double rms = sim.rms_speed();
    const bool grown = shrink == 1 || block >= kGrowBlocks;
    if (grown && sim.time() > min_time && rms < scene.settle_rms_speed) break;
    if (sim.time() > scene.settle_max_time) {
      std::ostringstream os;
      os << "the bed did not settle within fill.settle_max_time = " << scene.settle_max_time
         << " s (rms speed " << rms << " m/s > fill.settle_rms_speed = " << scene.settle_rms_speed
         << "); raise fill.settle_max_time";
      throw RunError(os.str());
    }
    if (log && seconds_since(last) > scene.progress_interval) {
      last = Clock::now();
      *log << "[fill] t = " << std::setprecision(4) << sim.time() << " s, rms speed " << rms
           << " m/s, " << format_hms(seconds_since(t0)) << " elapsed" << std::endl;
    }
  }
  sim.check_health();
  if (log)
    *log << "[fill] settled at t = " << sim.time() << " s (" << sim.step_count() << " steps, "
         << std::setprecision(3) << seconds_since(t0) << " s wall)" << std::endl;
  Particles out = sim.gather_all();
  for (std::size_t i = 0; i < out.size(); ++i) {
    out.v[i] = out.w[i] = out.f[i] = out.t[i] = out.wall_spring[i] = Vec3{};
  }
  return out;
}

Particles settled_bed(const Scene& scene, std::ostream* log, bool* reused, MPI_Comm comm,
                      const std::function<void()>& between_blocks) {
  if (reused) *reused = true;
  // Every rank reads the bed itself, agreed (base/agreed_input.hpp): a damaged file is said once,
  // and a node that lacks the file (a bed cache on a node's own disk) ends every rank, named
  // (exit 2: fill.bed_cache), where the other ranks went on and waited for it for ever.
  Particles bed;
  if (!scene.bed_file.empty()) {
    if (log) *log << "[fill] starting from bed file " << scene.bed_file << "\n";
    agreed_input(comm, [&] { bed = io::read_bed(scene.bed_file, scene); });
    return bed;
  }
  const std::string cached = io::bed_cache_path(scene);
  int have = fs::exists(cached) ? 1 : 0;  // rank 0 decides for all
  if (size_of(comm) > 1) MPI_Bcast(&have, 1, MPI_INT, 0, comm);
  if (have) {
    int settled_on = 0;
    agreed_input(comm, [&] {
      // (Rank 0 has the file: a rank without it sees another directory under the same name.)
      if (!fs::exists(cached))
        throw InputError("fill.bed_cache = '" + scene.bed_cache +
                         "' is not the same directory on every rank: rank 0 has the settled bed " +
                         fs::path(cached).filename().string() +
                         " there, this rank has not; the bed cache must be on a file system every "
                         "rank sees (or give each run its own fill.bed_file)");
      bed = io::read_bed(cached, scene, io::BedSource::Cache);
      settled_on = io::bed_settled_on_ranks(cached);
    });
    if (log)
      *log << "[fill] reusing settled bed " << cached
           << made_on_ranks("settled", settled_on, size_of(comm),
                            "a bed settled here would differ in round-off")
           << "\n";
    return bed;
  }
  if (reused) *reused = false;
  bed = fill_and_settle(scene, log, comm, between_blocks);
  // Rank 0 writes it for all; its end is the barrier that keeps the others until the file is
  // there. A cache it cannot write (read-only, shared beds; a full disk) costs the next run with
  // this bed its settling again, not this run its bed: the run goes on with the bed it holds and
  // says so. (It failed here, after the settling, and a campaign's every case settled and failed
  // in turn.)
  on_rank_0_agreed(comm, [&] {
    try {
      fs::create_directories(scene.bed_cache);
      io::write_bed(cached, bed, scene, size_of(comm));
      if (log) *log << "[fill] saved settled bed to " << cached << "\n";
    } catch (const std::exception& e) {
      if (log)
        *log << "[fill] warning: the settled bed was not saved to fill.bed_cache = '"
             << scene.bed_cache << "' (" << e.what()
             << "); the run goes on with it, and the next run of this bed settles it again\n";
    }
  });
  return bed;
}

}  // namespace tumble
