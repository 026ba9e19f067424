#include "run/run_state.hpp"

namespace tumble {

bool RunState::lead() const {
  int r = 0;
  if (comm != MPI_COMM_NULL) MPI_Comm_rank(comm, &r);
  return r == 0;
}

const Particles& RunState::whole_bed() {
  if (comm == MPI_COMM_NULL) return sim.particles();
  if (gathered_at_ != sim.step_count()) {
    gathered_ = sim.gather_all();
    gathered_at_ = sim.step_count();
  }
  return gathered_;
}

}  // namespace tumble
