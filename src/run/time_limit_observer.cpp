#include "run/time_limit_observer.hpp"

#include <mpi.h>

#include <string>

namespace tumble {

void TimeLimitObserver::check(const RunState& s) const {
  double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  // The run's rank 0 decides for all its ranks: their clocks started at slightly different
  // moments, and a rank that stopped alone would leave the others waiting in a collective.
  if (s.comm != MPI_COMM_NULL) MPI_Bcast(&el, 1, MPI_DOUBLE, 0, s.comm);
  if (el > limit_)
    throw TimeLimitError("time limit: the attempt ran " + std::to_string(el) +
                         " s wall, more than its limit of " + std::to_string(limit_) +
                         " s (at step " + std::to_string(s.sim.step_count()) + ")");
}

}  // namespace tumble
