#pragma once
// Radial segregation time series (Yu 2022 Sec. II): the large-particle volume fraction among
// particles whose centres lie in the outer shell 0.9 < r/R < 1 of the tumbler, against the bed
// average. Large particles enriched at the wall give shell > bed.
#include <vector>

#include "analysis/cylinder_segregation.hpp"
#include "base/particles.hpp"

namespace tumble::analysis {

struct SegregationSample {
  double shell_large_fraction = 0;  // large volume / all volume, centres in 0.9R < r < R
  double bed_large_fraction = 0;    // same over the whole bed
  double shell_count = 0;           // particles in the shell
};

SegregationSample radial_segregation(const Particles& p, double tumbler_radius, double inner = 0.9);

// Share of the particles of species `which` whose centres lie in the shell inner R < r <= R
// (tumbler-centred positions); NaN if there is none of that species. A species gathered at the
// wall has a larger share than one spread evenly (Yu 2022 Fig. 13: the light particles of a
// density-bidisperse bed).
double shell_share(const std::vector<Vec3>& x, const std::vector<std::int32_t>& species, int which,
                   double R, double inner);

struct Series {
  std::vector<double> time, iteration, shell_large_fraction, bed_large_fraction, kinetic_energy;
  // Sphere scenes that turn (single-axis and biaxial): dynamic repose angle (degrees) and surface
  // speed (flow_profile.hpp) about the axis of the protocol's segment, one per sample; empty
  // otherwise (a cylinder, a bed at rest).
  std::vector<double> repose_angle, surface_speed;
  // Biaxial scenes: the protocol segment of each sample (counted from the run's start: period x
  // segments per period + segment) and the wall's turn since that segment began (degrees), so an
  // analysis can follow each start of the flow about a new axis
  // (jobs/accuracy/segment_start_table.py).
  std::vector<double> segment, segment_turn;
  // ... and the surface velocity profile: the bin centres h (same for every sample) and, per
  // sample, the downhill speed per bin (samples x bins, row-major; NaN where no surface particle).
  std::vector<double> profile_h, surface_profile;
  // fidelity.bulk = "rigid": the share of particles frozen at each sample (empty otherwise).
  std::vector<double> frozen_fraction;
  CylinderSeries cylinder;  // cylinder scenes: Rapaport's measures (sphere scenes: empty)
  void append(double t, double iter, const SegregationSample& s, double ke) {
    time.push_back(t);
    iteration.push_back(iter);
    shell_large_fraction.push_back(s.shell_large_fraction);
    bed_large_fraction.push_back(s.bed_large_fraction);
    kinetic_energy.push_back(ke);
  }
};

}  // namespace tumble::analysis
