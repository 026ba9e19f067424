#pragma once
// KAM tubes (Yu 2022 Fig. 1(b)): the islands of one shell are cross-sections of tubes through the
// bed. Each elliptic point is continued from shell to shell by Newton's method, starting from its
// chart position on the previous shell (the chart coordinates are the Lambert coordinates of
// the direction, comparable across radii), and the islands are extracted on every shell.
#include <vector>

#include "cm/island.hpp"

namespace tumble::cm {

struct KamOptions {
  PeriodicSearch search;
  IslandOptions islands;
  // Rays per elliptic point on the tube shells (the section shell uses islands.rays): the tubes
  // only give the crossings of Fig. 5, and 16 rays on 8 shells would cost minutes.
  int tube_rays = 4;
};

// Islands on each shell of `radii`, continuing the elliptic points of `points` (found on shell
// r0). A tube ends where its point stops converging or stops being elliptic. Island::point
// indexes `points` (the r0 point the tube continues).
// Progress counts shells.
std::vector<Island> kam_tubes(const Protocol& pr, const std::vector<PeriodicPoint>& points,
                              double r0, const std::vector<double>& radii, const KamOptions& opt,
                              const Progress& progress = {});

}  // namespace tumble::cm
