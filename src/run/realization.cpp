#include "run/realization.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <ostream>

#include "base/agreed_input.hpp"
#include "base/comm.hpp"
#include "base/error.hpp"
#include "base/memory.hpp"
#include "base/text_util.hpp"
#include "engine/simulation.hpp"
#include "h5/hdf5_file.hpp"
#include "io/checkpoint.hpp"
#include "io/series_io.hpp"
#include "io/snapshot.hpp"
#include "run/checkpoint_observer.hpp"
#include "run/drift_observer.hpp"
#include "run/event_steps.hpp"
#include "run/health_observer.hpp"
#include "run/progress_observer.hpp"
#include "run/repose_measure.hpp"
#include "run/run_state.hpp"
#include "run/series_observer.hpp"
#include "run/snapshot_observer.hpp"

namespace tumble {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// The still slope, where the rigid bulk has one (" (still slope 11.3 deg, measured)").
std::string still_slope_note(const Scene& scene) {
  const StillSlope& s = scene.bulk_still_slope;
  if (s.deg <= 0) return "";
  return " (still slope " + short_number(s.deg) + " deg" + (s.measured ? ", measured)" : ")");
}

geometry::Protocol protocol_of(const Scene& scene) {
  if (scene.repose_pending())  // run_realization resolves it first
    throw std::logic_error("protocol.repose = 'measured' was not measured before the run");
  if (scene.mode == Mode::biaxial)
    return geometry::Protocol::biaxial(deg2rad(scene.theta_z), deg2rad(scene.theta_x),
                                       deg2rad(scene.repose.deg), scene.omega());
  if (scene.mode == Mode::single_axis)
    return geometry::Protocol::single_axis(name_of(scene.axis)[0], scene.omega());
  return geometry::Protocol::at_rest();
}

// Keys that must agree between a checkpoint and the scene it is restarted with (physics and bed);
// output, run-length and neighbour-list keys may differ (the skin changes no physics), and so may
// the rigid bulk's: a rigid run's state is a state of the dynamic engine (its frozen particles at
// the wall's velocity, their held springs in the contact records), so it may continue dynamic
// (everything thawed: Simulation resets the states), a dynamic one rigid, or rigid with other
// thresholds.
// A resolved value as the user would write it: a number in the fewest digits that give it back
// (0.6, not 0.59999999999999998), anything else as it is.
std::string readable(const std::string& value) {
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size()) return value;
  return canonical_number(v);
}

void check_restart_compatible(const Scene& scene, const std::string& ckpt_scene_text,
                              const std::string& path) {
  const Scene old = parse_scene(ckpt_scene_text, {}, "checkpoint");
  std::string diffs;
  for (const auto& [key, value] : scene.resolved) {
    // The fill's keys say how the first bed was made, which the checkpoint's state replaces; but
    // fill.seed names the realization (results.h5's `seed`, a campaign's replicas): a restart
    // under another seed went on with the checkpoint's bed recorded as the new seed's.
    if (key.rfind("output.", 0) == 0 || key == "protocol.iterations" ||
        key == "protocol.duration" || key == "scene.output_dir" || key == "scene.name" ||
        (key.rfind("fill.", 0) == 0 && key != "fill.seed") || key.rfind("neighbor.", 0) == 0 ||
        key.rfind("parallel.", 0) == 0 || key.rfind("fidelity.bulk", 0) == 0)
      continue;
    auto it = old.resolved.find(key);
    if (it == old.resolved.end() || it->second != value)
      diffs += (diffs.empty() ? " " : "; ") + key + " (checkpoint " +
               (it == old.resolved.end() ? "?" : readable(it->second)) + ", scene " +
               readable(value) + ")";
  }
  if (!diffs.empty())
    throw InputError("cannot restart from '" + path +
                     "': the scene differs from the checkpoint's in:" + diffs);
}

// A checkpoint read and checked for a restart of `scene`: its contents, and the scene it was
// written with (the run's restart and `run --check` alike).
io::CheckpointData read_checkpoint_for(const Scene& scene, const std::string& path, MPI_Comm comm) {
  io::CheckpointData c = io::read_checkpoint(path, comm);
  check_restart_compatible(scene, c.scene_text, path);
  io::check_checkpoint_fits(c, scene, path, comm);
  return c;
}

// The checkpoint to continue from ("" for a fresh start), decided by rank 0 for the whole run.
std::string restart_path(const RunOptions& opt, const std::string& ckpt_path, MPI_Comm comm) {
  std::string restart = opt.restart_file;
  if (restart.empty() && opt.resume && fs::exists(ckpt_path)) restart = ckpt_path;
  int have = restart.empty() ? 0 : 1;
  if (comm != MPI_COMM_NULL) MPI_Bcast(&have, 1, MPI_INT, 0, comm);
  if (!have) return "";
  return opt.restart_file.empty() ? ckpt_path : opt.restart_file;
}

// The engine and the observers' shared state (which refers to the engine, hence both on the heap).
struct Started {
  std::unique_ptr<Simulation> sim;
  std::unique_ptr<RunState> state;
};

// The engine at the checkpoint's state, with the series and the snapshot list it had.
Started restart_from(const std::string& path, const Scene& scene,
                     const geometry::Protocol& protocol, double snap_steps, MPI_Comm comm,
                     std::ostream* log) {
  // (A damaged checkpoint or one of another scene: every rank refuses it together; rank 0 says so.)
  io::CheckpointData c;
  thrown_together(comm, [&] { c = read_checkpoint_for(scene, path, comm); });
  double rows = static_cast<double>(c.particles.size());
  if (comm != MPI_COMM_NULL) MPI_Allreduce(MPI_IN_PLACE, &rows, 1, MPI_DOUBLE, MPI_SUM, comm);
  const auto n = static_cast<std::size_t>(rows);
  if (log)
    *log << "[run] restarting from " << path << " at t = " << c.time << " s (step " << c.step
         << ")\n";
  Started st;
  thrown_together(comm,
                  [&] { st.sim = io::engine_from_checkpoint(c, scene, protocol, path, comm); });
  st.state = std::make_unique<RunState>(scene, *st.sim, comm, log);
  st.state->series = std::move(c.series);
  if (scene.drift_grid == OnOff::on) st.state->drift = std::move(c.drift);
  const double dt = scene.time_step();
  for (std::int64_t k = 0; k < c.snapshots_written; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "snap_%06lld.h5", static_cast<long long>(k));
    // The times the checkpoint recorded; an older checkpoint's from the interval (exact unless
    // the interval changed or a run's end was written between two snapshots).
    const auto i = static_cast<std::size_t>(k);
    st.state->snapshots.push_back({name,
                                   i < c.snapshot_times.size()
                                       ? c.snapshot_times[i]
                                       : static_cast<double>(snapshot_step(k, snap_steps)) * dt,
                                   n});
  }
  return st;
}

// The engine at step 0 on the settled bed.
Started fresh_start(const Scene& scene, const geometry::Protocol& protocol, MPI_Comm comm,
                    std::ostream* log, bool* reused_bed) {
  Particles bed = settled_bed(scene, log, reused_bed, comm);
  Started st;
  st.sim = std::make_unique<Simulation>(scene, share_of(bed, comm), protocol, 0, 0, comm);
  st.sim->compute_forces();
  st.state = std::make_unique<RunState>(scene, *st.sim, comm, log);
  return st;
}

// results.h5: the time series and a summary, written atomically (rank 0's series: all ranks hold
// the same).
void write_results(const std::string& path, const RunState& s, const RunResult& res,
                   MPI_Comm comm) {
  io::AtomicH5Writer out(path, comm);
  io::H5File& f = out.file();
  io::write_series(f, s.series);
  f.set_attr("/", "steps", static_cast<std::int64_t>(s.sim.step_count()));
  f.set_attr("/", "time", s.sim.time());
  f.set_attr("/", "particles", res.particles);
  f.set_attr("/", "complete", static_cast<std::int64_t>(s.sim.step_count() >= s.total_steps));
  f.set_attr("/", "particle_steps_per_second", res.particle_steps_per_second);
  // (the rate is the ranks' together: with their count a reader can compare runs made on others)
  f.set_attr("/", "ranks", static_cast<std::int64_t>(size_of(comm)));
  io::write_provenance(f, s.scene);
  out.commit();
}

void log_done(std::ostream* log, const RunState& s, const RunResult& res) {
  const Simulation& sim = s.sim;
  long long ghosts = 0;     // over all ranks (collective, before the rank-0-only log)
  long long refreshed = 0;  // ... of them in a pair of their rank's list (Domain::keep_used_ghosts)
  // The least and most time any rank spent in the halo refresh: the refresh waits for the slowest
  // neighbour, so the spread says how unevenly the work is shared (the busiest rank waits least).
  double refresh_min = 0, refresh_max = 0, test_min = 0, test_max = 0, pairs_max = 0,
         pairs_mean = 0;
  if (const parallel::Domain* dom = sim.domain()) {
    long long mine[2] = {dom->ghosts(), dom->refreshed_ghosts()}, all[2] = {0, 0};
    MPI_Allreduce(mine, all, 2, MPI_LONG_LONG, MPI_SUM, dom->comm());
    ghosts = all[0];
    refreshed = all[1];
    const double t = dom->refresh_seconds();
    MPI_Allreduce(&t, &refresh_min, 1, MPI_DOUBLE, MPI_MIN, dom->comm());
    MPI_Allreduce(&t, &refresh_max, 1, MPI_DOUBLE, MPI_MAX, dom->comm());
    // The per-step rebuild test, an allreduce: since the refresh travels behind the interior
    // pairs, the wait for the slowest rank is mostly here.
    const double tt = dom->test_seconds();
    MPI_Allreduce(&tt, &test_min, 1, MPI_DOUBLE, MPI_MIN, dom->comm());
    MPI_Allreduce(&tt, &test_max, 1, MPI_DOUBLE, MPI_MAX, dom->comm());
    // The pair work's share: the entries of each rank's last neighbour list (border pairs on both
    // sides with Newton off, on one with it on), max / mean over the ranks.
    const auto pairs = static_cast<double>(sim.neighbors().nbr.size());
    MPI_Allreduce(&pairs, &pairs_max, 1, MPI_DOUBLE, MPI_MAX, dom->comm());
    MPI_Allreduce(&pairs, &pairs_mean, 1, MPI_DOUBLE, MPI_SUM, dom->comm());
    pairs_mean /= dom->size();
  }
  // The engine's memory (its arrays' capacities): summed over the ranks, per particle of the
  // realization, and the largest rank's.
  const EngineMemory mem = sim.memory();
  double parts[3] = {static_cast<double>(mem.particles), static_cast<double>(mem.neighbors),
                     static_cast<double>(mem.scratch)};
  double largest = static_cast<double>(mem.total());
  if (const parallel::Domain* dom = sim.domain()) {
    MPI_Allreduce(MPI_IN_PLACE, parts, 3, MPI_DOUBLE, MPI_SUM, dom->comm());
    MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPI_DOUBLE, MPI_MAX, dom->comm());
  }
  if (!log) return;
  const double per = 1.0 / static_cast<double>(std::max<std::int64_t>(1, s.particles));
  *log << "[run] memory: engine " << format_bytes(parts[0] + parts[1] + parts[2]) << " ("
       << std::fixed << std::setprecision(0) << (parts[0] + parts[1] + parts[2]) * per
       << " B per particle: state " << parts[0] * per << ", neighbour list " << parts[1] * per
       << ", scratch " << parts[2] * per << std::defaultfloat << ")";
  if (sim.domain()) *log << ", largest rank " << format_bytes(largest);
  *log << "\n";
  *log << "[run] done: " << res.steps << " steps in " << std::setprecision(4) << res.wall_seconds
       << " s (" << std::scientific << std::setprecision(3) << res.particle_steps_per_second
       << std::defaultfloat << " particle-steps/s";
  if (const parallel::Domain* dom = sim.domain())
    *log << " on " << dom->size() << " ranks, imbalance " << std::fixed << std::setprecision(3)
         << dom->imbalance() << " (list pairs " << pairs_max / std::max(pairs_mean, 1.0) << "), "
         << ghosts << " ghosts, " << refreshed << " of them in pairs, " << dom->bisections()
         << " bisections, " << sim.rebuilds() << " rebuilds; rank 0 in halo refresh "
         << dom->refresh_seconds() << " s (ranks " << refresh_min << "-" << refresh_max
         << " s), in the rebuild test " << dom->test_seconds() << " s (ranks " << test_min << "-"
         << test_max << " s), in migration + ghost exchange " << dom->rebuild_seconds() << " s";
  *log << "); results in " << res.results_file << ", snapshots in " << s.scene.output_dir
       << "/snapshots.xdmf\n";
}
}  // namespace

namespace {
// The folders a run made for its output (the output folder and any parents it lacked): removed
// again, if still empty, when the run is refused before it begins (a checkpoint that does not
// fit the scene or is damaged, a bed that does not settle), so that a refused run leaves nothing
// behind. (Only on the rank that made them; empty on the others.)
class FoldersMade {
 public:
  FoldersMade() = default;
  FoldersMade(fs::path leaf, fs::path outermost)
      : leaf_(std::move(leaf)), outermost_(std::move(outermost)) {}
  FoldersMade(const FoldersMade&) = delete;
  FoldersMade& operator=(const FoldersMade&) = delete;
  FoldersMade& operator=(FoldersMade&& o) noexcept {
    leaf_ = std::move(o.leaf_);
    outermost_ = std::move(o.outermost_);
    o.keep();
    return *this;
  }
  void keep() { outermost_.clear(); }
  ~FoldersMade() {
    if (outermost_.empty()) return;
    std::error_code ec;
    for (fs::path p = leaf_; !p.empty(); p = p.parent_path()) {
      if (!fs::is_empty(p, ec) || ec || !fs::remove(p, ec)) return;
      if (p == outermost_ || p == p.parent_path()) return;
    }
  }

 private:
  fs::path leaf_, outermost_;  // outermost_ empty: nothing to remove
};

FoldersMade make_folders(const std::string& dir) {
  const fs::path leaf = fs::absolute(dir).lexically_normal();
  fs::path outermost;
  for (fs::path p = leaf; !fs::exists(p) && p != p.parent_path(); p = p.parent_path())
    outermost = p;
  fs::create_directories(dir);
  return {leaf, outermost};
}
}  // namespace

void check_restart_from(const Scene& scene, const std::string& path) {
  read_checkpoint_for(scene, path, MPI_COMM_NULL);
}

RunResult run_realization(const Scene& given, const RunOptions& opt) {
  const MPI_Comm comm = size_of(opt.comm) > 1 ? opt.comm : MPI_COMM_NULL;
  const bool lead = rank_in(comm) == 0;  // writes the serial files and the log
  std::ostream* log = lead ? opt.log : nullptr;
  RunResult res;
  res.output_dir = given.output_dir;
  // Rank 0 makes the folder for all; its error (a parent that is a file, no permission) is every
  // rank's: thrown on rank 0 alone, the others waited at the barrier this replaces for ever.
  FoldersMade made;
  on_rank_0_agreed(comm, [&] { made = make_folders(given.output_dir); });
  const std::string ckpt_path = given.output_dir + "/checkpoint.h5";

  const std::string restart = restart_path(opt, ckpt_path, comm);
  if (restart.empty() && opt.resume && log)
    *log << "[run] resume: no checkpoint at " << ckpt_path << " yet; starting from step 0\n";
  // β and the still slope = "measured" become numbers before anything uses the protocol or the
  // engine (a campaign resolves them earlier, for its collection plan; then this changes nothing).
  const Scene scene = with_bed_turn_resolved(given, restart, log, comm);

  const geometry::Protocol protocol = protocol_of(scene);
  const double dt = scene.time_step();
  const double period = protocol.periodic() ? protocol.period() : 1.0;
  // Snapshots: the interval in steps, not rounded (snapshot_observer.hpp, snapshot_step).
  const double snap_steps = (scene.snapshot_interval > 0 ? scene.snapshot_interval : period) / dt;
  Started st = restart.empty() ? fresh_start(scene, protocol, comm, log, &res.reused_bed)
                               : restart_from(restart, scene, protocol, snap_steps, comm, log);
  made.keep();  // the run begins: its folder stays whatever happens next
  Simulation* sim = st.sim.get();
  RunState& s = *st.state;
  s.particles = res.particles = sim->global_count();
  s.total_steps = scene.protocol_steps();
  s.first_step = sim->step_count();
  s.end_step =
      opt.max_steps >= 0 ? std::min(s.total_steps, s.first_step + opt.max_steps) : s.total_steps;

  // The observers, in the order they run (see run/observer.hpp).
  std::vector<std::unique_ptr<Observer>> own;
  std::vector<Observer*> observers;
  auto add = [&](std::unique_ptr<Observer> o) {
    observers.push_back(o.get());
    own.push_back(std::move(o));
  };
  if (scene.analysis_interval > 0)
    add(std::make_unique<SeriesObserver>(
        scene, steps_between_events(scene.analysis_interval, dt, period)));
  for (Observer* o : opt.observers) observers.push_back(o);
  if (scene.drift_grid == OnOff::on) add(std::make_unique<DriftObserver>(scene));
  add(std::make_unique<HealthObserver>());
  if (opt.write_snapshots) add(std::make_unique<SnapshotObserver>(snap_steps));
  add(std::make_unique<CheckpointObserver>(
      ckpt_path, steps_between_events(scene.checkpoint_interval, dt, period),
      scene.checkpoint_wall));
  add(std::make_unique<ProgressObserver>(opt.on_progress));

  if (sim->step_count() == 0)
    for (Observer* o : observers) o->start(s);
  if (log)
    *log << "[run] " << scene.name << ": " << res.particles << " particles, dt = " << dt << " s, "
         << s.total_steps << " steps (" << scene.run_time() << " s simulated"
         << (protocol.periodic() ? ", " + std::to_string(scene.iterations) + " iterations" : "")
         << (scene.mode == Mode::biaxial ? ", beta = " + short_number(scene.repose.deg) + " deg" +
                                               (scene.repose.measured ? " (measured)" : "")
                                         : std::string())
         << "), pair loop: " << sim->pair_kernel_name()
         << (sim->rigid_bulk() ? ", bulk: rigid" + still_slope_note(scene) : "") << ", output in "
         << scene.output_dir << "\n";

  // The run loop.
  s.started = Clock::now();
  // The caller hears that the protocol begins (where a restart left off) now, after the bed or
  // checkpoint is loaded: a campaign's ETA credits the case's rate from here, not its setup.
  if (s.log && opt.on_progress) opt.on_progress(s);
  while (sim->step_count() < s.end_step) {
    const std::int64_t next = sim->step_count() + 1;
    for (Observer* o : observers) o->before_step(s, next);
    sim->step();
    for (Observer* o : observers) o->after_step(s);
  }

  res.wall_seconds = std::chrono::duration<double>(Clock::now() - s.started).count();
  res.steps = sim->step_count() - s.first_step;
  res.particle_steps_per_second =
      res.wall_seconds > 0 ? res.steps * static_cast<double>(res.particles) / res.wall_seconds : 0;
  if (sim->rigid_bulk() && log)  // rank 0's counts (every rank rebuilds together)
    *log << "[run] rigid bulk: " << sim->rebuilds() << " neighbour rebuilds, "
         << sim->thaw_rebuilds() << " of them forced by thaws, " << sim->gravity_thaws()
         << " particles thawed by gravity's turn on rank 0\n";
  if (sim->fast_rebuilds() > 0 && log)
    *log << "[run] warning: " << sim->fast_rebuilds() << " of " << sim->rebuilds()
         << " neighbour rebuilds came < 10 steps apart (one every " << std::setprecision(3)
         << static_cast<double>(res.steps) / std::max<std::uint64_t>(1, sim->rebuilds())
         << " steps on average): raise neighbor.skin (now " << scene.skin << " d_small)\n";
  res.results_file = scene.output_dir + "/results.h5";
  write_results(res.results_file, s, res, comm);
  for (Observer* o : observers) o->finish(s);
  res.series = std::move(s.series);
  log_done(log, s, res);
  return res;
}

}  // namespace tumble
