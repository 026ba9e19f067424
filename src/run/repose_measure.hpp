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
// The value is a property of the bed (its seed included: every replica measures its own, so the
// result never depends on which case ran first) and is kept beside the cached bed; a run that
// resumes takes it from its checkpoint, whose scene text holds the number.
//
// The turn itself (hours on the paper's bed: 2 h of a core for bst_paper at `standard`) is kept
// like a run's protocol: on a stop signal and every output.checkpoint_wall of wall time, the
// engine and the samples so far go to a checkpoint beside the cached value (repose_turn_path),
// written after a step that rebuilt its neighbour list by itself, so the next run goes on from it
// and ends with the number the uninterrupted turn gives, bit for bit (on the same ranks). The file
// is removed once the value is cached; one that does not fit (another bed, damaged) is ignored
// with a line in the log and the turn starts again.
#include <mpi.h>

#include <functional>
#include <iosfwd>
#include <string>

#include "base/particles.hpp"
#include "scene/scene.hpp"

namespace tumble {

inline constexpr double kReposeSpinUpDeg = 40;  // the bed flows from ~35° (docs/accuracy.md)
inline constexpr double kReposeEndDeg = 80;
// Bump when the measurement changes, so that cached values of the old procedure are not reused.
inline constexpr int kReposeCodeVersion = 1;

struct ReposeMeasurement {
  double mean_deg = 0;  // β
  double sd_deg = 0;    // spread of the samples (correlated in time: not an error of the mean)
  int samples = 0;
};

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

// The scene with β known. A given number, or a scene that is not biaxial: unchanged. Otherwise
// the number in the scene text of `checkpoint` (the file the run resumes from; "" for none), else
// the cached value, else measured on the settled bed (made or reused through the bed cache) and
// cached. Collective over `comm`; every rank gets the same number.
Scene with_repose_resolved(const Scene& scene, const std::string& checkpoint, std::ostream* log,
                           MPI_Comm comm = MPI_COMM_NULL,
                           const std::function<void()>& between_blocks = nullptr);

}  // namespace tumble
