#include "cm/drift_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "base/error.hpp"
#include "cm/flow_field.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::cm {

namespace {
constexpr const char* kConvention =
    "cell (i,j), row-major [i][j]: i along the streamwise x (positive downstream), j along the "
    "axial z of the driving rotation; cell covers x in [-1+2i/n, -1+2(i+1)/n], z in "
    "[-1+2j/n, -1+2(j+1)/n] (lengths in R); v_ax > 0 towards +z";

double cell_centre(int i, int n) { return -1 + (2 * i + 1.0) / n; }
}  // namespace

int DriftGrid::cell(double x, double z) const {
  const int i = static_cast<int>(std::floor((x + 1) * 0.5 * n));
  const int j = static_cast<int>(std::floor((z + 1) * 0.5 * n));
  if (i < 0 || j < 0 || i >= n || j >= n) return -1;
  return i * n + j;
}

double DriftGrid::v(double x, double z) const {
  const int c = cell(x, z);
  return c < 0 ? 0.0 : v_ax[c];
}

double DriftGrid::sigma(double x, double z) const {
  const int c = cell(x, z);
  return c < 0 ? 0.0 : sigma_ax[c];
}

namespace {
// Mean of f(cell) over the cells whose centre lies in the layer's footprint x² + z² < 1.
template <class F>
double footprint_mean(int n, F f) {
  double s = 0;
  int k = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = cell_centre(i, n), z = cell_centre(j, n);
      if (x * x + z * z >= 1) continue;
      s += f(i * n + j);
      ++k;
    }
  return k ? s / k : 0.0;
}
}  // namespace

double DriftGrid::mean_abs_v() const {
  return footprint_mean(n, [this](int c) { return std::abs(v_ax[c]); });
}

double DriftGrid::mean_sigma() const {
  return footprint_mean(n, [this](int c) { return sigma_ax[c]; });
}

DriftGrid synthetic_drift(const SyntheticDrift& sd) {
  DriftGrid g;
  g.n = sd.n;
  g.source = "synthetic";
  g.v_ax.assign(sd.n * sd.n, 0.0);
  g.sigma_ax.assign(sd.n * sd.n, 0.0);
  const double v_max = sd.drift_per_pass / (kPi * sd.eps);
  for (int i = 0; i < sd.n; ++i)
    for (int j = 0; j < sd.n; ++j) {
      const double x = cell_centre(i, sd.n), z = cell_centre(j, sd.n);
      if (x * x + z * z >= 1) continue;
      g.v_ax[i * sd.n + j] = v_max * std::sin(kPi * z / sd.z_reversal);
      g.sigma_ax[i * sd.n + j] = sd.sigma;
    }
  return g;
}

DriftGrid drift_grid_from_statistics(int n, DriftStatistics statistics, const std::string& source) {
  const auto& count = statistics.count;
  const auto& sum = statistics.sum;
  const auto& sum2 = statistics.sum2;
  DriftGrid g;
  g.n = n;
  g.source = source;
  g.v_ax.assign(count.size(), 0.0);
  g.sigma_ax.assign(count.size(), 0.0);
  double sigma_sum = 0, sigma_cells = 0;
  for (std::size_t c = 0; c < count.size(); ++c) {
    if (count[c] < 2) continue;
    const double mean = sum[c] / count[c];
    const double var = std::max(0.0, (sum2[c] - count[c] * mean * mean) / (count[c] - 1));
    g.v_ax[c] = mean;
    g.sigma_ax[c] = std::sqrt(var);
    sigma_sum += g.sigma_ax[c];
    sigma_cells += 1;
  }
  const double fill = sigma_cells > 0 ? sigma_sum / sigma_cells : 0.0;
  for (std::size_t c = 0; c < count.size(); ++c)
    if (count[c] < 2) g.sigma_ax[c] = fill;
  g.statistics = std::move(statistics);
  return g;
}

DriftGrid merge_drift_grids(const std::vector<DriftGrid>& grids, const std::string& source) {
  if (grids.empty()) throw InputError("merging drift grids: no grid given");
  const int n = grids.front().n;
  const std::size_t cells = static_cast<std::size_t>(n) * n;
  DriftStatistics all = DriftStatistics::zeros(n);
  for (const auto& g : grids) {
    if (!g.has_statistics())
      throw InputError("drift grid '" + g.source +
                       "' holds no per-cell statistics (/count, /sum, /sum2): only measured "
                       "grids (output.drift_grid = on) can be merged");
    if (g.n != n)
      throw InputError("drift grid '" + g.source + "' has n = " + std::to_string(g.n) +
                       ", the first grid n = " + std::to_string(n) + ": merge grids of one n");
    for (std::size_t c = 0; c < cells; ++c) {
      all.count[c] += g.statistics.count[c];
      all.sum[c] += g.statistics.sum[c];
      all.sum2[c] += g.statistics.sum2[c];
    }
  }
  return drift_grid_from_statistics(n, std::move(all), source);
}

DriftGrid read_drift_grid(const std::string& path) {
  io::H5File f(path, io::H5File::Mode::Read);
  DriftGrid g;
  const auto shape = f.shape("/v_ax");
  if (shape.size() != 2 || shape[0] != shape[1] || shape[0] < 1 || shape[0] > kMaxDriftGridN)
    throw InputError(
        "drift grid '" + path +
        "': /v_ax must be a square [n][n] dataset, 1 <= n <= " + std::to_string(kMaxDriftGridN));
  if (f.shape("/sigma_ax") != shape)
    throw InputError("drift grid '" + path + "': /sigma_ax must have the shape of /v_ax");
  g.n = static_cast<int>(shape[0]);
  // (the attribute a reader of the file trusts; a grid whose datasets were replaced by another n)
  if (f.has_attr("/", "n") && f.attr_int64("/", "n") != g.n)
    throw InputError("drift grid '" + path +
                     "': its attribute n = " + std::to_string(f.attr_int64("/", "n")) +
                     " but /v_ax is " + std::to_string(g.n) + " x " + std::to_string(g.n));
  g.v_ax = f.read_double("/v_ax");
  g.sigma_ax = f.read_double("/sigma_ax");
  // A NaN here would reach every tracer that enters its cell, and a negative sigma flips kicks.
  for (std::size_t c = 0; c < g.v_ax.size(); ++c)
    if (!std::isfinite(g.v_ax[c]) || !std::isfinite(g.sigma_ax[c]) || g.sigma_ax[c] < 0)
      throw InputError("drift grid '" + path + "': cell [" + std::to_string(c / g.n) + "][" +
                       std::to_string(c % g.n) + "] has v_ax = " + std::to_string(g.v_ax[c]) +
                       ", sigma_ax = " + std::to_string(g.sigma_ax[c]) +
                       " (both finite, sigma_ax >= 0)");
  g.source = f.has_attr("/", "source") ? f.attr_string("/", "source") : path;
  if (f.exists("/count")) {
    for (const char* name : {"/count", "/sum", "/sum2"})
      if (!f.exists(name) || f.shape(name) != shape)
        throw InputError("drift grid '" + path + "': " + name +
                         " must be present with the shape of /v_ax when /count is");
    DriftStatistics& st = g.statistics;
    st.count = f.read_double("/count");
    st.sum = f.read_double("/sum");
    st.sum2 = f.read_double("/sum2");
    for (std::size_t c = 0; c < st.count.size(); ++c)
      if (!(st.count[c] >= 0) || !std::isfinite(st.sum[c]) || !(st.sum2[c] >= 0) ||
          !std::isfinite(st.sum2[c]))
        throw InputError("drift grid '" + path + "': cell [" + std::to_string(c / g.n) + "][" +
                         std::to_string(c % g.n) +
                         "] has count < 0 or a sum that is not finite (or sum2 < 0)");
  }
  return g;
}

void write_drift_grid(const std::string& path, const DriftGrid& g) {
  io::AtomicH5Writer w(path);
  auto& f = w.file();
  const hsize_t n = static_cast<hsize_t>(g.n);
  f.write("/v_ax", g.v_ax, {n, n});
  f.write("/sigma_ax", g.sigma_ax, {n, n});
  if (g.has_statistics()) {
    f.write("/count", g.statistics.count, {n, n});
    f.write("/sum", g.statistics.sum, {n, n});
    f.write("/sum2", g.statistics.sum2, {n, n});
  }
  f.set_attr("/", "n", static_cast<std::int64_t>(g.n));
  f.set_attr("/", "source", g.source);
  f.set_attr("/", "convention", std::string(kConvention));
  f.set_attr("/", "units", std::string("omega*R (nondimensional velocity)"));
  w.commit();
}

}  // namespace tumble::cm
