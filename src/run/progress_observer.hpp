#pragma once
// Progress lines every scene.progress_interval wall seconds (checked every 64 steps): simulated
// time, iteration and phase (revolutions for a constant spin), step, particle-steps per second,
// ETA, and for a decomposed run the rank count and load imbalance.
#include <chrono>
#include <functional>
#include <utility>

#include "run/observer.hpp"

namespace tumble {

class ProgressObserver : public Observer {
 public:
  // `then`: called after each line (RunOptions::on_progress), if set.
  explicit ProgressObserver(std::function<void(const RunState&)> then = {})
      : then_(std::move(then)) {}
  void after_step(RunState& s) override;

 private:
  std::function<void(const RunState&)> then_;
  std::chrono::steady_clock::time_point last_{};
  bool started_ = false;
};

}  // namespace tumble
