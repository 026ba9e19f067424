#pragma once
// A campaign file (TOML): a scene template, overrides for every case, the parameter set as
// products or zipped lists over (θz, θx, f, R_ρ, size ratio, any scene key), replicas, the rank
// layout, the fidelity tier, the retry policy and which fields to collect when. Validated in full
// before any work, with messages that name the key, as for scenes (docs/campaign.md).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "base/text_util.hpp"

namespace tumble::campaign {

struct ParamValue {
  bool numeric = true;
  double num = 0;
  std::string text;  // as written (strings), or the number rendered canonically
};

// One [[sweep]] table: a product over its lists (or, with zip = true, lists paired element by
// element); scalars are lists of one.
struct Sweep {
  std::vector<std::pair<std::string, std::vector<ParamValue>>> axes;  // name -> values
  bool zip = false;
  int replicas = -1;        // -1: campaign.replicas
  double time_limit = -1;   // -1: campaign.time_limit
  int ranks_per_case = -1;  // -1: campaign.ranks_per_case (a bigger point may get more ranks)
  std::string ranks_key;    // "sweep[i].ranks_per_case" when set (error messages)
};

struct CollectSpec {
  bool concentration = true, displacement = true, series = true;
  double from = 0, to = -1;       // protocol iterations averaged over; to < 0: end of run
  int samples_per_iteration = 1;  // 1: stroboscopic, at the end of every iteration
  // k of Δψ over k periods, one map per lag (Yu 2022 Figs. 6-7 use 6 and 18 iterations for
  // period-3 islands). The first is the primary lag (fields group "displacement"); the others
  // are written as "displacement_k<k>" (displacement_group()).
  std::vector<double> displacement_periods = {1};
  int grid = 24;              // N of the N x N equal-area Lambert grid
  std::string frame = "lab";  // lab | tumbler
  double shell_inner = 0.9;   // concentration shell: shell_inner < r/R < 1
  // shell_inner = "one_diameter": the shell is one diameter of the mapped species thick
  // (1 - d/R of each case's scene after its tier; Yu 2022's 0.97 for 2 mm grains at R = 70 mm).
  bool shell_one_diameter = false;
  double displacement_inner = 0.8;  // Δψ particles: displacement_inner <= r/R <= 1
  bool any() const { return concentration || displacement || series; }
  // Set from the scene template (not a key): a cylinder campaign collects Rapaport's series
  // (S_a, S_r, band count against revolutions) and no sphere fields.
  bool cylinder = false;
  std::string canonical() const;  // enters the case id: different collection, different output
  // The fields-file group of lag i: "displacement" for the first, "displacement_k6" for k = 6.
  std::string displacement_group(std::size_t i) const;
};

struct CampaignSpec {
  std::string file;  // the campaign file as given
  std::string name = "campaign";
  std::string scene_path;  // resolved against the campaign file's directory
  std::string scene_text;  // the template's contents
  std::string output_dir;  // campaign directory (relative to the working directory)
  std::string bed_cache;   // "" = OUTPUT/beds
  std::int64_t seed = 1;
  int replicas = 1;
  int ranks_per_case = 1;  // ranks of the group that runs each case (domain decomposition)
  std::string tier = "standard";
  int max_attempts = 2;
  std::string retry_seed = "same";     // same | new
  double time_limit = 0;               // wall seconds per attempt (0 = none)
  bool snapshots = false;              // keep particle snapshots of every case
  double progress_interval = 30;       // wall seconds between progress lines
  std::vector<std::string> overrides;  // [overrides] as "section.key=value"
  std::vector<Sweep> sweeps;
  CollectSpec collect;
};

// Throws InputError naming the key on the first problem.
CampaignSpec parse_campaign(const std::string& toml_text, const std::string& origin,
                            const std::string& base_dir);
CampaignSpec load_campaign(const std::string& path);

// The five named parameters of Yu 2022 and the scene keys they set. size_ratio sets
// particles.d_large = size_ratio * particles.d_small (size_ratio = 1 with R_rho != 1 is a
// density-bidisperse bed, Yu 2022 Sec. IV D).
struct NamedParam {
  const char* name;
  const char* scene_key;  // nullptr for size_ratio
  const char* help;
};
const std::vector<NamedParam>& named_params();

// Keys the campaign sets itself for every case; sweeps and [overrides] may not touch them.
bool campaign_controlled_key(const std::string& scene_key);

// Number rendering: canonical (round-trip, for hashing; base/text_util.hpp) and display (for
// people).
std::string display_number(double v);

}  // namespace tumble::campaign
