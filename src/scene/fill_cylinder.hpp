#pragma once
// Filling the horizontal cylinder (Rapaport 2007): N particles with sizes uniform in [d - spread,
// d]. Mixed start (the paper's): one particle per site of a cubic lattice spread over the
// cylinder, species drawn at random (large_fraction is the large particles' volume share).
// Presegregated start: each species packed bottom first into its own axial part. Placements never
// overlap; where the particles do not fit at full size (every mixed start of Table I, whose lattice
// side is below a big diameter) they are placed shrunk by a common factor and grown back while the
// bed settles (realization.cpp).
#include "base/particles.hpp"
#include "scene/scene.hpp"

namespace tumble {

struct CylinderBed {
  Particles particles;  // full radii, masses and inertias set; positions on the lattice
  double shrink = 1;    // common radius factor the placement needed (1: fits at full size)
};

// Deterministic in fill.seed; throws InputError if the bed cannot be placed even shrunk to 0.6.
CylinderBed make_cylinder_bed(const Scene& s);

}  // namespace tumble
