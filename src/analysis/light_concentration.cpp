#include "analysis/light_concentration.hpp"

#include <stdexcept>

namespace tumble::analysis {

int lighter_species(double density_ratio) {
  if (density_ratio > 1) return 0;
  if (density_ratio < 1) return 1;
  return -1;
}

std::vector<double> light_concentration(const std::vector<SnapshotData>& snaps,
                                        const LambertGrid& grid, double inner) {
  if (snaps.empty()) throw std::invalid_argument("light concentration: no snapshots");
  const int light = lighter_species(snaps.front().density_ratio);
  if (light < 0)
    throw std::invalid_argument(
        "light concentration: the two species have equal densities (particles.density_ratio = 1)");
  ConcentrationMap m(grid.cells());
  for (const auto& s : snaps)
    m.add(bin_shell(s.as_particles(), Mat3::identity(), grid, s.R, inner));
  return light == 1 ? m.c_large() : m.c_small();
}

}  // namespace tumble::analysis
