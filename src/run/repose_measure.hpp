#pragma once
// protocol.repose = "measured" (the default): the tilt β of the biaxial protocol is the dynamic
// angle of repose of the scene's own bed. Yu 2022 tilts each rotation to the bed's repose angle,
// which moves with the tier (Froude number, stiffness), f and R_ρ; a fixed 27° can cut the flowing
// layer obliquely.
//
// Measured as docs/accuracy.md measures the flowing layer: the settled bed turns about z (the
// protocol's first axis, in its sense) at the scene's ω through kReposeEndDeg; it turns as a solid
// until ~35° and flows after; the line fitted to the free surface (analysis/flow_profile.hpp) is
// sampled once per degree from kReposeSpinUpDeg to kReposeEndDeg and averaged. The cost is 80° of
// rotation, about a third of one (57°, 57°) iteration (57 + 57 + 4 × 27 degrees).
//
// fidelity.bulk_still_slope = "measured" comes from the same turn: the surface is sampled from
// the first degree, and the slope at which it starts to creep (its downhill speed stays above
// kCreepSpeed ωR for kCreepSamples samples, as jobs/accuracy/onset_table.py reads dynamic runs)
// less kStillSlopeMargin (scene/scene_keys.hpp) is the still slope (docs/accuracy.md, "The still
// surface"). A bed held still above that onset releases its creep as a burst; below it nothing is
// held.
//
// The values are properties of the bed (its seed included: every replica measures its own, so the
// result never depends on which case ran first) and are kept beside the cached bed; a run that
// resumes takes them from its checkpoint, whose scene text holds the numbers.
//
// The turn itself (hours on the paper's bed: 2 h of a core for bst_paper at `standard`) is kept
// like a run's protocol: on a stop signal and every output.checkpoint_wall of wall time, the
// engine and the samples so far go to a checkpoint beside the cached value (repose_turn_path),
// written after a step that rebuilt its neighbour list by itself, so the next run goes on from it
// and ends with the numbers the uninterrupted turn gives, bit for bit (on the same ranks). The
// file is removed once the values are cached; one that does not fit (another bed, damaged) is
// ignored with a line in the log and the turn starts again.
#include <mpi.h>

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "base/particles.hpp"
#include "scene/scene.hpp"

namespace tumble {

inline constexpr double kReposeSpinUpDeg = 40;  // the bed flows from ~35° (docs/accuracy.md)
inline constexpr double kReposeEndDeg = 80;
// The surface creeps: its downhill speed above this many ωR (a bed turning as a solid reads
// within ±0.06 ωR but for single samples), for this many samples in a row (degrees).
inline constexpr double kCreepSpeed = 0.1;
inline constexpr int kCreepSamples = 3;
// Bump when the measurement changes, so that cached values of the old procedure are not reused.
// 2: the turn samples from the first degree and also gives the creep onset.
inline constexpr int kReposeCodeVersion = 2;

// One sample of the turn: the wall's rotation so far, the fitted surface's slope (degrees) and the
// surface layer's mean downhill speed (m/s). A turn's file keeps them flat, three numbers each.
struct TurnSample {
  double rotation_deg = 0;
  double slope_deg = 0;
  double speed = 0;
};

struct ReposeMeasurement {
  double mean_deg = 0;  // β
  double sd_deg = 0;    // spread of the samples (correlated in time: not an error of the mean)
  int samples = 0;
  double creep_onset_deg = 0;  // the slope where the surface starts to creep (NaN: it never did)
};

// The slope of the first sample from which the speed stays above `creep_speed` for
// kCreepSamples samples of consecutive degrees (NaN if none).
double creep_onset_slope(const std::vector<TurnSample>& samples, double creep_speed);
// β and the creep onset from a turn's samples (ωR: the wall's speed). Throws RunError when the
// free surface was found in fewer than 3 samples of kReposeSpinUpDeg-kReposeEndDeg or β lies
// outside [0, 89].
ReposeMeasurement repose_from_samples(const std::vector<TurnSample>& samples, double wall_speed);

// The measurement on the settled bed that `bed` gives (the whole bed, on every rank of `comm`;
// called only when there is no turn to go on from), kept in and resumed from `turn_path` ("":
// nowhere; a stop then keeps nothing). Collective. Throws RunError when no free surface is found
// (the key to set is named), StopRequest on a stop signal once the turn is kept.
ReposeMeasurement measure_repose(const Scene& scene, const std::function<Particles()>& bed,
                                 const std::string& turn_path, std::ostream* log,
                                 MPI_Comm comm = MPI_COMM_NULL,
                                 const std::function<void()>& between_blocks = nullptr);

// Everything the measurement depends on: the bed's key (or its file), ω, the law's own keys and
// the code version; its hash names the cached value (beside the bed, in fill.bed_cache).
std::string repose_key(const Scene& scene);
std::string repose_cache_path(const Scene& scene);
// The turn so far of a measurement stopped or still running (beside the cached value).
std::string repose_turn_path(const Scene& scene);

// The scene with β and the still slope known. Given numbers, or a scene that asks for neither
// (Scene::bed_turn_pending): unchanged. Otherwise the numbers in the scene text of `checkpoint`
// (the file the run resumes from; "" for none), else the cached values, else measured on the
// settled bed (made or reused through the bed cache) and cached. Collective over `comm`; every
// rank gets the same numbers. Throws RunError, naming fidelity.bulk_still_slope, when the still
// slope is asked for and the bed never crept.
Scene with_bed_turn_resolved(const Scene& scene, const std::string& checkpoint, std::ostream* log,
                             MPI_Comm comm = MPI_COMM_NULL,
                             const std::function<void()>& between_blocks = nullptr);

}  // namespace tumble
