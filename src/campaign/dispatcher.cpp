#include "campaign/dispatcher.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <set>
#include <sstream>

#include "base/error.hpp"
#include "base/stop_request.hpp"
#include "base/text_util.hpp"
#include "campaign/eta.hpp"
#include "campaign/expand.hpp"
#include "campaign/rank_pool.hpp"
#include "io/bed_io.hpp"
#include "run/repose_measure.hpp"

namespace tumble::campaign {
namespace fs = std::filesystem;
namespace {
constexpr double kRetryDelay = 5;  // seconds before a second attempt, doubling after
// Progress reports a running case's rate is taken over: 10 progress intervals (5 min at the
// default 30 s, 20 min at the accuracy campaigns' 120 s), long enough to smooth a case's phases,
// short enough to follow a pause or a busier machine.
constexpr std::size_t kRecentReports = 11;
constexpr double kMaxRetryDelay = 300;
// The ranks that run cases: with one group size k, a world that is not a multiple of k leaves
// its last ranks idle (the start line says so), and the ETA shares the work among the others;
// with several sizes, groups are placed on any free ranks.
int working_ranks(const ScheduleInput& in, const Expansion& e, int ranks) {
  int lo = ranks, hi = 0;
  for (const CaseTask& t : in.tasks) {
    lo = std::min(lo, e.cases[t.case_index].ranks);
    hi = std::max(hi, e.cases[t.case_index].ranks);
  }
  return hi > 0 && lo == hi ? std::max(1, ranks / hi * hi) : ranks;
}
double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

Dispatcher::Dispatcher(const CaseContext& ctx, const ScheduleInput& in,
                       std::vector<std::string> hosts, int ranks)
    : ctx_(ctx),
      in_(in),
      hosts_(std::move(hosts)),
      ranks_(working_ranks(in, *ctx.expansion, ranks)),
      queue_(in.tasks.begin(), in.tasks.end()),
      done_(in.done_before),
      failed_(in.failed_before) {}

const CaseTask* Dispatcher::peek(const std::vector<int>& group) {
  const auto now = Clock::now();
  deferred_.clear();
  // Rank 0 peeks after each of its own time steps: when every due case waited on another's
  // preparation at the last look and nothing has changed since, they still do.
  if (all_waiting_at_ == changes_ && all_waiting_for_ == group && not_before_.empty())
    return nullptr;
  for (peeked_ = queue_.begin(); peeked_ != queue_.end(); ++peeked_) {
    const auto wait = not_before_.find(peeked_->case_index);
    if (wait != not_before_.end() && wait->second > now) continue;
    const long long by = preparing_its_files(*peeked_, group);
    if (by < 0) return &*peeked_;
    if (deferred_.empty())
      deferred_ = "ahead of " + ctx_.expansion->cases[peeked_->case_index].id +
                  ", which waits for the settled bed or measured beta that " +
                  ctx_.expansion->cases[static_cast<std::size_t>(by)].id + " is preparing";
  }
  if (!deferred_.empty()) {
    all_waiting_at_ = changes_;
    all_waiting_for_ = group;
  }
  return nullptr;
}

namespace {
// The cache files a case would make before its protocol: its settled bed unless given one, and
// its measured β and still slope if the scene asks for them; those that exist are not made again.
// None when it resumes from its checkpoint (which holds the particles and both numbers), or when
// its scene is invalid (it fails at once).
std::vector<std::string> missing_preparation_files(const CaseContext& ctx, const CaseTask& t) {
  const Case& c = ctx.expansion->cases[t.case_index];
  const std::string dir = case_dir(ctx.campaign_dir, c.id);
  if (!c.scene_error.empty() || (!t.fresh && fs::exists(dir + "/checkpoint.h5"))) return {};
  std::vector<std::string> files;
  try {
    const Scene s = case_scene(*ctx.spec, c, dir, ctx.bed_cache, t.seed);
    const std::string bed = io::bed_cache_path(s), repose = repose_cache_path(s);
    if (s.bed_file.empty() && !fs::exists(bed)) files.push_back(bed);
    if (s.bed_turn_pending() && !fs::exists(repose)) files.push_back(repose);
  } catch (const InputError&) {
    return {};
  }
  return files;
}
}  // namespace

const std::vector<std::string>& Dispatcher::files_to_prepare(const CaseTask& t) {
  const auto key = std::make_pair(t.case_index, t.seed);
  auto it = prepares_.find(key);
  if (it == prepares_.end()) it = prepares_.emplace(key, missing_preparation_files(ctx_, t)).first;
  return it->second;
}

long long Dispatcher::preparing_its_files(const CaseTask& t, const std::vector<int>& group) {
  // The cases that prepare now: each group's running case (not one held next in line, which
  // begins only when that one ends: a case that needs its files before then makes them itself),
  // before its protocol's first report, on another group than the one this case is for.
  std::vector<std::size_t> preparing;
  for (const auto& [ranks, idx] : running_cases()) {
    const Held& h = running_.at(idx);
    if (h.recent.empty() && !h.prepares.empty() && ranks != group) preparing.push_back(idx);
  }
  if (preparing.empty()) return -1;  // (the common path: no scene is read)
  const std::vector<std::string>& mine = files_to_prepare(t);
  for (const std::size_t idx : preparing) {
    const std::vector<std::string>& theirs = running_.at(idx).prepares;
    for (const std::string& f : mine)
      if (std::find(theirs.begin(), theirs.end(), f) != theirs.end())
        return static_cast<long long>(idx);
  }
  return -1;
}

int Dispatcher::files_left_to_prepare() {
  std::set<std::string> made, left;
  const std::map<std::vector<int>, std::size_t> first_of_group = running_cases();
  for (const auto& [ranks, idx] : first_of_group)
    made.insert(running_.at(idx).prepares.begin(), running_.at(idx).prepares.end());
  // (A file found on disk is not asked again: on a cluster the bed cache is on a shared file
  // system, and each progress line would stat every queued case's files.)
  const auto add = [&](const CaseTask& t) {
    for (const std::string& f : files_to_prepare(t))
      if (!made.count(f) && !left.count(f) && !on_disk_.count(f)) {
        if (fs::exists(f))
          on_disk_.insert(f);
        else
          left.insert(f);
      }
  };
  for (const CaseTask& t : queue_) add(t);
  for (const auto& [idx, held] : running_)  // (held next on a group: not begun)
    if (first_of_group.at(held.ranks) != idx) add(held.task);
  return static_cast<int>(left.size());
}

void Dispatcher::pop() {
  ++changes_;
  not_before_.erase(peeked_->case_index);
  queue_.erase(peeked_);
}

int Dispatcher::ranks_for(const CaseTask& t) const {
  return ctx_.expansion->cases[t.case_index].ranks;
}

double Dispatcher::cost(const CaseTask& t) const {
  return std::max(1.0, ctx_.expansion->cases[t.case_index].cost);
}

std::string Dispatcher::case_label(const CaseTask& t) const {
  const Case& c = ctx_.expansion->cases[t.case_index];
  return c.id + " [" + c.params_text + ", replica " + std::to_string(c.replica) + ", attempt " +
         std::to_string(t.attempt) + "]";
}

CaseRecord Dispatcher::record(const CaseTask& t, const std::vector<int>& ranks) const {
  const Case& c = ctx_.expansion->cases[t.case_index];
  CaseRecord r;
  r.case_id = c.id;
  r.point_id = c.point_id;
  r.params = c.params_text;
  r.tier = ctx_.spec->tier;
  r.replica = c.replica;
  r.attempt = t.attempt;
  r.seed = t.seed;
  r.rank = ranks.front();
  r.group = ranks.front() / static_cast<int>(ranks.size());
  r.ranks = rank_list_text(ranks);
  r.host = hosts_[static_cast<std::size_t>(ranks.front())];
  std::set<std::string> seen;
  for (int k : ranks) {
    const std::string& h = hosts_[static_cast<std::size_t>(k)];
    if (seen.insert(h).second) r.hosts += (r.hosts.empty() ? "" : ",") + h;
  }
  r.output = case_output(c.id);
  r.slice = in_.slice;
  r.t = unix_now();
  return r;
}

void Dispatcher::started(const CaseTask& t, const std::vector<int>& ranks) {
  // A group that still runs a case holds this one as its next (scheduler.cpp): it starts when
  // that one ends, and the line says so rather than "start".
  bool held = false;
  for (const auto& [idx, other] : running_) held = held || other.ranks == ranks;
  Held h;
  h.ranks = ranks;
  h.handed = Clock::now();
  h.task = t;
  ++changes_;
  h.prepares = missing_preparation_files(ctx_, t);  // (afresh: the memo may predate a bed)
  running_[t.case_index] = h;
  CaseRecord r = record(t, ranks);
  r.status = "running";
  r.start = utc_now();
  append(r);
  if (!in_.quiet)
    line(std::string(held ? "next " : "start ") + case_label(t) + " on rank" +
         (ranks.size() > 1 ? "s " : " ") + r.ranks + " (" + r.hosts + ")" +
         (held ? ", held: starts when the case running there ends" : "") +
         (deferred_.empty() ? "" : ", " + deferred_));
  deferred_.clear();
}

std::vector<int> Dispatcher::finished(const CaseTask& t, const CaseOutcome& o) {
  ++changes_;
  const Held held = running_.at(t.case_index);
  running_.erase(t.case_index);
  // The group's next case, held while this one ran, starts now: its age counts from here, and
  // the manifest gets its real start (its first record has the hand-out time), and the log a
  // "start" line after this case's own line, so that every case's start shows in the log.
  std::vector<std::string> now_starting;
  for (auto& [idx, other] : running_)
    if (other.ranks == held.ranks) {
      other.handed = std::max(other.handed, Clock::now());
      CaseRecord next = record(other.task, other.ranks);
      next.status = "running";
      next.start = utc_now();
      append(next);
      const std::string start = "start " + case_label(other.task) + " on rank" +
                                (other.ranks.size() > 1 ? "s " : " ") + next.ranks + " (" +
                                next.hosts + "), held until now";
      // When stopping, the held case may have begun before the stop reached its group, or end
      // "not begun": its own result says which, and its start line waits for it.
      if (stopping())
        other.start_line = start;
      else
        now_starting.push_back(start);
    }
  const double k = static_cast<double>(held.ranks.size());
  CaseRecord r = record(t, held.ranks);
  r.start = o.start;
  r.end = o.end;
  r.wall = o.wall;
  r.resumed_from_step = o.resumed_from_step;
  stats_.cases_run += 1;
  stats_.rank_seconds += o.wall * k;
  std::string what;
  bool appended = false;
  if (o.failure == "stopped") {  // neither done nor failed: the rerun continues the same attempt
    r.status = "stopped";
    r.diagnostic = o.diagnostic;
    // A held case that had not begun is not started, not stopped; a case stopped before its
    // protocol's first report kept no run checkpoint (its bed starts again; a β measurement goes
    // on from the turn it kept).
    if (ended_not_begun(o))
      stats_.not_started += 1;
    else if (held.recent.empty())
      stats_.stopped_preparing += 1;
    else
      stats_.stopped += 1;
    what = o.diagnostic;  // "stopped by SIGUSR1 at step ..." or "not begun: ..."
  } else if (o.ok) {
    r.status = "done";
    r.checksum = o.checksum;
    done_ += 1;
    // The rate takes what this call ran: a case resumed from its checkpoint did only the rest of
    // its steps in o.wall (credited with its whole cost, a case resumed at 90% made the rate ten
    // times too fast); one whose total its leader never reported is left out of the rate.
    double share = 1;
    if (o.resumed_from_step > 0) {
      const long long total = held.recent.empty() ? 0 : held.recent.back().total_steps;
      share = total > 0 ? std::max(0.0, 1.0 - static_cast<double>(o.resumed_from_step) /
                                                  static_cast<double>(total))
                        : 0.0;
    }
    // And the protocol's wall time (a case that settled its bed and measured β took hours more
    // on a paper bed, which the running cases' rates do not count either).
    const double ran = o.protocol_wall > 0 ? o.protocol_wall : o.wall;
    if (share > 0) {
      done_cost_ += cost(t) * share;
      done_rank_seconds_ += ran * k;
      EtaInput::Rate& point = done_by_point_[ctx_.expansion->cases[t.case_index].point_id];
      point.cost += cost(t) * share;
      point.rank_seconds += ran * k;
    }
    what = "done";
  } else {
    r.status = "failed";
    r.failure = o.failure;
    r.diagnostic = o.diagnostic;
    // When stopping, no retry starts here; the rerun makes it (a stop loses nothing), so the
    // failure is final only if no attempt is left.
    const bool may_retry = o.retryable && t.attempt < ctx_.spec->max_attempts;
    r.final_failure = !may_retry;
    // The line first: if it is the one the manifest cannot take, the campaign halts here and
    // queues no retry (the log said "retrying" beside HALTED, and the retry never came).
    append(r);
    appended = true;
    const bool retry = may_retry && !stopping() && !halted();
    what = "FAILED (" + o.failure + "): " + o.diagnostic;
    if (retry) {
      const Case& c = ctx_.expansion->cases[t.case_index];
      CaseTask again{t.case_index, t.attempt + 1, case_seed(*ctx_.spec, c, t.attempt + 1),
                     ctx_.spec->retry_seed == "new"};
      queue_.push_back(again);
      const double delay = kRetryDelay * std::pow(2.0, again.attempt - 2);
      not_before_[t.case_index] =
          Clock::now() + std::chrono::duration_cast<Clock::duration>(
                             std::chrono::duration<double>(std::min(delay, kMaxRetryDelay)));
      what += "; retrying (attempt " + std::to_string(again.attempt) + " of " +
              std::to_string(ctx_.spec->max_attempts) + ") in " +
              format_hms(std::min(delay, kMaxRetryDelay));
    } else {
      failed_ += 1;
      if (may_retry)
        what += "; the rerun retries it (attempt " + std::to_string(t.attempt + 1) + ")";
    }
  }
  if (!appended) append(r);
  if (!in_.quiet && !held.start_line.empty() && !ended_not_begun(o))
    line(held.start_line);  // (it began, though the stop came before its predecessor's result)
  if (!o.ok || !in_.quiet)
    line(what + ": " + case_label(t) + " on rank" + (held.ranks.size() > 1 ? "s " : " ") + r.ranks +
             " in " + format_hms(o.wall) +
             (o.resumed_from_step > 0
                  ? " (resumed at step " + std::to_string(o.resumed_from_step) + ")"
                  : ""),
         true);
  if (!in_.quiet)
    for (const std::string& s : now_starting) line(s);
  return held.ranks;
}

void Dispatcher::stop(int signal) {
  if (stopping()) return;
  stop_signal_ = signal;
  stats_.stop_signal = signal;
  stats_.not_started = static_cast<int>(queue_.size());
  queue_.clear();
  not_before_.clear();
  const std::size_t n = running_cases().size();  // (a case held next in line ends "not begun")
  line(signal_name(signal) + ": stopping; no case starts any more, " +
       (n == 1 ? std::string("the running case ends") : std::to_string(n) + " running cases end") +
       " at the next neighbour rebuild with a checkpoint (one still settling its bed keeps none: "
       "that starts again; one measuring beta or the still slope keeps its turn so far); rerun the "
       "same command to go on");
}

void Dispatcher::progress(const CaseProgress& p) {
  const auto it = running_.find(p.case_index);
  if (it == running_.end() || it->second.task.attempt != p.attempt) return;
  ++changes_;  // (a protocol's first report ends its case's preparation)
  Held& h = it->second;
  if (p.preparing && !h.preparing) {
    h.preparing_since = Clock::now();
    // Its files as it begins: a case held next on its group was handed out while the case before
    // it made the bed and β they share (one replica's points run in a row), and loads them now.
    h.prepares = missing_preparation_files(ctx_, h.task);
  }
  // Its preparation's cost, for the ETA of those still to come (a β measurement that went on
  // from a kept turn counts only its rest: the measure errs short after a stop).
  if (!p.preparing && h.preparing && !h.prepares.empty()) {
    prepared_rank_seconds_ += since(h.preparing_since) * static_cast<double>(h.ranks.size());
    prepared_files_ += static_cast<int>(h.prepares.size());
  }
  h.preparing = p.preparing;
  if (p.preparing) {
    h.recent.clear();
    h.reported_at = Clock::now();
    return;
  }
  if (p.total_steps <= 0) return;
  auto& recent = it->second.recent;
  if (!recent.empty() && recent.back().first_step != p.first_step) recent.clear();  // (a new call)
  recent.push_back(p);
  if (recent.size() > kRecentReports) recent.pop_front();
  it->second.reported_at = Clock::now();
}

std::map<std::vector<int>, std::size_t> Dispatcher::running_cases() const {
  std::map<std::vector<int>, std::size_t> first_of_group;
  for (const auto& [idx, held] : running_) {
    auto [it, fresh] = first_of_group.emplace(held.ranks, idx);
    if (!fresh && held.handed < running_.at(it->second).handed) it->second = idx;
  }
  return first_of_group;
}

void Dispatcher::append(const CaseRecord& r) {
  waiting_.push_back(r);
  if (write_waiting() || halted()) return;
  stats_.manifest_error = last_append_error_;
  stats_.halted_not_started = static_cast<int>(queue_.size());
  queue_.clear();
  not_before_.clear();
  const std::size_t n = running_cases().size(), held = running_.size() - n;
  // (A case held next on a group was handed out already: the group starts it when its running
  // case ends, and nothing reaches a remote group between its cases but a new assignment.)
  line("HALTED: " + stats_.manifest_error + ". No case is handed out any more; " +
       (n == 0   ? std::string("none is running")
        : n == 1 ? std::string("the running case goes on to its end")
                 : std::to_string(n) + " running cases go on to their end") +
       (held == 0   ? std::string()
        : held == 1 ? std::string(", and the one held next on its group, handed out before, runs")
                    : ", and the " + std::to_string(held) +
                          " held next on their groups, handed out before, run") +
       ". The lines not written are kept and written as soon as there is room");
}

bool Dispatcher::write_waiting() {
  try {
    while (!waiting_.empty()) {
      in_.manifest->append(waiting_.front());
      waiting_.pop_front();
    }
  } catch (const RunError& e) {
    last_append_error_ = e.what();
    return false;
  }
  return true;
}

void Dispatcher::flush_unwritten() {
  write_waiting();
  stats_.unwritten.clear();
  for (const CaseRecord& r : waiting_) stats_.unwritten.push_back(to_json(r));
}

void Dispatcher::tick() {
  if (since(last_tick_) < std::max(1.0, ctx_.spec->progress_interval)) return;
  if (!waiting_.empty()) write_waiting();
  in_.manifest->sync();
  if (in_.quiet || since(last_line_) >= ctx_.spec->progress_interval) line("");
  last_tick_ = Clock::now();
}

// An event, with the counts on the next line when `counts` (or when there is no event).
void Dispatcher::line(const std::string& event, bool counts) {
  if (!in_.out) return;
  if (!event.empty() && !counts) {
    *in_.out << "[campaign] " << event << std::endl;
    return;
  }
  // ETA from the cost (particles x steps) and the rank-seconds of the cases done in this
  // invocation (campaign/eta.hpp).
  EtaInput eta_in;
  eta_in.done_cost = done_cost_;
  eta_in.done_rank_seconds = done_rank_seconds_;
  eta_in.done_by_point = done_by_point_;
  for (const auto& t : queue_)
    eta_in.queued_by_point[ctx_.expansion->cases[t.case_index].point_id] += cost(t);
  eta_in.ranks = std::max(1, ranks_);
  if (prepared_files_ > 0) {
    eta_in.rank_seconds_per_file = prepared_rank_seconds_ / prepared_files_;
    eta_in.queued_files = files_left_to_prepare();
  }
  // A group that still runs a case may already hold its next one (started() says "next"): that
  // one has not begun. It is charged as queued, not credited with the time it waits, and counted
  // as next, not as running, so "running" never exceeds the groups.
  const std::map<std::vector<int>, std::size_t> first_of_group = running_cases();
  for (const auto& [idx, held] : running_) {
    const double c = cost(CaseTask{idx, 1, 0, false});
    if (first_of_group.at(held.ranks) != idx) {
      eta_in.queued_by_point[ctx_.expansion->cases[idx].point_id] += c;
      continue;
    }
    EtaInput::Running r{c, since(held.handed), static_cast<int>(held.ranks.size())};
    r.point = ctx_.expansion->cases[idx].point_id;
    r.preparing = held.preparing;
    r.files = static_cast<int>(held.prepares.size());
    r.preparing_for = held.preparing ? since(held.preparing_since) : 0.0;
    if (!held.recent.empty()) {
      // The rate over the recent reports (from the call's start while there is one report).
      const CaseProgress &first = held.recent.front(), &last = held.recent.back();
      const bool one = held.recent.size() == 1;
      const auto total = static_cast<double>(last.total_steps);
      r.reported = true;
      r.done_share = static_cast<double>(last.step) / total;
      r.call_share = static_cast<double>(last.step - (one ? last.first_step : first.step)) / total;
      r.call_seconds = last.seconds - (one ? 0.0 : first.seconds);
      r.since_report = since(held.reported_at);
    }
    eta_in.running.push_back(r);
  }
  const double eta = estimate_eta(eta_in);
  const int running = static_cast<int>(first_of_group.size());
  const int next = static_cast<int>(running_.size()) - running;
  const int left = in_.total - done_ - failed_ - static_cast<int>(running_.size());
  std::ostringstream os;
  os << "[campaign] ";
  if (!event.empty()) os << event << "\n[campaign] ";
  os << "done " << done_ << " | running " << running;
  // How far the running cases are (their leaders' last reports), in case order.
  std::string shares;
  int reported = 0, preparing = 0;
  for (const auto& [idx, held] : running_) {
    // (Only the cases running: a held case's leader may report before its group's last result
    // is in, since the two come with different tags.)
    if (first_of_group.at(held.ranks) != idx) continue;
    preparing += held.preparing;
    if (!held.recent.empty()) {
      ++reported;
      std::ostringstream one;
      one << std::fixed << std::setprecision(1)
          << 100.0 * static_cast<double>(held.recent.back().step) /
                 static_cast<double>(held.recent.back().total_steps)
          << "%";
      shares += (shares.empty() ? "" : ", ") + one.str();
    }
  }
  // (A case preparing settles its bed or measures β before its protocol's first step.)
  if (reported > 0 || preparing > 0) {
    os << " (";
    if (reported > 0) os << shares << (reported == 1 ? " of its steps" : " of their steps");
    if (reported > 0 && preparing > 0) os << "; ";
    if (preparing > 0) os << preparing << " preparing";
    os << ")";
  }
  if (next > 0) os << " | next " << next;
  os << " | failed " << failed_ << " | left " << left << " of " << in_.total << " | elapsed "
     << format_hms(since(t0_)) << " | ETA " << format_hms(eta);
  *in_.out << os.str() << std::endl;
  last_line_ = Clock::now();
}

}  // namespace tumble::campaign
