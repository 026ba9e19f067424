#pragma once
// Which species of a bed is which, named by what tells them apart. The engine knows species 0
// and 1 (particles.d_small/d_large, density and density * density_ratio, large_fraction = the
// volume fraction of species 1); the analyses and reports need roles: in a size-bidisperse bed
// (Yu 2022 Secs. III-IV C) species 1 is "large" and the maps show it; in a density-bidisperse bed
// of equal sizes (Sec. IV D) the species are "light" and "heavy" and the maps show the light one
// (Fig. 13), whichever index it has. The minority is the species of the smaller volume fraction.
#include <string>

#include "scene/scene.hpp"

namespace tumble {

enum class MixtureKind { size, density, mono };

struct Mixture {
  MixtureKind kind = MixtureKind::mono;
  std::string name[2];  // "small"/"large", "light"/"heavy" (in index order), "species 0"/"species 1"
  int mapped = 1;       // the species whose concentration the pattern maps show
  int minority = 1;     // the species of the smaller volume fraction (1 on a tie)
  double fraction[2] = {0.85, 0.15};  // volume fractions
  double diameter[2] = {0, 0};
  const char* kind_name() const;
  // One line for logs and reports: "light (species 0, 2 vol %, minority, mapped) / heavy ...".
  std::string describe() const;
};

// Sizes differing by more than 1e-9 (relative) make a size-bidisperse bed, whatever the
// densities; equal sizes and density_ratio != 1 a density-bidisperse one.
Mixture mixture_of(const Scene& s);

}  // namespace tumble
