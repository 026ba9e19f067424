#include "campaign/expand.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "base/error.hpp"
#include "base/hash.hpp"
#include "campaign/collect_plan.hpp"
#include "scene/fill.hpp"

namespace tumble::campaign {
namespace {

// One combination of sweep values: scene key or named parameter -> value.
using Combo = std::vector<std::pair<std::string, ParamValue>>;

std::vector<Combo> combos(const Sweep& sw) {
  std::vector<Combo> out(1);
  if (sw.zip) {
    std::size_t len = 1;
    for (const auto& [k, vals] : sw.axes) len = std::max(len, vals.size());
    out.assign(len, {});
    for (std::size_t i = 0; i < len; ++i)
      for (const auto& [k, vals] : sw.axes) out[i].emplace_back(k, vals[vals.size() == 1 ? 0 : i]);
    return out;
  }
  for (const auto& [k, vals] : sw.axes) {
    std::vector<Combo> next;
    for (const auto& c : out)
      for (const auto& v : vals) {
        Combo n = c;
        n.emplace_back(k, v);
        next.push_back(std::move(n));
      }
    out = std::move(next);
  }
  return out;
}

ParamValue num(double v) {
  ParamValue p;
  p.numeric = true;
  p.num = v;
  p.text = canonical_number(v);
  return p;
}

std::string display(const ParamValue& v) { return v.numeric ? display_number(v.num) : v.text; }

// A rigid-bulk key added after rigid campaigns existed, at the value that keeps the behaviour of
// before the key: it stays out of case ids, so their ids stand. fidelity.bulk_thaw_gravity = 2
// (its rule off), fidelity.bulk_segment_thaw = on (every segment change thaws) and
// fidelity.bulk_still_slope = 0 (the surface layer never freezes).
bool added_bulk_key_off(const std::string& key, const Scene& scene) {
  return (key == "fidelity.bulk_thaw_gravity" && scene.bulk_thaw_gravity == 2) ||
         (key == "fidelity.bulk_segment_thaw" && scene.bulk_segment_thaw == SegmentThaw::on) ||
         (key == "fidelity.bulk_still_slope" && scene.bulk_still_slope.known &&
          scene.bulk_still_slope.deg == 0);
}

}  // namespace

Expansion expand(const CampaignSpec& spec) {
  Expansion e;
  try {
    e.base = parse_scene(spec.scene_text, spec.overrides, spec.scene_path);
  } catch (const InputError& err) {
    throw InputError("campaign error (" + spec.file + "): the scene template '" + spec.scene_path +
                     "' with [overrides] is invalid: " + err.what());
  }
  // Every key that can change a case's numbers enters its id. Of the output keys only the
  // checkpoint interval does (a checkpoint forces a neighbour rebuild, which reorders sums); the
  // others (progress, snapshots, analysis outputs) may change without recomputing anything.
  // The rigid bulk's keys change nothing while the bulk is dynamic (bitwise: test_rigid_bulk.cpp),
  // and leaving them out then keeps the ids that campaigns had before the keys existed.
  // parallel.frozen_weight moves only the cuts between ranks, and parallel.newton only which rank
  // computes a border pair (round-off, as the rank count does, which is not in the id either;
  // leaving the latter out also keeps the ids campaigns had before the key existed).
  const bool dynamic_bulk = e.base.bulk == Bulk::dynamic;
  std::string base_text;
  for (const auto& [k, v] : e.base.resolved)
    if (!campaign_controlled_key(k) &&
        (k.rfind("output.", 0) != 0 || k == "output.checkpoint_interval") &&
        k != "parallel.frozen_weight" && k != "parallel.newton" &&
        !(dynamic_bulk && k.rfind("fidelity.bulk", 0) == 0) && !added_bulk_key_off(k, e.base))
      base_text += k + "=" + v + "\n";
  e.base_hash = hex16(fnv1a64(base_text));
  // A window beyond the base run is a campaign error, not one failure per case.
  try {
    (void)make_collect_plan(spec.collect, e.base);
  } catch (const InputError& err) {
    throw InputError("campaign error (" + spec.file + "): " + err.what());
  }

  std::vector<Sweep> sweeps = spec.sweeps;
  if (sweeps.empty()) sweeps.emplace_back();  // no sweep: the template itself, replicated
  // The cases the lists make, counted before they are made: a product of long lists (a range
  // with a step slipped by a unit) ran out of memory in the expansion itself, std::bad_alloc.
  {
    double total = 0;
    for (std::size_t k = 0; k < sweeps.size(); ++k) {
      const Sweep& sw = sweeps[k];
      double points = 1;
      for (const auto& [key, vals] : sw.axes)
        points = sw.zip ? std::max(points, static_cast<double>(vals.size()))
                        : points * static_cast<double>(vals.size());
      const double cases = points * (sw.replicas > 0 ? sw.replicas : spec.replicas);
      total += cases;
      if (total > kMaxCases) {
        std::ostringstream os;
        os << "campaign error (" << spec.file << "): sweep " << k + 1 << " makes " << cases
           << " cases (" << total << " with the sweeps before it): at most " << kMaxCases
           << " in one campaign; shorten its lists or split the campaign";
        throw InputError(os.str());
      }
    }
  }
  std::set<std::string> seen;
  std::map<std::string, std::size_t> point_index;
  for (std::size_t sweep_index = 0; sweep_index < sweeps.size(); ++sweep_index) {
    const Sweep& sw = sweeps[sweep_index];
    // A point given twice by one sweep is a value listed twice (a typo, or 57 and 57.0): it
    // would run once, and the campaign would have fewer points than the lists say. Two sweeps
    // may share a point (it runs once), one sweep may not repeat one.
    std::set<std::string> points_of_this_sweep;
    for (const Combo& combo : combos(sw)) {
      std::map<std::string, ParamValue> given(combo.begin(), combo.end());
      auto named_value = [&](const char* name, double fallback) {
        auto it = given.find(name);
        return it != given.end() ? it->second : num(fallback);
      };
      // d_small may itself be swept; size_ratio scales it.
      double d_small = e.base.d_small;
      if (auto it = given.find("particles.d_small"); it != given.end() && it->second.numeric)
        d_small = it->second.num;
      Case c;
      if (e.base.cylinder()) {  // the cylinder turns about its axis: no biaxial angles
        for (const char* angle : {"theta_z", "theta_x"})
          if (given.count(angle))
            throw InputError("campaign error (" + spec.file + "): sweep key '" + angle +
                             "' is a biaxial-sphere parameter; the template is a cylinder");
      } else {
        c.params.push_back({"theta_z", named_value("theta_z", e.base.theta_z)});
        c.params.push_back({"theta_x", named_value("theta_x", e.base.theta_x)});
      }
      c.params.push_back({"f", named_value("f", e.base.large_fraction)});
      c.params.push_back({"R_rho", named_value("R_rho", e.base.density_ratio)});
      c.params.push_back({"size_ratio", named_value("size_ratio", e.base.d_large / d_small)});
      for (const auto& [k, v] : given)  // std::map: extras in key order
        if (k.find('.') != std::string::npos) c.params.push_back({k, v});
      for (const auto& p : named_params()) {
        auto it = given.find(p.name);
        if (it == given.end()) continue;
        if (p.scene_key)
          c.overrides.push_back(std::string(p.scene_key) + "=" + it->second.text);
        else
          c.overrides.push_back("particles.d_large=" + canonical_number(it->second.num * d_small));
      }
      for (const auto& [k, v] : given)
        if (k.find('.') != std::string::npos) c.overrides.push_back(k + "=" + v.text);

      std::string canon = "tier=" + spec.tier, shown;
      for (const auto& p : c.params) {
        canon += ";" + p.name + "=" + p.value.text;
        shown += (shown.empty() ? "" : ";") + p.name + "=" + display(p.value);
        // Keys that act only after the bed is settled (the protocol, the output, the rigid-bulk
        // option) leave the seed alone: points that differ only in them run on common beds, so
        // their differences are paired (e.g. fidelity.bulk = dynamic against rigid).
        const bool after_bed =
            p.name == "theta_z" || p.name == "theta_x" || p.name.rfind("protocol.", 0) == 0 ||
            p.name.rfind("output.", 0) == 0 || p.name.rfind("fidelity.bulk", 0) == 0;
        if (!after_bed) c.bed_text += p.name + "=" + p.value.text + ";";
      }
      canon += ";scene=" + e.base_hash + ";collect=" + spec.collect.canonical();
      if (!points_of_this_sweep.insert(canon).second)
        throw InputError("campaign error (" + spec.file + "): sweep[" +
                         std::to_string(sweep_index) + "] gives the point " + shown +
                         " twice (a value listed twice in one list?); list each value once");
      c.params_text = shown;
      c.time_limit = sw.time_limit >= 0 ? sw.time_limit : spec.time_limit;
      c.ranks = sw.ranks_per_case > 0 ? sw.ranks_per_case : spec.ranks_per_case;
      c.ranks_key = sw.ranks_per_case > 0 ? sw.ranks_key : "campaign.ranks_per_case";

      // Cost and validity of the scene, once per point (replicas differ only in the seed).
      double cost = 0;
      std::string scene_error;
      try {
        Scene s = case_scene(spec, c, "case", "beds", 1);
        // A point the sweep makes rigid on a dynamic template: the template's hash left the bulk's
        // thresholds out, so they enter here (as they would for a rigid template), and a change
        // of their defaults gives other cases instead of mixing two settings in one point.
        if (dynamic_bulk && s.bulk == Bulk::rigid)
          for (const auto& [k, v] : s.resolved)
            if (k.rfind("fidelity.bulk_", 0) == 0 && !added_bulk_key_off(k, s))
              canon += ";" + k + "=" + v;
        (void)make_collect_plan(spec.collect, s);
        const auto steps = static_cast<double>(s.protocol_steps());
        double particles = 1000;  // a given bed file: its size is not known without reading it
        if (s.bed_file.empty()) particles = static_cast<double>(planned_particle_count(s));
        cost = particles * steps;
      } catch (const InputError& err) {
        scene_error = err.what();
      }
      c.point_id = hex16(mix64(fnv1a64(canon)));

      const int replicas = sw.replicas > 0 ? sw.replicas : spec.replicas;
      for (int r = 0; r < replicas; ++r) {
        Case cr = c;
        cr.replica = r;
        cr.id = hex16(mix64(fnv1a64(canon + ";campaign_seed=" + std::to_string(spec.seed) +
                                    ";replica=" + std::to_string(r))));
        if (!seen.insert(cr.id).second) continue;  // the same case from two sweeps
        cr.cost = cost;
        cr.scene_error = scene_error;
        cr.index = e.cases.size();
        auto [it, fresh] = point_index.emplace(cr.point_id, e.points.size());
        if (fresh) e.points.push_back({cr.point_id, cr.params, cr.params_text, {}});
        e.points[it->second].cases.push_back(cr.index);
        e.cases.push_back(std::move(cr));
      }
    }
  }
  return e;
}

std::int64_t case_seed(const CampaignSpec& spec, const Case& c, int attempt) {
  std::string key = "campaign_seed=" + std::to_string(spec.seed) +
                    ";replica=" + std::to_string(c.replica) + ";" + c.bed_text;
  if (spec.retry_seed == "new" && attempt > 1) key += ";attempt=" + std::to_string(attempt);
  // fill.seed accepts [0, 9e15] (exact in a double).
  return static_cast<std::int64_t>(mix64(fnv1a64(key)) % 9000000000000000ull);
}

Scene case_scene(const CampaignSpec& spec, const Case& c, const std::string& case_dir,
                 const std::string& bed_cache, std::int64_t seed) {
  std::vector<std::string> o = spec.overrides;
  o.insert(o.end(), c.overrides.begin(), c.overrides.end());
  // The tier derives its values from the template; the sweep's own keys still win.
  if (spec.tier != "standard") o.push_back("fidelity.tier=" + spec.tier);
  o.push_back("scene.output_dir=" + case_dir);
  o.push_back("scene.name=" + spec.name + "_" + c.id);
  o.push_back("fill.seed=" + std::to_string(seed));
  o.push_back("fill.bed_cache=" + bed_cache);
  o.push_back("output.progress_interval=" + canonical_number(spec.progress_interval));
  return parse_scene(spec.scene_text, o, spec.scene_path);
}

bool runs_before(const Case& a, const Case& b) {
  if (a.cost != b.cost) return a.cost > b.cost;
  if (a.replica != b.replica) return a.replica < b.replica;
  return a.index < b.index;
}

std::vector<std::size_t> slice_cases(const Expansion& e, int i, int n) {
  std::vector<std::size_t> order(e.cases.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (e.cases[a].cost != e.cases[b].cost) return e.cases[a].cost > e.cases[b].cost;
    return e.cases[a].id < e.cases[b].id;
  });
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t round = k / n, pos = k % n;
    const std::size_t slot = round % 2 == 0 ? pos : n - 1 - pos;  // snake: balances the costs
    if (static_cast<int>(slot) == i - 1) out.push_back(order[k]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace tumble::campaign
