#include "run/run_state.hpp"

#include "base/comm.hpp"

namespace tumble {

bool RunState::lead() const { return rank_in(comm) == 0; }

const Particles& RunState::whole_bed() {
  if (comm == MPI_COMM_NULL) return sim.particles();
  if (gathered_at_ != sim.step_count()) {
    gathered_ = sim.gather_all();
    gathered_at_ = sim.step_count();
  }
  return gathered_;
}

}  // namespace tumble
