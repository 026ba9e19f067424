#include "run/repose_measure.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <ostream>
#include <sstream>
#include <vector>

#include "analysis/flow_profile.hpp"
#include "base/agreed_input.hpp"
#include "base/comm.hpp"
#include "base/error.hpp"
#include "base/hash.hpp"
#include "base/stop_request.hpp"
#include "base/text_util.hpp"
#include "engine/simulation.hpp"
#include "h5/hdf5_file.hpp"
#include "io/bed_io.hpp"
#include "io/checkpoint.hpp"
#include "io/snapshot.hpp"
#include "run/settled_bed.hpp"

namespace tumble {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// The turn so far: the engine and the samples. resume_turn() fills it from the file written at a
// stop or by the wall clock, or returns false: no file, or one that does not fit this measurement
// (the reason logged).
struct Turn {
  std::unique_ptr<Simulation> sim;
  std::vector<double> angles;
};

bool resume_turn(const Scene& dynamic, const std::string& path, Turn& turn, std::ostream* log,
                 MPI_Comm comm) {
  int have = rank_in(comm) == 0 && !path.empty() && fs::exists(path) ? 1 : 0;
  if (size_of(comm) > 1) MPI_Bcast(&have, 1, MPI_INT, 0, comm);
  if (!have) return false;
  try {
    io::CheckpointData c = io::read_checkpoint(path, comm);  // collective; same error on all
    if (repose_key(parse_scene(c.scene_text, {}, "repose turn " + path)) != repose_key(dynamic))
      throw InputError("it was written for another bed, speed or contact law");
    io::check_checkpoint_fits(c, dynamic, path, comm);
    turn.sim = io::engine_from_checkpoint(
        c, dynamic, geometry::Protocol::single_axis('z', dynamic.omega()), path, comm);
    turn.angles = std::move(c.measure_samples);
  } catch (const std::runtime_error& e) {  // (every rank alike: the reads agree their errors)
    if (log)
      *log << "[repose] not going on from " << path << ": " << e.what()
           << "; turning from the start" << std::endl;
    return false;
  }
  if (log)
    *log << "[repose] going on from " << path << " at " << std::setprecision(3)
         << rad2deg(dynamic.omega() * turn.sim->time()) << " of " << kReposeEndDeg << " degrees ("
         << turn.angles.size() << " samples)" << std::endl;
  return true;
}

}  // namespace

ReposeMeasurement measure_repose(const Scene& scene, const std::function<Particles()>& bed,
                                 const std::string& turn_path, std::ostream* log, MPI_Comm comm,
                                 const std::function<void()>& between_blocks) {
  const double w = scene.omega();
  const double dt = scene.time_step();
  const auto steps_per_degree = std::max<std::int64_t>(1, std::llround(deg2rad(1.0) / w / dt));
  const auto first = static_cast<std::int64_t>(kReposeSpinUpDeg) * steps_per_degree;
  const auto last = static_cast<std::int64_t>(kReposeEndDeg) * steps_per_degree;
  // The dynamic bed's angle, whatever fidelity.bulk: β is cached by a key that does not hold it.
  Scene dynamic = scene;
  dynamic.bulk = Bulk::dynamic;
  Turn turn;
  if (!resume_turn(dynamic, turn_path, turn, log, comm)) {
    if (log)
      *log << "[repose] protocol.repose = 'measured': turning the settled bed " << kReposeEndDeg
           << " degrees about z at " << std::setprecision(4) << w << " rad/s (" << last
           << " steps), sampling the free surface once a degree from " << kReposeSpinUpDeg
           << " degrees" << std::endl;
    turn.sim = std::make_unique<Simulation>(dynamic, share_of(bed(), comm),
                                            geometry::Protocol::single_axis('z', w), 0, 0, comm);
    turn.sim->compute_forces();
  }
  Simulation& sim = *turn.sim;
  std::vector<double>& angles = turn.angles;
  analysis::FlowFrame frame;  // as the series observer's flow measure (run/series_observer.cpp)
  frame.axis = Vec3{0, 0, 1};
  frame.radius = scene.radius;
  frame.bin = 2 * scene.d_large;
  frame.depth = scene.d_large;
  const bool lead = rank_in(comm) == 0;
  const auto t0 = Clock::now();
  auto shown = t0, saved = t0;
  // The turn is kept as a run keeps its protocol (run/checkpoint_observer.hpp): after a step in
  // which the engine rebuilt its list by itself, so that going on from the file repeats the
  // uninterrupted turn bit for bit (a still bed gets a forced rebuild after kStopWait steps).
  // Asked for by a stop signal, or by output.checkpoint_wall of wall time since the last; the
  // ranks agree every kAgree steps (rank 0's clock decides).
  constexpr std::int64_t kAgree = 200, kStopWait = 1000;
  int stop = 0;
  bool keep = false;
  std::int64_t asked = 0;
  std::uint64_t rebuilds = sim.rebuilds();
  while (sim.step_count() < last) {
    // (Only for a stop: a keep by the clock that forced a rebuild would make β depend on the
    // machine's speed.)
    if (keep && stop != 0 && sim.step_count() + 1 - asked >= kStopWait) sim.request_rebuild();
    sim.step();
    const std::int64_t k = sim.step_count();
    const bool rebuilt = sim.rebuilds() != rebuilds;
    rebuilds = sim.rebuilds();
    if (k >= first && k % steps_per_degree == 0) {
      const Particles all = sim.gather_all();  // collective
      const double a = analysis::flow_profile(all, all.size(), frame).repose_deg;
      if (std::isfinite(a)) angles.push_back(a);
    }
    if (k % kAgree == 0) {
      if (between_blocks) between_blocks();
      int ask[2] = {
          stop_signal(),
          lead && scene.checkpoint_wall > 0 &&
              std::chrono::duration<double>(Clock::now() - saved).count() >= scene.checkpoint_wall};
      if (size_of(comm) > 1) MPI_Allreduce(MPI_IN_PLACE, ask, 2, MPI_INT, MPI_MAX, comm);
      if (turn_path.empty() && ask[0] != 0)  // nowhere to keep it
        stop_if_requested(comm, "measuring the repose angle");
      const bool stop_now = stop == 0 && ask[0] != 0;
      if (stop_now) stop = ask[0];
      if (stop_now || (ask[1] != 0 && !keep)) {  // (a stop waits its kStopWait from here)
        keep = true;
        asked = k;
      }
    }
    if (keep && rebuilt && k < last) {
      sim.check_health();  // (a blown-up state is not kept)
      io::write_checkpoint(turn_path, sim, dynamic, {}, {}, {}, angles);  // collective
      saved = Clock::now();
      keep = false;
      const std::string at =
          short_number(rad2deg(w * sim.time())) + " of " + short_number(kReposeEndDeg) + " degrees";
      if (stop != 0)
        throw StopRequest(
            "stopped by " + signal_name(stop) + " while measuring the repose angle, at " + at +
            ": the turn so far is kept in " + turn_path + " (the next run goes on from it)");
      if (log) *log << "[repose] turn kept at " << at << " in " << turn_path << std::endl;
    }
    if (log &&
        std::chrono::duration<double>(Clock::now() - shown).count() > scene.progress_interval) {
      shown = Clock::now();
      *log << "[repose] " << std::setprecision(3) << rad2deg(w * sim.time()) << " of "
           << kReposeEndDeg << " degrees, "
           << format_hms(std::chrono::duration<double>(shown - t0).count()) << " elapsed"
           << std::endl;
    }
  }
  sim.check_health();
  if (angles.size() < 3)
    throw RunError(
        "protocol.repose = 'measured': no free surface was found while the bed turned (" +
        std::to_string(angles.size()) +
        " samples); give the tilt in degrees, e.g. protocol.repose = 27");
  ReposeMeasurement m;
  m.samples = static_cast<int>(angles.size());
  for (double a : angles) m.mean_deg += a / m.samples;
  for (double a : angles) m.sd_deg += (a - m.mean_deg) * (a - m.mean_deg) / (m.samples - 1);
  m.sd_deg = std::sqrt(m.sd_deg);
  if (!(m.mean_deg > 0 && m.mean_deg < 89))
    throw RunError("protocol.repose = 'measured' found " + std::to_string(m.mean_deg) +
                   " degrees, outside [0, 89]; give the tilt in degrees");
  if (log)
    *log << "[repose] beta = " << std::setprecision(4) << m.mean_deg << " degrees (mean of "
         << m.samples << " samples, SD " << std::setprecision(2) << m.sd_deg << "; "
         << format_hms(std::chrono::duration<double>(Clock::now() - t0).count()) << " wall)"
         << std::endl;
  return m;
}

std::string repose_key(const Scene& s) {
  std::ostringstream os;
  os.precision(17);
  if (s.bed_file.empty())
    os << io::bed_key(s);
  else
    os << "bed_file=" << fs::absolute(s.bed_file).string();
  os << ";omega=" << s.omega() << ";law=" << s.law;
  for (const auto& [key, value] : s.law_values)  // every law's keys: the scene's own among them
    os << ";" << key << "=" << value;
  os << ";repose_code=" << kReposeCodeVersion;
  return os.str();
}

// The two files of one measurement: its value (.h5) and its turn so far (.turn.h5).
static std::string repose_stem(const Scene& s) {
  return s.bed_cache + "/repose_" + hex16(fnv1a64(repose_key(s)));
}

std::string repose_cache_path(const Scene& s) { return repose_stem(s) + ".h5"; }

std::string repose_turn_path(const Scene& s) { return repose_stem(s) + ".turn.h5"; }

namespace {

// The tilt a checkpoint's run used (NaN if its scene does not say).
double repose_of_checkpoint(const std::string& path) {
  if (!fs::exists(path)) return std::nan("");
  io::H5File f(path, io::H5File::Mode::Read);
  const Scene old = parse_scene(f.attr_string("/", "scene"), {}, "checkpoint " + path);
  return old.repose.known ? old.repose.deg : std::nan("");
}

// The cached value for this scene (NaN if none, or if the file is for another key).
double cached_repose(const std::string& path, const std::string& key) {
  if (!fs::exists(path)) return std::nan("");
  io::H5File f(path, io::H5File::Mode::Read);
  if (f.attr_string("/", "repose_key") != key) return std::nan("");
  return f.attr_double("/", "repose_deg");
}

void write_cached_repose(const std::string& path, const Scene& scene, const ReposeMeasurement& m) {
  fs::create_directories(fs::path(path).parent_path());
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  f.set_attr("/", "kind", std::string("tumble repose"));
  f.set_attr("/", "repose_key", repose_key(scene));
  f.set_attr("/", "repose_deg", m.mean_deg);
  f.set_attr("/", "sd_deg", m.sd_deg);
  f.set_attr("/", "samples", static_cast<std::int64_t>(m.samples));
  f.set_attr("/", "from_deg", kReposeSpinUpDeg);
  f.set_attr("/", "to_deg", kReposeEndDeg);
  io::write_provenance(f, scene);
  out.commit();
}

}  // namespace

Scene with_repose_resolved(const Scene& scene, const std::string& checkpoint, std::ostream* log,
                           MPI_Comm comm, const std::function<void()>& between_blocks) {
  if (!scene.repose_pending()) return scene;
  const std::string cache = repose_cache_path(scene);
  double deg = std::nan("");
  std::string source;
  // Rank 0 reads the files for all, and its error (a damaged cache) is every rank's: thrown on
  // rank 0 alone, it left the others of a campaign's group in the broadcast below for ever.
  on_rank_0_agreed(comm, [&] {
    if (!checkpoint.empty()) {
      deg = repose_of_checkpoint(checkpoint);
      source = "from the checkpoint " + checkpoint;
    }
    if (!std::isfinite(deg)) {
      deg = cached_repose(cache, repose_key(scene));
      source = "cached in " + cache;
    }
  });
  if (size_of(comm) > 1) MPI_Bcast(&deg, 1, MPI_DOUBLE, 0, comm);
  if (std::isfinite(deg)) {
    if (log)
      *log << "[repose] beta = " << std::setprecision(6) << deg << " degrees (measured, " << source
           << ")" << std::endl;
  } else {
    const std::string turn = repose_turn_path(scene);
    const ReposeMeasurement m = measure_repose(
        scene, [&] { return settled_bed(scene, log, nullptr, comm, between_blocks); }, turn, log,
        comm, between_blocks);
    deg = m.mean_deg;
    // (Its end is the barrier the others wait at until the cache is written; a full disk is
    // every rank's error.)
    on_rank_0_agreed(comm, [&] {
      write_cached_repose(cache, scene, m);
      fs::remove(turn);  // (none if the turn was never kept)
      if (log) *log << "[repose] saved in " << cache << std::endl;
    });
  }
  Scene resolved = scene;
  set_measured_repose(resolved, deg);
  return resolved;
}

}  // namespace tumble
