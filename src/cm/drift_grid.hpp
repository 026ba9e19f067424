#pragma once
// The MCM's axial drift field (Yu 2022 App. A): mean axial velocity v_ax(i, j) and its standard
// deviation sigma_ax(i, j) of large particles in the flowing layer, on an n x n grid (n = 30,
// cells about one large-particle diameter) over the layer's footprint.
//
// Grid convention (also the HDF5 format, docs/cm.md "Drift-grid file"): in the frame of the
// rotation that drives the layer (x streamwise, positive downstream = the surface flow direction;
// y up; z axial, along the rotation axis), cell (i, j) covers
//   x in [-1 + 2i/n, -1 + 2(i+1)/n],  z in [-1 + 2j/n, -1 + 2(j+1)/n]   (lengths in R),
// stored row-major [i][j]. v_ax > 0 points to +z. Velocities in units of omega R. The same grid
// serves both phases of a protocol through the phase frame of protocol.hpp.
#include <string>
#include <vector>

namespace tumble::cm {

// The raw statistics of a measured grid: samples, sum and sum of squares of v_ax per cell
// (n*n, [i][j]). What a run accumulates (run/drift_measure.hpp), what its checkpoints keep, and
// what lets the grids of several runs be merged exactly (merge_drift_grids).
struct DriftStatistics {
  std::vector<double> count, sum, sum2;
  static DriftStatistics zeros(int n) {
    const std::size_t cells = static_cast<std::size_t>(n) * n;
    return {std::vector<double>(cells, 0.0), std::vector<double>(cells, 0.0),
            std::vector<double>(cells, 0.0)};
  }
  bool empty() const { return count.empty(); }
  double samples() const {
    double total = 0;
    for (const double c : count) total += c;
    return total;
  }
};

struct DriftGrid {
  int n = 30;
  std::vector<double> v_ax, sigma_ax;  // n*n, [i][j]
  std::string source;                  // "synthetic" or where it was measured
  DriftStatistics statistics;          // a measured grid's; empty for a synthetic one
  bool has_statistics() const { return !statistics.empty(); }

  // Cell of a point of the layer's footprint, or -1 outside [-1,1]^2.
  int cell(double x, double z) const;
  double v(double x, double z) const;
  double sigma(double x, double z) const;
  // Means over cells whose centre lies in the footprint x^2 + z^2 < 1: <|v_ax|> and <sigma_ax>
  // of the Peclet number (Yu 2022 Sec. III B).
  double mean_abs_v() const;
  double mean_sigma() const;
};

// A documented stand-in for a DEM-measured grid (the paper's field is not tabulated). Shaped
// as App. A describes: zero at the equator, towards the poles on either side, reversing near the
// poles; uniform along the stream; constant sigma.
//   v_ax(x, z) = v_max sin(pi z / z_rev)  for x^2 + z^2 < 1, else 0;
//   v_max = drift_per_pass / (pi eps): `drift_per_pass` is the largest axial displacement in one
//           layer transit (which lasts pi eps): "about one-half large-particle diameter per
//           pass", d_L/2 = 2 mm = 0.0286 R for R = 70 mm;
//   sigma = 22.1 mm/s / (omega R) = 1.005 for omega = 3 rpm, R = 70 mm (ref. [44]).
struct SyntheticDrift {
  int n = 30;
  double drift_per_pass = 2.0 / 70.0;
  double eps = 0.15;
  double z_reversal = 0.85;  // drift changes sign here ("near the poles")
  double sigma = 22.1 / (3.0 * 2 * 3.14159265358979323846 / 60.0 * 70.0);
};
DriftGrid synthetic_drift(const SyntheticDrift& s);

// The grid of raw per-cell statistics: v_ax = mean, sigma_ax = sample standard deviation where a
// cell holds >= 2 samples; elsewhere v_ax = 0 and sigma_ax = the mean sigma of the sampled cells
// (the MCM needs a sigma everywhere in the footprint). The statistics are kept in the grid.
DriftGrid drift_grid_from_statistics(int n, DriftStatistics statistics, const std::string& source);

// Several measured grids of one n as one: the statistics summed cell by cell (the grid of all
// their samples together). Throws InputError naming the grid (by its source) that has no
// statistics or another n.
DriftGrid merge_drift_grids(const std::vector<DriftGrid>& grids, const std::string& source);

// The largest grid read or made (`tumble cm drift --n`): 1000 x 1000 cells, 16 MB.
inline constexpr int kMaxDriftGridN = 1000;
// Bytes of an n x n grid (v_ax and sigma_ax).
inline double drift_grid_memory_bytes(int n) { return 16.0 * n * n; }

// HDF5: datasets /v_ax and /sigma_ax, shape [n][n], and for a measured grid /count, /sum, /sum2
// of the same shape; attributes on "/": n (int64), source, convention, units (strings). A grid that
// is not square, larger than kMaxDriftGridN, or holds a value that is not finite (or a negative
// sigma) is refused (InputError, the cell named).
DriftGrid read_drift_grid(const std::string& path);
void write_drift_grid(const std::string& path, const DriftGrid& grid);

}  // namespace tumble::cm
