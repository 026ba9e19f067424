#include "campaign/fault_injection.hpp"

#include <cstdint>
#include <cstdlib>
#include <sstream>

#include "base/comm.hpp"
#include "run/run_state.hpp"

namespace tumble::campaign {
namespace {

class EscapeInjector : public Observer {
 public:
  EscapeInjector(int rank, std::int64_t step) : rank_(rank), step_(step) {}
  void after_step(RunState& s) override {
    Simulation& sim = s.sim;
    // Observers run before the health check of the same step (run/realization.cpp), which then
    // finds the particle outside on this rank only.
    if (done_ || sim.step_count() < step_ || sim.step_count() % 1000 != 0) return;
    done_ = true;
    if (rank_in(s.comm) != rank_ || sim.local_count() == 0) return;
    sim.particles().x[0] = Vec3{3 * s.scene.radius, 0, 0};
  }

 private:
  int rank_;
  std::int64_t step_;
  bool done_ = false;
};

}  // namespace

std::unique_ptr<Observer> fault_injection_for(const std::string& case_id) {
  const char* env = std::getenv("TUMBLE_TEST_FAULT");
  if (!env) return nullptr;
  std::string spec(env), id;
  for (char& ch : spec)
    if (ch == ':') ch = ' ';
  std::istringstream is(spec);
  int rank = 0;
  long long step = 0;
  if (!(is >> id >> rank >> step) || id != case_id) return nullptr;
  return std::make_unique<EscapeInjector>(rank, step);
}

}  // namespace tumble::campaign
