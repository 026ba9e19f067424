#pragma once
// An observer of one realization: something the run loop calls around every time step without
// the engine knowing of it (series sampling, snapshots, checkpoints, the MCM's drift grid, health
// checks, progress lines, a campaign's field collector or wall-clock limit). run_realization
// calls the observers of its list in order, so an observer that records what others produced
// (the checkpoint: the series, the snapshots written) comes after them. Virtual calls happen
// once per observer per step, never per particle or contact.
#include <cstdint>

namespace tumble {

struct RunState;

class Observer {
 public:
  virtual ~Observer() = default;
  // Once, at step 0 of a fresh run (a restarted run observed its step 0 before).
  virtual void start(RunState&) {}
  // Before the step that brings the step count to `next`.
  virtual void before_step(RunState&, std::int64_t /*next*/) {}
  // After every step.
  virtual void after_step(RunState&) = 0;
  // Once, after the last step of this call (files that summarise the run).
  virtual void finish(RunState&) {}
};

}  // namespace tumble
