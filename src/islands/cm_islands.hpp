#pragma once
// The CM islands a DEM analysis compares with: read from a `tumble cm orbits` file, or computed
// for the protocol (seconds) and cached in that format, so that every analysis of one protocol
// uses the same boundaries and the report can draw them.
#include <string>
#include <vector>

#include "cm/island.hpp"
#include "islands/island_mask.hpp"

namespace tumble::analysis {

struct CmIslandOptions {
  double r = 0.95;     // section shell, as Yu 2022 Figs. 1(a), 4, 8
  int max_period = 6;  // periodic points searched up to this period
  int grid = 40;       // Newton starts per chart axis
  bool kam = false;    // also the KAM-tube shells 0.55 ... 0.9 (Fig. 5's tube boundaries)
};

// All islands of the orbits file `path` (every shell).
std::vector<cm::Island> load_islands(const std::string& path);

// Islands of the (theta_z, theta_x) protocol [deg] with eps = 0.15: read from
// cache_dir/orbits_TZ_TX[_kam]_<method>.h5 (cm::island_method_tag) if present, else computed and
// written there (cache_dir may be "": no cache).
std::vector<cm::Island> protocol_islands(double theta_z, double theta_x, const CmIslandOptions& opt,
                                         const std::string& cache_dir);

// The mask of islands on one shell, a secondary chain's islands counting as the primary island
// they surround (the Fig. 8 fates' "same island"): what the classification and enrichment use,
// from a campaign and from the command line alike. shell_mask takes the islands of shell r.
IslandMask grouped_mask(const std::vector<cm::Island>& on_shell);
IslandMask shell_mask(const std::vector<cm::Island>& all, double r);

}  // namespace tumble::analysis
