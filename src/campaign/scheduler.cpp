#include "campaign/scheduler.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <future>
#include <iomanip>
#include <list>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "base/text_util.hpp"
#include "campaign/eta.hpp"
#include "campaign/expand.hpp"

namespace tumble::campaign {
namespace {
using Clock = std::chrono::steady_clock;
constexpr int kTagResult = 4101;  // leader -> rank 0: a result (or "" to say hello)
constexpr int kTagAssign = 4102;  // rank 0 -> leader: "index attempt seed fresh" or "stop"
constexpr auto kPoll = std::chrono::microseconds(200);
constexpr auto kPollBusy = std::chrono::milliseconds(2);

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Non-blocking sends that own their buffers. A blocking MPI_Send of even a short message may
// wait until the receiver polls (measured: about the receiver's poll interval per message), so
// every send is posted and completed later.
class Outbox {
 public:
  explicit Outbox(MPI_Comm comm) : comm_(comm) {}
  ~Outbox() { drain(); }
  void send(std::string s, int dest, int tag) {
    progress();
    pending_.emplace_back(std::move(s), MPI_REQUEST_NULL);
    auto& [buf, req] = pending_.back();
    MPI_Isend(buf.data(), static_cast<int>(buf.size()), MPI_CHAR, dest, tag, comm_, &req);
  }
  void progress() {
    for (auto it = pending_.begin(); it != pending_.end();) {
      int done = 0;
      MPI_Test(&it->second, &done, MPI_STATUS_IGNORE);
      it = done ? pending_.erase(it) : std::next(it);
    }
  }
  void drain() {
    while (progress(), !pending_.empty()) std::this_thread::sleep_for(kPoll);
  }

 private:
  MPI_Comm comm_;
  std::list<std::pair<std::string, MPI_Request>> pending_;  // list: buffers never move
};
std::string recv_string(int source, int tag, MPI_Comm comm, int* from = nullptr) {
  MPI_Status st;
  MPI_Probe(source, tag, comm, &st);
  int n = 0;
  MPI_Get_count(&st, MPI_CHAR, &n);
  std::string s(static_cast<std::size_t>(n), '\0');
  MPI_Recv(s.data(), n, MPI_CHAR, st.MPI_SOURCE, tag, comm, MPI_STATUS_IGNORE);
  if (from) *from = st.MPI_SOURCE;
  return s;
}
// Waits for a message by polling with sleeps, then receives it.
std::string recv_string_sleeping(int source, int tag, MPI_Comm comm) {
  int flag = 0;
  while (true) {
    MPI_Iprobe(source, tag, comm, &flag, MPI_STATUS_IGNORE);
    if (flag) return recv_string(source, tag, comm);
    std::this_thread::sleep_for(kPoll);
  }
}

std::string encode_task(const CaseTask& t) {
  std::ostringstream os;
  os << t.case_index << " " << t.attempt << " " << t.seed << " " << (t.fresh ? 1 : 0);
  return os.str();
}
CaseTask decode_task(const std::string& s) {
  CaseTask t;
  int fresh = 0;
  std::istringstream is(s);
  long long seed = 0;
  is >> t.case_index >> t.attempt >> seed >> fresh;
  t.seed = seed;
  t.fresh = fresh != 0;
  return t;
}

std::string processor_name() {
  char name[MPI_MAX_PROCESSOR_NAME];
  int len = 0;
  MPI_Get_processor_name(name, &len);
  return std::string(name, static_cast<std::size_t>(len));
}

// Rank 0's bookkeeping: the queue, who runs what, the manifest and the progress lines.
class Dispatcher {
 public:
  Dispatcher(const CaseContext& ctx, const ScheduleInput& in, std::vector<std::string> hosts)
      : ctx_(ctx),
        in_(in),
        hosts_(std::move(hosts)),
        queue_(in.tasks.begin(), in.tasks.end()),
        done_(in.done_before),
        failed_(in.failed_before) {
    for (const auto& t : queue_) left_cost_ += cost(t);
  }

  bool next(CaseTask& t) {
    if (queue_.empty()) return false;
    t = queue_.front();
    queue_.pop_front();
    return true;
  }
  bool idle() const { return queue_.empty() && running_.empty(); }
  std::size_t queued() const { return queue_.size(); }

  void started(const CaseTask& t, int group, int rank) {
    running_[t.case_index] = {group, rank, Clock::now()};
    CaseRecord r = record(t, group, rank);
    r.status = "running";
    r.start = utc_now();
    in_.manifest->append(r);
    if (!in_.quiet)
      line("start " + case_label(t) + " on group " + std::to_string(group) + " (" + hosts_[rank] +
           ")");
  }

  void finished(const CaseTask& t, const CaseOutcome& o) {
    const auto [group, rank, handed] = running_.at(t.case_index);
    running_.erase(t.case_index);
    freed_[rank] = Clock::now();
    CaseRecord r = record(t, group, rank);
    r.start = o.start;
    r.end = o.end;
    r.wall = o.wall;
    r.resumed_from_step = o.resumed_from_step;
    stats_.cases_run += 1;
    stats_.case_wall += o.wall;
    left_cost_ -= cost(t);
    std::string what;
    if (o.ok) {
      r.status = "done";
      r.checksum = o.checksum;
      done_ += 1;
      done_cost_ += cost(t);
      done_wall_ += o.wall;
      what = "done";
    } else {
      r.status = "failed";
      r.failure = o.failure;
      r.diagnostic = o.diagnostic;
      const bool retry = o.retryable && t.attempt < ctx_.spec->max_attempts;
      r.final_failure = !retry;
      what = "FAILED (" + o.failure + "): " + o.diagnostic;
      if (retry) {
        const Case& c = ctx_.expansion->cases[t.case_index];
        CaseTask again{t.case_index, t.attempt + 1, case_seed(*ctx_.spec, c, t.attempt + 1),
                       ctx_.spec->retry_seed == "new"};
        queue_.push_back(again);
        left_cost_ += cost(again);
        what += "; retrying (attempt " + std::to_string(again.attempt) + " of " +
                std::to_string(ctx_.spec->max_attempts) + ")";
      } else {
        failed_ += 1;
      }
    }
    in_.manifest->append(r);
    if (!o.ok || !in_.quiet)
      line(what + ": " + case_label(t) + " in " + format_hms(o.wall) +
               (o.resumed_from_step > 0
                    ? " (resumed at step " + std::to_string(o.resumed_from_step) + ")"
                    : ""),
           true);
  }

  // A status line now and then, and the manifest flushed to disk.
  void tick() {
    if (since(last_tick_) < std::max(1.0, ctx_.spec->progress_interval)) return;
    in_.manifest->sync();
    if (in_.quiet || since(last_line_) >= ctx_.spec->progress_interval) line("");
    last_tick_ = Clock::now();
  }

  ScheduleStats& stats() { return stats_; }
  Clock::time_point start() const { return t0_; }

 private:
  double cost(const CaseTask& t) const {
    return std::max(1.0, ctx_.expansion->cases[t.case_index].cost);
  }
  std::string case_label(const CaseTask& t) const {
    const Case& c = ctx_.expansion->cases[t.case_index];
    return c.id + " [" + c.params_text + ", replica " + std::to_string(c.replica) + ", attempt " +
           std::to_string(t.attempt) + "]";
  }
  CaseRecord record(const CaseTask& t, int group, int rank) const {
    const Case& c = ctx_.expansion->cases[t.case_index];
    CaseRecord r;
    r.case_id = c.id;
    r.point_id = c.point_id;
    r.params = c.params_text;
    r.tier = ctx_.spec->tier;
    r.replica = c.replica;
    r.attempt = t.attempt;
    r.seed = t.seed;
    r.group = group;
    r.rank = rank;
    r.host = hosts_[rank];
    r.output = case_output(c.id);
    r.slice = in_.slice;
    r.t = unix_now();
    return r;
  }
  // An event, with the counts on the next line when `counts` (or when there is no event).
  void line(const std::string& event, bool counts = false) {
    if (!in_.out) return;
    if (!event.empty() && !counts) {
      *in_.out << "[campaign] " << event << std::endl;
      return;
    }
    const double el = since(t0_);
    // ETA from the cost (particles x steps) and wall time of the cases done in this invocation.
    // A remote leader holds up to two cases: the one handed out first runs, since it was handed
    // out or since the leader's previous case ended, whichever is later; the other waits.
    EtaInput eta_in;
    eta_in.done_cost = done_cost_;
    eta_in.done_wall = done_wall_;
    eta_in.queued_cost = left_cost_;
    eta_in.workers = std::max(1, stats_.workers);
    std::map<int, std::pair<Clock::time_point, std::size_t>> first;  // rank -> oldest hand-out
    for (const auto& [idx, held] : running_) {
      auto it = first.find(held.rank);
      if (it == first.end() || held.handed < it->second.first)
        first[held.rank] = {held.handed, idx};
    }
    for (const auto& [rank, oldest] : first) {
      const auto freed = freed_.find(rank);
      const Clock::time_point start =
          freed == freed_.end() ? oldest.first : std::max(oldest.first, freed->second);
      const double c = cost(CaseTask{oldest.second, 1, 0, false});
      eta_in.running.push_back({c, since(start)});
      eta_in.queued_cost -= c;
    }
    const double eta = estimate_eta(eta_in);
    const int running = static_cast<int>(first.size());  // held but waiting counts as left
    const int left = in_.total - done_ - failed_ - running;
    std::ostringstream os;
    os << "[campaign] ";
    if (!event.empty()) os << event << "\n[campaign] ";
    os << "done " << done_ << " | running " << running << " | failed " << failed_ << " | left "
       << left << " of " << in_.total << " | elapsed " << format_hms(el) << " | ETA "
       << format_hms(eta);
    *in_.out << os.str() << std::endl;
    last_line_ = Clock::now();
  }

  const CaseContext& ctx_;
  const ScheduleInput& in_;
  std::vector<std::string> hosts_;
  std::deque<CaseTask> queue_;
  struct Held {
    int group, rank;           // rank group, world rank of its leader
    Clock::time_point handed;  // when the case was handed out
  };
  std::map<std::size_t, Held> running_;     // case index -> who holds it
  std::map<int, Clock::time_point> freed_;  // world rank -> when its last case ended
  int done_ = 0, failed_ = 0;
  double left_cost_ = 0, done_cost_ = 0, done_wall_ = 0;
  ScheduleStats stats_;
  Clock::time_point t0_ = Clock::now(), last_tick_ = Clock::now(), last_line_ = Clock::now();
};

// Rank 0's loop. Each remote group holds up to two cases, the one it runs and the next, so that
// it never waits for a reply between cases (the second is granted only while the queue is longer
// than there are groups: at the tail, cases go to whoever is free first).
ScheduleStats dispatch(const CaseContext& ctx, MPI_Comm world, const ScheduleInput& in,
                       const std::vector<std::string>& hosts, int ranks_per_case) {
  int size = 1, provided = MPI_THREAD_SINGLE;
  MPI_Comm_size(world, &size);
  MPI_Query_thread(&provided);
  // The local thread makes no MPI calls; with one rank nothing else does either.
  const bool local = size == 1 || provided >= MPI_THREAD_FUNNELED;
  std::map<int, int> held;    // remote group leader -> cases assigned and not yet reported
  std::map<int, bool> ready;  // leaders that have said hello and not been stopped
  for (int r = ranks_per_case; r < size; r += ranks_per_case) held[r] = 0;
  const std::size_t groups = held.size() + (local ? 1 : 0);
  Dispatcher d(ctx, in, hosts);
  d.stats().workers = static_cast<int>(groups);
  if (in.out && !local && size > 1)
    *in.out << "[campaign] MPI thread level below FUNNELED: rank 0 only dispatches" << std::endl;

  std::future<CaseOutcome> local_run;
  CaseTask local_task;
  bool local_busy = false;
  int stopped = 0;
  Outbox outbox(world);
  while (true) {
    bool progressed = false;
    if (local && !local_busy && d.next(local_task)) {
      d.started(local_task, 0, 0);
      local_run =
          std::async(std::launch::async, [&ctx, t = local_task] { return run_case(ctx, t); });
      local_busy = true;
      progressed = true;
    }
    if (local_busy && local_run.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      d.finished(local_task, local_run.get());
      local_busy = false;
      progressed = true;
    }
    int flag = 0;
    MPI_Status st;
    while (MPI_Iprobe(MPI_ANY_SOURCE, kTagResult, world, &flag, &st), flag) {
      int from = -1;
      const std::string msg = recv_string(st.MPI_SOURCE, kTagResult, world, &from);
      if (msg.empty()) {
        ready[from] = true;  // hello
      } else {
        CaseTask t;
        CaseOutcome o;
        if (!decode(msg, t, o))
          throw std::runtime_error("campaign: garbled result from rank " + std::to_string(from));
        d.finished(t, o);
        held[from] -= 1;
      }
      progressed = true;
    }
    for (auto& [rank, n] : held) {
      if (!ready[rank]) continue;
      while (n < 2 && (n == 0 || d.queued() > groups)) {
        CaseTask t;
        if (!d.next(t)) break;
        d.started(t, rank / ranks_per_case, rank);
        outbox.send(encode_task(t), rank, kTagAssign);
        n += 1;
        progressed = true;
      }
    }
    if (d.idle() && !local_busy) {
      for (auto& [rank, ok] : ready)
        if (ok) {
          outbox.send("stop", rank, kTagAssign);
          ok = false;
          ++stopped;
        }
      if (stopped == static_cast<int>(held.size())) break;
    }
    d.tick();
    outbox.progress();
    if (progressed) continue;
    // Sleep until the next poll, or until rank 0's own case ends, whichever comes first. While
    // that case runs, poll less often: its thread shares this rank's core, and the remote groups
    // hold their next case already, so a slower refill costs them nothing.
    if (local_busy)
      local_run.wait_for(kPollBusy);
    else
      std::this_thread::sleep_for(kPoll);
  }
  in.manifest->sync();
  ScheduleStats s = d.stats();
  s.loop_wall = since(d.start());
  return s;
}

// A group leader's loop: say hello, then run what arrives, reporting each result (which also
// asks for more). Cases that arrive while one runs wait in the inbox.
void work(const CaseContext& ctx, MPI_Comm world) {
  std::deque<std::string> inbox;
  Outbox outbox(world);
  outbox.send("", 0, kTagResult);
  while (true) {
    if (inbox.empty()) inbox.push_back(recv_string_sleeping(0, kTagAssign, world));
    int flag = 0;
    while (MPI_Iprobe(0, kTagAssign, world, &flag, MPI_STATUS_IGNORE), flag)
      inbox.push_back(recv_string(0, kTagAssign, world));
    const std::string msg = inbox.front();
    inbox.pop_front();
    if (msg == "stop") return;
    const CaseTask t = decode_task(msg);
    outbox.send(encode(t, run_case(ctx, t)), 0, kTagResult);
  }
}

}  // namespace

double ScheduleStats::overhead() const {
  if (workers <= 0 || loop_wall <= 0) return 0;
  return 1.0 - case_wall / (workers * loop_wall);
}

void sleeping_barrier(MPI_Comm comm) {
  MPI_Request req;
  MPI_Ibarrier(comm, &req);
  int flag = 0;
  while (MPI_Test(&req, &flag, MPI_STATUS_IGNORE), !flag) std::this_thread::sleep_for(kPoll);
}

ScheduleStats schedule(const CaseContext& ctx, MPI_Comm world, const ScheduleInput& in) {
  int rank = 0, size = 1;
  MPI_Comm_rank(world, &rank);
  MPI_Comm_size(world, &size);
  const int rpc = ctx.spec->ranks_per_case;
  // Rank groups: consecutive ranks share a case. The engine takes a group communicator
  // (RunOptions::comm); groups still have one rank (validated in the spec) until the dispatcher
  // hands a case to a whole group and the collectors sample the gathered bed (docs/parallel.md).
  MPI_Comm group;
  MPI_Comm_split(world, rank / rpc, rank, &group);
  CaseContext local = ctx;
  local.group = group;

  // Host names for the manifest.
  const std::string me = processor_name();
  std::vector<char> all(static_cast<std::size_t>(size) * MPI_MAX_PROCESSOR_NAME, '\0');
  std::vector<char> mine(MPI_MAX_PROCESSOR_NAME, '\0');
  me.copy(mine.data(), mine.size() - 1);
  MPI_Gather(mine.data(), MPI_MAX_PROCESSOR_NAME, MPI_CHAR, all.data(), MPI_MAX_PROCESSOR_NAME,
             MPI_CHAR, 0, world);

  ScheduleStats stats;
  try {
    if (rank == 0) {
      std::vector<std::string> hosts;
      for (int r = 0; r < size; ++r)
        hosts.emplace_back(&all[static_cast<std::size_t>(r) * MPI_MAX_PROCESSOR_NAME]);
      stats = dispatch(local, world, in, hosts, rpc);
    } else if (rank % rpc == 0) {
      work(local, world);
    }
  } catch (const std::exception& e) {
    // A failure of the scheduler itself (not of a case): nothing sensible to continue with.
    std::fprintf(stderr, "tumble campaign: rank %d: %s\n", rank, e.what());
    MPI_Abort(world, 1);
  }
  MPI_Comm_free(&group);
  return stats;
}

}  // namespace tumble::campaign
