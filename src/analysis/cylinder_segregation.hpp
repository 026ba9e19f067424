#pragma once
// Segregation measures of the rotating cylinder (Rapaport 2007, Sec. II C and III): the axial
// and radial segregation indices S_a (Eq. 6) and S_r (Eq. 7), the axial and radial space-time
// profiles, the free-surface fit, the axial band count and the surface profiles (Fig. 15).
// The cylinder's axis is z (from -L/2 to L/2), gravity -y; the cross-section is the (x, y) plane.
#include <vector>

#include "base/particles.hpp"

namespace tumble::analysis {

struct CylinderFrame {
  double radius = 0;  // R = D/2
  double length = 0;  // L
  double slice = 0;   // bin width along the axis, across the section and in depth (paper: 2.5)
  double b3 = 1;      // (d_large / d_small)^3 of the nominal sizes: S_a's mass weight
  int slices() const;
};

// Eq. 6 with the normalisation read as a ratio of slice averages: S_a = <|b^3 n_b(q) - n_s(q)|>_q
// / <b^3 n_b(q) + n_s(q)>_q, in [0, 1]: 0 when every slice holds the two species in the bed's
// (equal-volume) proportion, 1 when every slice holds one species only.
double axial_segregation(const Particles& p, const CylinderFrame& c);

// Eq. 7: S_r = [(<r_b^2> - <r_b>^2) - (<r_s^2> - <r_s>^2)] / (<r^2> - <r>^2), r the position in
// the cross-section, so each bracket is the species' mean-square distance from its own centre of
// mass there. S_r > 0: the big particles spread further out, a core of small particles.
double radial_segregation_index(const Particles& p);

// Volume fraction of big particles in each axial slice (one row of the axial space-time plot);
// slices without particles get -1.
std::vector<double> axial_profile(const Particles& p, const CylinderFrame& c);

// Free surface in the cross-section: the highest particle centre in each (axial slice, column)
// cell, averaged over the slices per column, fitted by y = a + b x over the inner 2/3 of the
// columns that hold particles.
struct SurfaceFit {
  double intercept = 0, slope = 0;
  double x_lo = 0, x_hi = 0;  // the fitted (inner 2/3) range of x
  bool ok = false;
};
SurfaceFit fit_surface(const Particles& p, const CylinderFrame& c);

// Volume fraction of big particles in slabs parallel to the fitted surface (one row of the radial
// space-time plot), bin k covering depths [k w, (k+1) w) below the surface; only particles whose
// position along the surface lies within the fitted range count (the paper's slab "of similar
// width", avoiding the bias of the section's shape). Empty bins get -1.
std::vector<double> radial_profile(const Particles& p, const CylinderFrame& c, const SurfaceFit& s,
                                   int bins);

// Number of axial bands (both species counted, as "12 alternating bands") in an axial profile:
// the profile is smoothed over three slices, each slice is big-rich or small-rich when it departs
// from the bed's mean fraction by more than `threshold`, and the count is the number of runs of
// equal sign (slices in between inherit the last sign). 0 when no slice departs.
int band_count(const std::vector<double>& profile, double mean_fraction, double threshold = 0.1);

// Axially averaged surface height per column for each species (Fig. 15): the highest centre of a
// big (small) particle in each (slice, column) cell, averaged over slices. Columns of width
// `slice` across [-R, R]; empty columns get NaN.
struct SurfaceProfiles {
  std::vector<double> x, large, small;
};
SurfaceProfiles surface_profiles(const Particles& p, const CylinderFrame& c);

// Bed-wide big-particle volume fraction.
double large_volume_fraction(const Particles& p);

// The time series of a cylinder run; 2D profiles are stored row by row.
struct CylinderSeries {
  std::vector<double> time, revolutions, sa, sr, bands, surface_slope, kinetic_energy;
  std::vector<double> axial, radial, surface_x, surface_large, surface_small;
  int axial_cols = 0, radial_cols = 0, surface_cols = 0;
  bool empty() const { return time.empty(); }
};
// Measures one configuration and appends it.
void sample_cylinder(const Particles& p, const CylinderFrame& c, double time, double revolutions,
                     double kinetic_energy, CylinderSeries& out);

}  // namespace tumble::analysis
