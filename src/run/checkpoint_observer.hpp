#pragma once
// Checkpoints (checkpoint.h5, written atomically) every output.checkpoint_interval of simulated
// time (one per iteration by default), at the protocol's end and where this call stops
// (--max-steps), so a run can always be continued. The neighbour list is rebuilt in the step
// before a checkpoint: a restart rebuilds it from the same sorted particles, which is what makes
// the continued run bitwise identical. Comes after the observers whose data it saves (the series,
// the snapshots written, a campaign's collector state).
//
// Also, so that a kill never loses more than output.checkpoint_wall of wall time (10 minutes by
// default; a bst_paper iteration is hours): once that much wall time has passed since the last
// checkpoint, one is written after the next step in which the engine rebuilt its neighbour list
// by itself. Such a step leaves the engine exactly as a forced rebuild does, so the checkpoint
// changes nothing in the run (forcing a rebuild at a wall-clock moment would make the trajectory
// depend on the machine's speed) and a restart from it is still bitwise. On a decomposed run
// rank 0's clock decides.
//
// And on a stop request (SIGUSR1, SIGTERM, SIGINT: base/stop_request.hpp) the same: a checkpoint
// after the next step that rebuilt by itself, then the run ends with StopRequest, and its
// continuation is bitwise the run that was never stopped. A bed that goes more than
// kStopWait steps without a rebuild (a still one) gets a forced rebuild instead: that run's
// continuation then differs from the unstopped one in round-off. The ranks agree (one reduction
// of a few bits) at every rebuild and every kStopPoll steps, so a signal that reached only some
// ranks still stops them all together.
#include <chrono>
#include <cstdint>
#include <string>

#include "run/observer.hpp"

namespace tumble {

class CheckpointObserver : public Observer {
 public:
  static constexpr std::int64_t kStopPoll = 256;   // steps between checks when nothing rebuilds
  static constexpr std::int64_t kStopWait = 1000;  // steps to wait for a rebuild before forcing one

  CheckpointObserver(std::string path, std::int64_t every_steps, double wall_seconds)
      : path_(std::move(path)), every_(every_steps), wall_(wall_seconds) {}
  void start(RunState& s) override;
  void before_step(RunState& s, std::int64_t next) override;
  void after_step(RunState& s) override;

 private:
  using Clock = std::chrono::steady_clock;
  enum Request : int { kLate = 1, kStop = 2 };
  bool due(const RunState& s, std::int64_t step) const;
  int agreed_requests(const RunState& s, bool rebuilt) const;
  void write(RunState& s);
  std::string path_;
  std::int64_t every_;
  double wall_;
  Clock::time_point last_ = Clock::now();
  // The engine's rebuild count at the last step, taken before this call's first step (a
  // restart's load builds the list once, and start() runs only at step 0 of a fresh run: taken
  // there alone, the first step of a resumed call counted as a rebuild, and a stop that came
  // while the checkpoint loaded wrote one at a step the engine did not rebuild at, which the
  // next resume could not continue bit for bit).
  std::uint64_t rebuilds_seen_ = 0;
  bool primed_ = false;
  int stop_signal_ = 0;          // agreed: the run stops at its next rebuild
  std::int64_t stop_asked_ = 0;  // the step at which the ranks agreed
};

}  // namespace tumble
