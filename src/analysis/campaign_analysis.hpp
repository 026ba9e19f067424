#pragma once
// `tumble analyze campaign DIR`: the analyses of Yu 2022 that need the CM islands, for every case
// of a campaign directory (docs/campaign.md layout), folded per parameter point with 95%
// confidence intervals across replicas:
//   * island enrichment of each case from its time-averaged large-particle volume map
//     (fields.h5 concentration/volume_large, the c_L window of the campaign) and, when the case
//     kept snapshots, from the particles of its last snapshot;
//   * Fig. 8 counts between the case's first and last snapshot (or the snapshots nearest the
//     iterations asked for), when it kept snapshots;
//   * for density-bidisperse points, the lighter species' concentration map (Fig. 13): from
//     snapshots on 0.97 < r/R < 1 when there are any, else the fields' c_S / c_L on the
//     campaign's shell (its shell_inner is recorded).
#include <string>
#include <vector>

#include "analysis/cm_islands.hpp"
#include "analysis/fates.hpp"
#include "analysis/replica_stats.hpp"

namespace tumble::analysis {

struct CampaignAnalysisOptions {
  CmIslandOptions islands;
  double fates_from = -1, fates_to = -1;  // iterations; < 0: first / last snapshot
  double light_inner = 0.97;
  double enrichment_inner = 0.9;  // shell of the snapshot-based enrichment
};

struct CaseAnalysis {
  std::string case_id, point_id, params;
  long long replica = 0;
  double enrichment_map = 0;   // from fields.h5 (NaN without islands)
  double enrichment_snap = 0;  // from the last snapshot (NaN without snapshots or islands)
  bool has_fates = false;
  FateCounts fates;
  FateResult fate_detail;  // per particle (the file keeps it for the point's first case)
  double fates_from = 0, fates_to = 0;  // iterations actually compared
  std::vector<double> light;            // lighter-species map (density-bidisperse points)
};

struct PointAnalysis {
  std::string point_id, params;
  double theta_z = 0, theta_x = 0, density_ratio = 1, size_ratio = 2;
  int grid_n = 0;
  std::vector<cm::Island> islands;  // shell r, the mask
  double island_area_fraction = 0;  // of the unit Lambert disc
  std::vector<double> coverage;     // per cell of the fields grid
  std::vector<CaseAnalysis> cases;  // by replica
  MeanCI enrichment_map, enrichment_snap;
  MeanCI persistent, captured, dispersed, other, same_island;
  int light_species = -1;    // -1: not density-bidisperse
  std::string light_source;  // "snapshots r/R > 0.97" or "fields c_S, r/R > 0.9", ...
  std::vector<double> light_mean, light_ci95;
};

// Reads every DIR/cases/*/fields.h5 (the finished cases), groups them by parameter point.
std::vector<PointAnalysis> analyze_campaign(const std::string& dir,
                                            const CampaignAnalysisOptions& opt);

// Writes the result atomically (layout in docs/report.md).
void write_campaign_analysis(const std::string& path, const std::string& dir,
                             const std::vector<PointAnalysis>& points);

}  // namespace tumble::analysis
