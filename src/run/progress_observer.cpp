#include "run/progress_observer.hpp"

#include <iomanip>
#include <ostream>

#include "base/text_util.hpp"
#include "run/run_state.hpp"

namespace tumble {

void ProgressObserver::after_step(RunState& s) {
  using Clock = std::chrono::steady_clock;
  if (!s.log) return;
  if (!started_) {  // the interval counts from the start of the protocol loop
    last_ = s.started;
    started_ = true;
  }
  const Simulation& sim = s.sim;
  const std::int64_t step = sim.step_count();
  if ((step & 63) != 0 ||
      std::chrono::duration<double>(Clock::now() - last_).count() < s.scene.progress_interval)
    return;
  last_ = Clock::now();
  std::ostream& log = *s.log;
  const double el = std::chrono::duration<double>(last_ - s.started).count();
  const double rate = (step - s.first_step) * static_cast<double>(s.particles) / el;
  const double eta = el / (step - s.first_step) * (s.end_step - step);
  log << "[run] t = " << std::fixed << std::setprecision(3) << sim.time() << " s  ";
  if (s.scene.mode == Mode::single_axis)  // constant rotation: count revolutions
    log << "rev " << std::setprecision(2) << s.scene.omega() * sim.time() / (2 * kPi);
  else
    log << "iter " << std::setprecision(2) << sim.protocol().iteration(sim.time()) << " ("
        << sim.protocol().phase(sim.time()) << ")";
  log << "  step " << step << "/" << s.end_step << "  " << std::scientific << std::setprecision(2)
      << rate << " particle-steps/s  ETA " << format_hms(eta) << std::defaultfloat;
  if (sim.rigid_bulk())
    log << "  frozen " << std::fixed << std::setprecision(3) << sim.frozen_fraction()
        << std::defaultfloat;
  if (const parallel::Domain* dom = sim.domain())
    log << "  " << dom->size() << " ranks, imbalance " << std::fixed << std::setprecision(3)
        << dom->imbalance() << std::defaultfloat;
  log << std::endl;
  if (then_) then_(s);
}

}  // namespace tumble
