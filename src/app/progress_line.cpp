#include "app/progress_line.hpp"

#include <algorithm>
#include <cstdio>

#include "base/text_util.hpp"

namespace tumble::app {

ProgressLine::ProgressLine(std::string tag, double interval) : state_(std::make_shared<State>()) {
  state_->tag = std::move(tag);
  state_->interval = interval;
  state_->start = state_->stage_start = state_->last = Clock::now();
}

cm::Progress ProgressLine::stage(const std::string& name) {
  if (state_->interval <= 0) return {};
  State& s = *state_;
  s.stage = name;
  s.stage_start = Clock::now();
  const int id = ++s.stage_id;
  // The reporter holds the state, not this object; a reporter of an ended stage stays silent.
  return [st = state_, id](double done) {
    if (st->stage_id != id) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - st->last).count() < st->interval) return;
    st->last = now;
    done = std::clamp(done, 0.0, 1.0);
    const double elapsed = std::chrono::duration<double>(now - st->start).count();
    const double in_stage = std::chrono::duration<double>(now - st->stage_start).count();
    const double eta = done > 0 ? in_stage / done * (1 - done) : -1;
    std::printf("[%s] %s: %.1f%%  elapsed %s  ETA %s\n", st->tag.c_str(), st->stage.c_str(),
                100 * done, format_hms(elapsed).c_str(), format_hms(eta).c_str());
    std::fflush(stdout);
  };
}

}  // namespace tumble::app
