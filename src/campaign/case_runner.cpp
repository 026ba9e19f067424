#include "campaign/case_runner.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>

#include "base/error.hpp"
#include "base/hash.hpp"
#include "campaign/collect_plan.hpp"
#include "campaign/cylinder_fields.hpp"
#include "campaign/field_collector.hpp"
#include "campaign/json_line.hpp"
#include "campaign/manifest.hpp"
#include "engine/simulation.hpp"
#include "h5/hdf5_file.hpp"
#include "io/bed_io.hpp"
#include "run/realization.hpp"
#include "run/time_limit_observer.hpp"

namespace tumble::campaign {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {
long long checkpoint_step(const std::string& path) {
  io::H5File f(path, io::H5File::Mode::Read);
  return static_cast<long long>(f.attr_int64("/", "step"));
}

// Settle the case's bed into the shared cache when it is not there yet, so that every attempt of
// every case, fresh or repeated, starts from the same bytes on disk (the run then reads it back).
// A bed already cached, or a bed file, is left for the run to read once.
void ensure_bed_on_disk(const Scene& scene, std::ostream& log) {
  if (scene.bed_file.empty() && !fs::exists(io::bed_cache_path(scene)))
    (void)settled_bed(scene, &log);
}
}  // namespace

std::string case_output(const std::string& id) { return "cases/" + id; }
std::string case_dir(const std::string& dir, const std::string& id) {
  return dir + "/" + case_output(id);
}
std::string fields_path(const std::string& dir, const std::string& id) {
  return case_dir(dir, id) + "/fields.h5";
}

// A cylinder case: the run itself samples S_a, S_r and the band count (and keeps them in its
// checkpoints, so a resumed case ends with the whole series); the fields file is written from
// the run's result. Failures propagate to run_case's handlers.
void run_cylinder_case(const CaseContext& ctx, const CaseTask& task, const Case& c,
                       const Scene& scene, const std::string& dir, std::ofstream& log,
                       Clock::time_point t0, CaseOutcome& out) {
  const std::string ckpt = dir + "/checkpoint.h5";
  if (fs::exists(ckpt)) {
    out.resumed_from_step = checkpoint_step(ckpt);
    log << "[case] resuming from " << ckpt << " at step " << out.resumed_from_step << std::endl;
  } else {
    ensure_bed_on_disk(scene, log);
  }
  RunOptions ro;
  ro.resume = true;
  ro.write_snapshots = ctx.spec->snapshots;
  ro.log = &log;
  TimeLimitObserver time_limit(t0, c.time_limit);
  if (c.time_limit > 0) ro.observers.push_back(&time_limit);
  const RunResult res = run_realization(scene, ro);
  FieldsMeta meta{c.id,      c.point_id, c.params_text, ctx.spec->tier, scene_to_text(scene),
                  c.replica, task.seed};
  const std::string fields = fields_path(ctx.campaign_dir, c.id);
  write_cylinder_fields(fields, meta, ctx.spec->collect, res.series.cylinder);
  out.checksum = file_checksum(fields);
  out.ok = true;
}

CaseOutcome run_case(const CaseContext& ctx, const CaseTask& task) {
  const CampaignSpec& spec = *ctx.spec;
  const Case& c = ctx.expansion->cases.at(task.case_index);
  const std::string dir = case_dir(ctx.campaign_dir, c.id);
  CaseOutcome out;
  out.start = utc_now();
  const auto t0 = Clock::now();
  std::ofstream log;
  try {
    if (task.fresh) fs::remove_all(dir);
    fs::create_directories(dir);
    log.open(dir + "/log.txt", std::ios::app);
    log << "[case] " << c.id << " (" << c.params_text << ", replica " << c.replica << ") attempt "
        << task.attempt << ", seed " << task.seed << ", started " << out.start << std::endl;
    if (!c.scene_error.empty()) throw InputError(c.scene_error);
    const Scene scene = case_scene(spec, c, dir, ctx.bed_cache, task.seed);
    const CollectPlan plan = make_collect_plan(spec.collect, scene);
    if (scene.cylinder()) {
      run_cylinder_case(ctx, task, c, scene, dir, log, t0, out);
    } else {
      FieldCollector collector(plan, dir + "/state.h5");

      // Resume only from a checkpoint that the collector's saved state is not behind: the state is
      // written after each sample, before the checkpoint of that step, so this always holds unless
      // files were removed by hand; then start the case afresh.
      const std::string ckpt = dir + "/checkpoint.h5";
      if (fs::exists(ckpt)) {
        const long long step = checkpoint_step(ckpt);
        const bool loaded = collector.load();
        if (loaded && (collector.finished() || step < collector.next_sample_step())) {
          out.resumed_from_step = step;
          log << "[case] resuming from " << ckpt << " at step " << step << "; collector at sample "
              << collector.next_sample() << std::endl;
        } else {
          log << "[case] checkpoint and collector state disagree; starting afresh" << std::endl;
          fs::remove(ckpt);
          collector = FieldCollector(plan, dir + "/state.h5");
        }
      }
      if (out.resumed_from_step == 0) {
        fs::remove(dir + "/state.h5");
        ensure_bed_on_disk(scene, log);
      }

      RunOptions ro;
      ro.resume = true;  // uses DIR/cases/<id>/checkpoint.h5 when it exists
      ro.write_snapshots = spec.snapshots;
      ro.log = &log;
      ro.observers.push_back(&collector);
      TimeLimitObserver time_limit(t0, c.time_limit);
      if (c.time_limit > 0) ro.observers.push_back(&time_limit);
      (void)run_realization(scene, ro);
      if (!collector.finished())
        throw RunError("the run ended before the collector's last sample (" +
                       std::to_string(collector.next_sample()) + ")");
      FieldsMeta meta{c.id,      c.point_id, c.params_text, spec.tier, scene_to_text(scene),
                      c.replica, task.seed};
      const std::string fields = fields_path(ctx.campaign_dir, c.id);
      collector.write_fields(fields, meta);
      out.checksum = file_checksum(fields);
      out.ok = true;
    }
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
  out.end = utc_now();
  out.wall = std::chrono::duration<double>(Clock::now() - t0).count();
  if (log.is_open())
    log << "[case] " << (out.ok ? "done" : "failed (" + out.failure + "): " + out.diagnostic)
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
  o.resumed_from_step = static_cast<long long>(j["resumed_from_step"].number);
  return true;
}

}  // namespace tumble::campaign
