#pragma once
// Yu 2022 Fig. 13: in a density-bidisperse bed (equal sizes, R_rho = rho_1 / rho_0 != 1) the
// pattern is read from the lighter species' concentration in a one-diameter layer at the wall,
// 0.97 < r/R < 1. Species 1 ("large" in the campaign's vocabulary) is the heavy one when R_rho > 1.
#include <vector>

#include "analysis/concentration.hpp"
#include "analysis/snapshot_data.hpp"

namespace tumble::analysis {

// The lighter species (0 or 1), or -1 when the densities are equal.
int lighter_species(double density_ratio);

// Time average over the configurations of the lighter species' share of the solid volume per
// Lambert cell of the shell inner < r/R < 1 (lab frame). Throws if the densities are equal.
std::vector<double> light_concentration(const std::vector<SnapshotData>& snaps,
                                        const LambertGrid& grid, double inner);

}  // namespace tumble::analysis
