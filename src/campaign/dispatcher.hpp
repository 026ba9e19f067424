#pragma once
// World rank 0's bookkeeping in a campaign (campaign/scheduler.hpp moves the messages): the queue
// of cases, which ranks run what, the manifest lines of every start and end, retries, the progress
// lines and their ETA, and the statistics of the invocation.
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "campaign/case_runner.hpp"
#include "campaign/eta.hpp"
#include "campaign/manifest.hpp"
#include "campaign/scheduler.hpp"

namespace tumble::campaign {

class Dispatcher {
 public:
  // `hosts`: the host of every world rank; `ranks`: how many of them can run cases.
  Dispatcher(const CaseContext& ctx, const ScheduleInput& in, std::vector<std::string> hosts,
             int ranks);

  // The next case to hand out (nullptr if none is due now) and the ranks it needs; pop() takes
  // that case off the queue. A retry waits out its back-off (kRetryDelay, doubling with each
  // attempt) while the cases behind it go ahead, so a fault that fails attempts at once (a full
  // disk) does not burn every attempt within a second. A case that would settle a bed or measure
  // a β that a case handed out before it is still preparing waits too (the cases behind it go
  // ahead): it finds them made once that case's protocol begins, instead of making them again
  // beside it (two points that differ only in keys outside the bed, such as fidelity.bulk, share
  // each replica's bed and β). `group`: the ranks the case would be held on, next in line, when
  // it is for a group that runs a case (a case preparing there is done before this one begins).
  const CaseTask* peek(const std::vector<int>& group = {});
  int ranks_for(const CaseTask& t) const;
  void pop();
  std::size_t queued() const { return queue_.size(); }
  bool idle() const { return queue_.empty() && running_.empty(); }

  void started(const CaseTask& t, const std::vector<int>& ranks);
  // Records the outcome (and queues a retry under the policy); returns the case's ranks. A case
  // handed to the same ranks before this one ended (held next in line) starts counting now.
  std::vector<int> finished(const CaseTask& t, const CaseOutcome& o);

  // A running case's progress from its group's leader (ignored if the case is not running or
  // the report is of an earlier attempt: reports and results travel apart).
  void progress(const CaseProgress& p);

  // A stop request (base/stop_request.hpp): no case starts any more; those running end at their
  // next checkpoint with the outcome "stopped" (recorded as such: a rerun continues them).
  void stop(int signal);
  bool stopping() const { return stop_signal_ != 0; }
  // A manifest line that cannot be written (a full disk, a quota) halts the campaign: no case
  // is handed out any more, while those running (and one held next on a group: handed out
  // already) go on to their end (their results are theirs to keep;
  // the scheduler cannot reach a remote group mid-case, and a stop would need a checkpoint
  // written to the same disk). The lines not written wait in order and are tried again before
  // each new one and at each tick, so none is lost if the disk gets room; they keep their time
  // stamps, which order the manifest's lines on reading. Before, the error ended the job with
  // MPI_Abort, and every running case lost its steps since its last checkpoint.
  bool halted() const { return !stats_.manifest_error.empty(); }
  // Tries the lines not written once more, and leaves those that still fail in
  // stats().unwritten (the end of the invocation).
  void flush_unwritten();
  // A status line now and then, the lines not written tried again, and the manifest flushed.
  void tick();
  ScheduleStats& stats() { return stats_; }
  std::chrono::steady_clock::time_point start() const { return t0_; }

 private:
  using Clock = std::chrono::steady_clock;
  double cost(const CaseTask& t) const;
  std::string case_label(const CaseTask& t) const;
  CaseRecord record(const CaseTask& t, const std::vector<int>& ranks) const;
  void line(const std::string& event, bool counts = false);
  // Appends `r` to the manifest after the lines still waiting; halts on the first failure.
  void append(const CaseRecord& r);
  // Writes the waiting lines in order; false (and they stay waiting) if one fails.
  bool write_waiting();
  // The cache files (settled bed, measured β) the case would make before its protocol begins:
  // those missing, none if it resumes from its checkpoint. Kept per case and seed once known.
  const std::vector<std::string>& files_to_prepare(const CaseTask& t);

  // Each group's running case (ranks -> case index): the one it was handed first; a later one
  // is held next in line (its leader may report before this one's result is in).
  std::map<std::vector<int>, std::size_t> running_cases() const;

  const CaseContext& ctx_;
  const ScheduleInput& in_;
  std::vector<std::string> hosts_;
  int ranks_ = 1;
  std::deque<CaseTask> queue_;
  std::deque<CaseTask>::iterator peeked_;
  std::map<std::size_t, Clock::time_point> not_before_;  // case index -> earliest retry
  struct Held {
    std::vector<int> ranks;    // the group's world ranks, leader first
    Clock::time_point handed;  // when the case was handed out (or, if held, when it started)
    CaseTask task;
    // Its leader's recent progress reports (the last kRecentReports: the rate the ETA takes is
    // over them, so that it follows a change of speed, a pause or a busier machine, within a
    // few progress intervals rather than averaging the whole call), and when the last came.
    std::deque<CaseProgress> recent;
    Clock::time_point reported_at;
    bool preparing = false;             // it said so and its protocol has not begun (bed, β)
    Clock::time_point preparing_since;  // when it said so
    std::vector<std::string> prepares;  // the files it makes before its protocol (as handed out)
    std::string start_line;  // held, and its group's last case ended while stopping: its start
                             // line, logged with its result unless that says "not begun"
  };
  std::map<std::size_t, Held> running_;  // case index -> who runs it
  std::map<std::pair<std::size_t, std::int64_t>, std::vector<std::string>> prepares_;  // memo
  std::string deferred_;  // why peek() passed over the queue's first due case ("": it did not)
  // Counts the changes a deferral depends on (hand-outs, results, reports); all_waiting_at_: the
  // count when every due case last waited on another's preparation.
  long long changes_ = 0, all_waiting_at_ = -1;
  std::vector<int> all_waiting_for_;  // the group of that peek
  // The running case of another group that is still preparing a file this one would make: its
  // index, or -1.
  long long preparing_its_files(const CaseTask& t, const std::vector<int>& group);
  int done_ = 0, failed_ = 0, stop_signal_ = 0;
  std::deque<CaseRecord> waiting_;  // manifest lines not yet written (halted), oldest first
  std::string last_append_error_;   // why the last write of a waiting line failed
  double done_cost_ = 0, done_rank_seconds_ = 0;
  std::map<std::string, EtaInput::Rate> done_by_point_;  // the cases done, by point (the ETA)
  // The preparations that ended in this invocation: their rank-seconds and the files they made.
  double prepared_rank_seconds_ = 0;
  int prepared_files_ = 0;
  // The distinct files the cases not begun will make that exist nowhere yet and that no running
  // case makes (the ETA; scenes are read only once a preparation has been measured).
  int files_left_to_prepare();
  std::set<std::string> on_disk_;  // the files it found made
  ScheduleStats stats_;
  Clock::time_point t0_ = Clock::now(), last_tick_ = Clock::now(), last_line_ = Clock::now();
};

}  // namespace tumble::campaign
