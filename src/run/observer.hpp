#pragma once
// An observer of one realization: something the run loop calls around every time step without
// the engine knowing of it (series sampling, snapshots, checkpoints, the MCM's drift grid, health
// checks, progress lines, a campaign's field collector or wall-clock limit). run_realization
// calls the observers of its list in order, so an observer that records what others produced
// (the checkpoint: the series, the snapshots written) comes after them. Virtual calls happen
// once per observer per step, never per particle or contact.
//
// A decomposed run (RunOptions::comm of several ranks) has one instance of each observer on
// every rank, called at the same steps. An observer that measures the whole bed either reduces
// its own ranks' particles over RunState::comm or asks for RunState::whole_bed() (collective:
// every rank asks at the same step); files are written by the run's rank 0 (RunState::lead()),
// and a decision that stops the run (health, time limit) is taken for all ranks together, since a
// rank that stopped alone would leave the others waiting in the next collective.
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
