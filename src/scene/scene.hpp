#pragma once
// A scene: everything one DEM realization needs, read from TOML, overridable key by key on the
// command line, and validated in full before any particle is made.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene_keys.hpp"

namespace tumble {

struct Scene {
  // Every key of scene/scene_keys.hpp, with its default.
#define TUMBLE_SCENE_MEMBER(T, MEMBER, KEY, DEFAULT, LO, HI, HELP) T MEMBER = DEFAULT;
  TUMBLE_SCENE_KEYS(TUMBLE_SCENE_MEMBER)
#undef TUMBLE_SCENE_MEMBER
  // The keys a contact law owns (src/contact/<law>.hpp declares them: rapaport2007's k_n, γ_n, ...;
  // hertz_mindlin's Young's modulus, ...), by key; every registered law's keys, defaults included.
  // The law reads them once per scene (law_value).
  std::map<std::string, double> law_values;

  // The fully resolved key=value list, for provenance attributes.
  std::map<std::string, std::string> resolved;

  // Derived.
  double time_step() const { return dt > 0 ? dt : dt_fraction * collision_time; }
  double omega() const;  // [rad/s]
  double mass_small() const;
  double mass_large() const;
  double run_time() const;              // simulated seconds the protocol runs (after settling)
  std::int64_t protocol_steps() const;  // the protocol's time steps: run_time / time_step
  bool cylinder() const { return shape == Shape::cylinder; }
  // The value of a key owned by a contact law (law_values); throws std::logic_error if no
  // registered law declares `key`.
  double law_value(const std::string& key) const;
  // Mean of d^3 over the size distribution of a species with nominal (largest) diameter d.
  double mean_cube(double d) const;
  // protocol.repose = "measured" in a biaxial scene whose β has not been filled in yet
  // (run/repose_measure.hpp resolves it before a run).
  bool repose_pending() const { return mode == Mode::biaxial && !repose.known; }
  // fidelity.bulk_still_slope = "measured" in a rigid-bulk scene, not filled in yet (the same
  // turn of the bed measures it).
  bool still_slope_pending() const { return bulk == Bulk::rigid && !bulk_still_slope.known; }
  // Either: the run turns its settled bed once before the protocol (run/repose_measure.hpp).
  bool bed_turn_pending() const { return repose_pending() || still_slope_pending(); }
};

// Fills in a measured repose tilt β [deg]: the scene's value, its provenance text and its
// resolved key list then hold the number.
void set_measured_repose(Scene& s, double deg);
// The same for a measured still slope [deg].
void set_measured_still_slope(Scene& s, double deg);

// One key of the schema: its type, default, allowed range and a one-line description.
struct KeySpec {
  enum Type { Real, Integer, Text };  // Text with choices: an enum (or contact.law)
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
  std::string word;                  // a number's alternative word ("measured"), or empty
  std::string help;
  double def = 0;   // default of a law's key (law_values); the struct holds the others
  std::string law;  // the contact law that owns this key (scene/law_registry.hpp), or empty
};
// Every key in provenance order: the scene's own keys (scene/scene_keys.hpp) with the registered
// contact laws' keys after contact.tangential_damping. (Main thread only: it is built on first
// use.)
const std::vector<KeySpec>& scene_schema();
// A key's default as text, numbers to 6 digits (for --list-keys).
std::string default_text(const KeySpec& spec);

// Reads `path` (TOML), applies `overrides` ("section.key=value"), checks every key and value and
// the cross-key constraints. Throws InputError naming the key on the first problem.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
// The text of a scene file, refused (InputError naming the file and what is missing) when the path
// is a directory or unreadable, the file is empty or holds only comments, or it does not name
// itself ([scene] name = "..."): a file that says nothing must not run a default scene. TOML errors
// are left to parse_scene, which reports them with their line. Used by load_scene and campaigns.
std::string read_scene_file(const std::string& path);
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
// Scenes whose protocol takes more time steps than this are refused: ~10^5 times bst_paper's
// 8 iterations, years of any machine; below 2^63, so the count fits its integer.
inline constexpr double kMaxProtocolSteps = 1e12;
// Scenes whose wall moves more than this fraction of d_small in one time step are refused.
inline constexpr double kMaxWallStep = 0.1;
// Scenes that would write more snapshots than this are refused (each is a file of the whole bed).
inline constexpr double kMaxSnapshots = 1e5;
// Rendering of the resolved scene as TOML-like text (provenance).
std::string scene_to_text(const Scene& s);

}  // namespace tumble
