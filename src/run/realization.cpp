#include "run/realization.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "run/drift_measure.hpp"
#include "analysis/flow_profile.hpp"
#include "cm/drift_grid.hpp"
#include "base/error.hpp"
#include "scene/fill.hpp"
#include "scene/fill_cylinder.hpp"
#include "engine/simulation.hpp"
#include "base/text_util.hpp"
#include "io/bed_io.hpp"
#include "io/checkpoint.hpp"
#include "h5/hdf5_file.hpp"
#include "io/series_io.hpp"
#include "io/snapshot.hpp"

namespace tumble {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
int rank_in(MPI_Comm comm) {
  int r = 0;
  if (comm != MPI_COMM_NULL) MPI_Comm_rank(comm, &r);
  return r;
}
int size_of(MPI_Comm comm) {
  int n = 1;
  if (comm != MPI_COMM_NULL) MPI_Comm_size(comm, &n);
  return n;
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
  return mine;
}

Particles fill_and_settle(const Scene& scene, std::ostream* log, MPI_Comm comm) {
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
  Simulation sim(scene, share_of(bed, comm), geometry::Protocol::at_rest(), 0, 0, comm);
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

Particles settled_bed(const Scene& scene, std::ostream* log, bool* reused, MPI_Comm comm) {
  if (reused) *reused = true;
  if (!scene.bed_file.empty()) {
    if (log) *log << "[fill] starting from bed file " << scene.bed_file << "\n";
    return io::read_bed(scene.bed_file, scene);
  }
  const std::string cached = io::bed_cache_path(scene);
  int have = fs::exists(cached) ? 1 : 0;  // rank 0 decides for all
  if (size_of(comm) > 1) MPI_Bcast(&have, 1, MPI_INT, 0, comm);
  if (have) {
    if (log) *log << "[fill] reusing settled bed " << cached << "\n";
    return io::read_bed(cached, scene);
  }
  if (reused) *reused = false;
  Particles bed = fill_and_settle(scene, log, comm);
  if (rank_in(comm) == 0) {
    fs::create_directories(scene.bed_cache);
    io::write_bed(cached, bed, scene);
    if (log) *log << "[fill] saved settled bed to " << cached << "\n";
  }
  if (size_of(comm) > 1) MPI_Barrier(comm);
  return bed;
}

namespace {
// Keys that must agree between a checkpoint and the scene it is restarted with (physics and bed);
// output, run-length and neighbour-list keys may differ (the skin changes no physics).
void check_restart_compatible(const Scene& scene, const std::string& ckpt_scene_text) {
  const Scene old = parse_scene(ckpt_scene_text, {}, "checkpoint");
  std::string diffs;
  for (const auto& [key, value] : scene.resolved) {
    if (key.rfind("output.", 0) == 0 || key == "protocol.iterations" ||
        key == "protocol.duration" || key == "scene.output_dir" || key == "scene.name" ||
        key.rfind("fill.", 0) == 0 || key.rfind("neighbor.", 0) == 0 ||
        key.rfind("parallel.", 0) == 0)
      continue;
    auto it = old.resolved.find(key);
    if (it == old.resolved.end() || it->second != value)
      diffs += " " + key + " (checkpoint " + (it == old.resolved.end() ? "?" : it->second) +
               ", scene " + value + ")";
  }
  if (!diffs.empty())
    throw InputError("cannot restart: the scene differs from the checkpoint's in:" + diffs);
}

std::int64_t steps_for(double interval, double dt, double fallback) {
  const double t = interval > 0 ? interval : fallback;
  return std::max<std::int64_t>(1, std::llround(t / dt));
}
}  // namespace

RunResult run_realization(const Scene& scene, const RunOptions& opt) {
  const MPI_Comm comm = size_of(opt.comm) > 1 ? opt.comm : MPI_COMM_NULL;
  const bool lead = rank_in(comm) == 0;  // writes the serial files and the log
  std::ostream* log = lead ? opt.log : nullptr;
  if (comm != MPI_COMM_NULL && !opt.observers.empty())
    throw InputError("in-situ observers need a serial run (one rank per realization)");
  RunResult res;
  res.output_dir = scene.output_dir;
  if (lead) fs::create_directories(scene.output_dir);
  if (comm != MPI_COMM_NULL) MPI_Barrier(comm);
  const std::string ckpt_path = scene.output_dir + "/checkpoint.h5";

  geometry::Protocol protocol =
      scene.mode == Mode::biaxial
          ? geometry::Protocol::biaxial(deg2rad(scene.theta_z), deg2rad(scene.theta_x),
                                        deg2rad(scene.repose), scene.omega())
          : (scene.mode == Mode::single_axis
                 ? geometry::Protocol::single_axis(name_of(scene.axis)[0], scene.omega())
                 : geometry::Protocol::at_rest());
  const double dt = scene.time_step();
  const std::int64_t total_steps = std::llround(scene.run_time() / dt);
  const double period = protocol.periodic() ? protocol.period() : 1.0;
  const std::int64_t snap_every = steps_for(scene.snapshot_interval, dt, period);
  const std::int64_t ckpt_every = steps_for(scene.checkpoint_interval, dt, period);
  const std::int64_t sample_every =
      scene.analysis_interval > 0 ? steps_for(scene.analysis_interval, dt, period) : 0;

  std::string restart = opt.restart_file;
  if (restart.empty() && opt.resume && fs::exists(ckpt_path)) restart = ckpt_path;

  std::unique_ptr<Simulation> sim;
  analysis::Series series;
  std::vector<io::SnapshotEntry> snaps;
  // Every rank takes the same branch: rank 0 looks for the checkpoint.
  int have_restart = restart.empty() ? 0 : 1;
  if (comm != MPI_COMM_NULL) MPI_Bcast(&have_restart, 1, MPI_INT, 0, comm);
  if (!have_restart)
    restart.clear();
  else if (restart.empty())
    restart = opt.restart_file.empty() ? ckpt_path : opt.restart_file;
  if (!restart.empty()) {
    io::CheckpointData c = io::read_checkpoint(restart, comm);
    check_restart_compatible(scene, c.scene_text);
    double rows = static_cast<double>(c.particles.size());
    if (comm != MPI_COMM_NULL) MPI_Allreduce(MPI_IN_PLACE, &rows, 1, MPI_DOUBLE, MPI_SUM, comm);
    const auto n = static_cast<std::size_t>(rows);
    if (log)
      *log << "[run] restarting from " << restart << " at t = " << c.time << " s (step " << c.step
           << ")\n";
    sim =
        std::make_unique<Simulation>(scene, std::move(c.particles), protocol, c.time, c.step, comm);
    sim->restore(c.history);
    series = std::move(c.series);
    for (std::int64_t k = 0; k < c.snapshots_written; ++k) {
      char name[64];
      std::snprintf(name, sizeof name, "snap_%06lld.h5", static_cast<long long>(k));
      snaps.push_back({name, static_cast<double>(k * snap_every) * dt, n});
    }
  } else {
    Particles bed = settled_bed(scene, log, &res.reused_bed, comm);
    sim = std::make_unique<Simulation>(scene, share_of(bed, comm), protocol, 0, 0, comm);
    sim->compute_forces();
  }
  res.particles = sim->global_count();
  // Analyses see the whole bed: a domain-decomposed run gathers it (sorted by id) when sampling.
  Particles gathered;
  auto whole_bed = [&]() -> const Particles& {
    if (comm == MPI_COMM_NULL) return sim->particles();
    gathered = sim->gather_all();
    return gathered;
  };

  auto snapshot = [&]() {
    if (!opt.write_snapshots) return;
    char name[64];
    std::snprintf(name, sizeof name, "snap_%06zu.h5", snaps.size());
    io::write_snapshot(scene.output_dir + "/" + name, *sim, scene);
    snaps.push_back({name, sim->time(), static_cast<std::size_t>(res.particles)});
    if (lead) io::write_xdmf(scene.output_dir, snaps);
  };
  // Cylinder scenes measure Rapaport's S_a, S_r and profiles; sphere scenes Yu's shell fraction.
  analysis::CylinderFrame frame;
  frame.radius = scene.radius;
  frame.length = scene.length;
  frame.slice =
      scene.slice_width > 0 ? scene.slice_width : 2.5 * (scene.d_small - 0.5 * scene.size_spread);
  frame.b3 = std::pow(scene.d_large / scene.d_small, 3);
  analysis::FlowFrame flow;
  flow.axis = scene.axis == Axis::x ? Vec3{1, 0, 0} : Vec3{0, 0, 1};
  flow.radius = scene.radius;
  flow.bin = 2 * scene.d_large;
  flow.depth = scene.d_large;
  auto sample = [&]() {
    const double kinetic = sim->energy().kinetic;  // collective: before the gather, on all ranks
    const Particles& all = whole_bed();
    if (scene.cylinder()) {
      analysis::sample_cylinder(all, frame, sim->time(), scene.omega() * sim->time() / (2 * kPi),
                                kinetic, series.cylinder);
      return;
    }
    series.append(sim->time(), sim->protocol().iteration(sim->time()),
                  analysis::radial_segregation(all, scene.radius), kinetic);
    if (scene.mode == Mode::single_axis) {  // the flowing layer: repose angle and surface speed
      const analysis::FlowProfile fp = analysis::flow_profile(all, all.size(), flow);
      series.repose_angle.push_back(fp.repose_deg);
      series.surface_speed.push_back(fp.surface_speed);
      series.profile_h = fp.h;
      series.surface_profile.insert(series.surface_profile.end(), fp.speed.begin(), fp.speed.end());
    }
  };
  // The MCM's drift grid (output.drift_grid = on): large particles at the free surface of the
  // flowing layer, every 0.1 s of the "rotate" segments, as Yu 2022 App. A.
  std::unique_ptr<analysis::DriftGridMeter> drift;
  std::int64_t drift_every = 0;
  if (scene.drift_grid == OnOff::on) {
    drift = std::make_unique<analysis::DriftGridMeter>(30, scene.radius, deg2rad(scene.repose),
                                                       scene.omega(), scene.d_large);
    drift_every = std::max<std::int64_t>(1, std::llround(0.1 / dt));
  }
  if (sim->step_count() == 0) {
    snapshot();
    if (sample_every) sample();
    for (const auto& o : opt.observers) o.observe(*sim);
  }

  if (log)
    *log << "[run] " << scene.name << ": " << res.particles << " particles, dt = " << dt << " s, "
         << total_steps << " steps (" << scene.run_time() << " s simulated"
         << (protocol.periodic() ? ", " + std::to_string(scene.iterations) + " iterations" : "")
         << "), output in " << scene.output_dir << "\n";

  std::int64_t end_step = total_steps;
  if (opt.max_steps >= 0) end_step = std::min(end_step, sim->step_count() + opt.max_steps);
  const std::int64_t first_step = sim->step_count();
  const auto t0 = Clock::now();
  auto last_progress = t0;
  while (sim->step_count() < end_step) {
    const std::int64_t next = sim->step_count() + 1;
    const bool ckpt_now = next % ckpt_every == 0 || next == total_steps || next == end_step;
    if (ckpt_now) sim->request_rebuild();
    sim->step();
    const std::int64_t s = sim->step_count();
    if (sample_every && s % sample_every == 0) sample();
    for (const auto& o : opt.observers)
      if (s % o.every_steps == 0) o.observe(*sim);
    if (drift && s % drift_every == 0 &&
        std::string(sim->protocol().phase(sim->time())) ==
            (protocol.periodic() ? "rotate" : "spin"))
      drift->sample(whole_bed(), sim->protocol().omega(sim->time()));
    if (s % 1000 == 0) sim->check_health();
    if (s % snap_every == 0 || s == total_steps) snapshot();
    if (ckpt_now) {  // also where --max-steps stops, so the run can be continued
      sim->check_health();
      io::write_checkpoint(ckpt_path, *sim, scene, series, static_cast<std::int64_t>(snaps.size()));
    }
    if (log && (s & 63) == 0 && seconds_since(last_progress) >= scene.progress_interval) {
      last_progress = Clock::now();
      const double el = seconds_since(t0);
      const double rate = (s - first_step) * static_cast<double>(res.particles) / el;
      const double eta = el / (s - first_step) * (end_step - s);
      *log << "[run] t = " << std::fixed << std::setprecision(3) << sim->time() << " s  ";
      if (scene.mode == Mode::single_axis)  // constant rotation: count revolutions
        *log << "rev " << std::setprecision(2) << scene.omega() * sim->time() / (2 * kPi);
      else
        *log << "iter " << std::setprecision(2) << sim->protocol().iteration(sim->time()) << " ("
             << sim->protocol().phase(sim->time()) << ")";
      *log << "  step " << s << "/" << end_step << "  " << std::scientific << std::setprecision(2)
           << rate << " particle-steps/s  ETA " << format_hms(eta) << std::defaultfloat;
      if (const parallel::Domain* dom = sim->domain())
        *log << "  " << dom->size() << " ranks, imbalance " << std::fixed << std::setprecision(3)
             << dom->imbalance() << std::defaultfloat;
      *log << std::endl;
    }
  }
  res.wall_seconds = seconds_since(t0);
  res.steps = sim->step_count() - first_step;
  res.particle_steps_per_second =
      res.wall_seconds > 0 ? res.steps * static_cast<double>(res.particles) / res.wall_seconds : 0;
  if (sim->fast_rebuilds() > 0 && log)
    *log << "[run] warning: " << sim->fast_rebuilds() << " of " << sim->rebuilds()
         << " neighbour rebuilds came < 10 steps apart (one every " << std::setprecision(3)
         << static_cast<double>(res.steps) / std::max<std::uint64_t>(1, sim->rebuilds())
         << " steps on average): raise neighbor.skin (now " << scene.skin << " d_small)\n";

  // Results: the time series and a summary, written atomically.
  res.results_file = scene.output_dir + "/results.h5";
  {
    io::AtomicH5Writer out(res.results_file, comm);  // rank 0's series (all ranks hold it)
    io::H5File& f = out.file();
    io::write_series(f, series);
    f.set_attr("/", "steps", static_cast<std::int64_t>(sim->step_count()));
    f.set_attr("/", "time", sim->time());
    f.set_attr("/", "particles", res.particles);
    f.set_attr("/", "complete", static_cast<std::int64_t>(sim->step_count() >= total_steps));
    f.set_attr("/", "particle_steps_per_second", res.particle_steps_per_second);
    io::write_provenance(f, scene);
    out.commit();
  }
  if (drift && lead) {
    const std::string path = scene.output_dir + "/drift_grid.h5";
    cm::write_drift_grid(
        path, drift->grid("DEM scene " + scene.name + ", seed " + std::to_string(scene.seed) +
                          ", " + std::to_string(drift->samples()) + " samples"));
    if (log) *log << "[run] drift grid (" << drift->samples() << " samples) in " << path << "\n";
  }
  res.series = std::move(series);
  long long ghosts = 0;  // over all ranks (collective, before the rank-0-only log)
  if (const parallel::Domain* dom = sim->domain()) {
    long long mine = dom->ghosts();
    MPI_Allreduce(&mine, &ghosts, 1, MPI_LONG_LONG, MPI_SUM, dom->comm());
  }
  if (log)
    *log << "[run] done: " << res.steps << " steps in " << std::setprecision(4) << res.wall_seconds
         << " s (" << std::scientific << std::setprecision(3) << res.particle_steps_per_second
         << std::defaultfloat << " particle-steps/s";
  if (const parallel::Domain* dom = sim->domain(); dom && log)
    *log << " on " << dom->size() << " ranks, imbalance " << std::fixed << std::setprecision(3)
         << dom->imbalance() << ", " << ghosts << " ghosts, " << dom->bisections()
         << " bisections, " << sim->rebuilds() << " rebuilds; rank 0 in halo refresh "
         << dom->refresh_seconds() << " s, in migration + ghost exchange " << dom->rebuild_seconds()
         << " s";
  if (log)
    *log << "); results in " << res.results_file << ", snapshots in " << scene.output_dir
         << "/snapshots.xdmf\n";
  return res;
}

}  // namespace tumble
