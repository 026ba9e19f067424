#include "campaign/case_runner.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <ostream>

#include "base/agreed_input.hpp"
#include "base/comm.hpp"
#include "base/error.hpp"
#include "base/hash.hpp"
#include "base/stop_request.hpp"
#include "campaign/case_collector.hpp"
#include "campaign/collect_plan.hpp"
#include "campaign/fault_injection.hpp"
#include "campaign/json_line.hpp"
#include "campaign/manifest.hpp"
#include "engine/simulation.hpp"
#include "h5/hdf5_file.hpp"
#include "io/bed_io.hpp"
#include "run/realization.hpp"
#include "run/repose_measure.hpp"
#include "run/run_state.hpp"
#include "run/time_limit_observer.hpp"
#include "scene/scene.hpp"

namespace tumble::campaign {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {
long long checkpoint_step(const std::string& path) {
  io::H5File f(path, io::H5File::Mode::Read);
  return static_cast<long long>(f.attr_int64("/", "step"));
}

// Runs `work` on the group's rank 0 and ends every rank of the group the same way: if it threw,
// every rank throws an error of the same kind with its message (a rank that went on alone would
// wait forever in the run's first collective).
template <class Work>
void on_leader(MPI_Comm group, Work&& work) {
  if (size_of(group) == 1) {
    work();
    return;
  }
  int kind = 0;  // 0: fine, 1: bad input, 2: run-time failure
  std::string what;
  if (rank_in(group) == 0) {
    try {
      work();
    } catch (const InputError& e) {
      kind = 1;
      what = e.what();
    } catch (const std::exception& e) {
      kind = 2;
      what = e.what();
    }
  }
  int head[2] = {kind, static_cast<int>(what.size())};
  MPI_Bcast(head, 2, MPI_INT, 0, group);
  if (head[0] == 0) return;
  what.resize(static_cast<std::size_t>(head[1]));
  MPI_Bcast(what.data(), head[1], MPI_CHAR, 0, group);
  if (head[0] == 1) throw InputError(what);
  throw RunError(what);
}

// The step to resume from (0: start afresh). A sphere case resumes only from a checkpoint that
// its collector's saved state is not behind: the state is written after each sample, before the
// checkpoint of that step, so this always holds unless files were removed by hand; then the
// checkpoint goes and the case starts afresh.
long long resume_point(CaseCollector& collector, const std::string& dir, std::ostream& log) {
  const std::string ckpt = dir + "/checkpoint.h5";
  if (!fs::exists(ckpt)) return 0;
  const long long step = checkpoint_step(ckpt);
  if (collector.resumable_from(step)) {
    log << "[case] resuming from " << ckpt << " at step " << step << std::endl;
    return step;
  }
  log << "[case] checkpoint and collector state disagree; starting afresh" << std::endl;
  fs::remove(ckpt);
  return 0;
}

// The dispatcher's poll, called after every step of a case that the dispatching rank computes.
class PollObserver : public Observer {
 public:
  explicit PollObserver(const std::function<void()>& poll) : poll_(poll) {}
  void after_step(RunState&) override { poll_(); }

 private:
  const std::function<void()>& poll_;
};
}  // namespace

std::string case_output(const std::string& id) { return "cases/" + id; }
std::string case_dir(const std::string& dir, const std::string& id) {
  return dir + "/" + case_output(id);
}
std::string fields_path(const std::string& dir, const std::string& id) {
  return case_dir(dir, id) + "/fields.h5";
}

namespace {
// The bed seed of the run checkpoint in a case directory (its scene's fill.seed); 0 where there
// is none or it does not read (the run's own resume then decides, and says why).
std::int64_t checkpoint_seed(const std::string& dir) {
  const std::string path = dir + "/checkpoint.h5";
  try {
    if (!fs::exists(path)) return 0;
    io::H5File f(path, io::H5File::Mode::Read);
    return parse_scene(f.attr_string("/", "scene"), {}, "checkpoint " + path).seed;
  } catch (const std::exception&) {
    return 0;
  }
}
}  // namespace

CaseOutcome run_case(const CaseContext& ctx, const CaseTask& task) {
  const CampaignSpec& spec = *ctx.spec;
  const Case& c = ctx.expansion->cases.at(task.case_index);
  const std::string dir = case_dir(ctx.campaign_dir, c.id);
  const MPI_Comm group = ctx.group;
  const int ranks = size_of(group);
  const bool lead = rank_in(group) == 0;
  CaseOutcome out;
  out.start = utc_now();
  const auto t0 = Clock::now();
  // A stop request that came after this case was handed to its group and before it began: it
  // does not begin (the rerun starts it). The group agrees, as its ranks may have seen it apart.
  if (const int signal = agreed_stop_signal(group); signal != 0) {
    out.failure = "stopped";
    out.diagnostic = std::string(kNotBegun) + ": " + signal_name(signal) + " came first";
    out.end = utc_now();
    return out;
  }
  std::ofstream log;  // the group's rank 0 only
  try {
    on_leader(group, [&] {
      // A checkpoint of another seed is an earlier attempt's (retry_seed = "new": a retry
      // handed out, then stopped or killed before it began, is rerun as the same attempt, and
      // went on from the failed attempt's checkpoint under the new seed's name).
      const std::int64_t kept = checkpoint_seed(dir);
      const bool other_seed = !task.fresh && kept != 0 && kept != task.seed;
      if (task.fresh || other_seed) fs::remove_all(dir);
      fs::create_directories(dir);
      log.open(dir + "/log.txt", std::ios::app);
      log << "[case] " << c.id << " (" << c.params_text << ", replica " << c.replica << ") attempt "
          << task.attempt << ", seed " << task.seed << ", on " << ranks << " rank"
          << (ranks > 1 ? "s" : "") << ", started " << out.start << std::endl;
      if (other_seed)
        log << "[case] the checkpoint there was of seed " << kept
            << " (an earlier attempt's): removed with its files; this attempt starts afresh"
            << std::endl;
    });
    if (!c.scene_error.empty()) throw InputError(c.scene_error);
    if (lead && ctx.progress) ctx.progress({task.case_index, task.attempt, true});  // bed, β
    // The attempt's time limit holds while it settles its bed and measures β too (hours on a
    // paper-scale bed): checked between blocks of steps, which every rank of the group reaches
    // together. (Before, an attempt overran its limit by its whole preparation and then failed
    // at the protocol's first step.)
    const std::function<void()> between_blocks = [&] {
      if (ctx.poll) ctx.poll();
      if (c.time_limit > 0)
        check_time_limit(t0, c.time_limit, group, "while settling the bed or measuring beta");
    };
    // β = "measured" is filled in first: the collection plan counts steps per iteration.
    const Scene scene = with_bed_turn_resolved(case_scene(spec, c, dir, ctx.bed_cache, task.seed),
                                               dir + "/checkpoint.h5", lead ? &log : nullptr, group,
                                               between_blocks);
    const CollectPlan plan = make_collect_plan(spec.collect, scene);
    std::unique_ptr<CaseCollector> collector = make_case_collector(plan, scene, dir);

    // Rank 0 decides from the files whether to resume, and whether the bed must be settled (so
    // that every attempt, fresh or repeated, starts from the same bytes in the bed cache).
    long long decision[2] = {0, 0};  // resume step, settle
    on_leader(group, [&] {
      decision[0] = resume_point(*collector, dir, log);
      if (decision[0] == 0) {
        collector->discard_saved();
        decision[1] = scene.bed_file.empty() && !fs::exists(io::bed_cache_path(scene)) ? 1 : 0;
      }
    });
    if (ranks > 1) MPI_Bcast(decision, 2, MPI_LONG_LONG, 0, group);
    out.resumed_from_step = decision[0];
    collector->share(group);
    if (decision[1])
      (void)settled_bed(scene, lead ? &log : nullptr, nullptr, group, between_blocks);

    RunOptions ro;
    ro.comm = group;
    ro.resume = true;  // uses DIR/cases/<id>/checkpoint.h5 when it exists
    ro.write_snapshots = spec.snapshots;
    ro.log = lead ? &log : nullptr;
    ro.observers.push_back(collector.get());
    TimeLimitObserver time_limit(t0, c.time_limit);
    if (c.time_limit > 0) ro.observers.push_back(&time_limit);
    PollObserver poll(ctx.poll);
    if (ctx.poll) ro.observers.push_back(&poll);
    if (lead && ctx.progress)  // when the protocol loop begins, then with each progress line
      ro.on_progress = [&](const RunState& s) {
        ctx.progress({task.case_index, task.attempt, false, s.first_step, s.sim.step_count(),
                      s.total_steps,
                      std::chrono::duration<double>(Clock::now() - s.started).count()});
      };
    const std::unique_ptr<Observer> fault = fault_injection_for(c.id);
    if (fault) ro.observers.push_back(fault.get());
    out.protocol_wall = run_realization(scene, ro).wall_seconds;

    on_leader(group, [&] {
      const std::string missing = collector->missing();
      if (!missing.empty()) throw RunError(missing);
      FieldsMeta meta{c.id,      c.point_id, c.params_text, spec.tier, scene_to_text(scene),
                      c.replica, task.seed};
      const std::string fields = fields_path(ctx.campaign_dir, c.id);
      collector->write_fields(fields, meta);
      out.checksum = file_checksum(fields);
    });
    out.ok = true;
  } catch (const StopRequest& e) {
    out.failure = "stopped";
    out.diagnostic = e.what();
  } catch (const TimeLimitError& e) {
    out.failure = "time_limit";
    out.diagnostic = e.what();
    out.retryable = true;
  } catch (const InputError& e) {
    out.failure = "input";
    out.diagnostic = e.what();
    out.retryable = false;
  } catch (const RunError& e) {
    out.failure = "run";
    out.diagnostic = e.what();
    out.retryable = true;
  } catch (const std::exception& e) {
    out.failure = "exception";
    out.diagnostic = e.what();
    out.retryable = true;
  }
  error_said();  // (a failure agreed over the group silenced std::cerr on its other ranks)
  out.end = utc_now();
  out.wall = std::chrono::duration<double>(Clock::now() - t0).count();
  if (log.is_open())
    log << "[case] "
        << (out.ok                     ? "done"
            : out.failure == "stopped" ? out.diagnostic
                                       : "failed (" + out.failure + "): " + out.diagnostic)
        << " after " << out.wall << " s" << std::endl;
  return out;
}

std::string encode(const CaseTask& t, const CaseOutcome& o) {
  JsonWriter w;
  w.add("case_index", static_cast<long long>(t.case_index))
      .add("attempt", t.attempt)
      .add("seed", static_cast<long long>(t.seed))
      .add("fresh", t.fresh)
      .add("ok", o.ok)
      .add("failure", o.failure)
      .add("diagnostic", o.diagnostic)
      .add("retryable", o.retryable)
      .add("checksum", o.checksum)
      .add("start", o.start)
      .add("end", o.end)
      .add("wall", o.wall)
      .add("protocol_wall", o.protocol_wall)
      .add("resumed_from_step", o.resumed_from_step);
  return w.str();
}

bool decode(const std::string& line, CaseTask& t, CaseOutcome& o) {
  JsonObject j;
  if (!parse_json_line(line, j)) return false;
  t.case_index = static_cast<std::size_t>(j["case_index"].number);
  t.attempt = static_cast<int>(j["attempt"].number);
  t.seed = static_cast<std::int64_t>(std::stoll(j["seed"].text));
  t.fresh = j["fresh"].number != 0;
  o.ok = j["ok"].number != 0;
  o.failure = j["failure"].text;
  o.diagnostic = j["diagnostic"].text;
  o.retryable = j["retryable"].number != 0;
  o.checksum = j["checksum"].text;
  o.start = j["start"].text;
  o.end = j["end"].text;
  o.wall = j["wall"].number;
  o.protocol_wall = j["protocol_wall"].number;
  o.resumed_from_step = static_cast<long long>(j["resumed_from_step"].number);
  return true;
}

std::string encode(const CaseProgress& p) {
  JsonWriter w;
  w.add("case_index", static_cast<long long>(p.case_index))
      .add("attempt", p.attempt)
      .add("preparing", p.preparing ? 1 : 0)
      .add("first_step", static_cast<long long>(p.first_step))
      .add("step", static_cast<long long>(p.step))
      .add("total_steps", static_cast<long long>(p.total_steps))
      .add("seconds", p.seconds);
  return w.str();
}

bool decode(const std::string& line, CaseProgress& p) {
  JsonObject j;
  if (!parse_json_line(line, j)) return false;
  p.case_index = static_cast<std::size_t>(j["case_index"].number);
  p.attempt = static_cast<int>(j["attempt"].number);
  p.preparing = j["preparing"].number != 0;
  p.first_step = static_cast<std::int64_t>(j["first_step"].number);
  p.step = static_cast<std::int64_t>(j["step"].number);
  p.total_steps = static_cast<std::int64_t>(j["total_steps"].number);
  p.seconds = j["seconds"].number;
  return true;
}

}  // namespace tumble::campaign
