#pragma once
// Large- and small-particle concentration on the equal-area Lambert grid (lambert.hpp) of the
// outer shell inner R < r < R of the tumbler, lower hemisphere viewed from below (Yu 2022 Fig. 4):
// c_L of a cell is the large-particle share of the solid volume whose centres lie in it. A sample
// bins one configuration; ConcentrationMap time-averages samples as ratios of summed volumes, so a
// cell that is empty at some instants is weighted by what it held, not dropped.
#include <vector>

#include "base/particles.hpp"
#include "base/vec3.hpp"
#include "projection/lambert.hpp"

namespace tumble::analysis {

struct ShellBins {
  std::vector<double> large, small;  // solid volume per cell [m^3]
};

// Bins particles with centres in inner R < |x| < R whose direction, mapped by `to_frame` (the
// identity for the lab frame, Q^T for the tumbler frame), lies on the lower hemisphere (y <= 0).
// Species 1 is "large" (the heavier species of a density-bidisperse bed).
ShellBins bin_shell(const Particles& p, const Mat3& to_frame, const LambertGrid& grid, double R,
                    double inner);

// The square root of Danckwerts' intensity of segregation (his is a ratio of variances) of one
// sample, a ratio of standard deviations: the volume-weighted standard deviation of
// c_L over the cells, divided by its value for complete segregation, sqrt(c(1 - c)) with c the
// shell's mean. 0 = evenly mixed (up to sampling noise), 1 = fully segregated; NaN if the shell
// holds one species only or nothing.
double intensity_of_segregation(const ShellBins& b);

// Solid volume a cell of the lower half-shell can hold: (2 pi / 3)(R^3 - (inner R)^3) / N^2.
double shell_cell_volume(const LambertGrid& grid, double R, double inner);

class ConcentrationMap {
 public:
  explicit ConcentrationMap(int cells = 0) : volume_large(cells, 0.0), volume_small(cells, 0.0) {}
  void add(const ShellBins& b);
  std::vector<double> c_large() const;  // sum V_L / sum (V_L + V_S); NaN where nothing was seen
  std::vector<double> c_small() const;  // 1 - c_L where defined
  // Mean solid fraction of each cell over the samples (0 where nothing was seen).
  std::vector<double> solid_fraction(double cell_volume) const;

  // Running sums (public: they are the persisted state of a case).
  std::vector<double> volume_large, volume_small;
  long long samples = 0;
};

}  // namespace tumble::analysis
