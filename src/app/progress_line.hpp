#pragma once
// Progress lines of a long `tumble cm` computation, on stdout like `tumble run`'s own
// ("[run] ... ETA h:mm:ss"): at most one every `interval` wall seconds, so a run shorter than
// that prints none. A line names the stage, its share done, the wall time since the command
// started and the stage's ETA (its elapsed time / share done x share left):
//   [cm orbits] periodic points, period <= 6: 42.0%  elapsed 0:00:12  ETA 0:00:16
#include <chrono>
#include <memory>
#include <string>

#include "cm/progress.hpp"

namespace tumble::app {

class ProgressLine {
 public:
  // `tag`: "cm orbits"; `interval` in seconds, <= 0 for no lines at all.
  ProgressLine(std::string tag, double interval);
  // Starts a stage and returns its reporter (cm::Progress); the previous stage ends.
  cm::Progress stage(const std::string& name);

 private:
  using Clock = std::chrono::steady_clock;
  struct State {
    std::string tag, stage;
    double interval = 0;
    Clock::time_point start, stage_start, last;
    int stage_id = 0;
  };
  std::shared_ptr<State> state_;
};

}  // namespace tumble::app
