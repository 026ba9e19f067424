#include "run/time_limit_observer.hpp"

#include <mpi.h>

#include <string>

namespace tumble {

void check_time_limit(std::chrono::steady_clock::time_point t0, double limit_seconds, MPI_Comm comm,
                      const std::string& where) {
  double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // The run's rank 0 decides for all its ranks: their clocks started at slightly different
  // moments, and a rank that stopped alone would leave the others waiting in a collective.
  if (comm != MPI_COMM_NULL) MPI_Bcast(&el, 1, MPI_DOUBLE, 0, comm);
  if (el > limit_seconds)
    throw TimeLimitError("time limit: the attempt ran " + std::to_string(el) +
                         " s wall, more than its limit of " + std::to_string(limit_seconds) +
                         " s (" + where + ")");
}

void TimeLimitObserver::check(const RunState& s) const {
  check_time_limit(t0_, limit_, s.comm, "at step " + std::to_string(s.sim.step_count()));
}

}  // namespace tumble
