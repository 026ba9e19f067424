#pragma once
// Checkpoints: the complete engine state, written atomically (temp file + rename).
//
// Bitwise restarts: a checkpoint is taken at the end of a step whose neighbour list was rebuilt
// (the run loop forces that rebuild), and it stores particles in memory order with their forces.
// A restart rebuilds the list from the same positions in the same order (the cell sort is stable
// and idempotent), re-attaches the springs by global id and reuses the stored forces, so every
// later floating-point operation repeats exactly.
#include <string>

#include "analysis/radial_segregation.hpp"
#include "core/scene.hpp"
#include "core/simulation.hpp"

namespace tumble::io {

struct CheckpointData {
  Particles particles;
  neighbor::ContactHistory history;
  double time = 0;
  std::int64_t step = 0;
  analysis::Series series;
  std::string scene_text;  // the scene that wrote it
  std::int64_t snapshots_written = 0;
};

void write_checkpoint(const std::string& path, const Simulation& sim, const Scene& scene,
                      const analysis::Series& series, std::int64_t snapshots_written);
CheckpointData read_checkpoint(const std::string& path);

}  // namespace tumble::io
