#pragma once
// Expansion of a campaign into cases: every sweep's product (or zip) of parameter values, times
// replicas. Pure and deterministic: every rank, slice and re-run computes the same list, the same
// case ids (a hash of the canonical parameters) and the same seeds, so resubmitting is safe.
#include <cstdint>
#include <string>
#include <vector>

#include "campaign/campaign_spec.hpp"
#include "scene/scene.hpp"

namespace tumble::campaign {

// The most cases one campaign may list (every sweep's points times its replicas): each case is a
// DEM run of minutes to days, and the list, its table and manifest are held whole; more is a
// list slipped by a unit, refused before it is made (it ran out of memory).
inline constexpr double kMaxCases = 1e6;

struct CaseParam {
  std::string name;  // a named parameter (theta_z, theta_x, f, R_rho, size_ratio) or a scene key
  ParamValue value;
};

struct Case {
  std::size_t index = 0;  // position in the expansion
  std::string id;         // 16 hex digits
  std::string point_id;
  int replica = 0;
  std::vector<CaseParam> params;       // the five named ones (resolved), then swept scene keys
  std::string params_text;             // "theta_z=57;theta_x=57;f=0.15;R_rho=1;size_ratio=2"
  std::vector<std::string> overrides;  // what the parameters set in the scene
  std::string bed_text;                // parameters that shape the bed (seed derivation)
  double cost = 0;                     // particles x protocol steps (scheduling, slicing)
  double time_limit = 0;               // wall seconds per attempt (0 = none)
  int ranks = 1;                       // ranks of the group that runs it
  std::string ranks_key;               // the key that set `ranks` (error messages)
  std::string scene_error;  // non-empty: the case's scene is invalid; it fails without running
};

struct Point {
  std::string id;
  std::vector<CaseParam> params;
  std::string params_text;
  std::vector<std::size_t> cases;  // indices into Expansion::cases, by replica
};

struct Expansion {
  Scene base;             // template + [overrides]
  std::string base_hash;  // of the resolved base scene, less the keys the campaign sets
  std::vector<Case> cases;
  std::vector<Point> points;
};

// Throws InputError (campaign-level problems: the template with its overrides is invalid, the
// collection window does not fit the base run). A single case whose parameters make an invalid
// scene is not an error here: it is recorded as failed with the scene's message.
Expansion expand(const CampaignSpec& spec);

// The seed of a case's bed: a stable hash of the campaign seed, the replica and the parameters
// that shape the bed (not the protocol, so cases that differ only in (θz, θx) share a bed: common
// random numbers, and each bed settles once). attempt > 1 with retry_seed = "new" draws afresh.
std::int64_t case_seed(const CampaignSpec& spec, const Case& c, int attempt);

// The case's scene, validated (throws InputError).
Scene case_scene(const CampaignSpec& spec, const Case& c, const std::string& case_dir,
                 const std::string& bed_cache, std::int64_t seed);

// The order in which a campaign starts its cases: the largest cost first (the long cases start
// early, the short ones fill the gaps at the end); among equal costs the lower replica first, then
// the expansion's order. So a campaign stopped part-way (a job's time limit, a machine taken back)
// has the same replicas of every point of equal cost, a paired comparison rather than all the
// replicas of one point and none of the next.
bool runs_before(const Case& a, const Case& b);

// Slice i of n (1-based): cases sorted by cost (largest first) dealt in a snake over the slices,
// so each slice gets a similar share of the work. Returns case indices.
std::vector<std::size_t> slice_cases(const Expansion& e, int i, int n);

}  // namespace tumble::campaign
