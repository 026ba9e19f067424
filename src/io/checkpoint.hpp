#pragma once
// Checkpoints: the complete engine state, written atomically (temp file + rename).
//
// Bitwise restarts: a checkpoint is taken at the end of a step whose neighbour list was rebuilt
// (the run loop forces that rebuild), and it stores particles in memory order with their forces.
// A restart rebuilds the list from the same positions in the same order (the cell sort is stable
// and idempotent), re-attaches the springs by global id and reuses the stored forces, so every
// later floating-point operation repeats exactly.
//
// Domain-decomposed runs write one file collectively (parallel HDF5): each rank its own particles
// and contact records, one after the other. The layout is the same as a serial checkpoint's, and
// any number of ranks can read it (each takes a block of rows; the engine moves them to their
// owners), so a checkpoint written on 2 ranks restarts on 1 or 3 and vice versa. Each contact
// record carries an anchor (where the pair was) that routes it to the ranks near the pair.
#include <memory>
#include <string>

#include "analysis/radial_segregation.hpp"
#include "cm/drift_grid.hpp"
#include "engine/simulation.hpp"
#include "scene/scene.hpp"

namespace tumble::io {

struct CheckpointData {
  Particles particles;
  neighbor::ContactHistory history;
  // Whether the records hold their pair's position (contacts/anchor; files written before
  // 2026-11-23 lack it, and their records read as anchored at the origin).
  bool anchored = true;
  double time = 0;
  std::int64_t step = 0;
  analysis::Series series;
  cm::DriftStatistics drift;  // empty unless the run measured the drift grid
  std::string scene_text;     // the scene that wrote it
  std::int64_t snapshots_written = 0;
  // Each snapshot's simulated time, for the resumed run's list (snapshots.xdmf); empty in files
  // written before 2026-11-28, whose times are rebuilt from the snapshot interval.
  std::vector<double> snapshot_times;
  // The samples a measurement that runs the engine before a protocol has taken so far (the
  // repose angle's, run/repose_measure.cpp); empty in a run's checkpoint.
  std::vector<double> measure_samples;
  // The boxes of the ranks that wrote it (Simulation::decomposition), when it is read on as many
  // ranks (each rank then holds the rows it wrote, in their order); empty otherwise.
  std::vector<double> domain_tree;
};

void write_checkpoint(const std::string& path, const Simulation& sim, const Scene& scene,
                      const analysis::Series& series, const std::vector<double>& snapshot_times,
                      const cm::DriftStatistics& drift = {},
                      const std::vector<double>& measure_samples = {});
// Whole checkpoint (serial), or with `comm` of more than one rank this rank's block of the
// particle rows and of the contact records (collective).
// Refuses (CorruptInputError, naming file and dataset) a file whose checksums fail or whose
// contents Tumble cannot have written: lengths that disagree, ids outside [0, N) or repeated,
// species other than 0 and 1, values that are not finite, non-positive radii, contact pairs of
// particles that do not exist. Every rank throws the same error.
CheckpointData read_checkpoint(const std::string& path, MPI_Comm comm = MPI_COMM_NULL);
// Whether `path` opens as a checkpoint Tumble wrote (its header only, no MPI): asked of
// `run --restart FILE` with the other input, so that a file that is not one is refused before
// the output folder is made or `--check` says the input is fine. CorruptInputError for a file
// HDF5 cannot open (damaged), InputError for an HDF5 file that is not a Tumble checkpoint.
void check_is_checkpoint(const std::string& path);
// The checks that need the scene the run restarts with (collective over `comm` like
// read_checkpoint): each particle's radius is its species' diameter (within particles.size_spread),
// every centre lies inside the tumbler within one d_large, and the time agrees with step x dt.
void check_checkpoint_fits(const CheckpointData& c, const Scene& scene, const std::string& path,
                           MPI_Comm comm = MPI_COMM_NULL);
// The engine that goes on from `c` (read by read_checkpoint on `comm`): its particles (moved out of
// `c`), its springs, and on as many ranks as wrote it their boxes, so that the run continues bit
// for bit. Collective; CorruptInputError (naming `path`) for boxes that are not a decomposition.
std::unique_ptr<Simulation> engine_from_checkpoint(CheckpointData& c, const Scene& scene,
                                                   const geometry::Protocol& protocol,
                                                   const std::string& path,
                                                   MPI_Comm comm = MPI_COMM_NULL);

}  // namespace tumble::io
