#pragma once
// The one list of the scene's own keys (the contact laws add theirs: scene/law_registry.hpp). Each
// line defines a key completely:
//
//   X(C++ type, Scene member, "section.key", default, lowest, highest, "meaning")
//
// and from it come the Scene struct's members and defaults (scene.hpp), the parser's type, range
// and choice checks, `tumble run --list-keys`, and the provenance text scene_to_text (in this
// order: the order of the lines is part of every stored scene text, so a new key goes where its
// section is and existing lines never move). Numbers are double (Real) or std::int64_t (Integer)
// with a closed range; std::string is free text; an enum (scene/scene_enums.hpp) is one of its
// names; ReposeTilt and StillSlope are a number in their range or the word "measured". To add a
// key: one line here, and the code that uses it.
#include <cstdint>
#include <string>

#include "scene/scene_enums.hpp"

namespace tumble {

// protocol.repose: the tilt β in degrees, or the word "measured" (the default): the dynamic
// angle of repose of the scene's own settled bed, measured before the run
// (run/repose_measure.hpp) and written into the scene as a number. Until then `deg` holds the
// paper's 27° for plans and estimates only: building the protocol from it is refused.
struct ReposeTilt {
  double deg = 27;
  bool measured = true;  // the scene asked for "measured"
  bool known = false;    // deg is the number to use (given, or measured and filled in)
  static constexpr const char* kWord = "measured";
  static ReposeTilt pending() { return {}; }
  static ReposeTilt given(double d) { return {d, false, true}; }
};

// The measured still slope lies this many degrees below the onset the turn reads. On bst_small at
// `standard` a fixed 12° left the onset and the layer as dynamic's and 20° did not (it holds the
// creep back and lets it go as a burst). The turn (about z) reads the onset 14.5 ± 2.0° over six
// beds, 2.3° earlier than the flow runs about x, and 12° lies 2.5° below its mean: with this
// margin the six keys were 8.5-14.3° and nothing resolved in the onset (docs/accuracy.md, "The
// still slope measured per bed"; a margin of 5 gave 6.0-11.8° and gained less). A macro as well
// as a constant so that the key's `--list-keys` text below prints the number the code uses.
#define TUMBLE_STILL_SLOPE_MARGIN_DEG 2.5
#define TUMBLE_TEXT_OF(x) TUMBLE_TEXT_OF_TOKENS(x)
#define TUMBLE_TEXT_OF_TOKENS(x) #x
inline constexpr double kStillSlopeMargin = TUMBLE_STILL_SLOPE_MARGIN_DEG;

// fidelity.bulk_still_slope: degrees (0, the default: the surface layer never freezes), or the
// word "measured": the slope at which the scene's own settled bed starts to creep when it turns
// from rest, less kStillSlopeMargin (the turn is run/repose_measure.hpp's, the same as β's).
// Until it is filled in `deg` is 0 and a rigid engine is refused.
struct StillSlope {
  double deg = 0;
  bool measured = false;  // the scene asked for "measured"
  bool known = true;      // deg is the number to use
  static constexpr const char* kWord = "measured";
  static StillSlope pending() { return {0, true, false}; }
  static StillSlope given(double d) { return {d, false, true}; }
};

}  // namespace tumble

// clang-format off
#define TUMBLE_SCENE_KEYS(X) \
  X(std::string, name, "scene.name", "scene", 0, 0, \
    "scene name (used in output file names)") \
  X(std::string, output_dir, "scene.output_dir", "results/scene", 0, 0, \
    "directory for snapshots, checkpoints and results") \
  X(Shape, shape, "tumbler.shape", Shape::sphere, 0, 0, \
    "tumbler geometry (cylinder: horizontal, axis along z)") \
  X(double, radius, "tumbler.radius", 0.035, 1e-6, 1e6, \
    "tumbler radius R (cylinder: D/2)") \
  X(double, length, "tumbler.length", 0, 0, 1e6, \
    "cylinder length L") /* axis z, from -L/2 to L/2 */ \
  X(OnOff, periodic, "tumbler.periodic", OnOff::off, 0, 0, \
    "cylinder: axially periodic (no end caps)") \
  X(double, d_small, "particles.d_small", 0.002, 1e-9, 1e6, \
    "small-particle diameter") \
  X(double, d_large, "particles.d_large", 0.004, 1e-9, 1e6, \
    "large-particle diameter (= d_small for density-bidisperse beds)") \
  X(double, density, "particles.density", 2500, 1e-9, 1e9, \
    "small-particle density") /* [kg/m^3] */ \
  X(double, density_ratio, "particles.density_ratio", 1, 0.1, 10, \
    "R_rho = rho_large / rho_small") \
  X(double, large_fraction, "particles.large_fraction", 0.15, 0, 1, \
    "f, large-particle volume fraction of the solids") \
  X(double, fill_level, "particles.fill_level", 0.5, 0.05, 0.95, \
    "fraction of the tumbler volume occupied by the bed") \
  X(double, packing_fraction, "particles.packing_fraction", 0.6, 0.3, 0.74, \
    "solid fraction of the settled bed (sets the particle count)") \
  X(std::int64_t, count, "particles.count", 0, 0, 1e8, \
    "cylinder: number of particles (spheres are filled by particles.fill_level)") \
  X(double, size_spread, "particles.size_spread", 0, 0, 1e6, \
    "diameters uniform in [d - spread, d] (rapaport2007 law only)") /* Rapaport 2007: 0.2 */ \
  X(std::string, law, "contact.law", "yu2022", 0, 0, \
    "contact law") /* choices: the registered laws (contact/laws.hpp) */ \
  X(double, restitution, "contact.restitution", 0.87, 0.05, 1, \
    "normal restitution coefficient e") \
  X(double, collision_time, "contact.collision_time", 5e-4, 1e-9, 1, \
    "binary collision time t_c") \
  X(double, friction, "contact.friction", 0.6, 0, 2, \
    "particle-particle friction coefficient mu") \
  X(double, wall_friction, "contact.wall_friction", 0.6, 0, 2, \
    "particle-wall friction coefficient mu_w") \
  X(double, tangential_damping, "contact.tangential_damping", 0, 0, 1e9, \
    "tangential damping gamma_t [1/s]") \
  /* the contact laws' own keys are written here (scene_schema) */ \
  X(std::int64_t, seed, "fill.seed", 1, 0, 9.0e15, \
    "random seed of the bed") \
  X(Start, start, "fill.start", Start::mixed, 0, 0, \
    "initial arrangement (large_zneg: cylinder presegregated in two axial halves)") \
  X(double, settle_rms_speed, "fill.settle_rms_speed", 1e-3, 1e-12, 1e3, \
    "settling ends when the rms speed falls below this") /* [m/s] */ \
  X(double, settle_max_time, "fill.settle_max_time", 2.0, 0, 1e6, \
    "settling gives up (error) after this simulated time") /* [s] */ \
  X(std::string, bed_file, "fill.bed_file", "", 0, 0, \
    "start from this settled bed (HDF5) instead of filling") \
  X(std::string, bed_cache, "fill.bed_cache", "beds", 0, 0, \
    "directory where settled beds are saved and reused") \
  X(Mode, mode, "protocol.mode", Mode::biaxial, 0, 0, \
    "rotation protocol") \
  X(double, theta_z, "protocol.theta_z", 57, 0, 360, \
    "rotation angle about z per iteration [deg]") \
  X(double, theta_x, "protocol.theta_x", 57, 0, 360, \
    "rotation angle about x per iteration [deg]") \
  X(ReposeTilt, repose, "protocol.repose", ReposeTilt{}, 0, 89, \
    "repose tilt beta before/after each rotation [deg], or \"measured\": the bed's own dynamic repose angle") \
  X(double, rpm, "protocol.rpm", 3, 0, 1e4, \
    "angular speed [rev/min]") \
  X(Axis, axis, "protocol.axis", Axis::x, 0, 0, \
    "axis of single_axis mode") \
  X(double, omega_set, "protocol.omega", 0, 0, 1e6, \
    "angular speed [rad per time unit], overrides protocol.rpm when > 0") \
  X(double, revolutions, "protocol.revolutions", 0, 0, 1e9, \
    "single_axis: run length in revolutions (0 = protocol.duration)") \
  X(double, iterations, "protocol.iterations", 1, 0, 1e6, \
    "biaxial: protocol iterations to run") \
  X(double, duration, "protocol.duration", 0, 0, 1e9, \
    "single_axis/rest: simulated time to run") \
  X(double, g, "gravity.g", 9.81, 0, 1e4, \
    "gravitational acceleration (along -y)") \
  X(double, dt, "time.dt", 0, 0, 1, \
    "time step (0 = dt_fraction * collision_time)") \
  X(double, dt_fraction, "time.dt_fraction", 0.02, 1e-6, 1, \
    "time step as a fraction of t_c") /* t_c/50 by default */ \
  X(Integrator, integrator, "time.integrator", Integrator::velocity_verlet, 0, 0, \
    "velocity_verlet, or leapfrog (one kick per step; velocities reported at half steps)") \
  X(double, skin, "neighbor.skin", 0.1, 0.01, 2, \
    "Verlet skin as a fraction of d_small") /* fastest measured, docs/performance.md */ \
  X(Tier, tier, "fidelity.tier", Tier::standard, 0, 0, \
    "speed/accuracy preset derived from the scene (docs/accuracy.md); standard = as written") \
  /* The tier whose values this scene already holds. The resolved text (provenance, checkpoints) \
     records it here and writes fidelity.tier = "standard", so reading it back does not apply \
     the tier twice. */ \
  X(Tier, tier_applied, "fidelity.applied", Tier::standard, 0, 0, \
    "written by Tumble: the tier already applied to a resolved scene's values") \
  /* The rigid bulk (docs/accuracy.md, "Rigid bulk"; engine/rigid_bulk.cpp). */ \
  X(Bulk, bulk, "fidelity.bulk", Bulk::dynamic, 0, 0, \
    "dynamic: every particle integrated; rigid: calm particles deep in the bed turn with the wall as a solid (no contacts among them)") \
  X(double, bulk_calm_distance, "fidelity.bulk_calm_distance", 0.05, 1e-3, 1, \
    "rigid bulk: calm while it stays within this many d_large of where its stay began, in the tumbler's frame (0.02: the flowing layer's speed within ~1% at R/d_large 17.5, ~13% more wall time per iteration; docs/accuracy.md)") \
  X(double, bulk_dwell, "fidelity.bulk_dwell", 0.05, 0, 1e3, \
    "rigid bulk: a particle and its neighbours stay calm this long [s] before it freezes") \
  X(double, bulk_margin, "fidelity.bulk_margin", 3, 0.5, 1e3, \
    "rigid bulk: only particles deeper than this many d_large below the free surface freeze") \
  X(double, bulk_thaw_force, "fidelity.bulk_thaw_force", 200, 0.1, 1e6, \
    "rigid bulk: a frozen particle thaws when its moving neighbours push it harder than this many times its weight") \
  X(double, bulk_thaw_gravity, "fidelity.bulk_thaw_gravity", 2, 0.01, 2, \
    "rigid bulk: a frozen particle thaws when gravity, seen from the tumbler, has changed by more than this many g since it froze (2 sin of half the turn; 2: never)") \
  X(SegmentThaw, bulk_segment_thaw, "fidelity.bulk_segment_thaw", SegmentThaw::on, 0, 0, \
    "rigid bulk: on: a change of the protocol's segment (a tilt, a new axis) thaws every frozen particle; omega: only a change of the tumbler's angular velocity does (not a tilt becoming its rotation about the same axis); off: the other rules alone decide") \
  X(StillSlope, bulk_still_slope, "fidelity.bulk_still_slope", StillSlope{}, 0, 89, \
    "rigid bulk: while the free surface is inclined less than this many degrees (a tilt below the repose angle), the surface layer within the margin may freeze too, and it thaws when the slope passes it (0: never; set it below the slope where the scene's surface starts to creep at its tier, 12 for bst_small at standard; \"measured\": that slope of the scene's own bed, less " TUMBLE_TEXT_OF(TUMBLE_STILL_SLOPE_MARGIN_DEG) " degrees)") \
  X(double, rebalance_threshold, "parallel.rebalance_threshold", 1.1, 1, 100, \
    "domain-decomposed runs: re-bisect when max/mean particles per rank exceeds this") \
  X(double, frozen_weight, "parallel.frozen_weight", 1, 0.01, 1, \
    "rigid bulk on several ranks: a frozen particle's share of a moving one's work when the ranks' regions are cut (1: by count)") \
  /* Newton's third law across rank borders (docs/parallel.md, "Newton across borders"). */ \
  X(OnOff, newton, "parallel.newton", OnOff::on, 0, 0, \
    "domain-decomposed runs: on: a pair across a rank border is computed by one of its ranks, which sends the other its particle's force; off: by both (the rigid bulk: always off)") \
  X(double, snapshot_interval, "output.snapshot_interval", 0, 0, 1e9, \
    "simulated time between snapshots (0 = once per iteration)") \
  X(double, checkpoint_interval, "output.checkpoint_interval", 0, 0, 1e9, \
    "simulated time between checkpoints (0 = once per iteration)") \
  X(double, checkpoint_wall, "output.checkpoint_wall", 600, 0, 1e9, \
    "wall seconds after which a checkpoint is also written, at the next neighbour rebuild (0 = off)") \
  X(double, progress_interval, "output.progress_interval", 10, 0, 1e6, \
    "wall seconds between progress lines") \
  X(double, analysis_interval, "output.analysis_interval", 0.5, 0, 1e9, \
    "simulated time between segregation samples (0 = off)") \
  X(OnOff, drift_grid, "output.drift_grid", OnOff::off, 0, 0, \
    "measure the MCM axial drift grid (Yu 2022 App. A) into drift_grid.h5") \
  X(double, slice_width, "output.slice_width", 0, 0, 1e6, \
    "cylinder: width of axial and radial bins (0 = 2.5 mean small diameters)")
// clang-format on
