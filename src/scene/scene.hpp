#pragma once
// A scene: everything one DEM realization needs, read from TOML, overridable key by key on the
// command line, and validated in full before any particle is made.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace tumble {

struct Scene {
  // [scene]
  std::string name = "scene";
  std::string output_dir = "results/scene";
  // [tumbler]
  std::string shape = "sphere";  // sphere | cylinder (axis along z, horizontal)
  double radius = 0.035;         // R [m]
  double length = 0;             // cylinder length L (axis z, from -L/2 to L/2)
  std::string periodic = "off";  // cylinder: on = axially periodic, no end caps
  // [particles]
  double d_small = 0.002, d_large = 0.004;  // diameters [m]
  double density = 2500;                    // small-particle density [kg/m^3]
  double density_ratio = 1;                 // R_ρ = ρ_large / ρ_small
  double large_fraction = 0.15;             // f: large-particle volume fraction of solids
  double fill_level = 0.5;                  // fraction of the tumbler volume filled by the bed
  double packing_fraction = 0.6;            // solid fraction of the settled bed (sets N)
  std::int64_t count = 0;                   // cylinder: number of particles (Rapaport's N)
  double size_spread = 0;  // diameters uniform in [d - spread, d] (Rapaport 2007: 0.2)
  // [contact]
  std::string law = "yu2022";
  double restitution = 0.87, collision_time = 5e-4, friction = 0.6, wall_friction = 0.6;
  double tangential_damping = 0;  // γ_t [1/s]
  // The keys a contact law owns (src/contact/<law>.hpp declares them: rapaport2007's k_n, γ_n, ...;
  // hertz_mindlin's Young's modulus, ...), by key; every registered law's keys, defaults included.
  // The law reads them once per scene (law_value).
  std::map<std::string, double> law_values;
  // [fill]
  std::int64_t seed = 1;
  std::string start = "mixed";     // mixed | large_top | large_xneg
  double settle_rms_speed = 1e-3;  // [m/s]
  double settle_max_time = 2.0;    // [s]
  std::string bed_file;            // reuse this settled bed (HDF5) instead of filling
  std::string bed_cache = "beds";  // where settled beds are saved and looked up
  // [protocol]
  std::string mode = "biaxial";                    // biaxial | single_axis | rest
  double theta_z = 57, theta_x = 57, repose = 27;  // degrees
  double rpm = 3;
  std::string axis = "x";  // single_axis only
  double omega_set = 0;    // angular speed [rad per time unit]; 0: from rpm
  double revolutions = 0;  // single_axis: run length in revolutions (0: protocol.duration)
  double iterations = 1;   // biaxial: protocol iterations to run
  double duration = 0;     // single_axis / rest: simulated seconds to run
  // [gravity]
  double g = 9.81;
  // [time]
  double dt = 0;                               // 0: dt_fraction * collision_time
  double dt_fraction = 0.02;                   // δt / t_c (t_c/50 by default)
  std::string integrator = "velocity_verlet";  // velocity_verlet | leapfrog
  // [neighbor]
  double skin = 0.1;  // Verlet skin / d_small (fastest measured, docs/performance.md)
  // [fidelity]
  std::string tier = "standard";  // standard | reference | fast | preview (scene/fidelity.hpp)
  // The tier whose values this scene already holds. The resolved text (provenance, checkpoints)
  // records it here and writes fidelity.tier = "standard", so reading it back does not apply the
  // tier twice.
  std::string tier_applied = "standard";
  // [parallel]
  double rebalance_threshold = 1.1;  // re-bisect when max/mean owned particles exceeds this
  // [output]
  double snapshot_interval = 0;    // simulated seconds between snapshots (0: one per iteration)
  double checkpoint_interval = 0;  // simulated seconds between checkpoints (0: one per iteration)
  double progress_interval = 10;   // wall seconds between progress lines
  double analysis_interval = 0.5;  // simulated seconds between radial-segregation samples
  std::string drift_grid = "off";  // on: measure the MCM's axial drift grid (drift_grid.h5)
  double slice_width = 0;          // cylinder: axial/radial bin width (0: 2.5 mean small diameters)

  // The fully resolved key=value list, for provenance attributes.
  std::map<std::string, std::string> resolved;

  // Derived.
  double time_step() const { return dt > 0 ? dt : dt_fraction * collision_time; }
  double omega() const;  // [rad/s]
  double mass_small() const;
  double mass_large() const;
  double run_time() const;  // simulated seconds the protocol runs (after settling)
  bool cylinder() const { return shape == "cylinder"; }
  // The value of a key owned by a contact law (law_values); throws std::logic_error if no
  // registered law declares `key`.
  double law_value(const std::string& key) const;
  // Mean of d^3 over the size distribution of a species with nominal (largest) diameter d.
  double mean_cube(double d) const;
};

// One key of the schema: its type, default, allowed range and a one-line description.
struct KeySpec {
  enum Type { Real, Integer, Text };
  KeySpec(std::string key_, Type type_, double lo_, double hi_, std::vector<std::string> choices_,
          std::string help_, double def_ = 0, std::string law_ = {})
      : key(std::move(key_)),
        type(type_),
        lo(lo_),
        hi(hi_),
        choices(std::move(choices_)),
        help(std::move(help_)),
        def(def_),
        law(std::move(law_)) {}
  std::string key;  // "section.name"
  Type type;
  double lo = 0, hi = 0;             // allowed closed range (numbers)
  std::vector<std::string> choices;  // allowed values (text), empty = any
  std::string help;
  double def = 0;   // default of a law's key (law_values); the struct holds the others
  std::string law;  // the contact law that owns this key (scene/law_registry.hpp), or empty
};
// Every key in provenance order: the scene's own keys with the registered contact laws' keys
// after contact.tangential_damping.
std::vector<KeySpec> scene_schema();

// Reads `path` (TOML), applies `overrides` ("section.key=value"), checks every key and value and
// the cross-key constraints. Throws InputError naming the key on the first problem.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
// Same from TOML text (tests).
Scene parse_scene(const std::string& toml_text, const std::vector<std::string>& overrides = {},
                  const std::string& origin = "<string>");
// Cross-key checks that need derived quantities (time-step bound, bed fits). Called by load_scene.
void validate_scene(const Scene& s);
// The time-step stability bound of the stiffest pair (see scene.cpp for the derivation).
double time_step_bound(const Scene& s);
// Estimated overlap of the bottom particles under the bed's weight, as a fraction of d_small.
double weight_overlap_fraction(const Scene& s);
// Scenes whose estimated weight overlap exceeds this fraction of d_small are refused; a settled
// bed may press into the wall by as much (io/bed_io.cpp).
inline constexpr double kMaxWeightOverlap = 0.25;
// Rendering of the resolved scene as TOML-like text (provenance).
std::string scene_to_text(const Scene& s);

}  // namespace tumble
