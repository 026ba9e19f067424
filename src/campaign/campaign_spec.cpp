#include "campaign/campaign_spec.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "base/error.hpp"
#include "base/text_util.hpp"
#include "scene/scene.hpp"

namespace tumble::campaign {
namespace fs = std::filesystem;

const std::vector<NamedParam>& named_params() {
  static const std::vector<NamedParam> p = {
      {"theta_z", "protocol.theta_z", "rotation about z per iteration [deg]"},
      {"theta_x", "protocol.theta_x", "rotation about x per iteration [deg]"},
      {"f", "particles.large_fraction", "large-particle volume fraction of the solids"},
      {"R_rho", "particles.density_ratio", "density ratio rho_large / rho_small"},
      {"size_ratio", nullptr, "d_large / d_small (1 with R_rho != 1: density-bidisperse bed)"},
  };
  return p;
}

bool campaign_controlled_key(const std::string& k) {
  return k == "scene.output_dir" || k == "scene.name" || k == "fill.seed" || k == "fill.bed_cache";
}

std::string display_number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string CollectSpec::canonical() const {
  std::ostringstream os;
  os << "fields=" << (concentration ? "c" : "") << (displacement ? "d" : "") << (series ? "s" : "")
     << ";from=" << canonical_number(from) << ";to=" << canonical_number(to)
     << ";n=" << samples_per_iteration << ";k=";
  // One lag prints as before, so the case ids of single-lag campaigns do not change.
  for (std::size_t i = 0; i < displacement_periods.size(); ++i)
    os << (i ? "," : "") << canonical_number(displacement_periods[i]);
  os << ";grid=" << grid << ";frame=" << frame << ";shell="
     << (shell_one_diameter ? std::string("one_diameter") : canonical_number(shell_inner))
     << ";dinner=" << canonical_number(displacement_inner);
  if (cylinder) os << ";cylinder";
  return os.str();
}

std::string CollectSpec::displacement_group(std::size_t i) const {
  return i == 0 ? "displacement" : "displacement_k" + canonical_number(displacement_periods.at(i));
}

namespace {

// True if any collect.* key differs from its default (a [collect] table was given).
bool collect_keys_given(const CollectSpec& c) { return c.canonical() != CollectSpec{}.canonical(); }

// Error context: every message starts "campaign error (FILE): key 'K'".
struct Ctx {
  std::string origin;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError("campaign error (" + origin + "): key '" + key + "' " + what);
  }
  // `bare` is the key as it is spelled in its table, compared with the `known` spellings.
  [[noreturn]] void unknown(const std::string& key, const std::vector<std::string>& known,
                            const std::string& where, const std::string& bare = "") const {
    std::string best;
    std::size_t best_d = 1000;
    for (const auto& k : known) {
      const std::size_t d = edit_distance(bare.empty() ? key : bare, k);
      if (d < best_d) best_d = d, best = k;
    }
    std::string msg = "campaign error (" + origin + "): unknown key '" + key + "' in " + where;
    if (best_d <= 4) msg += " (did you mean '" + best + "'?)";
    msg += "; see docs/campaign.md for the keys";
    throw InputError(msg);
  }
};

std::optional<double> number_of(const toml::node& n) {
  if (n.is_integer() || n.is_floating_point()) return n.value<double>();
  return std::nullopt;
}

double real(const Ctx& c, const std::string& key, const toml::node& n, double lo, double hi) {
  const auto v = number_of(n);
  std::ostringstream range;
  range << "[" << lo << ", " << hi << "]";
  if (!v || !std::isfinite(*v)) c.fail(key, "must be a number in " + range.str());
  if (*v < lo || *v > hi)
    c.fail(key, "= " + display_number(*v) + " is out of range " + range.str());
  return *v;
}
long long integer(const Ctx& c, const std::string& key, const toml::node& n, double lo, double hi) {
  const double v = real(c, key, n, lo, hi);
  if (v != std::floor(v)) c.fail(key, "= " + display_number(v) + " must be an integer");
  return static_cast<long long>(v);
}
std::string text(const Ctx& c, const std::string& key, const toml::node& n,
                 const std::vector<std::string>& choices = {}) {
  const auto s = n.value<std::string>();
  if (!s || !n.is_string()) c.fail(key, "must be a string");
  if (!choices.empty() && std::find(choices.begin(), choices.end(), *s) == choices.end()) {
    std::string allowed;
    for (const auto& ch : choices) allowed += (allowed.empty() ? "" : ", ") + ch;
    c.fail(key, "= '" + *s + "' is not one of: " + allowed);
  }
  return *s;
}
bool boolean(const Ctx& c, const std::string& key, const toml::node& n) {
  if (!n.is_boolean()) c.fail(key, "must be true or false");
  return *n.value<bool>();
}

// Flattens nested tables into dotted keys: `time.dt = 1` and `"time.dt" = 1` read the same.
void flatten(const toml::table& t, const std::string& prefix,
             std::vector<std::pair<std::string, const toml::node*>>& out) {
  for (const auto& [k, node] : t) {
    const std::string key =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = node.as_table())
      flatten(*sub, key, out);
    else
      out.emplace_back(key, &node);
  }
}

std::vector<std::string> scene_keys() {
  std::vector<std::string> keys;
  for (const auto& s : scene_schema()) keys.push_back(s.key);
  return keys;
}

ParamValue param_value(const Ctx& c, const std::string& key, const toml::node& n, bool named) {
  ParamValue v;
  if (auto d = number_of(n)) {
    if (!std::isfinite(*d)) c.fail(key, "must be finite");
    v.numeric = true;
    v.num = *d;
    v.text = canonical_number(*d);
  } else if (n.is_string() && !named) {
    v.numeric = false;
    v.text = *n.value<std::string>();
  } else if (n.is_boolean() && !named) {
    v.numeric = false;
    v.text = *n.value<bool>() ? "true" : "false";
  } else {
    c.fail(key, named ? "must be a number or a list of numbers"
                      : "must be a number or a string, "
                        "or a list of them");
  }
  return v;
}

void parse_campaign_table(const Ctx& c, const toml::table& t, CampaignSpec& s,
                          const std::string& base_dir) {
  static const std::vector<std::string> known = {
      "name",           "scene",     "output_dir",       "seed",       "replicas",
      "ranks_per_case", "tier",      "max_attempts",     "retry_seed", "time_limit",
      "bed_cache",      "snapshots", "progress_interval"};
  bool have_scene = false, have_output = false;
  for (const auto& [k, node] : t) {
    const std::string name(k.str());
    const std::string key = "campaign." + name;
    if (name == "name") {
      s.name = text(c, key, node);
      // (It names results/<name>, the default output_dir: ".." was the folder above results.)
      if (s.name.empty() || s.name.find('/') != std::string::npos || s.name == "." ||
          s.name == "..")
        c.fail(key, "must be a non-empty name without '/', not '.' or '..'");
    } else if (name == "scene") {
      const std::string p = text(c, key, node);
      s.scene_path =
          fs::path(p).is_absolute() ? p : (fs::path(base_dir) / p).lexically_normal().string();
      have_scene = true;
    } else if (name == "output_dir") {
      s.output_dir = text(c, key, node);
      if (s.output_dir.find_first_not_of(" \t") == std::string::npos)  // ("" wrote into "/")
        c.fail(key, "must name a directory (it is empty)");
      have_output = true;
    } else if (name == "seed") {
      s.seed = integer(c, key, node, 0, 9.0e15);
    } else if (name == "replicas") {
      s.replicas = static_cast<int>(integer(c, key, node, 1, 1e6));
    } else if (name == "ranks_per_case") {
      s.ranks_per_case = static_cast<int>(integer(c, key, node, 1, 1e6));
    } else if (name == "tier") {
      s.tier = text(c, key, node, {"standard", "reference", "fast", "preview"});
    } else if (name == "max_attempts") {
      s.max_attempts = static_cast<int>(integer(c, key, node, 1, 100));
    } else if (name == "retry_seed") {
      s.retry_seed = text(c, key, node, {"same", "new"});
    } else if (name == "time_limit") {
      s.time_limit = real(c, key, node, 0, 1e9);
    } else if (name == "bed_cache") {
      s.bed_cache = text(c, key, node);
    } else if (name == "snapshots") {
      s.snapshots = boolean(c, key, node);
    } else if (name == "progress_interval") {
      s.progress_interval = real(c, key, node, 0, 1e6);
    } else {
      std::vector<std::string> full;
      for (const auto& kk : known) full.push_back("campaign." + kk);
      c.unknown(key, full, "[campaign]");
    }
  }
  if (!have_scene)
    c.fail("campaign.scene", "is required: the scene template every case starts from");
  if (!have_output) s.output_dir = "results/" + s.name;
}

void parse_overrides(const Ctx& c, const toml::table& t, CampaignSpec& s) {
  std::vector<std::pair<std::string, const toml::node*>> flat;
  flatten(t, "", flat);
  for (const auto& [key, node] : flat) {
    const std::string full = "overrides." + key;
    if (campaign_controlled_key(key))
      c.fail(full, "is set by the campaign for every case (case directory, seed, bed cache)");
    const ParamValue v = param_value(c, full, *node, false);
    s.overrides.push_back(key + "=" + v.text);
  }
}

Sweep parse_sweep(const Ctx& c, const toml::table& t, int index) {
  Sweep sw;
  const std::string where = "sweep[" + std::to_string(index) + "]";
  std::vector<std::pair<std::string, const toml::node*>> flat;
  flatten(t, "", flat);
  std::vector<std::string> known = {"zip", "replicas", "time_limit", "ranks_per_case"};
  for (const auto& p : named_params()) known.push_back(p.name);
  const auto skeys = scene_keys();
  known.insert(known.end(), skeys.begin(), skeys.end());
  std::set<std::string> scene_keys_set;  // to catch a named parameter given twice
  for (const auto& [key, node] : flat) {
    const std::string full = where + "." + key;
    if (key == "zip") {
      sw.zip = boolean(c, full, *node);
      continue;
    }
    if (key == "replicas") {
      sw.replicas = static_cast<int>(integer(c, full, *node, 1, 1e6));
      continue;
    }
    if (key == "time_limit") {
      sw.time_limit = real(c, full, *node, 0, 1e9);
      continue;
    }
    if (key == "ranks_per_case") {
      sw.ranks_per_case = static_cast<int>(integer(c, full, *node, 1, 1e6));
      sw.ranks_key = full;
      continue;
    }
    const NamedParam* named = nullptr;
    for (const auto& p : named_params())
      if (key == p.name) named = &p;
    // A scene key that a parameter name stands for ("protocol.theta_z" for theta_z) is that
    // parameter: two sweeps that give the same point by either name give one point (before, two
    // points with the same seed and physics, run twice).
    for (const auto& p : named_params())
      if (!named && p.scene_key && key == p.scene_key) named = &p;
    if (!named && std::find(skeys.begin(), skeys.end(), key) == skeys.end())
      c.unknown(
          full, known,
          where + " (a parameter name, a scene key, zip, replicas, time_limit or ranks_per_case)",
          key);
    if (!named && campaign_controlled_key(key))
      c.fail(full, "is set by the campaign for every case (case directory, seed, bed cache)");
    const std::string skey =
        named ? (named->scene_key ? named->scene_key : "particles.d_large") : key;
    if (!scene_keys_set.insert(skey).second)
      c.fail(full, "sets scene key '" + skey + "' which another key of " + where + " already sets");
    std::vector<ParamValue> values;
    if (const auto* arr = node->as_array()) {
      if (arr->empty()) c.fail(full, "is an empty list");
      for (const auto& item : *arr) values.push_back(param_value(c, full, item, named != nullptr));
    } else {
      values.push_back(param_value(c, full, *node, named != nullptr));
    }
    if (named && std::string(named->name) == "size_ratio")
      for (const auto& v : values)
        if (v.num < 1) c.fail(full, "= " + display_number(v.num) + " must be >= 1");
    sw.axes.emplace_back(named ? std::string(named->name) : key, std::move(values));
  }
  if (sw.zip) {
    std::size_t len = 1;
    for (const auto& [k, vals] : sw.axes) {
      if (vals.size() == 1) continue;
      if (len != 1 && vals.size() != len)
        c.fail(where + "." + k, "has " + std::to_string(vals.size()) +
                                    " values but another list of this zip sweep has " +
                                    std::to_string(len));
      len = vals.size();
    }
  }
  return sw;
}

void parse_collect(const Ctx& c, const toml::table& t, CollectSpec& cs) {
  static const std::vector<std::string> known = {"collect.fields",
                                                 "collect.iterations",
                                                 "collect.samples_per_iteration",
                                                 "collect.displacement_periods",
                                                 "collect.grid",
                                                 "collect.frame",
                                                 "collect.shell_inner",
                                                 "collect.displacement_inner"};
  for (const auto& [k, node] : t) {
    const std::string key = "collect." + std::string(k.str());
    if (key == "collect.fields") {
      const auto* arr = node.as_array();
      if (!arr) c.fail(key, "must be a list of: concentration, displacement, series");
      cs.concentration = cs.displacement = cs.series = false;
      for (const auto& item : *arr) {
        const std::string f = text(c, key, item, {"concentration", "displacement", "series"});
        bool& on = f == "concentration"  ? cs.concentration
                   : f == "displacement" ? cs.displacement
                                         : cs.series;
        if (on) c.fail(key, "lists '" + f + "' twice");
        on = true;
      }
      if (!cs.any()) c.fail(key, "is empty: nothing would be collected");
    } else if (key == "collect.iterations") {
      const auto* arr = node.as_array();
      if (!arr || arr->size() != 2)
        c.fail(key, "must be [from, to]: the protocol iterations to average over");
      cs.from = real(c, key, *arr->get(0), 0, 1e6);
      cs.to = real(c, key, *arr->get(1), 0, 1e6);
      if (cs.to <= cs.from)
        c.fail(key, "= [" + display_number(cs.from) + ", " + display_number(cs.to) +
                        "]: 'to' must be larger than 'from'");
    } else if (key == "collect.samples_per_iteration") {
      cs.samples_per_iteration = static_cast<int>(integer(c, key, node, 1, 1e7));
    } else if (key == "collect.displacement_periods") {
      // A number, or a list of distinct lags: [1, 6, 18] gives a Δψ map per lag.
      cs.displacement_periods.clear();
      if (const auto* arr = node.as_array()) {
        if (arr->empty() || arr->size() > 8)
          c.fail(key, "must be a number or a list of 1 to 8 numbers (periods), not " +
                          std::to_string(arr->size()));
        for (const auto& item : *arr) {
          const double k = real(c, key, item, 1e-9, 1e6);
          for (const double prev : cs.displacement_periods)
            if (prev == k) c.fail(key, "lists " + display_number(k) + " twice");
          cs.displacement_periods.push_back(k);
        }
      } else {
        cs.displacement_periods.push_back(real(c, key, node, 1e-9, 1e6));
      }
    } else if (key == "collect.grid") {
      cs.grid = static_cast<int>(integer(c, key, node, 2, 1024));
    } else if (key == "collect.frame") {
      cs.frame = text(c, key, node, {"lab", "tumbler"});
    } else if (key == "collect.shell_inner") {
      // A number in [0, 0.999], or "one_diameter" (resolved per case by the collect plan).
      if (node.is_string()) {
        (void)text(c, key, node, {"one_diameter"});
        cs.shell_one_diameter = true;
      } else {
        cs.shell_inner = real(c, key, node, 0, 0.999);
        cs.shell_one_diameter = false;
      }
    } else if (key == "collect.displacement_inner") {
      cs.displacement_inner = real(c, key, node, 0, 0.999);
    } else {
      c.unknown(key, known, "[collect]");
    }
  }
  // Δψ pairs samples k periods apart: k must be a whole number of sample spacings.
  for (const double k : cs.displacement_periods) {
    const double m = k * cs.samples_per_iteration;
    if (cs.displacement && (std::fabs(m - std::round(m)) > 1e-9 * std::max(1.0, m) || m < 0.5))
      c.fail("collect.displacement_periods",
             "= " + display_number(k) +
                 " must be a whole multiple of 1 / collect.samples_per_iteration (= " +
                 display_number(1.0 / cs.samples_per_iteration) + ")");
  }
}

}  // namespace

CampaignSpec parse_campaign(const std::string& toml_text, const std::string& origin,
                            const std::string& base_dir) {
  const Ctx c{origin};
  toml::table tbl;
  try {
    tbl = toml::parse(toml_text, origin);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << "campaign error: " << origin << " is not valid TOML: " << e.description() << " (line "
       << e.source().begin.line << ")";
    throw InputError(os.str());
  }
  CampaignSpec s;
  s.file = origin;
  bool have_campaign = false;
  for (const auto& [k, node] : tbl) {
    const std::string name(k.str());
    if (name == "campaign") {
      if (!node.is_table()) c.fail("campaign", "must be a table");
      parse_campaign_table(c, *node.as_table(), s, base_dir);
      have_campaign = true;
    } else if (name == "overrides") {
      if (!node.is_table()) c.fail("overrides", "must be a table of scene keys");
      parse_overrides(c, *node.as_table(), s);
    } else if (name == "sweep") {
      if (const auto* arr = node.as_array()) {
        int i = 0;
        for (const auto& item : *arr) {
          if (!item.is_table()) c.fail("sweep", "must be tables ([[sweep]])");
          s.sweeps.push_back(parse_sweep(c, *item.as_table(), i++));
        }
      } else if (const auto* t = node.as_table()) {
        s.sweeps.push_back(parse_sweep(c, *t, 0));
      } else {
        c.fail("sweep", "must be a table ([[sweep]])");
      }
    } else if (name == "collect") {
      if (!node.is_table()) c.fail("collect", "must be a table");
      parse_collect(c, *node.as_table(), s.collect);
    } else {
      c.unknown(name, {"campaign", "overrides", "sweep", "collect"}, "the top level");
    }
  }
  if (!have_campaign) c.fail("campaign", "table is missing (it names at least the scene template)");
  // The template goes through the scene loader's file checks (a directory, an empty or
  // comment-only file, no [scene] name), named here as the campaign key that points to it.
  try {
    s.scene_text = read_scene_file(s.scene_path);
  } catch (const InputError& e) {
    std::string why = e.what();
    if (why.rfind("scene error: ", 0) == 0) why = why.substr(13);
    c.fail("campaign.scene", "= '" + s.scene_path + "': " + why);
  }
  // The template's shape (or its override) decides what a case collects. (A name that is no
  // shape is reported by the scene loader when the cases are expanded.)
  Shape shape = Shape::sphere;
  try {
    const toml::table scene = toml::parse(s.scene_text, s.scene_path);
    if (auto v = scene["tumbler"]["shape"].value<std::string>()) enum_from_name(*v, shape);
  } catch (const toml::parse_error&) {
    // Reported with its line by the scene loader when the cases are expanded.
  }
  for (const auto& o : s.overrides)
    if (o.rfind("tumbler.shape=", 0) == 0) enum_from_name(o.substr(14), shape);
  if (shape == Shape::cylinder) {
    if (collect_keys_given(s.collect))
      c.fail("collect",
             "is for the sphere's maps; a cylinder campaign collects S_a, S_r and the "
             "band count over the whole run (remove the [collect] table)");
    s.collect.cylinder = true;
    s.collect.concentration = s.collect.displacement = false;
  }
  return s;
}

CampaignSpec load_campaign(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec))  // an ifstream opens a directory and reads it as empty
    throw InputError("campaign error: '" + path + "' is a directory, not a campaign file (TOML)");
  std::ifstream in(path);
  if (!in) throw InputError("campaign error: cannot read campaign file '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_campaign(ss.str(), path, fs::path(path).parent_path().string());
}

}  // namespace tumble::campaign
