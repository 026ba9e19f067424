#pragma once
// Checkpoints (checkpoint.h5, written atomically) every output.checkpoint_interval of simulated
// time (one per iteration by default), at the protocol's end and where this call stops
// (--max-steps), so a run can always be continued. The neighbour list is rebuilt in the step
// before a checkpoint: a restart rebuilds it from the same sorted particles, which is what makes
// the continued run bitwise identical. Comes after the observers whose data it saves (the series,
// the snapshots written, a campaign's collector state).
#include <cstdint>
#include <string>

#include "run/observer.hpp"

namespace tumble {

class CheckpointObserver : public Observer {
 public:
  CheckpointObserver(std::string path, std::int64_t every_steps)
      : path_(std::move(path)), every_(every_steps) {}
  void before_step(RunState& s, std::int64_t next) override;
  void after_step(RunState& s) override;

 private:
  bool due(const RunState& s, std::int64_t step) const;
  std::string path_;
  std::int64_t every_;
};

}  // namespace tumble
