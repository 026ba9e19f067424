#pragma once
// The flowing layer of a tumbler rotating about one horizontal axis: the dynamic angle of repose
// and the surface velocity profile (docs/accuracy.md's flow observables).
//
// Frame: e_a the rotation axis, e_up = +y (gravity is −y), e_h = e_up × e_a the horizontal
// across the axis. In the central slab |x·e_a| < slab, the free surface height in each bin of h
// (width `bin`) is the highest particle top; a line v = a + b h fitted to the bins with
// |h| < fit_half_width gives the repose angle atan|b|. Particles whose top lies within `depth`
// below that line form the surface layer; their mean velocity along the downhill tangent, per bin,
// is the surface velocity profile, and its mean over |h| < 0.3 R the surface speed.
#include <vector>

#include "base/particles.hpp"

namespace tumble::analysis {

struct FlowFrame {
  Vec3 axis{1, 0, 0};   // rotation axis (unit)
  double radius = 1;    // tumbler radius R
  double slab = 0.5;    // half thickness of the central slab along the axis (× R)
  double bin = 0.1;     // bin width along h (length)
  double fit = 0.6;     // bins with |h| < fit R enter the line fit
  double depth = 0.01;  // surface layer depth below the fitted line (length)
};

struct FlowProfile {
  double repose_deg = 0;      // dynamic angle of repose (NaN: no surface found)
  double surface_speed = 0;   // mean downhill speed of the surface layer over |h| < 0.3 R
  std::vector<double> h;      // bin centres
  std::vector<double> speed;  // mean downhill speed per bin (NaN where no surface particle)
};

FlowProfile flow_profile(const Particles& p, std::size_t count, const FlowFrame& frame);

}  // namespace tumble::analysis
