#include "campaign/campaign_run.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>
#include <utility>

#include "base/agreed_input.hpp"
#include "base/comm.hpp"
#include "base/error.hpp"
#include "base/exit_codes.hpp"
#include "base/hash.hpp"
#include "base/stop_request.hpp"
#include "base/sync_to_disk.hpp"
#include "base/usable_directory.hpp"
#include "base/version.hpp"
#include "campaign/campaign_spec.hpp"
#include "campaign/case_runner.hpp"
#include "campaign/directory_lock.hpp"
#include "campaign/ensemble.hpp"
#include "campaign/expand.hpp"
#include "campaign/field_collector.hpp"
#include "campaign/manifest.hpp"
#include "campaign/scheduler.hpp"
#include "h5/hdf5_file.hpp"
#include "run/repose_measure.hpp"
#include "scene/scene.hpp"

namespace tumble::campaign {
namespace fs = std::filesystem;

void parse_slice(const std::string& text, int& i, int& n) {
  const auto slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no /");
    // (digits only: std::stoi skips leading blanks, so " 1/2" passed where "1/2 " did not)
    if (text.find_first_not_of("0123456789/") != std::string::npos)
      throw std::invalid_argument("not digits");
    std::size_t a = 0, b = 0;
    i = std::stoi(text.substr(0, slash), &a);
    n = std::stoi(text.substr(slash + 1), &b);
    if (a != slash || b != text.size() - slash - 1) throw std::invalid_argument("junk");
  } catch (const std::exception&) {
    throw InputError("campaign error: --slice '" + text + "' must be i/n, e.g. 3/16");
  }
  if (n < 1 || i < 1 || i > n)
    throw InputError("campaign error: --slice " + text + ": need 1 <= i <= n");
}

int parse_ranks_per_case(const std::string& text) {
  std::size_t used = 0;
  long long k = 0;
  try {
    k = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || k < 1 || k > 1000000)
    throw InputError("campaign error: --ranks-per-case '" + text +
                     "' must be an integer from 1 to 1000000 (ranks per case)");
  return static_cast<int>(k);
}

std::vector<CaseTableRow> case_table(const std::string& dir) {
  std::vector<CaseTableRow> rows;
  std::ifstream in(dir + "/cases.tsv");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    // index, case, point, replica, cost, params, scene_error (tab-separated; see cases_table)
    std::vector<std::string> cols;
    std::istringstream fields(line);
    for (std::string col; std::getline(fields, col, '\t');) cols.push_back(col);
    CaseTableRow r;
    if (cols.size() > 1) r.id = cols[1];
    if (cols.size() > 2) r.point = cols[2];
    if (cols.size() > 5) r.params = cols[5];
    rows.push_back(r);
  }
  return rows;
}

std::set<std::string> case_table_ids(const std::string& dir) {
  std::set<std::string> ids;
  for (const CaseTableRow& r : case_table(dir)) ids.insert(r.id);
  return ids;
}

std::string partial_path(const std::string& dir, int i, int n) {
  return dir + "/partials/slice_" + std::to_string(i) + "_of_" + std::to_string(n) + ".h5";
}

namespace {

enum class State { Done, Failed, Pending };

struct CaseState {
  State state = State::Pending;
  CaseRecord last;  // latest manifest line (if any)
  bool has_record = false;
  CaseTask next;     // Pending: what to run
  std::string note;  // why it is pending again
};

// Where each case of the slice stands, from the manifests and the files they point to. A case is
// done only if its fields file still has the checksum the manifest recorded.
std::vector<CaseState> classify(const CampaignSpec& spec, const Expansion& e,
                                const std::string& dir, const std::vector<std::size_t>& slice,
                                bool retry_failed, int* torn) {
  const ManifestState ms = read_manifests(dir);
  if (torn) *torn = ms.torn_lines;
  std::vector<CaseState> out;
  for (std::size_t idx : slice) {
    const Case& c = e.cases[idx];
    CaseState s;
    int attempt = 1;
    bool resume_same_attempt = false;
    if (auto it = ms.latest.find(c.id); it != ms.latest.end()) {
      s.last = it->second;
      s.has_record = true;
      const int attempts = ms.attempts.at(c.id);
      if (s.last.status == "done") {
        const std::string f = fields_path(dir, c.id);
        std::string sum;
        try {
          if (fs::exists(f)) sum = file_checksum(f);
        } catch (const std::exception&) {
        }
        if (!sum.empty() && sum == s.last.checksum) {
          s.state = State::Done;
          out.push_back(s);
          continue;
        }
        s.note = sum.empty() ? "its fields file is missing" : "its fields file changed";
        attempt = attempts + 1;
      } else if (s.last.status == "failed") {
        if ((s.last.final_failure || attempts >= spec.max_attempts) && !retry_failed) {
          s.state = State::Failed;
          out.push_back(s);
          continue;
        }
        attempt = attempts + 1;
      } else {  // running when its invocation died: continue the same attempt
        attempt = std::max(1, s.last.attempt);
        resume_same_attempt = true;
        s.note = "interrupted";
      }
    }
    s.next.case_index = idx;
    s.next.attempt = attempt;
    s.next.seed = case_seed(spec, c, attempt);
    s.next.fresh = spec.retry_seed == "new" && attempt > 1 && !resume_same_attempt;
    out.push_back(s);
  }
  return out;
}

// The cases of the slice still to run (or to retry under the policy), from the files.
std::size_t cases_left(const CampaignSpec& spec, const Expansion& e, const std::string& dir,
                       const std::vector<std::size_t>& slice) {
  std::size_t n = 0;
  for (const CaseState& s : classify(spec, e, dir, slice, false, nullptr))
    n += s.state == State::Pending;
  return n;
}

// How far a case's checkpoint is ("checkpoint at step 302049 of 9477915, 3.2%"; "" if it has none
// or it does not read): the step and the resolved scene (its run length, β included) it holds.
std::string checkpoint_progress(const std::string& campaign_dir, const Case& c) {
  const std::string path = case_dir(campaign_dir, c.id) + "/checkpoint.h5";
  try {
    if (!fs::exists(path)) return "";
    io::H5File f(path, io::H5File::Mode::Read);
    const std::int64_t step = f.attr_int64("/", "step");
    const Scene s = parse_scene(f.attr_string("/", "scene"), {}, "checkpoint");
    const std::int64_t total = s.protocol_steps();
    std::ostringstream os;
    os << "checkpoint at step " << step << " of " << total << ", " << std::fixed
       << std::setprecision(1) << 100.0 * static_cast<double>(step) / static_cast<double>(total)
       << "%";
    return os.str();
  } catch (const std::exception&) {
    return "";
  }
}

// How far a case's turn of its settled bed is, when it has no checkpoint yet and a turn is kept
// for its bed ("beta turn kept at 46.6 of 80 degrees"; "" otherwise): a stop in the hours of a
// paper bed's turn keeps it (run/repose_measure.hpp), and the status says so. The one turn reads
// β and the still slope's onset, so the line names what the case waits on.
std::string repose_turn_progress(const CampaignSpec& spec, const Case& c,
                                 const std::string& campaign_dir, const std::string& bed_cache,
                                 std::int64_t seed) {
  try {
    if (!c.scene_error.empty()) return "";
    const Scene s = case_scene(spec, c, case_dir(campaign_dir, c.id), bed_cache, seed);
    const std::string path = repose_turn_path(s);
    if (!s.bed_turn_pending() || !fs::exists(path)) return "";
    io::H5File f(path, io::H5File::Mode::Read);
    std::ostringstream os;
    const char* what = !s.still_slope_pending() ? "beta"
                       : s.repose_pending()     ? "beta and still-slope"
                                                : "still-slope";
    os << what << " turn kept at " << std::fixed << std::setprecision(1)
       << rad2deg(s.omega() * f.attr_double("/", "time")) << " of "
       << static_cast<int>(kReposeEndDeg) << " degrees";
    return os.str();
  } catch (const std::exception&) {
    return "";
  }
}

void write_text_atomically(const std::string& path, const std::string& text) {
  // A write that failed (a full disk) is not renamed: a truncated case table would read as a
  // smaller campaign. Nor is its temporary left behind.
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  std::ofstream o(tmp);
  o << text;
  o.close();
  std::error_code ec;
  if (o.fail()) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + tmp + " (is the disk full?)");
  }
  try {
    sync_to_disk(tmp);
  } catch (const std::exception&) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
  }
}

// `from` copied to `to` through a temporary and a rename: a copy cut short (a full disk, a kill)
// leaves the old `to`, not a truncated one.
void copy_atomically(const std::string& from, const std::string& to) {
  const std::string tmp = to + ".tmp." + std::to_string(::getpid());
  std::error_code ec;
  fs::copy_file(from, tmp, fs::copy_options::overwrite_existing, ec);
  try {
    if (!ec) sync_to_disk(tmp);
  } catch (const std::exception&) {
    fs::remove(tmp, ec);
    throw;
  }
  if (!ec) fs::rename(tmp, to, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error("cannot copy " + from + " to " + to + ": " + ec.message());
  }
}

std::string cases_table(const Expansion& e) {
  std::ostringstream os;
  os << "# index\tcase\tpoint\treplica\tcost\tparams\tscene_error\n";
  for (const auto& c : e.cases)
    os << c.index << "\t" << c.id << "\t" << c.point_id << "\t" << c.replica << "\t" << c.cost
       << "\t" << c.params_text << "\t" << c.scene_error << "\n";
  return os.str();
}

Ensemble build_ensemble(const CampaignSpec& spec, const Expansion& e, const std::string& dir,
                        const std::vector<std::size_t>& slice, const std::vector<CaseState>& states,
                        const std::string& slice_text) {
  Ensemble ens;
  ens.notes["campaign"] = spec.name;
  ens.notes["campaign_file"] = spec.file;
  ens.notes["slice"] = slice_text;
  ens.notes["written_utc"] = utc_now();
  ens.notes["tumble_version"] = kVersion;
  ens.notes["git_hash"] = kGitHash;
  const auto names = field_names(spec.collect);
  // Members are folded in case-id order, so that a result never depends on which rank group
  // finished first: a killed and resumed campaign gives the same bits as an uninterrupted one.
  std::vector<std::size_t> order(slice.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return e.cases[slice[a]].id < e.cases[slice[b]].id;
  });
  std::map<std::string, const Point*> points;
  for (const auto& p : e.points) points[p.id] = &p;
  for (std::size_t k : order) {
    const Case& c = e.cases[slice[k]];
    PointStats& ps = ens.point(*points.at(c.point_id), spec);
    const CaseState& s = states[k];
    if (s.state == State::Done)
      ens.add_case(c.point_id, c.id, fields_path(dir, c.id), names);
    else if (s.state == State::Failed)
      ps.failed.push_back(c.id + ": [" + s.last.failure + ", attempt " +
                          std::to_string(s.last.attempt) + "] " + s.last.diagnostic);
    else
      ps.missing.push_back(c.id);
  }
  return ens;
}

// Why the statistics of a slice whose cases all ended (`path`: the slice's partial, or for the
// whole campaign its ensemble.h5, which `tumble merge` writes too) are not its current result,
// "" if they are: absent, unreadable, or folding other cases than those now done and failed (a
// partial written before the campaign grew and dealt its cases anew, or before a retry). The
// job-array scripts skip a slice whose status is 0: a stale partial was never written again.
std::string statistics_not_current(const std::string& path, const Expansion& e,
                                   const std::vector<std::size_t>& slice,
                                   const std::vector<CaseState>& states) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    return slice.empty() ? "statistics not written (this slice holds no case: more slices than "
                           "cases; one run writes its empty partial, which tumble merge expects)"
                         : "statistics not written (the run that finished the cases was stopped "
                           "or killed before it wrote them)";
  std::set<std::string> done, failed, members, excluded, missing;
  for (std::size_t k = 0; k < slice.size(); ++k)
    if (states[k].state == State::Done)
      done.insert(e.cases[slice[k]].id);
    else if (states[k].state == State::Failed)
      failed.insert(e.cases[slice[k]].id);
  try {
    // (Its ids only: no PETSc, so no MPI, which `--status` does not start: app/main.cpp)
    for (const auto& [id, p] : Ensemble::read(path, false).points) {
      members.insert(p.members.begin(), p.members.end());
      missing.insert(p.missing.begin(), p.missing.end());
      const std::set<std::string> f = p.failed_ids();
      excluded.insert(f.begin(), f.end());
    }
  } catch (const std::exception& x) {
    return "statistics file " + path + " does not read (" + x.what() + ")";
  }
  if (members == done && excluded == failed && missing.empty()) return "";
  std::set<std::string> mine = done, held = members;
  mine.insert(failed.begin(), failed.end());
  held.insert(excluded.begin(), excluded.end());
  held.insert(missing.begin(), missing.end());
  auto count_not_in = [](const std::set<std::string>& a, const std::set<std::string>& b) {
    return std::count_if(a.begin(), a.end(), [&](const std::string& x) { return !b.count(x); });
  };
  std::ostringstream os;
  os << "statistics file " << path << " is not this slice's current result: of the slice's "
     << mine.size() << " ended cases it lacks " << count_not_in(mine, held) << ", it holds "
     << count_not_in(held, mine) << " other cases, and " << missing.size()
     << " without result; done in it " << members.size() << ", now " << done.size()
     << "; failed in it " << excluded.size() << ", now " << failed.size()
     << " (written before the campaign grew and dealt its cases anew, or before a retry)";
  return os.str();
}

// This slice's statistics from the manifests and fields files (not from memory: the result is
// the same whoever ran which case, and however often the campaign was interrupted).
// Returns the number of cases of the slice that are failed or without result.
std::size_t fold_statistics(const CampaignSpec& spec, const Expansion& e, const std::string& dir,
                            const std::vector<std::size_t>& slice, const CampaignOptions& opt,
                            const ScheduleStats& stats, std::ostream& out) {
  const std::string slice_text = std::to_string(opt.slice_i) + "/" + std::to_string(opt.slice_n);
  const auto final_states = classify(spec, e, dir, slice, false, nullptr);
  PetscScope petsc;
  const Ensemble ens = build_ensemble(spec, e, dir, slice, final_states, slice_text);
  const std::string partial = partial_path(dir, opt.slice_i, opt.slice_n);
  const std::string where = opt.slice_n == 1 ? dir + "/ensemble.h5" : partial;
  ens.write(where);
  if (opt.slice_n == 1)  // the whole campaign is its own single partial (for `tumble merge`)
    copy_atomically(where, partial);
  out << "[campaign] finished slice " << slice_text << ": " << ens.member_count() << " done, "
      << ens.failed_count() << " failed (excluded from the ensemble), " << ens.missing_count()
      << " without result; " << stats.cases_run << " attempts run on " << stats.ranks << " rank"
      << (stats.ranks == 1 ? "" : "s") << " in " << std::setprecision(4) << stats.loop_wall
      << " s; ranks idle " << std::setprecision(3) << 100 * stats.overhead()
      << "% of the time (scheduling, ranks no group fits, and the tail once fewer cases than "
         "groups are left)";
  if (stats.local_seconds > 0)
    out << "; rank 0 dispatched for " << std::setprecision(3) << 100 * stats.dispatch_share()
        << "% of its own cases' time (" << stats.polls << " polls between steps)";
  out << std::endl;
  for (const auto& [id, p] : ens.points)
    for (const auto& f : p.failed) out << "[campaign]   excluded " << f << "\n";
  out << "[campaign] statistics: " << where
      << (opt.slice_n > 1 ? " (fold all slices with: tumble merge " + dir + ")" : "") << std::endl;
  const std::size_t unfinished = ens.failed_count() + ens.missing_count();
  if (unfinished > 0)
    out << "[campaign] " << unfinished << " case" << (unfinished == 1 ? "" : "s")
        << " of this slice failed or have no result and are not in the ensemble: rerun the same "
           "command with --retry-failed to try them again (their diagnostics: "
        << dir << "/manifest); exit code 4" << std::endl;
  return unfinished;
}

// What a campaign halted by a manifest it could not write (Dispatcher::halted) leaves: the lines
// that never reached the file are printed, so that nothing computed is lost: appended to the
// manifest once there is room, they record the cases they describe (a case done counts as done if
// its fields file still has the checksum they carry); without them the rerun runs those cases
// again (from their checkpoints where they kept one).
void report_halt(const ScheduleStats& stats, const std::string& manifest, std::ostream& out) {
  out << "[campaign] halted: " << stats.manifest_error << "; " << stats.halted_not_started
      << " case" << (stats.halted_not_started == 1 ? "" : "s")
      << " not started, the running ones ran to their end; no statistics written. ";
  if (stats.unwritten.empty()) {
    out << "Every line was written in the end; rerun the same command to go on" << std::endl;
    return;
  }
  out << stats.unwritten.size() << " manifest line" << (stats.unwritten.size() == 1 ? "" : "s")
      << " could not be written; they follow. Make room, append them to " << manifest
      << " (e.g. paste them into `cat >> " << manifest
      << "`), and rerun the same command; a rerun without them runs their cases again\n";
  for (const std::string& l : stats.unwritten) out << l << "\n";
  out << std::flush;
}

// The cases of DIR/cases.tsv that `e` does not have: their count and one of them.
std::pair<int, std::string> foreign_cases(const std::string& dir, const Expansion& e) {
  std::set<std::string> ids;
  for (const Case& c : e.cases) ids.insert(c.id);
  int foreign = 0;
  std::string example;
  for (const std::string& id : case_table_ids(dir))
    if (!ids.count(id) && ++foreign == 1) example = id;
  return {foreign, example};
}

// Refuses to run into a directory that holds another campaign: one whose case table lists cases
// this campaign does not have (their results would silently leave the ensemble). A campaign that
// grew (a sweep added) keeps every old case and is let in.
void check_same_campaign(const std::string& dir, const Expansion& e, const std::string& file) {
  const auto [foreign, example] = foreign_cases(dir, e);
  if (foreign == 0) return;
  throw InputError("campaign error: '" + dir +
                   "' holds another campaign: " + std::to_string(foreign) + " of its " +
                   std::to_string(case_table_ids(dir).size()) + " cases (e.g. " + example +
                   ") are not cases of " + file +
                   ", and their results would leave the ensemble; run into another --output, "
                   "or pass --force to replace that campaign's table and statistics");
}

// --force into a directory that holds another campaign: that campaign's statistics go (its
// ensemble.h5 and partials; `tumble merge` folded them into this one's), said on `out`.
void remove_other_statistics(const std::string& dir, const Expansion& e, std::ostream& out) {
  if (foreign_cases(dir, e).first == 0) return;
  int removed = 0;
  if (fs::remove(dir + "/ensemble.h5")) ++removed;
  if (fs::is_directory(dir + "/partials"))
    for (const auto& entry : fs::directory_iterator(dir + "/partials"))
      if (entry.path().extension() == ".h5" && fs::remove(entry.path())) ++removed;
  if (removed > 0)
    out << "[campaign] --force: removed the other campaign's statistics (" << removed << " file"
        << (removed == 1 ? "" : "s") << ": ensemble.h5, partials/)" << std::endl;
}

// Refuses a campaign in which any case's scene is invalid (e.g. a swept time step above the
// stability bound, f = 1.5): every invalid point is named with its parameters and the scene's
// message, before anything is written.
void check_cases_valid(const CampaignSpec& spec, const Expansion& e) {
  std::string bad;
  int points = 0;
  for (const Point& p : e.points) {
    const Case& c = e.cases[p.cases.front()];
    if (c.scene_error.empty()) continue;
    if (++points <= 5) bad += "\n  point " + p.id + " [" + p.params_text + "]: " + c.scene_error;
  }
  if (points == 0) return;
  throw InputError("campaign error (" + spec.file + "): " + std::to_string(points) + " of " +
                   std::to_string(e.points.size()) + " parameter points make an invalid scene" +
                   (points > 5 ? " (the first 5 shown)" : "") + ":" + bad +
                   "\n  fix or remove them (tumble campaign FILE --list marks them INVALID)");
}

// Refuses a case whose group is larger than the world, naming the key that asked for it.
void check_groups_fit(const CampaignSpec& spec, const Expansion& e,
                      const std::vector<std::size_t>& slice, int world, bool from_cli) {
  for (std::size_t idx : slice) {
    const Case& c = e.cases[idx];
    if (c.ranks <= world) continue;
    const bool cli = from_cli && c.ranks_key == "campaign.ranks_per_case";
    throw InputError("campaign error (" + spec.file +
                     "): " + (cli ? "--ranks-per-case " : "key '" + c.ranks_key + "' = ") +
                     std::to_string(c.ranks) + ": a case needs more ranks than this run has (" +
                     std::to_string(world) + "); launch at least " + std::to_string(c.ranks) +
                     " ranks (mpirun -n) or lower it to at most " + std::to_string(world));
  }
}

// "groups of 2: 2 groups" / "groups of 4: 1 group, rank 4 idle" / "groups of 1 to 4 ranks, by
// point": how the world is used, for the start line.
std::string group_layout(const Expansion& e, const std::vector<std::size_t>& slice, int world) {
  int lo = 1 << 30, hi = 0;
  for (std::size_t idx : slice) {
    lo = std::min(lo, e.cases[idx].ranks);
    hi = std::max(hi, e.cases[idx].ranks);
  }
  if (hi == 0) return "no cases";
  if (lo != hi)
    return "groups of " + std::to_string(lo) + " to " + std::to_string(hi) +
           " ranks, by point, placed on free consecutive ranks";
  const int groups = world / hi, idle = world % hi;
  std::string s = "groups of " + std::to_string(hi) + ": " + std::to_string(groups) + " group" +
                  (groups == 1 ? "" : "s");
  if (idle > 0)
    s += ", rank" + std::string(idle > 1 ? "s " : " ") + std::to_string(world - idle) +
         (idle > 1 ? "-" + std::to_string(world - 1) : "") + " idle (" + std::to_string(world) +
         " is not a multiple of " + std::to_string(hi) + ")";
  return s;
}

}  // namespace

int run_campaign(const CampaignOptions& opt, MPI_Comm world, std::ostream& out) {
  // (MPI_COMM_NULL: `--list` or `--status` in one process without MPI, app/main.cpp)
  const int rank = rank_in(world), size = size_of(world);
  // The campaign file and what it expands to, read on every rank and agreed before any work: a
  // file one node cannot read is refused on all ranks, naming that rank, instead of rank 0
  // waiting for it in the first collective call.
  CampaignSpec spec;
  Expansion e;
  std::vector<std::size_t> slice;
  agreed_input(world, [&] {
    spec = load_campaign(opt.file);
    if (!opt.output.empty()) spec.output_dir = opt.output;
    if (opt.ranks_per_case > 0) spec.ranks_per_case = opt.ranks_per_case;
    const std::string& out_dir = spec.output_dir;
    // (A file in the way, or a folder that cannot be written; a bed cache that exists may be
    // read-only: beds shared.)
    if (const std::string why = cannot_make_directory(out_dir); !why.empty())
      throw InputError("campaign.output_dir (or --output) = '" + out_dir +
                       "' cannot be used: " + why);
    const std::string cache = spec.bed_cache.empty() ? out_dir + "/beds" : spec.bed_cache;
    if (const std::string why = cannot_make_directory(cache, true); !why.empty())
      throw InputError("campaign.bed_cache = '" + cache + "' cannot be used: " + why);
    e = expand(spec);
    slice = slice_cases(e, opt.slice_i, opt.slice_n);
    // Every case's scene is valid, or nothing runs (--list and --status show the invalid ones).
    if (!opt.list && !opt.status) check_cases_valid(spec, e);
    // Every case's group must fit in this run's world (checked on every rank alike, before any
    // work); a world that is not a multiple of the group size leaves its last ranks idle.
    if (!opt.list && !opt.status) check_groups_fit(spec, e, slice, size, opt.ranks_per_case > 0);
  });
  const std::string dir = spec.output_dir;
  const std::string bed_cache = spec.bed_cache.empty() ? dir + "/beds" : spec.bed_cache;
  const std::string slice_text = std::to_string(opt.slice_i) + "/" + std::to_string(opt.slice_n);

  if (opt.list) {
    if (rank == 0) {
      out << "# campaign " << spec.name << ": " << e.cases.size() << " cases in " << e.points.size()
          << " points; slice " << slice_text << " holds " << slice.size()
          << (slice.empty() ? " (more slices than cases: its run only writes an empty partial)"
                            : "")
          << "\n";
      out << "# case\tpoint\treplica\tseed\tcost(particle-steps)\tparams\n";
      for (std::size_t idx : slice) {
        const Case& c = e.cases[idx];
        out << c.id << "\t" << c.point_id << "\t" << c.replica << "\t" << case_seed(spec, c, 1)
            << "\t" << std::setprecision(4) << c.cost << "\t" << c.params_text
            << (c.scene_error.empty() ? "" : "\tINVALID: " + c.scene_error) << "\n";
      }
    }
    return 0;
  }

  // Rank 0 decides what is left and takes the slice's manifest lock; the others wait for its word
  // so that a refusal (the slice is already running: exit 2) or an error (a full disk: exit 1)
  // ends every rank the same way.
  std::vector<CaseState> states;
  ScheduleInput in;
  std::unique_ptr<DirectoryLock> dir_lock;  // held until the statistics are written
  std::unique_ptr<ManifestWriter> manifest;
  int status_rc = 0;
  on_rank_0_agreed(world, [&] {
    int torn = 0;
    states = classify(spec, e, dir, slice, opt.retry_failed, &torn);
    int done = 0, failed = 0;
    std::vector<std::size_t> pending;
    for (std::size_t k = 0; k < states.size(); ++k) {
      if (states[k].state == State::Done) ++done;
      if (states[k].state == State::Failed) ++failed;
      if (states[k].state == State::Pending) pending.push_back(k);
    }
    std::sort(pending.begin(), pending.end(), [&](std::size_t a, std::size_t b) {
      return runs_before(e.cases[slice[a]], e.cases[slice[b]]);
    });
    for (std::size_t k : pending) in.tasks.push_back(states[k].next);
    in.total = static_cast<int>(slice.size());
    in.done_before = done;
    in.failed_before = failed;
    if (opt.status) {
      // (A directory holding another campaign is refused by the run: its status says so, rather
      // than "to run" for cases that never would.)
      if (!opt.force) check_same_campaign(dir, e, opt.file);  // (the job scripts pass --force on)
      out << "campaign " << spec.name << " slice " << slice_text << ": " << slice.size()
          << " cases: " << done << " done, " << failed << " failed, " << pending.size()
          << " to run\n";
      if (torn > 0)
        out << "  ignored " << torn << " manifest line(s) that do not read (a crash mid-write, "
            << "or edited): the cases they recorded count as their earlier lines say\n";
      // A case whose last record says "running" may be running now if a campaign holds the
      // directory (its record cannot tell this invocation from one that died before it).
      const int runner = DirectoryLock::running_process(dir);
      // A kept β turn is looked for case by case (a scene each) only if the bed cache has one.
      bool any_turn = false;
      std::error_code ec;
      for (fs::directory_iterator it(bed_cache, ec), end; !ec && it != end && !any_turn;
           it.increment(ec)) {
        const std::string name = it->path().filename().string();
        any_turn = name.size() > 8 && name.compare(name.size() - 8, 8, ".turn.h5") == 0;
      }
      for (std::size_t k : pending) {
        std::string note = states[k].note;
        if (runner != 0 && note == "interrupted")
          note = "interrupted, or running now: " +
                 (runner > 0 ? "process " + std::to_string(runner) : "another process") +
                 " runs this campaign";
        // (A retry with a new seed starts afresh: its folder's checkpoint is not its own.)
        std::string at = checkpoint_progress(dir, e.cases[slice[k]]);
        if (states[k].next.fresh) at.clear();
        if (at.empty() && any_turn)
          at = repose_turn_progress(spec, e.cases[slice[k]], dir, bed_cache, states[k].next.seed);
        if (!at.empty()) note += (note.empty() ? "" : ", ") + at;
        out << "  to run: " << e.cases[slice[k]].id << " [" << e.cases[slice[k]].params_text
            << "] attempt " << states[k].next.attempt << (note.empty() ? "" : " (" + note + ")")
            << "\n";
      }
      status_rc = pending.empty() ? exit_code::kOk : exit_code::kWorkLeft;
      // Nothing to run, and yet no statistics: an invocation ended by a stop (or killed) after
      // its last case. The job-array scripts skip a slice whose status is 0, so it would never
      // be folded, and `tumble merge` would wait for it for ever.
      // A stale or damaged file is as good as none.
      const std::string stats_file =
          opt.slice_n == 1 ? dir + "/ensemble.h5" : partial_path(dir, opt.slice_i, opt.slice_n);
      if (pending.empty())
        if (const std::string why = statistics_not_current(stats_file, e, slice, states);
            !why.empty()) {
          out << "  " << why << ": rerun the same command to write them\n";
          status_rc = exit_code::kWorkLeft;
        }
    } else {
      fs::create_directories(dir + "/partials");
      dir_lock = std::make_unique<DirectoryLock>(dir, opt.slice_n);
      const CaseTableLock table_lock(dir);  // (until the table below is written)
      if (!opt.force)
        check_same_campaign(dir, e, opt.file);
      else
        remove_other_statistics(dir, e, out);
      manifest =
          std::make_unique<ManifestWriter>(dir + "/manifest/slice_" + std::to_string(opt.slice_i) +
                                           "_of_" + std::to_string(opt.slice_n) + ".jsonl");
      std::ifstream src(opt.file);
      std::stringstream ss;
      ss << src.rdbuf();
      write_text_atomically(dir + "/campaign.toml", ss.str());
      write_text_atomically(dir + "/cases.tsv", cases_table(e));
      out << "[campaign] " << spec.name << ": " << e.cases.size() << " cases in " << e.points.size()
          << " points; slice " << slice_text << ": " << slice.size() << " cases, " << done
          << " done before, " << failed << " failed before, " << in.tasks.size() << " to run on "
          << size << " rank" << (size > 1 ? "s" : "") << " (" << group_layout(e, slice, size)
          << "); output in " << dir << std::endl;
      if (slice.empty())
        out << "[campaign] slice " << slice_text << " holds no case (" << e.cases.size()
            << " cases in " << opt.slice_n << " slices): it writes an empty partial, which "
            << "tumble merge expects of every slice" << std::endl;
      if (torn > 0)
        out << "[campaign] ignored " << torn << " torn manifest line(s) (a crash mid-write)\n";
    }
  });
  if (size > 1) MPI_Bcast(&status_rc, 1, MPI_INT, 0, world);
  if (opt.status) return status_rc;

  in.manifest = manifest.get();
  in.slice = slice_text;
  in.out = &out;
  in.quiet = opt.quiet;
  CaseContext ctx{&spec, &e, dir, bed_cache, MPI_COMM_NULL, nullptr, nullptr};
  const ScheduleStats stats = schedule(ctx, world, in);

  // Rank 0 folds the statistics while the others wait (sleeping); its error (a full disk, an
  // ensemble.h5 it cannot replace) ends every rank, said once: thrown by rank 0 alone, the others
  // waited for ever for its verdict below.
  // A stop request leaves the statistics to the rerun that finishes the slice: the point of the
  // signal is to be gone before the batch system's time limit. One that came when no case was
  // left (the last ones ended at it) does not: nothing would run the slice again.
  int rc = exit_code::kOk;
  on_rank_0_agreed(
      world,
      [&] {
        const std::string manifest_file = manifest->path();
        manifest.reset();  // releases the lock: the slice may be run again
        if (!stats.manifest_error.empty()) {
          report_halt(stats, manifest_file, out);
          rc = exit_code::kRunFailed;
        } else if (stats.stop_signal != 0 && cases_left(spec, e, dir, slice) > 0) {
          out << "[campaign] stopped by " << signal_name(stats.stop_signal) << ": " << stats.stopped
              << " case" << (stats.stopped == 1 ? "" : "s") << " stopped at a checkpoint, ";
          if (stats.stopped_preparing > 0)
            out << stats.stopped_preparing
                << " while preparing (a bed starts again, a beta measurement goes on from its "
                   "turn), ";
          out << stats.not_started << " not started; rerun the same command to go on\n";
          rc = exit_code::kWorkLeft;
        } else if (fold_statistics(spec, e, dir, slice, opt, stats, out) > 0) {
          rc = exit_code::kFailedCases;
        }
      },
      [&] { sleeping_barrier(world); });
  // Every rank exits with rank 0's verdict (mpirun reports the first non-zero code).
  MPI_Bcast(&rc, 1, MPI_INT, 0, world);
  return rc;
}

}  // namespace tumble::campaign
