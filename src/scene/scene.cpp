#include "scene/scene.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "base/error.hpp"
#include "base/text_util.hpp"
#include "base/vec3.hpp"
#include "scene/fidelity.hpp"
#include "scene/fill.hpp"
#include "scene/law_registry.hpp"
#include "scene/scene_schema.hpp"

namespace tumble {

double Scene::omega() const { return omega_set > 0 ? omega_set : rpm * 2.0 * kPi / 60.0; }
double Scene::mean_cube(double d) const {
  if (size_spread <= 0) return d * d * d;
  const double a = d - size_spread;  // uniform in [a, d]: E[d^3] = (d^4 - a^4) / (4 (d - a))
  return (d * d * d * d - a * a * a * a) / (4.0 * size_spread);
}
double Scene::law_value(const std::string& key) const {
  const auto it = law_values.find(key);
  if (it == law_values.end())
    throw std::logic_error("no registered contact law declares the key '" + key + "'");
  return it->second;
}
double Scene::mass_small() const { return density * kPi / 6.0 * d_small * d_small * d_small; }
double Scene::mass_large() const {
  return density * density_ratio * kPi / 6.0 * d_large * d_large * d_large;
}
std::int64_t Scene::protocol_steps() const { return std::llround(run_time() / time_step()); }

double Scene::run_time() const {
  if (mode == Mode::biaxial) {
    const double w = omega();
    if (w <= 0) return 0;
    // Before a measured β is filled in, repose.deg is the 27° estimate (plans, cost estimates).
    const double period = (deg2rad(theta_z) + deg2rad(theta_x) + 4.0 * deg2rad(repose.deg)) / w;
    return iterations * period;
  }
  if (mode == Mode::single_axis && revolutions > 0 && omega() > 0)
    return revolutions * 2.0 * kPi / omega();
  return duration;
}

namespace {
std::string as_scene_text_writes(double deg) {  // so that the texts compare equal
  std::ostringstream os;
  os.precision(17);
  os << deg;
  return os.str();
}
}  // namespace

void set_measured_repose(Scene& s, double deg) {
  s.repose = ReposeTilt{deg, true, true};
  s.resolved["protocol.repose"] = as_scene_text_writes(deg);
}

void set_measured_still_slope(Scene& s, double deg) {
  s.bulk_still_slope = StillSlope{deg, true, true};
  s.resolved["fidelity.bulk_still_slope"] = as_scene_text_writes(deg);
}

namespace {

struct Value {
  bool numeric = false;
  double num = 0;
  std::string text;
  std::string origin;  // where it came from, for messages
};

std::optional<KeySpec> find_spec(const std::string& key) {
  for (const auto& s : scene_schema())
    if (s.key == key) return s;
  return std::nullopt;
}

[[noreturn]] void unknown_key(const std::string& key, const std::string& origin) {
  std::string best;
  std::size_t best_d = 1000;
  for (const auto& s : scene_schema()) {
    const std::size_t d = edit_distance(key, s.key);
    if (d < best_d) best_d = d, best = s.key;
  }
  std::string msg = "scene error (" + origin + "): unknown key '" + key + "'";
  if (best_d <= 4) msg += " (did you mean '" + best + "'?)";
  msg += "; run 'tumble run --list-keys' for all keys";
  throw InputError(msg);
}

void flatten(const toml::table& t, const std::string& prefix, const std::string& origin,
             std::map<std::string, Value>& out) {
  for (const auto& [k, node] : t) {
    const std::string key =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = node.as_table()) {
      flatten(*sub, key, origin, out);
      continue;
    }
    Value v;
    v.origin = origin;
    if (const auto* i = node.as_integer()) {  // (any integer: value<double> refuses those beyond
      v.numeric = true;                       // 2^53, and value<bool> then read them as 'true')
      v.num = static_cast<double>(i->get());
      v.text = std::to_string(i->get());
    } else if (auto d = node.value<double>()) {
      v.numeric = true;
      v.num = *d;
      std::ostringstream os;
      os.precision(17);
      os << *d;
      v.text = os.str();
    } else if (auto s = node.value<std::string>()) {
      v.text = *s;
    } else if (const auto* b = node.as_boolean()) {
      v.text = b->get() ? "true" : "false";
    } else {
      throw InputError("scene error (" + origin + "): key '" + key +
                       "' has an unsupported value type (use a number or a string)");
    }
    out[key] = v;
  }
}

Value parse_override(const std::string& item, std::string& key) {
  const auto eq = item.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("scene error: override '" + item + "' is not of the form section.key=value");
  key = item.substr(0, eq);
  std::string text = item.substr(eq + 1);
  if (text.size() >= 2 && (text.front() == '"' || text.front() == '\'') &&
      text.back() == text.front())
    text = text.substr(1, text.size() - 2);
  Value v;
  v.origin = "--set " + item;
  v.text = text;
  char* end = nullptr;
  const double d = std::strtod(text.c_str(), &end);
  if (!text.empty() && end && *end == '\0') {
    v.numeric = true;
    v.num = d;
  }
  return v;
}

std::string range_text(const KeySpec& s) {
  std::ostringstream os;
  os << "[" << s.lo << ", " << s.hi << "]";
  return os.str();
}

// Whether `text`, written as scene_to_text writes it, reads back as itself.
bool reads_back(const std::string& text) {
  try {
    const toml::table t = toml::parse("k = " + toml_quoted(text));
    const std::optional<std::string> back = t["k"].value<std::string>();
    return back && *back == text;
  } catch (const toml::parse_error&) {
    return false;
  }
}

// Checks every key and value (range, choices) and sets them on a default scene.
Scene apply_values(const std::map<std::string, Value>& values) {
  Scene s;
  for (const auto& law : contact_laws())
    for (const KeySpec& k : law.keys) s.law_values[k.key] = k.def;
  for (const auto& [key, v] : values) {
    const std::optional<KeySpec> spec = find_spec(key);
    if (!spec) unknown_key(key, v.origin);
    const std::string where = "scene error (" + v.origin + "): key '" + key + "'";
    if (spec->type == KeySpec::Text) {
      // Every text value is written back into the scene text that results, snapshots and
      // checkpoints carry and a resume reads: it must read back as itself (TOML strings are
      // UTF-8 without control characters).
      if (!reads_back(v.text))
        throw InputError(where +
                         " must be UTF-8 text without control characters (newlines, "
                         "escapes): it is written into every output file's scene");
      if (!spec->choices.empty() &&
          std::find(spec->choices.begin(), spec->choices.end(), v.text) == spec->choices.end()) {
        std::string allowed;
        for (const auto& c : spec->choices) allowed += (allowed.empty() ? "" : ", ") + c;
        throw InputError(where + " = '" + v.text + "' is not one of: " + allowed);
      }
      set_key(s, *spec, v.text, 0);
    } else if (!spec->word.empty() && !v.numeric && v.text == spec->word) {
      set_key(s, *spec, v.text, 0);
    } else {
      const std::string alt = spec->word.empty() ? "" : " or '" + spec->word + "'";
      if (!v.numeric || !std::isfinite(v.num))
        throw InputError(where + " = '" + v.text + "' must be a number in " + range_text(*spec) +
                         alt + " (" + spec->help + ")");
      if (v.num < spec->lo || v.num > spec->hi)
        throw InputError(where + " = " + v.text + " is out of range " + range_text(*spec) + alt +
                         " (" + spec->help + ")");
      if (spec->type == KeySpec::Integer) {
        if (v.num != std::floor(v.num))
          throw InputError(where + " = " + v.text + " must be an integer");
      }
      set_key(s, *spec, v.text, v.num);
    }
  }
  return s;
}

}  // namespace

Scene parse_scene(const std::string& toml_text, const std::vector<std::string>& overrides,
                  const std::string& origin) {
  std::map<std::string, Value> values;
  toml::table tbl;
  try {
    tbl = toml::parse(toml_text, origin);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << "scene error: " << origin << " is not valid TOML: " << e.description() << " (line "
       << e.source().begin.line << ")";
    throw InputError(os.str());
  }
  flatten(tbl, "", origin, values);
  std::map<std::string, Value> given;  // --set overrides: they win over a tier's values
  for (const auto& item : overrides) {
    std::string key;
    Value v = parse_override(item, key);
    // The tier a resolved scene's values already hold is Tumble's record, not a setting: given by
    // hand it records a tier that was not applied (the values stay the scene's).
    if (key == "fidelity.applied")
      throw InputError(
          "scene error: key 'fidelity.applied' is written by Tumble (the tier a "
          "resolved scene's values hold) and cannot be set; set fidelity.tier");
    values[key] = v;
    given[key] = v;
  }
  // A fidelity tier rewrites keys of the scene as written (scene/fidelity.hpp).
  Scene s = apply_values(values);
  if (s.tier != Tier::standard) {
    for (const auto& [key, text] : tier_values(s.tier, s)) {
      // Given keys win, except the diameters: the tier's coarsening scales the pair in effect
      // (given or not) by one factor, so a given size ratio survives (a campaign's size_ratio = 1
      // sets d_large; growing d_small alone would break the pair).
      const bool diameter = key == "particles.d_large" || key == "particles.d_small";
      if (given.count(key) && !diameter) continue;
      Value v;
      v.origin = std::string("fidelity.tier = ") + name_of(s.tier);
      v.text = text;
      v.numeric = true;
      v.num = std::strtod(text.c_str(), nullptr);
      values[key] = v;
    }
    const Tier applied = s.tier;
    s = apply_values(values);
    s.tier_applied = applied;
  }
  // Resolved scene for provenance: every key, defaults included.
  std::istringstream lines(scene_to_text(s));
  for (std::string line; std::getline(lines, line);) {
    const auto eq = line.find(" = ");
    if (eq != std::string::npos) s.resolved[line.substr(0, eq)] = line.substr(eq + 3);
  }
  validate_scene(s);
  return s;
}

std::string read_scene_file(const std::string& path) {
  std::error_code ec;
  // An ifstream opens a directory without complaint and reads it as empty.
  if (std::filesystem::is_directory(path, ec))
    throw InputError("scene error: '" + path + "' is a directory, not a scene file (TOML)");
  std::ifstream in(path);
  if (!in) throw InputError("scene error: cannot read scene file '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const std::string needed = "; a scene must at least name itself: [scene] name = \"...\"";
  toml::table tbl;
  try {
    tbl = toml::parse(text, path);
  } catch (const toml::parse_error&) {
    return text;  // parse_scene reports the error with its line
  }
  if (tbl.empty()) {
    const bool blank = text.find_first_not_of(" \t\r\n") == std::string::npos;
    throw InputError("scene error: scene file '" + path + "' is " +
                     (blank ? "empty" : "only comments (no keys)") + needed);
  }
  const auto name = tbl["scene"]["name"].value<std::string>();
  if (!name)
    throw InputError("scene error: scene file '" + path + "' has no [scene] name" + needed);
  if (name->find_first_not_of(" \t") == std::string::npos)
    throw InputError("scene error: scene file '" + path + "' has an empty [scene] name" + needed);
  return text;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  return parse_scene(read_scene_file(path), overrides, path);
}

// The stability bound of the scene's contact law (damped_time_step_bound in
// scene/law_registry.hpp; each law's ω0² and γ are derived in its file under src/contact/).
double time_step_bound(const Scene& s) { return contact_law(s.law).time_step_bound(s); }

// Static overlap under the bed's own weight, as a fraction of d_small: a column of H / d_small
// small particles of the denser species' density (H = 2R × the bed's volume share of the tumbler)
// resting on one small-small contact. Used to refuse contacts so soft that particles would pass
// through each other.
double weight_overlap_fraction(const Scene& s) {
  double share = s.fill_level;
  if (s.cylinder()) {
    const double fl = s.large_fraction / s.mean_cube(s.d_large);
    const double fs = (1 - s.large_fraction) / s.mean_cube(s.d_small);
    const double v_solid = s.count * kPi / 6.0 / (fl + fs);
    share = std::min(1.0, v_solid / s.packing_fraction / (kPi * s.radius * s.radius * s.length));
  }
  const double column = 2 * s.radius * share / s.d_small;
  const double ms = s.mass_small();
  const double heavy = std::max(1.0, s.density_ratio);  // a column of the denser species
  const double weight = column * heavy * ms * s.g;
  return contact_law(s.law).static_overlap(s, weight) / s.d_small;
}

void validate_scene(const Scene& s) {
  auto fail = [](const std::string& key, const std::string& what) {
    throw InputError("scene error: key '" + key + "' " + what);
  };
  // The rigid bulk turns with the wall: a scene without rotation has no wall motion to carry it
  // (a frozen particle is carried by the wall's rotation).
  if (s.bulk == Bulk::rigid && (s.mode == Mode::rest || s.omega() <= 0))
    fail("fidelity.bulk", "= 'rigid' needs a rotating tumbler (protocol.mode = '" +
                              std::string(name_of(s.mode)) +
                              "', omega = " + std::to_string(s.omega()) + " rad/s); use 'dynamic'");
  if (s.d_large < s.d_small)
    fail("particles.d_large", "= " + std::to_string(s.d_large) + " must be >= particles.d_small (" +
                                  std::to_string(s.d_small) + ")");
  if (s.d_large / s.d_small > 8)
    fail("particles.d_large", "gives a size ratio above the supported maximum 8");
  const ContactLawSpec& law = contact_law(s.law);
  if (s.size_spread > 0 && !law.size_spread) {
    std::string laws;
    for (const auto& l : contact_laws())
      if (l.size_spread) laws += (laws.empty() ? "'" : " or '") + l.name + "'";
    fail("particles.size_spread", "> 0 needs contact.law = " + laws + " (the " + s.law +
                                      " law tabulates two particle sizes)");
  }
  if (s.size_spread >= s.d_small)
    fail("particles.size_spread", "must be below particles.d_small = " + std::to_string(s.d_small));
  if (law.check) law.check(s);
  if (s.cylinder()) {
    if (s.length <= 0) fail("tumbler.length", "must be > 0 for tumbler.shape = 'cylinder'");
    const double cell = s.d_large + s.skin * s.d_small;
    if (s.length < 3 * cell)
      fail("tumbler.length",
           "must be at least 3 neighbour cells (" + std::to_string(3 * cell) + ") long");
    if (s.count <= 0)
      fail("particles.count", "must be > 0 for tumbler.shape = 'cylinder' (the particle number)");
    if (s.mode == Mode::biaxial)
      fail("protocol.mode",
           "= 'biaxial' is for the sphere; a cylinder turns about its axis: "
           "use 'single_axis' with protocol.axis = 'z', or 'rest'");
    if (s.mode == Mode::single_axis && s.axis != Axis::z)
      fail("protocol.axis", "must be 'z' for a cylinder (its axis)");
    if (s.start == Start::large_top || s.start == Start::large_xneg)
      fail("fill.start", "= '" + std::string(name_of(s.start)) +
                             "' is for the sphere; a cylinder starts 'mixed' or "
                             "'large_zneg' (presegregated in two axial halves)");
    // Cheap fit check (the placement itself is in fill_cylinder.cpp): solids must not exceed 60%
    // of the cylinder.
    const double fl = s.large_fraction / s.mean_cube(s.d_large);
    const double fs = (1 - s.large_fraction) / s.mean_cube(s.d_small);
    const double v_mean = kPi / 6.0 / (fl + fs);  // volume of the mean particle (by number)
    const double v_cyl = kPi * s.radius * s.radius * s.length;
    if (s.count * v_mean > 0.6 * v_cyl)
      fail("particles.count",
           "= " + std::to_string(s.count) + " does not fit: the solids would fill " +
               std::to_string(s.count * v_mean / v_cyl) + " of the cylinder (at most 0.6)");
  } else {
    if (s.count > 0)
      fail("particles.count", "is for cylinders; a sphere is filled by particles.fill_level");
    if (s.periodic == OnOff::on)
      fail("tumbler.periodic", "= 'on' needs tumbler.shape = 'cylinder'");
    if (s.start == Start::large_zneg)
      fail("fill.start", "= 'large_zneg' is for the cylinder (axial halves)");
  }
  if (s.d_large * 4 > s.radius)
    fail("tumbler.radius",
         "must be at least 4 large diameters (" + std::to_string(4 * s.d_large) + ")");
  // Before anything is planned or allocated, and before the checks whose advice (a time step, a
  // stiffness) would not help a scene that cannot fit: the estimate is arithmetic, the bed plan
  // below walks a lattice as large as the bed.
  check_resources(s);
  const double bound = time_step_bound(s);
  if (s.time_step() > bound) {
    std::ostringstream os;
    os.precision(4);
    // The allowed values are rounded down, so that pasting them back is accepted.
    auto down = [](double v) {
      const double unit = std::pow(10.0, std::floor(std::log10(v)) - 3);
      return std::floor(v / unit) * unit;
    };
    os << "gives a time step " << s.time_step() << " s above the stability bound " << bound
       << " s = 1/sqrt(max k/m) of the stiffest pair (about t_c/pi); allowed: time.dt <= "
       << down(bound);
    if (law.time_from_collision_time)
      os << " or time.dt_fraction <= " << down(bound / s.collision_time);
    fail(s.dt > 0 ? "time.dt" : "time.dt_fraction", os.str());
  }
  if (const double ov = weight_overlap_fraction(s); ov > kMaxWeightOverlap) {
    std::ostringstream os;
    os.precision(3);
    os << "makes the contacts so soft that the bed's weight would press the bottom particles "
          "into each other by about "
       << 100 * ov << "% of d_small (at most " << 100 * kMaxWeightOverlap << "%); ";
    const StifferHint hint = law.stiffer(s, ov);
    os << "use " << hint.key << hint.relation << hint.value;
    fail(hint.key, os.str());
  }
  if (s.mode != Mode::rest && s.omega() <= 0)
    fail("protocol.rpm", "(or protocol.omega) must be > 0 when protocol.mode is '" +
                             std::string(name_of(s.mode)) + "'");
  if (s.repose_pending() && s.g <= 0)
    fail("protocol.repose",
         "= 'measured' needs gravity.g > 0 (a bed without weight has no angle of repose); give "
         "the tilt in degrees, in [0, 89]");
  if (s.still_slope_pending() && s.g <= 0)
    fail("fidelity.bulk_still_slope",
         "= 'measured' needs gravity.g > 0 (a bed without weight does not creep); give the "
         "slope in degrees, in [0, 89]");
  if (s.mode == Mode::biaxial && s.theta_z + s.theta_x <= 0 && s.iterations > 0)
    fail("protocol.theta_z",
         "and protocol.theta_x are both 0: the biaxial protocol would not move");
  // More steps than any run could take: an rpm or a time step far below the physical range (the
  // count would overflow, or the run would never end).
  if (const double steps = s.run_time() / s.time_step(); !(steps <= kMaxProtocolSteps)) {
    std::ostringstream os;
    os << "gives " << steps << " protocol steps of " << s.time_step() << " s for " << s.run_time()
       << " s of protocol (protocol.rpm, protocol.iterations, time.dt): at most "
       << kMaxProtocolSteps;
    // (The key to blame: the time step when it is below any contact's scale, else the rotation.)
    fail(s.time_step() < 1e-9 ? (s.dt > 0 ? "time.dt" : "time.dt_fraction") : "protocol.rpm",
         os.str());
  }
  // A wall that moves a good part of a particle in one step: no contact can resolve it (the
  // shipped scenes move 1e-5 to 2e-2 d_small per step; protocol.omega = 1e6 turned the cylinder
  // ~5000 rad per step, in a run of no steps).
  if (s.mode != Mode::rest && s.omega() > 0) {
    const double per_step = s.omega() * s.radius * s.time_step() / s.d_small;
    if (per_step > kMaxWallStep) {
      std::ostringstream os;
      os << "(or protocol.omega) moves the wall " << per_step
         << " d_small per time step (radius x omega x dt): at most " << kMaxWallStep
         << "; lower the rotation or the time step";
      fail("protocol.rpm", os.str());
    }
  }
  // A protocol shorter than half a time step runs no step: `protocol.iterations = 1e-7` ran "0
  // steps" and exited 0, as if it had done what was asked. (0 runs none on purpose: the bed
  // alone.)
  if (s.run_time() > 0 && s.protocol_steps() == 0) {
    const bool turns = s.mode == Mode::single_axis && s.revolutions > 0;
    const char* key = s.mode == Mode::biaxial ? "protocol.iterations"
                      : turns                 ? "protocol.revolutions"
                                              : "protocol.duration";
    std::ostringstream os;
    os << "= "
       << (s.mode == Mode::biaxial ? s.iterations
           : turns                 ? s.revolutions
                                   : s.duration)
       << " gives " << s.run_time() << " s of protocol, less than half a time step ("
       << s.time_step()
       << " s): no step would run; give a protocol of at least one time step, or 0 "
          "for the bed alone";
    fail(key, os.str());
  }
  // An interval shorter than one time step cannot be kept: it silently meant an event every step
  // (output.checkpoint_interval = 1e-12 wrote bst_tiny's whole state each step, 40x slower).
  struct Interval {
    const char* key;
    double value;
    const char* zero;  // what 0 means for the key
  };
  for (const Interval& i :
       {Interval{"output.checkpoint_interval", s.checkpoint_interval, "once per iteration"},
        Interval{"output.snapshot_interval", s.snapshot_interval, "once per iteration"},
        Interval{"output.analysis_interval", s.analysis_interval, "off"}}) {
    if (i.value > 0 && i.value < s.time_step()) {
      std::ostringstream os;
      os << "= " << i.value << " s is shorter than one time step (" << s.time_step()
         << " s): allowed 0 (" << i.zero << ") or at least the time step";
      fail(i.key, os.str());
    }
  }
  // Snapshots are files of the whole bed: more than kMaxSnapshots of them is a typo, not a study
  // (1e-300 wrote one per step: ~160 GB for bst_tiny's one iteration).
  if (s.snapshot_interval > 0) {
    const double n = s.run_time() / std::max(s.snapshot_interval, s.time_step());
    if (n > kMaxSnapshots) {
      std::ostringstream os;
      os << "= " << s.snapshot_interval << " s gives " << n << " snapshots over " << s.run_time()
         << " s of protocol: at most " << kMaxSnapshots << " (0: one per iteration)";
      fail("output.snapshot_interval", os.str());
    }
  }
  // The files a run writes: a name and two directories that must be usable before any work (a
  // run found out only when it wrote, after the bed; under mpirun one rank failed alone).
  if (s.name.find_first_not_of(" \t") == std::string::npos)
    fail("scene.name", "must not be empty (it names the output files)");
  for (const auto& [key, dir] :
       {std::pair<const char*, const std::string&>{"scene.output_dir", s.output_dir},
        {"fill.bed_cache", s.bed_cache}}) {
    std::error_code ec;
    if (dir.empty()) fail(key, "must name a directory (it is empty)");
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
      fail(key, "= '" + dir + "' names a file, not a directory");
  }
  if (!s.bed_file.empty()) {
    std::error_code ec;
    if (std::filesystem::is_directory(s.bed_file, ec))
      fail("fill.bed_file", "names a directory, not a bed file: '" + s.bed_file + "'");
    std::ifstream f(s.bed_file);
    if (!f) fail("fill.bed_file", "names a file that cannot be read: '" + s.bed_file + "'");
  } else if (!s.cylinder()) {
    // Raises InputError if the requested bed does not fit in the tumbler (counts only: the same
    // walk as the bed's, nothing stored).
    (void)plan_bed(s, false);
  }
}

}  // namespace tumble
