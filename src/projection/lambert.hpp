#pragma once
// Lambert azimuthal equal-area projection of the lower hemisphere, viewed from below, and the
// N x N equal-area grid on it (Shirley-Chiu concentric square-to-disc map). One module for the
// DEM analyses (concentration c_L, displacement on the shell 0.9 < r < 1) and the continuum
// model (Poincare sections, island polygons), so that every map in Tumble lands on the same
// cells (docs/architecture.md, "Continuum model notes"; Yu 2022 Sec. II B, refs. [38,39]).
//
// Conventions (callers pass unit directions in whatever frame they analyse, e.g. the tumbler
// frame):
//   * projection centre: the south pole (0, -1, 0); for a unit vector u with u_y <= 0,
//       (X, Z) = (u_x, u_z) / sqrt(1 - u_y),
//     so the rim u_y = 0 maps to the unit circle and the pole to the origin. This is the
//     standard Lambert projection scaled by 1/sqrt(2): disc area = hemisphere area / 2.
//   * viewed from below: plotting X to the right and Z up is a true (unmirrored) picture of the
//     hemisphere seen by a camera under the tumbler looking up (+y).
//   * grid: the disc is the image of the square [-1,1]^2 (coordinates a along X, b along Z)
//     under the concentric map. Cell (i, j) covers a in [-1 + 2i/N, -1 + 2(i+1)/N] and
//     b in [-1 + 2j/N, -1 + 2(j+1)/N]; the flat index is i * N + j (row-major [i][j]).
//     Every cell has disc area pi / N^2, i.e. solid angle 2 pi / N^2 on the hemisphere.
#include <array>

namespace tumble::analysis {

struct DiscPoint {
  double X = 0, Z = 0;
};

// Unit direction (u_y <= 0 expected; u_y > 0 is mapped beyond the unit circle, up to sqrt(2))
// to disc coordinates.
DiscPoint lambert_from_below(double ux, double uy, double uz);
// Inverse for |(X, Z)| <= sqrt(2): the unit direction whose projection is (X, Z).
std::array<double, 3> lambert_inverse(DiscPoint p);

// Shirley-Chiu concentric map: square [-1,1]^2 -> unit disc, constant Jacobian pi/4.
DiscPoint square_to_disc(double a, double b);
// Its inverse: unit disc -> square [-1,1]^2, returned as {a, b}.
std::array<double, 2> disc_to_square(DiscPoint p);

class LambertGrid {
 public:
  explicit LambertGrid(int n);
  int n() const { return n_; }
  int cells() const { return n_ * n_; }
  // Flat cell index of a disc point, or -1 outside the unit disc.
  int cell_of(DiscPoint p) const;
  // Flat cell index of a unit direction, or -1 on the upper hemisphere (u_y > 0).
  int cell_of_direction(double ux, double uy, double uz) const;
  // Cell (i, j) -> flat index, and back.
  int flat(int i, int j) const { return i * n_ + j; }
  std::array<int, 2> ij(int flat_index) const { return {flat_index / n_, flat_index % n_}; }
  // Image of the centre of cell (i, j) of the square.
  DiscPoint cell_center(int i, int j) const;
  double cell_area_disc() const;    // pi / N^2
  double cell_solid_angle() const;  // 2 pi / N^2 steradians

 private:
  int n_;
};

}  // namespace tumble::analysis
