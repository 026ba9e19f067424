#pragma once
// Particle snapshots (snap_NNNNNN.h5 with snapshots.xdmf for ParaView) every
// output.snapshot_interval of simulated time (one per iteration by default), at step 0 and at the
// protocol's end.
#include <cstdint>

#include "run/observer.hpp"

namespace tumble {

class SnapshotObserver : public Observer {
 public:
  explicit SnapshotObserver(std::int64_t every_steps) : every_(every_steps) {}
  void start(RunState& s) override { write(s); }
  void after_step(RunState& s) override;

 private:
  void write(RunState& s);
  std::int64_t every_;
};

}  // namespace tumble
