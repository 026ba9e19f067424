#include "cm/kam.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::cm {

std::vector<Island> kam_tubes(const Protocol& pr, const std::vector<PeriodicPoint>& points,
                              double r0, const std::vector<double>& radii, const KamOptions& opt,
                              const Progress& progress) {
  // Walk outwards from r0 in both directions so each shell starts from its neighbour.
  std::vector<double> down, up;
  for (double r : radii) (r <= r0 ? down : up).push_back(r);
  std::sort(down.begin(), down.end(), std::greater<>());
  std::sort(up.begin(), up.end());

  std::vector<Island> out;
  const double shells = std::max<double>(radii.size(), 1);
  double shells_done = 0;
  for (const auto* walk : {&down, &up}) {
    std::vector<PeriodicPoint> tracked;  // elliptic points continued to the current shell
    std::vector<int> origin;             // their index in `points`
    for (std::size_t i = 0; i < points.size(); ++i)
      if (points[i].type == Stability::Elliptic) {
        tracked.push_back(points[i]);
        origin.push_back(static_cast<int>(i));
      }
    for (double r : *walk) {
      const SectionMap map(pr, ShellChart(r, pr.eps));
      std::vector<PeriodicPoint> next;
      std::vector<int> next_origin;
      for (std::size_t k = 0; k < tracked.size(); ++k) {
        PeriodicPoint pt = tracked[k];
        if (std::abs(r - r0) > 1e-12) {
          Vec2 v;
          if (!newton_periodic(map, pt.v, pt.period, opt.search, v)) continue;
          pt.v = v;
          classify(map, pt, opt.search);
          if (pt.type != Stability::Elliptic) continue;
        }
        next.push_back(pt);
        next_origin.push_back(origin[k]);
      }
      tracked = next;
      origin = next_origin;
      const Progress shell_progress = sub_progress(progress, shells_done / shells, 1 / shells);
      IslandOptions tube = opt.islands;
      tube.rays = std::min(tube.rays, opt.tube_rays);
      tube.max_chain_q = 0;  // tubes are the primary islands continued; chains are not tracked
      for (auto isl : find_islands(map, tracked, tube, shell_progress)) {
        isl.point = origin[isl.point];
        out.push_back(std::move(isl));
      }
      ++shells_done;
    }
  }
  report(progress, 1.0);
  return out;
}

}  // namespace tumble::cm
