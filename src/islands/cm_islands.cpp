#include "islands/cm_islands.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "cm/cm_io.hpp"
#include "cm/kam.hpp"
#include "cm/section_map.hpp"

namespace tumble::analysis {

std::vector<cm::Island> load_islands(const std::string& path) { return cm::read_islands(path); }

std::vector<cm::Island> protocol_islands(double theta_z, double theta_x, const CmIslandOptions& opt,
                                         const std::string& cache_dir) {
  namespace fs = std::filesystem;
  const cm::IslandOptions iopt;
  // The method is in the name: islands cached by an older method are not reused.
  char name[128];
  std::snprintf(name, sizeof name, "orbits_%g_%g%s_%s.h5", theta_z, theta_x, opt.kam ? "_kam" : "",
                cm::island_method_tag(iopt).c_str());
  const std::string path = cache_dir.empty() ? "" : (fs::path(cache_dir) / name).string();
  if (!path.empty() && fs::exists(path)) return cm::read_islands(path);

  const cm::Protocol pr = cm::Protocol::degrees(theta_z, theta_x);
  const cm::SectionMap map(pr, cm::ShellChart(opt.r, pr.layer_eps()));
  cm::PeriodicSearch search;
  search.max_period = opt.max_period;
  search.grid = opt.grid;
  const auto points = cm::find_periodic_points(map, search);
  auto islands = cm::find_islands(map, points, iopt);
  if (opt.kam) {
    std::vector<double> radii;
    for (int k = 11; k <= 18; ++k) radii.push_back(0.05 * k);  // 0.55 ... 0.9 (Fig. 1(b))
    const auto tubes = cm::kam_tubes(pr, points, opt.r, radii, {search, iopt});
    islands.insert(islands.end(), tubes.begin(), tubes.end());
  }
  if (!path.empty()) {
    fs::create_directories(cache_dir);
    cm::write_orbits(path, pr, opt.r, points, islands);
  }
  return islands;
}

IslandMask grouped_mask(const std::vector<cm::Island>& on_shell) {
  std::vector<cm::Polygon> polys;
  for (const auto& is : on_shell) polys.push_back(is.boundary);
  return IslandMask(std::move(polys), cm::primary_island_of(on_shell));
}

IslandMask shell_mask(const std::vector<cm::Island>& all, double r) {
  return grouped_mask(cm::islands_on_shell(all, r));
}

}  // namespace tumble::analysis
