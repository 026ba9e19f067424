#pragma once
// Particle snapshots (snap_NNNNNN.h5 with snapshots.xdmf for ParaView) every
// output.snapshot_interval of simulated time (one per iteration by default), at step 0 and at the
// protocol's end.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "run/observer.hpp"

namespace tumble {

// The step of the k-th snapshot: the step nearest k intervals (interval_steps = interval / dt,
// at least 1). Not k × round(interval / dt): rounding the interval once makes snapshot k drift by
// k times the rounding (1e-4 of an iteration at k = 35 for one per iteration, past the analysis'
// 1e-3 window slack near k = 1,000); this stays within half a step of k intervals for any k, and
// the k-th stroboscopic snapshot of a protocol of k iterations falls on its last step, so the end
// is not written twice a few steps apart.
inline std::int64_t snapshot_step(std::int64_t k, double interval_steps) {
  return std::llround(static_cast<double>(k) * std::max(1.0, interval_steps));
}

class SnapshotObserver : public Observer {
 public:
  explicit SnapshotObserver(double interval_steps) : interval_steps_(interval_steps) {}
  void start(RunState& s) override { write(s); }
  void after_step(RunState& s) override;

 private:
  void write(RunState& s);
  double interval_steps_;
};

}  // namespace tumble
