#include "run/repose_measure.hpp"

#include <algorithm>
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
#include "run/made_on_ranks.hpp"
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
  std::vector<TurnSample> samples;
};

// A turn's samples as its file keeps them (three numbers each), and back.
std::vector<double> flat(const std::vector<TurnSample>& samples) {
  std::vector<double> out;
  out.reserve(3 * samples.size());
  for (const TurnSample& t : samples) out.insert(out.end(), {t.rotation_deg, t.slope_deg, t.speed});
  return out;
}

std::vector<TurnSample> unflat(const std::vector<double>& numbers) {
  if (numbers.size() % 3 != 0)
    throw InputError("its measure/samples do not come in threes (rotation, slope, speed)");
  std::vector<TurnSample> out(numbers.size() / 3);
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = {numbers[3 * k], numbers[3 * k + 1], numbers[3 * k + 2]};
  return out;
}

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
    turn.samples = unflat(c.measure_samples);
  } catch (const std::runtime_error& e) {  // (every rank alike: the reads agree their errors)
    if (log)
      *log << "[repose] not going on from " << path << ": " << e.what()
           << "; turning from the start" << std::endl;
    return false;
  }
  if (log)
    *log << "[repose] going on from " << path << " at " << std::setprecision(3)
         << rad2deg(dynamic.omega() * turn.sim->time()) << " of " << kReposeEndDeg << " degrees ("
         << turn.samples.size() << " samples)" << std::endl;
  return true;
}

}  // namespace

ReposeMeasurement measure_repose(const Scene& scene, const std::function<Particles()>& bed,
                                 const std::string& turn_path, std::ostream* log, MPI_Comm comm,
                                 const std::function<void()>& between_blocks) {
  const double w = scene.omega();
  const double dt = scene.time_step();
  const auto steps_per_degree = std::max<std::int64_t>(1, std::llround(deg2rad(1.0) / w / dt));
  const auto last = static_cast<std::int64_t>(kReposeEndDeg) * steps_per_degree;
  // The dynamic bed's angle, whatever fidelity.bulk: β is cached by a key that does not hold it.
  Scene dynamic = scene;
  dynamic.bulk = Bulk::dynamic;
  Turn turn;
  if (!resume_turn(dynamic, turn_path, turn, log, comm)) {
    if (log)
      *log << "[repose] measuring beta and the creep onset: turning the settled bed "
           << kReposeEndDeg << " degrees about z at " << std::setprecision(4) << w << " rad/s ("
           << last << " steps), sampling the free surface once a degree (beta from "
           << kReposeSpinUpDeg << " degrees)" << std::endl;
    turn.sim = std::make_unique<Simulation>(dynamic, share_of(bed(), comm),
                                            geometry::Protocol::single_axis('z', w), 0, 0, comm);
    turn.sim->compute_forces();
  }
  Simulation& sim = *turn.sim;
  std::vector<TurnSample>& samples = turn.samples;
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
    if (k % steps_per_degree == 0) {  // (every degree: the creep onset comes before β's samples)
      const Particles all = sim.gather_all();  // collective
      const analysis::FlowProfile f = analysis::flow_profile(all, all.size(), frame);
      if (std::isfinite(f.repose_deg) && std::isfinite(f.surface_speed))
        samples.push_back(
            {static_cast<double>(k / steps_per_degree), f.repose_deg, f.surface_speed});
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
      io::write_checkpoint(turn_path, sim, dynamic, {}, {}, {}, flat(samples));  // collective
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
  const ReposeMeasurement m = repose_from_samples(samples, w * scene.radius);
  if (log)
    *log << "[repose] beta = " << std::setprecision(4) << m.mean_deg << " degrees (mean of "
         << m.samples << " samples, SD " << std::setprecision(2) << m.sd_deg << "; "
         << format_hms(std::chrono::duration<double>(Clock::now() - t0).count())
         << " wall); the surface crept from a slope of " << std::setprecision(3)
         << m.creep_onset_deg << " degrees" << std::endl;
  return m;
}

double creep_onset_slope(const std::vector<TurnSample>& samples, double creep_speed) {
  std::size_t run = 0;  // samples in a row, on consecutive degrees, above the creep speed
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const bool next_degree = k > 0 && samples[k].rotation_deg == samples[k - 1].rotation_deg + 1;
    run = samples[k].speed > creep_speed ? (next_degree ? run + 1 : 1) : 0;
    if (run == static_cast<std::size_t>(kCreepSamples))
      return samples[k + 1 - kCreepSamples].slope_deg;
  }
  return std::nan("");
}

ReposeMeasurement repose_from_samples(const std::vector<TurnSample>& samples, double wall_speed) {
  std::vector<double> angles;
  for (const TurnSample& t : samples)
    if (t.rotation_deg >= kReposeSpinUpDeg) angles.push_back(t.slope_deg);
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
  m.creep_onset_deg = creep_onset_slope(samples, kCreepSpeed * wall_speed);
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

// The two numbers a turn gives, as a run uses them: β and the still slope (NaN: not known, or
// for the still slope also a bed that never crept); `turned`: they come from a turn of this bed.
struct BedTurnValues {
  double repose_deg = std::nan("");
  double still_slope_deg = std::nan("");
  bool turned = false;
};

// The numbers a checkpoint's run used (NaN where its scene does not say).
BedTurnValues values_of_checkpoint(const std::string& path) {
  BedTurnValues v;
  if (!fs::exists(path)) return v;
  io::H5File f(path, io::H5File::Mode::Read);
  const Scene old = parse_scene(f.attr_string("/", "scene"), {}, "checkpoint " + path);
  if (old.repose.known) v.repose_deg = old.repose.deg;
  if (old.bulk_still_slope.known) v.still_slope_deg = old.bulk_still_slope.deg;
  return v;
}

// The still slope a creep onset gives: kStillSlopeMargin below it, 0 (off) for a bed that creeps
// below the margin itself; NaN for a bed that never crept.
double still_slope_of(double creep_onset_deg) {
  return std::isfinite(creep_onset_deg) ? std::max(0.0, creep_onset_deg - kStillSlopeMargin)
                                        : std::nan("");
}

// The cached values for this scene (both NaN if none, or if the file is for another key).
BedTurnValues cached_values(const std::string& path, const std::string& key) {
  BedTurnValues v;
  if (!fs::exists(path)) return v;
  io::H5File f(path, io::H5File::Mode::Read);
  if (f.attr_string("/", "repose_key") != key) return v;
  v.turned = true;
  v.repose_deg = f.attr_double("/", "repose_deg");
  v.still_slope_deg = still_slope_of(f.attr_double("/", "creep_onset_deg"));
  return v;
}

// The rank count a cached turn was made on; 0 where the file does not say (written before the
// count was kept).
long long turned_on_ranks(const std::string& path) {
  io::H5File f(path, io::H5File::Mode::Read);
  return f.has_attr("/", "turned_on_ranks") ? f.attr_int64("/", "turned_on_ranks") : 0;
}

// `turned_on_ranks` is kept with the values: a turn on another rank count reads another β and
// onset in round-off (the cache's name does not hold the count, as the bed's does not).
void write_cached_values(const std::string& path, const Scene& scene, const ReposeMeasurement& m,
                         int turned_on_ranks) {
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
  f.set_attr("/", "creep_onset_deg", m.creep_onset_deg);  // NaN: the surface never crept
  f.set_attr("/", "creep_speed_wall", kCreepSpeed);
  f.set_attr("/", "turned_on_ranks", static_cast<std::int64_t>(turned_on_ranks));
  io::write_provenance(f, scene);
  out.commit();
}

}  // namespace

Scene with_bed_turn_resolved(const Scene& scene, const std::string& checkpoint, std::ostream* log,
                             MPI_Comm comm, const std::function<void()>& between_blocks) {
  if (!scene.bed_turn_pending()) return scene;
  const std::string cache = repose_cache_path(scene);
  BedTurnValues v;
  std::string source;
  // Rank 0 reads the files for all, and its error (a damaged cache) is every rank's: thrown on
  // rank 0 alone, it left the others of a campaign's group in the broadcast below for ever.
  const auto enough = [&] {
    return (!scene.repose_pending() || std::isfinite(v.repose_deg)) &&
           (!scene.still_slope_pending() || std::isfinite(v.still_slope_deg));
  };
  on_rank_0_agreed(comm, [&] {
    if (!checkpoint.empty()) {
      v = values_of_checkpoint(checkpoint);
      v.turned = enough();
      source = "from the checkpoint " + checkpoint;
    }
    if (!v.turned) {
      v = cached_values(cache, repose_key(scene));
      source = "cached in " + cache +
               (v.turned ? made_on_ranks("turned", turned_on_ranks(cache), size_of(comm),
                                         "a turn here would read another value in round-off")
                         : "");
    }
  });
  // (A cached turn in which the surface never crept is final too: turning again gives the same.)
  double numbers[3] = {v.repose_deg, v.still_slope_deg, v.turned ? 1.0 : 0.0};
  if (size_of(comm) > 1) MPI_Bcast(numbers, 3, MPI_DOUBLE, 0, comm);
  v = {numbers[0], numbers[1], numbers[2] != 0};
  if (!v.turned) {
    const std::string turn = repose_turn_path(scene);
    const ReposeMeasurement m = measure_repose(
        scene, [&] { return settled_bed(scene, log, nullptr, comm, between_blocks); }, turn, log,
        comm, between_blocks);
    v = {m.mean_deg, still_slope_of(m.creep_onset_deg), true};
    source = "by this run's turn above";
    // (Its end is the barrier the others wait at until the cache is written; a full disk is
    // every rank's error.)
    on_rank_0_agreed(comm, [&] {
      write_cached_values(cache, scene, m, size_of(comm));
      fs::remove(turn);  // (none if the turn was never kept)
      if (log) *log << "[repose] saved in " << cache << std::endl;
    });
  }
  Scene resolved = scene;
  if (scene.repose_pending()) {
    set_measured_repose(resolved, v.repose_deg);
    if (log)
      *log << "[repose] beta = " << std::setprecision(6) << v.repose_deg << " degrees (measured, "
           << source << ")" << std::endl;
  }
  if (scene.still_slope_pending()) {
    if (!std::isfinite(v.still_slope_deg))
      throw RunError(
          "fidelity.bulk_still_slope = 'measured': the bed's surface never crept while it turned " +
          short_number(kReposeEndDeg) + " degrees from rest (" + source +
          "); give the slope in degrees, in [0, 89] (0: off)");
    set_measured_still_slope(resolved, v.still_slope_deg);
    if (log)
      *log << "[repose] fidelity.bulk_still_slope = " << std::setprecision(4) << v.still_slope_deg
           << " degrees (" << kStillSlopeMargin << " below the slope where the surface crept; "
           << source << ")" << std::endl;
  }
  return resolved;
}

}  // namespace tumble
