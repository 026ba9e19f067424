#include "run/checkpoint_observer.hpp"

#include <mpi.h>

#include <chrono>
#include <iomanip>
#include <sstream>

#include "base/stop_request.hpp"
#include "io/checkpoint.hpp"
#include "run/run_state.hpp"

namespace tumble {

bool CheckpointObserver::due(const RunState& s, std::int64_t step) const {
  return step % every_ == 0 || step == s.total_steps || step == s.end_step;
}

void CheckpointObserver::start(RunState& s) {
  rebuilds_seen_ = s.sim.rebuilds();
  primed_ = true;
}

void CheckpointObserver::before_step(RunState& s, std::int64_t next) {
  if (!primed_) {
    rebuilds_seen_ = s.sim.rebuilds();
    primed_ = true;
  }
  if (due(s, next) || (stop_signal_ != 0 && next - stop_asked_ >= kStopWait))
    s.sim.request_rebuild();
}

// What the ranks ask for together: kLate from rank 0's clock (at rebuilds), kStop from any rank's
// signal, with the signal's number above those bits (the largest, should ranks differ).
// Collective: called at the same steps on every rank (rebuilds are collective).
int CheckpointObserver::agreed_requests(const RunState& s, bool rebuilt) const {
  int ask[2] = {0, stop_signal()};
  if (rebuilt && wall_ > 0 && s.lead() &&
      std::chrono::duration<double>(Clock::now() - last_).count() >= wall_)
    ask[0] = kLate;
  if (s.comm != MPI_COMM_NULL) MPI_Allreduce(MPI_IN_PLACE, ask, 2, MPI_INT, MPI_MAX, s.comm);
  return ask[0] | (ask[1] != 0 ? kStop | (ask[1] << 2) : 0);
}

void CheckpointObserver::after_step(RunState& s) {
  const std::int64_t step = s.sim.step_count();
  const bool rebuilt = s.sim.rebuilds() != rebuilds_seen_;
  rebuilds_seen_ = s.sim.rebuilds();
  int ask = 0;
  if (rebuilt || step % kStopPoll == 0) ask = agreed_requests(s, rebuilt);
  if ((ask & kStop) && stop_signal_ == 0) {
    stop_signal_ = ask >> 2;
    stop_asked_ = step;
  }
  if (due(s, step) || (rebuilt && ((ask & kLate) || stop_signal_ != 0))) write(s);
  if (stop_signal_ != 0 && rebuilt && step < s.end_step) {  // (at the end: simply done)
    // This call's steps and wall time, as the done line of a finished call gives them, so that
    // a run made of stopped and resumed calls can be costed from its log (pattern_table.py).
    const double wall = std::chrono::duration<double>(Clock::now() - s.started).count();
    const std::int64_t steps = step - s.first_step;
    std::ostringstream os;
    os << "stopped by " << signal_name(stop_signal_) << " at step " << step << " of "
       << s.total_steps << " (t = " << s.sim.time() << " s): checkpoint written to " << path_
       << "; this call ran " << steps << " steps in " << std::setprecision(4) << wall << " s ("
       << std::scientific << std::setprecision(3)
       << (wall > 0 ? static_cast<double>(steps) * static_cast<double>(s.particles) / wall : 0.0)
       << " particle-steps/s)";
    throw StopRequest(os.str());
  }
}

void CheckpointObserver::write(RunState& s) {
  s.sim.check_health();
  std::vector<double> times;  // the snapshot list a resumed run rebuilds
  times.reserve(s.snapshots.size());
  for (const auto& e : s.snapshots) times.push_back(e.time);
  io::write_checkpoint(path_, s.sim, s.scene, s.series, times, s.drift);
  last_ = Clock::now();
}

}  // namespace tumble
