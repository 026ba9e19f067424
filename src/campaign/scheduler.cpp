#include "campaign/scheduler.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <list>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "base/stop_request.hpp"
#include "campaign/dispatcher.hpp"
#include "campaign/rank_pool.hpp"

namespace tumble::campaign {
namespace {
using Clock = std::chrono::steady_clock;
constexpr int kTagResult = 4101;    // group leader -> rank 0: the outcome of a case
constexpr int kTagAssign = 4102;    // rank 0 -> every rank of a group: an Assignment, or "stop"
constexpr int kTagGroup = 4103;     // MPI_Comm_create_group of a case's ranks
constexpr int kTagProgress = 4104;  // group leader -> rank 0: how far its case is (CaseProgress)
constexpr auto kPoll = std::chrono::microseconds(200);
// A rank that waits long (an idle group for the rest of a campaign, a barrier behind a long case)
// polls ever less often, up to every kPollMax: at a steady 200 us an idle rank took ~6% of a core
// (a 1-case campaign on 2 ranks) and half a core beside two busy processes. 2 ms, not more: with
// 10 ms the 1,000 trivial cases of jobs/bench/bench_campaign_overhead.sh left the ranks idle
// 1.0-1.3% of the loop instead of 0.6-0.7% (results noticed up to 10 ms late).
constexpr auto kPollMax = std::chrono::microseconds(2000);

// Sleeps kPoll, then twice as long each time, up to kPollMax.
class Backoff {
 public:
  void sleep() {
    std::this_thread::sleep_for(wait_);
    wait_ = std::min(wait_ * 2, kPollMax);
  }
  void reset() { wait_ = kPoll; }

 private:
  std::chrono::microseconds wait_ = kPoll;
};

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
  Backoff backoff;
  while (true) {
    MPI_Iprobe(source, tag, comm, &flag, MPI_STATUS_IGNORE);
    if (flag) return recv_string(source, tag, comm);
    backoff.sleep();
  }
}

// An assignment: the case and the world ranks of its group, leader first.
struct Assignment {
  CaseTask task;
  std::vector<int> ranks;
};

std::string encode_assignment(const Assignment& a) {
  std::ostringstream os;
  const CaseTask& t = a.task;
  os << t.case_index << " " << t.attempt << " " << t.seed << " " << (t.fresh ? 1 : 0);
  for (int r : a.ranks) os << " " << r;
  return os.str();
}
Assignment decode_assignment(const std::string& s) {
  Assignment a;
  int fresh = 0;
  long long seed = 0;
  std::istringstream is(s);
  is >> a.task.case_index >> a.task.attempt >> seed >> fresh;
  a.task.seed = seed;
  a.task.fresh = fresh != 0;
  for (int r; is >> r;) a.ranks.push_back(r);
  if (a.ranks.empty()) throw std::runtime_error("campaign: garbled assignment '" + s + "'");
  return a;
}

std::string processor_name() {
  char name[MPI_MAX_PROCESSOR_NAME];
  int len = 0;
  MPI_Get_processor_name(name, &len);
  return std::string(name, static_cast<std::size_t>(len));
}

// The communicator of a case's group: MPI_COMM_NULL for one rank (a serial run), else made by
// the group's ranks alone.
MPI_Comm make_group(MPI_Comm world, const std::vector<int>& ranks) {
  if (ranks.size() == 1) return MPI_COMM_NULL;
  MPI_Group all, mine;
  MPI_Comm_group(world, &all);
  MPI_Group_incl(all, static_cast<int>(ranks.size()), ranks.data(), &mine);
  MPI_Comm comm;
  MPI_Comm_create_group(world, mine, kTagGroup, &comm);
  MPI_Group_free(&mine);
  MPI_Group_free(&all);
  return comm;
}
void free_group(MPI_Comm& comm) {
  if (comm != MPI_COMM_NULL) MPI_Comm_free(&comm);
}

// One case on this rank's share of its group.
CaseOutcome run_assignment(const CaseContext& ctx, MPI_Comm world, const Assignment& a,
                           std::function<void()> poll) {
  MPI_Comm group = make_group(world, a.ranks);
  CaseContext mine = ctx;
  mine.group = group;
  mine.poll = std::move(poll);
  CaseOutcome o = run_case(mine, a.task);
  free_group(group);
  return o;
}

// World rank 0: hands out cases and runs its own group's share of them. pump() is the whole of
// the dispatching (results in, assignments out, progress); the main loop calls it between cases,
// and a case that rank 0 computes calls it between its time steps.
class Coordinator {
 public:
  Coordinator(const CaseContext& ctx, MPI_Comm world, const ScheduleInput& in,
              std::vector<std::string> hosts)
      : ctx_(ctx),
        world_(world),
        pool_(static_cast<int>(hosts.size())),
        book_(ctx, in, std::move(hosts), pool_.size()),
        outbox_(world) {
    book_.stats().ranks = pool_.size();
  }

  ScheduleStats run() {
    Backoff backoff;  // rank 0 without a case of its own waits for the others' results
    while (true) {
      pump();
      if (local_pending_) {
        local_pending_ = false;
        run_local();
        backoff.reset();
        continue;
      }
      if (book_.idle()) break;
      backoff.sleep();
    }
    for (int r = 1; r < pool_.size(); ++r) outbox_.send("stop", r, kTagAssign);
    outbox_.drain();
    take_progress();  // (reports that came after their cases' results)
    book_.flush_unwritten();
    ScheduleStats s = book_.stats();
    s.loop_wall = since(book_.start());
    return s;
  }

 private:
  void pump() {
    if (const int signal = stop_signal(); signal != 0) book_.stop(signal);
    int flag = 0;
    MPI_Status st;
    while (MPI_Iprobe(MPI_ANY_SOURCE, kTagResult, world_, &flag, &st), flag) {
      int from = -1;
      const std::string msg = recv_string(st.MPI_SOURCE, kTagResult, world_, &from);
      CaseTask t;
      CaseOutcome o;
      if (!decode(msg, t, o))
        throw std::runtime_error("campaign: garbled result from rank " + std::to_string(from));
      const std::vector<int> ranks = book_.finished(t, o);
      auto it = held_.find(ranks);
      if (it != held_.end() && --it->second > 0) continue;  // its next case is already there
      if (it != held_.end()) held_.erase(it);
      pool_.release(ranks);
    }
    take_progress();
    // Strictly in queue order (largest first): a case waits until its group is free, so a big
    // case is never starved by small ones behind it.
    while (const CaseTask* next = book_.peek()) {
      if (book_.ranks_for(*next) > pool_.size())  // validated before; never wait for ever
        throw std::runtime_error("campaign: a case needs " +
                                 std::to_string(book_.ranks_for(*next)) + " ranks, the run has " +
                                 std::to_string(pool_.size()));
      const std::vector<int> ranks = pool_.place(book_.ranks_for(*next));
      if (ranks.empty()) break;
      const Assignment a{*next, ranks};
      pool_.take(ranks);
      if (ranks.front() == 0) {  // rank 0 is free only between its cases (in run())
        hand_out(a);
        local_ = a;
        local_pending_ = true;
        break;
      }
      hand_out(a);
      held_[ranks] = 1;
    }
    // A remote group also holds its next case while the queue is longer than there are groups,
    // so that it starts it without waiting for this rank's next poll (which, while rank 0
    // computes, comes only between its own time steps); at the tail, cases go to whoever is
    // free first.
    for (auto& [ranks, n] : held_) {
      const CaseTask* next = book_.peek(ranks);
      if (!next || n != 1 || book_.ranks_for(*next) != static_cast<int>(ranks.size()) ||
          book_.queued() <= static_cast<std::size_t>(pool_.size()) / ranks.size())
        continue;
      hand_out({*next, ranks});
      n = 2;
    }
    book_.tick();
    outbox_.progress();
  }

  // The remote leaders' progress reports (a report may arrive after its case's result: the
  // book ignores it then).
  void take_progress() {
    int flag = 0;
    MPI_Status st;
    while (MPI_Iprobe(MPI_ANY_SOURCE, kTagProgress, world_, &flag, &st), flag) {
      CaseProgress p;
      if (decode(recv_string(st.MPI_SOURCE, kTagProgress, world_), p)) book_.progress(p);
    }
  }

  // Sends the queue's head to every rank of the group but this one, and records it.
  void hand_out(const Assignment& a) {
    book_.pop();
    book_.started(a.task, a.ranks);
    for (int r : a.ranks)
      if (r != 0) outbox_.send(encode_assignment(a), r, kTagAssign);
  }

  void run_local() {
    const auto t0 = Clock::now();
    CaseContext mine = ctx_;
    mine.progress = [this](const CaseProgress& p) { book_.progress(p); };
    const CaseOutcome o = run_assignment(mine, world_, local_, [this] {
      const auto p0 = Clock::now();
      pump();
      ScheduleStats& s = book_.stats();
      s.poll_seconds += since(p0);
      s.polls += 1;
    });
    book_.stats().local_seconds += since(t0);
    pool_.release(book_.finished(local_.task, o));
  }

  const CaseContext& ctx_;
  MPI_Comm world_;
  RankPool pool_;
  Dispatcher book_;
  Outbox outbox_;
  Assignment local_;
  bool local_pending_ = false;
  std::map<std::vector<int>, int> held_;  // remote groups -> cases handed and not reported
};

// Every other rank: wait (sleeping) for an assignment, run the case with its group, and, as the
// group's leader, report the outcome.
void work(const CaseContext& ctx, MPI_Comm world) {
  int me = 0;
  MPI_Comm_rank(world, &me);
  Outbox outbox(world);
  CaseContext mine = ctx;  // a leader's progress reports go to rank 0 as they come
  mine.progress = [&outbox](const CaseProgress& p) { outbox.send(encode(p), 0, kTagProgress); };
  while (true) {
    const std::string msg = recv_string_sleeping(0, kTagAssign, world);
    if (msg == "stop") return;
    const Assignment a = decode_assignment(msg);
    const CaseOutcome o = run_assignment(mine, world, a, nullptr);
    if (a.ranks.front() == me) outbox.send(encode(a.task, o), 0, kTagResult);
  }
}

}  // namespace

double ScheduleStats::overhead() const {
  if (ranks <= 0 || loop_wall <= 0) return 0;
  return 1.0 - rank_seconds / (ranks * loop_wall);
}

double ScheduleStats::dispatch_share() const {
  return local_seconds > 0 ? poll_seconds / local_seconds : 0;
}

void sleeping_barrier(MPI_Comm comm) {
  MPI_Request req;
  MPI_Ibarrier(comm, &req);
  int flag = 0;
  Backoff backoff;
  while (MPI_Test(&req, &flag, MPI_STATUS_IGNORE), !flag) backoff.sleep();
}

ScheduleStats schedule(const CaseContext& ctx, MPI_Comm world, const ScheduleInput& in) {
  int rank = 0, size = 1;
  MPI_Comm_rank(world, &rank);
  MPI_Comm_size(world, &size);

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
      stats = Coordinator(ctx, world, in, hosts).run();
    } else {
      work(ctx, world);
    }
  } catch (const std::exception& e) {
    // A failure of the scheduler itself (not of a case): nothing sensible to continue with.
    std::fprintf(stderr, "tumble campaign: rank %d: %s\n", rank, e.what());
    MPI_Abort(world, 1);
  }
  return stats;
}

}  // namespace tumble::campaign
