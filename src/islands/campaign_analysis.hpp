#pragma once
// `tumble analyze campaign DIR`: the analyses of Yu 2022 that need the CM islands, for every case
// of a campaign directory (docs/campaign.md layout), folded per parameter point with 95%
// confidence intervals across replicas:
//   * island enrichment of each case from its time-averaged volume map of the mapped species
//     (scene/mixture.hpp: the large one of a size-bidisperse bed, the light one of a
//     density-bidisperse bed; fields.h5 concentration/volume_large or volume_small over the
//     campaign's window) and, when the case kept snapshots, from the particles of its last one;
//   * Fig. 8 counts between the case's first and last snapshot (or the snapshots nearest the
//     iterations asked for), when it kept snapshots;
//   * for density-bidisperse points, the lighter species' concentration map (Fig. 13): from
//     the snapshots inside the campaign's collection window on the one-diameter shell
//     1 - d/R < r/R < 1 (0.97 in the paper) when there are any, else the fields' c_S / c_L on
//     the campaign's shell (its shell_inner is recorded);
//   * cross-enrichment: each case's map against the islands of every point of the campaign that
//     has islands. A point without islands, e.g. (68°, 68°), is measured against the islands of
//     (57°, 57°): 1 within its CI is the absence of that pattern, on the same scale on which
//     (57°, 57°) shows it;
//   * Fig. 5: c_L in the plane through the tumbler centre and two islands, from the snapshots
//     of the last half of each case (a point without islands uses the plane of the first point
//     that has them, so the sections compare side by side), with the KAM-tube boundaries;
//   * Figs. 6-7, when lags are asked for: Δψ inside and outside the islands from the snapshots,
//     over every start in the Fig. 8 window (dpsi_snapshots.hpp); and always from the Δψ maps
//     the run collected (fields.h5 displacement*), with the same weighting (dpsi_contrast).
#include <map>
#include <string>
#include <vector>

#include "islands/cm_islands.hpp"
#include "islands/cross_section.hpp"
#include "islands/dpsi_snapshots.hpp"
#include "islands/fates.hpp"
#include "islands/replica_stats.hpp"
#include "scene/mixture.hpp"

namespace tumble::analysis {

// The Fig. 8 classes in the order of the Fate codes (fates.hpp) and of analysis.h5's columns.
inline constexpr const char* kFateNames[5] = {"persistent", "captured", "dispersed", "other",
                                              "switched"};
static_assert(static_cast<int>(Fate::Captured) == 1 && static_cast<int>(Fate::Switched) == 4,
              "kFateNames follows the Fate codes");

struct CampaignAnalysisOptions {
  CmIslandOptions islands;
  double fates_from = -1, fates_to = -1;  // iterations; < 0: first / last snapshot
  double light_inner = -1;        // Fig. 13 shell from snapshots; -1: one light diameter (1 - d/R)
  double enrichment_inner = 0.9;  // shell of the snapshot-based enrichment
  int section_grid = 0;           // Fig. 5: bins per in-plane axis (0: one per large diameter)
  double section_half_width = 1;  // Fig. 5: slab half-width, in large diameters
  std::string islands_cache;      // where computed islands are cached ("": DIR/analysis)
  // Figs. 6-7 from the snapshots (dpsi_snapshots.hpp): Δψ over each lag [iterations], summed
  // over every start in the Fig. 8 window whose end is in it, inside and outside the islands.
  std::vector<double> dpsi_lags;
  double dpsi_inner = 0.8;  // particles with dpsi_inner <= r/R <= 1 at the start
};

// One lag's Δψ from a case's snapshots [rad], by species (index 1 the large one).
struct CaseDpsi {
  double lag = 0;
  int starts = 0;              // intervals averaged (0: the window holds none)
  double first = 0, last = 0;  // their first and last start iteration
  DpsiContrast species[2];
};

struct CaseAnalysis {
  std::string case_id, point_id, params;
  long long replica = 0;
  double enrichment_map = 0;   // from fields.h5 (NaN without islands)
  double enrichment_snap = 0;  // from the last snapshot (NaN without snapshots or islands)
  // From the mapped particles of every snapshot in the collection window, pooled (stroboscopic:
  // the islands are where the CM puts them); NaN without snapshots or islands.
  double enrichment_window = 0;
  double repose_deg = 0;  // the tilt β the case ran with (measured or given: its scene text)
  // Radial segregation by species: the share of the mapped species (and of the other one) whose
  // centres lie in the enrichment shell, averaged over the window's snapshots; NaN without
  // snapshots.
  double shell_share_mapped = 0, shell_share_other = 0;
  bool has_fates = false;
  FateCounts fates;
  FateExpectation fates_by_chance;  // the same counts for randomly relabelled end positions
  FateResult fate_detail;           // per particle (the file keeps it for the point's first case)
  double fates_from = 0, fates_to = 0;          // iterations actually compared
  std::vector<double> light;                    // lighter-species map (density-bidisperse points)
  int light_snapshots = 0;                      // configurations averaged into it
  double light_from = 0, light_to = 0;          // their iterations
  std::map<std::string, double> enrichment_vs;  // map enrichment against each island point's
  std::vector<double> section;                  // Fig. 5 c_L per bin (NaN: nothing binned)
  int section_snapshots = 0;                    // configurations averaged into it
  std::vector<CaseDpsi> dpsi;                   // per CampaignAnalysisOptions::dpsi_lags
  std::vector<CaseDpsi> dpsi_fields;            // per lag the run collected (fields.h5)
};

// One lag's Δψ over the cases [deg], by species (index 1 the large one).
struct PointDpsi {
  double lag = 0;
  int starts_min = 0, starts_max = 0;  // per case
  MeanCI inside[2], outside[2], contrast[2];
};

struct PointAnalysis {
  std::string point_id, params;
  double theta_z = 0, theta_x = 0, density_ratio = 1, size_ratio = 2;
  int grid_n = 0;
  std::vector<cm::Island> islands;  // shell r, the mask
  double island_area_fraction = 0;  // of the unit Lambert disc
  std::vector<double> coverage;     // per cell of the fields grid
  std::vector<CaseAnalysis> cases;  // by replica
  MeanCI enrichment_map, enrichment_snap, enrichment_window;
  MeanCI repose;  // β over the cases [deg]
  // The shares in the shell over the cases, and their ratio mapped / other per case (> 1: the
  // mapped species gathers at the wall).
  MeanCI shell_share_mapped, shell_share_other, shell_ratio;
  double repose_min = 0, repose_max = 0;  // its range
  // Fig. 8 over replicas, observed and by chance (fates.hpp), in the order of kFateNames.
  MeanCI fates[5], fates_by_chance[5];
  int island_period = 0;     // least common multiple of the islands' periods (0: no islands)
  Mixture mixture;           // the species' roles; enrichment counts mixture.mapped
  int light_species = -1;    // -1: equal densities
  std::string light_source;  // "snapshots r/R > 0.971, iterations 25-35" or "fields c_S, ..."
  std::vector<double> light_mean, light_ci95;
  std::map<std::string, MeanCI> enrichment_vs;  // by the id of the point whose islands are used
  // Fig. 5 (empty when no point of the campaign has two islands).
  std::string section_plane_of;  // the point whose islands define the plane
  int section_grid = 0;          // bins per in-plane axis
  std::pair<int, int> section_pair{-1, -1};
  SectionPlane section_plane;
  double section_half_width = 0;  // [m]
  std::vector<double> section_mean, section_ci95;
  std::vector<TubeCrossing> section_tubes;
  std::vector<PointDpsi> dpsi;  // per CampaignAnalysisOptions::dpsi_lags (points with islands)
  // The same contrast from the Δψ maps the run collected (fields.h5 displacement*), per lag
  // (points with islands): the numbers of the report's table 3c.
  std::vector<PointDpsi> dpsi_fields;
};

// Reads every DIR/cases/*/fields.h5 (the finished cases), groups them by parameter point.
std::vector<PointAnalysis> analyze_campaign(const std::string& dir,
                                            const CampaignAnalysisOptions& opt);

// Writes the result atomically (layout in docs/report.md).
void write_campaign_analysis(const std::string& path, const std::string& dir,
                             const std::vector<PointAnalysis>& points);

}  // namespace tumble::analysis
