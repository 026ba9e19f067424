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
// rank 0's clock decides, broadcast at rebuild steps only.
#include <chrono>
#include <cstdint>
#include <string>

#include "run/observer.hpp"

namespace tumble {

class CheckpointObserver : public Observer {
 public:
  CheckpointObserver(std::string path, std::int64_t every_steps, double wall_seconds)
      : path_(std::move(path)), every_(every_steps), wall_(wall_seconds) {}
  void start(RunState& s) override;
  void before_step(RunState& s, std::int64_t next) override;
  void after_step(RunState& s) override;

 private:
  using Clock = std::chrono::steady_clock;
  bool due(const RunState& s, std::int64_t step) const;
  bool wall_due(const RunState& s);
  void write(RunState& s);
  std::string path_;
  std::int64_t every_;
  double wall_;
  Clock::time_point last_ = Clock::now();
  std::uint64_t rebuilds_seen_ = 0;
};

}  // namespace tumble
